// The codec's one thread pool (codec/core/parallel.h): every job runs once,
// on a worker that exists, and one worker stays on one thread, which is what
// per-worker scratch (and the warp's per-thread texture-system state) relies on.
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "codec/core/parallel.h"

namespace gltfwarp {
namespace {

TEST(Parallel, EveryJobRunsOnceOnAWorkerThatKeepsItsThread) {
  for (const size_t count : {0u, 1u, 2u, 7u, 1000u})
    for (const size_t workers : {1u, 2u, 3u, 8u}) {
      std::vector<std::atomic<int>> runs(count);
      std::mutex lock;
      std::map<size_t, std::thread::id> thread_of_worker;
      bool worker_in_range = true, worker_kept_its_thread = true;
      run_in_parallel(count, workers, [&](size_t i, size_t worker) {
        ++runs[i];
        std::lock_guard<std::mutex> hold(lock);
        worker_in_range = worker_in_range && worker < workers && worker < std::max<size_t>(count, 1);
        const auto [at, added] = thread_of_worker.emplace(worker, std::this_thread::get_id());
        worker_kept_its_thread =
            worker_kept_its_thread && (added || at->second == std::this_thread::get_id());
      });
      for (size_t i = 0; i < count; ++i) EXPECT_EQ(runs[i].load(), 1) << i << " of " << count;
      EXPECT_TRUE(worker_in_range) << count << " jobs, " << workers << " workers";
      EXPECT_TRUE(worker_kept_its_thread) << count << " jobs, " << workers << " workers";
      // Worker 0 is the calling thread.
      if (thread_of_worker.count(0)) {
        EXPECT_EQ(thread_of_worker[0], std::this_thread::get_id());
      }
    }
}

TEST(Parallel, WorkerCountStaysWithinJobsCapAndCores) {
  const size_t cores = std::max<size_t>(1, std::thread::hardware_concurrency());
  EXPECT_EQ(worker_count(0), 1u);
  EXPECT_EQ(worker_count(1), 1u);
  EXPECT_EQ(worker_count(1000), cores);
  EXPECT_EQ(worker_count(1000, 3), 3u);
  EXPECT_EQ(worker_count(2, 3), 2u);
  EXPECT_EQ(worker_count(5, 1), 1u);
}

}  // namespace
}  // namespace gltfwarp
