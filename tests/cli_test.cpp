// The plumetrace command, run as a user would: outputs, exit codes and error messages.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

using nlohmann::json;

const std::string kCli = PLUMETRACE_CLI;
const std::string kScenarios = std::string(PLUMETRACE_SOURCE_DIR) + "/scenarios/";

using Output = testing::CommandOutput;
using testing::read_file;

// runs the command with `args`, capturing stdout, stderr and the exit code
Output cli(const std::string& args) { return testing::run_command(kCli + " " + args); }

TEST(Cli, RunJsonHasEveryDocumentedKey) {
  const Output o = cli("run --algorithm surge-spiral --seed 3 --trial 2 --json");
  ASSERT_EQ(o.code, 0) << o.err;
  const json j = json::parse(o.out);
  for (const char* key :
       {"outcome", "success", "time_s", "d_t", "d_u", "overhead", "losses", "seed", "trial"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["seed"], 3);
  EXPECT_EQ(j["trial"], 2);
  EXPECT_EQ(j["algorithm"], "surge-spiral");
  EXPECT_EQ(j["success"], j["outcome"] == "success");
  const std::string outcome = j["outcome"];
  EXPECT_TRUE(outcome == "success" || outcome == "wall" || outcome == "timeout" ||
              outcome == "gave_up")
      << outcome;
}

TEST(Cli, SameSeedGivesTheSameOutputAndAnotherTrialDiffers) {
  const Output a = cli("run --algorithm casting --seed 5 --trial 1 --json");
  const Output b = cli("run --algorithm casting --seed 5 --trial 1 --json");
  const Output c = cli("run --algorithm casting --seed 5 --trial 2 --json");
  ASSERT_EQ(a.code, 0);
  EXPECT_EQ(a.out, b.out);
  EXPECT_NE(a.out, c.out);
}

TEST(Cli, ScenarioFileAndSetAreApplied) {
  // --set may come before the scenario file without swallowing it
  const Output o = cli("config --set plume.sigma_p=0.2 " + kScenarios +
                       "paper-literal.toml --set odor.threshold=50 --json");
  ASSERT_EQ(o.code, 0) << o.err;
  const json j = json::parse(o.out);
  EXPECT_EQ(j["plume"]["preset"], "paper-literal");
  EXPECT_EQ(j["plume"]["kernel"], "printed");
  EXPECT_EQ(j["plume"]["sigma_p"], 0.2);
  EXPECT_EQ(j["odor"]["threshold"], 50.0);
}

TEST(Cli, PrintedConfigRunsTheSameAsTheOptionsThatMadeIt) {
  const std::string path = testing::temp_path("resolved", ".toml");
  const Output config = cli("config --algorithm surge-cast --set surge_cast.d_cast=0.4");
  ASSERT_EQ(config.code, 0) << config.err;
  std::ofstream(path) << config.out;
  const Output a = cli("run --algorithm surge-cast --set surge_cast.d_cast=0.4 --json");
  const Output b = cli("run " + path + " --json");
  EXPECT_EQ(a.out, b.out);
}

TEST(Cli, ScenariosThatPutTheRobotOutsideOdorWarnNamingTheKeys) {
  // coherent: nothing on stderr, the derived ring and warm-up in the resolved config
  const Output paper = cli("config");
  EXPECT_EQ(paper.err, "");
  const Output slow = cli("config --set wind.vx=0.5");
  ASSERT_EQ(slow.code, 0) << slow.err;
  EXPECT_EQ(slow.err, "");
  EXPECT_NE(slow.out.find("\ncapacity = 2880  #"), std::string::npos) << slow.out;
  EXPECT_NE(slow.out.find("\nwarmup = 36.0  #"), std::string::npos) << slow.out;
  // incoherent: config and run still work, and say which keys to change
  const Output ring = cli("config --set wind.vx=0.5 --set plume.capacity=1600");
  EXPECT_EQ(ring.code, 0);
  EXPECT_EQ(ring.err.rfind("plumetrace: warning: ", 0), 0u) << ring.err;
  EXPECT_NE(ring.err.find("plume.capacity"), std::string::npos) << ring.err;
  const Output aside =
      cli("run --set source.y=1.0 --set robot.start_y=0 --set supervisor.timeout=2 --json");
  EXPECT_EQ(aside.code, 0);
  EXPECT_NE(aside.err.find("plumetrace: warning: the robot starts outside odor"), std::string::npos)
      << aside.err;
  EXPECT_NE(aside.err.find("robot.start_y"), std::string::npos) << aside.err;
  EXPECT_EQ(json::parse(aside.out)["outcome"], "timeout");
  // a sweep names the point
  const std::string sweep = testing::temp_path("warn", ".toml");
  std::ofstream(sweep) << "name = \"warn\"\nruns = 1\n[set]\nsupervisor.timeout = 1.0\n"
                          "sim.warmup = 20.0\n[[axis]]\nkey = \"wind.vx\"\nvalues = [0.9, 0.5]\n";
  const Output swept =
      cli("sweep " + sweep + " --out " + testing::temp_path("warn", "") + " --threads 1 --quiet");
  EXPECT_EQ(swept.code, 0) << swept.err;
  EXPECT_NE(swept.err.find("sweep warn, point 1 (wind.vx = 0.5): the plume cannot reach"),
            std::string::npos)
      << swept.err;
  EXPECT_EQ(swept.err.find("point 0"), std::string::npos) << swept.err;
}

// the meandering wind's keys of 0.4.0 still work until the next version, each said once on
// stderr naming its new key; the resolved config has the new keys only (issue 24)
TEST(Cli, OldMeanderKeysWarnNamingTheirNewKeys) {
  const Output o =
      cli("config --set wind.model=meander --set wind.meander_gain=0.3 --set wind.meander_gain=0.2 "
          "--set meander.nx=9");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(o.err,
            "plumetrace: warning: --set: config key wind.meander_gain is deprecated: write "
            "meander.gain (renamed after version 0.4.0; the old name is accepted until the next "
            "version)\n");
  EXPECT_NE(o.out.find("[meander]\ngain = 0.2  #"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("\nnx = 9  #"), std::string::npos) << o.out;
  EXPECT_EQ(o.out.find("meander_"), std::string::npos) << o.out;
}

TEST(Cli, ConfigErrorsNameTheKeyExitTwoAndPrintNothing) {
  struct Case {
    std::string args, expect;
  };
  const Case cases[] = {
      {"run --set sim.dt=0 --json", "sim.dt"},
      {"run --set plume.nonsense=1", "unknown config key 'plume.nonsense'"},
      {"run --set plume.capacity=0", "plume.capacity"},
      {"run --algorithm no-such-algorithm", "controller.algorithm"},
      {"run --set plume.preset=foo", "plume.preset"},
      {"run --set robot.wheel_speed=-0.1", "robot.wheel_speed"},
      {"run --set odor.threshold=0", "odor.threshold"},
      {"run no/such/scenario.toml", "no/such/scenario.toml"},
      {"probe --points 1,2", "--points"},
      {"config --set supervisor.success_radius=-1", "supervisor.success_radius"},
      {"run --trace out.txt", "out.txt"},
      {"run --no-such-flag", "no-such-flag"},
      {"config /", "cannot read scenario file '/'"},
      {"run --seed -1", "--seed"},
      {"run --trial 1.5", "--trial"},
      {"run --set wind.vx=inf", "wind.vx: must be a finite number"},
      {"run --set robot.start_heading_deg=200", "robot.start_heading_deg"},
      {"run --set sim.dt=1e-300", "at most 1e7 steps"},
      {"probe --points 1,0,nan", "--points"},
      {"probe --points 1,0,0 --duration 0.1 --interval 1", "--duration"},
      {"probe", "--points: required"},
      {"probe --plume-stats --points 1,0,0", "--points excludes --plume-stats"},
      {"probe --trials 3", "--trials requires --plume-stats"},
      {"probe --plume-stats --offsets 0,x", "--offsets: '0,x'"},
      {"probe --plume-stats --turns 200", "--turns"},
      // issue 24, item 8: teams, starts, sensors and declarations
      {"run --set team.count=0", "team.count"},
      {"run --set team.count=1001", "team.count"},
      {"run --set team.count=2 --set team.spacing=0.1", "team.spacing"},
      {"run --set team.count=30", "team.count"},
      {"run --set start.region=disc --set start.cy=9", "start.cx, start.cy, start.radius"},
      {"run --set start.region=rectangle --set team.count=1000", "team.count"},
      {"run --set team.range=-1", "team.range"},
      {"run --set team.delay=-1", "team.delay"},
      {"run --set odor.model=mox", "odor.model"},
      {"run --set supervisor.declaration_radius=0", "supervisor.declaration_radius"},
      {"run --set meander.gain=11", "meander.gain: must be a number >= 0 and <= 10"},
      {"run --set wind.meander_gain=11", "wind.meander_gain: must be a number >= 0 and <= 10"},
      // issue 25: the random walks' and chemotaxis's keys, refused before any run
      {"run --set controller.algorithm=levy --set levy.mu=1",
       "levy.mu: must be a number > 1 and <= 3"},
      {"run --set controller.algorithm=levy --set levy.mu=3.5",
       "levy.mu: must be a number > 1 and <= 3"},
      {"run --set controller.algorithm=levy --set levy.l_max=0.1",
       "levy.l_max: must be greater than levy.l_min"},
      {"run --set controller.algorithm=crw --set crw.rho=1.5",
       "crw.rho: must be a number >= 0 and <= 1"},
      {"run --set controller.algorithm=crw --set crw.upwind_bias=-0.1", "crw.upwind_bias"},
      {"run --set controller.algorithm=crw --set crw.step=0", "crw.step: must be a number > 0"},
      {"run --set controller.algorithm=crw --set crw.step_law=gamma",
       "crw.step_law: must be one of 'fixed', 'exponential'"},
      {"run --set chemotaxis.signal=smell",
       "chemotaxis.signal: must be one of 'concentration', 'binary'"},
      {"run --set chemotaxis.run_length=-1", "chemotaxis.run_length"},
      {"run --set chemotaxis.bias=-1", "chemotaxis.bias"},
      // issue 25, item 8: infotaxis' model and grid
      {"run --algorithm infotaxis --set infotaxis.diffusivity=0", "infotaxis.diffusivity"},
      {"run --algorithm infotaxis --set infotaxis.lifetime=-1", "infotaxis.lifetime"},
      {"run --algorithm infotaxis --set infotaxis.detector_size=5",
       "infotaxis.detector_size: must be below the correlation length"},
      {"run --algorithm infotaxis --set infotaxis.cells_upwind=400 --set "
       "infotaxis.cells_crosswind=100",
       "infotaxis.cells_upwind, infotaxis.cells_downwind, infotaxis.cells_crosswind: the grid"},
      {"run --algorithm infotaxis --set infotaxis.cells_upwind=1001", "infotaxis.cells_upwind"},
      // issue 25, item 8: the particle filter's limits
      {"run --algorithm particle-filter --set particle_filter.particles=20001",
       "particle_filter.particles"},
      {"run --algorithm particle-filter --set particle_filter.diffusivity=0",
       "particle_filter.diffusivity"},
      {"run --algorithm particle-filter --set particle_filter.particles=20000 --set "
       "particle_filter.wind_history=600",
       "particle_filter.wind_history"},
  };
  for (const auto& c : cases) {
    const Output o = cli(c.args);
    EXPECT_EQ(o.code, 2) << c.args;
    EXPECT_EQ(o.out, "") << c.args;
    EXPECT_NE(o.err.find(c.expect), std::string::npos) << c.args << " said: " << o.err;
  }
}

TEST(Cli, SeedAndTrialShowAsWholeNumbersInHelpAndKeepTheirChecks) {
  for (const char* command : {"run", "probe"}) {
    const Output o = cli(std::string(command) + " --help");
    ASSERT_EQ(o.code, 0) << command;
    EXPECT_NE(o.out.find("--seed UINT"), std::string::npos) << command << ":\n" << o.out;
    EXPECT_EQ(o.out.find("--seed TEXT"), std::string::npos) << command;
  }
  const Output run = cli("run --help");
  EXPECT_NE(run.out.find("--trial UINT"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("--trial TEXT"), std::string::npos) << run.out;
  // the whole range of a 64-bit seed, and nothing past it
  const Output top = cli("run --seed 18446744073709551615 --trial 18446744073709551615 --json");
  ASSERT_EQ(top.code, 0) << top.err;
  EXPECT_EQ(json::parse(top.out)["seed"].get<std::uint64_t>(), 18446744073709551615ULL);
  for (const char* args : {"run --seed 18446744073709551616", "run --trial x",
                           "probe --points 1,0,0 --seed 1e3", "run --seed=-0"}) {
    const Output o = cli(args);
    EXPECT_EQ(o.code, 2) << args;
    EXPECT_NE(o.err.find("must be a whole number from 0 to 18446744073709551615"),
              std::string::npos)
        << args << " said: " << o.err;
  }
}

TEST(Cli, TomlValuesOfTheWrongTypeNameTheKey) {
  const std::string path = testing::temp_path("array", ".toml");
  std::ofstream(path) << "[plume]\nsigma_p = [0.1]\n";
  const Output o = cli("run " + path);
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("plume.sigma_p: must be a number >= 0 (got '<array>')"), std::string::npos)
      << o.err;
}

TEST(Cli, UnwritableTraceFailsBeforeTheRunWithCodeThree) {
  const Output o = cli("run --trace /nonexistent-dir/trace.csv --json");
  EXPECT_EQ(o.code, 3);
  EXPECT_EQ(o.out, "");
  EXPECT_NE(o.err.find("/nonexistent-dir/trace.csv"), std::string::npos) << o.err;
}

TEST(Cli, CsvTraceHoldsStepsAndFilamentSnapshots) {
  const std::string path = testing::temp_path("trace", ".csv");
  const Output o = cli("run --algorithm surge-cast --set supervisor.timeout=5 --trace " + path +
                       " --snapshot-interval 1 --json");
  ASSERT_EQ(o.code, 0) << o.err;
  const json result = json::parse(o.out);
  std::istringstream steps(read_file(path));
  std::string header, line;
  std::getline(steps, header);
  EXPECT_EQ(
      header.rfind("agent,time,x,y,heading,odometer,state,odor,concentration,wind_samples", 0), 0u);
  int rows = 0;
  while (std::getline(steps, line)) ++rows;
  // one row at release plus one per step
  EXPECT_EQ(rows, result["steps"].get<int>() + 1);

  const std::string filaments = read_file(path.substr(0, path.size() - 4) + ".filaments.csv");
  EXPECT_EQ(filaments.rfind("time,x,y,z,w\n", 0), 0u);
  // snapshots at 0..5 s, 1600 filaments each after the 20 s warm-up
  const auto lines = std::count(filaments.begin(), filaments.end(), '\n');
  EXPECT_EQ(lines, 1 + 6 * 1600);
}

TEST(Cli, JsonTraceMatchesTheRunResult) {
  const std::string path = testing::temp_path("trace", ".json");
  const Output o = cli("run --algorithm casting --set supervisor.timeout=3 --trace " + path +
                       " --snapshot-interval 0.5 --json");
  ASSERT_EQ(o.code, 0) << o.err;
  const json trace = json::parse(read_file(path));
  EXPECT_EQ(trace["result"], json::parse(o.out));
  const auto& steps = trace["steps"];
  const std::size_t n = steps["time"].size();
  EXPECT_EQ(n, trace["result"]["steps"].get<std::size_t>() + 1);
  for (const char* col : {"x", "y", "heading", "state", "odor", "wind_x_body"}) {
    EXPECT_EQ(steps[col].size(), n) << col;
  }
  // the interval is rounded to whole steps: every 16 steps (0.512 s), starting at release
  const auto every = std::lround(0.5 / 0.032);
  EXPECT_EQ(trace["snapshots"].size(), static_cast<std::size_t>((n - 1) / every + 1));
  EXPECT_EQ(trace["snapshots"][1]["time"], every * 0.032);
  EXPECT_EQ(trace["config"]["controller"]["algorithm"], "casting");
  // the wind is sampled at release: the first step carries a sample
  EXPECT_EQ(steps["wind_samples"][1], 1);
  EXPECT_FALSE(steps["wind_x_body"][1].is_null());
}

TEST(Cli, RunViewWritesThePageAndViewRedrawsItFromTheTrace) {
  const std::string trace = testing::temp_path("run", ".json");
  const std::string page = testing::temp_path("run", ".html");
  const Output o = cli("run --set supervisor.timeout=10 --trace " + trace + " --view " + page);
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("view      " + page), std::string::npos) << o.out;
  const std::string html = read_file(page);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  // --view alone records filaments every 0.25 s (8 steps); so does the trace written beside it
  EXPECT_EQ(json::parse(read_file(trace))["snapshots"].size(), 1u + 313u / 8u);

  // view: the same page from the trace, and the static figure
  const std::string again = testing::temp_path("again", ".html");
  ASSERT_EQ(cli("view " + trace + " -o " + again).code, 0);
  EXPECT_EQ(read_file(again), html);
  const std::string figure = testing::temp_path("figure", ".svg");
  const Output f = cli("view " + trace + " -o " + figure + " --at 5");
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_EQ(read_file(figure).rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
  // without -o: the trace's name with .html
  ASSERT_EQ(cli("view " + trace).code, 0);
  EXPECT_EQ(read_file(trace.substr(0, trace.size() - 5) + ".html"), html);
}

TEST(Cli, ViewErrorsNameTheFileAndExitNonZero) {
  const Output missing = cli("view /nonexistent-dir/run.json");
  EXPECT_EQ(missing.code, 3);
  EXPECT_NE(missing.err.find("/nonexistent-dir/run.json"), std::string::npos) << missing.err;

  const Output csv = cli("view run.csv");
  EXPECT_EQ(csv.code, 2);
  EXPECT_NE(csv.err.find("write the trace as .json"), std::string::npos) << csv.err;

  const std::string trace = testing::temp_path("run", ".json");
  ASSERT_EQ(cli("run --set supervisor.timeout=1 --trace " + trace).code, 0);
  const Output png = cli("view " + trace + " -o run.png");
  EXPECT_EQ(png.code, 2);
  EXPECT_NE(png.err.find("--output 'run.png'"), std::string::npos) << png.err;

  // a bad --view fails before the run: nothing printed
  const Output bad = cli("run --view run.txt");
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.out, "");
  EXPECT_NE(bad.err.find("--view 'run.txt'"), std::string::npos) << bad.err;
  const Output unwritable = cli("run --view /nonexistent-dir/run.html");
  EXPECT_EQ(unwritable.code, 3);
  EXPECT_EQ(unwritable.out, "");
}

TEST(Cli, ProbeReportsEveryPoint) {
  const Output o = cli("probe --points \"8,0,0;8,1.5,0\" --duration 5 --json");
  ASSERT_EQ(o.code, 0) << o.err;
  const json j = json::parse(o.out);
  ASSERT_EQ(j["points"].size(), 2u);
  EXPECT_EQ(j["points"][1]["y"], 1.5);
  // on the axis the default plume is intermittent; 1.5 m to the side it never reaches
  EXPECT_GT(j["points"][0]["detect_fraction"].get<double>(), 0.05);
  EXPECT_EQ(j["points"][1]["detect_fraction"].get<double>(), 0.0);
}

TEST(Cli, PlumeStatsReportEachLineTheReleaseAndTheSpirals) {
  const Output o =
      cli("probe --plume-stats --trials 2 --surges 2 --offsets \"0;0.3\" --across 2 --threads 2 "
          "--set robot.start_offset_x=3 --set sim.warmup=5 --json");
  ASSERT_EQ(o.code, 0) << o.err;
  const json j = json::parse(o.out);
  EXPECT_EQ(j["trials"], 2);
  EXPECT_EQ(j["d_lost"], 0.614);
  ASSERT_EQ(j["along"].size(), 2u);
  EXPECT_EQ(j["along"][1]["offset"], 0.3);
  EXPECT_EQ(j["along"][0]["paths"], 2);
  // 0.3 m beside the axis the default plume never reaches
  EXPECT_EQ(j["along"][1]["detections"], 0);
  EXPECT_GT(j["along"][0]["detections"].get<long>(), 0);
  ASSERT_EQ(j["across"].size(), 1u);
  EXPECT_EQ(j["across"][0]["distance"], 2.0);
  EXPECT_EQ(j["release"]["trials"], 2);
  EXPECT_EQ(j["spirals"]["surges"], 4);
  const Output text =
      cli("probe --plume-stats --trials 1 --surges 1 --offsets 0 --across 2 "
          "--set robot.start_offset_x=3 --set sim.warmup=5");
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("released in odor"), std::string::npos) << text.out;
}

