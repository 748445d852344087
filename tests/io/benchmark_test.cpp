// Benchmark suites: reading a suite file, planning a benchmark, and the digest every result
// carries (docs/benchmark.md, "Suite files" and "Versions and digests").
#include "plumetrace/io/benchmark.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/io/suite_file.hpp"
#include "support/command.hpp"

namespace plumetrace {
namespace {

const std::string kScenario = std::string(PLUMETRACE_SOURCE_DIR) + "/scenarios/lochmatter2008.toml";

// a suite of two tasks on the paper's scenario; `extra` is appended (more keys or tasks)
std::string suite_text(const std::string& head = "", const std::string& extra = "") {
  return head + R"(
name = "mini"
version = "1"
title = "a small suite"
seed = 7
runs = 3
controllers = ["surge-spiral", "crw"]
null_models = ["crw"]

[[task]]
name = "near"
title = "near the source"
why = "a short run"
source = "a test"
scenario = ")" +
         kScenario + R"("
[task.set]
robot.start_x = 3.0
supervisor.timeout = 30.0

[[task]]
name = "far"
title = "far from the source"
why = "a longer run"
source = "a test"
scenario = ")" +
         kScenario + R"("
[task.set]
supervisor.timeout = 30.0
)" + extra;
}

SuiteFile read_text(const std::string& text) {
  return read_suite_file(testing::write_temp("suite", ".toml", text));
}

BenchmarkPlan plan_of(const std::string& text, const BenchmarkChoice& choice = {}) {
  return plan_benchmark(read_text(text), choice);
}

// the message of the ConfigError reading (or planning) a suite throws
std::string refusal(const std::string& text, const BenchmarkChoice& choice = {}) {
  try {
    plan_of(text, choice);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SuiteFile, ReadsTasksInOrderWithTheirSettings) {
  const SuiteFile suite = read_text(suite_text());
  EXPECT_EQ(suite.name, "mini");
  EXPECT_EQ(suite.version, "1");
  EXPECT_EQ(suite.seed, 7u);
  EXPECT_EQ(suite.runs, 3);
  ASSERT_EQ(suite.tasks.size(), 2u);
  EXPECT_EQ(suite.tasks[0].name, "near");
  EXPECT_EQ(suite.tasks[1].name, "far");
  ASSERT_EQ(suite.tasks[0].settings.size(), 2u);
  EXPECT_EQ(suite.tasks[0].settings[0].key, "robot.start_x");
  EXPECT_FALSE(suite.tasks[0].scenario_settings.empty());
}

TEST(SuiteFile, RefusesWhatIsMissingDuplicatedOrUnknownNamingTheKey) {
  const std::string dup =
      "\n[[task]]\nname = \"far\"\ntitle = \"t\"\nwhy = \"w\"\nsource = \"s\"\n";
  EXPECT_NE(refusal(suite_text("", dup)).find("task far: name is given twice"), std::string::npos);
  const std::string nameless = "\n[[task]]\ntitle = \"t\"\nwhy = \"w\"\nsource = \"s\"\n";
  EXPECT_NE(refusal(suite_text("", nameless)).find("task 3: name: missing"), std::string::npos);
  const std::string whyless = "\n[[task]]\nname = \"x\"\ntitle = \"t\"\nsource = \"s\"\n";
  EXPECT_NE(refusal(suite_text("", whyless)).find("task x: why: missing"), std::string::npos);
  EXPECT_NE(refusal(suite_text("colour = 1\n")).find("unknown or mistyped key 'colour'"),
            std::string::npos);
  const std::string bad_name =
      "\n[[task]]\nname = \"../x\"\ntitle = \"t\"\nwhy = \"w\"\nsource = \"s\"\n";
  EXPECT_NE(refusal(suite_text("", bad_name)).find("name: '../x' must be"), std::string::npos);
  EXPECT_NE(refusal(R"(name = "n"
version = "1"
title = "t"
controllers = ["crw"]
)")
                .find("no [[task]]"),
            std::string::npos);
  std::string no_null = suite_text();
  no_null.replace(no_null.find("null_models = [\"crw\"]"), 21, "null_models = [\"levy\"]");
  EXPECT_NE(refusal(no_null).find("null_models: 'levy' is not among the controllers"),
            std::string::npos);
  std::string bad_value = suite_text();
  bad_value.replace(bad_value.find("robot.start_x = 3.0"), 19, "robot.start_x = \"x\"");
  EXPECT_NE(refusal(bad_value).find("task near: [task.set]: robot.start_x"), std::string::npos);
}

TEST(BenchmarkPlan, RefusesAnUnknownControllerOrTaskNamingTheOption) {
  BenchmarkChoice choice;
  choice.controllers = {"no-such-walk"};
  const std::string controller = refusal(suite_text(), choice);
  EXPECT_NE(controller.find("--controller: unknown controller 'no-such-walk'"), std::string::npos);
  EXPECT_NE(controller.find("surge-spiral"), std::string::npos);  // the known ones are listed
  choice = {};
  choice.tasks = {"middle"};
  const std::string task = refusal(suite_text(), choice);
  EXPECT_NE(task.find("--task: unknown task 'middle'"), std::string::npos);
  EXPECT_NE(task.find("near, far"), std::string::npos);
  std::string suite = suite_text();
  const std::string list = "controllers = [\"surge-spiral\", \"crw\"]\nnull_models = [\"crw\"]";
  suite.replace(suite.find(list), list.size(), "controllers = [\"walk\"]");
  EXPECT_NE(refusal(suite).find(": controllers: unknown controller 'walk'"), std::string::npos);
}

TEST(BenchmarkPlan, OneSweepPerTaskWithTheControllersAsItsAxis) {
  BenchmarkChoice choice;
  choice.controllers = {"levy", "crw"};  // crw is the suite's already: entered once
  const BenchmarkPlan plan = plan_of(suite_text(), choice);
  ASSERT_EQ(plan.sweeps.size(), 2u);
  EXPECT_EQ(plan.controllers, (std::vector<std::string>{"surge-spiral", "crw", "levy"}));
  for (const auto& sweep : plan.sweeps) {
    EXPECT_EQ(sweep.def.seed, 7u);
    EXPECT_EQ(sweep.def.runs, 3);
    ASSERT_EQ(sweep.points.size(), 3u);
    EXPECT_EQ(algorithm_name(sweep.points[2].scenario.controller.algorithm), "levy");
    // paired: every controller of a task meets the same plume at every trial
    EXPECT_EQ(plume_key(sweep.points[0].scenario), plume_key(sweep.points[2].scenario));
  }
  EXPECT_DOUBLE_EQ(plan.sweeps[0].points[0].scenario.robot.start.x, 3.0);
  choice.only = true;
  choice.tasks = {"far"};
  const BenchmarkPlan only = plan_of(suite_text(), choice);
  EXPECT_EQ(only.controllers, (std::vector<std::string>{"levy", "crw"}));
  ASSERT_EQ(only.sweeps.size(), 1u);
  EXPECT_EQ(only.sweeps[0].def.name, "far");
}

TEST(BenchmarkDigest, TheSameWhateverControllersAreRun) {
  BenchmarkChoice more;
  more.controllers = {"levy", "infotaxis"};
  const BenchmarkPlan a = plan_of(suite_text());
  const BenchmarkPlan b = plan_of(suite_text(), more);
  EXPECT_EQ(a.digest, b.digest);
  EXPECT_EQ(a.task_digests, b.task_digests);
  EXPECT_EQ(a.digest.size(), 16u);
}

TEST(BenchmarkDigest, ChangesWithEveryTaskSeedRunsAndVersion) {
  const BenchmarkPlan base = plan_of(suite_text());
  const auto changed = [&](const std::string& from, const std::string& to) {
    std::string text = suite_text();
    text.replace(text.find(from), from.size(), to);
    return plan_of(text);
  };
  const BenchmarkPlan task = changed("robot.start_x = 3.0", "robot.start_x = 3.5");
  EXPECT_NE(task.digest, base.digest);
  EXPECT_NE(task.task_digests[0], base.task_digests[0]);
  EXPECT_EQ(task.task_digests[1], base.task_digests[1]);  // the other task is unchanged
  EXPECT_NE(changed("seed = 7", "seed = 8").digest, base.digest);
  EXPECT_NE(changed("version = \"1\"", "version = \"2\"").digest, base.digest);
  BenchmarkChoice runs;
  runs.runs = 4;
  EXPECT_NE(plan_of(suite_text(), runs).digest, base.digest);
  // a controller's key the task sets belongs to the task
  const BenchmarkPlan keyed = changed("supervisor.timeout = 30.0\n\n[[task]]",
                                      "supervisor.timeout = 30.0\ncrw.rho = 0.7\n\n[[task]]");
  EXPECT_NE(keyed.task_digests[0], base.task_digests[0]);
  // a --set is part of every task
  BenchmarkChoice set;
  set.overrides = {parse_override("sim.dt=0.016")};
  const BenchmarkPlan with_set = plan_of(suite_text(), set);
  EXPECT_NE(with_set.task_digests[0], base.task_digests[0]);
  EXPECT_NE(with_set.task_digests[1], base.task_digests[1]);
  // a title or a reason is no part of what runs
  EXPECT_EQ(changed("why = \"a short run\"", "why = \"a brief run\"").digest, base.digest);
}

TEST(BenchmarkManifest, SaysWhatRanAndWhereEachControllerCameFrom) {
  BenchmarkChoice choice;
  choice.controllers = {"levy"};
  const BenchmarkPlan plan = plan_of(suite_text(), choice);
  const auto m = nlohmann::json::parse(benchmark_manifest(plan, {{"levy", "mine.py"}}));
  EXPECT_EQ(m["plumetrace_benchmark"], 1);
  EXPECT_EQ(m["suite"]["digest"], plan.digest);
  EXPECT_EQ(m["suite"]["runs"], 3);
  ASSERT_EQ(m["suite"]["tasks"].size(), 2u);
  EXPECT_EQ(m["suite"]["tasks"][0]["success"], "reach");
  EXPECT_EQ(m["suite"]["tasks"][0]["robots"], 1);
  EXPECT_EQ(m["suite"]["tasks"][1]["digest"], plan.task_digests[1]);
  ASSERT_EQ(m["controllers"].size(), 3u);
  EXPECT_EQ(m["controllers"][0]["origin"], "built-in");
  EXPECT_EQ(m["controllers"][1]["null_model"], true);
  EXPECT_EQ(m["controllers"][2]["origin"], "python");
  EXPECT_EQ(m["controllers"][2]["file"], "mine.py");
}

TEST(BenchmarkDigest, ARecordedDigestRefusesATaskChangedWithoutANewVersion) {
  const std::string digest = plan_of(suite_text()).digest;
  EXPECT_EQ(plan_of(suite_text("digest = \"" + digest + "\"\n")).digest, digest);
  // a run with other controllers, tasks or runs checks the suite as recorded, not the choice
  BenchmarkChoice choice;
  choice.tasks = {"far"};
  choice.runs = 9;
  EXPECT_NO_THROW(plan_of(suite_text("digest = \"" + digest + "\"\n"), choice));
  std::string changed = suite_text("digest = \"" + digest + "\"\n");
  changed.replace(changed.find("robot.start_x = 3.0"), 19, "robot.start_x = 3.5");
  const std::string message = refusal(changed);
  EXPECT_NE(message.find("digest: the tasks of mini version 1 at seed 7 and 3 runs give "),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("give the suite a new version"), std::string::npos);
}

// the suite that ships: every task has its reasons, and plans with every built-in controller
TEST(ShippedSuite, EveryTaskSaysWhyAndRunsWithEveryBuiltInController) {
  const SuiteFile suite =
      read_suite_file(std::string(PLUMETRACE_SOURCE_DIR) + "/studies/benchmark/suite.toml");
  EXPECT_GE(suite.tasks.size(), 9u);
  for (const auto& t : suite.tasks) {
    EXPECT_GE(t.why.size(), 40u) << t.name;
    EXPECT_FALSE(t.source.empty()) << t.name;
  }
  for (const Algorithm a : library_algorithms()) {
    const std::string name(algorithm_name(a));
    EXPECT_NE(std::find(suite.controllers.begin(), suite.controllers.end(), name),
              suite.controllers.end())
        << name << " is built in but not in the suite";
  }
  const BenchmarkPlan plan = plan_benchmark(suite, {});
  EXPECT_EQ(plan.sweeps.size(), suite.tasks.size());
  // version 1 as it was run and reported (docs/benchmark.md): planning checked it above
  EXPECT_EQ(suite.version, "1");
  EXPECT_EQ(plan.digest, "cbefbcab5737e285");
}

}  // namespace
}  // namespace plumetrace
