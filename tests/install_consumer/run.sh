#!/usr/bin/env bash
# The install test (issue 17): installs the build tree to a prefix, builds a
# small consumer of each component against it with find_package, and runs
# them: the encoder consumer encodes a generated plane (one patch; with
# fallbacks off, as its busy texture would keep explicit UVs), the decoder
# consumer decodes the result.
# Usage: run.sh BUILD_DIR SOURCE_DIR CLI
set -euo pipefail
build=$1 src=$2 cli=$3
work="$build/install-test"
rm -rf "$work" && mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
for c in decoder encoder; do
  cmake -S "$src/tests/install_consumer/$c" -B "$work/$c" -DCMAKE_PREFIX_PATH="$work/prefix" \
    -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$work/$c" -j2 >/dev/null
done
"$cli" sample --shape plane -o "$work/sample.glb" >/dev/null
"$work/encoder/encode_consumer" "$work/sample.glb" "$work/encoded.glb"
"$work/decoder/decode_consumer" "$work/encoded.glb" "$work/decoded.glb"
echo "install test: both components built against $work/prefix and ran"
