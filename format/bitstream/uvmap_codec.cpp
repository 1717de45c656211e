// GLTFWARP_implicit_texcoords bitstream 1.4 (spec/README.md): writer and reader.
// Partition coding: connectivity-predicted patch ids, face by face, with an
// adaptive binary range coder (range_coder.h, after the LZMA SDK's rc).
#include "format/bitstream/uvmap_codec.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "codec/core/layout.h"
#include "format/bitstream/range_coder.h"

namespace gltfwarp {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

// ---- mesh adjacency ------------------------------------------------------------
// Vertex -> incident faces, ascending face id (a face naming v twice is listed twice).
struct VertexFaceList {
  std::vector<uint32_t> offsets, faces;
};
VertexFaceList vertex_faces(const TriMesh& mesh) {  // indices already validated
  VertexFaceList vf;
  const uint32_t nv = mesh.vertex_count();
  const size_t nc = size_t{mesh.face_count()} * 3;
  vf.offsets.assign(size_t{nv} + 1, 0);
  for (size_t c = 0; c < nc; ++c) ++vf.offsets[mesh.indices[c] + 1];
  for (uint32_t v = 0; v < nv; ++v) vf.offsets[v + 1] += vf.offsets[v];
  vf.faces.resize(nc);
  std::vector<uint32_t> fill(vf.offsets.begin(), vf.offsets.end() - 1);
  for (size_t c = 0; c < nc; ++c) vf.faces[fill[mesh.indices[c]]++] = static_cast<uint32_t>(c / 3);
  return vf;
}

bool indices_valid(const TriMesh& mesh) {
  const uint32_t nv = mesh.vertex_count();
  for (size_t c = 0; c < size_t{mesh.face_count()} * 3; ++c)
    if (mesh.indices[c] >= nv) return false;
  return true;
}

// lower[3f+k] = the lowest face g < f that has both vertices of edge k of f
// (edge k joins indices[3f+k] and indices[3f+(k+1)%3]), or kNone.
// Linear time: each undirected edge {a, b}, a <= b, is met from a's face list
// in ascending face order, so the first face met with it is its lowest.
// Indices must be valid (indices_valid).
void lower_neighbours(const TriMesh& mesh, const VertexFaceList& vf, std::vector<uint32_t>& lower) {
  const uint32_t nf = mesh.face_count(), nv = mesh.vertex_count();
  lower.assign(size_t{nf} * 3, kNone);
  // For the vertex a being swept: stamp[b] == a + 1 once edge {a, b} was met, in face first[b].
  std::vector<uint32_t> stamp(nv, 0), first(nv, 0);
  const uint32_t* idx = mesh.indices.data();
  for (uint32_t a = 0; a < nv; ++a) {
    uint32_t prev = kNone;
    for (uint32_t i = vf.offsets[a]; i < vf.offsets[a + 1]; ++i) {
      const uint32_t g = vf.faces[i];
      if (g == prev) continue;  // a face naming a twice is listed twice
      prev = g;
      const uint32_t* t = idx + 3 * size_t{g};
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t x = t[k], y = t[k == 2 ? 0 : k + 1];
        if (std::min(x, y) != a) continue;
        const uint32_t b = std::max(x, y);
        if (stamp[b] != a + 1) {
          stamp[b] = a + 1;
          first[b] = g;
        }
        if (first[b] < g) lower[3 * size_t{g} + k] = first[b];
      }
    }
  }
}

constexpr uint32_t kVertexScan = 16;  // faces examined per vertex
constexpr uint32_t kMaxVcand = 8;     // second-tier candidates

