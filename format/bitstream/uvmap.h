// The implicit UV map of one primitive: what our bitstream carries in place
// of TEXCOORD_0, the exact transform tables, and the status codes of the
// format/ functions. The bitstream itself is in uvmap_codec.h, the UVs in
// decode_uvs.h; spec/README.md is the normative description.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/layout_solve.h"
#include "codec/core/mesh.h"

namespace gltfwarp {

// Rigid placement of one patch in the atlas. The UV (in texels, x right,
// y down the image rows) of a patch-local point p is
//   texel = s * R(rotation) * p + (x, y),   s = texel_scale * patch_scale(scale_step)
// and uv = texel / (atlas_width, atlas_height). R and patch_scale are defined by
// the format (rotation_cos_sin, patch_scale) with exact, table-driven values.
// (x, y) is where the patch-local origin (the seed face's first vertex) lands,
// so it lies in the page: 0 <= x <= atlas_width, 0 <= y <= atlas_height.
struct PatchPlacement {
  uint32_t rotation = 0;   // rotation code, 0 <= rotation < kRotationSteps
  int32_t x = 0, y = 0;    // translation in texels, 0 <= x <= atlas_width, 0 <= y <= atlas_height
  uint32_t page = 0;       // atlas page, < page_count (0 unless page_count > 1)
  int32_t scale_step = 0;  // per-patch scale code in [kMinScaleStep, kMaxScaleStep], 0 = texel_scale alone
  // Format 1.3, a fine placement: the patch shares texels another patch
  // already holds (texel reuse), or holds its source's own texels (a
  // texel-exact patch, codec/encode/atlas/texel_alignment.h), so it must
  // land on them to a fraction of a texel. Then (cos_q, sin_q) / 2^15 replaces R(rotation) (a rotation, and
  // the small scale that makes two nearly congruent layouts match),
  // (x + x_frac / 256, y + y_frac / 256) the translation, and `mirror`
  // negates the patch-local y first (mirrored halves of a model).
  bool fine = false;
  bool mirror = false;
  int32_t cos_q = 0, sin_q = 0;     // in [-kFineUnit * 2, kFineUnit * 2], not both 0
  uint32_t x_frac = 0, y_frac = 0;  // 0..255; x_frac = 0 when x = atlas_width (likewise y)

  friend bool operator==(const PatchPlacement&, const PatchPlacement&) = default;
};

struct UvMap {
  float tau = 1.3f;          // distortion bound the encoder used (informative)
  float texel_scale = 1.0f;  // texels per model unit, finite and > 0
  uint32_t atlas_width = 0;  // page size in texels, 1..kMaxAtlasSize
  uint32_t atlas_height = 0;
  uint32_t page_count = 1;                 // 1..kMaxPages
  uint32_t patch_count = 0;                // 1..face_count (0 iff the mesh has no face)
  std::vector<uint32_t> patch_of_face;     // one per face, patches ordered by lowest face
  std::vector<PatchPlacement> placements;  // one per patch
  // Format 1.1: the face each patch's replay grows from, one per patch (a
  // face of that patch). Empty: every patch grows from its lowest face (1.0).
  std::vector<uint32_t> seeds;
  // Format 1.2: each patch's LayoutMethod (codec/core/layout.h), one per
  // patch, and the solve's iteration counts. Empty: every patch unfolds (a
  // writer given only unfold methods writes the same stream as without, and
  // a reader returns them empty, with default `solve`, when no patch solves).
  std::vector<uint8_t> methods;
  SolveParams solve;

  friend bool operator==(const UvMap&, const UvMap&) = default;
};

// ---- limits ----------------------------------------------------------------
constexpr uint32_t kMaxAtlasSize = 65536;  // atlas_width, atlas_height
constexpr uint32_t kMaxPages = 65536;
constexpr int32_t kMinScaleStep = -32;  // patch_scale from 2^-8 ...
constexpr int32_t kMaxScaleStep = 32;   // ... to 2^8

// ---- exact transforms (spec/README.md, "Transform tables") -------------------
// The full turn is split into kRotationSteps equal steps; code r is the
// angle 2*pi*r/kRotationSteps. Values come from a literal table (correctly
// rounded doubles), so every platform gets the same bits.
constexpr uint32_t kRotationSteps = 256;
// Fine placements (1.3): cos_q, sin_q count 1/kFineUnit; x_frac, y_frac 1/kFineFracSteps of a texel.
constexpr int32_t kFineUnit = 32768;
constexpr uint32_t kFineFracSteps = 256;
void rotation_cos_sin(uint32_t code, double& c, double& s);  // code is taken mod kRotationSteps
// Encoder side: the code nearest to an angle in radians (any value; wraps).
uint32_t rotation_code_for(double radians);
// 2^(step/4) from a literal table and an exact power of two; step is clamped
// to [kMinScaleStep, kMaxScaleStep].
double patch_scale(int32_t step);
// Encoder side: the step whose patch_scale is nearest (in log) to a factor > 0.
int32_t scale_step_for(double factor);

// ---- status codes ------------------------------------------------------------
enum class UvStatus : uint8_t {
  ok = 0,
  bad_magic,                // the stream does not start with "GWUV"
  unsupported_version,      // major != 1 or minor newer than this decoder
  truncated,                // the stream (or a section) ends before its contents
  trailing_bytes,           // bytes after the last section, or unused bytes inside a section
  face_count_mismatch,      // the stream was written for a mesh with another face count
  bad_count,                // a count or a size out of its range (patches, pages, atlas, section size)
  bad_value,                // a field out of its range (float not finite, translation, scale, id)
  reserved_bits,            // a flags bit that the stream's version reserves is set
  bad_mesh,                 // the mesh has an index >= vertex_count
  bad_argument,             // caller error: corner_xy size, UvMap fields inconsistent (writer)
  layout_bad_patch_id,      // layout_patches reported bad_patch_id
  layout_patch_order,       // layout_patches reported patch_order
  layout_unreachable_face,  // layout_patches: a face of a patch is never reached by the replay
  layout_bad_seed,          // layout_patches: a seed outside its patch (the writer checks this too)
  layout_bad_method,        // layout_patches: a method list of the wrong size or an unknown method
  layout_not_disc,          // layout_patches: a patch laid out by solve is not a disc
};
const char* to_string(UvStatus s);

}  // namespace gltfwarp
