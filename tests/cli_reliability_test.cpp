// The plumetrace command on bad input and in a hostile environment (issue 13): every case ends
// with the documented exit code (0 ok, 2 bad input, 3 I/O failure or out of memory), a message
// naming the key, file or option, and nothing half-written; never an abort, a hang or a crash.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "plumetrace/core/simd.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

using nlohmann::json;
using Output = testing::CommandOutput;
using testing::read_file;

const std::string kCli = PLUMETRACE_CLI;

// runs the command with `args`, capturing stdout, stderr and the exit code
// (under `timeout`: a regression that hangs fails the test instead of the suite)
Output cli(const std::string& args) {
  return testing::run_command("timeout 120 " + kCli + " " + args);
}

// why: AddressSanitizer maps terabytes of shadow memory at start, so a process under an
// address-space limit (ulimit -v) cannot even start in a sanitized build
#if defined(__SANITIZE_ADDRESS__)
#define SKIP_UNDER_ADDRESS_LIMIT() \
  GTEST_SKIP() << "an address-space limit cannot be tested under AddressSanitizer"
#else
#define SKIP_UNDER_ADDRESS_LIMIT() static_cast<void>(0)
#endif

// runs the command under bash with `limits` (ulimit options) set first
Output cli_limited(const std::string& limits, const std::string& args) {
  return testing::run_command("bash -c 'ulimit " + limits + " && exec " + kCli + " " + args + "'");
}

// expects bad input: exit 2, nothing on stdout, and `names` in the message
void expect_refused(const Output& o, const std::string& names, const std::string& what) {
  EXPECT_EQ(o.code, 2) << what << "\n" << o.err;
  EXPECT_EQ(o.out, "") << what;
  EXPECT_NE(o.err.find(names), std::string::npos) << what << " said: " << o.err;
}

// PLUMETRACE_SIMD forces a version of the vector loops: a run in the meandering wind (the
// plume's and the wind's loops) prints the same bytes on every path this machine runs as on the
// default; a name it does not run is bad input, refused before any work (the trace file is not
// created)
TEST(CliReliability, EverySimdPathRunsTheSameAndOneTheMachineLacksIsRefusedFirst) {
  const std::string run = "run --algorithm surge-spiral --seed 4 --set wind.model=meander --json";
  const auto with = [](const std::string& simd, const std::string& args) {
    return testing::run_command("PLUMETRACE_SIMD='" + simd + "' timeout 120 " + kCli + " " + args);
  };
  const Output plain = cli(run);
  ASSERT_EQ(plain.code, 0) << plain.err;
  for (const simd::Path p : simd::available()) {
    const Output o = with(std::string(simd::name(p)), run);
    ASSERT_EQ(o.code, 0) << simd::name(p) << ": " << o.err;
    EXPECT_EQ(o.out, plain.out) << simd::name(p);
  }
  const std::string trace = testing::temp_path("simd", ".json");
  expect_refused(with("fast", run + " --trace " + trace),
                 "PLUMETRACE_SIMD: unknown path \"fast\" (one of auto, scalar", "unknown name");
  EXPECT_FALSE(std::filesystem::exists(trace));
#if defined(__x86_64__)
  if (simd::available(simd::Path::kAvx512)) {
    GTEST_SKIP() << "this machine runs the AVX-512 path: nothing to refuse";
  }
  expect_refused(with("avx512", run + " --trace " + trace), "PLUMETRACE_SIMD: \"avx512\": this ",
                 "a path the machine lacks");
  EXPECT_FALSE(std::filesystem::exists(trace));
#endif
}

// F3: any exception reaches main's catch-all; out of memory is exit 3, not an abort (134)
TEST(CliReliability, OutOfMemoryIsReportedWithExitThreeNotAnAbort) {
  SKIP_UNDER_ADDRESS_LIMIT();
  // a ring of 1e7 filaments reserves 400 MB: more than the 300 MB the process may map
  const Output o = cli_limited("-v 300000", "run --set plume.capacity=10000000 --json");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_EQ(o.out, "");
  EXPECT_NE(o.err.find("out of memory"), std::string::npos) << o.err;
}