// Second-tier candidates of face f: distinct patches, not among cand[0..m), of
// the faces g < f that share a vertex with f; per vertex of f (k order), the
// kVertexScan highest such g, descending. At most kMaxVcand.
uint32_t vertex_candidates(const VertexFaceList& vf, const uint32_t* tri, uint32_t f,
                           const uint32_t* patch_of_face, const uint32_t* cand, uint32_t m,
                           uint32_t vcand[kMaxVcand]) {
  uint32_t vm = 0;
  for (uint32_t k = 0; k < 3; ++k) {
    const uint32_t* b = vf.faces.data() + vf.offsets[tri[k]];
    const uint32_t* e = vf.faces.data() + vf.offsets[tri[k] + 1];
    const uint32_t* it = std::lower_bound(b, e, f);
    for (uint32_t n = 0; it != b && n < kVertexScan; ++n) {
      const uint32_t p = patch_of_face[*--it];
      if (std::find(cand, cand + m, p) != cand + m || std::find(vcand, vcand + vm, p) != vcand + vm) continue;
      vcand[vm++] = p;
      if (vm == kMaxVcand) return vm;
    }
  }
  return vm;
}

// ---- partition model (shared by writer and reader) ------------------------------
struct PartitionModel {
  rc::BitModel hit[3][3][3];         // [m-1][seam context][lower neighbours - 1]
  rc::BitModel pick2[3];             // m == 2: second candidate?
  rc::BitModel pick3[2][3];          // m == 3: not first? then third?
  rc::BitModel fresh[2];             // [m > 0]: new patch (1) or an earlier one (0)
  rc::BitModel vhit;                 // the earlier patch is a second-tier candidate
  rc::BitModel vidx[kMaxVcand - 1];  // truncated unary index into the second tier
};

// Candidate patches of face f: distinct patches of its lower neighbours, most
// frequent first, ties by edge order. Returns m; seam context in *ctx.
uint32_t candidates(const uint32_t* lower3, const uint32_t* patch_of_face, const uint8_t* seam,
                    uint32_t cand[3], uint32_t* ctx, uint32_t* nlower) {
  uint32_t count[3] = {0, 0, 0};
  uint32_t m = 0, seams = 0, n = 0;
  for (uint32_t k = 0; k < 3; ++k) {
    const uint32_t g = lower3[k];
    if (g == kNone) continue;
    ++n;
    seams += seam[g];
    const uint32_t p = patch_of_face[g];
    uint32_t i = 0;
    while (i < m && cand[i] != p) ++i;
    if (i == m) cand[m++] = p;
    ++count[i];
  }
  // Stable sort by count, descending (m <= 3).
  for (uint32_t i = 1; i < m; ++i)
    for (uint32_t j = i; j > 0 && count[j] > count[j - 1]; --j) {
      std::swap(count[j], count[j - 1]);
      std::swap(cand[j], cand[j - 1]);
    }
  *ctx = std::min(seams, 2u);
  *nlower = n;
  return m;
}

// After face f is decoded: f is a seam face unless it took the single
// candidate; and every lower neighbour in another patch becomes a seam face.
void mark_seams(const uint32_t* lower3, const uint32_t* patch_of_face, uint32_t f, uint32_t m, bool hit,
                uint8_t* seam) {
  seam[f] = (m != 1 || !hit) ? 1 : 0;
  for (uint32_t k = 0; k < 3; ++k) {
    const uint32_t g = lower3[k];
    if (g != kNone && patch_of_face[g] != patch_of_face[f]) seam[g] = 1;
  }
}

// ---- little-endian byte I/O ------------------------------------------------------
void put_varint(std::vector<uint8_t>& out, uint32_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<uint8_t>(v | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<uint8_t>(v));
}

void put_f32(std::vector<uint8_t>& out, float f) {
  const uint32_t u = std::bit_cast<uint32_t>(f);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(u >> (8 * i)));
}

struct Reader {
  std::span<const uint8_t> b;
  size_t pos = 0;
  size_t left() const { return b.size() - pos; }
  UvStatus u8(uint8_t& v) {
    if (left() < 1) return UvStatus::truncated;
    v = b[pos++];
    return UvStatus::ok;
  }
  UvStatus f32(float& v) {
    if (left() < 4) return UvStatus::truncated;
    uint32_t u = 0;
    for (int i = 0; i < 4; ++i) u |= uint32_t{b[pos + i]} << (8 * i);
    pos += 4;
    v = std::bit_cast<float>(u);
    return UvStatus::ok;
  }
  // LEB128, at most 5 bytes, value < 2^32, no redundant trailing zero group.
  UvStatus varint(uint32_t& v) {
    uint64_t x = 0;
    for (uint32_t i = 0; i < 5; ++i) {
      if (left() < 1) return UvStatus::truncated;
      const uint8_t byte = b[pos++];
      x |= uint64_t{byte & 0x7Fu} << (7 * i);
      if (!(byte & 0x80)) {
        if (x > 0xFFFFFFFFu || (i > 0 && byte == 0)) return UvStatus::bad_value;
        v = static_cast<uint32_t>(x);
        return UvStatus::ok;
      }
    }
    return UvStatus::bad_value;
  }
};

