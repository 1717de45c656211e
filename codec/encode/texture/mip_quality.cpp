// Surface quality at MIP levels 0-3 and in the worst region (see mip_quality.h).
#include "codec/encode/texture/mip_quality.h"

#include <algorithm>
#include <cmath>

#include <OpenImageIO/parallel.h>

#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/texture/texel_reach.h"

namespace gltfwarp {

void MipQuality::add(const MipQuality& o) {
  for (int l = 0; l < kMipLevels; ++l) {
    const bool mine = level[l].values > 0, theirs = o.level[l].values > 0;
    worst_psnr[l] =
        mine && theirs ? std::min(worst_psnr[l], o.worst_psnr[l]) : (mine ? worst_psnr[l] : o.worst_psnr[l]);
    level[l].add(o.level[l]);
  }
}

std::vector<TextureSampler> mip_chain(TextureSampler s, int levels) {
  std::vector<TextureSampler> chain;
  chain.reserve(size_t(std::max(levels, 1)));
  chain.push_back(std::move(s));
  if (!chain[0].ok) return chain;
  while (int(chain.size()) < levels) {
    const TextureSampler& up = chain.back();
    const int w = up.pixels.spec().width, h = up.pixels.spec().height, nch = up.channels();
    if (w == 1 && h == 1) break;
    const int dw = std::max(1, w / 2), dh = std::max(1, h / 2);
    // The level's settings, not its texels (copying those would copy the level).
    TextureSampler down;
    down.wrap_s = up.wrap_s, down.wrap_t = up.wrap_t;
    down.srgb = up.srgb;
    down.transform = up.transform;
    down.ok = up.ok;
    down.pixels.reset(OIIO::ImageSpec(dw, dh, nch, OIIO::TypeDesc::FLOAT));
    const float* src = static_cast<const float*>(up.pixels.localpixels());
    float* dst = static_cast<float*>(down.pixels.localpixels());
    OIIO::parallel_for(0, dh, [&](int y) {
      for (int x = 0; x < dw; ++x)
        for (int c = 0; c < nch; ++c) {
          double sum = 0;
          for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
              const int sx = std::min(w - 1, 2 * x + i), sy = std::min(h - 1, 2 * y + j);
              sum += src[(size_t(sy) * w + sx) * nch + c];
            }
          dst[(size_t(y) * dw + x) * nch + c] = float(sum / 4);
        }
    });
    chain.push_back(std::move(down));
  }
  return chain;
}

namespace {

// PSNR over the worst groups holding `fraction` of the values.
double worst_region_psnr(std::vector<SurfaceError> groups, double fraction) {
  // Groups with nothing measured (ids no measured face has: texel copies,
  // zero-area faces) leave first. Against the cross-multiplied order below
  // an empty group is equal to every group, so that is no strict weak
  // order: with them in, std::sort may rank a clean patch first and the
  // worst region reads 99 dB over a crack (MipQuality.*WorstRegion*).
  std::erase_if(groups, [](const SurfaceError& g) { return !(g.values > 0); });
  double total = 0;
  for (const SurfaceError& g : groups) total += g.values;
  if (!(total > 0)) return 0;
  std::sort(groups.begin(), groups.end(), [](const SurfaceError& a, const SurfaceError& b) {
    return a.squared * b.values > b.squared * a.values;  // highest MSE first
  });
  SurfaceError worst;
  for (const SurfaceError& g : groups) {
    worst.add(g);
    if (worst.values >= fraction * total) break;
  }
  return worst.psnr();
}

// A chain sampled at a fractional LOD: bilinear in the two nearest levels, blended.
void trilinear(std::span<const TextureSampler> chain, double lod, double u, double v, int channels,
               float* out, float* scratch) {
  const int l0 = int(std::floor(lod)), l1 = std::min(int(chain.size()) - 1, l0 + 1);
  const float frac = float(lod - l0);
  chain[size_t(l0)].sample(u, v, out);
  if (frac > 0 && l1 != l0) {
    chain[size_t(l1)].sample(u, v, scratch);
    for (int c = 0; c < channels; ++c) out[c] = (1 - frac) * out[c] + frac * scratch[c];
  }
}

}  // namespace

std::vector<TextureSampler> mip_reference(const TextureSampler& source, std::span<const float> reach_faces) {
  if (!source.ok) return {};
  const auto& sspec = source.pixels.spec();
  const int src_levels = 1 + int(std::ceil(std::log2(std::max(1, std::max(sspec.width, sspec.height)))));
  // Filled, so that the source's own chart bleed is not counted.
  return mip_chain(with_unreached_filled(source, reach_faces), std::min(src_levels, 16));
}

