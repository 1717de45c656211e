#include "codec/encode/implicit_uv_encoder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <set>

#include "codec/core/corner_match.h"
#include "codec/core/parallel.h"
#include "codec/decode/embedding_mesh.h"
#include "codec/encode/atlas/pack.h"
#include "codec/encode/atlas/pages.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/cut_primitive.h"
#include "codec/encode/partition/embed.h"
#include "codec/encode/partition/source_charts.h"
#include "codec/encode/partition/twin_partition.h"
#include "codec/encode/source_chart_measures.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/seam_continuity.h"
#include "codec/encode/texture/texture_sampler.h"
#include "codec/encode/texture/warp.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "format/gltf/draco_geometry.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_materials.h"

namespace gltfwarp {

namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

// The primitive keeps explicit UVs after all: it gets its own copy of its
// material (the original is warped for the group's other members, if any)
// and leaves the plan. pr.fallback says why; the caller writes the geometry.
Error fall_back(tinygltf::Model& model, tinygltf::Primitive& prim, ImplicitPlan& plan, PrimitiveReport& pr,
                FallbackReason why, LayoutStatus layout = LayoutStatus::ok) {
  for (const int material : primitive_materials(prim))
    if (static_cast<size_t>(material) < model.materials.size()) {
      model.materials.push_back(model.materials[material]);
      replace_primitive_material(prim, material, static_cast<int>(model.materials.size() - 1));
    }
  plan.group_of.erase({pr.mesh, pr.primitive});
  pr.handling = Handling::fallback;
  pr.fallback = Fallback{};
  pr.fallback.reason = why;
  pr.fallback.layout = layout;
  return {};
}

}  // namespace

std::vector<TextureSlot> primitive_uv0_slots(const tinygltf::Model& model, const tinygltf::Primitive& prim) {
  std::vector<TextureSlot> out;
  for (const int material : primitive_materials(prim))
    for (TextureSlot& s : texture_slots(model, material))
      if (s.tex_coord == 0 && texture_image(model, s.texture) >= 0) out.push_back(std::move(s));
  return out;
}

// The primitive's TEXCOORD_0 textures (those of every material it can show)
// as a viewer samples them; empty when one cannot be read (the seam test
// then hides no seam).
std::vector<TextureSampler> uv0_samplers(const tinygltf::Model& model, const tinygltf::Primitive& prim) {
  std::vector<TextureSampler> out;
  for (const TextureSlot& slot : primitive_uv0_slots(model, prim)) {
    TextureSampler t;
    if (!load_slot_sampler(model, slot, t).empty()) return {};
    out.push_back(std::move(t));
  }
  return out;
}

