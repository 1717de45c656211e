// The GLTFWARP_implicit_texcoords bitstream (format/bitstream/uvmap_codec.h): round
// trips over random maps, every truncation, corrupt headers and counts,
// trailing bytes, transform tables, and apply_placements arithmetic.
// Golden vectors are in test_bitstream_golden.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "fuzz/fuzz_mesh.h"
#include "test_bitstream_util.h"

using namespace gltfwarp;
using namespace gltfwarp::testutil;

namespace {

UvMap simple_map(const TriMesh& m, uint32_t patches, uint32_t seed) {
  std::mt19937 rng(seed);
  return random_uvmap(m, patches, rng, true, true, true);
}

}  // namespace

TEST(Bitstream, RoundTripRandomMaps) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 300; ++trial) {
    const TriMesh mesh = (trial % 3 == 0) ? make_sphere(3 + rng() % 20, 2 + rng() % 15)
                                          : make_grid(1 + rng() % 30, 1 + rng() % 30);
    const uint32_t patches =
        1 + rng() % std::max(1u, mesh.face_count() / static_cast<uint32_t>(1 + rng() % 20));
    UvMap map = random_uvmap(mesh, patches, rng, trial % 2 == 0, trial % 4 == 0, trial % 5 != 0);
    if (trial % 3 == 1) add_random_seeds(map, rng);
    std::vector<uint8_t> bytes;
    ASSERT_EQ(write_uvmap(map, mesh, bytes), UvStatus::ok) << trial;
    EXPECT_EQ(bytes[5], map.seeds.empty() ? 0 : 1) << "minor version: 1.0 unless seeds are stored";
    UvMap back;
    ASSERT_EQ(read_uvmap(bytes, mesh, back), UvStatus::ok) << trial;
    ASSERT_EQ(back, map) << trial;
    UvStreamInfo info;
    ASSERT_EQ(read_uvmap_info(bytes, info), UvStatus::ok);
    EXPECT_EQ(info.total_bytes, bytes.size());
    EXPECT_EQ(info.patch_count, map.patch_count);
  }
}

TEST(Bitstream, RoundTripArbitraryPartitions) {
  // Patches need not be connected or compact: explicit ids cover any numbering
  // in lowest-face order.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const TriMesh mesh = make_grid(1 + rng() % 12, 1 + rng() % 12);
    UvMap map;
    map.atlas_width = 100;
    map.atlas_height = 50;
    map.patch_of_face.resize(mesh.face_count());
    uint32_t created = 0;
    for (uint32_t& p : map.patch_of_face) {
      p = (created == 0 || rng() % 3 == 0) ? created++ : static_cast<uint32_t>(rng() % created);
    }
    map.patch_count = created;
    map.placements.resize(created);
    std::vector<uint8_t> bytes;
    ASSERT_EQ(write_uvmap(map, mesh, bytes), UvStatus::ok);
    UvMap back;
    ASSERT_EQ(read_uvmap(bytes, mesh, back), UvStatus::ok);
    ASSERT_EQ(back, map);
  }
}

TEST(Bitstream, EmptyMesh) {
  TriMesh mesh;
  UvMap map;
  map.atlas_width = map.atlas_height = 1;
  std::vector<uint8_t> bytes;
  ASSERT_EQ(write_uvmap(map, mesh, bytes), UvStatus::ok);
  UvMap back;
  ASSERT_EQ(read_uvmap(bytes, mesh, back), UvStatus::ok);
  EXPECT_EQ(back, map);
}

TEST(Bitstream, EveryTruncationIsRejected) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const TriMesh mesh = make_grid(4 + rng() % 10, 4 + rng() % 10);
    UvMap map = random_uvmap(mesh, 2 + rng() % 8, rng, trial % 2 == 0, trial % 3 == 0, true);
    if (trial % 4 < 2) add_random_seeds(map, rng);
    const auto bytes = write_uvmap(map, mesh);
    for (size_t len = 0; len < bytes.size(); ++len) {
      // A fresh allocation of exactly len bytes, so ASan flags any overread.
      std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + len);
      UvMap out;
      const UvStatus s = read_uvmap(cut, mesh, out);
      ASSERT_NE(s, UvStatus::ok) << "len " << len;
      EXPECT_EQ(s, UvStatus::truncated) << "len " << len << ": " << to_string(s);
    }
  }
}

