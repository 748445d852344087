#include "plumetrace/io/benchmark.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/paths.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

bool is_python_file(const std::string& name) { return ends_with(name, ".py"); }

// the suite a benchmark runs when none is named
std::string default_suite() { return data_dir() + "/studies/benchmark/suite.toml"; }

}  // namespace

BenchmarkCommand::BenchmarkCommand(int argc, char** argv) {
  int i = 1;
  while (i < argc && std::string(argv[i]) != "benchmark") ++i;
  for (++i; i < argc; ++i) words.emplace_back(argv[i]);
}

CLI::App* BenchmarkCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "benchmark",
      "run controllers on every task of a benchmark suite into a results store and write the "
      "leaderboard (under mpirun: across the ranks); --compare two results");
  sub->add_option("suite", file,
                  "suite file (default: the built-in suite, studies/benchmark/suite.toml)")
      ->check(not_empty());
  sub->add_option("--controller", controllers,
                  "a controller to enter besides the suite's: a registered name, or a .py file "
                  "that registers one or more (repeatable)")
      ->allow_extra_args(false)
      ->check(not_empty());
  sub->add_flag("--only", only, "run only the --controller ones, not the suite's");
  sub->add_option("--task", tasks, "run only this task of the suite (repeatable)")
      ->allow_extra_args(false)
      ->check(not_empty());
  add_campaign_options(*sub, "runs per controller and task (default: the suite's)",
                       "override a key of every task (repeatable)");
  sub->add_flag("--no-leaderboard", no_leaderboard,
                "write the store and the exports only (the leaderboard needs Python)");
  sub->add_option("--compare", compare,
                  "compare two results (leaderboard.json files or benchmark output folders) and "
                  "say which differences are beyond noise; nothing is run")
      ->expected(2)
      ->check(not_empty());
  sub->add_flag("--allow-runs", allow_runs,
                "with --compare: accept results of the same tasks at other run counts");
  return sub;
}

int BenchmarkCommand::run() {
  if (!compare.empty()) {
    std::vector<std::string> args = compare;
    if (allow_runs) args.emplace_back("--allow-runs");
    return run_python_module("plumetrace.benchmark.compare", args);
  }
  if (std::any_of(controllers.begin(), controllers.end(), is_python_file)) {
    // why: a Python controller runs in a Python process, which registers it and runs the same
    // benchmark through the compiled module (python/plumetrace/benchmark/__main__.py)
    if (launched_ranks() > 1) {
      throw ConfigError(
          "--controller: a controller written in Python runs in one process, not across the "
          "ranks of an MPI job; run it without mpirun, or split it with --shard");
    }
    return run_python_module("plumetrace.benchmark", words);
  }
  if (file.empty()) file = default_suite();
  return SweepCommand::run();
}

BenchmarkChoice BenchmarkCommand::choice() const {
  BenchmarkChoice choice;
  choice.controllers = controllers;
  choice.only = only;
  choice.tasks = tasks;
  choice.runs = runs;
  choice.overrides = parse_sets(sets);
  return choice;
}

SweepPlan BenchmarkCommand::plan() const {
  SweepPlan plan;
  plan.shard = shard.empty() ? Shard{} : parse_shard(shard);
  BenchmarkPlan bench = plan_benchmark(read_suite_file(file), choice());
  const SuiteFile& suite = bench.suite;
  plan.name = suite.name;
  plan.label = "benchmark " + suite.name;
  plan.file = file;
  plan.sweeps = std::move(bench.sweeps);
  check_campaign(plan.sweeps, 0);
  plan.place(out, store);
  return plan;
}

int BenchmarkCommand::finish(const SweepPlan& plan, const Store& store,
                             const CampaignResult& result, const std::string& where) const {
  if (plan.shard.count > 1) return SweepCommand::finish(plan, store, result, where);
  make_output_folder(plan.out, "--out");
  // the manifest first: the leaderboard reads it, and it says what the store holds
  const BenchmarkPlan bench = plan_benchmark(read_suite_file(file), choice());
  write_text_file(plan.out + "/benchmark.json", benchmark_manifest(bench));
  if (const int rc = SweepCommand::finish(plan, store, result, where)) return rc;
  std::printf("suite %s version %s, digest %s\n", bench.suite.name.c_str(),
              bench.suite.version.c_str(), bench.digest.c_str());
  if (no_leaderboard) return 0;
  if (const int rc = draw_report(plan.out, "plumetrace.benchmark.leaderboard")) return rc;
  std::printf("leaderboard: %s/leaderboard.html (and .md, .csv, .json, figures/)\n",
              plan.out.c_str());
  return 0;
}

}  // namespace plumetrace::cli
