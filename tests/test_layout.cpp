// The shared layout replay (codec/core/layout.h): validation of untrusted
// partitions, determinism pinned by a golden hash, and basic geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "codec/core/layout.h"
#include "codec/core/topology.h"
#include "tests/support/testing/shapes.h"

namespace gltfwarp {
namespace {

uint64_t fnv1a(const std::vector<double>& v) {
  uint64_t h = 1469598103934665603ull;
  const auto* b = reinterpret_cast<const unsigned char*>(v.data());
  for (size_t i = 0; i < v.size() * sizeof(double); ++i) {
    h ^= b[i];
    h *= 1099511628211ull;
  }
  return h;
}

TEST(Layout, PlaneIsIsometricInOnePatch) {
  const TriMesh m = make_plane(12, 9).mesh;
  std::vector<uint32_t> pof(m.face_count(), 0);
  std::vector<double> xy;
  ASSERT_EQ(layout_patches(m, pof, 1, xy), LayoutStatus::ok);
  ASSERT_EQ(xy.size(), m.indices.size() * 2);
  // Every corner of one vertex has one position, and edge lengths are kept.
  for (uint32_t f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.indices[3 * f + k], b = m.indices[3 * f + (k + 1) % 3];
      const double l3 = std::sqrt(length3_sq(m, a, b));
      const double dx = xy[6 * f + 2 * k] - xy[6 * f + 2 * ((k + 1) % 3)];
      const double dy = xy[6 * f + 2 * k + 1] - xy[6 * f + 2 * ((k + 1) % 3) + 1];
      EXPECT_NEAR(std::sqrt(dx * dx + dy * dy), l3, 1e-6);
    }
}

TEST(Layout, GoldenHashPinsTheFloats) {
  // A fixed saddle-like mesh built with + and * only (no libm, so the input
  // floats are the same everywhere), and a fixed partition in two patches.
  TriMesh m = make_plane(20, 12).mesh;
  for (size_t i = 0; i < m.positions.size(); i += 3) {
    const double x = 2.0 * m.positions[i] - 1.0, y = 2.0 * m.positions[i + 1] - 1.0;
    m.positions[i + 2] = float(0.45 * (x * x - y * y) + 0.2 * x * y * y);
  }
  std::vector<uint32_t> pof(m.face_count());
  for (uint32_t f = 0; f < m.face_count(); ++f) pof[f] = f < m.face_count() / 2 ? 0 : 1;
  std::vector<double> xy;
  ASSERT_EQ(layout_patches(m, pof, 2, xy), LayoutStatus::ok);
  for (double x : xy) ASSERT_TRUE(std::isfinite(x));
  // If this changes, the format changed: every decoder must change with it.
  EXPECT_EQ(fnv1a(xy), 0x8165c67fa3900322ull) << std::hex << fnv1a(xy);
}

TEST(Layout, RejectsBadInput) {
  const TriMesh m = make_plane(4, 4).mesh;
  const uint32_t nf = m.face_count();
  std::vector<double> xy;
  std::vector<uint32_t> pof(nf, 0);
  pof[5] = 3;
  EXPECT_EQ(layout_patches(m, pof, 2, xy), LayoutStatus::bad_patch_id);
  std::fill(pof.begin(), pof.end(), 0);
  EXPECT_EQ(layout_patches(m, pof, 2, xy), LayoutStatus::bad_patch_id);  // patch 1 empty
  EXPECT_EQ(layout_patches(m, std::span<const uint32_t>(pof).first(nf - 1), 1, xy),
            LayoutStatus::bad_patch_id);
  pof[0] = 1;  // patch 1's lowest face comes before patch 0's
  EXPECT_EQ(layout_patches(m, pof, 2, xy), LayoutStatus::patch_order);
  // Two faces far apart in one patch, the rest in another: unreachable.
  std::fill(pof.begin(), pof.end(), 1);
  pof[0] = 0;
  pof[nf - 1] = 0;
  EXPECT_EQ(layout_patches(m, pof, 2, xy), LayoutStatus::unreachable_face);
  TriMesh bad = m;
  bad.indices[7] = bad.vertex_count();
  std::fill(pof.begin(), pof.end(), 0);
  EXPECT_EQ(layout_patches(bad, pof, 1, xy), LayoutStatus::bad_mesh);
  bad = m;
  bad.indices.pop_back();
  EXPECT_EQ(layout_patches(bad, pof, 1, xy), LayoutStatus::bad_mesh);
  EXPECT_STREQ(to_string(LayoutStatus::patch_order), "patches not numbered by lowest face");
}

TEST(Layout, RandomPartitionsNeverCrash) {
  const TriMesh m = make_degenerate_soup().mesh;
  const uint32_t nf = m.face_count();
  std::mt19937 rng(3);
  std::vector<double> xy;
  for (int trial = 0; trial < 300; ++trial) {
    const uint32_t k = 1 + rng() % 12;
    std::vector<uint32_t> raw(nf), pof(nf), remap(k, ~0u);
    for (uint32_t& p : raw) p = rng() % k;
    uint32_t next = 0;
    for (uint32_t f = 0; f < nf; ++f) {
      if (remap[raw[f]] == ~0u) remap[raw[f]] = next++;
      pof[f] = remap[raw[f]];
    }
    if (trial % 3 == 0) pof[rng() % nf] = rng() % (next + 2);  // sometimes invalid
    const LayoutStatus s = layout_patches(m, pof, next, xy);
    if (s == LayoutStatus::ok) {
      for (double x : xy) ASSERT_FALSE(std::isnan(x));
    }
  }
}

TEST(Layout, DegenerateSingletonsAreFinite) {
  const TriMesh m = make_degenerate_soup().mesh;
  std::vector<uint32_t> pof(m.face_count());
  for (uint32_t f = 0; f < m.face_count(); ++f) pof[f] = f;  // every face its own patch
  std::vector<double> xy;
  ASSERT_EQ(layout_patches(m, pof, m.face_count(), xy), LayoutStatus::ok);
  for (double x : xy) ASSERT_TRUE(std::isfinite(x));
}

// Ranges of patches replay on several threads (layout.h): the positions, and
// the error a bad patch gives, must not depend on how many.
TEST(Layout, ThreadCountDoesNotChangeTheBits) {
  const TriMesh m = make_bumpy_sphere(400, 200).mesh;
  const uint32_t nf = m.face_count();
  ASSERT_GE(nf, 4u << 15);  // enough faces for four threads
  // Connected patches of up to 777 faces, grown breadth-first across edges
  // from the lowest unassigned face, so they are numbered by lowest face.
  const std::vector<uint32_t> opposite = build_opposite_corners(m, build_vertex_faces(m));
  std::vector<uint32_t> pof(nf, kNone);
  uint32_t patches = 0;
  for (uint32_t seed = 0; seed < nf; ++seed) {
    if (pof[seed] != kNone) continue;
    std::vector<uint32_t> queue = {seed};
    pof[seed] = patches;
    for (size_t i = 0; i < queue.size() && queue.size() < 777; ++i)
      for (int k = 0; k < 3; ++k) {
        const uint32_t c = opposite[3 * queue[i] + k];
        if (c == kNone || pof[c / 3] != kNone || queue.size() == 777) continue;
        pof[c / 3] = patches;
        queue.push_back(c / 3);
      }
    ++patches;
  }
  std::vector<double> one, many;
  ASSERT_EQ(layout_patches(m, pof, patches, one, {}, {}, {}, 1), LayoutStatus::ok);
  for (const uint32_t threads : {2u, 3u, 4u, 0u}) {
    ASSERT_EQ(layout_patches(m, pof, patches, many, {}, {}, {}, threads), LayoutStatus::ok);
    ASSERT_EQ(0, std::memcmp(one.data(), many.data(), one.size() * sizeof(double))) << threads << " threads";
  }
  // The face sink sees every face once, with the same positions.
  std::vector<double> sunk(one.size(), std::nan(""));
  auto sink = [](void* context, uint32_t, uint32_t f, const Vec2 xy[3]) {
    double* out = static_cast<double*>(context) + 6 * size_t{f};
    for (int k = 0; k < 3; ++k) out[2 * k] = xy[k].x, out[2 * k + 1] = xy[k].y;
  };
  ASSERT_EQ(layout_patches(m, pof, patches, sink, sunk.data(), {}, {}, {}, 4), LayoutStatus::ok);
  EXPECT_EQ(0, std::memcmp(one.data(), sunk.data(), one.size() * sizeof(double)));
  // A patch near the end that cannot be reached: the same error from any count.
  const uint32_t stray = nf - 10;
  pof[stray] = pof[nf / 4];  // joins an early patch far from it
  std::vector<uint32_t> renumbered(nf);
  std::vector<uint32_t> remap(patches, ~0u);
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    if (remap[pof[f]] == ~0u) remap[pof[f]] = next++;
    renumbered[f] = remap[pof[f]];
  }
  for (const uint32_t threads : {1u, 2u, 4u})
    EXPECT_EQ(layout_patches(m, renumbered, next, many, {}, {}, {}, threads), LayoutStatus::unreachable_face)
        << threads << " threads";
}

}  // namespace
}  // namespace gltfwarp
