#include "campaigns.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <thread>

#include "lochmatter2008/summary.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/paths.hpp"
#include "progress.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

std::string interval_text(double value, double lo, double hi, int digits) {
  if (!std::isfinite(value)) return "n/a";
  char buf[96];
  if (std::isfinite(lo) && std::isfinite(hi)) {
    std::snprintf(buf, sizeof buf, "%.*f [%.*f, %.*f]", digits, value, digits, lo, digits, hi);
  } else {
    std::snprintf(buf, sizeof buf, "%.*f", digits, value);
  }
  return buf;
}

std::string values_text(const ExpandedSweep& sweep, const SweepPoint& p) {
  std::string out;
  for (std::size_t a = 0; a < p.values.size(); ++a) {
    const auto& v = p.values[a];
    out += (a ? ", " : "") + sweep.def.axes[a].key + "=" +
           (std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : format_value(v));
  }
  return out;
}

void print_summary(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                   int runs_override) {
  std::printf("%-8s %-44s %5s  %-24s %-24s\n", "sweep", "point", "runs", "success [95% CI]",
              "overhead [95% CI]");
  for (const auto& sweep : sweeps) {
    const int runs = runs_per_point(sweep, runs_override);
    for (const auto& p : sweep.points) {
      const PointStats st = summarize(point_runs(rows, sweep.def.name, p.index, runs));
      std::printf("%-8s %-44s %5lld  %-24s %-24s\n", sweep.def.name.c_str(),
                  values_text(sweep, p).c_str(), static_cast<long long>(st.runs),
                  interval_text(st.success_rate, st.success_ci.lo, st.success_ci.hi, 2).c_str(),
                  interval_text(st.overhead.mean, st.overhead.lo, st.overhead.hi, 3).c_str());
    }
  }
}

std::vector<Setting> parse_sets(const std::vector<std::string>& sets) {
  std::vector<Setting> out;
  for (const auto& s : sets) out.push_back(parse_override(s));
  return out;
}

void write_exports(const std::string& out, const std::vector<ExpandedSweep>& sweeps,
                   const std::vector<RunRow>& rows, int runs_override) {
  write_runs_csv(out + "/runs.csv", sweeps, rows);
  write_summary_csv(out + "/summary.csv", sweeps, rows, runs_override);
  write_results_json(out + "/results.json", sweeps, rows, runs_override);
}

// the nine sets, in order
const char* const kSets[] = {"A", "B", "C", "D", "E", "F", "G", "H", "I"};

std::string experiments_dir(const std::string& given) {
  return given.empty() ? std::string(kSourceDir) + "/experiments/lochmatter2008" : given;
}

std::vector<SweepDef> read_sets(const std::string& dir) {
  std::vector<SweepDef> defs;
  for (const char* name : kSets) defs.push_back(read_sweep_file(dir + "/" + name + ".toml"));
  return defs;
}

std::string presets_dir(const std::string& experiments) { return experiments + "/presets"; }

// the readings to run: the main one first, then the extra ones ("none": no extra; empty: every
// preset file but the main one)
std::vector<Reading> readings_to_run(const std::string& dir, const ReproduceCommand& cmd) {
  std::vector<Reading> readings{read_reading(presets_dir(dir), cmd.preset)};
  std::vector<std::string> extra;
  if (cmd.presets.empty()) {
    extra = preset_names(presets_dir(dir));
  } else if (cmd.presets != "none") {
    std::stringstream list(cmd.presets);
    for (std::string name; std::getline(list, name, ',');) {
      if (!name.empty()) extra.push_back(name);
    }
  }
  for (const auto& name : extra) {
    const bool seen = std::any_of(readings.begin(), readings.end(),
                                  [&](const Reading& r) { return r.name == name; });
    if (!seen) readings.push_back(read_reading(presets_dir(dir), name));
  }
  return readings;
}

