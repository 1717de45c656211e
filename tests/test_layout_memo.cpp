// The layout memo of rate control (group_atlas.h, LayoutMemo): a layout
// that an earlier coder quality built is copied, with its warped pages,
// instead of being packed and warped again. A copy must give exactly the
// atlas a fresh build gives at the new quality: the same bitstreams, the
// same UVs in the plan, the same image bytes and the same measured error.
#include <gtest/gtest.h>

#include "codec/encode/encoder.h"
#include "codec/encode/group_atlas.h"
#include "codec/encode/implicit_uv_encoder.h"
#include "format/gltf/gltf_primitive.h"
#include "tests/support/testing/sample_model.h"

namespace gltfwarp {
namespace {

TEST(LayoutMemo, KeepsLayoutsWhoseStepBiasIsOneValue) {
  LayoutMemo memo;
  bool found = true;
  LayoutMemo::Entry* none = memo.find_or_add(1.0, {}, 0, "jpeg", found);
  ASSERT_NE(none, nullptr);
  EXPECT_FALSE(found);
  EXPECT_EQ(memo.find_or_add(1.0, {}, 0, "jpeg", found), none);
  EXPECT_FALSE(found) << "an entry is found only once its layout is built";
  none->filled = true;
  EXPECT_EQ(memo.find_or_add(1.0, {}, 0, "jpeg", found), none);
  EXPECT_TRUE(found);
  // A round's own choice (patches halved apart) is no other quality's.
  EXPECT_EQ(memo.find_or_add(1.0, {{0, -2}}, 0, "jpeg", found), nullptr);
  EXPECT_EQ(memo.find_or_add(1.0, {{-2}, {0}}, 0, "jpeg", found), nullptr);
  // Every patch halved once: kept, apart from the unbiased layout.
  LayoutMemo::Entry* halved = memo.find_or_add(1.0, {{-2, -2}, {-2}}, 0, "jpeg", found);
  ASSERT_NE(halved, nullptr);
  EXPECT_NE(halved, none);
  // Another factor, effort or image format is another layout.
  EXPECT_NE(memo.find_or_add(1.5, {}, 0, "jpeg", found), none);
  EXPECT_NE(memo.find_or_add(1.0, {}, 1, "jpeg", found), none);
  EXPECT_NE(memo.find_or_add(1.0, {}, 0, "png", found), none);
  EXPECT_EQ(memo.entries.size(), 5u);
}

// The torus sample, planned and prepared as the encoder does, up to its
// one atlas group.
void prepare_torus(tinygltf::Model& model, ImplicitPlan& plan, const EncodeOptions& options) {
  ASSERT_EQ(make_sample_model("torus", 3000, 256, model), "");
  EncodeReport report;
  ASSERT_FALSE(plan_implicit_uvs(model, plan, report).failed());
  std::vector<int> replaced;
  for (size_t mi = 0; mi < model.meshes.size(); ++mi)
    for (size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
      if (!plan.is_implicit(int(mi), int(pi))) continue;
      tinygltf::Primitive& prim = model.meshes[mi].primitives[pi];
      PrimitiveGeometry geom;
      ASSERT_EQ(read_primitive(model, prim, geom), "");
      PrimitiveReport pr;
      pr.mesh = int(mi), pr.primitive = int(pi);
      ASSERT_FALSE(prepare_implicit_primitive(model, prim, geom, plan, options, replaced, pr).failed());
    }
  ASSERT_EQ(plan.groups.size(), 1u);
}

std::vector<std::vector<float>> plan_uvs(const ImplicitPlan& plan, const AtlasGroup& group) {
  std::vector<std::vector<float>> uvs;
  for (size_t m : group.members) uvs.push_back(plan.prims[m].corner_uv);
  return uvs;
}

void expect_same_atlas(const GroupAtlas& a, const GroupAtlas& b) {
  EXPECT_EQ(a.bitstreams, b.bitstreams);
  EXPECT_EQ(a.report.page_sizes, b.report.page_sizes);
  ASSERT_EQ(a.jobs.size(), b.jobs.size());
  for (size_t j = 0; j < a.jobs.size(); ++j) EXPECT_EQ(a.jobs[j].bytes, b.jobs[j].bytes) << "job " << j;
  EXPECT_EQ(a.error.squared, b.error.squared);
  EXPECT_EQ(a.error.values, b.error.values);
  ASSERT_EQ(a.patch_error.size(), b.patch_error.size());
  for (size_t p = 0; p < a.patch_error.size(); ++p)
    EXPECT_EQ(a.patch_error[p].squared, b.patch_error[p].squared);
  EXPECT_EQ(a.patch_texels, b.patch_texels);
}

TEST(LayoutMemo, ALayoutTakenFromTheMemoBuildsWhatAFreshBuildDoes) {
  EncodeOptions high;
  high.image_format = "jpeg";
  high.image_quality = 90;
  tinygltf::Model model;
  ImplicitPlan plan;
  ASSERT_NO_FATAL_FAILURE(prepare_torus(model, plan, high));
  const AtlasGroup& group = plan.groups[0];
  EncodeOptions low = high;
  low.image_quality = 30;
  SourceImages sources;
  LayoutMemo memo;
  // A full build and an all-halved measurement at q90 fill the memo ...
  GroupAtlas first, first_measured;
  ASSERT_FALSE(build_group_atlas(model, plan, group, high, sources, 1.0, {}, first, 0, &memo).failed());
  StepBias halved;
  for (size_t m : group.members) halved.emplace_back(plan.prims[m].patch_count, -2);
  ASSERT_FALSE(
      measure_group_atlas(model, plan, group, high, sources, 1.0, halved, first_measured, &memo).failed());
  ASSERT_EQ(memo.entries.size(), 2u);
  for (const auto& [key, entry] : memo.entries) {
    EXPECT_TRUE(entry->filled);
    EXPECT_FALSE(entry->pages.empty()) << "the warped pages are kept with the layout";
  }
  EXPECT_GT(memo.warped_bytes, 0u);
  // ... q30 takes both from it ...
  GroupAtlas again, again_measured;
  ASSERT_FALSE(build_group_atlas(model, plan, group, low, sources, 1.0, {}, again, 0, &memo).failed());
  const auto uvs_again = plan_uvs(plan, group);
  ASSERT_FALSE(
      measure_group_atlas(model, plan, group, low, sources, 1.0, halved, again_measured, &memo).failed());
  EXPECT_EQ(memo.entries.size(), 2u) << "no new layout";
  // ... and gets what q30 builds without it, bit for bit.
  GroupAtlas fresh, fresh_measured;
  ASSERT_FALSE(build_group_atlas(model, plan, group, low, sources, 1.0, {}, fresh).failed());
  EXPECT_EQ(uvs_again, plan_uvs(plan, group)) << "the plan's UVs follow the copied layout";
  ASSERT_FALSE(measure_group_atlas(model, plan, group, low, sources, 1.0, halved, fresh_measured).failed());
  expect_same_atlas(again, fresh);
  expect_same_atlas(again_measured, fresh_measured);
  // The coder did run again: q30's pages are not q90's.
  ASSERT_FALSE(again.jobs.empty());
  EXPECT_NE(again.jobs[0].bytes, first.jobs[0].bytes);
  EXPECT_LT(again.report.atlas_image_bytes, first.report.atlas_image_bytes);
}

}  // namespace
}  // namespace gltfwarp
