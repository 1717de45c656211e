// draco_quantized predicts what a Draco decoder returns for quantized float
// attributes: the encoder prices an explicit-UV file's quality with it, so it
// must agree with a real Draco round trip bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "format/gltf/draco_geometry.h"

namespace gltfwarp {
namespace {

// A grid of n x n vertices with UVs that are not on any quantization step
// (an offset and irrational-ish spacing), and each vertex's index as an
// integer attribute that Draco keeps exactly, to find it again after Draco
// reorders the points.
struct GridMesh {
  std::vector<VertexAttribute> attributes;
  std::vector<uint32_t> triangles;
  std::vector<float> uv;
};

GridMesh grid(int n, float uv_scale, float uv_offset) {
  GridMesh g;
  std::vector<float> pos;
  std::vector<uint8_t> ids;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      pos.insert(pos.end(), {float(x), float(y), 0.1f * std::sin(float(x * y))});
      g.uv.insert(g.uv.end(),
                  {uv_offset + uv_scale * (float(x) + 0.3137f * std::sin(float(7 * y + x))) / n,
                   uv_offset + uv_scale * 0.77f * (float(y) + 0.2718f * std::cos(float(3 * x))) / n});
      const uint32_t id = uint32_t(y * n + x);
      const auto* b = reinterpret_cast<const uint8_t*>(&id);
      ids.insert(ids.end(), b, b + 4);
    }
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const uint32_t a = uint32_t(y * n + x), b = a + 1, c = a + uint32_t(n), d = c + 1;
      g.triangles.insert(g.triangles.end(), {a, b, d, a, d, c});
    }
  g.attributes.push_back(VertexAttribute::from_floats("POSITION", 3, pos));
  g.attributes.push_back(VertexAttribute::from_floats("TEXCOORD_0", 2, g.uv));
  VertexAttribute id;
  id.semantic = "_ID";
  id.component_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  id.components = 1;
  id.data = std::move(ids);
  g.attributes.push_back(std::move(id));
  return g;
}

TEST(DracoQuantized, MatchesADracoRoundTripBitForBit) {
  for (int bits : {8, 10, 12, 14}) {
    for (float scale : {1.0f, 3.5f}) {
      const GridMesh g = grid(24, scale, -0.25f);
      DracoOptions options;
      options.texcoord_bits = bits;
      const DracoEncoded enc = draco_encode(g.attributes, g.triangles, options);
      ASSERT_TRUE(enc.error.empty()) << enc.error;
      const DracoDecoded dec = draco_decode(
          enc.bytes.data(), enc.bytes.size(),
          {{"TEXCOORD_0", enc.attribute_ids.at("TEXCOORD_0"), TINYGLTF_COMPONENT_TYPE_FLOAT, 2, false},
           {"_ID", enc.attribute_ids.at("_ID"), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 1, false}});
      ASSERT_TRUE(dec.error.empty()) << dec.error;
      const std::vector<float> predicted = draco_quantized(g.uv, g.uv, 2, bits);
      const VertexAttribute& uv = dec.attributes[0];
      const VertexAttribute& ids = dec.attributes[1];
      ASSERT_EQ(uv.count(), dec.point_count);
      size_t moved = 0;
      for (size_t p = 0; p < dec.point_count; ++p) {
        uint32_t id = 0;
        std::memcpy(&id, ids.data.data() + 4 * p, 4);
        ASSERT_LT(size_t(id), g.uv.size() / 2);
        for (int c = 0; c < 2; ++c) {
          const float decoded = uv.get(p, c);
          EXPECT_EQ(decoded, predicted[2 * id + c]) << bits << " bits, point " << p << " component " << c;
          moved += decoded != g.uv[2 * id + c];
        }
      }
      EXPECT_GT(moved, dec.point_count) << "the UVs lie off the quantization grid, so most move";
    }
  }
}

TEST(DracoQuantized, LeavesValuesWhereDracoWouldNotQuantize) {
  const std::vector<float> v = {0.1f, 0.2f, 0.35f, 0.9f};
  EXPECT_EQ(draco_quantized(v, v, 2, 0), v);
  EXPECT_EQ(draco_quantized(v, v, 2, 31), v);
  EXPECT_EQ(draco_quantized({}, v, 2, 12), v);
  // Values outside the attribute's range still go through its quantizer.
  const std::vector<float> outside = {0.05f, 0.95f};
  EXPECT_EQ(draco_quantized(v, outside, 2, 12).size(), 2u);
  // A range of a few denormals makes the quantizer's scale infinite, and a
  // value far outside a range quantizes past int (undefined in Draco's
  // cast; a fuzzer's input): such values come back as they are.
  const std::vector<float> tiny = {0.0f, 0.0f, 1e-44f, 1e-44f};
  EXPECT_EQ(draco_quantized(tiny, tiny, 2, 12), tiny);
  const std::vector<float> far = {1e30f, 0.37f}, near = {0.35f, 0.37f};
  const std::vector<float> got = draco_quantized(v, far, 2, 12);
  EXPECT_EQ(got[0], 1e30f);
  EXPECT_EQ(got[1], draco_quantized(v, near, 2, 12)[1]);  // its neighbour quantized as ever
}

}  // namespace
}  // namespace gltfwarp