// the reading without the keys that are axes of `def` (the radius sweep varies the radius that
// a reading may set)
Reading without_axes(Reading reading, const SweepDef& def) {
  std::erase_if(reading.settings, [&](const Setting& s) {
    return std::any_of(def.axes.begin(), def.axes.end(),
                       [&](const Axis& a) { return a.key == s.key; });
  });
  return reading;
}

// runs the campaign (or a shard of it) with a progress bar; false when interrupted (after
// saying so)
bool run_with_progress(const std::string& label, const std::vector<ExpandedSweep>& sweeps,
                       Store& store, int runs, const CampaignFlags& flags, CampaignResult& result,
                       const Shard& shard = {}, const TaskRunner& runner = {}) {
  install_stop_handlers();
  ProgressBar bar(label, !flags.quiet && stderr_is_terminal());
  CampaignOptions options;
  options.threads = flags.threads;
  options.share_plumes = !flags.no_share;
  options.stop = &g_stop;
  options.on_progress = [&](const Progress& p) { bar.update(p); };
  result = run_campaign(sweeps, store, runs, options, shard, runner);
  bar.finish();
  if (!result.interrupted) return true;
  std::fprintf(stderr,
               "plumetrace: interrupted: %lld of %lld runs are in '%s'; run the same command "
               "again to compute the rest\n",
               static_cast<long long>(result.skipped + result.computed),
               static_cast<long long>(result.total), store.path().c_str());
  return false;
}

// draws report.html and report.md from OUT/summary.json with matplotlib
int draw_report(const std::string& out) {
  const std::string command = "PYTHONPATH='" + std::string(kSourceDir) + "/python' '" + kPython +
                              "' -m plumetrace.report '" + out + "'";
  const int rc = std::system(command.c_str());
  if (rc != 0) {
    std::fprintf(stderr,
                 "plumetrace: error: drawing the report failed (%s); the results are kept in "
                 "%s/\n",
                 command.c_str(), out.c_str());
    return kIoFailure;
  }
  return 0;
}

}  // namespace

void CampaignFlags::add_to(CLI::App& sub) {
  sub.add_option("--threads", threads, "worker threads (default: all cores)")
      ->check(whole_number(1, kMaxThreads));
  sub.add_option("--out", out, "output folder: stores, summary and report (default: out)")
      ->check(not_empty());
  sub.add_option("--experiments", experiments,
                 "folder of the sweep files (default: experiments/lochmatter2008)")
      ->check(not_empty());
  sub.add_flag("--quiet", quiet, "no progress bar");
  sub.add_flag("--fresh", fresh, "discard the store's runs if its definition differs");
  sub.add_flag("--no-share-plumes", no_share,
               "simulate the plume anew for every run (same results, slower)");
}

CLI::App* add_reproduce_command(CLI::App& app, ReproduceCommand& cmd) {
  auto* sub = app.add_subcommand(
      "reproduce", "run the paper's nine experiment sets and write the report (report.html)");
  std::string names = kDefaultReading;
  for (const auto& n : preset_names(presets_dir(experiments_dir("")))) names += ", " + n;
  sub->add_option("--preset", cmd.preset,
                  "the main reading of what the paper leaves unsaid: " + names +
                      " (files experiments/lochmatter2008/presets/NAME.toml; default: default, "
                      "the built-in defaults)")
      ->check(not_empty());
  sub->add_option("--presets", cmd.presets,
                  "the other readings whose nine sets are run too, for the claims columns, "
                  "comma-separated, or none (default: every preset file)")
      ->check(not_empty());
  sub->add_option("--runs", cmd.runs, "runs per value (default 50, as the paper)")
      ->check(whole_number(1, kMaxCampaignRuns));
  cmd.flags.add_to(*sub);
  return sub;
}

