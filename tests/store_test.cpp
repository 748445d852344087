// The results store's guarantees (issue 13): it never writes to a database that is not its own,
// reads nothing damaged without saying so, opens read-only what it only reads, lets two
// processes write one store, and names the cause of a failed write (exit 3).
#include "plumetrace/experiment/store.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/command.hpp"
#include "support/rows.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

namespace fs = std::filesystem;
using testing::expect_same_rows;
using testing::read_file;
using testing::run_command;

const std::string kCli = PLUMETRACE_CLI;
// 4 points x 12 quick runs (48 runs, a fraction of a second)
const std::string kSweep = PLUMETRACE_SOURCE_DIR "/tests/support/two_plumes.toml";

testing::CommandOutput plumetrace(const std::string& args) {
  return run_command(kCli + " " + args);
}

std::vector<ExpandedSweep> two_plumes() { return {expand_sweep(read_sweep_file(kSweep), {})}; }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// runs SQL on a database with SQLite itself, as another program or a hand edit would
void sql(const std::string& path, const std::string& statements) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* err = nullptr;
  const int rc = sqlite3_exec(db, statements.c_str(), nullptr, nullptr, &err);
  const std::string message = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << message;
}

// a complete store of the sweep, computed once and copied for each test that damages it
std::string clean_store() {
  static const std::string path = [] {
    const std::string p = testing::temp_path("clean", ".sqlite");
    const auto o = plumetrace("sweep " + kSweep + " --quiet --threads 2 --store " + p + " --out " +
                              testing::temp_path("clean_out", ""));
    EXPECT_EQ(o.code, 0) << o.err;
    return p;
  }();
  return path;
}

std::string copy_of_clean(const std::string& stem) {
  const std::string path = testing::temp_path(stem, ".sqlite");
  fs::copy_file(clean_store(), path);
  return path;
}

// the exports of a store, as text ("" when export fails)
std::string exports(const std::string& store) {
  const std::string out = testing::temp_path("exports", "");
  if (plumetrace("export " + kSweep + " --store " + store + " --out " + out).code != 0) return "";
  return read_file(out + "/runs.csv") + read_file(out + "/summary.csv");
}

void expect_names(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& p : parts) EXPECT_NE(message.find(p), std::string::npos) << p << ": " << message;
}

// F1 ---------------------------------------------------------------------------------------------

TEST(StoreSafety, AnotherProgramsDatabaseIsRefusedAndLeftByteForByte) {
  const std::string other = testing::temp_path("other", ".db");
  sql(other,
      "CREATE TABLE runs(id INTEGER PRIMARY KEY, name TEXT); INSERT INTO runs(name) "
      "VALUES ('x');");
  const std::string before = read_file(other);
  for (const std::string extra : {"", " --fresh"}) {
    const auto o = plumetrace("sweep " + kSweep + " --quiet --store " + other + " --out " +
                              testing::temp_path("out", "") + extra);
    EXPECT_EQ(o.code, 2) << extra;
    expect_names(o.err, {other, "not a plumetrace results store", "runs(id, name)"});
    EXPECT_EQ(read_file(other), before) << extra;
  }
  const auto merged = plumetrace("merge " + clean_store() + " --store " + other);
  EXPECT_EQ(merged.code, 2);
  expect_names(merged.err, {other, "not a plumetrace results store"});
  EXPECT_EQ(read_file(other), before);
  EXPECT_FALSE(fs::exists(other + "-wal") && fs::file_size(other + "-wal") > 0);
}

