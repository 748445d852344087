#include "lochmatter2008/axes.hpp"

#include <algorithm>
#include <filesystem>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

std::vector<std::string> axis_reading_names(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

AxisReading read_axis_reading(const std::string& folder, const std::string& name,
                              const std::vector<SweepDef>& sets) {
  AxisReading reading;
  reading.name = name;
  if (name == kSetsAxes) {
    reading.title = "the set files' axes (version 0.3.0)";
    return reading;
  }
  const auto known = axis_reading_names(folder);
  if (std::find(known.begin(), known.end(), name) == known.end()) {
    std::string list = kSetsAxes;
    for (const auto& n : known) list += ", " + n;
    throw ConfigError("--axes: unknown axis reading '" + name + "' (axis readings: " + list +
                      "; files " + folder + "/NAME.toml)");
  }
  reading.file = (std::filesystem::path(folder) / (name + ".toml")).string();
  const toml::table table = detail::parse_toml_file(reading.file, "axis reading");
  const auto fail = [&](const std::string& msg) { throw ConfigError(reading.file + ": " + msg); };
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "title") {
      if (!node.is_string() || node.as_string()->get().empty()) {
        fail("title: must be a non-empty string");
      }
      reading.title = node.as_string()->get();
      continue;
    }
    const auto set = std::find_if(sets.begin(), sets.end(),
                                  [&](const SweepDef& s) { return s.name == key; });
    if (set == sets.end() || !node.is_table()) {
      fail("unknown key '" + key + "' (keys: title, and a table per experiment set)");
    }
    if (set->axes.size() != 1) fail("[" + key + "]: the set has more than one axis");
    Axis axis = set->axes.front();
    axis.values.clear();
    axis.fixed.reset();
    for (const auto& [ak, anode] : *node.as_table()) {
      const std::string akey(ak.str());
      if (akey == "values" && anode.is_array()) {
        for (const auto& v : *anode.as_array()) {
          const auto x = detail::toml_scalar(v);
          if (!x || std::holds_alternative<std::string>(*x) ||
              std::holds_alternative<bool>(*x)) {
            fail("[" + key + "] values: must be numbers");
          }
          axis.values.push_back(*x);
        }
      } else if (akey == "fixed" && detail::toml_scalar(anode)) {
        axis.fixed = detail::toml_scalar(anode);
      } else {
        fail("[" + key + "]: unknown or mistyped key '" + akey + "' (keys: values, fixed)");
      }
    }
    const auto number = [](const ConfigValue& v) {
      const auto* i = std::get_if<std::int64_t>(&v);
      return i ? static_cast<double>(*i) : std::get<double>(v);
    };
    if (axis.values.size() < 2) fail("[" + key + "] values: give at least two");
    for (std::size_t i = 1; i < axis.values.size(); ++i) {
      if (!(number(axis.values[i - 1]) < number(axis.values[i]))) {
        fail("[" + key + "] values: must be increasing");
      }
    }
    if (axis.fixed &&
        std::none_of(axis.values.begin(), axis.values.end(),
                     [&](const ConfigValue& v) { return number(v) == number(*axis.fixed); })) {
      fail("[" + key + "] fixed: must be one of the values");
    }
    reading.axes[key] = std::move(axis);
  }
  if (reading.title.empty()) fail("title: missing");
  if (reading.axes.empty()) fail("no set's axis is given");
  return reading;
}

std::string axis_sweep_name(const std::string& reading, const std::string& set) {
  return "@" + reading + "/" + set;
}

std::vector<SweepDef> axis_reading_sets(const std::vector<SweepDef>& sets,
                                        const AxisReading& reading) {
  std::vector<SweepDef> out;
  for (const SweepDef& set : sets) {
    const auto it = reading.axes.find(set.name);
    if (it == reading.axes.end()) continue;
    SweepDef def = set;
    def.name = axis_sweep_name(reading.name, set.name);
    def.axes = {it->second};
    out.push_back(std::move(def));
  }
  return out;
}

}  // namespace plumetrace
