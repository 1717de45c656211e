// Surface error of a warped atlas against its source (see warp_quality.h).
#include "codec/encode/texture/warp_quality.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <OpenImageIO/parallel.h>

#include "codec/encode/atlas/texel_density.h"

namespace gltfwarp {

double SurfaceError::psnr() const {
  if (!(values > 0)) return 0;
  const double mse = squared / values;
  return mse > 0 ? std::min(99.0, 10.0 * std::log10(255.0 * 255.0 / mse)) : 99.0;
}

FaceSampling sample_faces(std::span<const SurfaceUvs> prims, double source_texels, uint64_t max_points) {
  FaceSampling out;
  out.side.resize(prims.size());
  out.weight.resize(prims.size());
  uint64_t total = 0;
  for (size_t p = 0; p < prims.size(); ++p) {
    const size_t nf = std::min(prims[p].source_uv.size(), prims[p].atlas_uv.size()) / 6;
    out.side[p].resize(nf);
    out.weight[p].assign(nf, 1.0);
    for (size_t f = 0; f < nf; ++f) {
      const int n =
          surface_points_per_side(face_area_texels(prims[p].source_uv, uint32_t(f), 1, 1) * source_texels);
      out.side[p][f] = n;
      total += uint64_t(n) * n;
      // By 3D area: the face's points together weigh the texels its
      // surface would hold at the mean density, not the n^2 they stand for.
      if (f < prims[p].face_area_uv.size())
        out.weight[p][f] = double(prims[p].face_area_uv[f]) * source_texels / (double(n) * n);
    }
  }
  if (total > max_points) {
    const double shrink = std::sqrt(double(std::max<uint64_t>(1, max_points)) / double(total));
    for (size_t p = 0; p < prims.size(); ++p)
      for (size_t f = 0; f < out.side[p].size(); ++f) {
        const int n = out.side[p][f], thinned = std::max(1, int(std::floor(n * shrink)));
        out.side[p][f] = thinned;
        out.weight[p][f] *= double(n) * n / (double(thinned) * thinned);
      }
  }
  for (uint32_t p = 0; p < prims.size(); ++p)
    for (size_t f = 0; f < out.side[p].size(); ++f) out.faces.push_back({p, uint32_t(f)});
  return out;
}

SurfaceError surface_error(const TextureSampler& source, const TextureSampler& atlas,
                           std::span<const SurfaceUvs> prims, uint64_t max_points,
                           std::vector<SurfaceError>* per_group, SourceSamples* cache) {
  SurfaceError e;
  if (!source.ok || !atlas.ok) return e;
  const auto& spec = source.pixels.spec();
  const auto& t = source.transform;
  const double texels = double(spec.width) * spec.height * std::abs(t[0] * t[4] - t[1] * t[3]);
  const int channels = std::min({3, source.channels(), atlas.channels()});
  // Points per face first, to spread a capped budget evenly over the faces.
  const FaceSampling sampling = sample_faces(prims, texels, max_points);
  const std::vector<SampledFace>& faces = sampling.faces;
  const std::vector<std::vector<int>>& side = sampling.side;
  const std::vector<std::vector<double>>& weight = sampling.weight;
  std::vector<SurfaceError> measured(faces.size());
  // Each primitive's cached faces, made before the faces run side by side
  // (each face then writes only its own entry).
  std::vector<std::vector<SourceSamples::Face>*> cached(prims.size(), nullptr);
  if (cache)
    for (size_t p = 0; p < prims.size(); ++p) {
      auto& entry = cache->prims[{prims[p].source_uv.data(), prims[p].source_uv.size()}];
      entry.resize(std::max(entry.size(), side[p].size()));
      cached[p] = &entry;
    }
  const size_t source_channels = size_t(std::max(1, source.channels()));
  OIIO::parallel_for_range(uint64_t(0), uint64_t(faces.size()), [&](uint64_t begin, uint64_t end) {
    std::vector<float> a(source_channels), b(size_t(std::max(1, atlas.channels())));
    for (uint64_t i = begin; i < end; ++i) {
      const auto [p, f] = faces[i];
      const float* s = &prims[p].source_uv[6 * size_t(f)];
      const float* d = &prims[p].atlas_uv[6 * size_t(f)];
      SurfaceError& face = measured[i];
      face = {};
      const int n = side[p][f];
      SourceSamples::Face* kept = cached[p] ? &(*cached[p])[f] : nullptr;
      const bool known = kept && kept->side == n;
      if (kept && !known) {
        kept->side = n;
        kept->values.resize(size_t(n) * n * source_channels);
      }
      size_t point = 0;
      for_each_surface_point(n, [&](double w0, double w1, double w2) {
        const float* src = a.data();
        if (known) {
          src = &kept->values[point * source_channels];
        } else {
          source.sample(w0 * s[0] + w1 * s[2] + w2 * s[4], w0 * s[1] + w1 * s[3] + w2 * s[5], a.data());
          if (kept) std::copy(a.begin(), a.end(), kept->values.begin() + ptrdiff_t(point * source_channels));
        }
        ++point;
        atlas.sample(w0 * d[0] + w1 * d[2] + w2 * d[4], w0 * d[1] + w1 * d[3] + w2 * d[5], b.data());
        for (int c = 0; c < channels; ++c) {
          const double diff = 255.0 * (double(src[c]) - b[c]);
          face.squared += diff * diff;
        }
        face.values += channels;
        face.points++;
      });
      face.squared *= weight[p][f], face.values *= weight[p][f];
    }
  });
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto [p, f] = faces[i];
    const SurfaceError& face = measured[i];
    e.add(face);
    const auto& groups = prims[p].group_of_face;
    if (per_group && f < groups.size()) {
      if (groups[f] >= per_group->size()) per_group->resize(size_t(groups[f]) + 1);
      (*per_group)[groups[f]].add(face);
    }
  }
  return e;
}

}  // namespace gltfwarp
