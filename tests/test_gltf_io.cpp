// The container layer: loading external files (pins that our own tinygltf
// copy, not libdraco's, serves the calls: the other one fails every load
// with "one or more FS callback not set"), data URIs, pass-through of
// everything the codec does not own, and clean errors on bad files.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "format/gltf/gltf_io.h"
#include "support/corpus.h"

using namespace gltfwarp;
using namespace gltfwarp::test;

TEST(GltfIo, LoadsGltfWithExternalBufferAndImages) {
  GLTFWARP_REQUIRE_CORPUS();
  tinygltf::Model m;
  const auto r = read_gltf(corpus_dir() + "/Duck/glTF/Duck.gltf", m);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(m.images.size(), 1u);
  EXPECT_GT(m.images[0].image.size(), 1000u);
  EXPECT_TRUE(m.images[0].as_is) << "images must keep their encoded bytes";
  EXPECT_EQ(m.images[0].mimeType, "image/png");
  EXPECT_EQ(m.buffers.size(), 1u);
  EXPECT_GT(m.buffers[0].data.size(), 1000u);
}

TEST(GltfIo, WritesGlbAndGltfThatReadBackTheSame) {
  GLTFWARP_REQUIRE_CORPUS();
  for (const auto& model : corpus_models()) {
    SCOPED_TRACE(model.name);
    tinygltf::Model m;
    ASSERT_TRUE(read_gltf(model.path, m).ok);
    const size_t images = m.images.size(), nodes = m.nodes.size(), anims = m.animations.size();
    std::vector<size_t> image_bytes;
    for (const auto& img : m.images) image_bytes.push_back(img.image.size());
    const std::string dir = scratch_dir("io-" + model.name);
    for (const std::string& out : {dir + "/a.glb", dir + "/b.gltf"}) {
      tinygltf::Model copy = m;
      ASSERT_EQ(write_gltf(copy, out), "");
      tinygltf::Model back;
      const auto r = read_gltf(out, back);
      ASSERT_TRUE(r.ok) << r.error;
      EXPECT_EQ(back.images.size(), images);
      EXPECT_EQ(back.nodes.size(), nodes);
      EXPECT_EQ(back.animations.size(), anims);
      for (size_t i = 0; i < images; ++i)
        EXPECT_EQ(back.images[i].image.size(), image_bytes[i]) << "image " << i;
    }
  }
}

TEST(GltfIo, BadFilesGiveOneLineErrors) {
  const std::string dir = scratch_dir("io-bad");
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name, std::ios::binary) << text;
    return dir + "/" + name;
  };
  const std::vector<std::string> bad = {
      write("broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": ["),
      write("truncated.glb", std::string("glTF\x02\0\0\0\xff\0\0\0", 12)),
      write("missing-buffer.gltf",
            R"({"asset":{"version":"2.0"},"buffers":[{"uri":"nope.bin","byteLength":12}]})"),
      dir + "/does-not-exist.glb",
  };
  for (const auto& path : bad) {
    tinygltf::Model m;
    const auto r = read_gltf(path, m);
    EXPECT_FALSE(r.ok) << path;
    EXPECT_FALSE(r.error.empty());
    EXPECT_EQ(r.error.find('\n'), std::string::npos) << r.error;
  }
}

// Meshopt-compressed views hold no readable data: the error names the
// extension instead of a byte count that does not add up.
TEST(GltfIo, RequiredMeshoptCompressionIsNamed) {
  const std::string path = scratch_dir("io-meshopt") + "/meshopt.gltf";
  std::ofstream(path, std::ios::binary)
      << R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_meshopt_compression"],)"
      << R"("extensionsRequired":["EXT_meshopt_compression"],"buffers":[{"byteLength":64}],)"
      << R"("bufferViews":[{"buffer":0,"byteLength":64,"extensions":{"EXT_meshopt_compression":)"
      << R"({"buffer":0,"byteLength":16,"byteStride":4,"count":16,"mode":"ATTRIBUTES"}}}]})";
  tinygltf::Model m;
  const auto r = read_gltf(path, m);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("EXT_meshopt_compression"), std::string::npos) << r.error;
  EXPECT_EQ(r.error.find('\n'), std::string::npos) << r.error;
}

TEST(GltfIo, WriteIsAtomic) {
  tinygltf::Model m;
  m.asset.version = "2.0";
  const std::string dir = scratch_dir("io-atomic");
  EXPECT_NE(write_gltf(m, dir + "/no-such-dir/x.glb"), "");
  EXPECT_FALSE(std::filesystem::exists(dir + "/no-such-dir/x.glb"));
}
