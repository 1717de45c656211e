// The implicit-UV half of the encoder: which primitives lose TEXCOORD_0, how
// they group into shared atlases, and the per-group steps (embed, pack,
// bitstream, warp) that replace explicit UVs by our extension.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "codec/core/layout_solve.h"
#include "codec/core/mesh.h"
#include "codec/encode/encoder.h"
#include "codec/encode/primitive_partition.h"
#include "codec/encode/texture/texture_sampler.h"
#include "format/gltf/gltf_materials.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {

struct ImplicitPrimitive {
  int mesh = -1, primitive = -1;
  size_t report_index = 0;       // into EncodeReport::primitives
  PrimitiveGeometry decoded;     // what every decoder sees (Draco output or raw arrays)
  TriMesh tri;                   // embedding mesh (decoded positions welded exactly)
  std::vector<float> source_uv;  // TEXCOORD_0 of the source, 2 per corner of `tri`
  // The same UVs as an explicit-UV file of the primitive carries them (Draco
  // quantizes them to --texcoord-bits): what its viewer samples, so what the
  // keep-or-fall-back choice prices (explicit_alternative.h). Empty: the
  // same as source_uv (raw geometry, or integer UVs Draco keeps exactly).
  std::vector<float> explicit_uv;
  std::vector<float> source_tangents;  // the source's TANGENT, 4 per corner of `tri` (empty if none)
  std::vector<uint32_t> patch_of_face;
  uint32_t patch_count = 0;
  std::vector<uint32_t> seeds;    // empty, or the replay's seed face of each patch
  std::vector<uint8_t> methods;   // empty, or each patch's LayoutMethod (format 1.2)
  SolveParams solve;              // the solve's iteration counts when a patch solves
  std::vector<double> corner_xy;  // layout_patches output
  // Texel reuse (twin_partition.h): per patch, the patch it is a congruent
  // copy of (or -1); per corner of a copy's face, the original's corner.
  // Empty: no copy patch.
  std::vector<int32_t> reuse_of;
  std::vector<uint32_t> twin_corner;
  std::vector<float> corner_uv;  // final UVs (decode_uvs output)
  // Per face, under QualityWeight::surface_area: the UV area the face would
  // cover at its group's mean UV area per 3D area (SurfaceUvs::face_area_uv).
  // Empty: the measures weigh source texels.
  std::vector<float> face_area_uv;
  bool had_tangents = false;
  // The primitive as the source had it, accessors included (they stay in the
  // model until compact_buffers), for a fall back to explicit UVs.
  tinygltf::Primitive source_primitive;
};

struct AtlasGroup {
  std::vector<int> materials;
  std::vector<size_t> members;  // indices into ImplicitPlan::prims
};

// A primitive cut into parts for atlas pages (prepare_implicit_primitive):
// what it was, and the parts appended to its mesh, so the cut can be
// undone when every part keeps explicit UVs after all.
struct PrimitiveCut {
  int mesh = -1, primitive = -1;
  tinygltf::Primitive original;
  std::vector<int> appended;
};

// A cut part's partition, prepared ahead of the encoder's loop
// (prefetch_partitions), with the inputs it was prepared from.
struct PrefetchedPartition {
  int mesh = -1, primitive = -1;        // the part it was prepared for
  std::vector<int> materials;           // primitive_materials of the part
  PrimitiveGeometry geom;               // without TEXCOORD_0 and TANGENT, welded
  std::vector<float> source_corner_uv;  // its TEXCOORD_0 per corner
  PreparedPartition prepared;
};

struct ImplicitPlan {
  std::map<std::pair<int, int>, int> group_of;  // (mesh, primitive) -> group
  std::vector<PrimitiveCut> cuts;               // in the order they were made
  std::vector<AtlasGroup> groups;
  std::vector<ImplicitPrimitive> prims;
  // The seam test's textures (seam_continuity.h) of the last material set
  // prepared (a primitive's own material and its variants'): primitives of
  // one material usually come together, so each set's textures are read
  // once and only one set's are held.
  std::vector<int> seam_materials;
  std::vector<TextureSampler> seam_textures;
  // Partitions of the parts of the latest cuts, not yet taken by
  // prepare_implicit_primitive.
  std::vector<PrefetchedPartition> prefetched;
  bool is_implicit(int mesh, int primitive) const { return group_of.count({mesh, primitive}) > 0; }
};

// Chooses the primitives and groups; clones materials that implicit and
// explicit primitives share, so the explicit ones keep their textures.
Error plan_implicit_uvs(tinygltf::Model& model, ImplicitPlan& plan, EncodeReport& report);

// Drops TEXCOORD_0/TANGENT, writes the geometry (Draco or raw), maps the
// decoded corners to source UVs and partitions the mesh.
Error prepare_implicit_primitive(tinygltf::Model& model, tinygltf::Primitive& prim, PrimitiveGeometry& geom,
                                 ImplicitPlan& plan, const EncodeOptions& options, std::vector<int>& replaced,
                                 PrimitiveReport& report);

// Puts `source` back in place of `prim` (whose accessors go to `replaced`)
// and writes its geometry with explicit UVs, as Draco or raw arrays: what
// the encoder writes for a primitive that keeps them. `geom` receives the
// geometry, `bytes` what it costs.
Error rewrite_explicit(tinygltf::Model& model, tinygltf::Primitive& prim, const tinygltf::Primitive& source,
                       const EncodeOptions& options, std::vector<int>& replaced, PrimitiveGeometry& geom,
                       size_t& bytes);

// Undoes, latest first, every cut whose parts all kept explicit UVs: the
// primitive is written whole again (as the encoder writes any primitive
// with explicit UVs), its parts leave the mesh, and the report's entries
// and notes follow. A fallback then gives the file it gave before pages.
Error undo_fallen_back_cuts(tinygltf::Model& model, ImplicitPlan& plan, const EncodeOptions& options,
                            std::vector<int>& replaced, EncodeReport& report);

// The TEXCOORD_0 slots whose texture has an image, of every material the
// primitive can show (primitive_materials: its own and its variants').
std::vector<TextureSlot> primitive_uv0_slots(const tinygltf::Model& model, const tinygltf::Primitive& prim);

// The size every image primitive_uv0_slots sample shares, when they all
// have one and no slot has a KHR_texture_transform: the texel grid a patch
// can land on exactly (texel_alignment.h). 0 x 0 otherwise.
void aligned_uv0_image(const tinygltf::Model& model, const tinygltf::Primitive& prim, uint32_t& width,
                       uint32_t& height);

// Largest image (by texel count) that primitive_uv0_slots sample, its size
// scaled by the slot's KHR_texture_transform (texels per UV unit); 0 x 0
// when none has a readable size. The partition's density rule and the
// atlas's texel density both measure against it.
void largest_uv0_image(const tinygltf::Model& model, const tinygltf::Primitive& prim, uint32_t& width,
                       uint32_t& height);

// Per group: pack, write bitstreams, rebuild UVs with decode_uvs, warp every
// TEXCOORD_0 texture into the atlas and retarget the materials. A group whose
// warped atlas stays below the quality floor (EncodeOptions::min_psnr) at
// every density tried goes back to explicit UVs (accessors it no longer
// uses are added to `replaced`).
Error finish_implicit_uvs(tinygltf::Model& model, ImplicitPlan& plan, const EncodeOptions& options,
                          std::vector<int>& replaced, EncodeReport& report);

}  // namespace gltfwarp
