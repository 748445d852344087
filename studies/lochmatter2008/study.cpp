#include "lochmatter2008/study.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <sstream>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/toml_input.hpp"
#include "plumetrace/paths.hpp"

namespace plumetrace {

namespace {

// reads one study file: its keys in turn, each checked for its type
class StudyReader {
 public:
  explicit StudyReader(const std::string& path)
      : path_(path), folder_(std::filesystem::path(path).parent_path()) {}

  [[noreturn]] void fail(const std::string& msg) const { throw ConfigError(path_ + ": " + msg); }

  std::string text(const toml::node& node, const std::string& key) const {
    if (!node.is_string() || node.as_string()->get().empty()) {
      fail(key + ": must be a non-empty string");
    }
    return node.as_string()->get();
  }

  // a path relative to the study file's folder, resolved
  std::string file(const toml::node& node, const std::string& key) const {
    return resolve(text(node, key));
  }

  std::string resolve(const std::string& file) const {
    const std::filesystem::path p(file);
    return (p.is_absolute() ? p : folder_ / p).lexically_normal().string();
  }

  std::vector<std::string> texts(const toml::node& node, const std::string& key) const {
    if (!node.is_array() || node.as_array()->empty()) fail(key + ": must be a list of strings");
    std::vector<std::string> out;
    for (const auto& item : *node.as_array()) out.push_back(text(item, key + " item"));
    return out;
  }

  Axis axis(const toml::node& node) const {
    const std::string where = "[[sensitivity.axis]]";
    if (!node.is_table()) fail(where + ": must be a table");
    Axis axis;
    for (const auto& [k, value] : *node.as_table()) {
      const std::string key(k.str());
      if (key == "key") {
        axis.key = text(value, where + " key");
      } else if (key == "label") {
        axis.label = text(value, where + " label");
      } else if (key == "values" && value.is_array()) {
        for (const auto& v : *value.as_array()) {
          const auto x = detail::toml_scalar(v);
          if (!x) fail(where + " values: must be numbers or strings");
          axis.values.push_back(*x);
        }
      } else {
        fail(where + ": unknown or mistyped key '" + key + "' (keys: key, label, values)");
      }
    }
    if (axis.key.empty()) fail(where + ": missing key = \"dotted.config.key\"");
    if (axis.values.empty()) fail(where + " " + axis.key + ": values must not be empty");
    if (axis.label.empty()) axis.label = axis.key;
    return axis;
  }

  std::vector<Axis> sensitivity(const toml::node& node) const {
    if (!node.is_table()) fail("sensitivity: must be a table");
    std::vector<Axis> axes;
    for (const auto& [k, value] : *node.as_table()) {
      if (k.str() != "axis" || !value.is_array_of_tables()) {
        fail("[sensitivity]: unknown or mistyped key '" + std::string(k.str()) +
             "' (keys: [[sensitivity.axis]])");
      }
      for (const auto& item : *value.as_array()) axes.push_back(axis(item));
    }
    return axes;
  }

 private:
  std::string path_;
  std::filesystem::path folder_;
};

}  // namespace

std::string default_study_file() {
  return cli::data_dir() + "/studies/lochmatter2008/study.toml";
}

Study read_study(const std::string& path) {
  const toml::table table = detail::parse_toml_file(path, "study file");
  const StudyReader read(path);
  Study study;
  study.file = path;
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "name") {
      study.name = read.text(node, key);
    } else if (key == "presets") {
      study.presets_dir = read.file(node, key);
    } else if (key == "axes") {
      study.axes_dir = read.file(node, key);
    } else if (key == "sets") {
      for (const auto& f : read.texts(node, key)) study.set_files.push_back(read.resolve(f));
    } else if (key == "trajectory_sets") {
      study.trajectory_sets = read.texts(node, key);
    } else if (key == "radius") {
      study.radius_file = read.file(node, key);
    } else if (key == "sensitivity") {
      study.sensitivity_axes = read.sensitivity(node);
    } else {
      read.fail("unknown key '" + key +
                "' (keys: name, presets, axes, sets, trajectory_sets, radius, [sensitivity])");
    }
  }
  for (const char* required : {"name", "presets", "sets", "radius"}) {
    if (!table.contains(required)) read.fail(std::string("missing ") + required + " = ...");
  }
  if (study.sensitivity_axes.empty()) read.fail("missing [[sensitivity.axis]]");
  return study;
}

std::vector<SweepDef> read_sets(const Study& study) {
  std::vector<SweepDef> sets;
  for (const auto& f : study.set_files) sets.push_back(read_sweep_file(f));
  const std::vector<std::string> names = set_names(sets);
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(i), names[i]) !=
        names.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw ConfigError(study.file + ": sets: two sets are named '" + names[i] + "'");
    }
  }
  for (const auto& t : study.trajectory_sets) {
    if (std::find(names.begin(), names.end(), t) == names.end()) {
      throw ConfigError(study.file + ": trajectory_sets: no set is named '" + t + "'");
    }
  }
  return sets;
}

std::vector<std::string> set_names(const std::vector<SweepDef>& sets) {
  std::vector<std::string> names;
  for (const auto& s : sets) names.push_back(s.name);
  return names;
}

}  // namespace plumetrace
