// Golden bitstreams: frozen bytes per format version (tests/golden/), the
// decoded map they must give, and a hash (FNV-1a over the float bytes) of
// the UVs decode_uvs must produce from them, bit for bit, on every platform
// (DESIGN.md, "The rule that makes the format work"). If the UV hash changes,
// the layout replay or apply_placements changed: that breaks every file ever
// written and needs a new format version, not a new hash.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "golden/uvmap_v1_0.h"
#include "golden/uvmap_v1_1.h"
#include "golden/uvmap_v1_2.h"
#include "golden/uvmap_v1_3.h"
#include "golden/uvmap_v1_4.h"
#include "test_bitstream_util.h"

using namespace gltfwarp;

namespace {

// The golden mesh: a 12 x 8 grid on the saddle z = 0.75 x y (not developable,
// so the relaxation matters); spec/reference_decoder.py builds the same.
TriMesh golden_mesh() { return testutil::make_grid(12, 8, 0.75f); }

// The golden map: 4 x 4-quad blocks (and odd one-face and one-quad patches), three pages,
// rotations and per-patch scales, so every field of 1.0 is exercised.
UvMap golden_map(const TriMesh& m) {
  UvMap map;
  map.tau = 1.25f;
  map.texel_scale = 300.0f;
  map.atlas_width = 1024;
  map.atlas_height = 512;
  map.page_count = 3;
  map.patch_of_face.resize(m.face_count());
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const uint32_t quad = f / 2, i = quad % 12, j = quad / 12;
    map.patch_of_face[f] = (j / 4) * 3 + i / 4;
  }
  map.patch_of_face[2 * (12 * 5 + 6) + 1] = 100;  // one lone triangle in the middle of a block
  // Small patches that cut blocks apart in face order: block 2's quad (11, 0)
  // then follows only patch 103 and needs an explicit id; row 0's first
  // triangles and quad (7, 1) find their patch through a shared vertex.
  map.patch_of_face[2 * 7] = map.patch_of_face[2 * 7 + 1] = 101;
  map.patch_of_face[2 * (12 + 6)] = map.patch_of_face[2 * (12 + 6) + 1] = 102;
  for (uint32_t q : {9u, 10u}) map.patch_of_face[2 * q] = map.patch_of_face[2 * q + 1] = 103;
  map.patch_count = testutil::renumber_by_lowest_face(map.patch_of_face);
  for (uint32_t p = 0; p < map.patch_count; ++p) {
    PatchPlacement pl;
    pl.rotation = (p * 37u) % kRotationSteps;
    pl.x = static_cast<int32_t>(100 + 90 * p);
    pl.y = static_cast<int32_t>(60 + 50 * (p % 7));
    pl.page = p % 3;
    pl.scale_step = static_cast<int32_t>(p % 5) - 2;
    map.placements.push_back(pl);
  }
  return map;
}

// The golden 1.1 map: the 1.0 map with a seed per patch, the median of its
// faces in ascending order (never its lowest face unless it has only one).
UvMap golden_map_v1_1(const TriMesh& m) {
  UvMap map = golden_map(m);
  std::vector<std::vector<uint32_t>> faces(map.patch_count);
  for (uint32_t f = 0; f < m.face_count(); ++f) faces[map.patch_of_face[f]].push_back(f);
  for (uint32_t p = 0; p < map.patch_count; ++p) map.seeds.push_back(faces[p][faces[p].size() / 2]);
  return map;
}

// The golden 1.2 map: the 1.1 map with six patches laid out by solve (the
// 32-face blocks 0, 6, 8 and 3 (28 faces), the 4-face patch 4 and the
// one-face patch 9); patch 1 (a block with two diagonal quads cut out, so
// two of its faces meet at a vertex only) and patch 7 (a block around a
// lone triangle) are not discs and unfold.
UvMap golden_map_v1_2(const TriMesh& m) {
  UvMap map = golden_map_v1_1(m);
  map.methods = {1, 0, 0, 1, 1, 0, 1, 0, 1, 1};
  map.solve.tutte_iterations = 24;
  map.solve.arap_iterations = 4;
  map.solve.arap_cg_iterations = 8;
  return map;
}

