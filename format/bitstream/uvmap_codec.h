// The GLTFWARP_implicit_texcoords bitstream, format version 1.4: writer and
// reader of a UvMap. spec/README.md is the normative description; this is
// its reference implementation.
//
// The partition is coded relative to the mesh connectivity (which both sides
// have: the Draco-decoded mesh), face by face in face order, as "same patch as
// one of the already-coded neighbours / a new patch / an explicit earlier
// patch", with an adaptive binary range coder (range_coder.h). Patch
// placements are quantized to the atlas (uniform codes over exactly the range
// the atlas allows) and coded with the same coder.
//
// read_uvmap is a pure function over caller memory: it validates every header
// field and size before allocating, never reads out of bounds, rejects
// trailing bytes, and returns a distinct UvStatus per kind of malformed input.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/core/mesh.h"
#include "format/bitstream/uvmap.h"

namespace gltfwarp {

constexpr uint8_t kUvMagic[4] = {'G', 'W', 'U', 'V'};
constexpr uint8_t kUvVersionMajor = 1;
constexpr uint8_t kUvVersionMinor = 4;  // the newest minor this reader knows
// Header flag bits (all others are reserved and must be 0).
constexpr uint8_t kUvFlagRotations = 1u << 0;  // per-patch rotation codes are present
constexpr uint8_t kUvFlagScales = 1u << 1;     // per-patch scale steps are present
constexpr uint8_t kUvFlagSeeds = 1u << 2;      // per-patch seeds are present (minor >= 1)
constexpr uint8_t kUvFlagMethods = 1u << 3;    // solve parameters and per-patch methods (minor >= 2)
constexpr uint8_t kUvFlagFine = 1u << 4;       // per-patch fine placements (minor >= 3)
// The solve's ARAP uses cotangent weights (minor >= 4, only with METHODS).
constexpr uint8_t kUvFlagCotangent = 1u << 5;

// Header fields and section sizes, read without the mesh (for `gltf-warp info`).
struct UvStreamInfo {
  uint8_t version_major = 0, version_minor = 0, flags = 0;
  uint32_t face_count = 0;
  float tau = 0, texel_scale = 0;
  uint32_t atlas_width = 0, atlas_height = 0, page_count = 0, patch_count = 0;
  SolveParams solve;             // when flags has kUvFlagMethods
  uint32_t header_bytes = 0;     // everything before the partition section's bytes
  uint32_t partition_bytes = 0;  // range-coded partition (without its size field)
  uint32_t placement_bytes = 0;  // range-coded placements (without its size field)
  uint32_t total_bytes = 0;
};

// Checks that a UvMap is writable for this mesh (bad_argument / bad_mesh otherwise):
// patch ids ordered by lowest face, placements in range, limits respected.
UvStatus validate_uvmap(const UvMap& map, const TriMesh& mesh);

// Writes the bitstream. The flags are chosen from the content (rotations are
// written only if some rotation is non-zero, scales only if some step is,
// seeds only if map.seeds is not empty, methods only if some patch solves,
// fine placements only if some placement is fine). The version is the lowest
// that expresses the stream: without seeds, solve patches or fine placements
// 1.0, byte for byte what a 1.0 writer produced; with seeds 1.1; with a solve
// patch 1.2; with a fine placement 1.3; with a solve by cotangent weights
// (map.solve.cotangent_weights and some patch solves) 1.4.
UvStatus write_uvmap(const UvMap& map, const TriMesh& mesh, std::vector<uint8_t>& out);
// Same, throwing std::invalid_argument (with to_string of the status) on error.
std::vector<uint8_t> write_uvmap(const UvMap& map, const TriMesh& mesh);

// Reads the bitstream for this mesh. On error `out` is left in an unspecified
// but valid state.
UvStatus read_uvmap(std::span<const uint8_t> bytes, const TriMesh& mesh, UvMap& out);

// Reads and validates the header and section sizes only.
UvStatus read_uvmap_info(std::span<const uint8_t> bytes, UvStreamInfo& info);

}  // namespace gltfwarp
