// How faithfully an atlas reproduces its source on the surface: the encoder's
// own check of a warp, before it commits to implicit UVs.
//
// The measure is the one `gltf-warp compare` and the benchmark report: at
// about one point per source texel of every face, the source texture at the
// source UV against the atlas at the new UV, both sampled as a viewer does
// (texture_sampler.h), colour channels, 8-bit scale.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "codec/encode/texture/texture_sampler.h"

namespace gltfwarp {

struct SurfaceError {
  // Both sums weight each point by the surface it stands for: 1, unless a
  // point budget thinned a face's points (sample_faces), so that a thinned
  // measure estimates the full one.
  double squared = 0;   // sum of squared channel differences, 0..255 scale
  double values = 0;    // channel values compared
  uint64_t points = 0;  // points actually sampled (unweighted: the work done)
  double psnr() const;  // 10 log10(255^2 / MSE); 99 when identical, 0 when nothing was compared
  void add(const SurfaceError& o) { squared += o.squared, values += o.values, points += o.points; }
};

// One primitive: per-corner UVs of the same faces (3 corners per face).
struct SurfaceUvs {
  std::span<const float> source_uv;  // as the source slot samples (its transform is the sampler's)
  std::span<const float> atlas_uv;
  // Optional, one per face: the error of each face also goes to
  // per_group[group_of_face[f]] (e.g. per patch), when per_group is given.
  std::span<const uint32_t> group_of_face;
  // Optional, one per face: the UV area (in UV units, as source_uv's) the
  // face would cover at its group's mean texels per 3D area. Given, a face
  // weighs that many texels' worth instead of the texels it holds: the
  // mean is then over the 3D surface (EncodeOptions::quality_weight).
  std::span<const float> face_area_uv;
};

// The source's side of a measurement, kept for the next measurement of the
// same faces: only the atlas side changes from one layout to the next, and
// rate control measures one group dozens of times (the truck at a 44 dB
// target: 83 measurements, half their time in sampling the source, an sRGB
// conversion per channel). Per primitive (by the address and length of its
// source UVs, which must outlive the cache), per face: the points' source
// values at the side they were sampled with.
struct SourceSamples {
  struct Face {
    int side = 0;
    std::vector<float> values;  // side^2 points, the source's channels each
  };
  std::map<std::pair<const float*, size_t>, std::vector<Face>> prims;
};

// Compares `atlas` at atlas_uv with `source` at source_uv over every face of
// every primitive. At most about max_points points: on larger meshes every
// face gets fewer points, weighted up to its full share. With `cache` (for
// this one source sampler), the source is sampled only where it holds no
// values yet; the figures are the same bits either way.
SurfaceError surface_error(const TextureSampler& source, const TextureSampler& atlas,
                           std::span<const SurfaceUvs> prims, uint64_t max_points = 4'000'000,
                           std::vector<SurfaceError>* per_group = nullptr, SourceSamples* cache = nullptr);

// A face both measures sample: its primitive and its index there.
struct SampledFace {
  uint32_t prim, face;
};
// Where both measures sample: points per side of every face
// (surface_points_per_side of its source area in texels), every face over
// the primitives in order. Over a budget of max_points, each face's side
// shrinks by the same factor (to one point, its centroid, at least) and its
// points weigh what the full count would: n^2 / side^2.
// Every face, not every k-th: the error of a warp sits in few faces (on
// the truck 1% of them carry 40% of it), and a stride can step over all of
// them (WarpQuality.ThinnedMeasureFindsErrorInFewFaces: 99 dB where every
// face measures 24 dB). The measures sample the faces in parallel and sum
// them in this order, so their figures do not depend on the thread count.
struct FaceSampling {
  std::vector<std::vector<int>> side;       // per primitive, per face: points per side to sample
  std::vector<std::vector<double>> weight;  // per primitive, per face: each point's weight (>= 1)
  std::vector<SampledFace> faces;
};
FaceSampling sample_faces(std::span<const SurfaceUvs> prims, double source_texels, uint64_t max_points);

}  // namespace gltfwarp
