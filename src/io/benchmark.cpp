#include "plumetrace/io/benchmark.hpp"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"

namespace plumetrace {

namespace {

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

std::vector<std::string> chosen_controllers(const SuiteFile& suite, const BenchmarkChoice& choice) {
  std::vector<std::string> names = choice.only ? std::vector<std::string>{} : suite.controllers;
  for (const auto& name : choice.controllers) {
    if (!contains(names, name)) names.push_back(name);
  }
  if (names.empty()) throw ConfigError("--controller: --only needs at least one controller");
  const auto& registry = controller_registry();
  for (const auto& name : names) {
    if (registry.find(name) < registry.size()) continue;
    std::string known;
    for (const auto& e : registry.entries()) known += (known.empty() ? "" : ", ") + e.name;
    const bool given = contains(choice.controllers, name);
    throw ConfigError((given ? std::string("--controller") : suite.file + ": controllers") +
                      ": unknown controller '" + name + "' (known: " + known +
                      "; a Python controller is given as its .py file)");
  }
  return names;
}

std::vector<SuiteTask> chosen_tasks(const SuiteFile& suite, const BenchmarkChoice& choice) {
  for (const auto& name : choice.tasks) {
    const bool known = std::any_of(suite.tasks.begin(), suite.tasks.end(),
                                   [&](const SuiteTask& t) { return t.name == name; });
    if (known) continue;
    std::string names;
    for (const auto& t : suite.tasks) names += (names.empty() ? "" : ", ") + t.name;
    throw ConfigError("--task: unknown task '" + name + "' of suite " + suite.name + " (" +
                      suite.file + "; its tasks: " + names + ")");
  }
  std::vector<SuiteTask> tasks;
  for (const auto& t : suite.tasks) {
    if (choice.tasks.empty() || contains(choice.tasks, t.name)) tasks.push_back(t);
  }
  return tasks;
}

// a canonical line's key is a controller's: "controller.*", a registered controller's table,
// or either under "member.K."
bool is_controller_key(const std::string& key, const std::set<std::string>& tables) {
  std::string_view k = key;
  if (k.rfind("member.", 0) == 0) {
    const auto dot = k.find('.', 7);
    if (dot != std::string_view::npos) k.remove_prefix(dot + 1);
  }
  const std::string table(k.substr(0, k.find('.')));
  return table == "controller" || tables.count(table) > 0;
}

// the task's resolved scenario as canonical lines, without the controllers' keys that neither
// the task nor --set gives
std::string task_values(const Scenario& scenario, const std::vector<Setting>& given) {
  std::set<std::string> tables;
  for (const auto& e : controller_registry().entries()) tables.insert(e.table);
  std::set<std::string> explicit_keys;
  for (const auto& s : given) explicit_keys.insert(s.key);
  std::istringstream lines(canonical_config(scenario, ConfigKeys::kAll));
  std::string text;
  for (std::string line; std::getline(lines, line);) {
    const std::string key = line.substr(0, line.find('='));
    if (key == "controller.algorithm") continue;
    if (is_controller_key(key, tables) && explicit_keys.count(key) == 0) continue;
    text += line + '\n';
  }
  return text;
}

// why: a suite's version names its tasks; a task changed without a new version would make
// "version 1" mean two things (issue 26, item 3)
void check_recorded_digest(SuiteFile suite) {
  const std::string recorded = suite.digest;
  suite.digest.clear();
  const std::string digest = plan_benchmark(suite, {}).digest;
  if (digest == recorded) return;
  throw ConfigError(suite.file + ": digest: the tasks of " + suite.name + " version " +
                    suite.version + " at seed " + std::to_string(suite.seed) + " and " +
                    std::to_string(suite.runs) + " runs give " + digest + ", not the " +
                    recorded +
                    " recorded: a task, the seed or the runs changed, or this plumetrace "
                    "resolves a task's values differently; give the suite a new version and "
                    "record digest = \"" +
                    digest + "\"");
}

}  // namespace

BenchmarkPlan plan_benchmark(const SuiteFile& suite, const BenchmarkChoice& choice) {
  BenchmarkPlan plan;
  plan.suite = suite;
  plan.controllers = chosen_controllers(suite, choice);
  plan.tasks = chosen_tasks(suite, choice);
  plan.runs = choice.runs > 0 ? choice.runs : suite.runs;
  const std::string header =
      "seed=" + std::to_string(suite.seed) + "\nruns=" + std::to_string(plan.runs) + '\n';
  std::string all = "plumetrace benchmark suite\nname=" + suite.name +
                    "\nversion=" + suite.version + '\n' + header;
  for (const auto& task : plan.tasks) {
    SweepDef def;
    def.name = task.name;
    def.title = task.title;
    def.scenario_path = task.scenario_path;
    def.scenario_settings = task.scenario_settings;
    def.settings = task.settings;
    def.runs = plan.runs;
    def.seed = suite.seed;
    def.file = suite.file;
    Axis axis;
    axis.key = "controller.algorithm";
    axis.label = "controller";
    for (const auto& c : plan.controllers) axis.values.emplace_back(c);
    def.axes.push_back(std::move(axis));
    plan.sweeps.push_back(expand_sweep(def, choice.overrides));
    std::vector<Setting> given = task.settings;
    given.insert(given.end(), choice.overrides.begin(), choice.overrides.end());
    const std::string text = "task=" + task.name + '\n' + header +
                             task_values(plan.sweeps.back().points.front().scenario, given);
    plan.task_digests.push_back(hash_text(text));
    all += "task=" + task.name + " " + plan.task_digests.back() + '\n';
  }
  plan.digest = hash_text(all);
  if (!suite.digest.empty()) check_recorded_digest(suite);
  return plan;
}

std::string benchmark_manifest(const BenchmarkPlan& plan,
                               const std::map<std::string, std::string>& python_files) {
  using json = nlohmann::ordered_json;
  json tasks = json::array();
  for (std::size_t i = 0; i < plan.tasks.size(); ++i) {
    const SuiteTask& t = plan.tasks[i];
    const Scenario& s = plan.sweeps[i].points.front().scenario;
    tasks.push_back(
        {{"name", t.name},
         {"title", t.title},
         {"why", t.why},
         {"source", t.source},
         {"scenario", t.scenario_path.empty() ? json() : json(recorded_path(t.scenario_path))},
         {"success", s.supervisor.success == SuccessRule::kReach ? "reach" : "declare"},
         {"robots", s.team.count},
         {"timeout", s.supervisor.timeout},
         {"digest", plan.task_digests[i]}});
  }
  const auto library = library_algorithms();
  json controllers = json::array();
  for (const auto& name : plan.controllers) {
    const bool built_in = std::any_of(library.begin(), library.end(),
                                      [&](Algorithm a) { return algorithm_name(a) == name; });
    const auto file = python_files.find(name);
    const char* origin = "registered";
    if (file != python_files.end()) {
      origin = "python";
    } else if (built_in) {
      origin = "built-in";
    }
    controllers.push_back(
        {{"name", name},
         {"origin", origin},
         {"file", file != python_files.end() ? json(recorded_path(file->second)) : json()},
         {"null_model", contains(plan.suite.null_models, name)}});
  }
  const json manifest = {{"plumetrace_benchmark", 1},
                         {"version", std::string(version())},
                         {"suite",
                          {{"name", plan.suite.name},
                           {"version", plan.suite.version},
                           {"title", plan.suite.title},
                           {"file", recorded_path(plan.suite.file)},
                           {"digest", plan.digest},
                           {"seed", plan.suite.seed},
                           {"runs", plan.runs},
                           {"tasks", tasks}}},
                         {"controllers", controllers},
                         {"runs_file", "runs.csv"}};
  return manifest.dump(1) + '\n';
}

}  // namespace plumetrace