// The golden 1.3 map: the 1.2 map with four fine placements (two mirrored,
// all with sub-texel fractions, one at the extreme sin_q = -2 * kFineUnit),
// on unfold and solve patches, some with per-patch scales; patches 0, 1, 3,
// 4, 7 and 8 keep their coarse placements.
struct FineSpec {
  uint32_t patch;
  bool mirror;
  int32_t cos_q, sin_q;
  uint32_t x_frac, y_frac;
};
constexpr FineSpec kGoldenFine[] = {
    {2, false, 28000, -17000, 77, 200},   // unfold, 2 faces, scale step 0
    {5, true, kFineUnit, 0, 0, 128},      // unfold, 2 faces, mirrored, scale step -2
    {6, true, -20000, 30000, 255, 1},     // solve, 32 faces, mirrored, scale step -1
    {9, false, 0, -2 * kFineUnit, 5, 0},  // solve, 1 face, scale step 2
};

UvMap golden_map_v1_3(const TriMesh& m) {
  UvMap map = golden_map_v1_2(m);
  for (const FineSpec& f : kGoldenFine) {
    PatchPlacement& pl = map.placements[f.patch];
    pl.fine = true;
    pl.rotation = 0;
    pl.mirror = f.mirror;
    pl.cos_q = f.cos_q;
    pl.sin_q = f.sin_q;
    pl.x_frac = f.x_frac;
    pl.y_frac = f.y_frac;
  }
  return map;
}

// The golden 1.4 map: the 1.3 map with the solve on cotangent weights. The
// saddle grid's faces are near-right triangles, so the quads' diagonals get
// weights near 0 from the corners opposite them, and 192 of the 576 corner
// weights land on the lower clamp.
UvMap golden_map_v1_4(const TriMesh& m) {
  UvMap map = golden_map_v1_3(m);
  map.solve.cotangent_weights = true;
  return map;
}

std::string hex(const std::vector<uint8_t>& b) {
  std::string s;
  char buf[8];
  for (size_t i = 0; i < b.size(); ++i) {
    std::snprintf(buf, sizeof buf, "0x%02x,%s", b[i], (i % 12 == 11) ? "\n" : " ");
    s += buf;
  }
  return s;
}

// Every proper prefix of a golden stream decodes to `truncated`, the stream
// with one byte more to `trailing_bytes`.
void expect_prefixes_truncated(const std::vector<uint8_t>& golden) {
  const TriMesh mesh = golden_mesh();
  for (size_t len = 0; len < golden.size(); ++len) {
    std::vector<uint8_t> cut(golden.begin(), golden.begin() + len);
    std::vector<float> uv;
    EXPECT_EQ(decode_uvs(mesh, cut, uv), UvStatus::truncated) << len;
  }
  auto longer = golden;
  longer.push_back(0);
  std::vector<float> uv;
  EXPECT_EQ(decode_uvs(mesh, longer, uv), UvStatus::trailing_bytes);
}

// The floats a golden stream decodes to (empty if it does not decode).
template <size_t N>
std::vector<float> golden_uvs(const TriMesh& mesh, const uint8_t (&stream)[N]) {
  std::vector<float> uv;
  if (decode_uvs(mesh, std::vector<uint8_t>(stream, stream + N), uv) != UvStatus::ok) uv.clear();
  return uv;
}

// Every face keeps its winding in the atlas (the golden faces are all
// positively oriented in 1.2), reversed only on mirrored fine patches.
void expect_windings(const TriMesh& mesh, const UvMap& map, const std::vector<float>& uv) {
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const float* c = &uv[6 * f];
    const double area =
        (double(c[2]) - c[0]) * (double(c[5]) - c[1]) - (double(c[3]) - c[1]) * (double(c[4]) - c[0]);
    const PatchPlacement& pl = map.placements[map.patch_of_face[f]];
    if (pl.fine && pl.mirror) {
      EXPECT_LT(area, 0.0) << "face " << f;
    } else {
      EXPECT_GT(area, 0.0) << "face " << f;
    }
  }
}

}  // namespace

