#include "apps/batch_progress.h"

#include <unistd.h>
#include <cstdio>

namespace gltfwarp::cli {

const char* to_string(FileStatus s) {
  switch (s) {
    case FileStatus::ok:
      return "ok";
    case FileStatus::skipped:
      return "skipped";
    default:
      return "error";
  }
}

BatchProgress::BatchProgress(size_t total, bool quiet) : total_(total), quiet_(quiet), tty_(isatty(2) != 0) {
  if (tty_ && !quiet_) draw_bar();
}

void BatchProgress::draw_bar() const {
  constexpr int width = 30;
  const double f = total_ ? double(done_) / double(total_) : 1.0;
  const int filled = int(f * width);
  std::string bar(size_t(filled), '#');
  bar.resize(width, '.');
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char eta[32] = "";
  if (done_ > 0 && done_ < total_) {
    const int left = int(elapsed / double(done_) * double(total_ - done_));
    std::snprintf(eta, sizeof eta, ", about %dm%02ds left", left / 60, left % 60);
  }
  std::fprintf(stderr, "\r[%s] %zu/%zu files, %zu failed%s\033[K", bar.c_str(), done_, total_,
               counts_[int(FileStatus::error)], eta);
  std::fflush(stderr);
}

void BatchProgress::file_done(FileStatus status, const std::string& line) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  ++counts_[int(status)];
  const bool print = status == FileStatus::error || !quiet_;
  if (print && (!tty_ || status == FileStatus::error)) {
    if (tty_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "[%zu/%zu] %-7s %s\n", done_, total_, to_string(status), line.c_str());
  }
  if (tty_ && !quiet_) draw_bar();
}

void BatchProgress::finish(const std::string& suffix) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (tty_ && !quiet_) std::fprintf(stderr, "\r\033[K");
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (!quiet_ || counts_[int(FileStatus::error)] > 0)
    std::fprintf(stderr, "gltf-warp: %zu encoded, %zu skipped, %zu failed of %zu files in %.1f s%s\n",
                 counts_[int(FileStatus::ok)], counts_[int(FileStatus::skipped)],
                 counts_[int(FileStatus::error)], total_, elapsed, suffix.c_str());
}

}  // namespace gltfwarp::cli