int run_reproduce_command(const ReproduceCommand& cmd) {
  const std::string dir = experiments_dir(cmd.flags.experiments);
  const std::vector<Reading> readings = readings_to_run(dir, cmd);
  const std::vector<SweepDef> sets = read_sets(dir);
  // the main reading's nine sets and its success-radius sweep, then the other readings' sets
  std::vector<ExpandedSweep> sweeps = reading_sets(sets, readings.front(), true);
  const SweepDef radius = read_sweep_file(dir + "/radius.toml");
  sweeps.push_back(expand_sweep(radius, without_axes(readings.front(), radius).settings));
  for (std::size_t i = 1; i < readings.size(); ++i) {
    for (auto& s : reading_sets(sets, readings[i], false)) sweeps.push_back(std::move(s));
  }
  check_campaign_size(sweeps, cmd.runs);
  std::filesystem::create_directories(cmd.flags.out);
  Store store(cmd.flags.out + "/results.sqlite", campaign_definition(sweeps), version(),
              cmd.flags.fresh);
  CampaignResult result;
  if (!run_with_progress("reproduce", sweeps, store, cmd.runs, cmd.flags, result)) {
    return kInterrupted;
  }
  const auto rows = store.rows();

  ReproduceInfo info;
  info.command = cmd.command_line;
  info.preset = readings.front().name;
  info.readings = readings;
  info.runs_override = cmd.runs;
  info.threads = cmd.flags.threads > 0 ? cmd.flags.threads
                                       : static_cast<int>(std::thread::hardware_concurrency());
  info.elapsed = result.elapsed;
  info.computed = result.computed;
  info.base_config =
      scenario_to_toml(load_scenario(sweeps.front().def.scenario_path, readings.front().settings));
  write_exports(cmd.flags.out, sweeps, rows, cmd.runs);
  write_text_file(cmd.flags.out + "/summary.json", build_summary(sweeps, rows, info));
  if (const int rc = draw_report(cmd.flags.out)) return rc;
  std::printf(
      "%lld runs (%lld computed now in %.1f s, %lld from the store)\nreport: %s/report.html "
      "(and report.md)\n",
      static_cast<long long>(result.total), static_cast<long long>(result.computed), result.elapsed,
      static_cast<long long>(result.skipped), cmd.flags.out.c_str());
  return 0;
}

CLI::App* add_sensitivity_command(CLI::App& app, SensitivityCommand& cmd) {
  auto* sub = app.add_subcommand(
      "sensitivity",
      "rerun the nine sets under every noise mode, kernel and success radius; claims matrix");
  sub->add_option("--runs", cmd.runs, "runs per value (default 10)")
      ->check(whole_number(1, kMaxCampaignRuns));
  cmd.flags.add_to(*sub);
  return sub;
}

int run_sensitivity_command(const SensitivityCommand& cmd) {
  std::vector<ExpandedSweep> sweeps;
  for (const auto& def :
       sensitivity_sweeps(read_sets(experiments_dir(cmd.flags.experiments)), cmd.runs)) {
    sweeps.push_back(expand_sweep(def, {}));
  }
  check_campaign_size(sweeps, cmd.runs);
  std::filesystem::create_directories(cmd.flags.out);
  Store store(cmd.flags.out + "/sensitivity.sqlite", campaign_definition(sweeps), version(),
              cmd.flags.fresh);
  CampaignResult result;
  if (!run_with_progress("sensitivity", sweeps, store, cmd.runs, cmd.flags, result)) {
    return kInterrupted;
  }
  const auto matrix = sensitivity_matrix(sweeps, store.rows(), cmd.runs);
  write_text_file(cmd.flags.out + "/sensitivity.json",
                  sensitivity_json(matrix, cmd.runs, result.elapsed));
  const std::string md = sensitivity_markdown(matrix, cmd.runs, result.elapsed);
  write_text_file(cmd.flags.out + "/sensitivity.md", md);
  std::fputs(md.c_str(), stdout);
  // a report already in the folder gains the matrix
  if (std::filesystem::exists(cmd.flags.out + "/summary.json")) return draw_report(cmd.flags.out);
  return 0;
}

