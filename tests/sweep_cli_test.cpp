// `plumetrace sweep` and `reproduce` as processes: kill -9 and Ctrl-C mid-way, resume, report.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "plumetrace/experiment/store.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

const std::string kCli = PLUMETRACE_CLI;

// 3 points x 20 whole default runs (20 shared plumes of about 0.15 s each): long enough to
// interrupt
const char* const kSweep = R"(
name = "interrupt"
runs = 20
seed = 5

[set]
controller.algorithm = "surge-spiral"

[[axis]]
key = "surge_spiral.d_gap"
values = [0.111, 0.222, 0.333]
)";

std::string write_sweep() { return testing::write_temp("sweep", ".toml", kSweep); }

using testing::read_file;

// starts the command in the background; returns its pid
pid_t spawn(const std::vector<std::string>& args) { return testing::spawn_program(kCli, args); }

// runs the command to its end without a shell, capturing stdout and stderr
testing::CommandOutput run_args(const std::vector<std::string>& args) {
  return testing::run_program(kCli, args);
}

int wait_exit(pid_t pid) { return testing::wait_for(pid); }

std::size_t stored_runs(const std::string& store) {
  try {
    return read_store_rows(store, nullptr).size();
  } catch (const StoreError&) {
    return 0;  // not created yet
  }
}

// waits until the store holds at least n runs (or the process ended)
void wait_for_runs(const std::string& store, std::size_t n, pid_t pid) {
  for (int i = 0; i < 3000; ++i) {
    if (stored_runs(store) >= n) return;
    int status;
    if (waitpid(pid, &status, WNOHANG) == pid) FAIL() << "the sweep ended before it was stopped";
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  FAIL() << "no runs were stored";
}

void expect_same_rows(const std::vector<RunRow>& a, const std::vector<RunRow>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].point, b[i].point);
    EXPECT_EQ(a[i].trial, b[i].trial);
    EXPECT_EQ(a[i].result.d_t, b[i].result.d_t);
    EXPECT_EQ(a[i].result.time, b[i].result.time);
    EXPECT_EQ(a[i].result.outcome, b[i].result.outcome);
    EXPECT_EQ(a[i].result.losses, b[i].result.losses);
  }
}

std::vector<RunRow> clean_rows(const std::string& sweep) {
  const std::string store = testing::temp_path("clean", ".sqlite");
  const std::string out = testing::temp_path("clean_out", "");
  EXPECT_EQ(wait_exit(spawn({"sweep", sweep, "--store", store, "--out", out, "--threads", "2"})),
            0);
  return read_store_rows(store, nullptr);
}

TEST(SweepCli, KilledSweepResumesToTheRowsOfACleanSweep) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("killed", ".sqlite");
  const std::string out = testing::temp_path("killed_out", "");
  const std::vector<std::string> args{"sweep", sweep, "--store",   store,
                                      "--out", out,   "--threads", "1"};
  const pid_t pid = spawn(args);
  wait_for_runs(store, 3, pid);
  kill(pid, SIGKILL);
  EXPECT_EQ(wait_exit(pid), 128 + SIGKILL);
  const std::size_t kept = stored_runs(store);
  EXPECT_GE(kept, 3u);
  EXPECT_LT(kept, 60u);

  EXPECT_EQ(wait_exit(spawn(args)), 0);
  const auto rows = read_store_rows(store, nullptr);
  EXPECT_EQ(rows.size(), 60u);  // no duplicates: (point, trial) is the store's key
  expect_same_rows(rows, clean_rows(sweep));
  EXPECT_TRUE(std::filesystem::exists(out + "/runs.csv"));
  EXPECT_TRUE(std::filesystem::exists(out + "/summary.csv"));
  EXPECT_TRUE(std::filesystem::exists(out + "/results.json"));
}

TEST(SweepCli, InterruptedSweepExitsWith130AndKeepsItsRuns) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("sigint", ".sqlite");
  const std::vector<std::string> args{"sweep",     sweep,   "--store",
                                      store,       "--out", testing::temp_path("sigint_out", ""),
                                      "--threads", "2"};
  const pid_t pid = spawn(args);
  wait_for_runs(store, 2, pid);
  kill(pid, SIGINT);
  EXPECT_EQ(wait_exit(pid), 130);
  const std::size_t kept = stored_runs(store);
  EXPECT_GE(kept, 2u);
  EXPECT_EQ(wait_exit(spawn(args)), 0);
  expect_same_rows(read_store_rows(store, nullptr), clean_rows(sweep));
}

