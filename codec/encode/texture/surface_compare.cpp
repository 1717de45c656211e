#include "codec/encode/texture/surface_compare.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <OpenImageIO/imagebuf.h>

#include "codec/core/corner_match.h"
#include "codec/core/mesh.h"
#include "codec/encode/texture/texture_sampler.h"
#include "format/gltf/gltf_materials.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {
namespace {

// The slot's texture as a viewer samples it, or ok = false.
TextureSampler slot_sampler(const tinygltf::Model& m, int material, const std::string& key) {
  TextureSampler s;
  for (const auto& slot : texture_slots(m, material)) {
    if (slot.name() != key || slot.tex_coord != 0) continue;
    load_slot_sampler(m, slot, s);
    return s;
  }
  return s;
}

// Lambert shading (N.L, clamped) under three fixed lights of the tangent-space
// normal in rgb[0..2] (0..1 encoded), in the frame a viewer builds at
// barycentric w of the face whose vertices are corners[0..2] of tris:
// normalize(T), w_sign * cross(N, T), normalize(N). Overwrites rgb[0..2].
void lambert(const VertexAttribute& normal, const VertexAttribute& tangent, const std::vector<uint32_t>& tris,
             const uint32_t corners[3], const double w[3], float* rgb) {
  double n[3] = {0, 0, 0}, t[3] = {0, 0, 0}, sign = 0;
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = tris[corners[k]];
    for (int i = 0; i < 3; ++i) n[i] += w[k] * normal.get(v, i), t[i] += w[k] * tangent.get(v, i);
    sign += w[k] * tangent.get(v, 3);
  }
  auto unit = [](double* x) {
    const double l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    if (l > 0) x[0] /= l, x[1] /= l, x[2] /= l;
  };
  unit(n);
  unit(t);
  const double s = sign < 0 ? -1 : 1;
  const double b[3] = {s * (n[1] * t[2] - n[2] * t[1]), s * (n[2] * t[0] - n[0] * t[2]),
                       s * (n[0] * t[1] - n[1] * t[0])};
  double m[3];
  for (int i = 0; i < 3; ++i)
    m[i] = t[i] * (2.0 * rgb[0] - 1) + b[i] * (2.0 * rgb[1] - 1) + n[i] * (2.0 * rgb[2] - 1);
  unit(m);
  // Lights around the surface's own normal (so either side of a double-sided
  // model is lit alike) in a frame built from the normal and a world axis
  // only: the tangents differ between the files, the lights must not.
  const double axis[3] = {std::abs(n[1]) < 0.9 ? 0.0 : 1.0, std::abs(n[1]) < 0.9 ? 1.0 : 0.0, 0.0};
  double u[3] = {axis[1] * n[2] - axis[2] * n[1], axis[2] * n[0] - axis[0] * n[2],
                 axis[0] * n[1] - axis[1] * n[0]};
  unit(u);
  const double v[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
  static const double lights[3][3] = {{0.0, 0.0, 1.0}, {0.6, 0.0, 0.8}, {0.0, -0.6, 0.8}};
  for (int l = 0; l < 3; ++l) {
    double dir[3];
    for (int i = 0; i < 3; ++i) dir[i] = lights[l][0] * u[i] + lights[l][1] * v[i] + lights[l][2] * n[i];
    rgb[l] = float(std::max(0.0, m[0] * dir[0] + m[1] * dir[1] + m[2] * dir[2]));
  }
}

// Where a decoded primitive's faces come from: one source primitive when
// the meshes have as many primitives, else every textured primitive of the
// source mesh (the encoder cut one into parts, one per atlas page), joined
// into one geometry so each decoded face finds its own source face.
struct SourceSide {
  PrimitiveGeometry geom;          // POSITION, TEXCOORD_0 and, when all have them, NORMAL, TANGENT
  std::vector<size_t> first_face;  // per candidate, then the total face count
  std::vector<const TextureSampler*> samplers;  // per candidate
  double tolerance = 0;                         // position match tolerance
  size_t candidate_of_face(size_t f) const {
    return size_t(std::upper_bound(first_face.begin(), first_face.end(), f) - first_face.begin()) - 1;
  }
};

// Joins the candidates (their geometries and samplers); false when none has
// the attributes a comparison needs.
bool join_sources(const std::vector<const PrimitiveGeometry*>& geoms,
                  const std::vector<const TextureSampler*>& samplers, SourceSide& out) {
  static const char* const kSemantics[] = {"POSITION", "TEXCOORD_0", "NORMAL", "TANGENT"};
  static const int kComponents[] = {3, 2, 3, 4};
  std::vector<float> values[4];
  bool present[4] = {true, true, true, true};
  for (const PrimitiveGeometry* g : geoms)
    for (int s = 0; s < 4; ++s) {
      const VertexAttribute* a = g->find(kSemantics[s]);
      if (!a || a->components < kComponents[s]) present[s] = false;
    }
  if (!present[0] || !present[1]) return false;
  out.first_face.clear();
  size_t vertices = 0;
  for (size_t c = 0; c < geoms.size(); ++c) {
    const PrimitiveGeometry& g = *geoms[c];
    out.first_face.push_back(out.geom.triangles.size() / 3);
    for (uint32_t v : g.triangles) out.geom.triangles.push_back(uint32_t(vertices + v));
    for (int s = 0; s < 4; ++s) {
      if (!present[s]) continue;
      const VertexAttribute& a = *g.find(kSemantics[s]);
      for (size_t e = 0; e < a.count(); ++e)
        for (int i = 0; i < kComponents[s]; ++i) values[s].push_back(a.get(e, i));
    }
    vertices += g.vertex_count();
  }
  out.first_face.push_back(out.geom.triangles.size() / 3);
  for (int s = 0; s < 4; ++s)
    if (present[s])
      out.geom.attributes.push_back(VertexAttribute::from_floats(kSemantics[s], kComponents[s], values[s]));
  out.samplers = samplers;
  // Tolerance: a Draco 14-bit step of the model's extent, generously.
  double lo = 1e300, hi = -1e300;
  for (float x : values[0]) lo = std::min<double>(lo, x), hi = std::max<double>(hi, x);
  out.tolerance = (hi - lo) / 16383.0 * 2.0 + 1e-9;
  return true;
}

}  // namespace