CLI::App* add_sweep_command(CLI::App& app, SweepCommand& cmd) {
  auto* sub = app.add_subcommand(
      "sweep",
      "run a sweep file's grid of runs into a results store (under mpirun: across the ranks)");
  sub->add_option("sweep", cmd.file, "sweep TOML file")->required()->check(not_empty());
  sub->add_option("--runs", cmd.runs, "runs per point (default: the sweep file's)")
      ->check(whole_number(1, kMaxCampaignRuns));
  sub->add_option("--threads", cmd.threads,
                  "worker threads (default: all cores; under mpirun, per rank: the cores shared "
                  "among the ranks on each machine)")
      ->check(whole_number(1, kMaxThreads));
  sub->add_option("--store", cmd.store,
                  "results store (default: OUT/results.sqlite; with --shard "
                  "OUT/part-I-of-N.sqlite)")
      ->check(not_empty());
  sub->add_option("--out", cmd.out, "output folder for exports (default: out/NAME)")
      ->check(not_empty());
  sub->add_option("--set", cmd.sets, "override a key of the base scenario (repeatable)")
      ->allow_extra_args(false);
  sub->add_option("--shard", cmd.shard,
                  "compute only part I of N (I/N, e.g. 2/8) for job arrays; merge the parts' "
                  "stores with plumetrace merge");
  sub->add_flag("--quiet", cmd.quiet, "no progress bar");
  sub->add_flag("--fresh", cmd.fresh, "discard the store's runs if its definition differs");
  sub->add_flag("--no-share-plumes", cmd.no_share,
                "simulate the plume anew for every run (same results, slower)");
  return sub;
}

namespace {

// what a sweep command works on, read alike on every rank
struct SweepPlan {
  std::string name;
  std::vector<ExpandedSweep> sweeps;
  Shard shard;
  std::string out;
  std::string store_path;
};

// the most characters of a sweep name used as a folder name
constexpr std::size_t kMaxFolderName = 100;

// whether a sweep name can be the folder of its exports under out/ as it is: letters, digits,
// '_', '-' and '.', not first
bool folder_name(const std::string& name) {
  const auto plain = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  };
  return !name.empty() && name.size() <= kMaxFolderName && name[0] != '.' && name[0] != '-' &&
         std::all_of(name.begin(), name.end(), plain);
}

SweepPlan plan_sweep(const SweepCommand& cmd) {
  SweepPlan plan;
  plan.shard = cmd.shard.empty() ? Shard{} : parse_shard(cmd.shard);
  const SweepDef def = read_sweep_file(cmd.file);
  plan.name = def.name;
  plan.sweeps = {expand_sweep(def, parse_sets(cmd.sets))};
  check_campaign_size(plan.sweeps, cmd.runs);
  // why: the name comes from a file; "../../etc/evil" must not lead out of out/ (issue 13, F12)
  if (cmd.out.empty() && !folder_name(def.name)) {
    throw ConfigError(cmd.file + ": name: '" + def.name +
                      "' cannot be the exports' folder under out/ (letters, digits, '_', '-' and "
                      "'.', not first, at most " +
                      std::to_string(kMaxFolderName) +
                      " characters); rename the sweep or give --out");
  }
  plan.out = cmd.out.empty() ? "out/" + def.name : cmd.out;
  if (!cmd.store.empty()) {
    plan.store_path = cmd.store;
  } else if (plan.shard.count > 1) {
    plan.store_path = plan.out + "/part-" + std::to_string(plan.shard.index) + "-of-" +
                      std::to_string(plan.shard.count) + ".sqlite";
  } else {
    plan.store_path = plan.out + "/results.sqlite";
  }
  return plan;
}

