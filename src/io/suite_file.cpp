#include "plumetrace/io/suite_file.hpp"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <utility>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

namespace {

// what a suite file's reader checks of every value: a non-empty printable string
struct Reader {
  const std::string& file;

  [[noreturn]] void fail(const std::string& msg) const { throw ConfigError(file + ": " + msg); }

  std::string text(const toml::node& node, const std::string& key) const {
    if (!node.is_string() || node.as_string()->get().empty()) {
      fail(key + ": must be a non-empty string");
    }
    std::string value = node.as_string()->get();
    check_printable(value, file, key);
    return value;
  }

  std::vector<std::string> names(const toml::node& node, const std::string& key) const {
    const auto* list = node.as_array();
    if (!list) fail(key + ": must be a list of names");
    std::vector<std::string> out;
    for (const auto& item : *list) {
      std::string name = text(item, key);
      if (std::find(out.begin(), out.end(), name) != out.end()) {
        fail(key + ": '" + name + "' is given twice");
      }
      out.push_back(std::move(name));
    }
    return out;
  }
};

// why: a task's name is a sweep's name in the store and a column of CSV files
bool is_task_name(const std::string& name) {
  static const std::regex pattern(R"([A-Za-z0-9][A-Za-z0-9_.-]{0,63})");
  return std::regex_match(name, pattern);
}

SuiteTask read_task(const Reader& in, const toml::table& table, std::size_t index) {
  SuiteTask task;
  const toml::table* set = nullptr;
  const std::string where = "task " + std::to_string(index + 1);
  const std::filesystem::path folder = std::filesystem::path(in.file).parent_path();
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "name") {
      task.name = in.text(node, where + ": name");
      if (!is_task_name(task.name)) {
        in.fail(where + ": name: '" + task.name +
                "' must be 1 to 64 letters, digits, '_', '-' or '.', not first");
      }
    } else if (key == "title" || key == "why" || key == "source") {
      std::string value = in.text(node, where + ": " + key);
      (key == "title" ? task.title : key == "why" ? task.why : task.source) = std::move(value);
    } else if (key == "scenario") {
      const std::filesystem::path p(in.text(node, where + ": scenario"));
      task.scenario_path = (p.is_absolute() ? p : folder / p).lexically_normal().string();
    } else if (key == "set" && node.is_table()) {
      set = node.as_table();
    } else {
      in.fail(where + ": unknown or mistyped key '" + key +
              "' (keys: name, title, why, source, scenario, [task.set])");
    }
  }
  if (task.name.empty()) in.fail(where + ": name: missing");
  if (set) {
    detail::flatten(*set, "", in.file + ": task " + task.name + ": [task.set]", Layer::kSweep,
                    task.settings);
  }
  const std::pair<const char*, const std::string*> texts[] = {
      {"title", &task.title}, {"why", &task.why}, {"source", &task.source}};
  for (const auto& [key, value] : texts) {
    if (value->empty()) in.fail("task " + task.name + ": " + key + ": missing");
  }
  if (!task.scenario_path.empty()) task.scenario_settings = read_scenario_file(task.scenario_path);
  return task;
}

}  // namespace

SuiteFile read_suite_file(const std::string& path) {
  const toml::table table = detail::parse_toml_file(path, "suite file");
  SuiteFile suite;
  suite.file = path;
  const Reader in{suite.file};
  bool has_controllers = false;
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "name") {
      suite.name = in.text(node, key);
    } else if (key == "version") {
      suite.version = in.text(node, key);
    } else if (key == "title") {
      suite.title = in.text(node, key);
    } else if (key == "seed") {
      if (!node.is_integer() || node.as_integer()->get() < 0) {
        in.fail("seed: must be an integer >= 0");
      }
      suite.seed = static_cast<std::uint64_t>(node.as_integer()->get());
    } else if (key == "runs") {
      const auto runs = node.is_integer() ? node.as_integer()->get() : 0;
      if (runs < 1 || runs > kMaxCampaignRuns) {
        in.fail("runs: must be an integer >= 1 and <= " + std::to_string(kMaxCampaignRuns));
      }
      suite.runs = static_cast<int>(runs);
    } else if (key == "digest") {
      suite.digest = in.text(node, key);
    } else if (key == "controllers") {
      suite.controllers = in.names(node, key);
      has_controllers = true;
    } else if (key == "null_models") {
      suite.null_models = in.names(node, key);
    } else if (key == "task" && node.is_array_of_tables()) {
      for (const auto& item : *node.as_array()) {
        SuiteTask task = read_task(in, *item.as_table(), suite.tasks.size());
        for (const auto& other : suite.tasks) {
          if (other.name == task.name) in.fail("task " + task.name + ": name is given twice");
        }
        suite.tasks.push_back(std::move(task));
      }
    } else {
      in.fail("unknown or mistyped key '" + key +
              "' (keys: name, version, title, seed, runs, controllers, null_models, digest, [[task]])");
    }
  }
  if (suite.name.empty()) in.fail("name: missing");
  if (suite.version.empty()) in.fail("version: missing");
  if (suite.title.empty()) in.fail("title: missing");
  if (suite.tasks.empty()) in.fail("no [[task]]: a suite has at least one task");
  if (!has_controllers || suite.controllers.empty()) {
    in.fail("controllers: missing (the controllers a benchmark runs by default)");
  }
  for (const auto& n : suite.null_models) {
    if (std::find(suite.controllers.begin(), suite.controllers.end(), n) ==
        suite.controllers.end()) {
      in.fail("null_models: '" + n + "' is not among the controllers");
    }
  }
  return suite;
}

}  // namespace plumetrace
