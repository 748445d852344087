// Shards of a campaign (fixed, disjoint parts for job arrays) and merging their stores.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/rows.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

using testing::expect_same_rows;

// two plumes (sigma_p) x two algorithms, quick runs: 4 points x 12 trials
std::vector<ExpandedSweep> two_plumes(const std::vector<Setting>& overrides = {}) {
  return {expand_sweep(read_sweep_file(PLUMETRACE_SOURCE_DIR "/tests/support/two_plumes.toml"),
                       overrides)};
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// a store of the campaign (or of one shard of it), computed; returns its path
std::string run_into(const std::vector<ExpandedSweep>& sweeps, const Shard& shard,
                     const std::string& stem, const std::string& def_version = "") {
  const std::string path = testing::temp_path(stem, ".sqlite");
  Store store(path, sweeps, def_version.empty() ? version() : def_version, false);
  CampaignOptions options;
  options.threads = 2;
  const CampaignResult r = run_campaign(sweeps, store, 0, options, shard);
  EXPECT_FALSE(r.interrupted);
  return path;
}

std::vector<RunRow> rows_of(const std::string& path) { return read_store_rows(path, nullptr); }

TEST(Shard, ParsesIOverNAndRefusesTheRestNamingTheOption) {
  const Shard s = parse_shard("2/8");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 8);
  EXPECT_EQ(shard_text(s), "2/8");
  EXPECT_EQ(shard_text(Shard{}), "");
  for (const char* bad : {"0/3", "4/3", "3", "/3", "1/", "a/b", "1/0", "-1/3", "1/3/4", " 1/3"}) {
    const std::string message = error_of([&] { parse_shard(bad); });
    EXPECT_NE(message.find("--shard"), std::string::npos) << bad << ": " << message;
  }
}

TEST(Shard, ThePartsAreDisjointCoverTheCampaignAndAreBalanced) {
  const auto sweeps = two_plumes();
  const auto all = missing_runs(sweeps, {}, 0);
  ASSERT_EQ(all.size(), 48u);
  std::set<std::tuple<int, int, std::uint64_t>> seen;
  for (int i = 1; i <= 3; ++i) {
    const auto part = missing_runs(sweeps, {}, 0, Shard{i, 3});
    EXPECT_EQ(part.size(), 16u) << i;  // 2 plumes x 12 trials: 24 units of 2 runs, 8 per part
    for (const auto& t : part) {
      EXPECT_TRUE(seen.insert({t.sweep, t.point, t.trial}).second) << "in two parts";
    }
  }
  EXPECT_EQ(seen.size(), all.size());
}

TEST(Shard, RunsThatShareAPlumeStayInOneShard) {
  const auto sweeps = two_plumes();
  const auto plumes = plume_indices(sweeps);
  EXPECT_EQ(plumes[0], (std::vector<int>{0, 0, 1, 1}));  // sigma_p varies slowest
  for (int i = 1; i <= 4; ++i) {
    // (plume, trial) -> how many of its runs this shard holds: all of them or none
    std::map<std::pair<int, std::uint64_t>, int> held;
    for (const auto& t : missing_runs(sweeps, {}, 0, Shard{i, 4})) {
      ++held[{plumes[0][static_cast<std::size_t>(t.point)], t.trial}];
    }
    for (const auto& [unit, count] : held) EXPECT_EQ(count, 2) << i;
  }
}

TEST(Shard, AShardKeepsItsRunsWhenTheRunsPerPointGrow) {
  const auto sweeps = two_plumes();
  const auto small = missing_runs(sweeps, {}, 5, Shard{2, 3});
  const auto large = missing_runs(sweeps, {}, 50, Shard{2, 3});
  std::set<std::tuple<int, int, std::uint64_t>> in_large;
  for (const auto& t : large) in_large.insert({t.sweep, t.point, t.trial});
  for (const auto& t : small) EXPECT_TRUE(in_large.count({t.sweep, t.point, t.trial}));
}

TEST(Shard, RunningAShardAgainComputesAndAddsNothing) {
  const auto sweeps = two_plumes();
  const std::string path = run_into(sweeps, Shard{1, 3}, "again");
  Store store(path, sweeps, version(), false);
  const CampaignResult again = run_campaign(sweeps, store, 0, {}, Shard{1, 3});
  EXPECT_EQ(again.computed, 0);
  EXPECT_EQ(again.skipped, 16);
  EXPECT_EQ(store.rows().size(), 16u);
  EXPECT_EQ(store.info().shard, "1/3");
}

TEST(Merge, ThreeShardsMergeToTheRowsOfTheWholeCampaign) {
  const auto sweeps = two_plumes();
  const auto whole = rows_of(run_into(sweeps, {}, "whole"));
  std::vector<std::string> parts;
  for (int i = 1; i <= 3; ++i) parts.push_back(run_into(sweeps, Shard{i, 3}, "part"));
  const std::string out = testing::temp_path("merged", ".sqlite");
  const MergeReport report = merge_stores(parts, out);
  EXPECT_EQ(report.added, 48);
  EXPECT_EQ(report.already, 0);
  EXPECT_EQ(report.total, 48);
  EXPECT_TRUE(report.gaps.empty());
  EXPECT_TRUE(report.missing_shards.empty());
  expect_same_rows(rows_of(out), whole);
  // the merged store is an ordinary store of the campaign: a sweep over it computes nothing
  Store merged(out, sweeps, version(), false);
  EXPECT_EQ(merged.info().shard, "");
  EXPECT_EQ(merged.info().points.at("two"), 4);
  EXPECT_EQ(run_campaign(sweeps, merged, 0, {}).computed, 0);
}