TEST(StoreSafety, AStoreWithoutItsDefinitionKeepsItsRunsUnlessFresh) {
  const std::string store = copy_of_clean("nodef");
  sql(store, "DELETE FROM meta WHERE key = 'definition';");
  const auto o = plumetrace("sweep " + kSweep + " --quiet --store " + store + " --out " +
                            testing::temp_path("out", ""));
  EXPECT_EQ(o.code, 2);
  expect_names(o.err, {store, "definition", "--fresh"});
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(store.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* q = nullptr;
  sqlite3_prepare_v2(db, "SELECT count(*) FROM runs", -1, &q, nullptr);
  ASSERT_EQ(sqlite3_step(q), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(q, 0), 48);
  sqlite3_finalize(q);
  sqlite3_close(db);
  // --fresh discards them, as asked
  EXPECT_EQ(plumetrace("sweep " + kSweep + " --quiet --fresh --store " + store + " --out " +
                       testing::temp_path("out", ""))
                .code,
            0);
  EXPECT_EQ(exports(store), exports(clean_store()));
}

// F7 ---------------------------------------------------------------------------------------------

TEST(StoreDamage, AStoreTruncatedByAFewBytesIsRefusedNamingTheFile) {
  for (int cut = 1; cut <= 50; ++cut) {
    const std::string store = copy_of_clean("cut");
    fs::resize_file(store, fs::file_size(store) - static_cast<std::uintmax_t>(cut));
    const std::string message = error_of([&] { read_store_rows(store, nullptr); });
    expect_names(message, {store, "truncated"});
    if (cut == 1 || cut == 50) {
      const auto o = plumetrace("export " + kSweep + " --store " + store + " --out " +
                                testing::temp_path("out", ""));
      EXPECT_EQ(o.code, 2) << cut;
      expect_names(o.err, {store, "truncated"});
      // nor does a sweep build on it (it leaves it as it is)
      const std::string before = read_file(store);
      EXPECT_EQ(plumetrace("sweep " + kSweep + " --quiet --store " + store + " --out " +
                           testing::temp_path("out", ""))
                    .code,
                2);
      EXPECT_EQ(read_file(store), before);
    }
  }
}

// F19 --------------------------------------------------------------------------------------------

// a copy of the clean store edited by `statements`; expects export to refuse it naming `names`
void expect_edit_refused(const std::string& statements, const std::vector<std::string>& names) {
  const std::string store = copy_of_clean("edited");
  sql(store, statements);
  const auto o = plumetrace("export " + kSweep + " --store " + store + " --out " +
                            testing::temp_path("out", ""));
  EXPECT_EQ(o.code, 2) << statements << "\n" << o.err;
  std::vector<std::string> all{store};
  all.insert(all.end(), names.begin(), names.end());
  expect_names(o.err, all);
  EXPECT_EQ(o.out, "");
}

TEST(StoreDamage, AnUnknownOutcomeIsRefusedNamingTheRunAndColumn) {
  expect_edit_refused("UPDATE runs SET outcome = 'banana' WHERE point = 1 AND trial = 2;",
                      {"point 1, trial 2", "outcome", "banana"});
}

TEST(StoreDamage, TextInARealColumnIsRefusedNamingTheRunAndColumn) {
  expect_edit_refused("UPDATE runs SET d_t = 'abc' WHERE point = 2 AND trial = 0;",
                      {"point 2, trial 0", "d_t", "abc"});
}

TEST(StoreDamage, ARunWhoseConfigHashDiffersFromItsPointIsRefused) {
  expect_edit_refused("UPDATE runs SET config_hash = '0123456789abcdef' WHERE point = 3;",
                      {"point 3", "config_hash", "0123456789abcdef"});
}

TEST(StoreDamage, AnUnknownSchemaIsRefused) {
  expect_edit_refused("UPDATE meta SET value = '7' WHERE key = 'schema';", {"schema", "'7'"});
}

TEST(StoreDamage, AChangedValueALostRunAndAnAddedRunAreRefusedByTheChecksum) {
  // the change of the truncated store of the issue, made by hand: wind_samples 12 -> 0
  expect_edit_refused("UPDATE runs SET wind_samples = 0 WHERE point = 0 AND trial = 5;",
                      {"checksum"});
  expect_edit_refused("DELETE FROM runs WHERE point = 0 AND trial = 5;", {"checksum", "47"});
  expect_edit_refused(
      "INSERT INTO runs SELECT sweep, point, trial + 100, seed, config_hash, outcome, success, "
      "time_s, d_t, d_u, overhead, losses, odor_fraction, steps, wind_samples, t_first_odor, d_first_odor, declaration_error FROM runs LIMIT 1;",
      {"checksum", "49"});
  expect_edit_refused("UPDATE points SET config = config || ' ' WHERE point = 1;",
                      {"points", "checksum"});
}

TEST(StoreDamage, MergeRefusesAPartWhoseDefinitionIsNotJsonOrOfAnotherVersion) {
  const std::string out = testing::temp_path("out", ".sqlite");
  const std::string not_json = copy_of_clean("notjson");
  sql(not_json, "UPDATE meta SET value = '{\"sweeps\": [' WHERE key = 'definition';");
  auto o = plumetrace("merge " + not_json + " --store " + out);
  EXPECT_EQ(o.code, 2);
  expect_names(o.err, {not_json, "definition", "not JSON"});
  EXPECT_FALSE(fs::exists(out));

  const std::string old = copy_of_clean("old");
  sql(old, "UPDATE meta SET value = '0.0.1' WHERE key = 'version';");
  o = plumetrace("merge " + old + " --store " + out);
  EXPECT_EQ(o.code, 2);
  expect_names(o.err, {old, "0.0.1", std::string(version())});
  EXPECT_FALSE(fs::exists(out));
}

// F3 ---------------------------------------------------------------------------------------------

TEST(StoreDamage, ANonNumericSeedOrRunsCountIsAnErrorNamingTheStoreAndKeyNotACrash) {
  const std::string seed = copy_of_clean("seed");
  sql(seed, "UPDATE runs SET seed = 'x1' WHERE point = 0 AND trial = 0;");
  const std::string runs = copy_of_clean("runs");
  sql(runs, "UPDATE meta SET value = 'twelve' WHERE key = 'runs:two';");
  for (const auto& [store, names] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {seed, {"seed", "'x1'", "point 0, trial 0"}}, {runs, {"runs:two", "'twelve'"}}}) {
    const std::string out = testing::temp_path("out", "");
    for (const std::string& command :
         {"export " + kSweep + " --store " + store + " --out " + out,
          "sweep " + kSweep + " --quiet --store " + store + " --out " + out,
          "merge " + store + " --store " + testing::temp_path("merged", ".sqlite")}) {
      const auto o = plumetrace(command);
      EXPECT_EQ(o.code, 2) << command << "\n" << o.err;
      std::vector<std::string> all{store};
      all.insert(all.end(), names.begin(), names.end());
      expect_names(o.err, all);
    }
  }
}

