#pragma once

#include <map>
#include <string>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/suite_file.hpp"

namespace plumetrace {

/// What a benchmark runs of a suite (docs/benchmark.md): which controllers and tasks, the runs
/// per cell and settings on top of every task.
struct BenchmarkChoice {
  /// Controllers added after the suite's (names a program has registered), or with `only` the
  /// only ones run.
  std::vector<std::string> controllers;
  bool only = false;               ///< run only `controllers`, not the suite's
  std::vector<std::string> tasks;  ///< the suite's tasks to run, in suite order (empty: all)
  int runs = 0;                    ///< runs per cell (0: the suite's)
  std::vector<Setting> overrides;  ///< --set, on every task
};

/// A benchmark ready to run: one sweep per task whose axis is controller.algorithm, every
/// task at the suite's master seed, so that trial t of every controller meets the same plume
/// and start (docs/experiments.md, "Seeds and pairing").
struct BenchmarkPlan {
  SuiteFile suite;                        ///< the suite read
  std::vector<SuiteTask> tasks;           ///< the tasks run, in suite order
  std::vector<std::string> controllers;   ///< the controllers run, in order
  int runs = 0;                           ///< runs per cell
  std::vector<ExpandedSweep> sweeps;      ///< one per task, named after it
  std::vector<std::string> task_digests;  ///< one per task (see `digest`)
  /// What every result carries: the hash (hash_text) of the suite's name, version, seed, runs
  /// per cell and every task's digest, a task's being the hash of its name, the seed, the runs
  /// and its resolved scenario's canonical values without the controllers' keys (those the
  /// task or --set gives stay). So the same suite, version, tasks, seed and run count give the
  /// same digest whatever controllers are run, and changing any of them changes it.
  std::string digest;
};

/// Plans a benchmark of `suite`; throws ConfigError naming the key (--controller, --task, the
/// suite's `controllers`) for an unknown controller or task, or naming the suite file and the
/// task for a task whose settings are refused.
BenchmarkPlan plan_benchmark(const SuiteFile& suite, const BenchmarkChoice& choice);

/// The manifest of a benchmark's output folder (OUT/benchmark.json, docs/benchmark.md): the
/// suite (name, version, title, file, digest, seed, runs, tasks with their texts, success rule,
/// robots, timeout and digest), the controllers (name, origin "built-in", "registered" or
/// "python", file, null_model) and the plumetrace version. `python_files` maps each controller
/// written in Python to the file it came from.
std::string benchmark_manifest(const BenchmarkPlan& plan,
                               const std::map<std::string, std::string>& python_files = {});

}  // namespace plumetrace
