// `plumetrace sweep --shard`, `plumetrace merge` and, in builds with MPI, `mpirun ... plumetrace
// sweep`, as processes: every way of splitting a sweep gives the single process's exports, byte
// for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "plumetrace/experiment/store.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

const std::string kCli = PLUMETRACE_CLI;

const std::string kSweep = PLUMETRACE_SOURCE_DIR "/tests/support/two_plumes.toml";

// the shared sweep, or a copy of it with another master seed
std::string write_sweep(const std::string& seed = "31") {
  std::string text = testing::read_file(kSweep);
  text.replace(text.find("seed = 31"), 9, "seed = " + seed);
  return testing::write_temp("sweep", ".toml", text);
}

using Outcome = testing::CommandOutput;
using testing::read_file;
using testing::run_command;

Outcome plumetrace(const std::string& args) { return run_command(kCli + " " + args); }

// the exports of a store of the sweep, as text
std::string exports(const std::string& sweep, const std::string& store) {
  const std::string out = testing::temp_path("exports", "");
  EXPECT_EQ(plumetrace("export " + sweep + " --store " + store + " --out " + out).code, 0);
  return read_file(out + "/runs.csv") + read_file(out + "/summary.csv");
}

// the single-process sweep everything else must equal
std::string baseline(const std::string& sweep) {
  const std::string store = testing::temp_path("baseline", ".sqlite");
  const Outcome o = plumetrace("sweep " + sweep + " --threads 2 --quiet --store " + store +
                               " --out " + testing::temp_path("baseline_out", ""));
  EXPECT_EQ(o.code, 0) << o.err;
  const std::string text = exports(sweep, store);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 48 + 1 + 4);
  return text;
}

// computes shard i/n into a store of its own; returns the store
std::string shard(const std::string& sweep, int i, int n, const std::string& extra = "") {
  const std::string store = testing::temp_path("part", ".sqlite");
  const Outcome o = plumetrace("sweep " + sweep + " --shard " + std::to_string(i) + "/" +
                               std::to_string(n) + " --store " + store + " " + extra);
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("shard " + std::to_string(i) + "/" + std::to_string(n)), std::string::npos)
      << o.out;
  return store;
}

TEST(ShardsCli, ThreeShardsMergedEqualASingleProcessSweep) {
  const std::string sweep = write_sweep();
  const std::string all = testing::temp_path("all", ".sqlite");
  const Outcome merged = plumetrace("merge " + shard(sweep, 1, 3) + " " + shard(sweep, 2, 3) + " " +
                                    shard(sweep, 3, 3) + " --store " + all);
  EXPECT_EQ(merged.code, 0) << merged.err;
  EXPECT_EQ(merged.err, "");
  EXPECT_NE(merged.out.find("48 runs added"), std::string::npos) << merged.out;
  EXPECT_EQ(exports(sweep, all), baseline(sweep));
}

TEST(ShardsCli, AShardRunTwiceAddsNoRows) {
  const std::string sweep = write_sweep();
  const std::string store = shard(sweep, 2, 3);
  const Outcome again = plumetrace("sweep " + sweep + " --shard 2/3 --store " + store);
  EXPECT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("16 runs (0 computed now, 16 from the store)"), std::string::npos)
      << again.out;
  EXPECT_EQ(read_store_rows(store, nullptr).size(), 16u);
}

TEST(ShardsCli, MergeWarnsOfMissingRunsAndASweepOverTheStoreComputesThem) {
  const std::string sweep = write_sweep();
  const std::string all = testing::temp_path("all", ".sqlite");
  const Outcome merged =
      plumetrace("merge " + shard(sweep, 1, 3) + " " + shard(sweep, 3, 3) + " --store " + all);
  EXPECT_EQ(merged.code, 0) << merged.err;
  EXPECT_NE(merged.err.find("sweep two: 16 of 48 runs are missing"), std::string::npos)
      << merged.err;
  EXPECT_NE(merged.err.find("shard(s) 2/3"), std::string::npos) << merged.err;
  const Outcome rest = plumetrace("sweep " + sweep + " --quiet --store " + all + " --out " +
                                  testing::temp_path("rest", ""));
  EXPECT_NE(rest.out.find("48 runs (16 computed now, 32 from the store)"), std::string::npos)
      << rest.out << rest.err;
  EXPECT_EQ(exports(sweep, all), baseline(sweep));
}

TEST(ShardsCli, MergeRefusesPartsOfAnotherSweepNamingTheFile) {
  const std::string sweep = write_sweep();
  const std::string other_seed = shard(write_sweep("32"), 2, 2);
  const std::string other_set = shard(sweep, 2, 2, "--set sim.dt=0.04");
  const std::string part = shard(sweep, 1, 2);
  const std::string all = testing::temp_path("all", ".sqlite");
  for (const std::string& other : {other_seed, other_set}) {
    const Outcome o = plumetrace("merge " + part + " " + other + " --store " + all);
    EXPECT_EQ(o.code, 2);
    EXPECT_NE(o.err.find("'" + other + "' holds runs of another sweep definition"),
              std::string::npos)
        << o.err;
  }
  const Outcome overlap =
      plumetrace("merge " + part + " " + shard(sweep, 1, 3) + " --store " + all);
  EXPECT_EQ(overlap.code, 2);
  EXPECT_NE(overlap.err.find("both hold"), std::string::npos) << overlap.err;
  EXPECT_FALSE(std::filesystem::exists(all));
}

