#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "campaign_run.hpp"
#include "commands.hpp"
#include "errors.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "progress.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

std::unique_ptr<Store> open_sweep_store(const SweepPlan& plan, const SweepCommand& cmd) {
  // the exports' folder first, so that one that cannot be made stops the sweep before it runs
  if (plan.shard.count <= 1) make_output_folder(plan.out, cmd.out.empty() ? "out/NAME" : "--out");
  const auto folder = std::filesystem::path(plan.store_path).parent_path();
  // why: no probe: a read-only store's own check names the store (exit 3, F15)
  if (!folder.empty()) make_output_folder(folder.string(), "the folder of --store", false);
  return std::make_unique<Store>(plan.store_path, plan.sweeps, version(), cmd.fresh);
}

CampaignFlags sweep_flags(const SweepCommand& cmd) {
  CampaignFlags flags;
  flags.threads = cmd.threads;
  flags.quiet = cmd.quiet;
  flags.no_share = cmd.no_share;
  return flags;
}

std::string ranks_text(const std::vector<std::int64_t>& runs_per_rank) {
  std::string text = " on " + std::to_string(runs_per_rank.size()) + " ranks (runs per rank:";
  for (std::size_t r = 0; r < runs_per_rank.size(); ++r) {
    text += (r ? ", " : " ") + std::to_string(runs_per_rank[r]);
  }
  return text + ")";
}

// ranks as "1, 3"
std::string rank_list(const std::vector<int>& ranks) {
  std::string text;
  for (const int r : ranks) text += (text.empty() ? "" : ", ") + std::to_string(r);
  return text;
}

// the ranks whose `codes` are not 0, as "1, 3"
std::string failed_ranks(const std::vector<int>& codes) {
  std::vector<int> failed;
  for (std::size_t r = 0; r < codes.size(); ++r) {
    if (codes[r] != 0) failed.push_back(static_cast<int>(r));
  }
  return rank_list(failed);
}

// why the job stopped, as rank 0 knows it
std::string stop_cause(const JobReport& report) {
  if (report.silent_ranks.empty()) {
    return "a signal, or a rank that ended early (the launcher names it)";
  }
  return "no goodbye from rank(s) " + rank_list(report.silent_ranks) +
         " (killed, crashed, or not done stopping)";
}

// every rank reads the sweep (rank 0 also opens the store) and they agree that all went well
// and that every rank expanded the same sweep; returns 0, or the exit code after saying why
int agree_on_sweep(Ranks& ranks, const SweepCommand& cmd, std::optional<SweepPlan>& plan,
                   std::unique_ptr<Store>& store) {
  const bool root = ranks.rank() == 0;
  std::exception_ptr failure;
  try {
    plan = cmd.plan();
    if (root) store = open_sweep_store(*plan, cmd);
  } catch (...) {
    failure = std::current_exception();
  }
  const int code = failure ? exit_code(failure) : 0;
  if (root && !failure) print_sweep_warnings(plan->sweeps);
  auto codes = ranks.all_gather(code);
  const int worst = *std::max_element(codes.begin(), codes.end());
  if (worst != 0) {
    // rank 0 says it; another rank only what rank 0 did not meet
    if (failure && (root || codes[0] == 0)) {
      report_error(failure, root ? "" : "rank " + std::to_string(ranks.rank()) + ": ");
    } else if (root) {
      std::fprintf(stderr, "plumetrace: error: rank(s) %s could not start the sweep (see above)\n",
                   failed_ranks(codes).c_str());
    }
    return worst;
  }
  // why: each machine reads the files itself; a rank that sees other files would compute
  // another sweep into this store
  const std::string definition = campaign_definition(plan->sweeps);
  const bool same = ranks.broadcast(definition) == definition;
  codes = ranks.all_gather(same ? 0 : kBadInput);
  if (std::count(codes.begin(), codes.end(), 0) == static_cast<long>(codes.size())) return 0;
  if (root) {
    std::fprintf(stderr,
                 "plumetrace: error: rank(s) %s read another sweep definition from '%s' (and "
                 "its scenario) than rank 0: every machine must see the same files\n",
                 failed_ranks(codes).c_str(), cmd.file.c_str());
  }
  return kBadInput;
}

int run_sweep_on_ranks(const SweepCommand& cmd, Ranks& ranks) {
  install_stop_handlers();
  std::optional<SweepPlan> plan;
  std::unique_ptr<Store> store;
  if (const int code = agree_on_sweep(ranks, cmd, plan, store)) return code;
  try {
    CampaignOptions options;
    options.threads = cmd.threads;
    options.share_plumes = !cmd.no_share;
    options.stop = &g_stop;
    if (ranks.rank() != 0) return serve_blocks(ranks, plan->sweeps, options) ? 0 : kInterrupted;

    JobReport report;
    CampaignResult result;
    if (!run_with_progress(plan->progress_label(), plan->sweeps, *store, cmd.runs, sweep_flags(cmd),
                           result, plan->shard, coordinator(ranks, &report))) {
      std::fprintf(stderr, "plumetrace: the MPI job stopped: %s; the store is consistent\n",
                   stop_cause(report).c_str());
      return kInterrupted;
    }
    // every run is in, but the job did not end as it should: say so first, since the launcher
    // may be about to kill this rank, then write the exports of the complete store
    if (g_stop.load() || ranks.abandoned()) {
      std::fprintf(stderr, "plumetrace: the MPI job stopped early: %s; all %lld runs are in '%s'\n",
                   stop_cause(report).c_str(), static_cast<long long>(result.total),
                   store->path().c_str());
      cmd.finish(*plan, *store, result, ranks_text(report.runs_per_rank));
      return kInterrupted;
    }
    return cmd.finish(*plan, *store, result, ranks_text(report.runs_per_rank));
  } catch (...) {
    // the other ranks may wait for this one: end the job once the error is reported
    ranks.abandon(exit_code(std::current_exception()));
    throw;
  }
}

}  // namespace

