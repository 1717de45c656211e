// MikkTSpace-convention tangent frames (sources and deviations in tangents.h).
#include "codec/decode/tangents.h"

#include <cmath>
#include <cstring>
#include <vector>

namespace gltfwarp {
namespace {

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double len(V3 a) { return std::sqrt(dot(a, a)); }
V3 unit(V3 a) {
  const double l = len(a);
  return l > 0 ? (1.0 / l) * a : a;
}

// Any unit vector orthogonal to n.
V3 orthogonal(V3 n) {
  const V3 a = std::abs(n.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
  const V3 t = unit(a - dot(a, n) * n);
  return len(t) > 0 ? t : V3{1, 0, 0};
}

// Welding key: the bits of position, normal, UV and the orientation flag.
struct Key {
  float v[8];
  bool flip;
  bool operator==(const Key& o) const { return flip == o.flip && std::memcmp(v, o.v, sizeof v) == 0; }
};
struct KeyHash {  // four 64-bit words of bits, multiply-xorshift mixed
  size_t operator()(const Key& k) const {
    uint64_t h = 0x9E3779B97F4A7C15ull ^ uint64_t(k.flip);
    for (int i = 0; i < 4; ++i) {
      uint64_t w;
      std::memcpy(&w, &k.v[2 * i], 8);
      h = (h ^ w) * 0xBF58476D1CE4E5B9ull;
      h ^= h >> 31;
    }
    return size_t(h ^ (h >> 29));
  }
};
float canon(float f) { return f == 0.0f ? 0.0f : f; }  // -0 welds with +0

// Key -> group id, open addressing with linear probing: the same ids, in the
// same order of first appearance, as a hash map, without a node per key.
class GroupTable {
 public:
  explicit GroupTable(size_t n) {
    size_t cap = 16;
    while (cap < 2 * n) cap <<= 1;
    slots_.assign(cap, UINT32_MAX);
    keys_.reserve(n);
  }
  // Returns the group of k, adding it as group size() when new.
  uint32_t find_or_add(const Key& k, bool& fresh) {
    const size_t mask = slots_.size() - 1;
    for (size_t i = KeyHash{}(k)&mask;; i = (i + 1) & mask) {
      const uint32_t g = slots_[i];
      if (g == UINT32_MAX) {
        slots_[i] = static_cast<uint32_t>(keys_.size());
        keys_.push_back(k);
        fresh = true;
        return slots_[i];
      }
      if (keys_[g] == k) {
        fresh = false;
        return g;
      }
    }
  }

 private:
  std::vector<uint32_t> slots_;
  std::vector<Key> keys_;
};

}  // namespace

namespace {

// Welding key of corner c without the orientation flag.
Key corner_key(const TriMesh& mesh, std::span<const float> corner_normals, std::span<const float> corner_uv,
               size_t c) {
  Key k{};
  const float* p = &mesh.positions[3 * size_t(mesh.indices[c])];
  k.v[0] = canon(p[0]), k.v[1] = canon(p[1]), k.v[2] = canon(p[2]);
  k.v[3] = canon(corner_normals[3 * c]), k.v[4] = canon(corner_normals[3 * c + 1]);
  k.v[5] = canon(corner_normals[3 * c + 2]);
  k.v[6] = canon(corner_uv[2 * c]), k.v[7] = canon(corner_uv[2 * c + 1]);
  return k;
}

// corner_class, when given, names for each corner a class of equal keys
// (without the flag), so that the welding needs no hash of every corner.
// The groups are then (class, flag) instead of (key, flag): the same
// partition of the corners, and the sums run in the same corner order.
std::vector<float> corner_tangents_impl(const TriMesh& mesh, std::span<const float> corner_normals,
                                        std::span<const float> corner_uv, const uint32_t* corner_class,
                                        uint32_t class_count) {
  const uint32_t nf = mesh.face_count();
  const size_t nc = size_t(nf) * 3;
  std::vector<float> out(nc * 4, 0.0f);
  if (corner_normals.size() < nc * 3 || corner_uv.size() < nc * 2) return out;
  auto P = [&](size_t c) {
    const float* p = &mesh.positions[3 * size_t(mesh.indices[c])];
    return V3{p[0], p[1], p[2]};
  };
  auto N = [&](size_t c) {
    return unit(V3{corner_normals[3 * c], corner_normals[3 * c + 1], corner_normals[3 * c + 2]});
  };
  std::vector<uint32_t> group_of(nc);
  std::vector<V3> sum;
  std::vector<double> bsign;
  std::vector<V3> face_t(nf), face_b(nf);
  std::vector<uint8_t> face_ok(nf, 0), face_flip(nf, 0);
  for (uint32_t f = 0; f < nf; ++f) {
    const size_t c0 = 3 * size_t(f);
    const V3 d1 = P(c0 + 1) - P(c0), d2 = P(c0 + 2) - P(c0);
    const double s1 = double(corner_uv[2 * (c0 + 1)]) - corner_uv[2 * c0];
    const double t1 = double(corner_uv[2 * (c0 + 1) + 1]) - corner_uv[2 * c0 + 1];
    const double s2 = double(corner_uv[2 * (c0 + 2)]) - corner_uv[2 * c0];
    const double t2 = double(corner_uv[2 * (c0 + 2) + 1]) - corner_uv[2 * c0 + 1];
    const double r = s1 * t2 - s2 * t1;
    // dP/du and dP/dv of the face's affine map.
    const V3 dpdu = (1.0 / r) * (t2 * d1 - t1 * d2);
    const V3 dpdv = (1.0 / r) * (s1 * d2 - s2 * d1);
    if (r != 0 && std::isfinite(len(dpdu)) && len(dpdu) > 0 && len(dpdv) > 0) {
      face_ok[f] = 1;
      face_t[f] = unit(dpdu);
      face_b[f] = unit(-1.0 * dpdv);  // glTF: bitangent toward decreasing v (image up)
      const V3 fn = cross(d1, d2);
      face_flip[f] = dot(cross(fn, face_t[f]), face_b[f]) < 0;
    }
  }
  if (corner_class) {
    for (size_t c = 0; c < nc; ++c) group_of[c] = 2 * corner_class[c] + face_flip[c / 3];
    sum.resize(2 * size_t(class_count));
    bsign.resize(2 * size_t(class_count), 0.0);
  } else {
    GroupTable groups(nc);
    for (size_t c = 0; c < nc; ++c) {
      Key k = corner_key(mesh, corner_normals, corner_uv, c);
      k.flip = face_flip[c / 3];
      bool fresh = false;
      group_of[c] = groups.find_or_add(k, fresh);
      if (fresh) sum.push_back({}), bsign.push_back(0);
    }
  }
  for (size_t c = 0; c < nc; ++c) {
    const uint32_t f = uint32_t(c / 3);
    const uint32_t g = group_of[c];
    if (!face_ok[f]) continue;
    // Corner angle weight.
    const size_t c0 = 3 * size_t(f), k0 = c - c0;
    const V3 e1 = unit(P(c0 + (k0 + 1) % 3) - P(c)), e2 = unit(P(c0 + (k0 + 2) % 3) - P(c));
    const double angle = std::acos(std::max(-1.0, std::min(1.0, dot(e1, e2))));
    const V3 n = N(c);
    const V3 t = unit(face_t[f] - dot(face_t[f], n) * n);
    sum[g] = sum[g] + angle * t;
    const V3 b = face_b[f] - dot(face_b[f], n) * n;
    bsign[g] += angle * dot(cross(n, t), b);
  }
  for (size_t c = 0; c < nc; ++c) {
    const uint32_t g = group_of[c];
    const V3 n = N(c);
    V3 t = unit(sum[g] - dot(sum[g], n) * n);
    if (!(len(t) > 0.5)) t = orthogonal(n);
    out[4 * c] = float(t.x), out[4 * c + 1] = float(t.y), out[4 * c + 2] = float(t.z);
    out[4 * c + 3] = bsign[g] < 0 ? -1.0f : 1.0f;
  }
  return out;
}

}  // namespace

std::vector<float> corner_tangents(const TriMesh& mesh, std::span<const float> corner_normals,
                                   std::span<const float> corner_uv) {
  return corner_tangents_impl(mesh, corner_normals, corner_uv, nullptr, 0);
}

std::vector<float> per_corner(const TriMesh& mesh, std::span<const float> per_vertex, int n) {
  std::vector<float> out(mesh.indices.size() * size_t(n), 0.0f);
  for (size_t c = 0; c < mesh.indices.size(); ++c) {
    const size_t v = mesh.indices[c];
    if ((v + 1) * size_t(n) > per_vertex.size()) continue;
    for (int k = 0; k < n; ++k) out[c * n + k] = per_vertex[v * n + k];
  }
  return out;
}

std::vector<float> vertex_tangents(std::span<const float> positions, std::span<const float> normals,
                                   std::span<const float> uvs, std::span<const uint32_t> indices) {
  TriMesh m;
  m.positions.assign(positions.begin(), positions.end());
  m.indices.assign(indices.begin(), indices.end() - indices.size() % 3);
  const size_t nv = positions.size() / 3;
  std::vector<float> out(nv * 4, 0.0f);
  for (size_t v = 0; v < nv; ++v) out[4 * v] = 1.0f, out[4 * v + 3] = 1.0f;
  for (uint32_t i : m.indices)
    if (i >= nv) return out;
  const std::vector<float> cn = per_corner(m, normals, 3), cu = per_corner(m, uvs, 2);
  // All corners of a vertex share its key: weld the vertices (each through
  // its first corner) rather than every corner.
  const size_t nc = m.indices.size();
  std::vector<uint32_t> vclass(nv, UINT32_MAX), corner_class(nc);
  uint32_t classes = 0;
  {
    GroupTable table(nv);
    for (size_t c = 0; c < nc; ++c) {
      const uint32_t v = m.indices[c];
      if (vclass[v] == UINT32_MAX) {
        bool fresh = false;
        vclass[v] = table.find_or_add(corner_key(m, cn, cu, c), fresh);
        if (fresh) ++classes;
      }
      corner_class[c] = vclass[v];
    }
  }
  const std::vector<float> ct = corner_tangents_impl(m, cn, cu, corner_class.data(), classes);
  std::vector<uint8_t> done(nv, 0);
  for (size_t c = 0; c < m.indices.size(); ++c) {
    const uint32_t v = m.indices[c];
    if (done[v]) continue;
    done[v] = 1;
    std::copy(&ct[4 * c], &ct[4 * c] + 4, &out[4 * size_t(v)]);
  }
  return out;
}

std::vector<float> flat_corner_normals(const TriMesh& mesh) {
  const uint32_t nf = mesh.face_count();
  std::vector<float> out(size_t(nf) * 9, 0.0f);
  for (uint32_t f = 0; f < nf; ++f) {
    V3 p[3];
    for (int k = 0; k < 3; ++k) {
      const float* q = &mesh.positions[3 * size_t(mesh.indices[3 * size_t(f) + k])];
      p[k] = {q[0], q[1], q[2]};
    }
    V3 n = unit(cross(p[1] - p[0], p[2] - p[0]));
    if (!(len(n) > 0)) n = {0, 0, 1};
    for (int k = 0; k < 3; ++k) {
      out[9 * size_t(f) + 3 * k] = float(n.x);
      out[9 * size_t(f) + 3 * k + 1] = float(n.y);
      out[9 * size_t(f) + 3 * k + 2] = float(n.z);
    }
  }
  return out;
}

}  // namespace gltfwarp
