// The paper's distortion measure (Sorkine & Cohen-Or 2001, section 3): for a
// triangle and its 2D image, the largest over the three edges of
// max(L3, L2) / min(L3, L2), where L3 and L2 are the edge's 3D and 2D lengths.
// 1 means the edge kept its length; the bound tau applies to every triangle.
//
// Degenerate cases are defined so that no NaN can arise:
//  * an edge of length 0 in both 3D and 2D has ratio 1 (it kept its length);
//  * an edge of length 0 in exactly one of them has ratio +infinity;
//  * non-finite inputs give +infinity.
#pragma once

#include <cmath>
#include <limits>

namespace gltfwarp {

inline double edge_distortion(double l3, double l2) {
  if (!(l3 >= 0) || !(l2 >= 0) || std::isinf(l3) || std::isinf(l2))
    return std::numeric_limits<double>::infinity();
  const double hi = l3 > l2 ? l3 : l2, lo = l3 > l2 ? l2 : l3;
  if (hi == 0) return 1.0;
  if (lo == 0) return std::numeric_limits<double>::infinity();
  return hi / lo;
}

// l3[k], l2[k]: lengths of the edge opposite corner k (any fixed pairing).
inline double triangle_distortion(const double l3[3], const double l2[3]) {
  double d = edge_distortion(l3[0], l2[0]);
  const double d1 = edge_distortion(l3[1], l2[1]), d2 = edge_distortion(l3[2], l2[2]);
  if (d1 > d) d = d1;
  if (d2 > d) d = d2;
  return d;
}

}  // namespace gltfwarp