// F3 with F2: out of memory in a sweep's worker thread reaches main's catch-all through the pool
TEST(CliReliability, OutOfMemoryInASweepWorkerIsExitThreeNotAnAbort) {
  SKIP_UNDER_ADDRESS_LIMIT();
  const std::string sweep =
      testing::write_temp("sweep", ".toml",
                          "name = \"oom\"\nruns = 1\n[set]\nplume.capacity = 10000000\n"
                          "[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
  const std::string store = testing::temp_path("oom", ".sqlite");
  const Output o = cli_limited("-v 300000", "sweep " + sweep + " --quiet --threads 1 --store " +
                                                store + " --out " + store + ".out");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_NE(o.err.find("out of memory"), std::string::npos) << o.err;
}

// a FIFO in place of a file: made fresh, so that nothing has written to it
std::string make_fifo(const std::string& suffix) {
  const std::string path = testing::temp_path("fifo", suffix);
  EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0) << path;
  return path;
}

// F8: a FIFO named as any input is refused at once instead of blocking for ever (`timeout` only
// keeps a regression from hanging the suite)
TEST(CliReliability, FifoInputsAreRefusedWithoutBlocking) {
  const std::string scenario = make_fifo(".toml");
  expect_refused(cli("config " + scenario), "'" + scenario + "': not a regular file", "config");

  const std::string sweep = make_fifo(".toml");
  expect_refused(cli("sweep " + sweep), "'" + sweep + "': not a regular file", "sweep");

  // a sweep file whose base scenario is a FIFO
  const std::string base = make_fifo(".toml");
  const std::string file =
      testing::write_temp("sweep", ".toml",
                          "name = \"fifo\"\nscenario = \"" + base +
                              "\"\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
  expect_refused(cli("export " + file + " --store none.sqlite --out none"),
                 "'" + base + "': not a regular file", "export");

  const std::string trace = make_fifo(".json");
  const Output view = cli("view " + trace);
  EXPECT_EQ(view.code, 3) << view.err;
  EXPECT_NE(view.err.find("'" + trace + "': not a regular file"), std::string::npos) << view.err;
}

// F5: keys nested without end are refused naming the file, before they reach the stack
TEST(CliReliability, DeeplyNestedKeysAreRefusedNamingTheFile) {
  // 30000 and 300000 dotted parts: a stack overflow in flatten, then in toml::parse
  for (const int parts : {30000, 300000}) {
    std::string key = "a";
    for (int i = 0; i < parts; ++i) key += ".b";
    const std::string scenario = testing::write_temp("deep", ".toml", key + " = 1\n");
    expect_refused(cli("config " + scenario), scenario + ":1: a key has more than 16 dotted parts",
                   "config");
    const std::string sweep = testing::write_temp(
        "deep", ".toml",
        "name = \"deep\"\n[set]\n" + key + " = 1\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
    expect_refused(cli("sweep " + sweep), sweep + ":3: a key has more than 16 dotted parts",
                   "sweep");
  }
  // quoted parts and a table header count as well
  std::string quoted = "[a";
  for (int i = 0; i < 20; ++i) quoted += ".\"b.c\"";
  const std::string header = testing::write_temp("header", ".toml", "x = 1.5\n" + quoted + "]\n");
  expect_refused(cli("config " + header), header + ":2: a key has more than 16 dotted parts",
                 "header");
  // inline tables nest too
  std::string inner = "1";
  for (int i = 0; i < 20; ++i) inner = "{ b = " + inner + " }";
  const std::string nested = testing::write_temp("inline", ".toml", "a = " + inner + "\n");
  expect_refused(cli("config " + nested), "is nested more than 16 levels deep", "inline");
}

// F9: the release rate has an upper bound, per second and per step, so that no run hangs and
// the count per step always converts to an integer
TEST(CliReliability, ReleaseRateIsBoundedPerSecondAndPerStep) {
  for (const char* rate : {"1e20", "6e20", "1000001"}) {
    expect_refused(cli(std::string("config --set plume.release_rate=") + rate),
                   "plume.release_rate: must be a number > 0 and <= 1e6", rate);
  }
  expect_refused(cli("config --set plume.release_rate=1e6 --set sim.dt=2"),
                 "plume.release_rate: must release at most 1e6 filaments per step of sim.dt (got "
                 "1e6 /s * 2 s = 2e6)",
                 "per step");
  EXPECT_EQ(cli("config --set plume.release_rate=1e6").code, 0);
}

// F23: a time step so small that a run takes more than 1e7 steps is refused, naming the count
TEST(CliReliability, TinyTimeStepsAreRefusedNamingTheStepCount) {
  // the reproduction: a two-hour run without a word
  expect_refused(cli("run --set sim.dt=1.3e-6"), "must be at most 1e7 steps of sim.dt", "issue");
  expect_refused(cli("run --set sim.dt=1.3e-6 --set sim.warmup=0"),
                 "supervisor.timeout: must be at most 1e7 steps of sim.dt (got 1200 s / 1.3e-6 s "
                 "= 9.23077e8 steps)",
                 "timeout");
  expect_refused(cli("run --set sim.dt=1e-6 --set supervisor.timeout=1"),
                 "sim.warmup: must be at most 1e7 steps of sim.dt (got 20 s / 1e-6 s = 2e7 steps)",
                 "warm-up");
  expect_refused(
      cli("probe --points 8,0,0 --set sim.dt=1e-6 --set sim.warmup=0 --set supervisor.timeout=1 "
          "--duration 11"),
      "--warmup, --duration: must be at most 1e7 steps", "probe");
}

// F3: a ring larger than any run needs is refused before it is allocated (exit 2, even under a
// 2 GB memory limit), rather than ending in std::bad_alloc
TEST(CliReliability, HugeRingIsRefusedBeforeItIsAllocated) {
  SKIP_UNDER_ADDRESS_LIMIT();
  const Output o = cli_limited("-v 2000000", "run --set plume.capacity=100000000 --json");
  expect_refused(o, "plume.capacity: must be an integer >= 1 and <= 10000000", "capacity");
}

// probe and trace intervals far beyond the run are what they say, not an integer conversion out
// of range (which sampled or snapshotted every step)
TEST(CliReliability, HugeIntervalsAreNotConvertedOutOfRange) {
  expect_refused(cli("probe --points 8,0,0 --duration 1 --interval 1e300"),
                 "--duration: must be at least --interval", "probe");
  const std::string trace = testing::temp_path("huge", ".json");
  const Output o = cli("run --set supervisor.timeout=1 --snapshot-interval 1e300 --trace " + trace);
  ASSERT_EQ(o.code, 0) << o.err;
  // only the snapshot at release
  EXPECT_EQ(json::parse(read_file(trace))["snapshots"].size(), 1u);
}

// a sweep file of `axes` axes of `values` values each (keys that accept any number)
std::string grid_sweep(int axes, int values, int runs) {
  const char* keys[] = {"arena.x_min",
                        "source.z",
                        "wind.vy",
                        "wind.vz",
                        "odor.height",
                        "surge_spiral.d_gap",
                        "surge_spiral.d_lost",
                        "surge_cast.d_cast",
                        "surge_cast.d_lost",
                        "casting.d_lost",
                        "robot.axle",
                        "robot.radius",
                        "plume.amount",
                        "odor.threshold",
                        "plume.initial_width",
                        "source.radius"};
  std::string text = "name = \"grid\"\nruns = " + std::to_string(runs) + "\n";
  for (int a = 0; a < axes; ++a) {
    text += "[[axis]]\nkey = \"" + std::string(keys[a]) + "\"\nvalues = [";
    for (int v = 0; v < values; ++v) text += (v ? ", " : "") + std::to_string(0.01 + 0.001 * v);
    text += "]\n";
  }
  return testing::write_temp("grid", ".toml", text);
}

// F10: the grid's size is checked, without overflow, before anything is expanded or written
TEST(CliReliability, GridsAboveTheLimitAreRefusedBeforeTheStoreIsTouched) {
  const std::string out = testing::temp_path("out", "");
  const std::string store = out + ".sqlite";
  // 16 axes of 16 values: 2^64 points, which overflowed to 0 (exit 0, empty exports)
  const std::string huge = grid_sweep(16, 16, 1);
  expect_refused(cli("sweep " + huge + " --out " + out + " --store " + store),
                 huge +
                     ": the grid has 16 x 16 x 16 x 16 x 16 x 16 x 16 x 16 x 16 x 16 x 16 x "
                     "16 x 16 x 16 x 16 x 16 = 1.84e+19 points, more than the 100000",
                 "16 axes");
  // just above the limit: refused as fast (nothing expanded)
  const std::string above = grid_sweep(5, 11, 1);
  expect_refused(cli("sweep " + above + " --out " + out + " --store " + store),
                 "= 1.61e+05 points, more than the 100000 a sweep may have", "161051 points");
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(store));
  expect_refused(cli("export " + huge + " --store " + store + " --out " + out), "1.84e+19 points",
                 "export");
}

// F3: more runs than the limit are refused before the store is touched (1e8 runs took 7 GB,
// aborted and left runs:NAME = 100000001 in the store)
TEST(CliReliability, CampaignsAboveTheRunLimitAreRefusedLeavingTheStoreAsItWas) {
  const std::string out = testing::temp_path("out", "");
  const std::string store = out + ".sqlite";
  const std::string small = grid_sweep(1, 1, 1);
  const std::string args =
      " --out " + out + " --store " + store + " --set supervisor.timeout=1 --quiet";
  ASSERT_EQ(cli("sweep " + small + args).code, 0);
  const std::string before = read_file(store);

  const std::string many = grid_sweep(1, 2, 10000000);
  expect_refused(cli("sweep " + many + args),
                 many + ": 2 points x 10000000 runs = 20000000 runs, more than the 10000000",
                 "file");
  const std::string too_many = grid_sweep(1, 1, 10000001);
  expect_refused(cli("sweep " + too_many + args),
                 too_many + ": runs: must be an integer >= 1 and <= 10000000 (got 10000001)",
                 "runs");
  EXPECT_EQ(read_file(store), before);
}

// the rows of a CSV text as RFC 4180 reads them: quoted fields may hold commas, doubled quotes
// and line breaks
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1, std::vector<std::string>(1));
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    std::string& field = rows.back().back();
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().emplace_back();
    } else if (c == '\n') {
      rows.emplace_back(1);
    } else {
      field += c;
    }
  }
  if (rows.back().size() == 1 && rows.back().front().empty()) rows.pop_back();
  return rows;
}