#define GW_TRY(expr)                                   \
  do {                                                 \
    const UvStatus gw_status_ = (expr);                \
    if (gw_status_ != UvStatus::ok) return gw_status_; \
  } while (0)

bool scale_step_ok(int32_t s) { return s >= kMinScaleStep && s <= kMaxScaleStep; }

bool solve_params_ok(const SolveParams& s) {
  return s.tutte_iterations <= kMaxSolveCg && s.arap_cg_iterations <= kMaxSolveCg &&
         s.arap_iterations <= kMaxSolveRounds;
}

bool any_solve(const UvMap& map) {
  return std::any_of(map.methods.begin(), map.methods.end(),
                     [](uint8_t m) { return m == uint8_t(LayoutMethod::solve); });
}

UvStatus check_header_fields(uint32_t face_count, float tau, float texel_scale, uint32_t w, uint32_t h,
                             uint32_t pages, uint32_t patches) {
  if (!std::isfinite(tau) || !(tau > 0.0f)) return UvStatus::bad_value;
  if (!std::isfinite(texel_scale) || !(texel_scale > 0.0f)) return UvStatus::bad_value;
  if (w < 1 || w > kMaxAtlasSize || h < 1 || h > kMaxAtlasSize) return UvStatus::bad_count;
  if (pages < 1 || pages > kMaxPages) return UvStatus::bad_count;
  if (face_count == 0 ? patches != 0 : (patches < 1 || patches > face_count)) return UvStatus::bad_count;
  return UvStatus::ok;
}

// Header up to (not including) the partition section size.
UvStatus read_header(Reader& r, UvStreamInfo& info) {
  if (r.left() < 4) {
    // A strict prefix of the magic is a truncated stream, anything else is not ours.
    const bool prefix = r.left() == 0 || std::memcmp(r.b.data(), kUvMagic, r.left()) == 0;
    return prefix ? UvStatus::truncated : UvStatus::bad_magic;
  }
  if (std::memcmp(r.b.data(), kUvMagic, 4) != 0) return UvStatus::bad_magic;
  r.pos = 4;
  GW_TRY(r.u8(info.version_major));
  GW_TRY(r.u8(info.version_minor));
  if (info.version_major != kUvVersionMajor || info.version_minor > kUvVersionMinor)
    return UvStatus::unsupported_version;
  GW_TRY(r.u8(info.flags));
  const uint8_t known = kUvFlagRotations | kUvFlagScales | (info.version_minor >= 1 ? kUvFlagSeeds : 0) |
                        (info.version_minor >= 2 ? kUvFlagMethods : 0) |
                        (info.version_minor >= 3 ? kUvFlagFine : 0) |
                        // COTANGENT qualifies the solve, so it means nothing without METHODS.
                        (info.version_minor >= 4 && (info.flags & kUvFlagMethods) ? kUvFlagCotangent : 0);
  if (info.flags & ~known) return UvStatus::reserved_bits;
  GW_TRY(r.varint(info.face_count));
  GW_TRY(r.f32(info.tau));
  GW_TRY(r.f32(info.texel_scale));
  GW_TRY(r.varint(info.atlas_width));
  GW_TRY(r.varint(info.atlas_height));
  GW_TRY(r.varint(info.page_count));
  GW_TRY(r.varint(info.patch_count));
  GW_TRY(check_header_fields(info.face_count, info.tau, info.texel_scale, info.atlas_width, info.atlas_height,
                             info.page_count, info.patch_count));
  if (info.flags & kUvFlagMethods) {
    GW_TRY(r.varint(info.solve.tutte_iterations));
    GW_TRY(r.varint(info.solve.arap_iterations));
    GW_TRY(r.varint(info.solve.arap_cg_iterations));
    info.solve.cotangent_weights = (info.flags & kUvFlagCotangent) != 0;
    if (!solve_params_ok(info.solve)) return UvStatus::bad_value;
  }
  return UvStatus::ok;
}