std::unique_ptr<Store> open_sweep_store(const SweepPlan& plan, const SweepCommand& cmd) {
  // the exports' folder first, so that one that cannot be made stops the sweep before it runs
  if (plan.shard.count <= 1) std::filesystem::create_directories(plan.out);
  const auto folder = std::filesystem::path(plan.store_path).parent_path();
  if (!folder.empty()) std::filesystem::create_directories(folder);
  return std::make_unique<Store>(plan.store_path, campaign_definition(plan.sweeps), version(),
                                 cmd.fresh);
}

CampaignFlags sweep_flags(const SweepCommand& cmd) {
  CampaignFlags flags;
  flags.threads = cmd.threads;
  flags.quiet = cmd.quiet;
  flags.no_share = cmd.no_share;
  return flags;
}

std::string sweep_label(const SweepPlan& plan) {
  const std::string shard = shard_text(plan.shard);
  return "sweep " + plan.name + (shard.empty() ? "" : " shard " + shard);
}

// after the runs: the exports and the summary, or for a shard what its store holds
int finish_sweep(const SweepPlan& plan, const Store& store, int runs, const CampaignResult& result,
                 const std::string& where) {
  const auto counts = [&] {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%lld runs (%lld computed now, %lld from the store) in %.1f s",
                  static_cast<long long>(result.total), static_cast<long long>(result.computed),
                  static_cast<long long>(result.skipped), result.elapsed);
    return std::string(buf) + where;
  };
  if (plan.shard.count > 1) {
    std::printf(
        "shard %s of sweep %s: %s; store %s; merge the parts' stores with plumetrace "
        "merge\n",
        shard_text(plan.shard).c_str(), plan.name.c_str(), counts().c_str(), store.path().c_str());
    return 0;
  }
  const auto rows = store.rows();
  std::filesystem::create_directories(plan.out);
  write_exports(plan.out, plan.sweeps, rows, runs);
  print_summary(plan.sweeps, rows, runs);
  std::printf("%s; store %s; exports in %s/\n", counts().c_str(), store.path().c_str(),
              plan.out.c_str());
  return 0;
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
    plan = plan_sweep(cmd);
    if (root) store = open_sweep_store(*plan, cmd);
  } catch (...) {
    failure = std::current_exception();
  }
  const int code = failure ? exit_code(failure) : 0;
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
    if (!run_with_progress(sweep_label(*plan), plan->sweeps, *store, cmd.runs, sweep_flags(cmd),
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
      finish_sweep(*plan, *store, cmd.runs, result, ranks_text(report.runs_per_rank));
      return kInterrupted;
    }
    return finish_sweep(*plan, *store, cmd.runs, result, ranks_text(report.runs_per_rank));
  } catch (...) {
    // the other ranks may wait for this one: end the job once the error is reported
    ranks.abandon(exit_code(std::current_exception()));
    throw;
  }
}

}  // namespace

int run_sweep_command(const SweepCommand& cmd, Ranks& ranks) {
  if (ranks.size() > 1) return run_sweep_on_ranks(cmd, ranks);
  const SweepPlan plan = plan_sweep(cmd);
  const auto store = open_sweep_store(plan, cmd);
  CampaignResult result;
  if (!run_with_progress(sweep_label(plan), plan.sweeps, *store, cmd.runs, sweep_flags(cmd), result,
                         plan.shard)) {
    return kInterrupted;
  }
  return finish_sweep(plan, *store, cmd.runs, result, "");
}

CLI::App* add_merge_command(CLI::App& app, MergeCommand& cmd) {
  auto* sub = app.add_subcommand(
      "merge", "merge the stores of a sweep's shards (plumetrace sweep --shard) into one store");
  sub->add_option("parts", cmd.parts, "the parts' results stores")->required()->check(not_empty());
  sub->add_option("--store", cmd.store, "the merged results store (created if needed)")
      ->required()
      ->check(not_empty());
  return sub;
}

