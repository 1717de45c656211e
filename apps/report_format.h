// Human-readable printing of the encoder's report.
#pragma once

#include <string>

#include "codec/encode/encoder.h"

namespace gltfwarp::cli {

void print_encode_report(const EncodeReport& report, const std::string& in, const std::string& out,
                         double seconds);

}  // namespace gltfwarp::cli
