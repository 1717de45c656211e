// The one-object JSON summary of an encode that a batch report line carries
// (apps/batch_encode.h): what the encoder measured and decided, per file.
#pragma once

#include <nlohmann/json.hpp>

#include "codec/encode/encoder.h"

namespace gltfwarp::cli {

// {"psnr_db": worst atlas surface PSNR or null when no atlas was measured,
//  "handling": {"implicit": n, "explicit": n, "untouched": n},
//  "fallbacks": n, "primitives": n, "atlases": n, "patches": n}
// implicit: TEXCOORD_0 replaced by our stream; explicit: Draco or raw
// geometry with the attributes it had (fallbacks, the primitives that
// were candidates but kept explicit UVs, count here too); untouched:
// passed through (points, lines, morph targets...).
nlohmann::json encode_summary(const EncodeReport& report);

}  // namespace gltfwarp::cli
