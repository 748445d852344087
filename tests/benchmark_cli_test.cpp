// `plumetrace benchmark` as a process: it runs a suite into a resumable store, gives the same
// exports whatever the threads or shards, and refuses bad input naming the file or option
// without losing what is stored (docs/benchmark.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "plumetrace/experiment/store.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

const std::string kCli = PLUMETRACE_CLI;
const std::string kSuite = PLUMETRACE_SOURCE_DIR "/tests/support/mini_suite.toml";

using Outcome = testing::CommandOutput;
using testing::read_file;

Outcome plumetrace(const std::vector<std::string>& args) {
  return testing::run_program(kCli, args);
}

// a benchmark of the mini suite into a fresh folder, without the leaderboard; returns the folder
std::string bench(const std::vector<std::string>& extra = {}, int expected = 0) {
  const std::string out = testing::temp_path("bench", "");
  std::vector<std::string> args{"benchmark", kSuite, "--out", out, "--quiet", "--no-leaderboard"};
  args.insert(args.end(), extra.begin(), extra.end());
  const Outcome o = plumetrace(args);
  EXPECT_EQ(o.code, expected) << o.err;
  return out;
}

std::size_t stored_runs(const std::string& store) { return read_store_rows(store, nullptr).size(); }

TEST(BenchmarkCli, RunsEveryControllerOnEveryTaskAndWritesTheManifest) {
  const std::string out = bench();
  const auto manifest = nlohmann::json::parse(read_file(out + "/benchmark.json"));
  EXPECT_EQ(manifest["suite"]["name"], "mini");
  EXPECT_EQ(manifest["suite"]["digest"].get<std::string>().size(), 16u);
  EXPECT_EQ(manifest["suite"]["tasks"].size(), 2u);
  EXPECT_EQ(manifest["controllers"].size(), 2u);
  // 2 tasks x 2 controllers x 4 runs, and the header
  const std::string runs = read_file(out + "/runs.csv");
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 1 + 16);
  EXPECT_EQ(stored_runs(out + "/results.sqlite"), 16u);
}

TEST(BenchmarkCli, AddingAControllerKeepsTheStoredRunsAndTheDigest) {
  const std::string out = bench();
  const std::string digest =
      nlohmann::json::parse(read_file(out + "/benchmark.json"))["suite"]["digest"];
  const Outcome o = plumetrace(
      {"benchmark", kSuite, "--out", out, "--quiet", "--no-leaderboard", "--controller", "levy"});
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("24 runs (8 computed now, 16 from the store)"), std::string::npos) << o.out;
  const auto manifest = nlohmann::json::parse(read_file(out + "/benchmark.json"));
  EXPECT_EQ(manifest["suite"]["digest"], digest);
  EXPECT_EQ(manifest["controllers"][2]["name"], "levy");
}

TEST(BenchmarkCli, TheSameExportsWhateverTheThreadsOrShards) {
  const std::string one = bench({"--threads", "1"});
  const std::string two = bench({"--threads", "2"});
  EXPECT_EQ(read_file(one + "/runs.csv"), read_file(two + "/runs.csv"));
  // two shards, merged, then the benchmark over the merged store computes nothing
  const std::string parts = testing::temp_path("parts", "");
  for (const char* s : {"1/2", "2/2"}) {
    const Outcome o = plumetrace({"benchmark", kSuite, "--out", parts, "--shard", s, "--quiet"});
    ASSERT_EQ(o.code, 0) << o.err;
    EXPECT_NE(o.out.find(std::string("shard ") + s + " of benchmark mini"), std::string::npos)
        << o.out;
  }
  const std::string merged = parts + "/merged.sqlite";
  ASSERT_EQ(plumetrace({"merge", parts + "/part-1-of-2.sqlite", parts + "/part-2-of-2.sqlite",
                        "--store", merged})
                .code,
            0);
  const Outcome o = plumetrace(
      {"benchmark", kSuite, "--out", parts, "--store", merged, "--quiet", "--no-leaderboard"});
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("(0 computed now, 16 from the store)"), std::string::npos) << o.out;
  EXPECT_EQ(read_file(parts + "/runs.csv"), read_file(one + "/runs.csv"));
}

TEST(BenchmarkCli, BadInputIsRefusedNamingTheFileOrOptionAndTheStoreIsKept) {
  const std::string out = bench();
  const auto refused = [&](const std::vector<std::string>& extra, const std::string& words,
                           const std::string& suite = kSuite) {
    std::vector<std::string> args{"benchmark", suite, "--out", out, "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Outcome o = plumetrace(args);
    EXPECT_EQ(o.code, 2) << o.err;
    EXPECT_NE(o.err.find(words), std::string::npos) << o.err;
  };
  refused({"--task", "far"}, "--task: unknown task 'far'");
  refused({"--controller", "walker"}, "--controller: unknown controller 'walker'");
  // copies of the suite elsewhere, naming the scenario by its whole path
  const auto copy = [] {
    std::string text = read_file(kSuite);
    const std::string relative = "\"../../scenarios/";
    for (auto at = text.find(relative); at != std::string::npos; at = text.find(relative)) {
      text.replace(at, relative.size(), "\"" PLUMETRACE_SOURCE_DIR "/scenarios/");
    }
    return text;
  };
  std::string text = copy();
  text.replace(text.find("name = \"aside\""), 14, "name = \"near\"");
  const std::string dup = testing::write_temp("dup", ".toml", text);
  refused({}, dup + ": task near: name is given twice", dup);
  text = copy();
  text.replace(text.find("name = \"mini\""), 13, "");
  const std::string nameless = testing::write_temp("nameless", ".toml", text);
  refused({}, nameless + ": name: missing", nameless);
  EXPECT_EQ(stored_runs(out + "/results.sqlite"), 16u);
  const Outcome missing = plumetrace({"benchmark", out + "/no-such-suite.toml"});
  EXPECT_EQ(missing.code, 2) << missing.err;  // as a missing sweep file
  EXPECT_NE(missing.err.find("no-such-suite.toml"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace plumetrace