TEST(Bitstream, TrailingBytesAreRejected) {
  const TriMesh mesh = make_grid(5, 5);
  auto bytes = write_uvmap(simple_map(mesh, 4, 1), mesh);
  for (uint8_t extra : {0x00, 0x5a}) {
    auto longer = bytes;
    longer.push_back(extra);
    UvMap out;
    EXPECT_EQ(read_uvmap(longer, mesh, out), UvStatus::trailing_bytes);
    UvStreamInfo info;
    EXPECT_EQ(read_uvmap_info(longer, info), UvStatus::trailing_bytes);
  }
}

namespace {

// Header of the stream written for the 5x5 grid below, field offsets.
struct Fixture {
  TriMesh mesh = make_grid(5, 5);
  UvMap map;
  std::vector<uint8_t> bytes;
  Fixture() {
    map = simple_map(mesh, 4, 1);
    map.atlas_width = map.atlas_height = 100;  // one-byte varints
    map.page_count = 2;
    for (auto& pl : map.placements) {
      pl.x %= 101;
      pl.y %= 101;
      pl.page %= 2;
    }
    bytes = write_uvmap(map, mesh);
  }
  // magic 0-3, major 4, minor 5, flags 6, face_count 7 (50 -> 1 byte), tau 8-11,
  // texel_scale 12-15, width 16, height 17, pages 18, patches 19, partition size 20.
  UvStatus read(const std::vector<uint8_t>& b) const {
    UvMap out;
    return read_uvmap(b, mesh, out);
  }
  UvStatus with(size_t offset, uint8_t value) const {
    auto b = bytes;
    b[offset] = value;
    return read(b);
  }
};

}  // namespace

TEST(Bitstream, CorruptHeadersAreRejected) {
  Fixture fx;
  ASSERT_EQ(fx.read(fx.bytes), UvStatus::ok);
  EXPECT_EQ(fx.with(0, 'X'), UvStatus::bad_magic);
  EXPECT_EQ(fx.with(3, 'X'), UvStatus::bad_magic);
  EXPECT_EQ(fx.with(4, 2), UvStatus::unsupported_version);
  EXPECT_EQ(fx.with(4, 0), UvStatus::unsupported_version);
  EXPECT_EQ(fx.with(5, 5), UvStatus::unsupported_version);
  EXPECT_EQ(fx.with(5, 3), UvStatus::ok);  // 1.4 reads every older stream
  EXPECT_EQ(fx.with(5, 4), UvStatus::ok);
  EXPECT_EQ(fx.with(6, 0x20), UvStatus::reserved_bits);  // the cotangent flag needs minor >= 4 and METHODS
  EXPECT_EQ(fx.with(6, 0x10), UvStatus::reserved_bits);  // the fine flag needs minor >= 3
  EXPECT_EQ(fx.with(6, 0x08), UvStatus::reserved_bits);  // the methods flag needs minor >= 2
  EXPECT_EQ(fx.with(6, 0x04), UvStatus::reserved_bits);  // the seeds flag needs minor >= 1
  EXPECT_EQ(fx.with(6, 0x80), UvStatus::reserved_bits);
  EXPECT_EQ(fx.with(7, 49), UvStatus::face_count_mismatch);
  EXPECT_EQ(fx.with(11, 0x7f), UvStatus::bad_value);  // tau: float with exponent bits all set
  {
    auto b = fx.bytes;
    b[12] = b[13] = b[14] = 0;
    b[15] = 0x80;  // texel_scale = -0
    EXPECT_EQ(fx.read(b), UvStatus::bad_value);
  }
  EXPECT_EQ(fx.with(16, 0), UvStatus::bad_count);     // atlas width 0
  EXPECT_EQ(fx.with(17, 0), UvStatus::bad_count);     // atlas height 0
  EXPECT_EQ(fx.with(18, 0), UvStatus::bad_count);     // no page
  EXPECT_EQ(fx.with(19, 0), UvStatus::bad_count);     // no patch on a non-empty mesh
  EXPECT_EQ(fx.with(19, 51), UvStatus::bad_count);    // more patches than faces
  EXPECT_EQ(fx.with(20, 0x7f), UvStatus::truncated);  // partition size past the end
  {
    // Overlong varint: 5 bytes of continuation.
    auto b = fx.bytes;
    b[7] = 0x80;
    b.insert(b.begin() + 8, {0x80, 0x80, 0x80, 0x80});
    EXPECT_EQ(fx.read(b), UvStatus::bad_value);
  }
  {
    // Redundant varint encoding (50 as 0xB2 0x00).
    auto b = fx.bytes;
    b[7] = 0xB2;
    b.insert(b.begin() + 8, 0x00);
    EXPECT_EQ(fx.read(b), UvStatus::bad_value);
  }
  // Wrong mesh.
  UvMap out;
  EXPECT_EQ(read_uvmap(fx.bytes, make_grid(6, 5), out), UvStatus::face_count_mismatch);
  TriMesh broken = fx.mesh;
  broken.indices[7] = 1000;
  EXPECT_EQ(read_uvmap(fx.bytes, broken, out), UvStatus::bad_mesh);
}