TEST(SweepCli, OffATerminalItPrintsOnlyTheSummary) {
  const std::string sweep = write_sweep();
  const std::string out = testing::temp_path("quiet_out", "");
  const std::string err = testing::temp_path("stderr", ".txt");
  const std::string stdout_path = testing::temp_path("stdout", ".txt");
  const std::string command =
      kCli + " sweep " + sweep + " --runs 2 --out " + out + " >" + stdout_path + " 2>" + err;
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(read_file(err), "");
  const std::string text = read_file(stdout_path);
  EXPECT_NE(text.find("surge_spiral.d_gap=0.222"), std::string::npos) << text;
  EXPECT_NE(text.find("6 runs"), std::string::npos) << text;
}

TEST(SweepCli, ReusingAStoreWithAnotherDefinitionNeedsFresh) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("other", ".sqlite");
  const std::string out = testing::temp_path("other_out", "");
  ASSERT_EQ(wait_exit(spawn({"sweep", sweep, "--runs", "1", "--store", store, "--out", out})), 0);
  EXPECT_EQ(wait_exit(spawn({"sweep", sweep, "--runs", "1", "--store", store, "--out", out, "--set",
                             "sim.dt=0.04"})),
            2);
  EXPECT_EQ(wait_exit(spawn({"sweep", sweep, "--runs", "1", "--store", store, "--out", out, "--set",
                             "sim.dt=0.04", "--fresh"})),
            0);
}

// a quick sweep of two axes, its sigma_a axis given `values` (a TOML array)
std::string write_grid(const std::string& values) {
  return testing::write_temp("grid", ".toml", R"(
name = "grid"
title = "a quick grid"
runs = 3
seed = 9

[set]
robot.start_x = 3.0
sim.warmup = 4.0
supervisor.timeout = 60.0

[[axis]]
key = "controller.algorithm"
values = ["casting", "surge-cast"]

[[axis]]
key = "wind_sensor.sigma_a"
values = )" + values + "\n");
}

TEST(SweepCli, AValueAddedToAnAxisComputesOnlyItsRunsAndGivesTheExportsOfAFreshSweep) {
  const std::string store = testing::temp_path("grow", ".sqlite");
  const std::string out = testing::temp_path("grow_out", "");
  ASSERT_EQ(run_args({"sweep", write_grid("[0.1, 0.5]"), "--store", store, "--out", out}).code, 0);
  const std::string grown = write_grid("[0.1, 0.3, 0.5]");
  const auto o = run_args({"sweep", grown, "--store", store, "--out", out});
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("18 runs (6 computed now, 12 from the store)"), std::string::npos) << o.out;
  const std::string fresh = testing::temp_path("grow_fresh", "");
  ASSERT_EQ(run_args({"sweep", grown, "--store", fresh + ".sqlite", "--out", fresh}).code, 0);
  for (const char* file : {"/runs.csv", "/summary.csv"}) {
    EXPECT_EQ(read_file(out + file), read_file(fresh + file)) << file;
  }
}