std::string SweepPlan::progress_label() const {
  const std::string part = shard_text(shard);
  return label + (part.empty() ? "" : " shard " + part);
}

void SweepPlan::place(const std::string& out_option, const std::string& store_option) {
  // why: the name comes from a file; "../../etc/evil" must not lead out of out/ (issue 13, F12)
  out = out_option.empty() ? default_output_folder(name, file) : out_option;
  store_path = store_option.empty() ? default_store_path(out, shard) : store_option;
}

SweepPlan SweepCommand::plan() const {
  SweepPlan plan;
  plan.shard = shard.empty() ? Shard{} : parse_shard(shard);
  const SweepDef def = read_sweep_file(file);
  plan.name = def.name;
  plan.file = file;
  plan.sweeps = {expand_sweep(def, parse_sets(sets))};
  check_campaign(plan.sweeps, runs);
  plan.place(out, store);
  plan.label = "sweep " + plan.name;
  return plan;
}

// after the runs: the exports and the summary, or for a shard what its store holds
int SweepCommand::finish(const SweepPlan& plan, const Store& store, const CampaignResult& result,
                         const std::string& where) const {
  const auto counts = [&] {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%lld runs (%lld computed now, %lld from the store) in %.1f s",
                  static_cast<long long>(result.total), static_cast<long long>(result.computed),
                  static_cast<long long>(result.skipped), result.elapsed);
    return std::string(buf) + where;
  };
  if (plan.shard.count > 1) {
    std::printf(
        "shard %s of %s: %s; store %s; merge the parts' stores with plumetrace "
        "merge\n",
        shard_text(plan.shard).c_str(), plan.label.c_str(), counts().c_str(), store.path().c_str());
    return 0;
  }
  const auto rows = store.rows();
  make_output_folder(plan.out, "--out");
  write_exports(plan.out, plan.sweeps, rows, runs);
  if (!quiet) std::fputs(summary_table(plan.sweeps, rows, runs).c_str(), stdout);
  std::printf("%s; store %s; exports in %s/\n", counts().c_str(), store.path().c_str(),
              plan.out.c_str());
  return 0;
}

CLI::App* SweepCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "sweep",
      "run a sweep file's grid of runs into a results store (under mpirun: across the ranks)");
  sub->add_option("sweep", file, "sweep TOML file")->required()->check(not_empty());
  add_campaign_options(*sub, "runs per point (default: the sweep file's)",
                       "override a key of the base scenario (repeatable)");
  return sub;
}

void SweepCommand::add_campaign_options(CLI::App& sub, const std::string& runs_help,
                                        const std::string& set_help) {
  sub.add_option("--runs", runs, runs_help)->check(whole_number(1, kMaxCampaignRuns));
  sub.add_option("--threads", threads,
                 "worker threads (default: all cores; under mpirun, per rank: the cores shared "
                 "among the ranks on each machine)")
      ->check(whole_number(1, kMaxThreads));
  sub.add_option("--store", store,
                 "results store (default: OUT/results.sqlite; with --shard "
                 "OUT/part-I-of-N.sqlite)")
      ->check(not_empty());
  sub.add_option("--out", out, "output folder for exports (default: out/NAME)")->check(not_empty());
  sub.add_option("--set", sets, set_help)->allow_extra_args(false);
  sub.add_option("--shard", shard,
                 "compute only part I of N (I/N, e.g. 2/8) for job arrays; merge the parts' "
                 "stores with plumetrace merge");
  sub.add_flag("--quiet", quiet, "no progress bar and no summary table");
  sub.add_flag("--fresh", fresh,
               "discard every run the store holds (needed only when the base scenario, a --set or "
               "the seed changed; a sweep given more values keeps its stored runs)");
  sub.add_flag("--no-share-plumes", no_share,
               "simulate the plume anew for every run (same results, slower)");
}

int SweepCommand::run() {
  ranks.emplace();
  if (ranks->size() > 1) return run_sweep_on_ranks(*this, *ranks);
  const SweepPlan plan = this->plan();
  print_sweep_warnings(plan.sweeps);
  const auto results = open_sweep_store(plan, *this);
  CampaignResult result;
  if (!run_with_progress(plan.progress_label(), plan.sweeps, *results, runs, sweep_flags(*this),
                         result, plan.shard)) {
    return kInterrupted;
  }
  return finish(plan, *results, result, "");
}

}  // namespace plumetrace::cli