TEST(Bitstream, CorruptSectionSizesAreRejected) {
  Fixture fx;
  const size_t part_size_at = 20;
  const uint8_t part = fx.bytes[part_size_at];
  ASSERT_LT(part, 0x80);
  // A smaller partition section moves the placements size field: never ok.
  for (int d = 1; d <= part; ++d)
    EXPECT_NE(fx.with(part_size_at, static_cast<uint8_t>(part - d)), UvStatus::ok);
  // Shortened final section: the stream ends with unused bytes.
  auto b = fx.bytes;
  const size_t place_size_at = part_size_at + 1 + part;
  ASSERT_GT(b[place_size_at], 0);
  b[place_size_at]--;
  EXPECT_EQ(fx.read(b), UvStatus::trailing_bytes);
}

TEST(Bitstream, RandomCorruptionNeverCrashes) {
  std::mt19937 rng(77);
  Fixture fx;
  int rejected = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const std::vector<uint8_t> b = with_flipped_bits(fx.bytes, rng, 4);
    std::vector<float> uv;
    UvMap out;
    const UvStatus s = read_uvmap(b, fx.mesh, out);
    if (s != UvStatus::ok) {
      ++rejected;
    } else {
      EXPECT_EQ(validate_uvmap(out, fx.mesh), UvStatus::ok);  // whatever decodes is valid
    }
  }
  EXPECT_GT(rejected, 0);
}

// Whatever reads also writes back to a stream that reads the same map, for
// streams that use every flag (seeds, a solve on cotangent weights, fine
// placements): corrupt bits may clear every method bit, say, and the map read
// must still be the one the writer writes for it.
TEST(Bitstream, DecodedMapsWriteBackToThemselves) {
  std::mt19937 rng(91);
  const TriMesh mesh = make_grid(5, 5);
  UvMap map = simple_map(mesh, 3, 5);
  add_random_seeds(map, rng);
  add_random_fine(map, rng);
  map.methods.assign(map.patch_count, 0);
  map.methods[1] = 1;
  map.solve.cotangent_weights = true;
  const std::vector<uint8_t> bytes = write_uvmap(map, mesh);
  int decoded = 0, without_methods = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::vector<uint8_t> b = with_flipped_bits(bytes, rng, 3);
    UvMap out;
    if (read_uvmap(b, mesh, out) != UvStatus::ok) continue;
    ++decoded;
    if ((b[6] & kUvFlagMethods) && out.methods.empty()) ++without_methods;
    std::vector<uint8_t> again;
    ASSERT_EQ(write_uvmap(out, mesh, again), UvStatus::ok) << "trial " << trial;
    UvMap back;
    ASSERT_EQ(read_uvmap(again, mesh, back), UvStatus::ok) << "trial " << trial;
    ASSERT_TRUE(back == out) << "trial " << trial;
  }
  EXPECT_GT(decoded, 100);
  EXPECT_GT(without_methods, 0);  // the case the fuzzer found is among them
}

// The fuzzer's finding (CI, 2026-12-07): a 1.4 stream whose METHODS flag is
// set while every patch unfolds. It reads as the map without methods.
TEST(Bitstream, MethodsWithoutASolveReadAsNoMethods) {
  const std::vector<uint8_t> bytes = {'G',  'W',  'U',  'V',  0x01, 0x04, 0x2a, 0x41, 0x47, 0x55, 0xfb, 0x01,
                                      0x00, 0x2f, 0x5f, 0x0a, 0x85, 0x55, 0xc5, 0x0b, 0x01, 0x02, 0x0a, 0x2f,
                                      0x5b, 0x0a, 0x85, 0x01, 0x00, 0x00, 0x00, 0x30, 0x0a, 0x0a, 0x2a, 0x0a,
                                      0x0a, 0x3d, 0x0a, 0x0a, 0x0a, 0x0a, 0x00, 0x0a, 0xae, 0x24, 0x00};
  const TriMesh mesh = fuzz_mesh();
  UvMap map;
  ASSERT_EQ(read_uvmap(bytes, mesh, map), UvStatus::ok);
  EXPECT_NE(bytes[6] & kUvFlagMethods, 0);
  EXPECT_TRUE(map.methods.empty());
  EXPECT_TRUE(map.solve == SolveParams{});
  UvMap back;
  ASSERT_EQ(read_uvmap(write_uvmap(map, mesh), mesh, back), UvStatus::ok);
  EXPECT_TRUE(back == map);
}

