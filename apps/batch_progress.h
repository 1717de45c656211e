// What a batch encode shows on stderr while it runs: a progress bar when
// stderr is a terminal, else one plain line per file (for logs: CI, Slurm,
// Kubernetes). Errors are always printed, one line each. Thread-safe.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace gltfwarp::cli {

enum class FileStatus { ok, skipped, error };
const char* to_string(FileStatus s);

class BatchProgress {
 public:
  BatchProgress(size_t total, bool quiet);
  // One file finished; `line` describes it (no status, no newline).
  void file_done(FileStatus status, const std::string& line);
  // Clears the bar and prints the summary line.
  void finish(const std::string& suffix);

  size_t failed() const { return counts_[int(FileStatus::error)]; }

 private:
  void draw_bar() const;

  std::mutex mutex_;
  const size_t total_;
  const bool quiet_, tty_;
  size_t done_ = 0;
  size_t counts_[3] = {0, 0, 0};
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace gltfwarp::cli
