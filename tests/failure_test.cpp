// How runs fail: a controller that throws or commands a non-finite value, and more threads than
// the limit or the system allows. The process never ends in std::terminate, and the runs
// finished before a failure are kept (docs/reliability.md).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <system_error>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/command.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

// 6 points x 4 runs of about twenty steps each, with no warm-up: quick to run
const char* const kShortSweep = R"(
name = "short"
runs = 4
seed = 3

[set]
sim.warmup = 0.0
supervisor.timeout = 2.0

[[axis]]
key = "wind_sensor.sigma_a"
values = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
)";

std::vector<ExpandedSweep> short_sweep() {
  return {expand_sweep(read_sweep_file(testing::write_temp("sweep", ".toml", kShortSweep)), {})};
}

// a controller that answers every step with one command, or throws at its first step
class Fixed : public Controller {
 public:
  explicit Fixed(Command command, bool fail = false) : command_(command), fail_(fail) {}
  Command step(const Observation&, WindProbe&) override {
    if (fail_) throw std::runtime_error("the controller failed");
    return command_;
  }
  std::string_view state() const override { return "fixed"; }
  int losses() const override { return 0; }

 private:
  Command command_;
  bool fail_;
};

// controllers that stand still, except the n-th one built (from 1), which throws
ControllerFactory failing_at(int n) {
  auto built = std::make_shared<std::atomic<int>>(0);
  return [built, n](const Scenario&, Rng) {
    return std::make_unique<Fixed>(Command::stop(), ++*built == n);
  };
}

TEST(RunTasks, AControllerErrorReachesTheCallerInsteadOfEndingTheProcess) {
  const auto sweeps = short_sweep();
  CampaignOptions options;
  options.threads = 2;
  options.make_controller = failing_at(5);
  try {
    run_tasks(sweeps, missing_runs(sweeps, {}, 0), options, [](const auto&) {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "the controller failed");
  }
}

TEST(RunCampaign, RunsFinishedBeforeAControllerErrorStayInTheStore) {
  const auto sweeps = short_sweep();
  const std::string path = testing::temp_path("store", ".sqlite");
  CampaignOptions options;
  options.threads = 1;  // one worker takes the runs in campaign order
  options.share_plumes = false;
  options.make_controller = failing_at(5);
  {
    Store store(path, sweeps, version(), false);
    EXPECT_THROW(run_campaign(sweeps, store, 0, options), std::runtime_error);
  }
  Store store(path, sweeps, version(), false);
  EXPECT_EQ(store.rows().size(), 4u);
  // and the same call without the failure computes only the rest
  options.make_controller = failing_at(0);
  const CampaignResult r = run_campaign(sweeps, store, 0, options);
  EXPECT_EQ(r.skipped, 4);
  EXPECT_EQ(r.computed, 20);
}

TEST(RunTasks, ThreadsAboveTheLimitAreRefusedNamingThreads) {
  const auto sweeps = short_sweep();
  for (const int threads : {-1, kMaxThreads + 1, 100000}) {
    CampaignOptions options;
    options.threads = threads;
    try {
      run_tasks(sweeps, missing_runs(sweeps, {}, 0), options, [](const auto&) {});
      ADD_FAILURE() << threads << " threads accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("threads"), std::string::npos) << e.what();
    }
  }
}

TEST(GroupPool, ThreadsTheSystemRefusesAreAnErrorNotAnAbort) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit set here";
#endif
  const auto sweeps = short_sweep();
  // why: in a child process, whose address space is capped a little above what it uses, so that
  // the stacks (8 MiB each) of 1000 threads cannot all be mapped
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    long pages = 0;
    std::ifstream("/proc/self/statm") >> pages;
    const rlim_t used = static_cast<rlim_t>(pages) * static_cast<rlim_t>(sysconf(_SC_PAGESIZE));
    const rlimit limit{used + (64u << 20), used + (64u << 20)};
    setrlimit(RLIMIT_AS, &limit);
    try {
      GroupPool pool(sweeps, 1000, {}, nullptr);
      _exit(3);  // every thread started: the limit did not bite
    } catch (const std::system_error& e) {
      _exit(std::string(e.what()).find("1000 worker threads") != std::string::npos ? 0 : 4);
    } catch (...) {
      _exit(5);
    }
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "the child ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

TEST(Cli, SweepThreadsAboveTheLimitExitWithBadInputNamingTheOption) {
  const std::string sweep = testing::write_temp("sweep", ".toml", kShortSweep);
  const std::string store = testing::temp_path("store", ".sqlite");
  const auto o = testing::run_command(std::string(PLUMETRACE_CLI) + " sweep " + sweep +
                                      " --quiet --threads 100000 --store " + store);
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("--threads"), std::string::npos) << o.err;
  EXPECT_EQ(o.out, "");
}

TEST(Agent, ANonFiniteCommandIsRefusedNamingTheValue) {
  const Scenario scenario = short_sweep()[0].points[0].scenario;
  for (const Command& command : {Command::go(NAN), Command::turn_to(INFINITY),
                                 Command::curve(-INFINITY), Command::curve(NAN)}) {
    const ControllerFactory factory = [command](const Scenario&, Rng) {
      return std::make_unique<Fixed>(command);
    };
    try {
      run_once(scenario, 1, 0, {}, factory);
      ADD_FAILURE() << "a non-finite command was taken";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("non-finite"), std::string::npos) << what;
      EXPECT_TRUE(what.find("nan") != std::string::npos || what.find("inf") != std::string::npos)
          << what;
    }
  }
}

}  // namespace
}  // namespace plumetrace
