// Format 1.3 fine placements (spec/README.md sections 4.3, 6.6): round trips,
// the validity rules on both sides (writer: bad_argument, reader: bad_value,
// header: reserved_bits / unsupported_version), and the placement arithmetic
// (a mirrored patch is the mirror image of the unmirrored one; the unit fine
// placement is bit for bit the coarse rotation 0). The golden 1.3 stream is in
// test_bitstream_golden.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/range_coder.h"
#include "format/bitstream/uvmap_codec.h"
#include "test_bitstream_util.h"

using namespace gltfwarp;
using namespace gltfwarp::testutil;

namespace {

// One patch over a small grid, no rotation, scale or page: the placement
// section then holds only x, y and the fine fields, so a test can code it by
// hand (FinePlacementCoder) with values the writer refuses.
UvMap one_patch_map(const TriMesh& mesh) {
  UvMap map;
  map.texel_scale = 40.0f;
  map.atlas_width = 100;
  map.atlas_height = 60;
  map.patch_count = 1;
  map.patch_of_face.assign(mesh.face_count(), 0);
  PatchPlacement pl;
  pl.fine = true;
  pl.cos_q = 30000;
  pl.sin_q = -12000;
  pl.x = 30;
  pl.y = 20;
  pl.x_frac = 17;
  pl.y_frac = 200;
  pl.mirror = true;
  map.placements = {pl};
  return map;
}

// The placement section of one_patch_map's stream, coded from raw field values
// (section 4.3: x, y, then fine, mirror, cos_code, sin_code, x_frac, y_frac).
std::vector<uint8_t> fine_section(uint32_t x, uint32_t y, uint32_t w, uint32_t h, bool mirror, int32_t cos_q,
                                  int32_t sin_q, uint32_t x_frac, uint32_t y_frac) {
  rc::Encoder e;
  rc::BitModel fine;
  e.uniform32(x, uint64_t{w} + 1);
  e.uniform32(y, uint64_t{h} + 1);
  e.bit(fine, 1);
  e.equiprobable(mirror ? 1 : 0);
  e.uniform32(static_cast<uint32_t>(cos_q + 2 * kFineUnit), 4 * uint64_t{kFineUnit} + 1);
  e.uniform32(static_cast<uint32_t>(sin_q + 2 * kFineUnit), 4 * uint64_t{kFineUnit} + 1);
  e.uniform(x_frac, kFineFracSteps);
  e.uniform(y_frac, kFineFracSteps);
  return e.finish();
}

// `stream` with its placement section (the last one) replaced by `section`.
std::vector<uint8_t> with_placements(const std::vector<uint8_t>& stream,
                                     const std::vector<uint8_t>& section) {
  UvStreamInfo info;
  EXPECT_EQ(read_uvmap_info(stream, info), UvStatus::ok);
  std::vector<uint8_t> out(stream.begin(), stream.begin() + info.header_bytes + info.partition_bytes);
  EXPECT_LT(section.size(), 0x80u);  // a one-byte varint
  out.push_back(static_cast<uint8_t>(section.size()));
  out.insert(out.end(), section.begin(), section.end());
  return out;
}

// Signed area of a UV triangle (corners c[0..5]), in double.
double uv_area(const float* c) {
  return (double(c[2]) - c[0]) * (double(c[5]) - c[1]) - (double(c[3]) - c[1]) * (double(c[4]) - c[0]);
}

}  // namespace

TEST(BitstreamFine, RoundTripRandomMaps) {
  std::mt19937 rng(1303);
  for (int trial = 0; trial < 200; ++trial) {
    const TriMesh mesh = (trial % 3 == 0) ? make_sphere(3 + rng() % 16, 2 + rng() % 12)
                                          : make_grid(1 + rng() % 24, 1 + rng() % 24);
    const uint32_t patches =
        1 + rng() % std::max(1u, mesh.face_count() / static_cast<uint32_t>(1 + rng() % 20));
    UvMap map = random_uvmap(mesh, patches, rng, trial % 2 == 0, trial % 4 == 0, trial % 5 != 0);
    if (trial % 3 == 1) add_random_seeds(map, rng);
    add_random_fine(map, rng, 1 + trial % 3);  // every patch fine in a third of the trials
    // Rotations stay on the coarse patches; put the far edges in play too.
    if (rng() % 4 == 0) {
      PatchPlacement& pl = map.placements[rng() % map.patch_count];
      pl.fine = true;
      pl.rotation = 0;
      pl.cos_q = -2 * kFineUnit;
      pl.sin_q = 2 * kFineUnit;
      pl.x = static_cast<int32_t>(map.atlas_width);
      pl.y = static_cast<int32_t>(map.atlas_height);
      pl.x_frac = pl.y_frac = 0;
    }
    std::vector<uint8_t> bytes;
    ASSERT_EQ(write_uvmap(map, mesh, bytes), UvStatus::ok) << trial;
    const bool any_fine = std::any_of(map.placements.begin(), map.placements.end(),
                                      [](const PatchPlacement& pl) { return pl.fine; });
    EXPECT_EQ(bytes[5], any_fine ? 3 : map.seeds.empty() ? 0 : 1) << trial;
    EXPECT_EQ((bytes[6] & kUvFlagFine) != 0, any_fine) << trial;
    UvMap back;
    ASSERT_EQ(read_uvmap(bytes, mesh, back), UvStatus::ok) << trial;
    ASSERT_EQ(back, map) << trial;
  }
}