TEST(ShardsCli, ABadShardIsRefusedNamingTheOption) {
  const std::string sweep = write_sweep();
  for (const char* bad : {"0/2", "3/2", "2", "one/two"}) {
    const Outcome o = plumetrace("sweep " + sweep + " --shard " + bad + " --store " +
                                 testing::temp_path("bad", ".sqlite"));
    EXPECT_EQ(o.code, 2) << bad;
    EXPECT_NE(o.err.find("--shard"), std::string::npos) << o.err;
    EXPECT_EQ(o.out, "");
  }
}

#ifdef PLUMETRACE_MPIEXEC
// The environment of mpirun in these tests, and only there. why: Open MPI refuses to run as root
// (CI and containers do) unless told; shared memory only, without the single-copy mechanism
// (it needs ptrace rights that containers withhold) and without probing for UCX devices
const char* const kMpiEnv =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader "
    "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_pml=ob1";

// runs plumetrace on `ranks` ranks, with `env` added; why: no binding to cores, so that tests
// running side by side on a small machine do not pile onto the same cores
Outcome mpirun(int ranks, const std::string& args, const std::string& env = "") {
  return run_command(std::string("env ") + kMpiEnv + " " + env + " " + PLUMETRACE_MPIEXEC + " -n " +
                     std::to_string(ranks) + " --oversubscribe --bind-to none --timeout 100 " +
                     kCli + " " + args);
}

// the runs each rank computed, from the summary line's "(runs per rank: a, b, c)"
std::vector<long> runs_per_rank(const std::string& out) {
  std::vector<long> runs;
  const auto at = out.find("runs per rank:");
  if (at == std::string::npos) return runs;
  std::istringstream in(out.substr(at + 14, out.find(')', at) - at - 14));
  for (std::string item; std::getline(in, item, ',');) runs.push_back(std::stol(item));
  return runs;
}

TEST(MpiCli, TwoRanksEqualASingleProcessSweep) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("two", ".sqlite");
  const Outcome o = mpirun(2, "sweep " + sweep + " --quiet --store " + store + " --out " +
                                  testing::temp_path("two_out", ""));
  ASSERT_EQ(o.code, 0) << o.err;
  const auto runs = runs_per_rank(o.out);
  ASSERT_EQ(runs.size(), 2u) << o.out;
  EXPECT_EQ(runs[0] + runs[1], 48);
  EXPECT_EQ(exports(sweep, store), baseline(sweep));
}

TEST(MpiCli, ThreeOversubscribedRanksWithoutSharedPlumesEqualASingleProcessSweep) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("three", ".sqlite");
  const Outcome o = mpirun(3, "sweep " + sweep + " --no-share-plumes --quiet --store " + store +
                                  " --out " + testing::temp_path("three_out", ""));
  ASSERT_EQ(o.code, 0) << o.err;
  const auto runs = runs_per_rank(o.out);
  ASSERT_EQ(runs.size(), 3u) << o.out;
  // why: the work was shared out; not "every rank", since on a loaded machine one late rank may
  // find every block taken
  EXPECT_GT(runs[1] + runs[2], 0) << o.out;
  EXPECT_EQ(runs[0] + runs[1] + runs[2], 48);
  EXPECT_EQ(exports(sweep, store), baseline(sweep));
}

TEST(MpiCli, AShardOnTwoRanksMergesWithAShardOfOneProcess) {
  const std::string sweep = write_sweep();
  const std::string first = testing::temp_path("first", ".sqlite");
  const Outcome o = mpirun(2, "sweep " + sweep + " --shard 1/2 --store " + first);
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("shard 1/2 of sweep two: 24 runs"), std::string::npos) << o.out;
  const std::string all = testing::temp_path("all", ".sqlite");
  ASSERT_EQ(plumetrace("merge " + first + " " + shard(sweep, 2, 2) + " --store " + all).code, 0);
  EXPECT_EQ(exports(sweep, all), baseline(sweep));
}

