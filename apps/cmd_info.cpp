#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "codec/core/layout.h"
#include "codec/core/layout_report.h"
#include "codec/decode/embedding_mesh.h"
#include "codec/decode/implicit_uv_primitive.h"
#include "format/bitstream/decode_uvs.h"
#include "format/bitstream/uvmap_codec.h"
#include "format/gltf/extension.h"
#include "format/gltf/gltf_accessors.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp::cli {
namespace {

// The bufferView an extension object names, or -1 (value_index refuses
// negatives, non-integers and out-of-int-range numbers).
int named_view(const tinygltf::Model& m, const tinygltf::Value& ext) {
  if (!ext.IsObject() || !ext.Has("bufferView")) return -1;
  const int v = value_index(ext.Get("bufferView"));
  return v >= 0 && static_cast<size_t>(v) < m.bufferViews.size() ? v : -1;
}

size_t view_bytes(const tinygltf::Model& m, const tinygltf::Value& ext) {
  const int v = named_view(m, ext);
  return v >= 0 ? m.bufferViews[v].byteLength : 0;
}

}  // namespace

Runner add_info(CLI::App& app) {
  struct Args {
    std::string in;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  app.add_option("file", a->in, "A .gltf or .glb (encoded or not)")->required()->check(CLI::ExistingFile);
  app.add_flag("--json", a->json, "Print JSON instead of a table");
  return [a]() {
    tinygltf::Model model;
    GltfReadResult rr = read_gltf(a->in, model);
    if (!rr.ok) return fail(rr.error);
    nlohmann::json out;
    out["file"] = a->in;
    out["primitives"] = nlohmann::json::array();
    for (size_t mi = 0; mi < model.meshes.size(); ++mi)
      for (size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
        const auto& prim = model.meshes[mi].primitives[pi];
        nlohmann::json p;
        p["mesh"] = mi;
        p["primitive"] = pi;
        const bool draco = prim.extensions.count(kDracoExtension) > 0;
        const bool ours = prim.extensions.count(ext::kName) > 0;
        p["geometry"] = draco ? "draco" : "plain";
        p["implicit_uv"] = ours;
        if (!is_triangle_mode(prim.mode)) {
          p["mode"] = prim.mode;
          out["primitives"].push_back(p);
          continue;
        }
        PrimitiveGeometry geom;
        std::string err = read_primitive(model, prim, geom);
        if (!err.empty())
          return fail(a->in + ": mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) + ": " +
                      err);
        const size_t tris = geom.triangles.size() / 3, verts = geom.vertex_count();
        p["triangles"] = tris;
        p["vertices"] = verts;
        if (draco) {
          p["geometry_bytes"] = view_bytes(model, prim.extensions.at(kDracoExtension));
        } else {
          size_t b = 0;
          for (const auto& at : geom.attributes) b += at.data.size();
          p["geometry_bytes"] = b;
        }
        if (ours) {
          // The checks decode makes, so that info never replays what decode would refuse.
          ReplayInput in;
          if (std::string bad = replay_input(model, prim, geom, in); !bad.empty())
            return fail(a->in + ": mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) + ": " +
                        bad);
          UvStreamInfo si;
          UvStatus st = read_uvmap_info(in.bitstream, si);
          if (st != UvStatus::ok) return fail(a->in + ": bad UV bitstream: " + to_string(st));
          p["bitstream_bytes"] = si.total_bytes;
          p["bitstream_sections"] = {{"header", si.header_bytes},
                                     {"partition", si.partition_bytes},
                                     {"placements", si.placement_bytes}};
          p["patches"] = si.patch_count;
          p["atlas"] = {si.atlas_width, si.atlas_height};
          p["tau"] = si.tau;
          p["bits_per_vertex"] = verts ? 8.0 * si.total_bytes / double(verts) : 0.0;
          p["bits_per_triangle"] = tris ? 8.0 * si.total_bytes / double(tris) : 0.0;
          // Quality of the map, measured on the replay the decoder runs.
          std::vector<uint32_t> p2v;
          const TriMesh mesh = embedding_mesh(*in.position, geom.triangles, p2v);
          std::vector<float> uv;
          UvMap map;
          st = decode_uvs(mesh, in.bitstream, uv, &map);
          if (st != UvStatus::ok) return fail(a->in + ": bad UV bitstream: " + to_string(st));
          std::vector<double> xy;
          layout_patches(mesh, map.patch_of_face, map.patch_count, xy, map.seeds, map.methods, map.solve);
          const EmbedReport er = measure_embedding(mesh, map.patch_of_face, map.patch_count, xy, si.tau);
          p["max_distortion"] = er.max_distortion;
          p["mean_distortion"] = er.mean_distortion;
          p["flipped"] = er.flipped;
          p["zero_area"] = er.zero_area;
          p["seam_edges"] = er.seam_edges;
          p["seam_length"] = er.seam_length;
          p["rect_fill"] = er.fill;
          p["holes"] = er.holes;
          p["version"] = std::to_string(si.version_major) + "." + std::to_string(si.version_minor);
          p["solve_patches"] =
              std::count(map.methods.begin(), map.methods.end(), uint8_t(LayoutMethod::solve));
          // 1.2: the work the stream asks of every decoder per solved face; 1.4: its ARAP weights.
          if (si.flags & kUvFlagMethods)
            p["solve"] = {{"tutte_steps", map.solve.tutte_iterations},
                          {"arap_rounds", map.solve.arap_iterations},
                          {"arap_steps", map.solve.arap_cg_iterations},
                          {"cotangent_weights", map.solve.cotangent_weights}};
          // 1.3: patches placed on another patch's texels (texel reuse), and how many of those mirror.
          p["fine_patches"] = std::count_if(map.placements.begin(), map.placements.end(),
                                            [](const PatchPlacement& pl) { return pl.fine; });
          p["mirrored_patches"] =
              std::count_if(map.placements.begin(), map.placements.end(),
                            [](const PatchPlacement& pl) { return pl.fine && pl.mirror; });
        }
        out["primitives"].push_back(p);
      }
    size_t image_bytes = 0;
    for (const auto& img : model.images) {
      const size_t b = img.bufferView >= 0 && static_cast<size_t>(img.bufferView) < model.bufferViews.size()
                           ? model.bufferViews[img.bufferView].byteLength
                           : img.image.size();
      image_bytes += b;
      out["images"].push_back({{"name", img.name}, {"mime", img.mimeType}, {"bytes", b}});
    }
    out["image_bytes"] = image_bytes;
    if (a->json) {
      std::printf("%s\n", out.dump(2).c_str());
      return 0;
    }
    std::printf("%s\n", a->in.c_str());
    std::printf("%-8s %-14s %8s %8s %9s %9s %7s %7s %6s %6s %6s %5s\n", "prim", "geometry", "tris", "verts",
                "geom B", "uvmap B", "bits/v", "patches", "maxD", "seams", "fill", "holes");
    for (const auto& p : out["primitives"]) {
      const std::string id =
          std::to_string(p["mesh"].get<size_t>()) + "/" + std::to_string(p["primitive"].get<size_t>());
      const std::string kind =
          p["geometry"].get<std::string>() + (p["implicit_uv"].get<bool>() ? "+implicit" : "");
      if (!p.contains("triangles")) {
        std::printf("%-8s %-14s (not triangles)\n", id.c_str(), kind.c_str());
        continue;
      }
      std::printf("%-8s %-14s %8zu %8zu %9zu", id.c_str(), kind.c_str(), p["triangles"].get<size_t>(),
                  p["vertices"].get<size_t>(), p["geometry_bytes"].get<size_t>());
      if (p.contains("bitstream_bytes"))
        std::printf(" %9zu %7.2f %7u %6.3f %6u %6.2f %5u\n", p["bitstream_bytes"].get<size_t>(),
                    p["bits_per_vertex"].get<double>(), p["patches"].get<unsigned>(),
                    p["max_distortion"].get<double>(), p["seam_edges"].get<unsigned>(),
                    p["rect_fill"].get<double>(), p["holes"].get<unsigned>());
      else
        std::printf("\n");
    }
    std::printf("images: %zu, %zu bytes\n", model.images.size(), image_bytes);
    return 0;
  };
}

}  // namespace gltfwarp::cli
