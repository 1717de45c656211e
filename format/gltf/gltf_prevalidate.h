// Checks on a glTF file that tinygltf 2.7 does not make, run before
// tinygltf sees the file: JSON nesting depth, integer-valued index members,
// relative URIs, image bufferViews inside their buffers, primitives and the
// codec's own extensions well-formed. Each returns a one-line reason.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace gltfwarp {

// True when arrays/objects nest deeper than `limit` (brackets outside
// strings). tinygltf turns extras and extensions into Values recursively and
// nlohmann serialises recursively: unbounded nesting would overflow the stack.
bool json_too_deep(const char* p, size_t n, size_t limit);

bool is_data_uri(const std::string& uri);
// "http:", "https:", "file:", ...: an absolute URI we do not fetch.
bool has_uri_scheme(const std::string& uri);
bool is_absolute_path(const std::string& uri);

// Empty when the parsed document passes every check.
std::string prevalidate(const nlohmann::json& doc);

}  // namespace gltfwarp