TEST(BitstreamGolden, WriterReproducesV1_0Bytes) {
  const TriMesh mesh = golden_mesh();
  const UvMap map = golden_map(mesh);
  const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_0), std::end(golden::kUvMapV1_0));
  EXPECT_EQ(bytes, golden) << "writer output changed; new bytes:\n" << hex(bytes);
}

TEST(BitstreamGolden, V1_0DecodesToFrozenUvs) {
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_0), std::end(golden::kUvMapV1_0));
  UvMap map;
  std::vector<float> uv;
  ASSERT_EQ(decode_uvs(mesh, golden, uv, &map), UvStatus::ok);
  EXPECT_EQ(map, golden_map(mesh));
  ASSERT_EQ(uv.size(), size_t{mesh.face_count()} * 6);
  const uint64_t h = testutil::fnv1a(uv.data(), uv.size() * sizeof(float));
  EXPECT_EQ(h, golden::kUvMapV1_0UvHash) << std::hex << "0x" << h;
  // Spot values, so a mismatch shows where (corner 0 is the first seed vertex).
  EXPECT_EQ(uv[0], golden::kUvMapV1_0Corner0[0]);
  EXPECT_EQ(uv[1], golden::kUvMapV1_0Corner0[1]);
}

TEST(BitstreamGolden, V1_0EveryTruncationIsRejected) {
  expect_prefixes_truncated(
      std::vector<uint8_t>(std::begin(golden::kUvMapV1_0), std::end(golden::kUvMapV1_0)));
}

TEST(BitstreamGolden, WriterReproducesV1_1Bytes) {
  const TriMesh mesh = golden_mesh();
  const UvMap map = golden_map_v1_1(mesh);
  const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_1), std::end(golden::kUvMapV1_1));
  EXPECT_EQ(bytes, golden) << "writer output changed; new bytes:\n" << hex(bytes);
}

TEST(BitstreamGolden, V1_1DecodesToFrozenUvs) {
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_1), std::end(golden::kUvMapV1_1));
  UvMap map;
  std::vector<float> uv;
  ASSERT_EQ(decode_uvs(mesh, golden, uv, &map), UvStatus::ok);
  EXPECT_EQ(map, golden_map_v1_1(mesh));
  ASSERT_EQ(uv.size(), size_t{mesh.face_count()} * 6);
  const uint64_t h = testutil::fnv1a(uv.data(), uv.size() * sizeof(float));
  EXPECT_EQ(h, golden::kUvMapV1_1UvHash) << std::hex << "0x" << h;
  // Spot values: the first vertex of patch 0's seed face lands on patch 0's
  // translation (face 0, the 1.0 seed, no longer does).
  ASSERT_EQ(map.seeds.size(), map.patch_count);
  EXPECT_EQ(map.seeds[0], golden::kUvMapV1_1Seed0);
  const size_t c = 6 * size_t{golden::kUvMapV1_1Seed0};
  EXPECT_EQ(uv[c], golden::kUvMapV1_1Seed0Corner0[0]);
  EXPECT_EQ(uv[c + 1], golden::kUvMapV1_1Seed0Corner0[1]);
  EXPECT_FALSE(uv[0] == golden::kUvMapV1_0Corner0[0] && uv[1] == golden::kUvMapV1_0Corner0[1]);
}

TEST(BitstreamGolden, V1_1EveryTruncationIsRejected) {
  expect_prefixes_truncated(
      std::vector<uint8_t>(std::begin(golden::kUvMapV1_1), std::end(golden::kUvMapV1_1)));
}

