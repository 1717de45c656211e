// Runs a program as a child process and captures what it prints. The batch
// encoder runs each file in its own child (apps/batch_encode.h says why).
#pragma once

#include <string>
#include <vector>

namespace gltfwarp::cli {

struct ChildResult {
  bool started = false;  // false: could not start it (error says why)
  int exit_code = -1;    // when it exited
  int signal = 0;        // when a signal ended it (a crash: 11 SIGSEGV, 6 SIGABRT, 9 SIGKILL ...)
  std::string output;    // its stdout and stderr, interleaved
  std::string error;
};

// argv[0] is the program's path (not searched in PATH). stdin is /dev/null.
// Safe to call from several threads at once: the pipe is close-on-exec, so
// no other child inherits it and each read ends when its own child exits.
ChildResult run_child(const std::vector<std::string>& argv);

// The path of the running executable (/proc/self/exe), "" if unknown.
std::string self_executable();

}  // namespace gltfwarp::cli
