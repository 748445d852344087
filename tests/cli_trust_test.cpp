// The plumetrace command against the findings of issue 22's fault campaign (G1-G20), and what a
// user expects of a tool they cite: each test is named after the guarantee it holds and was
// checked to fail against the command before the fix (docs/reliability.md, "The findings
// G1-G20").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Output = testing::CommandOutput;
using testing::read_file;

const std::string kCli = PLUMETRACE_CLI;
const std::string kTwoPlumes = PLUMETRACE_SOURCE_DIR "/tests/support/two_plumes.toml";

Output cli(const std::string& args) {
  return testing::run_command("timeout 300 " + kCli + " " + args);
}

// the command run in `dir`
Output cli_in(const std::string& dir, const std::string& args) {
  return testing::run_command("cd '" + dir + "' && timeout 300 " + kCli + " " + args);
}

// a new empty folder
std::string temp_dir(const std::string& stem) {
  const std::string dir = testing::temp_path(stem, "");
  fs::create_directories(dir);
  return dir;
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// expects bad input: exit 2, nothing on stdout, and `names` in the message
void expect_refused(const Output& o, const std::string& names, const std::string& what) {
  EXPECT_EQ(o.code, 2) << what << "\n" << o.err;
  EXPECT_EQ(o.out, "") << what;
  EXPECT_NE(o.err.find(names), std::string::npos) << what << " said: " << o.err;
}

// a study folder holding the two-plume sweep as k.toml and `study` as its study.toml
std::string study_folder(const std::string& study) {
  const std::string dir = temp_dir("study");
  fs::copy_file(kTwoPlumes, dir + "/k.toml");
  write(dir + "/study.toml", study);
  return dir;
}

// G1: combinations of the meander's keys, each inside its range, that made the wind NaN (exit 1,
// "internal error") are refused before any run, naming the keys
TEST(CliTrust, MeanderKeysBeyondTheStabilityBoundAreRefusedBeforeAnyRun) {
  const std::string keys =
      " --set wind.model=meander --set meander.gain=10 --set meander.bandwidth=100"
      " --set meander.damping=10";
  expect_refused(cli("run --json" + keys), "meander.gain, meander.damping", "run");
  const std::string store = testing::temp_path("g1", ".sqlite");
  expect_refused(cli("sweep " + kTwoPlumes + keys + " --store " + store + " --out " + store + ".o"),
                 "meander.bandwidth", "sweep");
  EXPECT_FALSE(fs::exists(store)) << "a refused sweep created its store";
}

// G2: merge removes only a store it created; any other file given as --store is kept as it was
TEST(CliTrust, MergeRemovesOnlyAStoreItCreated) {
  const std::string dir = temp_dir("g2");
  ASSERT_EQ(
      cli_in(dir, "sweep " + kTwoPlumes + " --runs 1 --shard 1/2 --store part1.sqlite --quiet")
          .code,
      0);
  for (const std::string& text : {std::string("x"), std::string("my notes\n"), std::string()}) {
    write(dir + "/notes.txt", text);
    const Output o = cli_in(dir, "merge part1.sqlite --store notes.txt");
    if (text.empty()) {
      // an empty file is a new store (a merge killed before its first commit, F16)
      EXPECT_EQ(o.code, 0) << o.err;
      continue;
    }
    EXPECT_EQ(o.code, 2) << o.err;
    ASSERT_TRUE(fs::exists(dir + "/notes.txt")) << "merge deleted '" << text << "'";
    EXPECT_EQ(read_file(dir + "/notes.txt"), text);
  }
  // a target the merge created is removed when the merge fails (a part of another definition)
  const std::string other = testing::write_temp(
      "other", ".toml", "name = \"two\"\nruns = 1\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
  ASSERT_EQ(cli_in(dir, "sweep " + other +
                            " --set supervisor.timeout=1 --store other.sqlite "
                            "--out o --quiet")
                .code,
            0);
  EXPECT_EQ(cli_in(dir, "merge part1.sqlite other.sqlite --store new.sqlite").code, 2);
  EXPECT_FALSE(fs::exists(dir + "/new.sqlite"));
}

// G3: a study's name becomes out/NAME only when it is a plain folder name; anything else is
// refused naming study.toml and `name`, and nothing is written
TEST(CliTrust, StudyNamesThatLeaveOutAreRefusedAsFolderNames) {
  for (const std::string name : {"../../escaped", "a/b", ".", "/abs", "a\\nb", ".."}) {
    const std::string dir = study_folder("name = \"" + name + "\"\nsets = [\"k.toml\"]\n");
    const std::string cwd = temp_dir("cwd");
    const Output o = cli_in(cwd, "study " + dir + " --runs 1 --quiet");
    EXPECT_EQ(o.code, 2) << name << ": " << o.err;
    EXPECT_NE(o.err.find(dir + "/study.toml: name"), std::string::npos) << o.err;
    EXPECT_TRUE(fs::is_empty(cwd)) << name;
    EXPECT_FALSE(fs::exists(fs::path(cwd).parent_path().parent_path() / "escaped"));
  }
}

// G4: a study's report runs only code of the plumetrace package or a .py file of the study's
// own folder, with the current folder off the module path
TEST(CliTrust, StudyReportsRunOnlyTheProjectsOrTheStudysOwnCode) {
  const std::string cwd = temp_dir("cwd");
  write(cwd + "/evilmod.py", "open('EVIL', 'w').write('ran')\n");
  fs::create_directories(cwd + "/plumetrace");
  write(cwd + "/plumetrace/__init__.py", "open('EVIL', 'w').write('ran')\n");
  write(cwd + "/plumetrace/evilmod.py", "open('EVIL', 'w').write('ran')\n");
  for (const std::string report : {"this", "evilmod", "os.path", "../evilmod.py", "/tmp/x.py"}) {
    const std::string dir =
        study_folder("name = \"s\"\nsets = [\"k.toml\"]\nreport = \"" + report + "\"\n");
    expect_refused(cli_in(cwd, "study " + dir + " --runs 1 --out o --quiet"),
                   dir + "/study.toml: report: '" + report + "'", report);
  }
  // a module name of the package's form is looked for in the package only, never here
  const std::string dir =
      study_folder("name = \"s\"\nsets = [\"k.toml\"]\nreport = \"plumetrace.evilmod\"\n");
  const Output o = cli_in(cwd, "study " + dir + " --runs 1 --out o --quiet");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_FALSE(fs::exists(cwd + "/EVIL")) << "a module of the current folder ran";
  // the study's own script runs
  const std::string own =
      study_folder("name = \"s\"\nsets = [\"k.toml\"]\nreport = \"report.py\"\n");
  write(own + "/report.py", "import sys\nopen(sys.argv[1] + '/report.html', 'w').write('ok')\n");
  const Output ran = cli_in(cwd, "study " + own + " --runs 1 --out o2 --quiet");
  EXPECT_EQ(ran.code, 0) << ran.err;
  EXPECT_EQ(read_file(cwd + "/o2/report.html"), "ok");
  EXPECT_FALSE(fs::exists(cwd + "/EVIL"));
}

// a trace of a short run, as JSON
json short_trace() {
  const std::string trace = testing::temp_path("run", ".json");
  EXPECT_EQ(cli("run --set supervisor.timeout=2 --snapshot-interval 1 --trace " + trace).code, 0);
  return json::parse(read_file(trace));
}

// G8: a trace's state names are bounded where it is read (a 1 MB name made a 5.8 MB trace take
// 4.8 GB to view), and out of memory is explained in the words of the command that ran out
TEST(CliTrust, TraceStateNamesAreBoundedWhereTracesAreRead) {
  json trace = short_trace();
  trace["steps"]["state_names"][0] = std::string(1 << 20, 's');
  const std::string path = testing::write_temp("big-state", ".json", trace.dump());
  expect_refused(cli("view " + path + " -o " + path + ".html"),
                 "steps.state_names[0]: a controller's state name must have at most 64 bytes",
                 "view");
  trace["steps"]["state_names"][0] = "a\x1b[31m";
  const std::string escape = testing::write_temp("escape-state", ".json", trace.dump());
  expect_refused(cli("view " + escape + " -o " + escape + ".html"), "control character", "view");
}

TEST(CliTrust, OutOfMemoryAdviceFitsTheCommand) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "an address-space limit cannot be tested under AddressSanitizer";
#endif
  const auto limited = [](const std::string& args) {
    return testing::run_command("bash -c 'ulimit -v 300000 && exec " + kCli + " " + args + "'");
  };
  const Output run = limited("run --set plume.capacity=10000000 --json");
  EXPECT_EQ(run.code, 3) << run.err;
  EXPECT_NE(run.err.find("plume.capacity"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("--threads"), std::string::npos) << "run has no --threads: " << run.err;
}

// G10: a campaign that names one sweep twice (one file twice, or two files of one sweep name)
// is refused naming both files, before anything is run or written
TEST(CliTrust, ACampaignNamingASweepTwiceIsRefusedNamingBothFiles) {
  const std::string dir = study_folder("name = \"s\"\nsets = [\"k.toml\", \"./k.toml\"]\n");
  expect_refused(cli("study " + dir + " --runs 1 --out " + dir + "/o --quiet"),
                 "sweep file '" + dir + "/k.toml' is given twice", "study");
  EXPECT_FALSE(fs::exists(dir + "/o"));
  fs::copy_file(kTwoPlumes, dir + "/b.toml");
  const std::string store = dir + "/s.sqlite";
  ASSERT_EQ(
      cli("sweep " + kTwoPlumes + " --runs 1 --store " + store + " --out " + dir + "/o1 --quiet")
          .code,
      0);
  for (const std::string command : {"export", "report"}) {
    expect_refused(cli(command + " " + dir + "/k.toml " + dir + "/b.toml --store " + store +
                       " --out " + dir + "/o2"),
                   "'" + dir + "/k.toml' and '" + dir + "/b.toml' both name their sweep 'two'",
                   command);
  }
}

// G13: an empty name in --presets is a typo, refused, not a reading dropped
TEST(CliTrust, EmptyPresetNamesAreRefused) {
  for (const std::string presets : {"printed,,plugin", "printed,", ",printed", ""}) {
    expect_refused(cli("reproduce --runs 1 --out " + testing::temp_path("rp", "") + " --presets '" +
                       presets + "'"),
                   "--presets", presets);
  }
}

// G14: control characters in a sweep's or study's name, title or axis label never reach a
// terminal or a file: they are refused naming the file and the key
TEST(CliTrust, ControlCharactersInNamesAreRefused) {
  const std::string axis = "[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n";
  for (const std::string bad : {"\\u001b[31mred", "a\\u0000b", "tab\\there", "c1\\u009b"}) {
    for (const std::string& text :
         {"name = \"" + bad + "\"\n" + axis, "name = \"ok\"\ntitle = \"" + bad + "\"\n" + axis,
          "name = \"ok\"\n[[axis]]\nkey = \"sim.dt\"\nlabel = \"" + bad +
              "\"\nvalues = [0.032]\n"}) {
      const std::string sweep = testing::write_temp("ctl", ".toml", text);
      const Output o = cli("sweep " + sweep + " --out " + sweep + ".o --quiet");
      expect_refused(o, "holds a control character", text);
      EXPECT_FALSE(fs::exists(sweep + ".o")) << text;
    }
    const std::string dir = study_folder("name = \"" + bad + "\"\nsets = [\"k.toml\"]\n");
    expect_refused(cli("study " + dir + " --out " + dir + "/o --quiet"),
                   "study.toml: name: holds a control character", bad);
  }
}

// G15: a value with spaces around it is refused whatever the key expects, "auto" as a number
TEST(CliTrust, SpacesAroundAutoAreRefusedLikeANumber) {
  for (const std::string value : {"auto ", " auto", "1 ", "\"auto \""}) {
    expect_refused(cli("run --json --set 'sim.warmup=" + value + "'"), "sim.warmup", value);
    expect_refused(cli("run --json --set 'plume.capacity=" + value + "'"), "plume.capacity", value);
  }
}

// G17: a trace whose codes decode to infinity (or whose numbers overflow) is refused naming the
// field, instead of drawing coordinates of infinity
TEST(CliTrust, TraceNumbersThatDecodeToInfinityAreRefusedNamingTheField) {
  const json good = short_trace();
  json bad = good;
  bad["snapshot_encoding"]["x"]["unit"] = 1e308;
  const std::string unit = testing::write_temp("unit", ".json", bad.dump());
  expect_refused(cli("view " + unit + " -o " + unit + ".svg"), "snapshot_encoding.x", "unit");
  // a number beyond a double's range
  std::string text = good.dump();
  const std::string x = "\"x\":[" + good["steps"]["x"][0].dump();
  ASSERT_NE(text.find(x), std::string::npos);
  text.replace(text.find(x), x.size(), "\"x\":[1e400");
  const std::string huge = testing::write_temp("huge", ".json", text);
  expect_refused(cli("view " + huge + " -o " + huge + ".html"), "number overflow parsing '1e400'",
                 "1e400");
}

// G18 and the sensor's height: a scenario that asks for hours of work, or whose sensor sits
// where the plume never reaches, is warned about, naming the keys, before anything runs
TEST(CliTrust, ScenariosOfLargeWorkOrASensorOutsideThePlumeAreWarnedAbout) {
  const Output work = cli("config --set plume.release_rate=1e5");
  EXPECT_EQ(work.code, 0) << work.err;
  EXPECT_NE(work.err.find("warning: a run may take up to 6.1e+10 filament-steps (plume.capacity "
                          "= 1600000 filaments"),
            std::string::npos)
      << work.err;
  const Output high = cli("config --set odor.height=0.3");
  EXPECT_NE(high.err.find("odor sensor is 0.3 m above the source's centre (odor.height"),
            std::string::npos)
      << high.err;
  // the paper's setups say nothing
  for (const char* scenario :
       {"lochmatter2008", "paper-literal", "meander-weak", "meander-strong"}) {
    const Output o =
        cli(std::string("config ") + PLUMETRACE_SOURCE_DIR "/scenarios/" + scenario + ".toml");
    EXPECT_EQ(o.err, "") << scenario;
  }
}

// G19: commands writing the same exports at once (two sweeps on one store and one --out, or
// exports of one store into one folder) all finish with the same files: every writer has a
// temporary name of its own (before, 18 of 30 such exports exited 3 "cannot write")
TEST(CliTrust, WritersOfOneOutputFolderAtOnceAllFinishWithTheSameFiles) {
  const std::string clean = temp_dir("clean");
  ASSERT_EQ(cli("sweep " + kTwoPlumes + " --runs 30 --out " + clean + " --quiet").code, 0);
  const auto same_files = [&](const std::string& out) {
    for (const char* file : {"runs.csv", "summary.csv", "results.json"}) {
      EXPECT_EQ(read_file(out + "/" + file), read_file(clean + "/" + file)) << file;
    }
    for (const auto& entry : fs::directory_iterator(out)) {
      EXPECT_NE(entry.path().extension(), ".part") << "left behind: " << entry.path();
    }
  };
  // a command line run `count` times at once; the exit codes, in order
  const auto at_once = [](const std::string& command, int count) {
    std::string script = "bash -c 'pids=(); for k in $(seq " + std::to_string(count) + "); do " +
                         command +
                         " >/dev/null & pids+=($!); done; for p in ${pids[@]}; do wait $p; " +
                         "printf \"%s \" $?; done'";
    return testing::run_command(script).out;
  };
  const std::string dir = temp_dir("both");
  const std::string sweep = "timeout 300 " + kCli + " sweep " + kTwoPlumes +
                            " --runs 30 --quiet --store " + dir + "/s.sqlite --out " + dir + "/o";
  EXPECT_EQ(at_once(sweep, 2), "0 0 ");
  same_files(dir + "/o");
  for (int round = 0; round < 4; ++round) {
    const std::string out = dir + "/shared" + std::to_string(round);
    const std::string exports = "timeout 300 " + kCli + " export " + kTwoPlumes +
                                " --runs 30 --store " + dir + "/s.sqlite --out " + out;
    EXPECT_EQ(at_once(exports, 6), "0 0 0 0 0 0 ") << "round " << round;
    same_files(out);
  }
}

// G20: the command line reproduce's report records is quoted for a POSIX shell
TEST(CliTrust, ReproducesCommandLineIsRecordedShellQuoted) {
  const std::string dir = temp_dir("g20");
  const Output o = cli_in(dir, "reproduce --runs 1 --presets none --quiet --out \"rp odd 'q' ü\"");
  ASSERT_EQ(o.code, 0) << o.err;
  const json summary = json::parse(read_file(dir + "/rp odd 'q' ü/summary.json"));
  const std::string command = summary["generated_by"].get<std::string>();
  EXPECT_EQ(command,
            "plumetrace reproduce --runs 1 --presets none --quiet --out 'rp odd '\\''q'\\'' ü'");
  // the shell reads it back as the words given
  const Output words = testing::run_command("bash -c 'for w; do printf \"%s|\" \"$w\"; done' _ " +
                                            command.substr(std::string("plumetrace ").size()));
  EXPECT_EQ(words.out, "reproduce|--runs|1|--presets|none|--quiet|--out|rp odd 'q' ü|");
}

// the overhead d_t/d_u is at least 1: no interval the command prints or exports reaches below,
// whatever the number of runs (1, 2 and 5 runs per point here)
TEST(CliTrust, NoPrintedOverheadBoundIsBelowOne) {
  const std::regex interval(R"((\d+\.\d+) \[(-?\d+\.\d+), (-?\d+\.\d+)\]\s*$)");
  int bounds = 0;
  for (const int runs : {1, 2, 5}) {
    const std::string out = testing::temp_path("oh", "");
    const Output o =
        cli("sweep " + kTwoPlumes + " --runs " + std::to_string(runs) + " --out " + out);
    ASSERT_EQ(o.code, 0) << o.err;
    std::istringstream lines(o.out);
    for (std::string line; std::getline(lines, line);) {
      std::smatch m;
      if (!std::regex_search(line, m, interval)) continue;
      EXPECT_GE(std::stod(m[2]), 1.0) << line;
      EXPECT_LE(std::stod(m[2]), std::stod(m[1])) << line;
      EXPECT_GE(std::stod(m[3]), std::stod(m[1])) << line;
      ++bounds;
    }
    std::istringstream csv(read_file(out + "/summary.csv"));
    std::string header;
    std::getline(csv, header);
    for (std::string row; std::getline(csv, row);) {
      std::vector<std::string> cells;
      std::stringstream split(row);
      for (std::string cell; std::getline(split, cell, ',');) cells.push_back(cell);
      // overhead_lo and overhead_hi are columns 15 and 16 (two axes before the statistics)
      ASSERT_GE(cells.size(), 17u) << row;
      for (const std::size_t c : {15u, 16u}) {
        if (!cells[c].empty()) {
          EXPECT_GE(std::stod(cells[c]), 1.0) << header << "\n" << row;
        }
      }
    }
  }
  EXPECT_GT(bounds, 0) << "no interval printed";
}

// sweep's table lines up (each column starts where its header does), and --quiet prints none
TEST(CliTrust, TheSummaryTableLinesUpAndQuietPrintsNone) {
  const std::string out = testing::temp_path("table", "");
  const Output o = cli("sweep " + kTwoPlumes + " --runs 2 --out " + out);
  ASSERT_EQ(o.code, 0) << o.err;
  std::istringstream lines(o.out);
  std::string header;
  std::getline(lines, header);
  std::vector<std::size_t> starts;
  for (const char* column : {"point", "success", "overhead"}) {
    starts.push_back(header.find(column));
    ASSERT_NE(starts.back(), std::string::npos) << header;
  }
  int rows = 0;
  for (std::string line; std::getline(lines, line) && line.rfind("two ", 0) == 0; ++rows) {
    for (const std::size_t at : starts) {
      EXPECT_EQ(line[at - 1], ' ') << line;
      EXPECT_NE(line[at], ' ') << line;
    }
  }
  EXPECT_EQ(rows, 4);
  const Output quiet = cli("sweep " + kTwoPlumes + " --runs 2 --quiet --out " + out);
  ASSERT_EQ(quiet.code, 0);
  EXPECT_EQ(quiet.out.find("success"), std::string::npos) << quiet.out;
  EXPECT_NE(quiet.out.find("8 runs (0 computed now, 8 from the store)"), std::string::npos)
      << quiet.out;
}

// the store remembers the --set its sweep ran with: export and report of it need not repeat them
TEST(CliTrust, ExportAndReportUseTheSetTheStoreRecorded) {
  const std::string dir = temp_dir("sets");
  const std::string set = " --set wind_sensor.sigma_a=0.3";
  ASSERT_EQ(
      cli_in(dir, "sweep " + kTwoPlumes + " --runs 2 --store s.sqlite --out o --quiet" + set).code,
      0);
  const Output o = cli_in(dir, "export " + kTwoPlumes + " --store s.sqlite --out e --runs 2");
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("using the --set the store recorded: --set wind_sensor.sigma_a=0.3"),
            std::string::npos)
      << o.err;
  EXPECT_EQ(read_file(dir + "/e/summary.csv"), read_file(dir + "/o/summary.csv"));
  // merged shards keep it
  for (const char* shard : {"1/2", "2/2"}) {
    ASSERT_EQ(cli_in(dir, "sweep " + kTwoPlumes + " --runs 2 --shard " + shard + " --store p" +
                              std::string(1, shard[0]) + ".sqlite --quiet" + set)
                  .code,
              0);
  }
  ASSERT_EQ(cli_in(dir, "merge p1.sqlite p2.sqlite --store m.sqlite").code, 0);
  EXPECT_EQ(cli_in(dir, "export " + kTwoPlumes + " --store m.sqlite --out m --runs 2").code, 0);
  EXPECT_EQ(read_file(dir + "/m/summary.csv"), read_file(dir + "/o/summary.csv"));
  // a --set given is used as given: another one names another definition
  EXPECT_EQ(cli_in(dir, "export " + kTwoPlumes +
                            " --store s.sqlite --out x --runs 2 --set wind_sensor.sigma_a=0.1")
                .code,
            2);
}

// one input-file contract for every file the command reads: regular, bounded, opened without
// blocking; and one output-folder check for every folder it writes into
TEST(CliTrust, InputsAboveTheSizeBoundAndUnusableOutputFoldersAreRefused) {
  const std::string big = testing::temp_path("big", ".toml");
  {
    std::ofstream out(big);
    const std::string line(1023, '#');
    for (int i = 0; i < 17 * 1024; ++i) out << line << '\n';
  }
  expect_refused(cli("config " + big), "larger than 16777216 bytes", "17 MB scenario");
  const std::string file = testing::write_temp("file", ".txt", "x");
  expect_refused(cli("sweep " + kTwoPlumes + " --runs 1 --quiet --out " + file),
                 "--out: '" + file + "' is a file, not a folder", "--out a file");
  const Output proc = cli("sweep " + kTwoPlumes + " --runs 1 --quiet --out /proc/plumetrace-out");
  EXPECT_EQ(proc.code, 3) << proc.err;
  EXPECT_NE(proc.err.find("/proc/plumetrace-out"), std::string::npos) << proc.err;
}

}  // namespace
}  // namespace plumetrace