// F11: text fields are quoted as RFC 4180 says, so a name with commas and quotes reads back as
// one field in every CSV export (a line break in a name is refused since issue 22, G14:
// CliTrust.ControlCharactersInNamesAreRefused)
TEST(CliReliability, CsvExportsQuoteTextFields) {
  const std::string name = "a,\"b\" c";
  const std::string sweep = testing::write_temp(
      "named", ".toml",
      "name = \"a,\\\"b\\\" c\"\nruns = 2\n[set]\nsupervisor.timeout = 1.0\n"
      "[[axis]]\nkey = \"controller.algorithm\"\nvalues = [\"casting\", \"surge-cast\"]\n");
  const std::string out = testing::temp_path("out", "");
  const Output o = cli("sweep " + sweep + " --out " + out + " --quiet");
  ASSERT_EQ(o.code, 0) << o.err;
  for (const std::string file : {"runs.csv", "summary.csv"}) {
    const auto rows = parse_csv(read_file(out + "/" + file));
    ASSERT_EQ(rows.size(), file == "runs.csv" ? 5u : 3u) << file;
    for (std::size_t r = 1; r < rows.size(); ++r) {
      EXPECT_EQ(rows[r].size(), rows[0].size()) << file << " row " << r;
      EXPECT_EQ(rows[r][0], name) << file << " row " << r;
    }
    EXPECT_EQ(rows[1][2], "casting") << file;
  }
}

