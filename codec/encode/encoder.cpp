// Encoder pipeline (DESIGN.md, "Data flow"): every triangle primitive goes
// through Draco; primitives whose materials sample textures through
// TEXCOORD_0 lose TEXCOORD_0 (and TANGENT) and get the implicit UV map plus
// warped atlas images instead (implicit_uv_encoder.cpp).
#include "codec/encode/encoder.h"

#include <algorithm>

#include "codec/encode/implicit_uv_encoder.h"
#include "format/gltf/gltf_io.h"
#include "format/gltf/gltf_primitive.h"

namespace gltfwarp {

std::string encode_model(tinygltf::Model& model, const EncodeOptions& options, EncodeReport& report) {
  std::vector<int> replaced;
  ImplicitPlan plan;
  if (options.implicit_uvs) {
    std::string err = plan_implicit_uvs(model, plan, report);
    if (!err.empty()) return err;
  }
  size_t done = 0, total = 0;
  for (const auto& mesh : model.meshes) total += mesh.primitives.size();
  // A primitive too large for one atlas page is cut into parts, appended to
  // its mesh: the loop reaches them in turn.
  for (size_t mi = 0; mi < model.meshes.size(); ++mi) {
    for (size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
      if (options.progress)
        options.progress("geometry", std::min(1.0, total ? double(done++) / double(total) : 1.0));
      const tinygltf::Primitive& source = model.meshes[mi].primitives[pi];
      PrimitiveReport pr;
      pr.mesh = static_cast<int>(mi);
      pr.primitive = static_cast<int>(pi);
      const std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
      if (!is_triangle_mode(source.mode)) {
        pr.handling = "pass: not triangles (mode " + std::to_string(source.mode) + ")";
        report.primitives.push_back(pr);
        continue;
      }
      if (!source.targets.empty()) {
        // Draco cannot carry morph targets, and the targets' accessors must
        // keep matching the base vertices one to one.
        pr.handling = "raw: morph targets";
        report.notes.push_back(where + " kept raw: Draco cannot carry morph targets");
        report.primitives.push_back(pr);
        continue;
      }
      PrimitiveGeometry geom;
      std::string err = read_primitive(model, source, geom);
      if (!err.empty()) return where + ": " + err;
      pr.triangles = geom.triangles.size() / 3;
      pr.vertices = geom.vertex_count();

      bool implicit = plan.is_implicit(pr.mesh, pr.primitive);
      if (implicit) {
        // prepare_implicit_primitive consumes its geometry; keep the source
        // in case the primitive falls back to explicit UVs.
        PrimitiveGeometry work = geom;
        err = prepare_implicit_primitive(model, model.meshes[mi].primitives[pi], work, plan, options,
                                         replaced, pr);
        if (!err.empty()) return where + ": " + err;
        if (pr.cut_parts > 1)
          report.notes.push_back(
              where + " cut into " + std::to_string(pr.cut_parts) +
              " primitives (the others appended to its mesh): its texels would pass one atlas "
              "page (--max-atlas-size, --max-pages)");
        if (plan.is_implicit(pr.mesh, pr.primitive)) {
          plan.prims.back().report_index = report.primitives.size();
        } else {
          report.notes.push_back(where + ": " + pr.handling);
          implicit = false;
          // It may have been cut into parts before it fell back.
          err = read_primitive(model, model.meshes[mi].primitives[pi], geom);
          if (!err.empty()) return where + ": " + err;
        }
      }
      if (implicit) {
        report.primitives.push_back(pr);
        continue;
      }
      // Not `source`: a cut appends primitives to the mesh, which may move them.
      tinygltf::Primitive& prim = model.meshes[mi].primitives[pi];
      if (geom.triangles.empty()) {
        if (pr.handling.empty()) pr.handling = "pass: no triangles";
        report.notes.push_back(where + " passed through: it has no triangles");
        report.primitives.push_back(pr);
        continue;
      }
      if (options.raw_geometry) {
        write_primitive_plain(model, prim, geom, replaced);
        if (pr.handling.empty()) pr.handling = "raw";
        pr.geometry_bytes += plain_geometry_bytes(geom);
      } else {
        PrimitiveGeometry decoded;
        err = write_primitive_draco(model, prim, geom, options.draco, replaced, decoded, pr.geometry_bytes);
        if (!err.empty() && err.find("NaN") != std::string::npos) return where + ": " + err;
        if (!err.empty()) {
          // Draco cannot carry it (e.g. a MAT4 attribute): the primitive
          // stays exactly as it came (write_primitive_draco touched nothing).
          pr.handling = "pass: " + err;
          report.notes.push_back(where + " passed through: " + err);
        } else if (pr.handling.empty()) {
          pr.handling = "draco";
        }
      }
      report.primitives.push_back(pr);
    }
  }
  if (options.implicit_uvs) {
    std::string err = finish_implicit_uvs(model, plan, options, replaced, report);
    if (!err.empty()) return err;
    err = undo_fallen_back_cuts(model, plan, options, replaced, report);
    if (!err.empty()) return err;
  }
  // Primitives read from Draco and written raw no longer need Draco, and
  // with TEXCOORD_0 gone, quantized input may need KHR_mesh_quantization no more.
  retire_extension_if_unused(model, kDracoExtension);
  retire_mesh_quantization_if_unused(model);
  compact_buffers(model, replaced);
  return {};
}

}  // namespace gltfwarp