MipQuality mip_surface_error(const TextureSampler& source, const TextureSampler& atlas,
                             std::span<const SurfaceUvs> prims, const MipQualityOptions& options) {
  std::vector<float> source_faces;
  for (const SurfaceUvs& p : prims)
    source_faces.insert(source_faces.end(), p.source_uv.begin(), p.source_uv.end());
  return mip_surface_error(mip_reference(source, source_faces), atlas, prims, options);
}

MipQuality mip_surface_error(std::span<const TextureSampler> schain, const TextureSampler& atlas,
                             std::span<const SurfaceUvs> prims, const MipQualityOptions& options) {
  MipQuality q;
  if (schain.empty() || !schain[0].ok || !atlas.ok) return q;
  const TextureSampler& source = schain[0];
  const auto& sspec = source.pixels.spec();
  const auto& t = source.transform;
  const double src_texels = double(sspec.width) * sspec.height * std::abs(t[0] * t[4] - t[1] * t[3]);
  const auto& at = atlas.transform;  // identity for an atlas page; a source's own for a source's form
  const double atlas_texels = double(atlas.pixels.spec().width) * atlas.pixels.spec().height *
                              std::abs(at[0] * at[4] - at[1] * at[3]);
  const int atlas_side = std::max(atlas.pixels.spec().width, atlas.pixels.spec().height);
  const std::vector<TextureSampler> achain =
      mip_chain(atlas, 1 + int(std::ceil(std::log2(std::max(1, atlas_side)))));
  const int channels = std::min({3, source.channels(), atlas.channels()});
  // Each level measures the sampled faces in parallel, each into its own
  // slot, then sums them in order.
  const FaceSampling sampling = sample_faces(prims, src_texels, options.max_points);
  const std::vector<SampledFace>& faces = sampling.faces;
  const std::vector<std::vector<int>>& side = sampling.side;
  const std::vector<std::vector<double>>& weight = sampling.weight;
  std::vector<SurfaceError> measured(faces.size());
  std::vector<uint8_t> in_atlas(faces.size());
  for (int l = 0; l < kMipLevels; ++l) {
    OIIO::parallel_for_range(uint64_t(0), uint64_t(faces.size()), [&](uint64_t begin, uint64_t end) {
      float a[4], a2[4], b[4];
      for (uint64_t i = begin; i < end; ++i) {
        const auto [p, f] = faces[i];
        measured[i] = {};
        in_atlas[i] = 0;
        const float* s = prims[p].source_uv.data() + 6 * size_t(f);
        const float* d = prims[p].atlas_uv.data() + 6 * size_t(f);
        // Areas in UV units (a 1 x 1 image), then in texels.
        const double sa = face_area_texels(prims[p].source_uv, f, 1, 1) * src_texels;
        const double da = face_area_texels(prims[p].atlas_uv, f, 1, 1) * atlas_texels;
        if (!(da > 0)) continue;
        in_atlas[i] = 1;
        // Level l: a screen footprint of 2^l texels of the finer grid; each
        // side at its own LOD there (trilinear), so level 0 magnifies both (the plain surface PSNR).
        const double rho = 0.5 * std::log2(std::max(sa, 1e-30) / da);  // log2 source texels per atlas texel
        const double slod = std::clamp(l + std::max(0.0, rho), 0.0, double(schain.size() - 1));
        const double alod = std::clamp(l + std::max(0.0, -rho), 0.0, double(achain.size() - 1));
        SurfaceError& face = measured[i];
        for_each_surface_point(side[p][f], [&](double w0, double w1, double w2) {
          const double us = w0 * s[0] + w1 * s[2] + w2 * s[4], vs = w0 * s[1] + w1 * s[3] + w2 * s[5];
          trilinear(schain, slod, us, vs, channels, a, a2);
          trilinear(achain, alod, w0 * d[0] + w1 * d[2] + w2 * d[4], w0 * d[1] + w1 * d[3] + w2 * d[5],
                    channels, b, a2);
          for (int c = 0; c < channels; ++c) {
            const double diff = 255.0 * (double(a[c]) - b[c]);
            face.squared += diff * diff;
          }
          face.values += channels;
          face.points++;
        });
        face.squared *= weight[p][f], face.values *= weight[p][f];
      }
    });
    std::vector<SurfaceError> groups;
    for (size_t i = 0; i < faces.size(); ++i) {
      const auto [p, f] = faces[i];
      if (!in_atlas[i]) continue;
      const SurfaceError& face = measured[i];
      q.level[l].add(face);
      const auto& g = prims[p].group_of_face;
      if (f < g.size()) {
        if (g[f] >= groups.size()) groups.resize(size_t(g[f]) + 1);
        groups[g[f]].add(face);
      } else {
        groups.push_back(face);
      }
    }
    q.worst_psnr[l] = worst_region_psnr(std::move(groups), options.worst_fraction);
  }
  return q;
}

}  // namespace gltfwarp