TEST(BitstreamGolden, WriterReproducesV1_2Bytes) {
  const TriMesh mesh = golden_mesh();
  const UvMap map = golden_map_v1_2(mesh);
  const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_2), std::end(golden::kUvMapV1_2));
  EXPECT_EQ(bytes, golden) << "writer output changed; new bytes:\n" << hex(bytes);
}

TEST(BitstreamGolden, V1_2DecodesToFrozenUvs) {
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_2), std::end(golden::kUvMapV1_2));
  UvMap map;
  std::vector<float> uv;
  ASSERT_EQ(decode_uvs(mesh, golden, uv, &map), UvStatus::ok);
  EXPECT_EQ(map, golden_map_v1_2(mesh));
  ASSERT_EQ(uv.size(), size_t{mesh.face_count()} * 6);
  const uint64_t h = testutil::fnv1a(uv.data(), uv.size() * sizeof(float));
  EXPECT_EQ(h, golden::kUvMapV1_2UvHash) << std::hex << "0x" << h;
  // Unfold patches decode exactly as in the 1.1 stream; solve patches differ.
  std::vector<float> uv11;
  ASSERT_EQ(
      decode_uvs(mesh, std::vector<uint8_t>(std::begin(golden::kUvMapV1_1), std::end(golden::kUvMapV1_1)),
                 uv11),
      UvStatus::ok);
  size_t same = 0, differ = 0;
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const bool eq = std::equal(&uv[6 * f], &uv[6 * f + 6], &uv11[6 * f]);
    if (map.methods[map.patch_of_face[f]] == 0) {
      EXPECT_TRUE(eq) << "unfold face " << f;
    } else {
      (eq ? same : differ) += 1;
    }
  }
  EXPECT_GT(differ, 100u);
  // The solve layout is fold-free: every face keeps its winding in the atlas.
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    if (map.methods[map.patch_of_face[f]] == 0) continue;
    const float* c = &uv[6 * f];
    const double area =
        (double(c[2]) - c[0]) * (double(c[5]) - c[1]) - (double(c[3]) - c[1]) * (double(c[4]) - c[0]);
    const uint32_t rot = map.placements[map.patch_of_face[f]].rotation;
    EXPECT_GT(area, 0.0) << "face " << f << " rotation " << rot;
  }
}

TEST(BitstreamGolden, V1_2EveryTruncationIsRejected) {
  expect_prefixes_truncated(
      std::vector<uint8_t>(std::begin(golden::kUvMapV1_2), std::end(golden::kUvMapV1_2)));
}

TEST(BitstreamGolden, V1_2SolveOnANonDiscPatchIsRejected) {
  const TriMesh mesh = golden_mesh();
  for (const uint32_t p : {1u, 7u}) {
    UvMap map = golden_map_v1_2(mesh);
    map.methods[p] = 1;
    const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
    std::vector<float> uv;
    EXPECT_EQ(decode_uvs(mesh, bytes, uv), UvStatus::layout_not_disc) << "patch " << p;
  }
  // Solve parameters past their limits are bad_value; a METHODS flag under minor 1 is reserved.
  std::vector<uint8_t> bytes(std::begin(golden::kUvMapV1_2), std::end(golden::kUvMapV1_2));
  std::vector<float> uv;
  auto minor1 = bytes;
  minor1[5] = 1;
  EXPECT_EQ(decode_uvs(mesh, minor1, uv), UvStatus::reserved_bits);
  auto rounds = bytes;  // arap_rounds, a one-byte varint after the 23 header bytes and tutte_steps
  ASSERT_EQ(rounds[24], 4);
  rounds[24] = kMaxSolveRounds + 1;
  EXPECT_EQ(decode_uvs(mesh, rounds, uv), UvStatus::bad_value);
  auto minor5 = bytes;
  minor5[5] = 5;
  EXPECT_EQ(decode_uvs(mesh, minor5, uv), UvStatus::unsupported_version);
  // Read as 1.3 or 1.4 (no FINE or COTANGENT flag) it decodes to the same floats.
  std::vector<float> uv12;
  ASSERT_EQ(decode_uvs(mesh, bytes, uv12), UvStatus::ok);
  for (const uint8_t minor : {3, 4}) {
    auto newer = bytes;
    newer[5] = minor;
    std::vector<float> uv_newer;
    ASSERT_EQ(decode_uvs(mesh, newer, uv_newer), UvStatus::ok) << int(minor);
    EXPECT_EQ(uv_newer, uv12) << int(minor);
  }
  UvMap map = golden_map_v1_2(mesh);
  map.solve.arap_iterations = kMaxSolveRounds + 1;
  EXPECT_EQ(write_uvmap(map, mesh, bytes), UvStatus::bad_argument);
}

