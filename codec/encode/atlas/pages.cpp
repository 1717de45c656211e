#include "codec/encode/atlas/pages.h"

#include <algorithm>
#include <cmath>

#include "codec/core/topology.h"
#include "codec/encode/atlas/texel_density.h"

namespace gltfwarp {
namespace {

double size_of(double t) { return std::isfinite(t) && t > 0 ? t : 0.0; }

// Patches that share a vertex with each patch, sorted, without repeats.
std::vector<std::vector<uint32_t>> patch_neighbours(const TriMesh& mesh, const VertexFaces& around,
                                                    std::span<const uint32_t> patch_of_face,
                                                    uint32_t patch_count) {
  std::vector<std::vector<uint32_t>> out(patch_count);
  std::vector<uint32_t> here;  // the patches at one vertex
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    here.clear();
    for (uint32_t i = around.offsets[v]; i < around.offsets[v + 1]; ++i) {
      const uint32_t p = patch_of_face[around.faces[i]];
      if (std::find(here.begin(), here.end(), p) == here.end()) here.push_back(p);
    }
    for (uint32_t a : here)
      for (uint32_t b : here)
        if (a != b) out[a].push_back(b);
  }
  for (auto& n : out) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return out;
}

}  // namespace

std::vector<std::vector<size_t>> assign_pages(std::span<const double> texels, double capacity) {
  std::vector<std::vector<size_t>> pages;
  std::vector<double> load;
  for (size_t item = 0; item < texels.size(); ++item) {
    const double t = size_of(texels[item]);
    size_t page = 0;
    while (page < pages.size() && !(load[page] + t <= capacity)) ++page;
    if (page == pages.size()) {
      pages.emplace_back();
      load.push_back(0);
    }
    pages[page].push_back(item);
    load[page] += t;
  }
  return pages;
}

std::vector<double> estimated_patch_texels(std::span<const double> corner_xy,
                                           std::span<const uint32_t> patch_of_face, uint32_t patch_count,
                                           std::span<const double> face_density, double factor) {
  std::vector<double> out(patch_count, 0.0);
  if (face_density.empty()) {  // one density: the faces' own texels
    const auto faces = estimated_face_texels(corner_xy, {}, factor);
    for (size_t f = 0; f < patch_of_face.size(); ++f) out[patch_of_face[f]] += faces[f];
    return out;
  }
  const auto dens = patch_densities(corner_xy, patch_of_face, patch_count, face_density, 0.5);
  for (uint32_t p = 0; p < patch_count; ++p) out[p] = dens[p].area * std::pow(factor * dens[p].density, 2);
  return out;
}

std::vector<uint32_t> parts_of_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                                       std::span<const double> patch_texels, double capacity,
                                       uint32_t& part_count) {
  const uint32_t patches = uint32_t(patch_texels.size());
  const auto neighbours = patch_neighbours(mesh, build_vertex_faces(mesh), patch_of_face, patches);
  std::vector<uint32_t> part(patches, 0), queue;
  std::vector<uint8_t> seen(patches, 0);
  double load = 0;
  part_count = 0;
  for (uint32_t seed = 0; seed < patches; ++seed) {
    if (seen[seed]) continue;
    queue.assign(1, seed);
    seen[seed] = 1;
    for (size_t head = 0; head < queue.size(); ++head) {
      const uint32_t p = queue[head];
      const double t = size_of(patch_texels[p]);
      if (part_count == 0 || (load > 0 && !(load + t <= capacity))) {
        ++part_count;
        load = 0;
      }
      part[p] = part_count - 1;
      load += t;
      for (uint32_t n : neighbours[p])
        if (!seen[n]) {
          seen[n] = 1;
          queue.push_back(n);
        }
    }
  }
  return part;
}

std::vector<double> estimated_face_texels(std::span<const double> corner_xy,
                                          std::span<const double> face_density, double factor) {
  std::vector<double> out(corner_xy.size() / 6, 0.0);
  for (size_t f = 0; f < out.size(); ++f) {
    const double s = face_density.empty() ? factor : factor * face_density[f];
    out[f] = size_of(layout_face_area(corner_xy, f) * s * s);
  }
  return out;
}