int run_merge_command(const MergeCommand& cmd) {
  const MergeReport report = merge_stores(cmd.parts, cmd.store);
  std::printf(
      "merged %zu part(s) into %s: %lld runs added, %lld already there; %lld runs in the "
      "store\n",
      cmd.parts.size(), cmd.store.c_str(), static_cast<long long>(report.added),
      static_cast<long long>(report.already), static_cast<long long>(report.total));
  for (const auto& gap : report.gaps) {
    std::fprintf(stderr, "plumetrace: warning: sweep %s: %lld of %lld runs are missing\n",
                 gap.sweep.c_str(), static_cast<long long>(gap.expected - gap.present),
                 static_cast<long long>(gap.expected));
  }
  if (!report.missing_shards.empty()) {
    std::string shards;
    for (const auto& s : report.missing_shards) shards += (shards.empty() ? "" : ", ") + s;
    std::fprintf(stderr, "plumetrace: warning: no part holds shard(s) %s\n", shards.c_str());
  }
  if (!report.gaps.empty()) {
    std::fprintf(stderr,
                 "plumetrace: warning: the merged store is incomplete; merge the missing parts "
                 "into it, or run plumetrace sweep SWEEP.toml --store %s to compute the rest\n",
                 cmd.store.c_str());
  }
  return 0;
}

CLI::App* add_export_command(CLI::App& app, ExportCommand& cmd) {
  auto* sub = app.add_subcommand(
      "export", "write runs.csv, summary.csv and results.json from a results store");
  sub->add_option("sweeps", cmd.sweep_files, "the sweep files the store was made from")
      ->required()
      ->check(not_empty());
  sub->add_option("--store", cmd.store, "results store")->required()->check(not_empty());
  sub->add_option("--out", cmd.out, "output folder")->required()->check(not_empty());
  sub->add_option("--runs", cmd.runs, "runs per point (default: the sweep files')")
      ->check(whole_number(1, kMaxCampaignRuns));
  sub->add_option("--set", cmd.sets, "the --set overrides the sweep ran with (repeatable)")
      ->allow_extra_args(false);
  return sub;
}

int run_export_command(const ExportCommand& cmd) {
  std::vector<ExpandedSweep> sweeps;
  for (const auto& f : cmd.sweep_files) {
    sweeps.push_back(expand_sweep(read_sweep_file(f), parse_sets(cmd.sets)));
  }
  std::string definition;
  const auto rows = read_store_rows(cmd.store, &definition);
  if (definition != campaign_definition(sweeps)) {
    throw StoreError("results store '" + cmd.store +
                     "' was not made from these sweep files (or with other --set overrides)");
  }
  std::filesystem::create_directories(cmd.out);
  write_exports(cmd.out, sweeps, rows, cmd.runs);
  return 0;
}

int exit_code(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const ConfigError&) {
    return kBadInput;
  } catch (const StoreIoError&) {
    return kIoFailure;
  } catch (const StoreError&) {
    return kBadInput;
  } catch (const std::filesystem::filesystem_error&) {
    return kIoFailure;
  } catch (const IoError&) {
    return kIoFailure;
  } catch (const std::bad_alloc&) {
    return kOutOfMemory;
  } catch (...) {
    return kInternalError;
  }
}

int report_error(const std::exception_ptr& error, const std::string& prefix) {
  const int code = exit_code(error);
  try {
    std::rethrow_exception(error);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "plumetrace: error: %sout of memory; results already stored are kept (lower "
                 "--threads, plume.capacity or the grid, or raise the memory limit)\n",
                 prefix.c_str());
  } catch (const std::exception& e) {
    if (code == kInternalError) {
      std::fprintf(stderr, "plumetrace: internal error: %s%s (please report it)\n", prefix.c_str(),
                   e.what());
    } else {
      std::fprintf(stderr, "plumetrace: error: %s%s\n", prefix.c_str(), e.what());
    }
  } catch (...) {
    std::fprintf(stderr, "plumetrace: internal error: %san unknown exception (please report it)\n",
                 prefix.c_str());
  }
  return code;
}

}  // namespace plumetrace::cli
