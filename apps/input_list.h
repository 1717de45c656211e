// The input list of a batch encode (`gltf-warp encode A B DIR --out-dir OUT`):
// which files, in which order, which share of them this machine takes
// (--shard), where each one's output goes, and whether that output is
// already current (resume). Plain functions over paths; no encoding here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gltfwarp::cli {

struct BatchInput {
  std::string input;     // as found: the argument, or the argument joined with the path below it
  std::string relative;  // its path under --out-dir: below its directory argument, or its file name
};

struct InputList {
  std::vector<BatchInput> items;  // sorted (see list_inputs)
  std::string error;              // one line; set when an argument is neither a file nor a directory
};

// Every argument that is a file is taken as it is; every directory is walked
// recursively for *.gltf and *.glb (any letter case), skipping `exclude`
// (the output directory, so that a rerun never encodes its own outputs) and
// hidden entries (names starting with '.'). Sorted by argument order, then
// by relative path (byte order), so the list, and hence every shard, is the
// same on every machine that sees the same tree.
InputList list_inputs(const std::vector<std::string>& arguments, const std::string& exclude = "");

// `--shard i/n`: this machine's share is every n-th file of the sorted list,
// starting at the i-th (index mod n). Interleaving keeps the shards within
// one file of each other in count and spreads the large models that sit
// together in one folder across all shards.
struct Shard {
  uint32_t index = 0, count = 1;  // 0 <= index < count
};
// Parses "i/n"; returns an empty string, or a one-line error.
std::string parse_shard(const std::string& text, Shard& shard);
// The indices, into a list of `size`, of this shard's files.
std::vector<size_t> shard_indices(size_t size, Shard shard);

// The output of `item` under `out_dir`. container: "keep" (the input's own
// extension: .gltf writes .gltf + .bin, .glb writes .glb), "glb" or "gltf".
std::string output_path(const BatchInput& item, const std::string& out_dir, const std::string& container);

// The files a glTF file consists of: itself, and for a .gltf every buffer
// and image it names by a relative URI that exists (not data: URIs). A file
// that cannot be parsed is just itself.
std::vector<std::filesystem::path> files_of(const std::string& gltf_path);
uint64_t total_bytes(const std::vector<std::filesystem::path>& files);

// True when `output` and its files exist and the oldest of them is newer
// than the newest file of `input` (so editing a .gltf's .bin or a texture
// redoes it too).
bool output_is_current(const std::string& input, const std::string& output);

}  // namespace gltfwarp::cli