UvStatus read_sections(Reader& r, UvStreamInfo& info, std::span<const uint8_t>& part,
                       std::span<const uint8_t>& place) {
  GW_TRY(r.varint(info.partition_bytes));
  info.header_bytes = static_cast<uint32_t>(r.pos);
  if (info.partition_bytes > r.left()) return UvStatus::truncated;
  part = r.b.subspan(r.pos, info.partition_bytes);
  r.pos += info.partition_bytes;
  GW_TRY(r.varint(info.placement_bytes));
  if (info.placement_bytes > r.left()) return UvStatus::truncated;
  place = r.b.subspan(r.pos, info.placement_bytes);
  r.pos += info.placement_bytes;
  if (r.left() != 0) return UvStatus::trailing_bytes;
  info.total_bytes = static_cast<uint32_t>(r.pos);
  return UvStatus::ok;
}

UvStatus rc_status(const rc::Decoder& d) {
  switch (d.error()) {
    case rc::RcError::none:
      return d.fully_consumed() ? UvStatus::ok : UvStatus::trailing_bytes;
    case rc::RcError::overread:
      return UvStatus::truncated;
    case rc::RcError::bad_symbol:
      return UvStatus::bad_value;
  }
  return UvStatus::bad_value;
}

struct ScaleModel {
  rc::BitModel nonzero, negative;
  rc::BitModel magnitude[rc::kEgPrefix];
};

// ---- fine placements (1.3) ------------------------------------------------------
// cos_q and sin_q are coded as cos_q + 2 * kFineUnit over all 4 * kFineUnit + 1
// values of [-2 * kFineUnit, 2 * kFineUnit] (more than uniform()'s 2^16: uniform32).
constexpr uint64_t kFineCodes = 4 * uint64_t{kFineUnit} + 1;
constexpr int32_t kFineMax = 2 * kFineUnit;

// The rules of spec section 4.3 a fine placement obeys: (cos_q, sin_q) in
// range and not both 0 (no direction), and no fraction past the page's far
// edge (x = W or y = H already is the edge). `x`, `y` are already in range.
bool fine_fields_ok(const PatchPlacement& pl, uint32_t w, uint32_t h) {
  if (pl.cos_q < -kFineMax || pl.cos_q > kFineMax || pl.sin_q < -kFineMax || pl.sin_q > kFineMax)
    return false;
  if (pl.cos_q == 0 && pl.sin_q == 0) return false;
  if (pl.x_frac >= kFineFracSteps || pl.y_frac >= kFineFracSteps) return false;
  if (pl.x_frac != 0 && static_cast<uint32_t>(pl.x) == w) return false;
  if (pl.y_frac != 0 && static_cast<uint32_t>(pl.y) == h) return false;
  return true;
}

// A coarse placement carries no fine field, and a fine one no rotation code
// (the stream codes it as 0 and the decoder ignores it), so the map a
// reader returns is the map written, field for field.
bool placement_fields_ok(const PatchPlacement& pl, uint32_t w, uint32_t h) {
  if (pl.fine) return pl.rotation == 0 && fine_fields_ok(pl, w, h);
  return !pl.mirror && pl.cos_q == 0 && pl.sin_q == 0 && pl.x_frac == 0 && pl.y_frac == 0;
}

void write_fine(rc::Encoder& e, rc::BitModel& fine_model, const PatchPlacement& pl) {
  e.bit(fine_model, pl.fine ? 1 : 0);
  if (!pl.fine) return;
  e.equiprobable(pl.mirror ? 1 : 0);
  e.uniform32(static_cast<uint32_t>(pl.cos_q + kFineMax), kFineCodes);
  e.uniform32(static_cast<uint32_t>(pl.sin_q + kFineMax), kFineCodes);
  e.uniform(pl.x_frac, kFineFracSteps);
  e.uniform(pl.y_frac, kFineFracSteps);
}

