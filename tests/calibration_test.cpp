#include "lochmatter2008/calibration.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "lochmatter2008/summary.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

const std::string kSetsDir = std::string(PLUMETRACE_SOURCE_DIR) + "/studies/lochmatter2008/sets";

Setting command_line(const std::string& key, ConfigValue value) {
  return {key, std::move(value), false, "test", Layer::kCommandLine};
}

// a small evaluation: two sets, few runs, a seed of its own, and a shorter time limit
CalibrationOptions small_options() {
  CalibrationOptions options;
  options.sets_dir = kSetsDir;
  options.sets = {"A", "D"};
  options.runs = 3;
  options.seed = 7;
  options.threads = 2;
  options.overrides = {command_line("plume.amount", 1.0),
                       command_line("supervisor.timeout", 400.0)};
  return options;
}

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

void expect_same_point(const PointStats& a, const PointStats& b, const std::string& where) {
  EXPECT_EQ(a.runs, b.runs) << where;
  EXPECT_EQ(a.successes, b.successes) << where;
  EXPECT_EQ(a.walls, b.walls) << where;
  EXPECT_EQ(a.timeouts, b.timeouts) << where;
  EXPECT_EQ(a.gave_up, b.gave_up) << where;
  EXPECT_EQ(bits(a.success_rate), bits(b.success_rate)) << where;
  EXPECT_EQ(bits(a.success_ci.lo), bits(b.success_ci.lo)) << where;
  EXPECT_EQ(bits(a.success_ci.hi), bits(b.success_ci.hi)) << where;
  EXPECT_EQ(a.overhead.n, b.overhead.n) << where;
  EXPECT_EQ(bits(a.overhead.mean), bits(b.overhead.mean)) << where;
  EXPECT_EQ(bits(a.overhead.lo), bits(b.overhead.lo)) << where;
  EXPECT_EQ(bits(a.overhead.hi), bits(b.overhead.hi)) << where;
  EXPECT_EQ(bits(a.mean_time), bits(b.mean_time)) << where;
  EXPECT_EQ(bits(a.mean_losses), bits(b.mean_losses)) << where;
}

TEST(Calibration, GivesTheStatisticsAndClaimsOfAStoreBasedSweep) {
  const CalibrationOptions options = small_options();
  const CalibrationResult got = evaluate_sets(options);
  ASSERT_FALSE(got.interrupted);
  EXPECT_EQ(got.runs, 3 * (9 + 9));

  // the same files, seed, runs and overrides, through a results store as `plumetrace sweep`
  std::vector<ExpandedSweep> sweeps;
  for (const std::string& name : options.sets) {
    SweepDef def = read_sweep_file(kSetsDir + "/" + name + ".toml");
    def.seed = options.seed;
    sweeps.push_back(expand_sweep(def, options.overrides));
  }
  const std::string path = testing::temp_path("store", ".sqlite");
  std::map<std::string, SetStats> want;
  {
    Store store(path, sweeps, "test", true);
    CampaignOptions run_options;
    run_options.threads = 1;
    run_campaign(sweeps, store, options.runs, run_options);
    for (const auto& sweep : sweeps) {
      want[sweep.def.name] = set_stats(sweep, store.rows(), options.runs);
    }
  }
  std::filesystem::remove(path);

  ASSERT_EQ(got.sets.size(), want.size());
  // the comparison covers overheads too: some runs succeed
  std::int64_t successes = 0;
  for (const auto& [name, set] : got.sets) {
    for (const PointStats& p : set.points) successes += p.successes;
  }
  EXPECT_GT(successes, 0);
  for (const auto& [name, w] : want) {
    const SetStats& g = got.sets.at(name);
    EXPECT_EQ(g.key, w.key);
    EXPECT_EQ(g.algorithm, w.algorithm);
    EXPECT_EQ(g.values, w.values);
    EXPECT_EQ(g.fixed_index, w.fixed_index);
    ASSERT_EQ(g.points.size(), w.points.size());
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      expect_same_point(g.points[i], w.points[i], name + std::to_string(i));
    }
  }
  const auto claims = evaluate_claims(want);
  ASSERT_EQ(got.claims.size(), claims.size());
  for (std::size_t i = 0; i < claims.size(); ++i) {
    EXPECT_EQ(got.claims[i].id, claims[i].id);
    EXPECT_EQ(got.claims[i].verdict, claims[i].verdict);
    EXPECT_EQ(got.claims[i].evidence, claims[i].evidence);
    EXPECT_EQ(got.claims[i].parts.size(), claims[i].parts.size());
    EXPECT_EQ(std::isnan(got.claims[i].margin), std::isnan(claims[i].margin));
  }
}