SurfaceComparison compare_surface(const tinygltf::Model& src, const tinygltf::Model& dec,
                                  const SurfaceCompareOptions& options) {
  SurfaceComparison r;
  double sq = 0, weight = 0;
  if (src.meshes.size() != dec.meshes.size()) {
    r.error = "the scenes have different mesh counts";
    return r;
  }
  for (size_t mi = 0; mi < src.meshes.size(); ++mi) {
    const auto& sprims = src.meshes[mi].primitives;
    const auto& dprims = dec.meshes[mi].primitives;
    // The encoder appends the parts of a primitive it cut after the mesh's
    // own primitives; anything else is another scene.
    if (dprims.size() < sprims.size()) {
      r.error = "mesh " + std::to_string(mi) + " has a different primitive count";
      return r;
    }
    const bool cut = dprims.size() > sprims.size();
    // Source primitives read once: geometry and slot sampler.
    std::vector<PrimitiveGeometry> sgeom(sprims.size());
    std::vector<TextureSampler> ssampler(sprims.size());
    std::vector<uint8_t> usable(sprims.size(), 0);
    for (size_t pi = 0; pi < sprims.size(); ++pi) {
      const auto& sp = sprims[pi];
      if (!is_triangle_mode(sp.mode) || (!cut && !is_triangle_mode(dprims[pi].mode))) continue;
      ssampler[pi] = slot_sampler(src, sp.material, options.slot);
      usable[pi] = ssampler[pi].ok && read_primitive(src, sp, sgeom[pi]).empty();
    }
    // The source side of decoded primitive d: its own source primitive, or
    // with a cut every source primitive, joined once for all of them.
    auto join = [&](size_t first, size_t last, SourceSide& side) {
      std::vector<const PrimitiveGeometry*> geoms;
      std::vector<const TextureSampler*> samplers;
      for (size_t pi = first; pi < last; ++pi)
        if (usable[pi]) geoms.push_back(&sgeom[pi]), samplers.push_back(&ssampler[pi]);
      return !geoms.empty() && join_sources(geoms, samplers, side);
    };
    SourceSide all_sources;
    const bool all_joined = cut && join(0, sprims.size(), all_sources);
    for (size_t di_index = 0; di_index < dprims.size(); ++di_index) {
      const auto& dp = dprims[di_index];
      if (!is_triangle_mode(dp.mode)) continue;
      SourceSide single;
      if (cut ? !all_joined : !join(di_index, di_index + 1, single)) continue;
      const SourceSide& side = cut ? all_sources : single;
      const TextureSampler di = slot_sampler(dec, dp.material, options.slot);
      if (!di.ok) continue;
      PrimitiveGeometry dg;
      if (!read_primitive(dec, dp, dg).empty()) continue;
      const PrimitiveGeometry& sg = side.geom;
      const VertexAttribute *spos = sg.find("POSITION"), *dpos = dg.find("POSITION");
      const VertexAttribute *suv = sg.find("TEXCOORD_0"), *duv = dg.find("TEXCOORD_0");
      if (!dpos || !duv) continue;
      const CornerMatch match =
          match_corners(spos->to_floats(), sg.triangles, dpos->to_floats(), dg.triangles, side.tolerance);
      // Lit: the normal map's effect under three lights, through each file's
      // own normals and tangents (the decoded ones are rebuilt from new UVs).
      const VertexAttribute *sn = sg.find("NORMAL"), *st = sg.find("TANGENT");
      const VertexAttribute *dn = dg.find("NORMAL"), *dt = dg.find("TANGENT");
      const bool lit = options.lit;
      if (lit && (!sn || !st || !dn || !dt || dt->components != 4 || di.channels() < 3)) continue;
      r.unmatched_faces += match.unmatched_faces;
      r.primitives++;
      std::vector<float> b(static_cast<size_t>(std::max(3, di.pixels.nchannels())));
      const bool by_area = options.weight == SampleWeight::surface_area;
      const std::vector<float> source_xyz = by_area ? spos->to_floats() : std::vector<float>{};
      for (size_t f = 0; f < dg.triangles.size() / 3; ++f) {
        const uint32_t sc0 = match.source_corner[3 * f];
        if (sc0 == 0 && match.source_corner[3 * f + 1] == 0) continue;  // unmatched
        const TextureSampler& si = *side.samplers[side.candidate_of_face(sc0 / 3)];
        if (lit && si.channels() < 3) continue;
        const int nch = std::min(si.pixels.nchannels(), di.pixels.nchannels());
        const int channels =
            lit ? 3 : std::min(nch, 3);  // colour only; alpha is compared by its effect elsewhere
        std::vector<float> a(static_cast<size_t>(std::max(3, si.pixels.nchannels())));
        const double src_texels =
            double(si.pixels.spec().width) * si.pixels.spec().height *
            std::abs(si.transform[0] * si.transform[4] - si.transform[1] * si.transform[3]);
        double su[3], sv[3], du[3], dv[3];
        uint32_t source_vertex[3];
        for (int c = 0; c < 3; ++c) {
          const uint32_t sv_id = source_vertex[c] = sg.triangles[match.source_corner[3 * f + c]];
          const uint32_t dv_id = dg.triangles[3 * f + c];
          su[c] = suv->get(sv_id, 0), sv[c] = suv->get(sv_id, 1);
          du[c] = duv->get(dv_id, 0), dv[c] = duv->get(dv_id, 1);
        }
        // surface_area: the face's 3D area (the source's), shared by its points below.
        const double face_area = by_area ? triangle_area3(source_xyz.data(), source_vertex) : 1.0;
        double point_weight = 1;
        auto visit = [&](double w0, double w1, double w2) {
          si.sample(w0 * su[0] + w1 * su[1] + w2 * su[2], w0 * sv[0] + w1 * sv[1] + w2 * sv[2], a.data());
          di.sample(w0 * du[0] + w1 * du[1] + w2 * du[2], w0 * dv[0] + w1 * dv[1] + w2 * dv[2], b.data());
          if (lit) {
            const double w[3] = {w0, w1, w2};
            lambert(*sn, *st, sg.triangles, &match.source_corner[3 * f], w, a.data());
            const uint32_t own[3] = {uint32_t(3 * f), uint32_t(3 * f + 1), uint32_t(3 * f + 2)};
            lambert(*dn, *dt, dg.triangles, own, w, b.data());
          }
          for (int c = 0; c < channels; ++c) {
            const double d = 255.0 * (a[c] - b[c]);
            sq += d * d * point_weight;
            weight += point_weight;
            r.max_abs = std::max(r.max_abs, std::abs(d));
          }
          r.samples++;
        };
        if (options.samples_per_face > 0) {
          if (by_area) point_weight = face_area / options.samples_per_face;
          for (int s = 0; s < options.samples_per_face; ++s) {
            // Interior points spread over the triangle (low-discrepancy weights).
            const double u = (s + 0.5) / options.samples_per_face, v = std::fmod(0.618034 * (s + 1), 1.0);
            visit(1 - std::sqrt(u), std::sqrt(u) * (1 - v), std::sqrt(u) * v);
          }
        } else {
          const double area =
              0.5 * std::abs((su[1] - su[0]) * (sv[2] - sv[0]) - (su[2] - su[0]) * (sv[1] - sv[0]));
          const int side_points = surface_points_per_side(area * src_texels);
          if (by_area) point_weight = face_area / (double(side_points) * side_points);
          for_each_surface_point(side_points, visit);
        }
      }
    }
  }
  if (weight == 0) {
    r.error = r.samples > 0 ? "the textured faces have no surface area to weigh"
                            : "no textured primitive to compare";
    return r;
  }
  r.rmse = std::sqrt(sq / weight);
  r.psnr = r.rmse > 0 ? 20.0 * std::log10(255.0 / r.rmse) : std::numeric_limits<double>::infinity();
  return r;
}

}  // namespace gltfwarp