TEST(MpiCli, AKilledRankEndsTheJobWithAConsistentStoreThatARerunCompletes) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("killed", ".sqlite");
  const std::string args = "sweep " + sweep + " --no-share-plumes --threads 1 --quiet --store " +
                           store + " --out " + testing::temp_path("killed_out", "");
  // rank 1 dies (SIGKILL) when its first block arrives; the launcher then ends the job: rank 0
  // gets SIGTERM and then SIGKILL, each 3 s after the last (Open MPI's default is 1 s), so that
  // it can commit and say so on a loaded machine
  const Outcome killed =
      mpirun(3, args, "PLUMETRACE_TEST_KILL_RANK=1:1 OMPI_MCA_odls_base_sigkill_timeout=3");
  EXPECT_NE(killed.code, 0);
  const auto kept = read_store_rows(store, nullptr);
  if (killed.err.find("rank 1 dies holding no work") == std::string::npos) {
    // the usual case: rank 1's block is never computed
    EXPECT_NE(killed.err.find("rank 1 dies on receiving a block of 1 group(s)"), std::string::npos)
        << killed.err;
    EXPECT_NE(killed.err.find("plumetrace: interrupted: "), std::string::npos) << killed.err;
    // rank 2, stopped by the launcher, may say goodbye in time or not
    EXPECT_NE(killed.err.find("the MPI job stopped: no goodbye from rank(s) 1"), std::string::npos)
        << killed.err;
    EXPECT_NE(killed.err.find("(killed, crashed, or not done stopping); the store is consistent"),
              std::string::npos)
        << killed.err;
    EXPECT_LT(kept.size(), 48u);
  } else {
    // on a loaded machine ranks 0 and 2 may take every block before rank 1 asks
    EXPECT_NE(killed.err.find("the MPI job stopped early: no goodbye from rank(s) 1"),
              std::string::npos)
        << killed.err;
    EXPECT_NE(killed.err.find("(killed, crashed, or not done stopping); all 48 runs are in"),
              std::string::npos)
        << killed.err;
    EXPECT_EQ(kept.size(), 48u);
  }
  // what the store holds is what a single process computes, row for row
  const std::string full = baseline(sweep);
  std::istringstream lines(exports(sweep, store));
  std::string line;
  for (std::size_t n = 0; std::getline(lines, line) && n <= kept.size(); ++n) {
    EXPECT_NE(full.find(line + "\n"), std::string::npos) << line;
  }

  const Outcome rerun = mpirun(2, args);
  ASSERT_EQ(rerun.code, 0) << rerun.err;
  EXPECT_NE(rerun.out.find("from the store"), std::string::npos);
  EXPECT_EQ(exports(sweep, store), full);
}

TEST(MpiCli, ARankLostAfterItsLastBlockUnderALauncherThatKeepsTheJobIsGivenUpOnceEveryRunIsIn) {
  const std::string sweep = write_sweep();
  const std::string store = testing::temp_path("lost", ".sqlite");
  const std::string out = testing::temp_path("lost_out", "");
  // rank 1 dies when told there is no more work (it never gets 99 blocks of the 48 runs); this
  // mpirun does not end the job when a process dies, so rank 0 must not wait for it forever
  const Outcome o =
      mpirun(3,
             "sweep " + sweep + " --no-share-plumes --threads 1 --quiet --store " + store +
                 " --out " + out,
             "PLUMETRACE_TEST_KILL_RANK=1:99 OMPI_MCA_orte_abort_on_non_zero_status=0");
  EXPECT_NE(o.code, 0);
  EXPECT_NE(o.err.find("rank 1 dies holding no work\n"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("the MPI job stopped early: no goodbye from rank(s) 1 (killed, crashed, "
                       "or not done stopping); all 48 runs are in '" +
                       store + "'"),
            std::string::npos)
      << o.err;
  // the exports of the complete store are written all the same
  EXPECT_EQ(read_file(out + "/runs.csv") + read_file(out + "/summary.csv"), baseline(sweep));
}

TEST(MpiCli, ABenchmarkOnTwoRanksEqualsOneProcess) {
  const std::string suite = PLUMETRACE_SOURCE_DIR "/tests/support/mini_suite.toml";
  const std::string one = testing::temp_path("bench_one", "");
  const std::string two = testing::temp_path("bench_two", "");
  ASSERT_EQ(plumetrace("benchmark " + suite + " --no-leaderboard --quiet --out " + one).code, 0);
  const Outcome o = mpirun(2, "benchmark " + suite + " --no-leaderboard --quiet --out " + two);
  ASSERT_EQ(o.code, 0) << o.err;
  const auto runs = runs_per_rank(o.out);
  ASSERT_EQ(runs.size(), 2u) << o.out;
  EXPECT_EQ(runs[0] + runs[1], 16);
  EXPECT_EQ(read_file(two + "/runs.csv"), read_file(one + "/runs.csv"));
  EXPECT_EQ(read_file(two + "/benchmark.json"), read_file(one + "/benchmark.json"));
}

TEST(MpiCli, OnlySweepRunsUnderMpirun) {
  const Outcome o = mpirun(2, "run --json");
  EXPECT_NE(o.code, 0);
  EXPECT_NE(
      o.err.find("only plumetrace sweep and benchmark run across the processes of an MPI job"),
      std::string::npos)
      << o.err;
  EXPECT_EQ(o.out, "");
}
#endif

}  // namespace
}  // namespace plumetrace
