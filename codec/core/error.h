// The errors of the encoder and decoder pipelines: a code a program can act
// on, and a one-line message for people. No program logic reads the
// message; the CLI prints it and maps the code to its exit status.
#pragma once

#include <string>
#include <utility>

namespace gltfwarp {

enum class ErrorCode {
  ok = 0,
  invalid_input,  // the model breaks glTF or its own declarations (an accessor past its buffer,
                  // NaN positions, an image that does not decode, a malformed bitstream)
  internal,       // a stage failed on input it had accepted (packing, the warp): a bug to report
};

struct Error {
  ErrorCode code = ErrorCode::ok;
  std::string message;  // one line; empty when ok

  Error() = default;
  Error(ErrorCode c, std::string m) : code(c), message(std::move(m)) {}
  bool failed() const { return code != ErrorCode::ok; }
  // The same error, its message prefixed by where it happened ("mesh 0 primitive 2: ...").
  Error at(const std::string& where) const { return {code, where + message}; }
};

// An error of `code` when `message` (a lower layer's one-line error) is not
// empty, else ok: for the layers below that report failures as text.
inline Error error_if(ErrorCode code, std::string message) {
  if (message.empty()) return {};
  return {code, std::move(message)};
}

}  // namespace gltfwarp