TEST(BitstreamGolden, WriterReproducesV1_3Bytes) {
  const TriMesh mesh = golden_mesh();
  const UvMap map = golden_map_v1_3(mesh);
  const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_3), std::end(golden::kUvMapV1_3));
  EXPECT_EQ(bytes, golden) << "writer output changed; new bytes:\n" << hex(bytes);
}

TEST(BitstreamGolden, V1_3DecodesToFrozenUvs) {
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_3), std::end(golden::kUvMapV1_3));
  ASSERT_GT(golden.size(), 6u);
  EXPECT_EQ(golden[5], 3);
  EXPECT_EQ(golden[6], 0x1f);
  UvMap map;
  std::vector<float> uv;
  ASSERT_EQ(decode_uvs(mesh, golden, uv, &map), UvStatus::ok);
  EXPECT_EQ(map, golden_map_v1_3(mesh));
  ASSERT_EQ(uv.size(), size_t{mesh.face_count()} * 6);
  const uint64_t h = testutil::fnv1a(uv.data(), uv.size() * sizeof(float));
  EXPECT_EQ(h, golden::kUvMapV1_3UvHash) << std::hex << "0x" << h;
  // Coarse patches decode exactly as in the 1.2 stream; every fine patch moves.
  const std::vector<float> uv12 = golden_uvs(mesh, golden::kUvMapV1_2);
  ASSERT_EQ(uv12.size(), uv.size());
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const bool eq = std::equal(&uv[6 * f], &uv[6 * f + 6], &uv12[6 * f]);
    EXPECT_EQ(eq, !map.placements[map.patch_of_face[f]].fine) << "face " << f;
  }
  // A mirrored patch reverses the winding of its faces in the atlas.
  expect_windings(mesh, map, uv);
}

TEST(BitstreamGolden, V1_3EveryTruncationIsRejected) {
  expect_prefixes_truncated(
      std::vector<uint8_t>(std::begin(golden::kUvMapV1_3), std::end(golden::kUvMapV1_3)));
}

TEST(BitstreamGolden, V1_3HeaderRules) {
  // FINE under an older minor is a reserved bit, and so is COTANGENT under
  // minor 3; minor 5 is newer than this decoder.
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> bytes(std::begin(golden::kUvMapV1_3), std::end(golden::kUvMapV1_3));
  std::vector<float> uv;
  for (uint8_t minor : {0, 1, 2}) {
    auto older = bytes;
    older[5] = minor;
    EXPECT_EQ(decode_uvs(mesh, older, uv), UvStatus::reserved_bits) << int(minor);
  }
  auto minor5 = bytes;
  minor5[5] = 5;
  EXPECT_EQ(decode_uvs(mesh, minor5, uv), UvStatus::unsupported_version);
  auto bit5 = bytes;
  bit5[6] |= 0x20;
  EXPECT_EQ(decode_uvs(mesh, bit5, uv), UvStatus::reserved_bits);
}

TEST(BitstreamGolden, WriterReproducesV1_4Bytes) {
  const TriMesh mesh = golden_mesh();
  const UvMap map = golden_map_v1_4(mesh);
  const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_4), std::end(golden::kUvMapV1_4));
  EXPECT_EQ(bytes, golden) << "writer output changed; new bytes:\n" << hex(bytes);
}