std::vector<uint32_t> split_large_patches(const TriMesh& mesh, std::span<const uint32_t> patch_of_face,
                                          uint32_t patch_count, std::span<const double> face_texels,
                                          double capacity, std::span<const uint32_t> chart) {
  std::vector<double> total(patch_count, 0.0);
  for (size_t f = 0; f < patch_of_face.size(); ++f) total[patch_of_face[f]] += size_of(face_texels[f]);
  if (!(capacity > 0) || std::none_of(total.begin(), total.end(), [&](double t) { return t > capacity; }))
    return {};
  std::vector<uint32_t> out(patch_of_face.size(), 0);
  if (!chart.empty()) std::copy(chart.begin(), chart.end(), out.begin());
  uint32_t next = out.empty() ? 0 : *std::max_element(out.begin(), out.end()) + 1;
  const VertexFaces around = build_vertex_faces(mesh);
  std::vector<uint8_t> taken(patch_of_face.size(), 0), queued(patch_of_face.size(), 0);
  std::vector<uint32_t> queue;
  // Passes until every face of a large patch has a region: a region's
  // frontier faces (queued, not taken) may precede its seed.
  for (bool grew = true; grew;) {
    grew = false;
    for (uint32_t seed = 0; seed < patch_of_face.size(); ++seed) {
      const uint32_t p = patch_of_face[seed];
      if (taken[seed] || !(total[p] > capacity)) continue;
      // One region: faces of the same patch and chart around the seed,
      // until it holds half a page.
      const uint32_t region = next++, seed_chart = out[seed];
      double held = 0;
      queue.assign(1, seed);
      queued[seed] = 1;
      for (size_t head = 0; head < queue.size() && held < 0.5 * capacity; ++head) {
        const uint32_t f = queue[head];
        out[f] = region;
        taken[f] = 1;
        held += size_of(face_texels[f]);
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = mesh.indices[3 * f + k];
          for (uint32_t i = around.offsets[v]; i < around.offsets[v + 1]; ++i) {
            const uint32_t g = around.faces[i];
            if (!queued[g] && !taken[g] && patch_of_face[g] == p && out[g] == seed_chart) {
              queued[g] = 1;
              queue.push_back(g);
            }
          }
        }
      }
      for (const uint32_t f : queue) queued[f] = 0;
      grew = true;
    }
  }
  return out;
}

std::vector<uint32_t> split_faces_into_parts(const TriMesh& mesh, std::span<const double> face_texels,
                                             double capacity, bool halve_pieces, uint32_t& part_count) {
  const size_t faces = mesh.face_count();
  const VertexFaces around = build_vertex_faces(mesh);
  std::vector<uint32_t> piece(faces, 0), queue;
  std::vector<double> piece_texels;
  std::vector<uint8_t> seen(faces, 0);
  auto centroid = [&](uint32_t f, int axis) {
    double c = 0;
    for (int k = 0; k < 3; ++k) c += mesh.positions[3 * size_t(mesh.indices[3 * f + k]) + axis];
    return c;
  };
  // Halves a set of faces across the longest side of its centroids' box, at
  // the texel-weighted median, until each half fits: compact pieces, where
  // runs of a breadth-first order would be rings (a band around a sphere
  // unfolds into a strip no page holds).
  auto bisect = [&](auto&& self, std::span<uint32_t> set, double total) -> void {
    if (total <= capacity || set.size() < 2 || !halve_pieces) {
      piece_texels.push_back(total);
      for (uint32_t f : set) piece[f] = uint32_t(piece_texels.size() - 1);
      return;
    }
    int axis = 0;
    double extent = -1;
    for (int i = 0; i < 3; ++i) {
      double lo = 1e300, hi = -1e300;
      for (uint32_t f : set) lo = std::min(lo, centroid(f, i)), hi = std::max(hi, centroid(f, i));
      if (hi - lo > extent) extent = hi - lo, axis = i;
    }
    std::sort(set.begin(), set.end(), [&](uint32_t x, uint32_t y) {
      const double cx = centroid(x, axis), cy = centroid(y, axis);
      return cx < cy || (cx == cy && x < y);
    });
    size_t half = 0;
    double low = 0;
    while (half + 1 < set.size() && low + size_of(face_texels[set[half]]) <= 0.5 * total)
      low += size_of(face_texels[set[half++]]);
    half = std::max<size_t>(half, 1);
    low = 0;
    for (size_t i = 0; i < half; ++i) low += size_of(face_texels[set[i]]);
    self(self, set.subspan(0, half), low);
    self(self, set.subspan(half), total - low);
  };
  for (uint32_t seed = 0; seed < faces; ++seed) {
    if (seen[seed]) continue;
    queue.assign(1, seed);
    seen[seed] = 1;
    double total = 0;
    for (size_t head = 0; head < queue.size(); ++head) {
      const uint32_t f = queue[head];
      total += size_of(face_texels[f]);
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.indices[3 * f + k];
        for (uint32_t i = around.offsets[v]; i < around.offsets[v + 1]; ++i)
          if (const uint32_t g = around.faces[i]; !seen[g]) {
            seen[g] = 1;
            queue.push_back(g);
          }
      }
    }
    bisect(bisect, queue, total);
  }
  const auto pages = assign_pages(piece_texels, capacity);
  std::vector<uint32_t> part_of_piece(piece_texels.size(), 0);
  for (size_t p = 0; p < pages.size(); ++p)
    for (size_t item : pages[p]) part_of_piece[item] = uint32_t(p);
  std::vector<uint32_t> part(faces, 0);
  for (size_t f = 0; f < faces; ++f) part[f] = part_of_piece[piece[f]];
  part_count = uint32_t(pages.size());
  return part;
}

}  // namespace gltfwarp