TEST(BitstreamFine, EveryTruncationIsRejected) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 10; ++trial) {
    const TriMesh mesh = make_grid(4 + rng() % 8, 4 + rng() % 8);
    UvMap map = random_uvmap(mesh, 2 + rng() % 8, rng, trial % 2 == 0, trial % 3 == 0, true);
    add_random_fine(map, rng);
    map.placements[0].fine = true;  // at least one
    map.placements[0].rotation = 0;
    if (map.placements[0].cos_q == 0 && map.placements[0].sin_q == 0) map.placements[0].cos_q = kFineUnit;
    const auto bytes = write_uvmap(map, mesh);
    for (size_t len = 0; len < bytes.size(); ++len) {
      std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + len);
      UvMap out;
      EXPECT_EQ(read_uvmap(cut, mesh, out), UvStatus::truncated) << "len " << len;
    }
  }
}

TEST(BitstreamFine, OldStreamsAreUnchangedAndVersionsChecked) {
  const TriMesh mesh = make_grid(5, 4);
  std::mt19937 rng(5);
  UvMap map = random_uvmap(mesh, 4, rng, true, true, true);
  const auto coarse = write_uvmap(map, mesh);
  EXPECT_EQ(coarse[5], 0);
  EXPECT_EQ(coarse[6] & kUvFlagFine, 0);
  // A 1.0 stream read as 1.3 decodes the same; minor 5 is newer than this decoder.
  auto as_13 = coarse;
  as_13[5] = 3;
  UvMap back;
  ASSERT_EQ(read_uvmap(as_13, mesh, back), UvStatus::ok);
  EXPECT_EQ(back, map);
  as_13[5] = 5;
  EXPECT_EQ(read_uvmap(as_13, mesh, back), UvStatus::unsupported_version);

  // FINE under minor 0..2 is a reserved bit; under minor 5 the version is refused first.
  map.placements.back().fine = true;
  map.placements.back().rotation = 0;
  map.placements.back().cos_q = kFineUnit;
  const auto fine = write_uvmap(map, mesh);
  EXPECT_EQ(fine[5], 3);
  EXPECT_EQ(fine[6] & kUvFlagFine, kUvFlagFine);
  ASSERT_EQ(read_uvmap(fine, mesh, back), UvStatus::ok);
  EXPECT_EQ(back, map);
  for (uint8_t minor : {0, 1, 2}) {
    auto older = fine;
    older[5] = minor;
    EXPECT_EQ(read_uvmap(older, mesh, back), UvStatus::reserved_bits) << int(minor);
  }
  auto newer = fine;
  newer[5] = 5;
  EXPECT_EQ(read_uvmap(newer, mesh, back), UvStatus::unsupported_version);
  auto bit5 = fine;
  bit5[6] |= 0x20;
  EXPECT_EQ(read_uvmap(bit5, mesh, back), UvStatus::reserved_bits);
}