Error plan_implicit_uvs(tinygltf::Model& model, ImplicitPlan& plan, EncodeReport& report) {
  // Images we can decode (others make their primitives keep explicit UVs).
  std::vector<int> decodable(model.images.size(), -1);
  auto image_ok = [&](int img) {
    if (decodable[img] < 0) {
      Note note;
      note.image = img;
      int w = 0, h = 0;
      // image_size reads KTX2 headers (for sizes), but only PNG/JPEG/WebP decode.
      if (sniff_image_codec(model.images[img].image) == ImageCodec::ktx2) {
        decodable[img] = 0;
        note.kind = NoteKind::image_ktx2;
      } else {
        decodable[img] = image_size(model.images[img].image, w, h, note.detail) ? 1 : 0;
        note.kind = NoteKind::image_not_decodable;
      }
      if (!decodable[img]) report.notes.push_back(note);
    }
    return decodable[img] == 1;
  };

  struct Candidate {
    int mesh, prim;
    std::vector<int> images;
  };
  std::vector<Candidate> cands;
  for (size_t mi = 0; mi < model.meshes.size(); ++mi)
    for (size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
      const auto& prim = model.meshes[mi].primitives[pi];
      if (!is_triangle_mode(prim.mode) || !prim.targets.empty() || !prim.attributes.count("TEXCOORD_0"))
        continue;
      if (!prim.attributes.count("POSITION")) continue;
      // A TEXCOORD_0 texture whose image we cannot reach or that also names
      // an image through an extension (KHR_texture_basisu, EXT_texture_webp,
      // ...) would keep sampling the old UVs: the primitive stays explicit.
      // Every material the primitive can show counts: its own and those of
      // its KHR_materials_variants, which all sample through the same UVs.
      const std::vector<int> materials = primitive_materials(prim);
      Note blocker;  // texture -1: none found
      blocker.mesh = static_cast<int>(mi);
      blocker.primitive = static_cast<int>(pi);
      for (const int material : materials) {
        for (const auto& s : texture_slots(model, material)) {
          if (s.tex_coord != 0 || s.texture < 0 || static_cast<size_t>(s.texture) >= model.textures.size())
            continue;
          const auto& tex = model.textures[s.texture];
          for (const auto& [name, ext] : tex.extensions)
            if (ext.IsObject() && ext.Has("source")) {
              blocker.kind = NoteKind::texture_in_extension;
              blocker.texture = s.texture;
              blocker.detail = name;
            }
          if (blocker.texture < 0 && texture_image(model, s.texture) < 0) {
            blocker.kind = NoteKind::texture_without_image;
            blocker.texture = s.texture;
          }
          if (blocker.texture >= 0) break;
        }
        if (blocker.texture >= 0) break;
      }
      if (blocker.texture >= 0) {
        report.notes.push_back(blocker);
        continue;
      }
      Candidate c{static_cast<int>(mi), static_cast<int>(pi), {}};
      bool ok = true;
      for (const auto& s : primitive_uv0_slots(model, prim)) {
        const int img = texture_image(model, s.texture);
        if (!image_ok(img)) ok = false;
        c.images.push_back(img);
      }
      if (ok && !c.images.empty()) cands.push_back(std::move(c));
    }
  if (cands.empty()) return {};

  // Primitives that share an image share an atlas.
  UnionFind uf(cands.size());
  std::map<int, size_t> first_user;
  for (size_t i = 0; i < cands.size(); ++i)
    for (int img : cands[i].images) {
      auto [it, inserted] = first_user.emplace(img, i);
      if (!inserted) uf.join(static_cast<int>(i), static_cast<int>(it->second));
    }
  std::map<int, int> group_index;
  for (size_t i = 0; i < cands.size(); ++i) {
    const int root = uf.find(static_cast<int>(i));
    auto [it, inserted] = group_index.emplace(root, static_cast<int>(plan.groups.size()));
    if (inserted) plan.groups.emplace_back();
    plan.group_of[{cands[i].mesh, cands[i].prim}] = it->second;
  }

  // A material used by an implicit primitive and by one that keeps explicit
  // UVs (as its own or as a variant) is cloned, so the explicit one keeps
  // the original textures.
  std::map<int, int> clone_of;
  for (size_t mi = 0; mi < model.meshes.size(); ++mi)
    for (size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
      if (plan.is_implicit(static_cast<int>(mi), static_cast<int>(pi))) continue;
      for (const int material : primitive_materials(model.meshes[mi].primitives[pi]))
        clone_of.emplace(material, -1);
    }
  for (auto& c : cands) {
    auto& prim = model.meshes[c.mesh].primitives[c.prim];
    for (const int material : primitive_materials(prim)) {
      auto it = clone_of.find(material);
      if (it == clone_of.end() || static_cast<size_t>(material) >= model.materials.size()) continue;
      if (it->second < 0) {
        model.materials.push_back(model.materials[material]);
        it->second = static_cast<int>(model.materials.size() - 1);
      }
      replace_primitive_material(prim, material, it->second);
    }
    auto& g = plan.groups[plan.group_of[{c.mesh, c.prim}]];
    for (const int material : primitive_materials(prim))
      if (static_cast<size_t>(material) < model.materials.size() &&
          std::find(g.materials.begin(), g.materials.end(), material) == g.materials.end())
        g.materials.push_back(material);
  }
  return {};
}

