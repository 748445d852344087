#include "options.hpp"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "shell.hpp"
#include "lochmatter2008/study.hpp"
#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

namespace {

// the registered algorithms: "casting, surge-spiral or surge-cast"
std::string algorithm_names() {
  const auto all = all_algorithms();
  std::string out;
  for (std::size_t i = 0; i < all.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == all.size() ? " or " : ", ");
    out += algorithm_name(all[i]);
  }
  return out;
}

}  // namespace

void ScenarioOptions::add_to(CLI::App& cmd, bool with_algorithm) {
  cmd.add_option("scenario", path, "scenario TOML file (default: the paper's setup)")
      ->check(not_empty());
  cmd.add_option("--set", sets, "override a config key: key.path=value (repeatable)")
      ->allow_extra_args(false);
  if (with_algorithm) {
    cmd.add_option("--algorithm", algorithm, algorithm_names())->check(not_empty());
  }
}

Scenario ScenarioOptions::load(bool warn) const {
  std::vector<Setting> overrides;
  if (!algorithm.empty()) {
    overrides.push_back(
        {"controller.algorithm", algorithm, true, "--algorithm", Layer::kCommandLine});
  }
  for (const auto& s : sets) overrides.push_back(parse_override(s));
  Scenario scenario = load_scenario(path, overrides);
  if (warn) print_warnings(scenario);
  return scenario;
}

void print_warnings(const Scenario& scenario, const std::string& where) {
  for (const std::string& w : scenario_warnings(scenario)) {
    std::fprintf(stderr, "plumetrace: warning: %s%s\n", where.c_str(), w.c_str());
  }
}

void print_sweep_warnings(const std::vector<ExpandedSweep>& sweeps) {
  // why: a grid may have thousands of points; a few show what to change
  constexpr int kShown = 3;
  int warned = 0;
  for (const ExpandedSweep& sweep : sweeps) {
    for (const SweepPoint& p : sweep.points) {
      if (scenario_warnings(p.scenario).empty()) continue;
      if (++warned > kShown) continue;
      std::string where = "sweep " + sweep.def.name + ", point " + std::to_string(p.index);
      for (std::size_t a = 0; a < p.values.size(); ++a) {
        where += (a ? ", " : " (") + sweep.def.axes[a].key + " = " + format_value(p.values[a]);
      }
      print_warnings(p.scenario, where + (p.values.empty() ? ": " : "): "));
    }
  }
  if (warned > kShown) {
    std::fprintf(stderr, "plumetrace: warning: %d more points of the sweep warn likewise\n",
                 warned - kShown);
  }
}

void CampaignFlags::add_to(CLI::App& sub) {
  sub.add_option("--threads", threads, "worker threads (default: all cores)")
      ->check(whole_number(1, kMaxThreads));
  sub.add_option("--out", out, "output folder: stores, summary and report (default: out)")
      ->check(not_empty());
  sub.add_option("--experiments", experiments,
                 "folder of the study: study.toml, its sweep files and presets (default: "
                 "studies/lochmatter2008)")
      ->check(not_empty());
  sub.add_flag("--quiet", quiet, "no progress bar");
  sub.add_flag("--fresh", fresh,
               "discard every run the store holds (needed only when the base scenario, a --set or "
               "the seed changed; a sweep given more values keeps its stored runs)");
  sub.add_flag("--no-share-plumes", no_share,
               "simulate the plume anew for every run (same results, slower)");
}

std::string CampaignFlags::study_file() const {
  return experiments.empty() ? default_study_file() : experiments + "/study.toml";
}

std::vector<Setting> parse_sets(const std::vector<std::string>& sets) {
  std::vector<Setting> out;
  for (const auto& s : sets) out.push_back(parse_override(s));
  return out;
}

std::uint64_t parse_u64(const std::string& option, const std::string& text) {
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) {
    throw ConfigError(option + ": must be a whole number from 0 to 18446744073709551615 (got '" +
                      text + "')");
  }
  return v;
}

void StoredSweepOptions::add_to(CLI::App& sub, const std::string& out_help, bool out_required) {
  sub.add_option("sweeps", sweep_files, "the sweep files the store was made from")
      ->required()
      ->check(not_empty());
  sub.add_option("--store", store, "results store")->required()->check(not_empty());
  sub.add_option("--out", out, out_help)->required(out_required)->check(not_empty());
  sub.add_option("--runs", runs, "runs per point (default: the sweep files')")
      ->check(whole_number(1, kMaxCampaignRuns));
  sub.add_option("--set", sets, "the --set overrides the sweep ran with (repeatable)")
      ->allow_extra_args(false);
}

std::vector<ExpandedSweep> StoredSweepOptions::sweeps() {
  std::vector<SweepDef> defs;
  for (const auto& f : sweep_files) defs.push_back(read_sweep_file(f));
  // why: a store remembers the --set its sweeps ran with, so that export and report of it need
  // not repeat them (issue 22); given --set values are used as given
  if (sets.empty() && std::filesystem::is_regular_file(store)) {
    const StoreInfo info = read_store_info(store);
    std::optional<std::vector<std::string>> recorded;
    for (const auto& def : defs) {
      const auto it = info.sets.find(def.name);
      const std::vector<std::string> mine =
          it == info.sets.end() ? std::vector<std::string>{} : it->second;
      if (recorded && *recorded != mine) {
        throw ConfigError("results store '" + store +
                          "' recorded other --set values for its sweeps; give --set");
      }
      recorded = mine;
    }
    if (recorded && !recorded->empty()) {
      sets = *recorded;
      std::string text;
      for (const auto& s : sets) text += " --set " + shell_word(s);
      std::fprintf(stderr, "plumetrace: note: using the --set the store recorded:%s\n",
                   text.c_str());
    }
  }
  std::vector<ExpandedSweep> result;
  for (const auto& def : defs) result.push_back(expand_sweep(def, parse_sets(sets)));
  check_campaign(result, runs);
  return result;
}

}  // namespace plumetrace::cli