// Reads the fine fields after `method`; x and y are already decoded.
UvStatus read_fine(rc::Decoder& d, rc::BitModel& fine_model, uint32_t w, uint32_t h, PatchPlacement& pl) {
  if (d.bit(fine_model) == 0) return UvStatus::ok;
  pl.fine = true;
  pl.rotation = 0;  // coded before `fine` and ignored for a fine patch
  pl.mirror = d.equiprobable() == 1;
  pl.cos_q = static_cast<int32_t>(d.uniform32(kFineCodes)) - kFineMax;
  pl.sin_q = static_cast<int32_t>(d.uniform32(kFineCodes)) - kFineMax;
  pl.x_frac = d.uniform(kFineFracSteps);
  pl.y_frac = d.uniform(kFineFracSteps);
  if (d.failed()) return UvStatus::ok;  // the caller reports the coder's error first
  return fine_fields_ok(pl, w, h) ? UvStatus::ok : UvStatus::bad_value;
}

}  // namespace

// ---- validation --------------------------------------------------------------------

UvStatus validate_uvmap(const UvMap& map, const TriMesh& mesh) {
  const uint32_t nf = mesh.face_count(), nv = mesh.vertex_count();
  for (size_t c = 0; c < size_t{nf} * 3; ++c)
    if (mesh.indices[c] >= nv) return UvStatus::bad_mesh;
  if (check_header_fields(nf, map.tau, map.texel_scale, map.atlas_width, map.atlas_height, map.page_count,
                          map.patch_count) != UvStatus::ok)
    return UvStatus::bad_argument;
  if (map.patch_of_face.size() != nf || map.placements.size() != map.patch_count)
    return UvStatus::bad_argument;
  uint32_t created = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t p = map.patch_of_face[f];
    if (p > created || p >= map.patch_count) return UvStatus::bad_argument;
    if (p == created) ++created;
  }
  if (created != map.patch_count) return UvStatus::bad_argument;
  if (!map.seeds.empty()) {
    if (map.seeds.size() != map.patch_count) return UvStatus::bad_argument;
    for (uint32_t p = 0; p < map.patch_count; ++p)
      if (map.seeds[p] >= nf || map.patch_of_face[map.seeds[p]] != p) return UvStatus::bad_argument;
  }
  if (!map.methods.empty()) {
    if (map.methods.size() != map.patch_count) return UvStatus::bad_argument;
    for (const uint8_t m : map.methods)
      if (m > uint8_t(LayoutMethod::solve)) return UvStatus::bad_argument;
    if (!solve_params_ok(map.solve)) return UvStatus::bad_argument;
  }
  for (const PatchPlacement& pl : map.placements) {
    if (pl.rotation >= kRotationSteps || pl.page >= map.page_count || !scale_step_ok(pl.scale_step))
      return UvStatus::bad_argument;
    if (pl.x < 0 || static_cast<uint32_t>(pl.x) > map.atlas_width || pl.y < 0 ||
        static_cast<uint32_t>(pl.y) > map.atlas_height)
      return UvStatus::bad_argument;
    if (!placement_fields_ok(pl, map.atlas_width, map.atlas_height)) return UvStatus::bad_argument;
  }
  return UvStatus::ok;
}

// ---- writer ------------------------------------------------------------------------

