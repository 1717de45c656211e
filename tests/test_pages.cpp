// Atlas pages: the page assignment, the patch-aligned cut of a primitive
// too large for one page, the texel estimate both rest on, and encodes
// that spread a texture set over several pages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <numeric>
#include <set>

#include "codec/encode/atlas/pack.h"
#include "codec/encode/atlas/pages.h"
#include "codec/encode/atlas/texel_density.h"
#include "codec/encode/encoder.h"
#include "codec/encode/implicit_uv_encoder.h"
#include "codec/encode/partition/embed.h"
#include "codec/encode/texture/image_io.h"
#include "codec/encode/texture/surface_compare.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"
#include "support/corpus.h"
#include "support/malformed.h"
#include "tests/support/testing/sample_model.h"
#include "tests/support/testing/shapes.h"

namespace gltfwarp {
namespace {

using test::scratch_dir;

TEST(Pages, EveryItemOnOnePageWithinCapacity) {
  const std::vector<double> texels = {5, 3, 9, 1, 12, 4, 4, 0, 7};
  const double capacity = 10;
  const auto pages = assign_pages(texels, capacity);
  std::vector<int> seen(texels.size(), 0);
  for (const auto& page : pages) {
    double load = 0;
    for (size_t item : page) load += texels[item], ++seen[item];
    // Only an item larger than a page alone may pass it.
    if (page.size() > 1) {
      EXPECT_LE(load, capacity);
    }
    EXPECT_TRUE(std::is_sorted(page.begin(), page.end()));
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  const double total = std::accumulate(texels.begin(), texels.end(), 0.0);
  EXPECT_GE(pages.size(), size_t(std::ceil(total / capacity)));
  // First fit: the 12-texel item has its own page; the 1 and the 0 join the first.
  EXPECT_EQ(pages[0], (std::vector<size_t>{0, 1, 3, 7}));
}

TEST(Pages, BadSizesCountAsNothing) {
  const std::vector<double> texels = {std::nan(""), -4, INFINITY, 2};
  const auto pages = assign_pages(texels, 3);
  ASSERT_EQ(pages.size(), 1u);
  EXPECT_EQ(pages[0].size(), 4u);
}

// Before any partition, faces are cut along the mesh's own pieces (faces
// sharing vertices: the source's UV charts) while those fit a part.
TEST(Pages, FacesSplitAlongChartsWhileTheyFit) {
  const ShapeMesh a = make_sphere(24, 12), b = make_torus(24, 12);
  const ShapeMesh both = concat(a, b);
  const size_t fa = a.mesh.face_count(), faces = both.mesh.face_count();
  const std::vector<double> texels(faces, 1.0);
  uint32_t parts = 0;
  // Each shape fits one part: no shape is cut.
  auto part = split_faces_into_parts(both.mesh, texels, double(faces), true, parts);
  EXPECT_EQ(parts, 1u);
  part = split_faces_into_parts(both.mesh, texels, double(std::max(fa, faces - fa)), true, parts);
  EXPECT_EQ(parts, 2u);
  for (size_t f = 0; f < faces; ++f) EXPECT_EQ(part[f], f < fa ? part[0] : part[faces - 1]) << f;
  // Too large for a part: halves, each within the capacity.
  const double capacity = double(faces) / 7;
  part = split_faces_into_parts(both.mesh, texels, capacity, true, parts);
  std::vector<double> load(parts, 0.0);
  for (uint32_t p : part) load.at(p) += 1;
  EXPECT_GE(parts, 7u);
  for (double l : load) EXPECT_LE(l, capacity);
  // Without halving, a shape larger than a part is a part of its own.
  part = split_faces_into_parts(both.mesh, texels, capacity, false, parts);
  EXPECT_EQ(parts, 2u);
}

// A sphere's partition, with a per-face density, for the estimate and the cut.
struct Partitioned {
  ShapeMesh shape;
  Embedding er;
  std::vector<double> density;
};

Partitioned partitioned_sphere() {
  Partitioned p;
  p.shape = make_sphere(48, 24);
  EmbedOptions eo;
  p.er = embed(p.shape.mesh, eo);
  p.density = layout_texel_density(p.er.corner_xy, p.shape.corner_uv, 512, 512);
  return p;
}

// The estimate the cut and the page spread rest on must match what the
// packer really covers: within a quarter, as the packer rounds each
// patch's scale to steps of 2^(1/4) and counts texel centres.
TEST(Pages, EstimatedTexelsMatchThePacker) {
  const Partitioned p = partitioned_sphere();
  ASSERT_EQ(p.er.status, LayoutStatus::ok);
  for (const double factor : {0.5, 1.0, 2.0}) {
    const auto patch =
        estimated_patch_texels(p.er.corner_xy, p.er.patch_of_face, p.er.patch_count, p.density, factor);
    const double estimate = std::accumulate(patch.begin(), patch.end(), 0.0);
    PackPrimitive pp{&p.shape.mesh,
                     p.er.patch_of_face,
                     p.er.patch_count,
                     p.er.corner_xy,
                     p.density,
                     {},
                     p.er.seeds,
                     p.er.methods,
                     p.er.solve,
                     {},
                     {},
                     {}};
    // The reference as the encoder sets it, near the faces' own densities
    // (the packer clamps each patch's scale to 1/16..8 times it).
    double sum = 0;
    for (double d : p.density) sum += d;
    PackOptions po;
    po.density_reference = sum / double(p.density.size());
    po.texel_scale = factor * po.density_reference;
    po.max_atlas_size = 8192;
    PackResult packed;
    ASSERT_EQ(pack_atlas(std::span(&pp, 1), po, packed), PackStatus::ok);
    std::printf("factor %.1f: %llu texels covered, %.0f estimated\n", factor,
                static_cast<unsigned long long>(packed.report.covered_texels), estimate);
    EXPECT_NEAR(double(packed.report.covered_texels), estimate, 0.25 * estimate) << "factor " << factor;
  }
}

TEST(Pages, PartsOfPatchesStayWithinAPage) {
  const Partitioned p = partitioned_sphere();
  ASSERT_EQ(p.er.status, LayoutStatus::ok);
  ASSERT_GT(p.er.patch_count, 4u);
  const auto texels =
      estimated_patch_texels(p.er.corner_xy, p.er.patch_of_face, p.er.patch_count, p.density, 1.0);
  const double total = std::accumulate(texels.begin(), texels.end(), 0.0);
  const double largest = *std::max_element(texels.begin(), texels.end());
  const double capacity = std::max(total / 5, largest);
  uint32_t parts = 0;
  const auto part = parts_of_patches(p.shape.mesh, p.er.patch_of_face, texels, capacity, parts);
  ASSERT_EQ(part.size(), p.er.patch_count);
  EXPECT_GE(parts, 5u);
  EXPECT_LE(parts, 2 * 5u + 1) << "parts only open when the current one is full";
  std::vector<double> load(parts, 0.0);
  for (uint32_t q = 0; q < p.er.patch_count; ++q) {
    ASSERT_LT(part[q], parts);
    load[part[q]] += texels[q];
  }
  for (double l : load) {
    EXPECT_GT(l, 0);
    EXPECT_LE(l, capacity * (1 + 1e-12));
  }
}

// Triangles and surface area of a model's first mesh, over all its primitives.
void triangles_and_area(const tinygltf::Model& m, size_t& tris, double& area) {
  tris = 0, area = 0;
  for (const auto& prim : m.meshes[0].primitives) {
    PrimitiveGeometry g;
    ASSERT_EQ(read_primitive(m, prim, g), "");
    tris += g.triangles.size() / 3;
    const VertexAttribute* pos = g.find("POSITION");
    for (size_t f = 0; f < g.triangles.size() / 3; ++f) {
      double e[2][3];
      for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 3; ++i)
          e[k][i] = pos->get(g.triangles[3 * f + k + 1], i) - pos->get(g.triangles[3 * f], i);
      area += 0.5 * std::hypot(e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                               e[0][0] * e[1][1] - e[0][1] * e[1][0]);
    }
  }
}

// Encodes `src` (one mesh) with --max-atlas-size `max_size` and decodes
// it: the primitive is cut into parts along patch boundaries, the parts go
// to pages no larger than the limit, and the decoded file keeps every
// triangle, the surface area and the look of the source.
// With `several_pages` false the parts may share one page in the end (the
// adaptive density can shrink the atlas after the cut).
void check_pages(const std::string& name, const std::string& src, int max_size, const std::string& extra_args,
                 bool several_pages) {
  const std::string dir = scratch_dir("pages-" + name);
  const std::string enc = dir + "/enc.glb", dec = dir + "/dec.glb";
  std::string out;
  ASSERT_EQ(test::run_command(std::string(GLTFWARP_CLI) + " encode " + extra_args + " --max-atlas-size " +
                                  std::to_string(max_size) + " '" + src + "' -o " + enc + " 2>&1",
                              &out),
            0)
      << out;
  EXPECT_NE(out.find("cut into"), std::string::npos) << out;
  ASSERT_EQ(test::run_command(std::string(GLTFWARP_CLI) + " decode -q " + enc + " -o " + dec + " 2>&1", &out),
            0)
      << out;
  tinygltf::Model sm, em, dm;
  ASSERT_TRUE(read_gltf(src, sm).ok);
  ASSERT_TRUE(read_gltf(enc, em).ok);
  ASSERT_TRUE(read_gltf(dec, dm).ok);
  ASSERT_EQ(em.meshes.size(), 1u);
  ASSERT_GT(em.meshes[0].primitives.size(), 1u);
  std::set<int> images;
  for (const auto& prim : em.meshes[0].primitives) {
    ASSERT_TRUE(prim.extensions.count(ext::kName));
    const auto& e = prim.extensions.at(ext::kName);
    EXPECT_LE(e.Get(ext::kAtlasWidth).GetNumberAsInt(), max_size);
    EXPECT_LE(e.Get(ext::kAtlasHeight).GetNumberAsInt(), max_size);
    const auto& mat = em.materials.at(prim.material);
    images.insert(em.textures.at(mat.pbrMetallicRoughness.baseColorTexture.index).source);
  }
  if (several_pages) {
    EXPECT_GT(images.size(), 1u) << "one page only";
  }
  for (int i : images) {
    int w = 0, h = 0;
    std::string err;
    ASSERT_TRUE(image_size(em.images[i].image, w, h, err)) << err;
    EXPECT_LE(std::max(w, h), max_size);
  }
  size_t st = 0, dt = 0;
  double sa = 0, da = 0;
  triangles_and_area(sm, st, sa);
  triangles_and_area(dm, dt, da);
  EXPECT_EQ(st, dt);
  EXPECT_NEAR(sa, da, 1e-3 * sa);
  const SurfaceComparison q = compare_surface(sm, dm);
  ASSERT_EQ(q.error, "");
  EXPECT_EQ(q.primitives, dm.meshes[0].primitives.size());
  std::printf("%s at %d: %zu pages, surface PSNR %.2f dB\n", name.c_str(), max_size, images.size(), q.psnr);
  EXPECT_GE(q.psnr, 38.0);
  const test::ValidatorResult vs = test::validate(src), vd = test::validate(dec), ve = test::validate(enc);
  if (!vd.ran && test::on_ci()) FAIL() << "gltf-validator is not installed";
  if (vd.ran) {
    EXPECT_LE(vd.errors, vs.errors) << vd.raw;
    EXPECT_LE(ve.errors, vs.errors) << ve.raw;
  }
}

// check_pages on a generated sample (always implicit: the samples' textures
// have detail at every scale, which the size rule would keep explicit).
void check_sample_pages(const std::string& shape, int faces, int texture, int max_size) {
  tinygltf::Model source;
  ASSERT_EQ(make_sample_model(shape, faces, texture, source), "");
  const std::string src = scratch_dir("pages-src") + "/" + shape + ".glb";
  ASSERT_EQ(write_gltf(source, src), "");
  check_pages(shape, src, max_size, "--always-implicit", true);
}

TEST(Pages, OversizedAtlasSpreadsOverPages) { check_sample_pages("sphere", 3000, 512, 256); }

// A flat plane is one patch, however large its texture: the patch is split
// into regions that can go to pages of their own.
TEST(Pages, OnePatchLargerThanAPageIsSplit) { check_sample_pages("plane", 2000, 512, 160); }

TEST(Pages, LargePatchesSplitIntoRegionsOfHalfAPage) {
  const ShapeMesh plane = make_plane(40, 40);
  Embedding er = embed(plane.mesh, EmbedOptions{});
  ASSERT_EQ(er.status, LayoutStatus::ok);
  ASSERT_EQ(er.patch_count, 1u);
  const std::vector<double> texels = estimated_face_texels(er.corner_xy, {}, 100.0);  // 100 texels per unit
  const double total = std::accumulate(texels.begin(), texels.end(), 0.0);
  const double capacity = total / 3;
  EXPECT_TRUE(split_large_patches(plane.mesh, er.patch_of_face, 1, texels, total * 1.01, {}).empty());
  const auto regions = split_large_patches(plane.mesh, er.patch_of_face, 1, texels, capacity, {});
  ASSERT_EQ(regions.size(), texels.size());
  std::map<uint32_t, double> held;
  for (size_t f = 0; f < regions.size(); ++f) held[regions[f]] += texels[f];
  EXPECT_GE(held.size(), 6u);
  const double face_max = *std::max_element(texels.begin(), texels.end());
  for (const auto& [region, t] : held) EXPECT_LE(t, 0.5 * capacity + face_max) << "region " << region;
  // Embedded again with the regions as charts, no patch passes a page.
  EmbedOptions eo;
  eo.face_chart = regions;
  er = embed(plane.mesh, eo);
  ASSERT_EQ(er.status, LayoutStatus::ok);
  const auto patch = estimated_patch_texels(er.corner_xy, er.patch_of_face, er.patch_count, {}, 100.0);
  for (double t : patch) EXPECT_LE(t, capacity);
}

TEST(Pages, CorpusModelIsCutForPages) {
  GLTFWARP_REQUIRE_CORPUS();
  for (const auto& m : test::corpus_models())
    // At 40 dB (not the default 44, where this cut atlas outweighs its
    // source and the cut is undone) the pages hold the implicit map.
    if (m.name == "Duck") return check_pages("Duck", m.path, 512, "--target-psnr 40", false);
  FAIL() << "Duck is not in the corpus";
}

// --max-pages 1 keeps one page: the density shrinks instead, and says so.
TEST(Pages, OnePageShrinksTheDensity) {
  tinygltf::Model model;
  ASSERT_EQ(make_sample_model("sphere", 3000, 512, model), "");
  EncodeOptions o;
  o.max_atlas_size = 256;
  o.max_pages = 1;
  o.quality_fallback = false;
  EncodeReport report;
  ASSERT_EQ(encode_model(model, o, report).message, "");
  ASSERT_EQ(model.meshes[0].primitives.size(), 1u);
  ASSERT_EQ(report.atlases.size(), 1u);
  EXPECT_EQ(report.atlases[0].page_sizes.size(), 1u);
  EXPECT_LT(report.atlases[0].density_factor, 0.9);
  EXPECT_LE(std::max(report.atlases[0].width, report.atlases[0].height), 256u);
}

// The parts of a cut are partitioned side by side ahead of the encoder's
// loop: the file is the one partitioning them one after another gives,
// byte for byte, with Draco and with raw geometry.
TEST(Pages, PrefetchedPartitionsGiveTheSameFile) {
  struct Case {
    const char* shape;
    int faces, texture;
    uint32_t max_size;
    bool raw;
  };
  for (const Case& c : {Case{"sphere", 3000, 512, 256, false}, Case{"torus", 2000, 512, 128, true}}) {
    std::vector<uint8_t> bytes[2];
    for (const bool prefetch : {false, true}) {
      tinygltf::Model model;
      ASSERT_EQ(make_sample_model(c.shape, c.faces, c.texture, model), "");
      EncodeOptions o;
      o.max_atlas_size = c.max_size;
      o.quality_fallback = false;
      o.raw_geometry = c.raw;
      o.prefetch_partitions = prefetch;
      EncodeReport report;
      ASSERT_EQ(encode_model(model, o, report).message, "");
      EXPECT_GT(model.meshes[0].primitives.size(), 1u) << c.shape << ": not cut";
      const std::string path = scratch_dir("pages-prefetch") + (prefetch ? "/on.glb" : "/off.glb");
      ASSERT_EQ(write_gltf(model, path), "");
      std::ifstream in(path, std::ios::binary);
      bytes[prefetch].assign(std::istreambuf_iterator<char>(in), {});
    }
    EXPECT_EQ(bytes[0], bytes[1]) << c.shape << (c.raw ? " raw" : "");
  }
}

// A cut whose parts all keep explicit UVs (here: a floor no atlas reaches)
// is undone: the file is the one a single page would have given, byte for
// byte, and the report lists the primitive once.
TEST(Pages, CutIsUndoneWhenEveryPartFallsBack) {
  std::vector<uint8_t> bytes[2];
  for (const uint32_t pages : {16u, 1u}) {
    tinygltf::Model model;
    ASSERT_EQ(make_sample_model("sphere", 3000, 512, model), "");
    EncodeOptions o;
    o.max_atlas_size = 256;
    o.max_pages = pages;
    o.min_psnr = 80;
    EncodeReport report;
    ASSERT_EQ(encode_model(model, o, report).message, "");
    ASSERT_EQ(model.meshes[0].primitives.size(), 1u);
    ASSERT_EQ(report.primitives.size(), 1u);
    EXPECT_EQ(report.primitives[0].handling, Handling::fallback);
    EXPECT_EQ(report.primitives[0].fallback.reason, FallbackReason::below_quality_floor);
    for (const Note& note : report.notes) EXPECT_NE(note.kind, NoteKind::cut_into_parts);
    const std::string path = scratch_dir("pages-undo") + (pages == 1 ? "/one.glb" : "/many.glb");
    ASSERT_EQ(write_gltf(model, path), "");
    std::ifstream in(path, std::ios::binary);
    bytes[pages == 1].assign(std::istreambuf_iterator<char>(in), {});
  }
  EXPECT_EQ(bytes[0], bytes[1]);
}

// Undoing a cut erases its parts from the mesh; the report's lines and the
// notes that name later primitives of that mesh move down with them.
TEST(Pages, UndoneCutRenumbersLaterPrimitivesInNotes) {
  tinygltf::Model m = test::empty_scene();
  const int mat = test::add_material(m, test::add_texture(m, test::add_png_image(m, 16)));
  // [0] A, cut, fell back; [1] B; [2] A's part, fell back; [3] B's part.
  for (int i = 0; i < 4; ++i) test::add_primitive(m, test::grid_mesh(3, 3, float(4 * i), 0), mat);
  ImplicitPlan plan;
  PrimitiveCut cut;
  cut.mesh = 0;
  cut.primitive = 0;
  cut.original = m.meshes[0].primitives[0];
  cut.appended = {2};
  plan.cuts.push_back(cut);
  EncodeReport report;
  for (int p = 0; p < 4; ++p) {
    PrimitiveReport pr;
    pr.mesh = 0;
    pr.primitive = p;
    pr.handling = p % 2 == 0 ? Handling::fallback : Handling::implicit_uv;
    report.primitives.push_back(pr);
  }
  auto note = [](NoteKind kind, int mesh, int primitive, const std::string& detail = {}) {
    Note n;
    n.kind = kind;
    n.mesh = mesh;
    n.primitive = primitive;
    n.detail = detail;
    return n;
  };
  report.notes = {note(NoteKind::cut_into_parts, 0, 0), note(NoteKind::fallback, 0, 2),
                  note(NoteKind::draco_unsupported, 0, 3, "a note on B's part"),
                  note(NoteKind::draco_unsupported, 1, 3, "another mesh"),
                  note(NoteKind::draco_unsupported, 0, 1, "a note on B")};
  EncodeOptions o;
  std::vector<int> replaced;
  ASSERT_EQ(undo_fallen_back_cuts(m, plan, o, replaced, report).message, "");
  EXPECT_EQ(m.meshes[0].primitives.size(), 3u);
  ASSERT_EQ(report.notes.size(), 3u);
  EXPECT_TRUE(report.notes[0].about(0, 2)) << report.notes[0].detail;  // B's part, formerly 3
  EXPECT_EQ(report.notes[0].detail, "a note on B's part");
  EXPECT_TRUE(report.notes[1].about(1, 3)) << "another mesh's notes keep their numbers";
  EXPECT_TRUE(report.notes[2].about(0, 1));
  ASSERT_EQ(report.primitives.size(), 3u);
  EXPECT_EQ(report.primitives[2].primitive, 2);
  EXPECT_EQ(report.primitives[2].handling, Handling::implicit_uv);  // B's part, formerly 3
}

}  // namespace
}  // namespace gltfwarp