TEST(Calibration, DoesNotDependOnTheThreadCount) {
  CalibrationOptions options = small_options();
  options.sets = {"D"};
  options.threads = 1;
  const CalibrationResult one = evaluate_sets(options);
  options.threads = 3;
  const CalibrationResult three = evaluate_sets(options);
  for (std::size_t i = 0; i < one.sets.at("D").points.size(); ++i) {
    expect_same_point(one.sets.at("D").points[i], three.sets.at("D").points[i], std::to_string(i));
  }
}

TEST(Calibration, OverridesApplyToEveryRun) {
  // a robot released 14.5 m downwind at 0.106 m/s cannot arrive within 1 s: every run times out
  CalibrationOptions options = small_options();
  options.overrides.push_back(command_line("supervisor.timeout", 1.0));
  const CalibrationResult result = evaluate_sets(options);
  for (const auto& [name, set] : result.sets) {
    for (const PointStats& p : set.points) {
      EXPECT_EQ(p.runs, 3) << name;
      EXPECT_EQ(p.timeouts, 3) << name;
      EXPECT_EQ(p.successes, 0) << name;
    }
  }
}

TEST(Calibration, ReplacesSeedAndRunsOnlyWhenAsked) {
  CalibrationOptions options;
  options.sets_dir = kSetsDir;
  options.sets = {"B"};
  const SweepDef file = read_sweep_file(kSetsDir + "/B.toml");
  const auto own = calibration_sweeps(options);
  EXPECT_EQ(own.at(0).def.seed, file.seed);
  EXPECT_EQ(own.at(0).def.runs, file.runs);
  options.seed = 99;
  options.runs = 4;
  const auto replaced = calibration_sweeps(options);
  EXPECT_EQ(replaced.at(0).def.seed, 99u);
  EXPECT_EQ(replaced.at(0).def.runs, 4);
}

TEST(Calibration, ReadsAllNineSetsByDefault) {
  CalibrationOptions options;
  options.sets_dir = kSetsDir;
  const auto sweeps = calibration_sweeps(options);
  ASSERT_EQ(sweeps.size(), 9u);
  for (std::size_t i = 0; i < sweeps.size(); ++i) {
    EXPECT_EQ(sweeps[i].def.name, experiment_set_names()[i]);
  }
}

TEST(Calibration, RefusesAnOverrideOfAnAxisKey) {
  CalibrationOptions options = small_options();
  options.overrides.push_back(command_line("casting.beta_deg", 10.0));
  EXPECT_THROW(evaluate_sets(options), ConfigError);
}

TEST(Calibration, ClaimsOfSetsNotRunAreUnclear) {
  CalibrationOptions options = small_options();
  options.sets = {"A"};
  options.overrides.push_back(command_line("supervisor.timeout", 1.0));
  const CalibrationResult result = evaluate_sets(options);
  ASSERT_EQ(result.claims.size(), 11u);
  // claim 1 pools surge-spiral's sets D, E and F, which were not run
  EXPECT_EQ(result.claims[0].id, 1);
  EXPECT_EQ(result.claims[0].verdict, Verdict::kUnclear);
}

TEST(Calibration, StopsWhenAskedAndSaysSo) {
  CalibrationOptions options = small_options();
  std::atomic<bool> stop{true};
  options.stop = &stop;
  const CalibrationResult result = evaluate_sets(options);
  EXPECT_TRUE(result.interrupted);
  EXPECT_TRUE(result.sets.empty());
  EXPECT_TRUE(result.claims.empty());
}

}  // namespace
}  // namespace plumetrace