TEST(ReportCli, WritesThePagesFiguresAndTablesOfAnySweep) {
  const std::string sweep = write_grid("[0.1, 0.5]");
  const std::string store = testing::temp_path("report", ".sqlite");
  ASSERT_EQ(
      run_args({"sweep", sweep, "--store", store, "--out", testing::temp_path("report_sweep", "")})
          .code,
      0);
  const std::string out = testing::temp_path("report_out", "");
  const auto o = run_args({"report", sweep, "--store", store, "--out", out});
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(o.err, "");
  EXPECT_NE(o.out.find("report: " + out + "/report.html"), std::string::npos) << o.out;
  for (const char* file : {"report.html", "report.md", "report.csv", "figures/sweep_grid.png",
                           "runs.csv", "summary.csv", "results.json"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  }
  EXPECT_GT(std::filesystem::file_size(out + "/figures/sweep_grid.png"), 10000u);
  const std::string md = read_file(out + "/report.md");
  // the title says what the data say; the table has every point; the figure is embedded
  EXPECT_EQ(md.rfind("# a quick grid: success ", 0), 0u) << md.substr(0, 200);
  EXPECT_NE(md.find("| casting | 0.5 | 3 |"), std::string::npos) << md;
  EXPECT_NE(read_file(out + "/report.html").find("data:image/png;base64,"), std::string::npos);
  // report.csv: a header and one row per point, with the summary's numbers
  const std::string csv = read_file(out + "/report.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_NE(md.find("plumetrace report " + sweep + " --store " + store), std::string::npos);
}

TEST(ReportCli, NamesThePointsWithRunsMissingAndTheCommandThatComputesThem) {
  const std::string store = testing::temp_path("partial", ".sqlite");
  ASSERT_EQ(run_args({"sweep", write_grid("[0.1, 0.5]"), "--store", store, "--out",
                      testing::temp_path("partial_sweep", "")})
                .code,
            0);
  const std::string grown = write_grid("[0.1, 0.3, 0.5]");
  const std::string out = testing::temp_path("partial_out", "");
  const auto o = run_args({"report", grown, "--store", store, "--out", out});
  ASSERT_EQ(o.code, 0) << o.err;
  for (const std::string& part :
       {std::string("2 of 6 points of sweep grid have runs missing"),
        std::string("(controller.algorithm = 'casting', wind_sensor.sigma_a = 0.3): 0 of 3 runs"),
        "plumetrace sweep " + grown + " --store " + store}) {
    EXPECT_NE(o.err.find(part), std::string::npos) << part << "\n" << o.err;
  }
  const std::string md = read_file(out + "/report.md");
  EXPECT_NE(md.find("0 of 3 (incomplete)"), std::string::npos) << md;
  EXPECT_NE(md.find("plumetrace sweep " + grown + " --store " + store), std::string::npos);
  // computed, the report has nothing missing
  ASSERT_EQ(run_args({"sweep", grown, "--store", store, "--out", out}).code, 0);
  const auto again = run_args({"report", grown, "--store", store, "--out", out});
  EXPECT_EQ(again.code, 0);
  EXPECT_EQ(again.err, "");
  EXPECT_EQ(read_file(out + "/report.md").find("incomplete"), std::string::npos);
}

TEST(ReportCli, ABadStoreOrFolderExitsTwoOrThreeNamingTheFile) {
  const std::string sweep = write_grid("[0.1, 0.5]");
  const std::string out = testing::temp_path("bad_out", "");
  const auto expect = [&](const std::vector<std::string>& args, int code,
                          const std::vector<std::string>& named) {
    const auto o = run_args(args);
    EXPECT_EQ(o.code, code) << o.err;
    for (const auto& n : named) EXPECT_NE(o.err.find(n), std::string::npos) << n << "\n" << o.err;
    EXPECT_FALSE(std::filesystem::exists(out + "/report.html"));
  };
  const std::string missing = testing::temp_path("missing", ".sqlite");
  expect({"report", sweep, "--store", missing, "--out", out}, 2, {missing, "no such file"});
  const std::string text = testing::write_temp("text", ".sqlite", "not a database at all\n");
  expect({"report", sweep, "--store", text, "--out", out}, 2,
         {text, "not a plumetrace results store"});
  // the same sweep under another base scenario: a --set other than the one the store recorded
  // (without --set, the recorded one is used: CliTrust.ExportAndReportUseTheSetTheStoreRecorded)
  const std::string other = testing::temp_path("other", ".sqlite");
  ASSERT_EQ(run_args({"sweep", write_grid("[0.1, 0.5]"), "--store", other, "--out",
                      testing::temp_path("other_sweep", ""), "--set", "sim.dt=0.04"})
                .code,
            0);
  expect({"report", sweep, "--store", other, "--out", out, "--set", "sim.dt=0.032"}, 2,
         {other, "another resolved scenario", "wind_sensor.sigma_a = 0.1"});
  // a store of other values of the sweep: nothing to report, and how to compute it
  const std::string elsewhere = testing::temp_path("elsewhere", ".sqlite");
  ASSERT_EQ(run_args({"sweep", write_grid("[0.2]"), "--store", elsewhere, "--out",
                      testing::temp_path("elsewhere_sweep", "")})
                .code,
            0);
  expect({"report", sweep, "--store", elsewhere, "--out", out}, 2,
         {elsewhere, "holds no run of these sweeps' points",
          "plumetrace sweep " + sweep + " --store " + elsewhere});
  // an output folder that cannot be made: exit 3 naming it
  const std::string file = testing::write_temp("a_file", ".txt", "in the way\n");
  const auto o =
      run_args({"report", sweep, "--store", other, "--out", file + "/out", "--set", "sim.dt=0.04"});
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_NE(o.err.find(file), std::string::npos) << o.err;
}

TEST(Reproduce, TinyReproductionWritesEveryFigureAndTheClaimsTable) {
  const std::string out = testing::temp_path("reproduce", "");
  ASSERT_EQ(wait_exit(spawn({"reproduce", "--runs", "1", "--out", out, "--quiet", "--presets",
                             "plugin-published"})),
            0);
  const std::string html = read_file(out + "/report.html");
  const std::string md = read_file(out + "/report.md");
  std::vector<std::string> figures;
  for (const char* set : {"A", "B", "C", "D", "E", "F", "G", "H", "I"}) {
    figures.push_back(std::string("set_") + set + ".png");
  }
  for (const char* f : {"trajectories.png", "sensitivity.png", "failures.png", "readings_map.png",
                        "readings_success.png"}) {
    figures.push_back(f);
  }
  for (const auto& f : figures) {
    EXPECT_TRUE(std::filesystem::file_size(out + "/figures/" + f) > 1000) << f;
    EXPECT_NE(md.find("figures/" + f), std::string::npos) << f;
  }
  // every figure embedded in the self-contained HTML
  std::size_t embedded = 0;
  for (std::size_t at = html.find("data:image/png;base64,"); at != std::string::npos;
       at = html.find("data:image/png;base64,", at + 1)) {
    ++embedded;
  }
  EXPECT_GE(embedded, figures.size());
  // the claims table with all eleven claims and a verdict for each
  for (int id = 1; id <= 11; ++id) {
    EXPECT_NE(md.find("| " + std::to_string(id) + " |"), std::string::npos) << "claim " << id;
  }
  EXPECT_NE(html.find("virtually all runs of D, E, F succeed"), std::string::npos);
  for (const char* file : {"results.sqlite", "summary.json", "runs.csv", "summary.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
  }
  // the main reading and the one asked for, each with its eleven verdicts and fixed values
  const auto summary = nlohmann::json::parse(read_file(out + "/summary.json"));
  ASSERT_EQ(summary["readings"].size(), 2u);
  EXPECT_EQ(summary["computed_runs"], summary["total_runs"]);  // a fresh folder: every run
  EXPECT_EQ(summary["readings"][0]["name"], "default");
  EXPECT_EQ(summary["readings"][1]["name"], "plugin-published");
  EXPECT_EQ(summary["readings"][1]["settings"]["plume.amount"], 1.0);
  // every key a preset sets, with the value each reading's runs used: the default column is
  // the built-in value, the preset's column its own
  EXPECT_EQ(summary["readings"][0]["values"]["plume.sigma_p"], Scenario{}.plume.sigma_p);
  EXPECT_EQ(summary["readings"][1]["values"]["plume.sigma_p"], 0.1);
  EXPECT_EQ(summary["readings"][0]["values"].size(), summary["readings"][1]["settings"].size());
  for (const auto& r : summary["readings"]) {
    EXPECT_EQ(r["claims"].size(), 11u);
    EXPECT_EQ(r["fixed"].size(), 3u);
    EXPECT_EQ(r["held"].get<int>() + r["not_held"].get<int>() + r["unclear"].get<int>(), 11);
  }
  EXPECT_NE(html.find("plugin-published"), std::string::npos);
  // the axis readings: the set files' own and each file of studies/lochmatter2008/axes/, each
  // with its eleven verdicts, side by side in the report with the captions' evidence
  ASSERT_EQ(summary["axis_readings"].size(), 2u);
  EXPECT_EQ(summary["axis_readings"][0]["name"], "sets");
  EXPECT_EQ(summary["axis_readings"][1]["sets"].size(), 3u);
  for (const auto& a : summary["axis_readings"]) EXPECT_EQ(a["claims"].size(), 11u);
  EXPECT_NE(md.find("## The axes side by side"), std::string::npos);
  EXPECT_NE(md.find("bars lacking: fewer than 2 successful runs"), std::string::npos);
}

TEST(Reproduce, AnUnknownPresetExitsTwoNamingItBeforeAnyRun) {
  const std::string out = testing::temp_path("reproduce_bad", "");
  const auto o = testing::run_command(kCli + " reproduce --preset paper-literal --out " + out);
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("unknown preset 'paper-literal'"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("plugin-published"), std::string::npos) << o.err;
  EXPECT_FALSE(std::filesystem::exists(out + "/results.sqlite"));
}

// the report runs without a shell: a folder name is never parsed (issue 14)
TEST(Reproduce, AnOutFolderWithAQuoteASpaceAndADollarGetsItsReport) {
  const std::string out = testing::temp_path("it's a $HOME", "");
  const auto o =
      run_args({"reproduce", "--runs", "1", "--presets", "none", "--quiet", "--out", out});
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_GT(std::filesystem::file_size(out + "/report.html"), 1000u);
  EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
  EXPECT_NE(o.out.find("report: " + out + "/report.html"), std::string::npos) << o.out;
}

TEST(Reproduce, AReportThatCannotBeDrawnExitsThreeKeepingTheResults) {
  const std::string out = testing::temp_path("it's a $HOME", "");
  std::filesystem::create_directories(out);
  std::ofstream(out + "/figures") << "a file where the report's figures folder goes\n";
  const auto o =
      run_args({"reproduce", "--runs", "1", "--presets", "none", "--quiet", "--out", out});
  EXPECT_EQ(o.code, 3);
  EXPECT_NE(o.err.find("plumetrace: error: drawing the report failed ("), std::string::npos)
      << o.err;
  EXPECT_NE(o.err.find(" -m plumetrace.report '"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("the results are kept in " + out + "/"), std::string::npos) << o.err;
  EXPECT_TRUE(std::filesystem::exists(out + "/summary.json"));
  EXPECT_TRUE(std::filesystem::exists(out + "/runs.csv"));
}

}  // namespace
}  // namespace plumetrace
