// Texel reuse (issue 16, item 2): where several faces show the same source
// texels through congruent triangles (a model built symmetric whose halves
// share one half of the texture, like the Duck; instanced parts; repeated
// UV regions), the partition gives their patches the same shape, so that
// the packer can land one patch on the texels of the other (a fine
// placement, format 1.3, mirrored where the halves are) and the atlas holds
// those texels once.
//
// The partition is made symmetric by construction: the faces that are not
// copies ("primaries") are partitioned by embed(); each primary patch's
// copies, where they form a connected set that maps one to one onto it, become
// a patch of their own with the corresponding seed and method; every other
// copy face is partitioned by embed() on its own. A copy patch whose replay
// is not acceptable (a face over tau, flipped or overlapping) goes back to
// that last set. Whether a copy patch really shares texels is the packer's
// call: it fits the placement and checks the residual (pack.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"
#include "codec/encode/partition/embed.h"

namespace gltfwarp {

inline constexpr uint32_t kNoTwin = 0xffffffffu;

// Faces that show the same source texels: primary[f] is the lowest face with
// f's source UV triangle (the same three UVs, exactly) whose 3D edges match
// f's to `tolerance` (relative), else f itself. twin_corner[c], for a corner
// of a face with primary[f] != f, is the corner of primary[f] with the same
// UV (kNoTwin otherwise). Faces with a zero-area UV triangle have no twin.
struct FaceTwins {
  std::vector<uint32_t> primary;      // one per face
  std::vector<uint32_t> twin_corner;  // one per corner
  uint32_t copies = 0;                // faces with primary[f] != f
};
FaceTwins find_face_twins(const TriMesh& mesh, std::span<const float> source_uv, double tolerance = 0.02);

struct TwinEmbedding {
  Embedding embedding;  // the whole mesh's partition and replay, as embed() returns it
  // Per patch: the patch whose congruent copy it is (its faces show the same
  // source texels), or -1.
  std::vector<int32_t> reuse_of;
  // Per corner of a face in a copy patch: the corner of the reused patch's
  // face with the same source UV; kNoTwin elsewhere.
  std::vector<uint32_t> twin_corner;
  uint32_t copy_faces = 0;  // faces in copy patches
};

// embed(mesh, options) with copy patches where the source repeats texels
// (above). With fewer than min_copies copy faces found, exactly embed()'s
// partition and no copy patch. source_uv: 2 floats per corner.
TwinEmbedding embed_with_twins(const TriMesh& mesh, std::span<const float> source_uv,
                               const EmbedOptions& options, uint32_t min_copies = 16);

}  // namespace gltfwarp
