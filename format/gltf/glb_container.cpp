// GLB container: the binary glTF layout of the glTF 2.0 specification,
// section "Binary glTF Layout".
#include "format/gltf/glb_container.h"

#include <utility>

namespace gltfwarp {
namespace {

constexpr uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534Au;
constexpr uint32_t kChunkBin = 0x004E4942u;

uint32_t load_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}

void put_u32(std::string& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

}  // namespace

std::string split_glb(const uint8_t* d, size_t n, GlbParts& out) {
  if (n < 12) return "truncated GLB header (" + std::to_string(n) + " bytes)";
  if (load_u32(d) != kGlbMagic) return "not a GLB file";
  const uint32_t version = load_u32(d + 4);
  if (version != 2) return "GLB version " + std::to_string(version) + " is not 2";
  const uint32_t length = load_u32(d + 8);
  if (length > n)
    return "truncated GLB: the header declares " + std::to_string(length) + " bytes, the file has " +
           std::to_string(n);
  if (length < 20) return "GLB has no JSON chunk";
  size_t off = 12;
  bool have_json = false, have_bin = false;
  while (off < length) {
    if (length - off < 8) return "truncated GLB chunk header at byte " + std::to_string(off);
    const uint32_t clen = load_u32(d + off), type = load_u32(d + off + 4);
    off += 8;
    if (clen > length - off)
      return "GLB chunk at byte " + std::to_string(off - 8) + " declares " + std::to_string(clen) +
             " bytes, past the end of the file";
    if (!have_json) {
      if (type != kChunkJson) return "the first GLB chunk is not JSON";
      if (clen == 0) return "the GLB JSON chunk is empty";
      out.json.assign(reinterpret_cast<const char*>(d + off), clen);
      have_json = true;
    } else if (type == kChunkBin && !have_bin) {
      out.bin = d + off;
      out.bin_size = clen;
      have_bin = true;
    }
    // Other chunk types are skipped, as the specification says.
    off += clen;
  }
  return {};
}

std::string glb_head(std::string json, size_t bin_size) {
  while (json.size() % 4) json.push_back(' ');
  const size_t bin_padded = (bin_size + 3) / 4 * 4;
  std::string glb = "glTF";
  put_u32(glb, 2);
  put_u32(glb, static_cast<uint32_t>(12 + 8 + json.size() + (bin_size ? 8 + bin_padded : 0)));
  put_u32(glb, static_cast<uint32_t>(json.size()));
  put_u32(glb, kChunkJson);
  glb += json;
  if (bin_size) {
    put_u32(glb, static_cast<uint32_t>(bin_padded));
    put_u32(glb, kChunkBin);
  }
  return glb;
}
std::string_view glb_tail(size_t bin_size) { return std::string_view("\0\0\0", (4 - bin_size % 4) % 4); }
std::string make_glb(std::string json, const uint8_t* bin, size_t bin_size) {
  std::string glb = glb_head(std::move(json), bin_size);
  glb.append(reinterpret_cast<const char*>(bin), bin_size);
  glb += glb_tail(bin_size);
  return glb;
}

}  // namespace gltfwarp