TEST(Cli, HumanOutputNamesTheOutcome) {
  const Output o = cli("run --algorithm surge-spiral --set supervisor.timeout=2");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("outcome   timeout"), std::string::npos) << o.out;
}

}  // namespace
}  // namespace plumetrace

namespace plumetrace {
namespace {

// a study folder of one small sweep: two algorithms, two runs each
std::string tiny_study(const std::string& extra = "") {
  const std::string dir = testing::temp_path("study", "");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/study.toml") << "name = \"tiny\"\ntitle = \"A tiny study\"\n"
                                        "sets = [\"a.toml\"]\n"
                                     << extra;
  std::ofstream(dir + "/a.toml") << "name = \"a\"\ntitle = \"algorithms\"\nruns = 2\nseed = 7\n"
                                    "[[axis]]\nkey = \"controller.algorithm\"\n"
                                    "values = [\"casting\", \"surge-cast\"]\n";
  return dir;
}

TEST(Study, RunsItsSweepsExportsThemAndResumes) {
  const std::string dir = tiny_study();
  const std::string out = dir + "/out";
  const Output first = cli("study " + dir + " --out " + out + " --quiet --threads 2");
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_NE(first.out.find("tiny: 4 runs (4 computed now"), std::string::npos) << first.out;
  const auto results = nlohmann::json::parse(testing::read_file(out + "/results.json"));
  ASSERT_EQ(results["sweeps"].size(), 1u);
  EXPECT_EQ(results["sweeps"][0]["points"].size(), 2u);
  const std::string runs = testing::read_file(out + "/runs.csv");
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 5);  // header and 4 runs
  // the same study again computes nothing and writes the same runs
  const Output again = cli("study " + dir + " --out " + out + " --quiet");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("(0 computed now"), std::string::npos) << again.out;
  EXPECT_EQ(testing::read_file(out + "/runs.csv"), runs);
}

