// Independent jobs shared out over threads. Every parallel loop of the codec
// goes through run_in_parallel, so that the rule it keeps is written once:
// a job writes only its own results (or its worker's scratch), and the
// outcome does not depend on the thread count or on which thread ran what.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace gltfwarp {

// Threads worth starting for `jobs` jobs: at most one per job, at most `cap`
// (0: one per hardware thread), at least one.
inline size_t worker_count(size_t jobs, size_t cap = 0) {
  const size_t cores = std::max<size_t>(1, std::thread::hardware_concurrency());
  return std::max<size_t>(1, std::min(jobs, cap > 0 ? cap : cores));
}

// Calls job(i, worker) once for every i < count, on `workers` threads (the
// calling one included), and returns when all are done. Jobs are taken in
// ascending order by whichever thread is free; worker < workers names the
// thread that runs a job, and one worker runs on one thread throughout, so
// per-worker scratch (and per-thread state such as a texture system's) can
// live in a vector indexed by it.
template <class Job>
void run_in_parallel(size_t count, size_t workers, const Job& job) {
  workers = std::max<size_t>(1, std::min(workers, count));
  std::atomic<size_t> next{0};
  auto work = [&](size_t worker) {
    for (size_t i; (i = next.fetch_add(1)) < count;) job(i, worker);
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
  work(0);
  for (std::thread& th : pool) th.join();
}

}  // namespace gltfwarp