TEST(StoreSafety, ACampaignRefusedBeforeItsFirstRunLeavesTheStoreUnchanged) {
  const auto sweeps = two_plumes();
  const std::string path = testing::temp_path("refused", ".sqlite");
  { Store store(path, sweeps, version(), false); }
  const StoreInfo before = [&] {
    Store store(path, sweeps, version(), false);
    return store.info();
  }();
  {
    Store store(path, sweeps, version(), false);
    const TaskRunner refuse = [](const auto&, const auto&, const auto&,
                                 const auto&) -> CampaignResult {
      throw ConfigError("refused");  // as a runner that cannot start (threads, ranks) would
    };
    EXPECT_THROW(run_campaign(sweeps, store, 7, {}, {}, refuse), ConfigError);
    const StoreInfo after = store.info();
    EXPECT_EQ(after.runs, before.runs);
    EXPECT_EQ(after.points, before.points);
    EXPECT_TRUE(after.runs.empty());
  }
}

// issue 16: points identified by their values ------------------------------------------------

// the quick sweep with a third algorithm between the two (a point more per plume)
std::vector<ExpandedSweep> two_plumes_three_algorithms() {
  std::ifstream in(kSweep);
  std::string text(std::istreambuf_iterator<char>(in), {});
  const std::string axis = R"(["casting", "surge-cast"])";
  text.replace(text.find(axis), axis.size(), R"(["casting", "surge-spiral", "surge-cast"])");
  const std::string path = testing::temp_path("three", ".toml");
  std::ofstream(path) << text;
  return {expand_sweep(read_sweep_file(path), {})};
}

std::string meta_of(const std::string& path, const std::string& key) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* q = nullptr;
  sqlite3_prepare_v2(db, "SELECT value FROM meta WHERE key = ?", -1, &q, nullptr);
  sqlite3_bind_text(q, 1, key.c_str(), -1, SQLITE_TRANSIENT);
  std::string value;
  if (sqlite3_step(q) == SQLITE_ROW)
    value = reinterpret_cast<const char*>(sqlite3_column_text(q, 0));
  sqlite3_finalize(q);
  sqlite3_close(db);
  return value;
}