namespace {

constexpr size_t kHalveChartsFromFaces = 100'000;

// Repeats beyond which an atlas cannot pay (texel uses per stored texel),
// and the atlas size below which the full measurement is cheap enough to
// decide instead (one 2048^2 page).
constexpr double kMaxTexelRepeat = 4.0;
constexpr double kTexelsWorthJudging = 2048.0 * 2048.0;

struct TexelUse {
  double uses = 0;          // the faces' texel-space areas, each use counted
  double image_texels = 0;  // texels of the distinct images the slots sample
};

// How many texels the faces cover through TEXCOORD_0 (after each slot's
// transform, in the largest image) against the texels the images store.
TexelUse uv0_texel_use(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                       std::span<const float> source_corner_uv) {
  TexelUse use;
  uint32_t width = 0, height = 0;
  largest_uv0_image(model, prim, width, height);
  if (width == 0 || height == 0) return use;
  std::set<int> images;
  for (const auto& s : primitive_uv0_slots(model, prim)) images.insert(texture_image(model, s.texture));
  for (const int image : images) {
    int iw = 0, ih = 0;
    std::string err;
    if (image >= 0 && image_size(model.images[size_t(image)].image, iw, ih, err))
      use.image_texels += double(iw) * double(ih);
  }
  for (uint32_t f = 0; f < source_corner_uv.size() / 6; ++f) {
    const double area = face_area_texels(source_corner_uv, f, width, height);
    if (std::isfinite(area)) use.uses += area;
  }
  return use;
}

// The attribute's value at every corner of the geometry, `components` floats each.
std::vector<float> per_corner(const PrimitiveGeometry& geom, const VertexAttribute& a) {
  const auto n = size_t(a.components);
  std::vector<float> out(geom.triangles.size() * n);
  for (size_t c = 0; c < geom.triangles.size(); ++c)
    for (size_t i = 0; i < n; ++i) out[n * c + i] = a.get(geom.triangles[c], int(i));
  return out;
}

bool all_finite(std::span<const float> values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

float largest_magnitude(std::span<const float> values) {
  float m = 0;
  for (const float v : values) m = std::max(m, std::abs(v));
  return m;
}

// What the geometry becomes when it loses its UVs: TEXCOORD_0 goes, and so
// does TANGENT (derived from the old UVs; regenerated at decode), and the
// vertices that differed only there are welded.
void strip_source_uvs(PrimitiveGeometry& geom) {
  geom.erase("TEXCOORD_0");
  geom.erase("TANGENT");
  weld_vertices(geom.attributes, geom.triangles);
}

// Empty, or why the geometry's POSITION cannot be embedded.
std::string position_error(const PrimitiveGeometry& geom) {
  const VertexAttribute* pos = geom.find("POSITION");
  if (!pos || pos->components != 3) return "POSITION is not a VEC3";
  for (size_t e = 0; e < pos->count(); ++e)
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(pos->get(e, i))) return "POSITION holds a NaN or infinite value";
  return {};
}

// What prepare_partition needs from the model: the largest image the
// primitive samples, and the seam test's textures. Those stay in the plan
// for the next primitive of the same materials.
PartitionContext partition_context(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                   ImplicitPlan& plan, const EncodeOptions& options) {
  PartitionContext context;
  largest_uv0_image(model, prim, context.image_w, context.image_h);
  if (options.keep_source_charts && options.cross_hidden_seams && context.image_w > 0) {
    // A seam is hidden only if every material the primitive can show hides it.
    if (const std::vector<int> materials = primitive_materials(prim); plan.seam_materials != materials) {
      plan.seam_textures = uv0_samplers(model, prim);
      plan.seam_materials = materials;
    }
    context.seam_textures = plan.seam_textures;
  }
  return context;
}

bool same_geometry(const PrimitiveGeometry& a, const PrimitiveGeometry& b) {
  if (a.triangles != b.triangles || a.attributes.size() != b.attributes.size()) return false;
  for (size_t i = 0; i < a.attributes.size(); ++i) {
    const VertexAttribute &x = a.attributes[i], &y = b.attributes[i];
    if (x.semantic != y.semantic || x.component_type != y.component_type || x.components != y.components ||
        x.normalized != y.normalized || x.data != y.data)
      return false;
  }
  return true;
}

bool same_bits(std::span<const float> a, std::span<const float> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

// Moves out the prefetched partition of exactly this input (materials,
// geometry and source UVs, bit for bit), if there is one.
bool take_prefetched(ImplicitPlan& plan, const tinygltf::Primitive& prim, const PrimitiveGeometry& geom,
                     std::span<const float> source_corner_uv, PreparedPartition& out) {
  const std::vector<int> materials = primitive_materials(prim);
  for (auto it = plan.prefetched.begin(); it != plan.prefetched.end(); ++it)
    if (it->materials == materials && same_bits(it->source_corner_uv, source_corner_uv) &&
        same_geometry(it->geom, geom)) {
      out = std::move(it->prepared);
      plan.prefetched.erase(it);
      return true;
    }
  return false;
}

// The parts of a cut are prepared one by one by the encoder's loop, and a
// large part's partition takes seconds on one core (4-7 s each for the
// 1M-face sample's parts). Their partitions are prepared here side by side,
// largest first, while the model is only read; prepare_implicit_primitive
// takes each from plan.prefetched when its own inputs are the same, so a
// part the loop treats otherwise (a fallback, a second cut) costs time,
// never bytes.
void prefetch_partitions(const tinygltf::Model& model, int mesh, std::vector<int> parts, ImplicitPlan& plan,
                         const EncodeOptions& options) {
  const size_t workers = worker_count(parts.size());
  if (workers < 2 || !options.prefetch_partitions) return;
  const auto& prims = model.meshes[size_t(mesh)].primitives;
  const std::vector<int> materials = primitive_materials(prims[size_t(parts[0])]);
  // Taken before the workers start: it may load the seam test's textures.
  const PartitionContext context = partition_context(model, prims[size_t(parts[0])], plan, options);
  auto faces = [&](int p) {
    const tinygltf::Primitive& prim = prims[size_t(p)];
    return prim.indices >= 0 ? model.accessors[size_t(prim.indices)].count : 0;
  };
  std::stable_sort(parts.begin(), parts.end(), [&](int a, int b) { return faces(a) > faces(b); });
  std::vector<PrefetchedPartition> found(parts.size());
  std::vector<char> ready(parts.size(), 0);
  run_in_parallel(parts.size(), workers, [&](size_t i, size_t) {
    const tinygltf::Primitive& prim = prims[size_t(parts[i])];
    PrefetchedPartition& out = found[i];
    out.mesh = mesh;
    out.primitive = parts[i];
    out.materials = primitive_materials(prim);
    if (out.materials != materials || !read_primitive(model, prim, out.geom).empty()) return;
    const VertexAttribute* uv0 = out.geom.find("TEXCOORD_0");
    if (!uv0 || uv0->components != 2) return;
    out.source_corner_uv = per_corner(out.geom, *uv0);
    if (!all_finite(out.source_corner_uv) || largest_magnitude(out.source_corner_uv) > kMaxSourceUv) return;
    strip_source_uvs(out.geom);
    if (!position_error(out.geom).empty() || out.geom.triangles.empty()) return;
    out.prepared = prepare_partition(out.geom, out.source_corner_uv, context, options);
    ready[i] = 1;
  });
  for (size_t i = 0; i < parts.size(); ++i)
    if (ready[i]) plan.prefetched.push_back(std::move(found[i]));
}

// Part of each face when the source's texels alone pass one page (their
// TEXCOORD_0 area times the largest image, or the 3D area at a fixed
// density); empty otherwise. geom: the primitive as read_primitive gives it;
// source_corner_uv: its TEXCOORD_0 per corner.
std::vector<uint32_t> source_page_parts(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                        const PrimitiveGeometry& geom,
                                        std::span<const float> source_corner_uv,
                                        const EncodeOptions& options) {
  uint32_t width = 0, height = 0;
  largest_uv0_image(model, prim, width, height);
  const VertexAttribute* pos = geom.find("POSITION");
  // The layout stretches faces and the atlas matches the stretch (Duck: 1.27
  // times the source's count): parts sized for 70% of a page by the source's
  // count seldom need a second cut.
  const double capacity = 0.7 * page_capacity(options.max_atlas_size);
  if (options.max_pages <= 1 || width == 0 || !pos || pos->components != 3 || !(capacity > 0)) return {};
  TriMesh mesh;  // built only when needed: for 3D areas, and for the cut
  auto build_mesh = [&] {
    if (mesh.indices.empty()) mesh = TriMesh{pos->to_floats(), geom.triangles};
  };
  if (options.texel_density > 0) build_mesh();
  std::vector<double> texels(geom.triangles.size() / 3, 0.0);
  double total = 0;
  for (uint32_t f = 0; f < texels.size(); ++f) {
    const double area = options.texel_density > 0
                            ? face_area3d(mesh, f) * options.texel_density * options.texel_density
                            : face_area_texels(source_corner_uv, f, width, height) *
                                  options.texel_density_factor * options.texel_density_factor;
    texels[f] = std::isfinite(area) ? area : 0.0;
    total += texels[f];
  }
  if (!(total > capacity)) return {};
  build_mesh();
  // Halving a UV chart cuts through its texture: a new seam, where the cut
  // along patches after the partition adds none but embeds the mesh twice.
  // That second embedding only weighs on large meshes. Measured: a 3000-face
  // sphere at --max-atlas-size 256 is 38.4 dB halved, 41.7 cut along
  // patches; the 1M-face sample at 4096 encodes in 52 s halved, 81 s not.
  const bool halve = texels.size() >= kHalveChartsFromFaces;
  uint32_t parts = 0;
  std::vector<uint32_t> part_of_face = within_part_count(
      capacity, options.max_pages,
      [&](double c, uint32_t& n) { return split_faces_into_parts(mesh, texels, c, halve, n); }, parts);
  if (parts < 2) return {};
  return part_of_face;
}

// When the primitive's patches would take more texels than one page holds
// (at the density the atlas will give them, codec/encode/atlas/pages.h): the part of
// each source face (read_primitive order), grouping whole patches so the
// cut adds no seam. Empty: no cut (it fits, --max-pages 1, or one patch).
std::vector<uint32_t> page_parts(const ImplicitPrimitive& ip, const Embedding& er, const CornerMatch& match,
                                 size_t source_faces, uint32_t image_w, uint32_t image_h,
                                 const EncodeOptions& options) {
  if (options.max_pages <= 1 || image_w == 0 || er.patch_count < 2) return {};
  std::vector<double> face_density;
  const double factor = atlas_density(er.corner_xy, ip.source_uv, image_w, image_h, options, face_density);
  const auto texels =
      estimated_patch_texels(er.corner_xy, er.patch_of_face, er.patch_count, face_density, factor);
  double total = 0;
  for (double t : texels) total += t;
  const double capacity = page_capacity(options.max_atlas_size);
  if (!(capacity > 0) || !(total > capacity)) return {};
  uint32_t parts = 0;
  const std::vector<uint32_t> part_of_patch = within_part_count(
      capacity, options.max_pages,
      [&](double c, uint32_t& n) { return parts_of_patches(ip.tri, er.patch_of_face, texels, c, n); }, parts);
  if (parts < 2) return {};
  // Back to the source's faces. A source face no decoded face came from
  // (one Draco dropped as degenerate) goes to the first part.
  std::vector<uint32_t> part_of_face(source_faces, UINT32_MAX);
  for (size_t f = 0; f < er.patch_of_face.size(); ++f) {
    const uint32_t source_face = match.source_corner[3 * f] / 3;
    if (source_face >= source_faces) continue;
    uint32_t& part = part_of_face[source_face];
    if (part == UINT32_MAX) part = part_of_patch[er.patch_of_face[f]];
  }
  for (uint32_t& part : part_of_face)
    if (part == UINT32_MAX) part = 0;
  return part_of_face;
}

// Cuts the primitive (its source geometry `source`, one part per face) into
// parts appended to its mesh, records the cut (undo_fallen_back_cuts) and
// prepares the first part in its place; the encoder's loop reaches the
// others.
Error cut_and_prepare_first(tinygltf::Model& model, const PrimitiveGeometry& source,
                            std::span<const uint32_t> part_of_face, ImplicitPlan& plan,
                            const EncodeOptions& options, std::vector<int>& replaced, PrimitiveReport& pr) {
  const uint32_t parts = *std::max_element(part_of_face.begin(), part_of_face.end()) + 1;
  const int group = plan.group_of.at({pr.mesh, pr.primitive});
  PrimitiveCut cut{pr.mesh, pr.primitive, model.meshes[pr.mesh].primitives[pr.primitive], {}};
  cut.appended = cut_primitive(model, pr.mesh, pr.primitive, source, part_of_face, parts, replaced);
  for (int appended : cut.appended) plan.group_of[{pr.mesh, appended}] = group;
  // A part cut again before it took its prefetched partition never will.
  std::erase_if(plan.prefetched, [&](const PrefetchedPartition& p) {
    return p.mesh == pr.mesh && p.primitive == pr.primitive;
  });
  std::vector<int> part_primitives{pr.primitive};
  part_primitives.insert(part_primitives.end(), cut.appended.begin(), cut.appended.end());
  plan.cuts.push_back(std::move(cut));
  prefetch_partitions(model, pr.mesh, std::move(part_primitives), plan, options);
  tinygltf::Primitive& first = model.meshes[pr.mesh].primitives[pr.primitive];
  PrimitiveGeometry part;
  if (Error e = error_if(ErrorCode::invalid_input, read_primitive(model, first, part)); e.failed()) return e;
  pr.triangles = part.triangles.size() / 3;
  pr.vertices = part.vertex_count();
  pr.geometry_bytes = 0;
  pr.cut_parts = std::max(pr.cut_parts, parts);
  return prepare_implicit_primitive(model, first, part, plan, options, replaced, pr);
}

}  // namespace

Error prepare_implicit_primitive(tinygltf::Model& model, tinygltf::Primitive& prim, PrimitiveGeometry& geom,
                                 ImplicitPlan& plan, const EncodeOptions& options, std::vector<int>& replaced,
                                 PrimitiveReport& pr) {
  ImplicitPrimitive ip;
  ip.source_primitive = prim;
  ip.mesh = pr.mesh;
  ip.primitive = pr.primitive;
  ip.had_tangents = geom.find("TANGENT") != nullptr;
  const VertexAttribute* uv0 = geom.find("TEXCOORD_0");
  if (!uv0 || uv0->components != 2)
    return fall_back(model, prim, plan, pr, FallbackReason::texcoord_not_vec2);
  const std::vector<float> source_corner_uv = per_corner(geom, *uv0);
  if (!all_finite(source_corner_uv))
    return {ErrorCode::invalid_input, "TEXCOORD_0 holds a NaN or infinite value"};
  if (const float reach = largest_magnitude(source_corner_uv); reach > kMaxSourceUv) {
    const Error e = fall_back(model, prim, plan, pr, FallbackReason::texcoord_out_of_range);
    pr.fallback.max_source_uv = reach;
    return e;
  }
  // Draco quantizes float UVs only; integer ones it keeps as they are.
  const bool explicit_uv_quantized =
      !options.raw_geometry && uv0->component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
  // Tiled or repeated UVs (a cloth whose texture repeats 30 times through
  // KHR_texture_transform): the atlas would store each repeat, many times the
  // texels the source stores once, and explicit UVs win by far. Decided here,
  // from the UVs alone, before Draco, the partition and the warp, so such an
  // input costs seconds, not the minutes a 16-page atlas takes to warp.
  if (options.quality_fallback) {
    const TexelUse use = uv0_texel_use(model, prim, source_corner_uv);
    if (use.uses > kMaxTexelRepeat * use.image_texels && use.uses > kTexelsWorthJudging) {
      if (Error e = fall_back(model, prim, plan, pr, FallbackReason::texture_repeats); e.failed()) return e;
      pr.fallback.texel_uses = use.uses;
      pr.fallback.image_texels = use.image_texels;
      return {};
    }
  }
  // Clearly more texels than one atlas page holds, by the source's own
  // count: cut along the source's UV charts before the costly steps (Draco,
  // the partition), so each part is embedded once. What this estimate
  // misses (the layout's stretch) the cut along patches below catches.
  if (std::vector<uint32_t> part_of_face = source_page_parts(model, prim, geom, source_corner_uv, options);
      !part_of_face.empty())
    return cut_and_prepare_first(model, geom, part_of_face, plan, options, replaced, pr);
  // A source TANGENT is the frame viewers light the source's normal map in:
  // the warp re-expresses normals from it (else from MikkTSpace on the UVs).
  std::vector<float> source_corner_tangent;
  if (const VertexAttribute* tan = geom.find("TANGENT"); tan && tan->components == 4)
    source_corner_tangent = per_corner(geom, *tan);
  strip_source_uvs(geom);
  if (Error e = error_if(ErrorCode::invalid_input, position_error(geom)); e.failed()) return e;

  if (geom.triangles.empty()) return fall_back(model, prim, plan, pr, FallbackReason::no_triangles);

  // The costly half (Draco, the partition) is a pure function of the
  // geometry and the textures: prefetched for the parts of a cut.
  const PartitionContext context = partition_context(model, prim, plan, options);
  PreparedPartition prepared;
  if (!take_prefetched(plan, prim, geom, source_corner_uv, prepared))
    prepared = prepare_partition(geom, source_corner_uv, context, options);
  // Draco cannot carry it (an attribute it has no type for, or integers past
  // its tables): the primitive keeps its UVs, and the explicit path, which
  // meets the same refusal, passes it through as it came.
  if (!prepared.error.empty()) return fall_back(model, prim, plan, pr, FallbackReason::draco_refused);

  // The geometry is written to a trial copy of the primitive first: if the
  // embedding fails, the primitive falls back to explicit UVs untouched, and
  // whatever the trial appended is dropped by compact_buffers.
  tinygltf::Primitive trial = prim;
  std::vector<int> trial_replaced;
  const size_t accessors_before = model.accessors.size();
  if (options.raw_geometry) {
    write_primitive_plain(model, trial, geom, trial_replaced);
    pr.geometry_bytes += prepared.geometry_bytes;
  } else {
    attach_draco(model, trial, prepared.encoded, prepared.decoded, trial_replaced);
    pr.geometry_bytes = prepared.geometry_bytes;
  }
  ip.decoded = std::move(prepared.decoded);
  auto discard_trial = [&](FallbackReason why, LayoutStatus layout = LayoutStatus::ok) {
    for (size_t i = accessors_before; i < model.accessors.size(); ++i)
      replaced.push_back(static_cast<int>(i));
    pr.geometry_bytes = 0;
    return fall_back(model, prim, plan, pr, why, layout);
  };
  if (ip.decoded.triangles.empty()) return discard_trial(FallbackReason::no_triangles_after_draco);

  ip.tri = std::move(prepared.tri);
  ip.source_uv = std::move(prepared.source_uv);
  // Draco's range comes from the values the corners reference (a vertex no
  // triangle uses could widen it in the file; no corpus model has one).
  if (explicit_uv_quantized)
    ip.explicit_uv = draco_quantized(source_corner_uv, ip.source_uv, 2, options.draco.texcoord_bits);
  const CornerMatch& match = prepared.match;
  if (!source_corner_tangent.empty()) {
    ip.source_tangents.resize(ip.decoded.triangles.size() * 4);
    for (size_t c = 0; c < ip.decoded.triangles.size(); ++c)
      for (int i = 0; i < 4; ++i)
        ip.source_tangents[4 * c + i] = source_corner_tangent[4 * match.source_corner[c] + i];
  }
  TwinEmbedding& te = prepared.twins;
  Embedding& er = te.embedding;
  if (er.status != LayoutStatus::ok) return discard_trial(FallbackReason::embedding_failed, er.status);
  const uint32_t image_w = context.image_w, image_h = context.image_h;

  // Too many texels for one atlas page: cut along patch boundaries into
  // parts of about a page each, and start again on the first part (the
  // encoder's loop reaches the others, appended to the mesh).
  if (std::vector<uint32_t> part_of_face =
          page_parts(ip, er, match, geom.triangles.size() / 3, image_w, image_h, options);
      !part_of_face.empty()) {
    PrimitiveGeometry source;
    if (Error e = error_if(ErrorCode::invalid_input, read_primitive(model, ip.source_primitive, source));
        e.failed())
      return e;
    for (size_t i = accessors_before; i < model.accessors.size(); ++i)
      replaced.push_back(static_cast<int>(i));
    return cut_and_prepare_first(model, source, part_of_face, plan, options, replaced, pr);
  }

  // Commit: the trial becomes the primitive. TEXCOORD_0 stays declared,
  // without data, as KHR_draco_mesh_compression does with the attributes it
  // replaces: validators and loaders expect it.
  prim = std::move(trial);
  replaced.insert(replaced.end(), trial_replaced.begin(), trial_replaced.end());
  tinygltf::Accessor decl;
  decl.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  decl.type = TINYGLTF_TYPE_VEC2;
  decl.count = ip.decoded.vertex_count();
  model.accessors.push_back(decl);
  prim.attributes["TEXCOORD_0"] = static_cast<int>(model.accessors.size() - 1);
  ip.patch_of_face = std::move(er.patch_of_face);
  ip.patch_count = er.patch_count;
  ip.seeds = std::move(er.seeds);
  ip.methods = std::move(er.methods);
  ip.solve = er.solve;
  ip.corner_xy = std::move(er.corner_xy);
  ip.reuse_of = std::move(te.reuse_of);
  ip.twin_corner = std::move(te.twin_corner);

  pr.handling = Handling::implicit_uv;
  pr.raw_geometry = options.raw_geometry;
  pr.patches = ip.patch_count;
  pr.max_distortion = er.report.max_distortion;
  pr.mean_distortion = er.report.mean_distortion;
  pr.seam_edges = er.report.seam_edges;
  pr.rect_fill = er.report.fill;
  pr.holes = er.report.holes;
  pr.source = measure_source_charts(ip.tri, ip.source_uv, prepared.face_chart, context.image_w,
                                    context.image_h, options.tau);
  if (options.report_greedy && !options.greedy_partition) {
    // The paper's plain growth on the same mesh, for comparison only.
    EmbedOptions go = partition_options(options, prepared.face_density, prepared.face_chart);
    go.mode = PartitionMode::greedy;
    go.solve_merge = false;
    const Embedding g = embed(ip.tri, go);
    if (g.status == LayoutStatus::ok) {
      pr.greedy.patches = g.patch_count;
      pr.greedy.seam_edges = g.report.seam_edges;
      pr.greedy.rect_fill = g.report.fill;
      pr.greedy.holes = g.report.holes;
    }
  }
  plan.prims.push_back(std::move(ip));
  plan.groups[plan.group_of.at({pr.mesh, pr.primitive})].members.push_back(plan.prims.size() - 1);
  // Rare: faces Draco moved beyond the tolerance; their UVs come from corner 0.
  pr.unmatched_faces = match.unmatched_faces;
  return {};
}

Error rewrite_explicit(tinygltf::Model& model, tinygltf::Primitive& prim, const tinygltf::Primitive& source,
                       const EncodeOptions& options, std::vector<int>& replaced, PrimitiveGeometry& geom,
                       size_t& bytes) {
  for (const auto& [semantic, accessor] : prim.attributes) replaced.push_back(accessor);
  if (prim.indices >= 0) replaced.push_back(prim.indices);
  prim = source;
  bytes = 0;
  if (Error e = error_if(ErrorCode::invalid_input, read_primitive(model, prim, geom)); e.failed()) return e;
  if (options.raw_geometry) {
    write_primitive_plain(model, prim, geom, replaced);
    bytes = plain_geometry_bytes(geom);
    return {};
  }
  PrimitiveGeometry decoded;
  return error_if(ErrorCode::invalid_input,
                  write_primitive_draco(model, prim, geom, options.draco, replaced, decoded, bytes));
}

Error undo_fallen_back_cuts(tinygltf::Model& model, ImplicitPlan& plan, const EncodeOptions& options,
                            std::vector<int>& replaced, EncodeReport& report) {
  auto entry = [&](int mesh, int primitive) -> PrimitiveReport* {
    for (PrimitiveReport& pr : report.primitives)
      if (pr.mesh == mesh && pr.primitive == primitive) return &pr;
    return nullptr;
  };
  auto is_fallback = [](const PrimitiveReport* pr) { return pr && pr->handling == Handling::fallback; };
  std::map<int, std::vector<int>> erased;  // mesh -> primitives to erase
  for (auto cut = plan.cuts.rbegin(); cut != plan.cuts.rend(); ++cut) {
    PrimitiveReport* first = entry(cut->mesh, cut->primitive);
    if (!is_fallback(first) || !std::all_of(cut->appended.begin(), cut->appended.end(),
                                            [&](int p) { return is_fallback(entry(cut->mesh, p)); }))
      continue;
    PrimitiveGeometry geom;
    if (Error e = rewrite_explicit(model, model.meshes[cut->mesh].primitives[cut->primitive], cut->original,
                                   options, replaced, geom, first->geometry_bytes);
        e.failed())
      return e;
    first->triangles = geom.triangles.size() / 3;
    first->vertices = geom.vertex_count();
    first->cut_parts = 0;
    // The parts' lines in the report and the notes go, and the note of the
    // cut; the whole's other notes stay.
    for (int p : cut->appended) erased[cut->mesh].push_back(p);
    std::erase_if(report.notes, [&](const Note& n) {
      if (n.mesh != cut->mesh) return false;
      if (n.primitive == cut->primitive) return n.kind == NoteKind::cut_into_parts;
      return std::find(cut->appended.begin(), cut->appended.end(), n.primitive) != cut->appended.end();
    });
  }
  for (auto& entry_of_mesh : erased) {
    const int mesh = entry_of_mesh.first;  // a plain variable: lambdas below capture it
    std::vector<int>& parts = entry_of_mesh.second;
    std::sort(parts.rbegin(), parts.rend());
    for (int p : parts) {
      auto& prims = model.meshes[mesh].primitives;
      prims.erase(prims.begin() + p);
      std::erase_if(report.primitives,
                    [&](const PrimitiveReport& pr) { return pr.mesh == mesh && pr.primitive == p; });
      for (PrimitiveReport& pr : report.primitives)
        if (pr.mesh == mesh && pr.primitive > p) --pr.primitive;
      // Notes on later primitives of the mesh move down too.
      for (Note& note : report.notes)
        if (note.mesh == mesh && note.primitive > p) --note.primitive;
    }
  }
  return {};
}

}  // namespace gltfwarp
