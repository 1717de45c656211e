// Splitting a source chart at its slits (see chart_split.h).
#include "codec/encode/partition/chart_split.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "codec/core/topology.h"

namespace gltfwarp {

double opposite_edge_length(const TriMesh& mesh, size_t c) {
  const size_t f = c / 3, k = c % 3;
  const float* a = &mesh.positions[3 * size_t{mesh.indices[3 * f + (k + 1) % 3]}];
  const float* b = &mesh.positions[3 * size_t{mesh.indices[3 * f + (k + 2) % 3]}];
  return std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]);
}

std::vector<uint32_t> grow_from_slit_sides(const TriMesh& mesh, std::span<const uint32_t> opp,
                                           std::span<const uint8_t> edge, std::span<const uint32_t> whole,
                                           std::span<const uint8_t> retry) {
  const uint32_t nf = mesh.face_count();
  // Slit edges, each by its corner in the face that runs from a to b.
  struct Slit {
    uint32_t corner, a, b;
  };
  std::vector<Slit> slits;
  for (size_t c = 0; c < edge.size(); ++c) {
    const uint32_t o = opp[c];
    if (edge[c] != kEdgeCut || o == kNone || o < c) continue;
    const uint32_t f = uint32_t(c / 3);
    if (whole[f] != whole[o / 3] || !retry[whole[f]]) continue;
    const uint32_t k = uint32_t(c % 3);
    slits.push_back(
        {uint32_t(c), mesh.indices[3 * size_t{f} + (k + 1) % 3], mesh.indices[3 * size_t{f} + (k + 2) % 3]});
  }
  // The slit edges at each vertex, as (vertex, slit) pairs sorted by vertex.
  std::vector<std::pair<uint32_t, uint32_t>> at;
  for (uint32_t i = 0; i < slits.size(); ++i) {
    at.emplace_back(slits[i].a, i);
    at.emplace_back(slits[i].b, i);
  }
  std::sort(at.begin(), at.end());
  const auto slits_at = [&](uint32_t v) {
    const auto lo = std::lower_bound(at.begin(), at.end(), std::pair<uint32_t, uint32_t>{v, 0});
    const auto hi = std::lower_bound(at.begin(), at.end(), std::pair<uint32_t, uint32_t>{v + 1, 0});
    return std::span(lo, hi);
  };
  // Orient each chain: an edge that meets another's head leaves from it, one
  // that meets its tail arrives there. forward[i]: the chain runs a to b.
  std::vector<uint32_t> chain(slits.size(), kNone), stack;
  std::vector<uint8_t> forward(slits.size(), 1);
  uint32_t chains = 0;
  for (uint32_t s = 0; s < slits.size(); ++s) {
    if (chain[s] != kNone) continue;
    chain[s] = chains;
    stack.assign(1, s);
    while (!stack.empty()) {
      const uint32_t i = stack.back();
      stack.pop_back();
      const uint32_t tail = forward[i] ? slits[i].a : slits[i].b, head = forward[i] ? slits[i].b : slits[i].a;
      for (const uint32_t v : {head, tail})
        for (const auto& [vertex, j] : slits_at(v)) {
          if (chain[j] != kNone) continue;
          chain[j] = chains;
          forward[j] = (v == head) == (slits[j].a == v);  // leaves the head, arrives at the tail
          stack.push_back(j);
        }
    }
    ++chains;
  }
  // Fronts: left of chain k is 2k, right is 2k+1; a face on two sides keeps
  // the first. Then they grow in step.
  std::vector<uint32_t> front(nf, kNone), queue;
  for (uint32_t i = 0; i < slits.size(); ++i) {
    const uint32_t f = slits[i].corner / 3, g = opp[slits[i].corner] / 3;
    const uint32_t left = forward[i] ? f : g, right = forward[i] ? g : f;
    for (const auto& [face, id] : {std::pair{left, 2 * chain[i]}, std::pair{right, 2 * chain[i] + 1}})
      if (front[face] == kNone) {
        front[face] = id;
        queue.push_back(face);
      }
  }
  for (size_t q = 0; q < queue.size(); ++q) {
    const uint32_t f = queue[q];
    for (uint32_t k = 0; k < 3; ++k) {
      const size_t c = 3 * size_t{f} + k;
      if (!joins(edge[c]) || front[opp[c] / 3] != kNone) continue;
      front[opp[c] / 3] = front[f];
      queue.push_back(opp[c] / 3);
    }
  }
  // Parts: faces joined to each other and reached by the same front (or by
  // none, outside the retried charts).
  return grow_components(nf, opp, [&](size_t c, uint32_t f, uint32_t g, uint32_t, const auto&) {
    return joins(edge[c]) && front[g] == front[f];
  });
}

