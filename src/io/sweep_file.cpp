#include "plumetrace/io/sweep_file.hpp"

#include <filesystem>
#include <optional>

#include "plumetrace/core/files.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

using detail::flatten;
using detail::parse_toml_file;

using detail::toml_scalar;

SweepDef read_sweep_file(const std::string& path) {
  const toml::table table = parse_toml_file(path, "sweep file");
  SweepDef def;
  def.file = path;
  const auto fail = [&](const std::string& msg) { throw ConfigError(path + ": " + msg); };
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (const auto& [k, node] : table) {
    const std::string key(k.str());
    if (key == "name" && node.is_string()) {
      def.name = node.as_string()->get();
    } else if (key == "title" && node.is_string()) {
      def.title = node.as_string()->get();
    } else if (key == "scenario" && node.is_string()) {
      const std::filesystem::path p(node.as_string()->get());
      def.scenario_path = (p.is_absolute() ? p : folder / p).lexically_normal().string();
    } else if (key == "runs" && node.is_integer()) {
      const auto runs = node.as_integer()->get();
      if (runs < 1 || runs > kMaxCampaignRuns) {
        fail("runs: must be an integer >= 1 and <= " + std::to_string(kMaxCampaignRuns) + " (got " +
             std::to_string(runs) + ")");
      }
      def.runs = static_cast<int>(runs);
    } else if (key == "seed" && node.is_integer()) {
      const auto seed = node.as_integer()->get();
      if (seed < 0) fail("seed: must be an integer >= 0");
      def.seed = static_cast<std::uint64_t>(seed);
    } else if (key == "set" && node.is_table()) {
      flatten(*node.as_table(), "", path + ": [set]", Layer::kSweep, def.settings);
    } else if (key == "axis" && node.is_array_of_tables()) {
      for (const auto& item : *node.as_array()) {
        Axis axis;
        for (const auto& [ak, anode] : *item.as_table()) {
          const std::string akey(ak.str());
          if (akey == "key" && anode.is_string()) {
            axis.key = anode.as_string()->get();
          } else if (akey == "label" && anode.is_string()) {
            axis.label = anode.as_string()->get();
          } else if (akey == "fixed" && toml_scalar(anode)) {
            axis.fixed = toml_scalar(anode);
          } else if (akey == "values" && anode.is_array()) {
            for (const auto& v : *anode.as_array()) {
              const auto value = toml_scalar(v);
              if (!value) fail("axis values must be numbers or strings");
              axis.values.push_back(*value);
            }
          } else {
            fail("[[axis]]: unknown or mistyped key '" + akey +
                 "' (keys: key = \"dotted.key\", values = [...], label, fixed)");
          }
        }
        if (axis.key.empty()) fail("[[axis]]: missing key = \"dotted.config.key\"");
        if (axis.label.empty()) axis.label = axis.key;
        def.axes.push_back(std::move(axis));
      }
    } else {
      fail("unknown or mistyped key '" + key +
           "' (keys: name, title, scenario, runs, seed, [set], [[axis]])");
    }
  }
  check_sweep_def(def, path);
  if (!def.scenario_path.empty()) def.scenario_settings = read_scenario_file(def.scenario_path);
  return def;
}

void check_sweep_def(const SweepDef& def, const std::string& where) {
  const auto fail = [&](const std::string& msg) { throw ConfigError(where + ": " + msg); };
  for (std::size_t a = 0; a < def.axes.size(); ++a) {
    const Axis& axis = def.axes[a];
    if (axis.key.empty()) fail("an axis has no key (a dotted config key)");
    if (axis.values.empty()) fail("axis " + axis.key + ": values must not be empty");
    for (std::size_t b = 0; b < a; ++b) {
      if (def.axes[b].key == axis.key) fail("axis " + axis.key + " is given twice");
    }
  }
  if (def.name.empty()) fail("missing name = \"...\"");
  // why: names, titles and labels reach terminals, CSV and HTML (issue 22, G14)
  check_printable(def.name, where, "name");
  check_printable(def.title, where, "title");
  for (const auto& axis : def.axes)
    check_printable(axis.label, where, "axis " + axis.key + ": label");
  if (def.axes.empty()) fail("no [[axis]]: a sweep varies at least one key");
  // unknown axis keys and values of the wrong type are found here, naming the axis
  Scenario probe;
  for (const auto& axis : def.axes) {
    for (const auto& v : axis.values) {
      try {
        set_field(probe, axis.key, v, where + ": axis " + axis.key);
      } catch (const ConfigError& e) {
        fail("axis " + axis.key + ": " + e.what());
      }
    }
  }
}

}  // namespace plumetrace