TEST(BitstreamFine, ReaderRejectsInvalidFields) {
  const TriMesh mesh = make_grid(3, 2);
  const UvMap map = one_patch_map(mesh);
  const auto stream = write_uvmap(map, mesh);
  const uint32_t w = map.atlas_width, h = map.atlas_height;
  // The hand coder reproduces the writer's section (so the edits below differ in one field only).
  ASSERT_EQ(with_placements(stream, fine_section(30, 20, w, h, true, 30000, -12000, 17, 200)), stream);
  UvMap out;
  const auto read = [&](const std::vector<uint8_t>& section) {
    return read_uvmap(with_placements(stream, section), mesh, out);
  };
  EXPECT_EQ(read(fine_section(30, 20, w, h, false, 0, 0, 17, 200)), UvStatus::bad_value);      // no direction
  EXPECT_EQ(read(fine_section(w, 20, w, h, false, kFineUnit, 0, 1, 0)), UvStatus::bad_value);  // x past W
  EXPECT_EQ(read(fine_section(30, h, w, h, false, kFineUnit, 0, 0, 255)), UvStatus::bad_value);  // y past H
  // The same far edges without a fraction, and the extreme codes, are valid.
  EXPECT_EQ(read(fine_section(w, h, w, h, true, -2 * kFineUnit, 2 * kFineUnit, 0, 0)), UvStatus::ok);
  EXPECT_TRUE(out.placements[0].fine && out.placements[0].mirror);
  EXPECT_EQ(out.placements[0].cos_q, -2 * kFineUnit);
  EXPECT_EQ(out.placements[0].sin_q, 2 * kFineUnit);
  EXPECT_EQ(read(fine_section(0, 0, w, h, false, 0, 1, 255, 255)), UvStatus::ok);
}

TEST(BitstreamFine, WriterRejectsInvalidFields) {
  const TriMesh mesh = make_grid(3, 2);
  const UvMap good = one_patch_map(mesh);
  std::vector<uint8_t> bytes;
  ASSERT_EQ(write_uvmap(good, mesh, bytes), UvStatus::ok);
  const auto rejects = [&](auto edit) {
    UvMap bad = good;
    edit(bad.placements[0]);
    return write_uvmap(bad, mesh, bytes) == UvStatus::bad_argument;
  };
  EXPECT_TRUE(rejects([](PatchPlacement& pl) { pl.cos_q = pl.sin_q = 0; }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) { pl.cos_q = 2 * kFineUnit + 1; }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) { pl.sin_q = -2 * kFineUnit - 1; }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) { pl.x_frac = kFineFracSteps; }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) { pl.y_frac = kFineFracSteps; }));
  EXPECT_TRUE(
      rejects([&](PatchPlacement& pl) { pl.x = static_cast<int32_t>(good.atlas_width); }));  // x_frac 17
  EXPECT_TRUE(rejects([&](PatchPlacement& pl) { pl.y = static_cast<int32_t>(good.atlas_height); }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) { pl.rotation = 3; }));  // a fine patch has no rotation code
  // Fine fields on a coarse placement.
  EXPECT_TRUE(rejects([](PatchPlacement& pl) {
    pl = PatchPlacement{};
    pl.mirror = true;
  }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) {
    pl = PatchPlacement{};
    pl.cos_q = kFineUnit;
  }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) {
    pl = PatchPlacement{};
    pl.sin_q = 1;
  }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) {
    pl = PatchPlacement{};
    pl.x_frac = 1;
  }));
  EXPECT_TRUE(rejects([](PatchPlacement& pl) {
    pl = PatchPlacement{};
    pl.y_frac = 1;
  }));
  // The edges themselves are fine without a fraction.
  EXPECT_FALSE(rejects([&](PatchPlacement& pl) {
    pl.x = static_cast<int32_t>(good.atlas_width);
    pl.y = static_cast<int32_t>(good.atlas_height);
    pl.x_frac = pl.y_frac = 0;
  }));
}

TEST(BitstreamFine, UnitFinePlacementIsTheCoarseOneBitForBit) {
  // cos_q = kFineUnit, sin_q = 0, no fraction, no mirror: exactly rotation 0
  // at the same (x, y), with any scale step (section 6.6).
  std::mt19937 rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    const TriMesh mesh = make_grid(2 + rng() % 10, 2 + rng() % 10);
    UvMap coarse = random_uvmap(mesh, 1 + rng() % 6, rng, trial % 2 == 0, trial % 3 == 0, false);
    UvMap fine = coarse;
    for (PatchPlacement& pl : fine.placements) {
      pl.fine = true;
      pl.cos_q = kFineUnit;
    }
    std::vector<float> uv_coarse, uv_fine;
    ASSERT_EQ(decode_uvs(mesh, write_uvmap(coarse, mesh), uv_coarse), UvStatus::ok);
    const auto fine_bytes = write_uvmap(fine, mesh);
    ASSERT_EQ(fine_bytes[5], 3);
    ASSERT_EQ(decode_uvs(mesh, fine_bytes, uv_fine), UvStatus::ok);
    ASSERT_EQ(uv_fine.size(), uv_coarse.size());
    EXPECT_EQ(std::memcmp(uv_fine.data(), uv_coarse.data(), uv_fine.size() * sizeof(float)), 0) << trial;
  }
}

