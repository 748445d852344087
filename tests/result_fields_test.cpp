// The one list of result fields (RunResult::fields) against every format that writes a run:
// each has exactly those columns, in that order, and reads back what it wrote.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/distributed/distributed.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/result.hpp"
#include "support/rows.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

const std::string kGoldenSweep = std::string(PLUMETRACE_SOURCE_DIR) + "/tests/golden/sweep.toml";

// the names RunResult::fields gives, in its order
std::vector<std::string> field_names() {
  std::vector<std::string> names;
  const RunResult r{};
  RunResult::fields(r, [&](const ResultField& f, const auto&) { names.emplace_back(f.name); });
  return names;
}

// a result whose member fields all differ from each other and from the defaults, so that a
// format that swaps, drops or zeroes one cannot read back the same run
RunResult distinct_result() {
  RunResult r;
  int k = 0;
  RunResult::fields(r, [&](const ResultField&, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    ++k;
    if constexpr (kDerivedField<decltype(value)>) {
      return;
    } else if constexpr (std::is_same_v<T, Outcome>) {
      value = Outcome::kWall;
    } else if constexpr (std::is_floating_point_v<T>) {
      value = k + 0.125;
    } else {
      value = static_cast<T>(1000 + k);
    }
  });
  r.seed = std::numeric_limits<std::uint64_t>::max() - 5;
  r.trial = 3;
  r.agent = 2;
  return r;
}

RunRow distinct_row(const ExpandedSweep& sweep) {
  RunRow row;
  row.sweep = sweep.def.name;
  row.point = 1;
  row.trial = 3;
  row.agent = 2;
  row.config_hash = sweep.points[1].config_hash;
  row.result = distinct_result();
  return row;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells{""};
  for (const char c : line) {
    if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

TEST(ResultFields, TheListIsTheOneFieldsGivesWithEachNameOnce) {
  const auto names = field_names();
  ASSERT_EQ(kResultFields.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) EXPECT_EQ(kResultFields[k].name, names[k]);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
}

// the run key's names with the axis keys after point, as runs.csv writes them
std::vector<std::string> key_header() {
  std::vector<std::string> names;
  for (const std::string_view name : kRunKeyFields) {
    names.emplace_back(name);
    if (name == "point") {
      names.insert(names.end(), {"controller.algorithm", "wind_sensor.sigma_a"});
    }
  }
  return names;
}

TEST(ResultFields, TheRunKeyIsSweepPointTrialAndAgentInThatOrder) {
  EXPECT_EQ(std::vector<std::string>(kRunKeyFields.begin(), kRunKeyFields.end()),
            (std::vector<std::string>{"sweep", "point", "trial", "agent"}));
  RunRow row;
  row.sweep = "s";
  row.point = 4;
  row.trial = 5;
  row.agent = 6;
  std::vector<std::string> seen;
  RunRow::key_fields(row, [&](std::string_view name, const auto&) { seen.emplace_back(name); });
  EXPECT_EQ(seen, std::vector<std::string>(kRunKeyFields.begin(), kRunKeyFields.end()));
  EXPECT_EQ(run_key(row), (RunKey{"s", 4, 5, 6}));
}

TEST(ResultFields, RunsCsvHasTheFieldsInOrderAfterTheRunsKey) {
  const ExpandedSweep sweep = expand_sweep(read_sweep_file(kGoldenSweep), {});
  const std::string path = testing::temp_path("runs", ".csv");
  write_runs_csv(path, {sweep}, {distinct_row(sweep)});
  std::ifstream in(path);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::vector<std::string> expected = key_header();
  expected.insert(expected.end(), {"seed", "config_hash"});
  for (const auto& name : field_names()) expected.push_back(name);
  EXPECT_EQ(split(header), expected);
  const auto cells = split(row);
  ASSERT_EQ(cells.size(), expected.size());
  EXPECT_EQ(cells[4], "3");  // trial
  EXPECT_EQ(cells[5], "2");  // agent, right after it
  const std::size_t first = expected.size() - field_names().size();
  EXPECT_EQ(cells[first], "wall");       // outcome
  EXPECT_EQ(cells[first + 1], "0");      // success
  EXPECT_EQ(cells[first + 2], "3.125");  // time_s, the third field
}

TEST(ResultFields, TheResultJsonHasTheFieldsAndTheRunsIdentity) {
  const nlohmann::json j =
      nlohmann::json::parse(result_to_json(distinct_result(), {"casting", 7, 3, 2}));
  std::set<std::string> expected{"algorithm", "seed", "trial", "agent", "version"};
  for (const auto& name : field_names()) expected.insert(name);
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.insert(key);
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(j["outcome"], "wall");
  EXPECT_EQ(j["success"], false);
  EXPECT_EQ(j["agent"], 2);
}

TEST(ResultFields, ATraceReadsBackEveryField) {
  const RunResult result = distinct_result();
  Trace trace;
  trace.agents.emplace_back().steps.resize(1);
  const std::string path = testing::temp_path("trace", ".json");
  write_trace(path, trace, Scenario{}, result,
              {"casting", result.seed, result.trial, result.agent});
  const RecordedRun back = read_trace(path);
  EXPECT_EQ(testing::field_bits(back.result), testing::field_bits(result));
  EXPECT_EQ(back.result.seed, result.seed);
  EXPECT_EQ(back.result.trial, result.trial);
  EXPECT_EQ(back.result.agent, 2);
  EXPECT_EQ(back.info.agent, 2);
}

// the columns of table runs: name, declared type, NOT NULL
struct Column {
  std::string name, type;
  bool not_null = false;
  bool operator==(const Column&) const = default;
};

std::vector<Column> run_table(const std::string& path) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* q = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, "PRAGMA table_info(runs)", -1, &q, nullptr), SQLITE_OK);
  std::vector<Column> columns;
  while (sqlite3_step(q) == SQLITE_ROW) {
    columns.push_back({reinterpret_cast<const char*>(sqlite3_column_text(q, 1)),
                       reinterpret_cast<const char*>(sqlite3_column_text(q, 2)),
                       sqlite3_column_int(q, 3) != 0});
  }
  sqlite3_finalize(q);
  sqlite3_close(db);
  return columns;
}