TEST(StoreUpgrade, AStoreOfTheFormerSchemaIsReadAsItIsAndExtendedAsSchemaThree) {
  // the clean store as the version before this one wrote it: schema 2, no epoch
  const std::string store = copy_of_clean("schema2");
  sql(store,
      "UPDATE meta SET value = '2' WHERE key = 'schema'; DELETE FROM meta WHERE key = "
      "'epoch';");
  EXPECT_EQ(exports(store), exports(clean_store()));  // read as it is
  const std::vector<RunRow> before = read_store_rows(store, nullptr);
  const auto three = two_plumes_three_algorithms();
  {
    Store extended(store, three, version(), false);
    CampaignOptions options;
    options.threads = 2;
    const CampaignResult r = run_campaign(three, extended, 0, options);
    EXPECT_EQ(r.skipped, 48);
    EXPECT_EQ(r.computed, 24);
  }
  EXPECT_EQ(meta_of(store, "schema"), "3");
  EXPECT_EQ(meta_of(store, "epoch").size(), 16u);
  const std::vector<RunRow> after = read_store_rows(store, nullptr);
  ASSERT_EQ(after.size(), 72u);
  // its own 48 rows first (points 0-3, as it numbered them), unchanged; the new points after
  expect_same_rows(std::vector<RunRow>(after.begin(), after.begin() + 48), before);
  EXPECT_EQ(after[48].point, 4);
  // the two algorithms' exports from the extended store equal those of the clean store
  EXPECT_EQ(exports(store), exports(clean_store()));
}

// F13 --------------------------------------------------------------------------------------------

TEST(StoreConcurrency, TwoStoresOnOneFileSkipIdenticalRunsAndRefuseDifferentOnes) {
  const auto sweeps = two_plumes();
  const std::string path = testing::temp_path("shared", ".sqlite");
  Store a(path, sweeps, version(), false);
  Store b(path, sweeps, version(), false);
  CampaignOptions options;
  options.threads = 1;
  run_campaign(sweeps, a, 2, options);
  // b computed the same runs meanwhile: they are identical, so the store keeps one of each
  const CampaignResult second = run_tasks(sweeps, missing_runs(sweeps, {}, 2), options,
                                          [&](const std::vector<RunRow>& rows) { b.insert(rows); });
  EXPECT_EQ(second.computed, 8);
  EXPECT_EQ(b.rows().size(), 8u);
  expect_same_rows(a.rows(), b.rows());
  RunRow other = b.rows().front();
  other.result.time += 0.5;
  const std::string message = error_of([&] { b.insert({other}); });
  expect_names(message, {path, "already holds", "other results"});
  EXPECT_EQ(read_store_rows(path, nullptr).size(), 8u);
}

TEST(StoreConcurrency, AStoreEmptiedForAnotherDefinitionMeanwhileTakesNoMoreRuns) {
  const auto sweeps = two_plumes();
  const std::vector<ExpandedSweep> other{
      expand_sweep(read_sweep_file(kSweep), {parse_override("sim.dt=0.04")})};
  const std::string path = testing::temp_path("emptied", ".sqlite");
  Store a(path, sweeps, version(), false);
  CampaignOptions options;
  options.threads = 1;
  run_campaign(sweeps, a, 1, options);
  const auto rows = a.rows();
  Store b(path, other, version(), true);  // another process's --fresh
  const std::string message = error_of([&] { a.insert(rows); });
  expect_names(message, {path, "another definition"});
  EXPECT_TRUE(b.rows().empty());
}

TEST(StoreConcurrency, ThreeSweepsOnOneStoreAllFinishWithTheExportsOfOne) {
  const std::string store = testing::temp_path("together", ".sqlite");
  std::vector<std::string> outs;
  std::string command;
  for (int i = 0; i < 3; ++i) {
    outs.push_back(testing::temp_path("out", ""));
    command += kCli + " sweep " + kSweep + " --quiet --threads 1 --store " + store + " --out " +
               outs.back() + " >/dev/null 2>" + outs.back() + ".err & ";
  }
  ASSERT_EQ(std::system(("(" + command + "wait)").c_str()), 0);
  for (const auto& out : outs) {
    EXPECT_EQ(read_file(out + ".err"), "");
    EXPECT_TRUE(fs::exists(out + "/runs.csv")) << out;
  }
  EXPECT_EQ(exports(store), exports(clean_store()));
}

// F14, F22 ---------------------------------------------------------------------------------------

// runs the command with a file size limit (bytes), which fails writes as a full disk does;
// SIGXFSZ is left at its default, so a command that does not ignore it dies of it
testing::CommandOutput plumetrace_limited(const std::vector<std::string>& args, rlim_t bytes) {
  const std::string err = testing::temp_path("stderr", ".txt");
  testing::CommandOutput o;
  o.code = testing::wait_for(testing::spawn_program(kCli, args, "/dev/null", err, [bytes] {
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_FSIZE, &limit);
    signal(SIGXFSZ, SIG_DFL);
  }));
  o.err = read_file(err);
  return o;
}

