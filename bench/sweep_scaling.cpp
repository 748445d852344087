// What limits a sweep's speed-up on many cores, measured on one: each plume group of the campaign
// is timed alone on one thread, the store's writer is timed on the rows, and the pool's schedule
// (every free worker takes the next group in queue order) is replayed on those times for 1 to
// 64 workers (docs/performance.md, "Scaling past two cores").
//
//   plumetrace_scaling SWEEP.toml... [--store FILE]
//
// Prints the groups' sizes and times, the efficiency each worker count would reach with the
// groups as run_tasks makes them (work_groups), what splitting every group in two costs, and the
// rows per second the store takes.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <queue>
#include <string>
#include <vector>

#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/version.hpp"

namespace {

using namespace plumetrace;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// the time the pool takes for jobs of these durations, in this order, on `workers` threads:
// each free worker takes the next job
double makespan(const std::vector<double>& jobs, int workers) {
  std::priority_queue<double, std::vector<double>, std::greater<>> free_at;
  for (int w = 0; w < workers; ++w) free_at.push(0.0);
  double end = 0.0;
  for (const double job : jobs) {
    const double start = free_at.top();
    free_at.pop();
    free_at.push(start + job);
    end = std::max(end, start + job);
  }
  return end;
}

struct Timed {
  std::vector<double> seconds;
  std::vector<RunRow> rows;
  std::vector<std::size_t> counts;  // each group's rows (a team's run gives one a robot)
};

Timed time_groups(const std::vector<ExpandedSweep>& sweeps, const std::vector<TaskGroup>& groups) {
  Timed out;
  for (const TaskGroup& g : groups) {
    const auto start = Clock::now();
    std::vector<RunRow> rows = run_group(sweeps, g, {});
    out.seconds.push_back(seconds_since(start));
    out.counts.push_back(rows.size());
    out.rows.insert(out.rows.end(), rows.begin(), rows.end());
  }
  return out;
}

void describe(const char* what, const std::vector<TaskGroup>& groups,
              const std::vector<double>& seconds) {
  double total = 0.0, lo = INFINITY, hi = 0.0, sq = 0.0;
  std::size_t runs = 0;
  for (std::size_t i = 0; i < seconds.size(); ++i) {
    total += seconds[i];
    sq += seconds[i] * seconds[i];
    lo = std::min(lo, seconds[i]);
    hi = std::max(hi, seconds[i]);
    runs += groups[i].size();
  }
  const double n = static_cast<double>(seconds.size());
  const double mean = total / n;
  const double sd = std::sqrt(std::max(0.0, sq / n - mean * mean));
  std::printf(
      "%s: %zu groups, %zu runs (%.1f a group), %.2f s on one thread; a group %.3f s "
      "(min %.3f, max %.3f, cv %.2f)\n",
      what, seconds.size(), runs, static_cast<double>(runs) / n, total, mean, lo, hi, sd / mean);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  std::string store_path =
      (std::filesystem::temp_directory_path() / "plumetrace_scaling.sqlite").string();
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--store" && i + 1 < argc) {
      store_path = argv[++i];
    } else if (arg.rfind("--", 0) == 0) {
      std::fprintf(stderr, "plumetrace_scaling: unknown option %s\n", arg.c_str());
      return 2;
    } else {
      files.push_back(arg);
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: plumetrace_scaling SWEEP.toml... [--store FILE]\n");
    return 2;
  }
  try {
    std::vector<ExpandedSweep> sweeps;
    for (const std::string& f : files) sweeps.push_back(expand_sweep(read_sweep_file(f), {}));
    const std::vector<RunTask> tasks = missing_runs(sweeps, {}, 0);
    const std::vector<TaskGroup> groups = plume_groups(sweeps, tasks, true);
    const Timed whole = time_groups(sweeps, groups);
    describe("shared plumes", groups, whole.seconds);
    double one = 0.0;
    for (const double s : whole.seconds) one += s;

    // each group in two parts: what a split costs (each part simulates its plume again)
    const std::vector<TaskGroup> halves = split_groups(groups, 2 * groups.size());
    const Timed split = time_groups(sweeps, halves);
    describe("split in two", halves, split.seconds);
    double two = 0.0;
    for (const double s : split.seconds) two += s;
    std::printf("splitting every group in two costs %.1f%% more work\n", 100.0 * (two / one - 1));

    // the schedule of run_tasks (groups split below 2 per worker) and, for comparison, with
    // every group split in two and with the longest groups first
    std::printf(
        "\n| workers | groups | efficiency (as run_tasks) | never split | groups split in "
        "two | longest first |\n|---|---|---|---|---|---|\n");
    std::vector<double> longest = whole.seconds;
    std::sort(longest.rbegin(), longest.rend());
    for (const int p : {1, 2, 4, 8, 16, 32, 64}) {
      const bool splits =
          work_groups(sweeps, tasks, true, static_cast<std::size_t>(p)).size() != groups.size();
      const std::vector<double>& jobs = splits ? split.seconds : whole.seconds;
      const double base = one / p;
      std::printf("| %d | %zu | %.2f%s | %.2f | %.2f | %.2f |\n", p,
                  splits ? halves.size() : groups.size(), base / makespan(jobs, p),
                  splits ? " (split)" : "", base / makespan(whole.seconds, p),
                  base / makespan(split.seconds, p), base / makespan(longest, p));
    }

    // the store's one writer: every row in batches of a group's rows, as a campaign writes them
    std::filesystem::remove(store_path);
    {
      Store store(store_path, sweeps, plumetrace::kVersion, true);
      store.put_points(sweeps);
      const auto start = Clock::now();
      std::size_t at = 0;
      for (const std::size_t rows : whole.counts) {
        store.insert({whole.rows.begin() + static_cast<std::ptrdiff_t>(at),
                      whole.rows.begin() + static_cast<std::ptrdiff_t>(at + rows)});
        at += rows;
      }
      const double t = seconds_since(start);
      std::printf(
          "\nstore: %zu rows in %zu transactions in %.3f s: %.0f rows/s; the campaign "
          "makes %.0f rows/s per thread\n",
          whole.rows.size(), groups.size(), t, static_cast<double>(whole.rows.size()) / t,
          static_cast<double>(whole.rows.size()) / one);
    }
    std::filesystem::remove(store_path);
    for (const char* suffix : {"-wal", "-shm"}) std::filesystem::remove(store_path + suffix);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plumetrace_scaling: %s\n", e.what());
    return 2;
  }
  return 0;
}
