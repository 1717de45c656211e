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

Error encode_model(tinygltf::Model& model, const EncodeOptions& options, EncodeReport& report) {
  std::vector<int> replaced;
  ImplicitPlan plan;
  if (options.implicit_uvs)
    if (Error e = plan_implicit_uvs(model, plan, report); e.failed()) return e;
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
      const std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi) + ": ";
      Note note;  // about this primitive
      note.mesh = pr.mesh;
      note.primitive = pr.primitive;
      if (!is_triangle_mode(source.mode)) {
        pr.handling = Handling::pass_not_triangles;
        pr.mode = source.mode;
        report.primitives.push_back(pr);
        continue;
      }
      if (!source.targets.empty()) {
        // Draco cannot carry morph targets, and the targets' accessors must
        // keep matching the base vertices one to one.
        pr.handling = Handling::raw_morph_targets;
        note.kind = NoteKind::morph_targets_raw;
        report.notes.push_back(note);
        report.primitives.push_back(pr);
        continue;
      }
      PrimitiveGeometry geom;
      if (Error e = error_if(ErrorCode::invalid_input, read_primitive(model, source, geom)); e.failed())
        return e.at(where);
      pr.triangles = geom.triangles.size() / 3;
      pr.vertices = geom.vertex_count();

      bool implicit = plan.is_implicit(pr.mesh, pr.primitive);
      if (implicit) {
        // prepare_implicit_primitive consumes its geometry; keep the source
        // in case the primitive falls back to explicit UVs.
        PrimitiveGeometry work = geom;
        if (Error e = prepare_implicit_primitive(model, model.meshes[mi].primitives[pi], work, plan, options,
                                                 replaced, pr);
            e.failed())
          return e.at(where);
        if (pr.cut_parts > 1) {
          Note cut = note;
          cut.kind = NoteKind::cut_into_parts;
          cut.parts = pr.cut_parts;
          report.notes.push_back(cut);
        }
        if (plan.is_implicit(pr.mesh, pr.primitive)) {
          plan.prims.back().report_index = report.primitives.size();
        } else {
          Note fell = note;
          fell.kind = NoteKind::fallback;
          fell.fallback = pr.fallback;
          report.notes.push_back(fell);
          implicit = false;
          // It may have been cut into parts before it fell back.
          if (Error e = error_if(ErrorCode::invalid_input,
                                 read_primitive(model, model.meshes[mi].primitives[pi], geom));
              e.failed())
            return e.at(where);
        }
      }
      if (implicit) {
        report.primitives.push_back(pr);
        continue;
      }
      const bool fell_back = pr.handling == Handling::fallback;
      // Not `source`: a cut appends primitives to the mesh, which may move them.
      tinygltf::Primitive& prim = model.meshes[mi].primitives[pi];
      if (geom.triangles.empty()) {
        if (!fell_back) pr.handling = Handling::pass_no_triangles;
        note.kind = NoteKind::no_triangles;
        report.notes.push_back(note);
        report.primitives.push_back(pr);
        continue;
      }
      if (options.raw_geometry) {
        write_primitive_plain(model, prim, geom, replaced);
        if (!fell_back) pr.handling = Handling::raw;
        pr.geometry_bytes += plain_geometry_bytes(geom);
      } else {
        // Draco quantizes over each attribute's range: a NaN or infinity is
        // an error in the input, not something to pass through.
        if (Error e = error_if(ErrorCode::invalid_input, non_finite_attribute(geom)); e.failed())
          return e.at(where);
        PrimitiveGeometry decoded;
        const std::string err =
            write_primitive_draco(model, prim, geom, options.draco, replaced, decoded, pr.geometry_bytes);
        if (!err.empty()) {
          // Draco cannot carry it (e.g. a MAT4 attribute): the primitive
          // stays exactly as it came (write_primitive_draco touched nothing).
          pr.handling = Handling::pass_unsupported;
          pr.detail = err;
          note.kind = NoteKind::draco_unsupported;
          note.detail = err;
          report.notes.push_back(note);
        } else if (!fell_back) {
          pr.handling = Handling::draco;
        }
      }
      report.primitives.push_back(pr);
    }
  }
  plan.prefetched = {};  // what no part took (a part that fell back or was cut again)
  if (options.implicit_uvs) {
    if (Error e = finish_implicit_uvs(model, plan, options, replaced, report); e.failed()) return e;
    if (Error e = undo_fallen_back_cuts(model, plan, options, replaced, report); e.failed()) return e;
  }
  // Primitives read from Draco and written raw no longer need Draco, and
  // with TEXCOORD_0 gone, quantized input may need KHR_mesh_quantization no more.
  retire_extension_if_unused(model, kDracoExtension);
  retire_mesh_quantization_if_unused(model);
  compact_buffers(model, replaced);
  return {};
}

}  // namespace gltfwarp