TEST(StoreIo, AFullDiskExitsThreeNamingTheCauseAndLosesNoCommittedRun) {
  // 48 runs committed, then 112 more asked for with room for no journal page: the first write
  // fails, whatever the timing of the batches
  const std::string store = copy_of_clean("full");
  const std::string out = testing::temp_path("out", "");
  const auto kept = read_store_rows(store, nullptr);
  const auto o = plumetrace_limited(
      {"sweep", kSweep, "--quiet", "--runs", "40", "--store", store, "--out", out}, 4096);
  EXPECT_EQ(o.code, 3) << o.err;
  expect_names(o.err, {store, "write failed"});
  EXPECT_EQ(o.err.find("rollback"), std::string::npos) << o.err;
  // what was committed is intact, and the same sweep, given room, completes it
  std::vector<RunRow> still;
  for (const auto& r : read_store_rows(store, nullptr)) {
    if (r.trial < 12) still.push_back(r);
  }
  expect_same_rows(still, kept);
  const auto resumed =
      plumetrace("sweep " + kSweep + " --quiet --runs 40 --store " + store + " --out " + out);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  const std::string whole = testing::temp_path("whole", ".sqlite");
  ASSERT_EQ(plumetrace("sweep " + kSweep + " --quiet --runs 40 --store " + whole + " --out " +
                       testing::temp_path("whole_out", ""))
                .code,
            0);
  expect_same_rows(read_store_rows(store, nullptr), read_store_rows(whole, nullptr));
}

// F15 --------------------------------------------------------------------------------------------

// runs a command as a user other than root (who may write anything), or "" when none can be
std::string as_unprivileged(const std::string& command) {
  if (geteuid() != 0) return command;
  if (std::system("command -v setpriv >/dev/null 2>&1") != 0) return "";
  return "setpriv --reuid=65534 --regid=65534 --clear-groups " + command;
}

TEST(StoreIo, AReadOnlyStoreIsExportedAndMergedButNotSweptInto) {
  if (as_unprivileged("true").empty()) GTEST_SKIP() << "root without setpriv: cannot drop rights";
  const std::string dir = testing::temp_path("readonly", "");
  fs::create_directories(dir);
  const std::string store = dir + "/results.sqlite";
  fs::copy_file(clean_store(), store);
  const std::string writable = testing::temp_path("writable", "");
  fs::create_directories(writable);
  fs::permissions(store, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                           fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  fs::permissions(writable, fs::perms::all);
  const std::string before = read_file(store);

  auto o = run_command(as_unprivileged(kCli + " export " + kSweep + " --store " + store +
                                       " --out " + writable + "/exports"));
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(read_file(writable + "/exports/runs.csv"), [&] {
    const std::string out = testing::temp_path("clean_exports", "");
    plumetrace("export " + kSweep + " --store " + clean_store() + " --out " + out);
    return read_file(out + "/runs.csv");
  }());
  o = run_command(
      as_unprivileged(kCli + " merge " + store + " --store " + writable + "/merged.sqlite"));
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(exports(writable + "/merged.sqlite"), exports(clean_store()));
  o = run_command(as_unprivileged(kCli + " sweep " + kSweep + " --quiet --store " + store +
                                  " --out " + writable + "/sweep"));
  EXPECT_EQ(o.code, 3);
  expect_names(o.err, {store, "cannot write"});
  EXPECT_EQ(read_file(store), before);
  fs::permissions(dir, fs::perms::all);
}

// F16 --------------------------------------------------------------------------------------------

TEST(StoreSafety, AMergeKilledBeforeItsFirstCommitCanBeRunAgain) {
  // what a merge killed early leaves: an empty file, or a database without tables
  const std::string empty = testing::temp_path("empty", ".sqlite");
  std::ofstream(empty).close();
  const std::string no_tables = testing::temp_path("notables", ".sqlite");
  sql(no_tables, "PRAGMA journal_mode=WAL;");
  for (const auto& out : {empty, no_tables}) {
    const auto o = plumetrace("merge " + clean_store() + " --store " + out);
    EXPECT_EQ(o.code, 0) << o.err;
    EXPECT_EQ(exports(out), exports(clean_store()));
  }
}

}  // namespace
}  // namespace plumetrace