UvStatus write_uvmap(const UvMap& map, const TriMesh& mesh, std::vector<uint8_t>& out) {
  GW_TRY(validate_uvmap(map, mesh));
  const uint32_t nf = mesh.face_count();
  if (!indices_valid(mesh)) return UvStatus::bad_mesh;
  const VertexFaceList vf = vertex_faces(mesh);
  std::vector<uint32_t> lower;
  lower_neighbours(mesh, vf, lower);

  // Partition.
  rc::Encoder pe;
  {
    PartitionModel pm;
    std::vector<uint8_t> seam(nf, 0);
    uint32_t created = nf > 0 ? 1 : 0;
    if (nf > 0) seam[0] = 1;
    for (uint32_t f = 1; f < nf; ++f) {
      uint32_t cand[3], ctx, nl;
      const uint32_t m = candidates(&lower[3 * f], map.patch_of_face.data(), seam.data(), cand, &ctx, &nl);
      const uint32_t p = map.patch_of_face[f];
      uint32_t idx = 0;
      while (idx < m && cand[idx] != p) ++idx;
      const bool hit = idx < m;
      if (m > 0) {
        pe.bit(pm.hit[m - 1][ctx][nl - 1], hit ? 1 : 0);
        if (hit && m == 2) pe.bit(pm.pick2[ctx], idx);
        if (hit && m == 3) {
          pe.bit(pm.pick3[0][ctx], idx > 0);
          if (idx > 0) pe.bit(pm.pick3[1][ctx], idx - 1);
        }
      }
      if (!hit) {
        const bool is_new = p == created;
        if (created < map.patch_count) pe.bit(pm.fresh[m > 0], is_new ? 1 : 0);
        if (is_new) {
          ++created;
        } else {
          uint32_t vcand[kMaxVcand];
          const uint32_t vm =
              vertex_candidates(vf, &mesh.indices[3 * f], f, map.patch_of_face.data(), cand, m, vcand);
          uint32_t vi = 0;
          while (vi < vm && vcand[vi] != p) ++vi;
          if (vm > 0) pe.bit(pm.vhit, vi < vm ? 1 : 0);
          if (vi < vm) {
            for (uint32_t i = 0; i + 1 < vm; ++i) {
              pe.bit(pm.vidx[i], vi > i ? 1 : 0);
              if (vi == i) break;
            }
          } else {
            pe.uniform32(p, created);
          }
        }
      }
      mark_seams(&lower[3 * f], map.patch_of_face.data(), f, m, hit, seam.data());
    }
  }
  const std::vector<uint8_t> part = pe.finish();

  // Placements.
  uint8_t flags = 0;
  for (const PatchPlacement& pl : map.placements) {
    if (pl.rotation != 0) flags |= kUvFlagRotations;
    if (pl.scale_step != 0) flags |= kUvFlagScales;
    if (pl.fine) flags |= kUvFlagFine;
  }
  if (!map.seeds.empty()) flags |= kUvFlagSeeds;
  if (any_solve(map)) flags |= kUvFlagMethods;
  if ((flags & kUvFlagMethods) && map.solve.cotangent_weights) flags |= kUvFlagCotangent;
  // Seeds are coded as their rank among their patch's faces in ascending order.
  std::vector<uint32_t> patch_faces, seed_rank;
  if (flags & kUvFlagSeeds) {
    patch_faces.assign(map.patch_count, 0);
    seed_rank.assign(map.patch_count, 0);
    for (uint32_t f = 0; f < nf; ++f) {
      const uint32_t p = map.patch_of_face[f];
      if (f < map.seeds[p]) ++seed_rank[p];
      ++patch_faces[p];
    }
  }
  rc::Encoder ce;
  {
    ScaleModel sm;
    rc::BitModel method_model, fine_model;
    for (uint32_t p = 0; p < map.patch_count; ++p) {
      const PatchPlacement& pl = map.placements[p];
      if (flags & kUvFlagRotations) ce.uniform(pl.rotation, kRotationSteps);
      ce.uniform32(static_cast<uint32_t>(pl.x), uint64_t{map.atlas_width} + 1);
      ce.uniform32(static_cast<uint32_t>(pl.y), uint64_t{map.atlas_height} + 1);
      if (map.page_count > 1) ce.uniform32(pl.page, map.page_count);
      if (flags & kUvFlagScales) {
        ce.bit(sm.nonzero, pl.scale_step != 0);
        if (pl.scale_step != 0) {
          ce.bit(sm.negative, pl.scale_step < 0);
          ce.exp_golomb(sm.magnitude, static_cast<uint32_t>(std::abs(pl.scale_step)) - 1);
        }
      }
      if (flags & kUvFlagSeeds) ce.uniform32(seed_rank[p], patch_faces[p]);
      if (flags & kUvFlagMethods) ce.bit(method_model, map.methods[p]);
      if (flags & kUvFlagFine) write_fine(ce, fine_model, pl);
    }
  }
  const std::vector<uint8_t> place = ce.finish();

  out.clear();
  out.reserve(40 + part.size() + place.size());
  for (const uint8_t b : kUvMagic) out.push_back(b);
  out.push_back(kUvVersionMajor);
  out.push_back((flags & kUvFlagCotangent) ? 4
                : (flags & kUvFlagFine)    ? 3
                : (flags & kUvFlagMethods) ? 2
                : (flags & kUvFlagSeeds)   ? 1
                                           : 0);  // the oldest minor that reads it
  out.push_back(flags);
  put_varint(out, nf);
  put_f32(out, map.tau);
  put_f32(out, map.texel_scale);
  put_varint(out, map.atlas_width);
  put_varint(out, map.atlas_height);
  put_varint(out, map.page_count);
  put_varint(out, map.patch_count);
  if (flags & kUvFlagMethods) {
    put_varint(out, map.solve.tutte_iterations);
    put_varint(out, map.solve.arap_iterations);
    put_varint(out, map.solve.arap_cg_iterations);
  }
  put_varint(out, static_cast<uint32_t>(part.size()));
  out.insert(out.end(), part.begin(), part.end());
  put_varint(out, static_cast<uint32_t>(place.size()));
  out.insert(out.end(), place.begin(), place.end());
  return UvStatus::ok;
}

