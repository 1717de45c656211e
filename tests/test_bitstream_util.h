// Synthetic meshes and partitions for the bitstream tests and benchmark:
// grids and UV spheres, partitioned into compact regions by multi-source BFS
// from random seeds (a stand-in for the encoder's partitions), then numbered
// by lowest face as the format requires.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <random>
#include <vector>

#include "codec/core/mesh.h"
#include "format/bitstream/uvmap.h"

namespace gltfwarp::testutil {

// nx * ny quads, two triangles each, row-major faces; z is a gentle bump.
// An nx x ny-quad grid over the unit square on the saddle z = bend * x * y,
// row-major, two triangles per quad; float arithmetic only (no libm), so
// every platform gets the same positions.
inline TriMesh make_grid(uint32_t nx, uint32_t ny, float bend = 0.125f) {
  TriMesh m;
  for (uint32_t j = 0; j <= ny; ++j)
    for (uint32_t i = 0; i <= nx; ++i) {
      const float x = static_cast<float>(i) / static_cast<float>(nx);
      const float y = static_cast<float>(j) / static_cast<float>(ny);
      m.positions.insert(m.positions.end(), {x, y, bend * x * y});
    }
  for (uint32_t j = 0; j < ny; ++j)
    for (uint32_t i = 0; i < nx; ++i) {
      const uint32_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

// Closed UV sphere with poles; nu around, nv from pole to pole.
inline TriMesh make_sphere(uint32_t nu, uint32_t nv) {
  TriMesh m;
  const double pi = 3.14159265358979323846;
  m.positions.insert(m.positions.end(), {0.f, 0.f, 1.f});
  for (uint32_t j = 1; j < nv; ++j)
    for (uint32_t i = 0; i < nu; ++i) {
      const double th = pi * j / nv, ph = 2 * pi * i / nu;
      m.positions.insert(m.positions.end(),
                         {static_cast<float>(std::sin(th) * std::cos(ph)),
                          static_cast<float>(std::sin(th) * std::sin(ph)), static_cast<float>(std::cos(th))});
    }
  m.positions.insert(m.positions.end(), {0.f, 0.f, -1.f});
  const uint32_t south = 1 + (nv - 1) * nu;
  auto ring = [&](uint32_t j, uint32_t i) { return 1 + (j - 1) * nu + i % nu; };
  for (uint32_t i = 0; i < nu; ++i) m.indices.insert(m.indices.end(), {0, ring(1, i), ring(1, i + 1)});
  for (uint32_t j = 1; j + 1 < nv; ++j)
    for (uint32_t i = 0; i < nu; ++i) {
      const uint32_t a = ring(j, i), b = ring(j, i + 1), c = ring(j + 1, i), d = ring(j + 1, i + 1);
      m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
    }
  for (uint32_t i = 0; i < nu; ++i)
    m.indices.insert(m.indices.end(), {south, ring(nv - 1, i + 1), ring(nv - 1, i)});
  return m;
}

// Edge-adjacent faces of each face.
inline std::vector<std::vector<uint32_t>> face_adjacency(const TriMesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;
  for (uint32_t f = 0; f < m.face_count(); ++f)
    for (uint32_t k = 0; k < 3; ++k) {
      uint32_t a = m.indices[3 * f + k], b = m.indices[3 * f + (k + 1) % 3];
      if (a > b) std::swap(a, b);
      edges[{a, b}].push_back(f);
    }
  std::vector<std::vector<uint32_t>> adj(m.face_count());
  for (auto& [e, fs] : edges)
    for (uint32_t x : fs)
      for (uint32_t y : fs)
        if (x != y) adj[x].push_back(y);
  return adj;
}

// Renumbers patch ids in order of their lowest face.
inline uint32_t renumber_by_lowest_face(std::vector<uint32_t>& patch_of_face) {
  std::map<uint32_t, uint32_t> remap;
  for (uint32_t& p : patch_of_face) {
    auto it = remap.find(p);
    if (it == remap.end()) it = remap.emplace(p, static_cast<uint32_t>(remap.size())).first;
    p = it->second;
  }
  return static_cast<uint32_t>(remap.size());
}

// Compact regions: multi-source BFS (random growth order) from patch_count seeds.
inline uint32_t bfs_partition(const TriMesh& m, uint32_t patch_count, std::mt19937& rng,
                              std::vector<uint32_t>& patch_of_face) {
  const uint32_t nf = m.face_count();
  const auto adj = face_adjacency(m);
  patch_of_face.assign(nf, UINT32_MAX);
  std::vector<uint32_t> frontier;
  std::uniform_int_distribution<uint32_t> pick(0, nf - 1);
  for (uint32_t p = 0; p < patch_count; ++p) {
    const uint32_t f = pick(rng);
    if (patch_of_face[f] != UINT32_MAX) continue;
    patch_of_face[f] = p;
    frontier.push_back(f);
  }
  // Round-robin BFS keeps regions roughly round.
  std::deque<uint32_t> q(frontier.begin(), frontier.end());
  while (!q.empty()) {
    const uint32_t f = q.front();
    q.pop_front();
    for (uint32_t g : adj[f])
      if (patch_of_face[g] == UINT32_MAX) {
        patch_of_face[g] = patch_of_face[f];
        q.push_back(g);
      }
  }
  for (uint32_t& p : patch_of_face)
    if (p == UINT32_MAX) p = 0;  // unreachable components (none on our meshes)
  return renumber_by_lowest_face(patch_of_face);
}

inline UvMap random_uvmap(const TriMesh& m, uint32_t target_patches, std::mt19937& rng, bool pages,
                          bool scales, bool rotations) {
  UvMap map;
  map.tau = 1.0f + static_cast<float>(rng() % 100) / 64.0f;
  map.texel_scale = static_cast<float>(1 + rng() % 5000) / 8.0f;
  map.atlas_width = 1u << (4 + rng() % 9);
  map.atlas_height = (rng() % 4 == 0) ? 1 + rng() % 3000 : map.atlas_width;
  map.page_count = pages ? 1 + rng() % 5 : 1;
  map.patch_count = bfs_partition(m, std::max(1u, target_patches), rng, map.patch_of_face);
  map.placements.resize(map.patch_count);
  for (PatchPlacement& pl : map.placements) {
    pl.rotation = rotations ? rng() % kRotationSteps : 0;
    pl.x = static_cast<int32_t>(rng() % (map.atlas_width + 1));
    pl.y = static_cast<int32_t>(rng() % (map.atlas_height + 1));
    pl.page = rng() % map.page_count;
    pl.scale_step = scales ? static_cast<int32_t>(rng() % 65) - 32 : 0;
  }
  return map;
}

// `bytes` with 1..max_flips random bits flipped (a corrupt stream).
inline std::vector<uint8_t> with_flipped_bits(std::vector<uint8_t> b, std::mt19937& rng, uint32_t max_flips) {
  const int flips = 1 + static_cast<int>(rng() % max_flips);
  for (int i = 0; i < flips; ++i) b[rng() % b.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
  return b;
}

// Format 1.1: a random face of each patch as its seed.
inline void add_random_seeds(UvMap& map, std::mt19937& rng) {
  std::vector<std::vector<uint32_t>> faces(map.patch_count);
  for (uint32_t f = 0; f < map.patch_of_face.size(); ++f) faces[map.patch_of_face[f]].push_back(f);
  map.seeds.resize(map.patch_count);
  for (uint32_t p = 0; p < map.patch_count; ++p) map.seeds[p] = faces[p][rng() % faces[p].size()];
}

// Format 1.3: about one patch in `one_in` gets a random fine placement
// (any valid cos_q, sin_q, fractions and mirror; rotation 0, as the writer
// requires of a fine patch).
inline void add_random_fine(UvMap& map, std::mt19937& rng, uint32_t one_in = 2) {
  const int32_t max = 2 * kFineUnit;
  for (PatchPlacement& pl : map.placements) {
    if (rng() % one_in != 0) continue;
    pl.fine = true;
    pl.rotation = 0;
    pl.mirror = rng() % 2 == 1;
    do {
      // Often the extremes and the unit, else anywhere in range.
      const auto pick = [&]() -> int32_t {
        switch (rng() % 6) {
          case 0:
            return -max;
          case 1:
            return max;
          case 2:
            return kFineUnit;
          case 3:
            return 0;
          default:
            return static_cast<int32_t>(rng() % (2 * uint32_t(max) + 1)) - max;
        }
      };
      pl.cos_q = pick();
      pl.sin_q = pick();
    } while (pl.cos_q == 0 && pl.sin_q == 0);
    pl.x_frac = static_cast<uint32_t>(pl.x) == map.atlas_width ? 0 : rng() % kFineFracSteps;
    pl.y_frac = static_cast<uint32_t>(pl.y) == map.atlas_height ? 0 : rng() % kFineFracSteps;
  }
}

inline uint64_t fnv1a(const void* data, size_t n) {
  uint64_t h = 0xcbf29ce484222325ull;
  const auto* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

}  // namespace gltfwarp::testutil