TEST(Study, ABadStudyFileNamesTheFileAndTheKeyAndExitsTwo) {
  const std::string dir = tiny_study("colour = \"blue\"\n");
  const Output bad = cli("study " + dir + " --out " + dir + "/out --quiet");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find(dir + "/study.toml: unknown key 'colour'"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
  const Output missing = cli("study " + dir + "/nowhere --quiet");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("nowhere/study.toml"), std::string::npos) << missing.err;
}

TEST(Study, TheMeanderStudyRunsAndDrawsItsReport) {
  const std::string out = testing::temp_path("meander", "");
  const Output o = cli("study " + std::string(PLUMETRACE_SOURCE_DIR) +
                       "/studies/meander --runs 2 --out " + out + " --quiet");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("meander: 216 runs"), std::string::npos) << o.out;
  const std::string md = testing::read_file(out + "/report.md");
  EXPECT_EQ(md.rfind("# Beyond the paper: ", 0), 0u) << md.substr(0, 200);
  for (const char* sweep : {"M", "Mc", "Ms", "Mg"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/figures/meander_" + sweep + ".png")) << sweep;
  }
}

TEST(Study, TheMultirobotStudyRunsAndDrawsItsReport) {
  const std::string out = testing::temp_path("multirobot", "");
  const Output o = cli("study " + std::string(PLUMETRACE_SOURCE_DIR) +
                       "/studies/multirobot --runs 2 --out " + out + " --quiet");
  ASSERT_EQ(o.code, 0) << o.err;
  // 2 winds x 3 algorithms x 5 team sizes x contacts on and off, 2 runs each
  EXPECT_NE(o.out.find("multirobot: 120 runs"), std::string::npos) << o.out;
  const std::string md = testing::read_file(out + "/report.md");
  EXPECT_EQ(md.rfind("# Several robots on one plume: ", 0), 0u) << md.substr(0, 200);
  // a row per algorithm, contact setting and team size in each wind's table
  for (const char* alg : {"casting", "surge-spiral", "surge-cast"}) {
    for (const char* contact : {"on", "off"}) {
      for (int robots = 1; robots <= 5; ++robots) {
        const std::string row =
            "| " + std::string(alg) + " | " + contact + " | " + std::to_string(robots) + " | ";
        std::size_t rows = 0;
        for (auto at = md.find(row); at != std::string::npos; at = md.find(row, at + 1)) ++rows;
        EXPECT_EQ(rows, 2u) << row;
      }
    }
  }
  for (const char* sweep : {"L", "M"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/figures/multirobot_" + std::string(sweep) + ".png"))
        << sweep;
  }
}

#ifndef PLUMETRACE_WITH_ZIGZAG
// (once: the zigzag build's run would repeat it without a controller of its own in the study)
TEST(Study, TheBaselinesStudyRunsEveryAlgorithmAndDrawsItsReport) {
  const std::string out = testing::temp_path("baselines", "");
  const Output o = cli("study " + std::string(PLUMETRACE_SOURCE_DIR) +
                       "/studies/baselines --runs 1 --out " + out + " --quiet");
  ASSERT_EQ(o.code, 0) << o.err;
  // 3 winds x (9 algorithms + 2 biased walks + hayes' team with and without messages) x 2 starts
  EXPECT_NE(o.out.find("baselines: 78 runs"), std::string::npos) << o.out;
  const std::string md = testing::read_file(out + "/report.md");
  EXPECT_EQ(md.rfind("# Baselines of the field: ", 0), 0u) << md.substr(0, 200);
  // every algorithm built into the library has a row in each of the 6 tables (wind x start)
  for (const char* a :
       {"casting", "surge-spiral", "surge-cast", "infotaxis", "particle-filter", "chemotaxis",
        "crw", "levy", "hayes", "crw + upwind bias", "levy + upwind bias",
        "hayes, team of 3, messages", "hayes, team of 3, no messages"}) {
    const std::string row = "| " + std::string(a) + " | ";
    std::size_t rows = 0;
    for (auto at = md.find(row); at != std::string::npos; at = md.find(row, at + 1)) ++rows;
    EXPECT_EQ(rows, 6u) << row;
  }
  EXPECT_TRUE(std::filesystem::exists(out + "/figures/baselines_success.png"));
}
#endif

#ifdef PLUMETRACE_WITH_ZIGZAG
// this build runs the tests of this file against examples/zigzag, the command with one more
// controller: its keys are config keys like the built-ins'
TEST(Cli, TheCommandUnderTestHasZigzagAndItsKeys) {
  const Output config = cli("config --algorithm zigzag --set zigzag.leg=0.8");
  ASSERT_EQ(config.code, 0) << config.err;
  EXPECT_NE(config.out.find("algorithm = \"zigzag\""), std::string::npos) << config.out;
  EXPECT_NE(config.out.find("[zigzag]\nleg = 0.8  #"), std::string::npos) << config.out;
}
#endif

}  // namespace
}  // namespace plumetrace