std::vector<uint8_t> write_uvmap(const UvMap& map, const TriMesh& mesh) {
  std::vector<uint8_t> out;
  const UvStatus s = write_uvmap(map, mesh, out);
  if (s != UvStatus::ok) throw std::invalid_argument(std::string("write_uvmap: ") + to_string(s));
  return out;
}

// ---- reader ------------------------------------------------------------------------

UvStatus read_uvmap_info(std::span<const uint8_t> bytes, UvStreamInfo& info) {
  info = UvStreamInfo{};
  Reader r{bytes};
  GW_TRY(read_header(r, info));
  std::span<const uint8_t> part, place;
  return read_sections(r, info, part, place);
}

UvStatus read_uvmap(std::span<const uint8_t> bytes, const TriMesh& mesh, UvMap& out) {
  UvStreamInfo info;
  Reader r{bytes};
  GW_TRY(read_header(r, info));
  if (info.face_count != mesh.face_count()) return UvStatus::face_count_mismatch;
  std::span<const uint8_t> part, place;
  GW_TRY(read_sections(r, info, part, place));

  // Everything below is sized by the mesh (face_count) or by patch_count <= face_count.
  const uint32_t nf = info.face_count;
  if (!indices_valid(mesh)) return UvStatus::bad_mesh;
  const VertexFaceList vf = vertex_faces(mesh);
  std::vector<uint32_t> lower;
  lower_neighbours(mesh, vf, lower);
  out.tau = info.tau;
  out.texel_scale = info.texel_scale;
  out.atlas_width = info.atlas_width;
  out.atlas_height = info.atlas_height;
  out.page_count = info.page_count;
  out.patch_count = info.patch_count;
  out.patch_of_face.assign(nf, 0);

  {
    rc::Decoder pd(part);
    PartitionModel pm;
    std::vector<uint8_t> seam(nf, 0);
    uint32_t created = nf > 0 ? 1 : 0;
    if (nf > 0) seam[0] = 1;
    for (uint32_t f = 1; f < nf; ++f) {
      uint32_t cand[3], ctx, nl;
      const uint32_t m = candidates(&lower[3 * f], out.patch_of_face.data(), seam.data(), cand, &ctx, &nl);
      bool hit = false;
      uint32_t p = 0;
      if (m > 0) {
        hit = pd.bit(pm.hit[m - 1][ctx][nl - 1]) == 1;
        if (hit) {
          uint32_t idx = 0;
          if (m == 2) idx = pd.bit(pm.pick2[ctx]);
          if (m == 3 && pd.bit(pm.pick3[0][ctx])) idx = 1 + pd.bit(pm.pick3[1][ctx]);
          p = cand[idx];
        }
      }
      if (!hit) {
        const bool is_new = created < out.patch_count && pd.bit(pm.fresh[m > 0]) == 1;
        if (is_new) {
          p = created++;
        } else {
          uint32_t vcand[kMaxVcand];
          const uint32_t vm =
              vertex_candidates(vf, &mesh.indices[3 * f], f, out.patch_of_face.data(), cand, m, vcand);
          if (vm > 0 && pd.bit(pm.vhit) == 1) {
            uint32_t vi = 0;
            while (vi + 1 < vm && pd.bit(pm.vidx[vi]) == 1) ++vi;
            p = vcand[vi];
          } else {
            p = pd.uniform32(created);
          }
        }
      }
      if (pd.failed()) return rc_status(pd);
      out.patch_of_face[f] = p;
      mark_seams(&lower[3 * f], out.patch_of_face.data(), f, m, hit, seam.data());
    }
    if (created != out.patch_count) return UvStatus::bad_count;
    GW_TRY(rc_status(pd));
  }

  out.placements.assign(out.patch_count, PatchPlacement{});
  out.seeds.clear();
  out.methods.clear();
  out.solve = (info.flags & kUvFlagMethods) ? info.solve : SolveParams{};
  if (info.flags & kUvFlagMethods) out.methods.assign(out.patch_count, 0);
  // Seeds: the rank-th face of each patch in ascending order (sized by nf;
  // every patch id is < patch_count after the partition section).
  std::vector<uint32_t> patch_start, face_list;
  if (info.flags & kUvFlagSeeds) {
    faces_by_patch(out.patch_of_face, out.patch_count, patch_start, face_list);
    out.seeds.assign(out.patch_count, 0);
  }
  {
    rc::Decoder cd(place);
    ScaleModel sm;
    rc::BitModel method_model, fine_model;
    for (uint32_t p = 0; p < out.patch_count; ++p) {
      PatchPlacement& pl = out.placements[p];
      if (info.flags & kUvFlagRotations) pl.rotation = cd.uniform(kRotationSteps);
      pl.x = static_cast<int32_t>(cd.uniform32(uint64_t{out.atlas_width} + 1));
      pl.y = static_cast<int32_t>(cd.uniform32(uint64_t{out.atlas_height} + 1));
      if (out.page_count > 1) pl.page = cd.uniform32(out.page_count);
      if (info.flags & kUvFlagScales) {
        if (cd.bit(sm.nonzero)) {
          const bool negative = cd.bit(sm.negative) == 1;
          const uint32_t mag = cd.exp_golomb(sm.magnitude);
          if (mag >= static_cast<uint32_t>(kMaxScaleStep))
            return cd.failed() ? rc_status(cd) : UvStatus::bad_value;
          pl.scale_step = negative ? -static_cast<int32_t>(mag + 1) : static_cast<int32_t>(mag + 1);
        }
      }
      if (info.flags & kUvFlagSeeds) {
        // uniform32 never returns >= n (a corrupt symbol is clamped and flagged).
        const uint32_t n = patch_start[p + 1] - patch_start[p];
        out.seeds[p] = face_list[patch_start[p] + cd.uniform32(n)];
      }
      if (info.flags & kUvFlagMethods) out.methods[p] = static_cast<uint8_t>(cd.bit(method_model));
      if (info.flags & kUvFlagFine) GW_TRY(read_fine(cd, fine_model, out.atlas_width, out.atlas_height, pl));
      if (cd.failed()) return rc_status(cd);
    }
    GW_TRY(rc_status(cd));
  }
  // A stream may set METHODS with every patch unfolding (the spec allows it;
  // our writer never does). Such a map means what one without methods means,
  // so it reads as that one: one map per meaning, and write_uvmap of what
  // read_uvmap returns reads back equal.
  if (!any_solve(out)) {
    out.methods.clear();
    out.solve = SolveParams{};
  }
  return UvStatus::ok;
}

}  // namespace gltfwarp