TEST(Bitstream, WriterRejectsInvalidMaps) {
  const TriMesh mesh = make_grid(3, 3);
  const UvMap good = simple_map(mesh, 3, 5);
  std::vector<uint8_t> bytes;
  ASSERT_EQ(write_uvmap(good, mesh, bytes), UvStatus::ok);
  auto bad = good;
  bad.patch_of_face[0] = 1;  // patch 1 before patch 0
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  bad = good;
  bad.placements[0].x = static_cast<int32_t>(bad.atlas_width) + 1;
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  bad = good;
  bad.placements[0].scale_step = 33;
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  bad = good;
  bad.placements.pop_back();
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  bad = good;
  bad.seeds.assign(bad.patch_count, 0);  // face 0 is in patch 0 only
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  bad.seeds.assign(bad.patch_count + 1, 0);
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  bad = good;
  bad.texel_scale = std::nanf("");
  EXPECT_EQ(write_uvmap(bad, mesh, bytes), UvStatus::bad_argument);
  EXPECT_THROW(write_uvmap(bad, mesh), std::invalid_argument);
}

TEST(Bitstream, TransformTables) {
  double c, s;
  rotation_cos_sin(0, c, s);
  EXPECT_EQ(c, 1.0);
  EXPECT_EQ(s, 0.0);
  rotation_cos_sin(64, c, s);
  EXPECT_EQ(c, 0.0);
  EXPECT_EQ(s, 1.0);
  rotation_cos_sin(128, c, s);
  EXPECT_EQ(c, -1.0);
  rotation_cos_sin(192, c, s);
  EXPECT_EQ(s, -1.0);
  for (uint32_t r = 0; r < kRotationSteps; ++r) {
    rotation_cos_sin(r, c, s);
    const double a = 2 * 3.14159265358979323846 * r / kRotationSteps;
    EXPECT_NEAR(c, std::cos(a), 1e-15);
    EXPECT_NEAR(s, std::sin(a), 1e-15);
    EXPECT_EQ(rotation_code_for(a), r);
    EXPECT_EQ(rotation_code_for(a - 2 * 3.14159265358979323846), r);
  }
  EXPECT_EQ(patch_scale(0), 1.0);
  EXPECT_EQ(patch_scale(4), 2.0);
  EXPECT_EQ(patch_scale(-4), 0.5);
  EXPECT_EQ(patch_scale(-1), 0x1.ae89f995ad3adp-1);
  EXPECT_EQ(patch_scale(2), 0x1.6a09e667f3bcdp+0);
  EXPECT_EQ(patch_scale(32), 256.0);
  EXPECT_EQ(patch_scale(-32), 1.0 / 256.0);
  for (int32_t k = kMinScaleStep; k <= kMaxScaleStep; ++k) {
    EXPECT_NEAR(patch_scale(k), std::exp2(k / 4.0), 1e-15 * std::exp2(k / 4.0));
    EXPECT_EQ(scale_step_for(patch_scale(k)), k);
  }
}

TEST(Bitstream, ApplyPlacementsFormula) {
  UvMap map;
  map.texel_scale = 10.0f;
  map.atlas_width = 200;
  map.atlas_height = 100;
  map.patch_count = 1;
  map.patch_of_face = {0};
  map.placements = {PatchPlacement{64, 50, 40, 0, 4}};  // 90 degrees, scale 2
  const std::vector<double> xy = {0, 0, 1, 0, 0, 1};
  std::vector<float> uv;
  ASSERT_EQ(apply_placements(xy, map, uv), UvStatus::ok);
  const std::vector<float> want = {0.25f, 0.4f, 0.25f, 0.6f, 0.15f, 0.4f};
  EXPECT_EQ(uv, want);
  EXPECT_EQ(apply_placements(std::vector<double>(5), map, uv), UvStatus::bad_argument);
}

TEST(Bitstream, StatusStrings) {
  for (int s = 0; s <= static_cast<int>(UvStatus::layout_not_disc); ++s)
    EXPECT_STRNE(to_string(static_cast<UvStatus>(s)), "unknown status");
}