// F12: a sweep name that is not a plain folder name is refused where it would be a path part
// (no --out), and nothing is written anywhere
TEST(CliReliability, SweepNamesThatLeaveOutAreRefusedAsFolderNames) {
  const std::string dir = testing::temp_path("cwd", "");
  std::filesystem::create_directories(dir);
  for (const std::string name : {"../../etc/evil", "..", "/abs", ".hidden", "a\\nb", ""}) {
    std::string escaped;
    for (const char c : name) escaped += c == '\\' ? std::string("\\\\") : std::string(1, c);
    const std::string sweep = testing::write_temp(
        "evil", ".toml",
        "name = \"" + escaped + "\"\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
    const Output o = testing::run_command("cd " + dir + " && timeout 120 " + kCli + " sweep " +
                                          sweep + " --set supervisor.timeout=1 --quiet");
    expect_refused(o, name.empty() ? "missing name" : sweep + ": name: '" + name + "'", name);
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  // with --out the name is only a name
  const std::string sweep = testing::write_temp(
      "evil", ".toml", "name = \"../../etc/evil\"\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
  const std::string out = testing::temp_path("out", "");
  EXPECT_EQ(cli("sweep " + sweep + " --out " + out + " --set supervisor.timeout=1 --quiet").code,
            0);
  EXPECT_TRUE(std::filesystem::exists(out + "/runs.csv"));
}

// F17: a CSV trace and its filaments are one pair: on a full disk (here a 100 KB file-size
// limit, with SIGXFSZ ignored so that writes fail as on a full disk) neither is put in place, the
// previous pair is kept whole, nothing is left behind, and the exit code is 3
TEST(CliReliability, CsvTraceAndFilamentsAreWrittenAsOnePair) {
  const std::string dir = testing::temp_path("trace", "");
  std::filesystem::create_directories(dir);
  const std::string trace = dir + "/t.csv", filaments = dir + "/t.filaments.csv";
  std::ofstream(trace) << "old steps\n";
  std::ofstream(filaments) << "old filaments\n";
  const std::string args = "run --set supervisor.timeout=5 --snapshot-interval 1 --trace " + trace;
  const Output o = testing::run_command("bash -c \"trap '' XFSZ && ulimit -f 100 && exec " + kCli +
                                        " " + args + "\"");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_NE(o.err.find(filaments), std::string::npos) << o.err;
  EXPECT_EQ(read_file(trace), "old steps\n");
  EXPECT_EQ(read_file(filaments), "old filaments\n");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 2u) << "a .part file was left behind";
  // with room, all three are written
  ASSERT_EQ(cli(args).code, 0);
  EXPECT_EQ(read_file(trace).rfind("agent,time,x,y", 0), 0u);
  EXPECT_EQ(read_file(filaments).rfind("time,x,y,z,w", 0), 0u);
  EXPECT_EQ(read_file(dir + "/t.controller.csv"), "time,agent,layer,x,y,value\n");
}

// F18, F22: nan, inf, empty texts and out-of-range counts are refused naming the option, with a
// message that states the range readably (CLI11's printed DBL_MAX with 300 digits)
TEST(CliReliability, BadOptionValuesAreRefusedNamingTheOptionReadably) {
  const std::string sweep = grid_sweep(1, 1, 1);
  struct Case {
    std::string args, names;
  };
  const Case cases[] = {
      {"run --snapshot-interval nan",
       "--snapshot-interval: must be a finite number >= 0 (got 'nan')"},
      {"run --snapshot-interval -1",
       "--snapshot-interval: must be a finite number >= 0 (got '-1')"},
      {"probe --points 8,0,0 --warmup nan", "--warmup: must be a finite number >= 0 (got 'nan')"},
      {"probe --points 8,0,0 --duration inf", "--duration: must be a finite number > 0"},
      {"probe --points 8,0,0 --interval 0", "--interval: must be a finite number > 0 (got '0')"},
      {"run --algorithm ''", "--algorithm: must not be empty"},
      {"config --algorithm ''", "--algorithm: must not be empty"},
      {"run --trace ''", "--trace: must not be empty"},
      {"run --view ''", "--view: must not be empty"},
      {"run ''", "scenario: must not be empty"},
      {"view run.json --at nan", "--at: must be a finite number >= 0 (got 'nan')"},
      {"view run.json -o ''", "--output: must not be empty"},
      {"view run.json --max-frames 0", "--max-frames: must be a whole number from 1 to 2147483647"},
      {"sweep " + sweep + " --runs 100000001",
       "--runs: must be a whole number from 1 to 10000000 (got '100000001')"},
      {"sweep " + sweep + " --runs 0", "--runs: must be a whole number from 1 to 10000000"},
      {"sweep " + sweep + " --out ''", "--out: must not be empty"},
      {"sweep " + sweep + " --store ''", "--store: must not be empty"},
      {"export " + sweep + " --store x.sqlite --out ''", "--out: must not be empty"},
      {"merge '' --store x.sqlite", "parts: must not be empty"},
      {"reproduce --runs 0", "--runs: must be a whole number from 1 to 10000000"},
      {"reproduce --presets ''", "--presets: must not be empty"},
      {"sensitivity --out ''", "--out: must not be empty"},
  };
  for (const auto& c : cases) {
    const Output o = cli(c.args);
    expect_refused(o, c.names, c.args);
    EXPECT_EQ(o.err.find("1797693134862315"), std::string::npos) << c.args << ": " << o.err;
  }
}

// F18: whole numbers in a trace that do not fit their field are refused naming the file and the
// field, instead of wrapping (get<int>) or truncating
TEST(CliReliability, TraceIntegersOutOfRangeAreRefusedNamingTheField) {
  const std::string trace = testing::temp_path("run", ".json");
  ASSERT_EQ(cli("run --set supervisor.timeout=1 --trace " + trace).code, 0);
  const json good = json::parse(read_file(trace));
  struct Case {
    std::string pointer;
    json value;
    std::string names;
  };
  const Case cases[] = {
      {"/result/losses", 1LL << 40, "result.losses must be a whole number from 0 to 2147483647"},
      {"/result/losses", -1, "result.losses"},
      {"/result/losses", 1.5, "result.losses"},
      {"/result/seed", -1, "result.seed must be a whole number from 0 to 18446744073709551615"},
      {"/result/trial", 0.5, "result.trial"},
      {"/result/steps", -3, "result.steps"},
      {"/result/wind_samples", "12", "result.wind_samples"},
      {"/steps/wind_samples/1", 10000000000LL, "steps.wind_samples[1]"},
  };
  for (const auto& c : cases) {
    json bad = good;
    bad[json::json_pointer(c.pointer)] = c.value;
    const std::string path = testing::write_temp("bad", ".json", bad.dump());
    const Output o = cli("view " + path + " -o " + testing::temp_path("bad", ".html"));
    expect_refused(o, "trace '" + path + "': " + c.names, c.pointer + " = " + c.value.dump());
  }
  // the file as written reads back
  EXPECT_EQ(cli("view " + trace + " -o " + testing::temp_path("good", ".html")).code, 0);
}

// F22: results.json records a sweep file's path normalised and relative to the folder the
// command ran in when it lies inside it, however it was typed: never an absolute path of this
// machine for a file typed relative
TEST(CliReliability, ResultsRecordTheSweepPathNormalisedAndRelative) {
  const std::string dir = testing::temp_path("cwd", "");
  std::filesystem::create_directories(dir + "/sub");
  std::ofstream(dir + "/sub/s.toml") << "name = \"s\"\nruns = 1\n[set]\nsupervisor.timeout = 1.0\n"
                                        "[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n";
  for (const std::string& typed :
       std::vector<std::string>{"sub/s.toml", "./sub/../sub/s.toml", dir + "/sub/s.toml"}) {
    const Output o =
        testing::run_command("cd " + dir + " && " + kCli + " sweep " + typed + " --out o --quiet");
    ASSERT_EQ(o.code, 0) << typed << ": " << o.err;
    const json results = json::parse(read_file(dir + "/o/results.json"));
    EXPECT_EQ(results["sweeps"][0]["file"], "sub/s.toml") << typed;
  }
}

}  // namespace
}  // namespace plumetrace
