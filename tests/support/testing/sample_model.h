// Generated, textured sample models: a glTF scene made from one of the
// shapes in tests/support/testing/shapes.h with a procedural texture, so the CLI and the
// tests have a model to run on without any external file.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace gltfwarp {

// Names accepted by make_sample_model.
std::vector<std::string> sample_model_names();

// Builds the named sample ("twisted-cone", "torus", "sphere", ...), with
// about `faces` triangles and a texture_size x texture_size PNG base colour.
// Empty string or a one-line error.
std::string make_sample_model(const std::string& name, int faces, int texture_size, tinygltf::Model& model);

}  // namespace gltfwarp