TEST(Merge, MissingPartsAreReportedAndASweepOverTheStoreCompletesIt) {
  const auto sweeps = two_plumes();
  const std::string out = testing::temp_path("partial", ".sqlite");
  const MergeReport report =
      merge_stores({run_into(sweeps, Shard{1, 3}, "p1"), run_into(sweeps, Shard{3, 3}, "p3")}, out);
  ASSERT_EQ(report.gaps.size(), 1u);
  EXPECT_EQ(report.gaps[0].sweep, "two");
  EXPECT_EQ(report.gaps[0].expected, 48);
  EXPECT_EQ(report.gaps[0].present, 32);
  EXPECT_EQ(report.missing_shards, std::vector<std::string>{"2/3"});
  Store store(out, sweeps, version(), false);
  EXPECT_EQ(run_campaign(sweeps, store, 0, {}).computed, 16);
  expect_same_rows(store.rows(), rows_of(run_into(sweeps, {}, "whole")));
}

TEST(Merge, MergingAgainSkipsIdenticalRunsAndRefusesDifferentOnes) {
  const auto sweeps = two_plumes();
  const std::string part = run_into(sweeps, Shard{1, 2}, "part");
  const std::string out = testing::temp_path("out", ".sqlite");
  EXPECT_EQ(merge_stores({part}, out).added, 24);
  const MergeReport again = merge_stores({part}, out);
  EXPECT_EQ(again.added, 0);
  EXPECT_EQ(again.already, 24);
  EXPECT_EQ(rows_of(out).size(), 24u);

  // a part whose run differs from the one the store holds (same key, other result)
  const std::string forged = testing::temp_path("forged", ".sqlite");
  {
    Store store(forged, sweeps, version(), false);
    store.put_points(sweeps);
    RunRow row = rows_of(part).front();
    row.result.d_t += 1.0;
    store.insert({row});
  }
  const std::string message = error_of([&] { merge_stores({forged}, out); });
  EXPECT_NE(message.find("other results"), std::string::npos) << message;
  EXPECT_NE(message.find(forged), std::string::npos) << message;
  EXPECT_EQ(rows_of(out).size(), 24u);  // unchanged
}

TEST(Merge, OverlappingPartsAreRefusedNamingBothFilesAndARun) {
  const auto sweeps = two_plumes();
  const std::string a = run_into(sweeps, Shard{1, 2}, "a");
  const std::string b = run_into(sweeps, Shard{1, 3}, "b");  // another count: overlaps a
  const std::string out = testing::temp_path("out", ".sqlite");
  const std::string message = error_of([&] { merge_stores({a, b}, out); });
  EXPECT_NE(message.find(a), std::string::npos) << message;
  EXPECT_NE(message.find(b), std::string::npos) << message;
  EXPECT_NE(message.find("trial"), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(out));  // a failed merge leaves no new store
  EXPECT_NE(error_of([&] { merge_stores({a, a}, out); }).find("given twice"), std::string::npos);
}

// the two plumes with a third algorithm between the two (its points share the plumes: the
// shards keep every run they held)
std::vector<ExpandedSweep> three_algorithms() {
  std::ifstream in(PLUMETRACE_SOURCE_DIR "/tests/support/two_plumes.toml");
  std::string text(std::istreambuf_iterator<char>(in), {});
  const std::string axis = R"(["casting", "surge-cast"])";
  text.replace(text.find(axis), axis.size(), R"(["casting", "surge-spiral", "surge-cast"])");
  const std::string path = testing::temp_path("three", ".toml");
  std::ofstream(path) << text;
  return {expand_sweep(read_sweep_file(path), {})};
}

TEST(Merge, PartsThatNumberTheSamePointsOtherwiseMergeByTheirValues) {
  const auto three = three_algorithms();
  // part 1 ran the two algorithms first, then the three: surge-spiral's points come last in it
  const std::string first = run_into(two_plumes(), Shard{1, 2}, "first");
  {
    Store store(first, three, version(), false);
    const CampaignResult r = run_campaign(three, store, 0, {}, Shard{1, 2});
    EXPECT_EQ(r.skipped, 24);
    EXPECT_EQ(r.computed, 12);
  }
  // part 2 ran the three algorithms from the start: they are numbered in grid order
  const std::string second = run_into(three, Shard{2, 2}, "second");
  const std::string out = testing::temp_path("merged", ".sqlite");
  const MergeReport report = merge_stores({first, second}, out);
  EXPECT_EQ(report.added, 72);
  EXPECT_TRUE(report.gaps.empty());
  Store merged(out, three, version(), false);
  expect_same_rows(merged.rows(), rows_of(run_into(three, {}, "whole")));
}

TEST(Merge, PartsOfAnotherDefinitionOrVersionAreRefusedNamingTheFile) {
  const auto sweeps = two_plumes();
  const std::string part = run_into(two_plumes(), Shard{1, 2}, "part");
  const std::string other_dt =
      run_into(two_plumes({parse_override("sim.dt=0.04")}), Shard{2, 2}, "other");
  const std::string out = testing::temp_path("out", ".sqlite");
  std::string message = error_of([&] { merge_stores({part, other_dt}, out); });
  EXPECT_NE(message.find(other_dt), std::string::npos) << message;
  EXPECT_NE(message.find("another sweep definition"), std::string::npos) << message;

  const std::string old = testing::temp_path("old", ".sqlite");
  { Store store(old, sweeps, "0.0.1", false); }
  message = error_of([&] { merge_stores({part, old}, out); });
  EXPECT_NE(message.find(old), std::string::npos) << message;
  EXPECT_NE(message.find("0.0.1"), std::string::npos) << message;

  const std::string text = testing::temp_path("text", ".sqlite");
  std::ofstream(text) << "not a database";
  message = error_of([&] { merge_stores({text}, out); });
  EXPECT_NE(message.find("is not a plumetrace results store"), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace plumetrace