TEST(Bitstream, DecodeUvsReportsLayoutErrors) {
  // Two faces far apart in one patch: a valid stream, but the replay cannot
  // reach the second face from the seed.
  const TriMesh mesh = make_grid(4, 1);  // faces 0..7 along a strip
  UvMap map;
  map.atlas_width = map.atlas_height = 64;
  map.patch_of_face = {0, 1, 1, 1, 1, 1, 1, 0};
  map.patch_count = 2;
  map.placements.resize(2);
  const auto bytes = write_uvmap(map, mesh);
  std::vector<float> uv;
  EXPECT_EQ(decode_uvs(mesh, bytes, uv), UvStatus::layout_unreachable_face);
  map.patch_of_face = {0, 0, 1, 1, 1, 1, 1, 1};
  std::vector<float> uv2;
  UvMap back;
  ASSERT_EQ(decode_uvs(mesh, write_uvmap(map, mesh), uv2, &back), UvStatus::ok);
  EXPECT_EQ(back, map);
  EXPECT_EQ(uv2.size(), 48u);
}

TEST(Bitstream, SeedsAreStoredAndReplayed) {
  // Format 1.1: a 1.1 header with only the 1.0 flags reads as before; the
  // seeds flag is honoured, a seed moves the replay's origin, and the flag
  // bits above it stay reserved.
  const TriMesh mesh = make_grid(6, 6);
  std::mt19937 rng(7);
  UvMap map = random_uvmap(mesh, 3, rng, false, false, false);
  const auto plain = write_uvmap(map, mesh);
  EXPECT_EQ(plain[5], 0);
  auto as_11 = plain;
  as_11[5] = 1;
  UvMap back;
  ASSERT_EQ(read_uvmap(as_11, mesh, back), UvStatus::ok);
  EXPECT_TRUE(back.seeds.empty());
  std::vector<float> uv_low, uv_seeded;
  ASSERT_EQ(decode_uvs(mesh, plain, uv_low), UvStatus::ok);

  add_random_seeds(map, rng);
  map.seeds[0] = 0;
  for (uint32_t f = 0; f < mesh.face_count(); ++f)  // patch 0's last face
    if (map.patch_of_face[f] == 0) map.seeds[0] = f;
  const auto seeded = write_uvmap(map, mesh);
  EXPECT_EQ(seeded[5], 1);
  EXPECT_EQ(seeded[6] & kUvFlagSeeds, kUvFlagSeeds);
  ASSERT_EQ(decode_uvs(mesh, seeded, uv_seeded, &back), UvStatus::ok);
  EXPECT_EQ(back.seeds, map.seeds);
  EXPECT_NE(uv_low, uv_seeded);  // patch 0 grew from another face
  auto reserved = seeded;
  reserved[6] |= 0x08;
  EXPECT_EQ(read_uvmap(reserved, mesh, back), UvStatus::reserved_bits);

  // The replay itself checks seeds too (it is called without the reader).
  std::vector<double> xy;
  std::vector<uint32_t> seeds = map.seeds;
  EXPECT_EQ(layout_patches(mesh, map.patch_of_face, map.patch_count, xy, seeds), LayoutStatus::ok);
  seeds.pop_back();
  EXPECT_EQ(layout_patches(mesh, map.patch_of_face, map.patch_count, xy, seeds), LayoutStatus::bad_seed);
  seeds = map.seeds;
  seeds[0] = mesh.face_count();
  EXPECT_EQ(layout_patches(mesh, map.patch_of_face, map.patch_count, xy, seeds), LayoutStatus::bad_seed);
}

TEST(Bitstream, InfoReadsHeaderWithoutMesh) {
  Fixture fx;
  UvStreamInfo info;
  ASSERT_EQ(read_uvmap_info(fx.bytes, info), UvStatus::ok);
  EXPECT_EQ(info.version_major, 1);
  EXPECT_EQ(info.version_minor, 0);
  EXPECT_EQ(info.face_count, 50u);
  EXPECT_EQ(info.patch_count, fx.map.patch_count);
  EXPECT_EQ(info.page_count, 2u);
  EXPECT_EQ(info.atlas_width, 100u);
  EXPECT_EQ(size_t{info.header_bytes} + info.partition_bytes + info.placement_bytes + 1, info.total_bytes);
  EXPECT_EQ(info.total_bytes, fx.bytes.size());
}
