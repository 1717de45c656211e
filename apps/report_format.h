// The encoder's report as text: the one place its typed state (handling,
// fallback reasons, notes) becomes words.
#pragma once

#include <string>

#include "codec/encode/encoder.h"

namespace gltfwarp::cli {

std::string fallback_text(const Fallback& fallback);
std::string handling_text(const PrimitiveReport& primitive);  // e.g. "implicit-uv", "fallback: ..."
std::string note_text(const Note& note);                      // one line, e.g. "mesh 0 primitive 1 ..."

void print_encode_report(const EncodeReport& report, const std::string& in, const std::string& out,
                         double seconds);

}  // namespace gltfwarp::cli