TEST(ResultFields, TheStoresRunsTableHasTheFieldsInOrderAfterTheRunsKey) {
  const ExpandedSweep sweep = expand_sweep(read_sweep_file(kGoldenSweep), {});
  const std::string path = testing::temp_path("store", ".sqlite");
  const RunRow row = distinct_row(sweep);
  // an outcome added since the first schema is a known name too
  RunRow declared = row;
  declared.agent = declared.result.agent = 3;
  declared.result.outcome = Outcome::kWrongDeclaration;
  {
    Store store(path, std::vector<ExpandedSweep>{sweep}, version(), true);
    store.put_points({sweep});
    store.insert({declared, row});
  }
  std::vector<Column> expected{{"sweep", "TEXT", true},    {"point", "INTEGER", true},
                               {"trial", "INTEGER", true}, {"agent", "INTEGER", true},
                               {"seed", "TEXT", true},     {"config_hash", "TEXT", true}};
  const RunResult none{};
  RunResult::fields(none, [&](const ResultField& f, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    const std::string type = std::is_same_v<T, Outcome>    ? "TEXT"
                             : std::is_floating_point_v<T> ? "REAL"
                                                           : "INTEGER";
    expected.push_back({std::string(f.name), type, !f.nullable});
  });
  EXPECT_EQ(run_table(path), expected);

  Store store(path, std::vector<ExpandedSweep>{sweep}, version(), false);
  testing::expect_same_rows(store.rows(), {row, declared});  // in key order: agent 2, then 3
}

TEST(ResultFields, TheRowMessageCarriesEveryField) {
  const ExpandedSweep sweep = expand_sweep(read_sweep_file(kGoldenSweep), {});
  const std::vector<RunRow> rows{distinct_row(sweep)};
  testing::expect_same_rows(decode_rows(encode_rows(rows)), rows);
}

TEST(ResultFields, AnOutcomeNameParsesBackAndAnUnknownOneIsRefusedNamingIt) {
  for (const Outcome o : {Outcome::kRunning, Outcome::kSuccess, Outcome::kWall, Outcome::kTimeout,
                          Outcome::kGaveUp, Outcome::kWrongDeclaration}) {
    EXPECT_EQ(parse_outcome(outcome_name(o)), o);
  }
  try {
    parse_outcome("banana");
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'banana'"), std::string::npos) << what;
    EXPECT_NE(what.find("gave_up"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace plumetrace