std::vector<uint32_t> absorb_small_parts(const TriMesh& mesh, std::span<const uint32_t> opp,
                                         std::span<const uint8_t> edge, std::span<const uint32_t> whole,
                                         std::span<const double> face_area,
                                         std::span<const double> whole_area, std::vector<uint32_t> part,
                                         double min_share) {
  const uint32_t nf = mesh.face_count();
  const uint32_t count = *std::max_element(part.begin(), part.end()) + 1;
  std::vector<uint32_t> root(count);
  for (uint32_t p = 0; p < count; ++p) root[p] = p;
  const auto find = [&](uint32_t p) {
    while (root[p] != p) p = root[p] = root[root[p]];
    return p;
  };
  std::vector<double> area(count, 0.0), floor(count, 0.0);
  for (uint32_t f = 0; f < nf; ++f) {
    area[part[f]] += face_area[f];
    floor[part[f]] = min_share * whole_area[whole[f]];
  }
  // Boundary pieces between parts: (smaller root, larger root, length, cut).
  struct Piece {
    uint32_t p, q;
    double length;
    bool cut;
  };
  for (bool merged = true; merged;) {
    merged = false;
    std::vector<Piece> pieces;
    for (size_t c = 0; c < edge.size(); ++c) {
      const uint32_t o = opp[c];
      if (o == kNone || o < c || (!joins(edge[c]) && edge[c] != kEdgeCut)) continue;
      const uint32_t p = find(part[c / 3]), q = find(part[o / 3]);
      if (p != q)
        pieces.push_back(
            {std::min(p, q), std::max(p, q), opposite_edge_length(mesh, c), edge[c] == kEdgeCut});
    }
    std::sort(pieces.begin(), pieces.end(),
              [](const Piece& x, const Piece& y) { return std::tie(x.p, x.q) < std::tie(y.p, y.q); });
    // Per small root, the neighbour with the longest uncut boundary.
    std::vector<uint32_t> best(count, kNone);
    std::vector<double> best_length(count, 0.0);
    for (size_t i = 0; i < pieces.size();) {
      size_t j = i;
      double sum = 0.0;
      bool cut = false;
      for (; j < pieces.size() && pieces[j].p == pieces[i].p && pieces[j].q == pieces[i].q; ++j) {
        sum += pieces[j].length;
        cut = cut || pieces[j].cut;
      }
      const uint32_t p = pieces[i].p, q = pieces[i].q;
      i = j;
      if (cut || sum <= 0.0) continue;
      for (const auto& [small, other] : {std::pair{p, q}, std::pair{q, p}})
        if (area[small] < floor[small] && sum > best_length[small]) {
          best[small] = other;
          best_length[small] = sum;
        }
    }
    // Smallest first; a part merged this round waits for the next.
    std::vector<uint32_t> order;
    for (uint32_t p = 0; p < count; ++p)
      if (find(p) == p && best[p] != kNone) order.push_back(p);
    std::sort(order.begin(), order.end(),
              [&](uint32_t x, uint32_t y) { return std::tie(area[x], x) < std::tie(area[y], y); });
    std::vector<uint8_t> touched(count, 0);
    for (const uint32_t p : order) {
      const uint32_t q = best[p];
      if (touched[p] || touched[q]) continue;
      touched[p] = touched[q] = 1;
      root[p] = q;
      area[q] += area[p];
      merged = true;
    }
  }
  std::vector<uint32_t> id(count, kNone);
  uint32_t next = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    uint32_t& i = id[find(part[f])];
    if (i == kNone) i = next++;
    part[f] = i;
  }
  return part;
}

}  // namespace gltfwarp