TEST(BitstreamFine, MirroredPatchIsTheMirrorImage) {
  // M(p) = N(p.x, -p.y): the mirrored patch is the unmirrored one reflected
  // across the line through (X, Y) along the patch's local x axis, so every
  // UV triangle has the opposite orientation.
  const TriMesh mesh = make_grid(6, 5);
  UvMap map;
  map.texel_scale = 50.0f;
  map.atlas_width = 256;
  map.atlas_height = 128;
  map.patch_count = 1;
  map.patch_of_face.assign(mesh.face_count(), 0);
  PatchPlacement pl;
  pl.fine = true;
  pl.cos_q = 27000;  // about 41 degrees at a scale of about 1.07
  pl.sin_q = 23500;
  pl.x = 120;
  pl.y = 40;
  pl.x_frac = 77;
  pl.y_frac = 3;
  map.placements = {pl};
  std::vector<float> uv, uv_mirror;
  ASSERT_EQ(decode_uvs(mesh, write_uvmap(map, mesh), uv), UvStatus::ok);
  map.placements[0].mirror = true;
  ASSERT_EQ(decode_uvs(mesh, write_uvmap(map, mesh), uv_mirror), UvStatus::ok);
  ASSERT_EQ(uv.size(), uv_mirror.size());

  const double W = map.atlas_width, H = map.atlas_height;
  const double X = pl.x + pl.x_frac / 256.0, Y = pl.y + pl.y_frac / 256.0;
  const double len = std::hypot(double(pl.cos_q), double(pl.sin_q));
  const double ax = pl.cos_q / len, ay = pl.sin_q / len;  // the mirror line's direction
  for (size_t c = 0; c < uv.size() / 2; ++c) {
    // Reflect the unmirrored texel position across the line, compare in texels.
    const double dx = uv[2 * c] * W - X, dy = uv[2 * c + 1] * H - Y;
    const double along = dx * ax + dy * ay;
    const double rx = X + 2 * along * ax - dx, ry = Y + 2 * along * ay - dy;
    EXPECT_NEAR(uv_mirror[2 * c] * W, rx, 1e-3) << c;
    EXPECT_NEAR(uv_mirror[2 * c + 1] * H, ry, 1e-3) << c;
  }
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const double a = uv_area(&uv[6 * f]), b = uv_area(&uv_mirror[6 * f]);
    EXPECT_NE(a, 0.0);
    EXPECT_LT(a * b, 0.0) << "face " << f;
    EXPECT_NEAR(a, -b, 1e-4 * std::abs(a)) << "face " << f;  // float UVs near 0.5: ulp 6e-8
  }
  // apply_placements and placement_texel (the encoder's view) agree with decode_uvs.
  std::vector<double> xy;
  ASSERT_EQ(layout_patches(mesh, map.patch_of_face, map.patch_count, xy), LayoutStatus::ok);
  std::vector<float> uv_apply;
  ASSERT_EQ(apply_placements(xy, map, uv_apply), UvStatus::ok);
  EXPECT_EQ(std::memcmp(uv_apply.data(), uv_mirror.data(), uv_apply.size() * sizeof(float)), 0);
  for (size_t c = 0; c < xy.size() / 2; ++c) {
    double tx, ty;
    placement_texel(map, map.placements[0], xy[2 * c], xy[2 * c + 1], tx, ty);
    EXPECT_EQ(static_cast<float>(tx / W), uv_mirror[2 * c]);
    EXPECT_EQ(static_cast<float>(ty / H), uv_mirror[2 * c + 1]);
  }
}

TEST(BitstreamFine, RandomCorruptionDecodesOnlyValidMaps) {
  // Whatever a corrupt 1.3 stream decodes to is a map the writer accepts and
  // writes back to the same map (the fuzz target's invariant, here on fine
  // placements with rotations coded).
  const TriMesh mesh = make_grid(6, 5);
  std::mt19937 rng(1313);
  UvMap map = random_uvmap(mesh, 6, rng, true, true, true);
  add_random_fine(map, rng);
  map.placements[0].fine = true;
  map.placements[0].rotation = 0;
  map.placements[0].cos_q = kFineUnit;
  const auto bytes = write_uvmap(map, mesh);
  int decoded = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const std::vector<uint8_t> b = with_flipped_bits(bytes, rng, 3);
    UvMap out;
    if (read_uvmap(b, mesh, out) != UvStatus::ok) continue;
    ++decoded;
    ASSERT_EQ(validate_uvmap(out, mesh), UvStatus::ok) << trial;
    UvMap back;
    ASSERT_EQ(read_uvmap(write_uvmap(out, mesh), mesh, back), UvStatus::ok) << trial;
    ASSERT_EQ(back, out) << trial;
  }
  EXPECT_GT(decoded, 0);
}
