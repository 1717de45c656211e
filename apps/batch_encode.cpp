#include "apps/batch_encode.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "apps/batch_progress.h"
#include "apps/child_process.h"
#include "apps/commands.h"
#include "codec/core/parallel.h"

namespace gltfwarp::cli {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// One file's work, decided before any encoding: its output, or why not.
struct Job {
  BatchInput item;
  std::string output;
  std::string refused;  // set: an error without running (two inputs share an output, ...)
};

std::vector<Job> plan_jobs(const std::vector<BatchInput>& all, const BatchOptions& o) {
  std::vector<Job> jobs;
  std::map<std::string, std::string> taken;  // canonical output -> the input that writes it
  for (const BatchInput& item : all) {
    Job job{item, output_path(item, o.out_dir, o.container), {}};
    std::error_code ec;
    const std::string key = fs::weakly_canonical(job.output, ec).string();
    if (key == fs::weakly_canonical(item.input, ec).string())
      job.refused = "the output would overwrite the input";
    else if (auto [it, fresh] = taken.emplace(key, item.input); !fresh)
      job.refused = "the output " + job.output + " is also " + it->second + "'s";
    jobs.push_back(std::move(job));
  }
  return jobs;
}

// The child's output: its summary (a line starting with '{') and its
// error (the lines "gltf-warp: ...", prefix removed).
void read_child_output(const std::string& text, Json& summary, std::string& error) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '{') {
      summary = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    } else if (line.rfind("gltf-warp: ", 0) == 0) {
      error += (error.empty() ? "" : "; ") + line.substr(11);
    }
  }
}

std::string signal_text(int sig) {
  const char* name = sigdescr_np(sig);
  return "the encoder crashed (signal " + std::to_string(sig) + (name ? std::string(", ") + name : "") + ")";
}

std::string human_line(const Json& r) {
  std::ostringstream s;
  s << r["input"].get<std::string>();
  const std::string status = r["status"].get<std::string>();
  if (status == "error") {
    s << ": " << r["error"].get<std::string>();
    return s.str();
  }
  s << " -> " << r["output"].get<std::string>();
  if (status == "skipped") {
    s << " (output is newer; --force redoes it)";
    return s.str();
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, ", %llu -> %llu bytes, %.1f s",
                static_cast<unsigned long long>(r["bytes_in"].get<uint64_t>()),
                static_cast<unsigned long long>(r["bytes_out"].get<uint64_t>()), r["seconds"].get<double>());
  s << buf;
  if (r.contains("psnr_db") && r["psnr_db"].is_number())
    s << ", surface PSNR " << r["psnr_db"].get<double>() << " dB";
  return s.str();
}

// Runs (or skips) one file; returns its report line.
Json run_job(const Job& job, const BatchOptions& o, const std::vector<std::string>& worker) {
  const auto t0 = std::chrono::steady_clock::now();
  Json r;
  r["input"] = job.item.input;
  r["output"] = job.output;
  r["status"] = "error";
  r["bytes_in"] = total_bytes(files_of(job.item.input));
  r["bytes_out"] = 0;
  auto finish = [&](FileStatus status, const std::string& error = {}) {
    r["status"] = to_string(status);
    if (status != FileStatus::error) r["bytes_out"] = total_bytes(files_of(job.output));
    r["seconds"] =
        std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() * 1000) /
        1000;
    if (!error.empty()) r["error"] = error;
    return r;
  };
  if (!job.refused.empty()) return finish(FileStatus::error, job.refused);
  if (!o.force && output_is_current(job.item.input, job.output)) return finish(FileStatus::skipped);
  std::error_code ec;
  fs::create_directories(fs::path(job.output).parent_path(), ec);
  if (ec) return finish(FileStatus::error, "cannot create the output's folder: " + ec.message());
  std::vector<std::string> argv = worker;
  for (const std::string& a : {std::string("--batch-worker-input"), job.item.input,
                               std::string("--batch-worker-output"), job.output})
    argv.push_back(a);
  const ChildResult child = run_child(argv);
  if (!child.started) return finish(FileStatus::error, child.error);
  Json summary;
  std::string error;
  read_child_output(child.output, summary, error);
  if (child.signal != 0) return finish(FileStatus::error, signal_text(child.signal));
  if (child.exit_code != 0 || !summary.is_object())
    return finish(FileStatus::error,
                  error.empty() ? "the encoder exited with " + std::to_string(child.exit_code) : error);
  for (auto it = summary.begin(); it != summary.end(); ++it) r[it.key()] = it.value();
  return finish(FileStatus::ok);
}

}  // namespace

int default_jobs() {
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    uint64_t kb = 0;
    meminfo >> kb;
    if (key == "MemAvailable:") return std::clamp(int(kb / (1843 * 1024)), 1, cores);
    meminfo.ignore(1 << 10, '\n');
  }
  return cores;
}

int run_batch_encode(const BatchOptions& o, const std::vector<std::string>& worker) {
  const InputList list = list_inputs(o.inputs, o.out_dir);
  if (!list.error.empty()) return fail(list.error, 2);
  if (list.items.empty()) return fail("no .gltf or .glb file among the inputs", 1);
  // Refusals are decided on the whole list, so that every shard agrees.
  const std::vector<Job> all = plan_jobs(list.items, o);
  std::vector<Job> jobs;
  for (size_t k : shard_indices(all.size(), o.shard)) jobs.push_back(all[k]);

  std::ofstream report;
  if (!o.report_path.empty()) {
    report.open(o.report_path, std::ios::trunc);
    if (!report) return fail("cannot write the report " + o.report_path + ": " + std::strerror(errno), 2);
  }
  const int nthreads = std::max(1, std::min(o.jobs > 0 ? o.jobs : default_jobs(), int(jobs.size())));
  BatchProgress progress(jobs.size(), o.quiet);
  std::mutex report_mutex;
  run_in_parallel(jobs.size(), size_t(nthreads), [&](size_t k, size_t) {
    const Json r = run_job(jobs[k], o, worker);
    {
      std::lock_guard<std::mutex> lock(report_mutex);
      if (report.is_open())
        report << r.dump(-1, ' ', false, Json::error_handler_t::replace) << '\n' << std::flush;
    }
    const std::string status = r["status"].get<std::string>();
    progress.file_done(status == "ok"        ? FileStatus::ok
                       : status == "skipped" ? FileStatus::skipped
                                             : FileStatus::error,
                       human_line(r));
  });
  std::string suffix;
  if (o.shard.count > 1)
    suffix += " (shard " + std::to_string(o.shard.index) + "/" + std::to_string(o.shard.count) + " of " +
              std::to_string(all.size()) + " files)";
  if (!o.report_path.empty()) suffix += "; report: " + o.report_path;
  progress.finish(suffix);
  return progress.failed() > 0 ? 1 : 0;
}

}  // namespace gltfwarp::cli