TEST(BitstreamGolden, V1_4DecodesToFrozenUvs) {
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> golden(std::begin(golden::kUvMapV1_4), std::end(golden::kUvMapV1_4));
  ASSERT_GT(golden.size(), 6u);
  EXPECT_EQ(golden[5], 4);
  EXPECT_EQ(golden[6], 0x3f);
  UvMap map;
  std::vector<float> uv;
  ASSERT_EQ(decode_uvs(mesh, golden, uv, &map), UvStatus::ok);
  EXPECT_EQ(map, golden_map_v1_4(mesh));
  ASSERT_EQ(uv.size(), size_t{mesh.face_count()} * 6);
  const uint64_t h = testutil::fnv1a(uv.data(), uv.size() * sizeof(float));
  EXPECT_EQ(h, golden::kUvMapV1_4UvHash) << std::hex << "0x" << h;
  // Only the solve changes: unfold patches decode exactly as in the 1.3
  // stream, and every solve patch of more than one face moves.
  const std::vector<float> uv13 = golden_uvs(mesh, golden::kUvMapV1_3);
  ASSERT_EQ(uv13.size(), uv.size());
  std::vector<uint32_t> faces_in(map.patch_count, 0), moved(map.patch_count, 0);
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t p = map.patch_of_face[f];
    ++faces_in[p];
    if (!std::equal(&uv[6 * f], &uv[6 * f + 6], &uv13[6 * f])) ++moved[p];
  }
  for (uint32_t p = 0; p < map.patch_count; ++p) {
    if (map.methods[p] == 0) {
      EXPECT_EQ(moved[p], 0u) << "unfold patch " << p;
    } else if (faces_in[p] > 1) {
      EXPECT_GT(moved[p], 0u) << "solve patch " << p;
    }
  }
  // Still fold-free, with the 1.3 stream's windings.
  expect_windings(mesh, map, uv);
}

TEST(BitstreamGolden, V1_4EveryTruncationIsRejected) {
  expect_prefixes_truncated(
      std::vector<uint8_t>(std::begin(golden::kUvMapV1_4), std::end(golden::kUvMapV1_4)));
}

TEST(BitstreamGolden, V1_4HeaderRules) {
  // COTANGENT under minor 3 or without METHODS is a reserved bit; read as
  // 1.3 the flag is unknown, so the stream is rejected, never decoded with
  // the wrong weights.
  const TriMesh mesh = golden_mesh();
  const std::vector<uint8_t> bytes(std::begin(golden::kUvMapV1_4), std::end(golden::kUvMapV1_4));
  std::vector<float> uv;
  for (uint8_t minor : {0, 1, 2, 3}) {
    auto older = bytes;
    older[5] = minor;
    EXPECT_EQ(decode_uvs(mesh, older, uv), UvStatus::reserved_bits) << int(minor);
  }
  auto no_methods = bytes;
  no_methods[6] &= ~kUvFlagMethods;
  EXPECT_EQ(decode_uvs(mesh, no_methods, uv), UvStatus::reserved_bits);
  auto bit6 = bytes;
  bit6[6] |= 0x40;
  EXPECT_EQ(decode_uvs(mesh, bit6, uv), UvStatus::reserved_bits);
  auto minor5 = bytes;
  minor5[5] = 5;
  EXPECT_EQ(decode_uvs(mesh, minor5, uv), UvStatus::unsupported_version);
  // A map whose every patch unfolds drops COTANGENT with METHODS: the writer
  // never spends a version on weights nobody uses.
  UvMap unfold = golden_map_v1_4(mesh);
  std::fill(unfold.methods.begin(), unfold.methods.end(), 0);
  const std::vector<uint8_t> plain = write_uvmap(unfold, mesh);
  EXPECT_EQ(plain[5], 3);
  EXPECT_EQ(plain[6] & (kUvFlagMethods | kUvFlagCotangent), 0);
}
