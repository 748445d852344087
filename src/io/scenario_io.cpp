#include "plumetrace/io/scenario_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "plumetrace/io/json_util.hpp"
#include "plumetrace/io/toml_input.hpp"

namespace plumetrace {

using detail::flatten;
using detail::parse_toml_file;
using detail::value_to_json;
using nlohmann::json;

std::vector<Setting> read_scenario_file(const std::string& path) {
  const toml::table table = parse_toml_file(path, "scenario file");
  std::vector<Setting> settings;
  flatten(table, "", path, Layer::kFile, settings);
  return settings;
}

std::vector<std::string> preset_names(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) return names;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const auto& path = entry.path();
    if (entry.is_regular_file(ec) && path.extension() == ".toml") {
      names.push_back(path.stem().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

Reading read_reading(const std::string& folder, const std::string& name) {
  Reading reading{name, "", {}};
  if (name == kDefaultReading) return reading;
  const auto names = preset_names(folder);
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string known = kDefaultReading;
    for (const auto& n : names) known += ", " + n;
    throw ConfigError("unknown preset '" + name + "' (presets: " + known + "; files " + folder +
                      "/NAME.toml)");
  }
  reading.file = folder + "/" + name + ".toml";
  const toml::table table = parse_toml_file(reading.file, "preset file");
  flatten(table, "", reading.file, Layer::kCommandLine, reading.settings);
  // every key and value checked now, naming the file, before any run
  build_scenario(reading.settings);
  return reading;
}

Scenario load_scenario(const std::string& path, const std::vector<Setting>& overrides) {
  std::vector<Setting> settings;
  if (!path.empty()) settings = read_scenario_file(path);
  settings.insert(settings.end(), overrides.begin(), overrides.end());
  return build_scenario(settings);
}

std::string scenario_to_json(const Scenario& scenario) {
  json j = json::object();
  for_each_value(scenario, [&j](const FieldValue& f) {
    const double* d = std::get_if<double>(&f.value);
    // why: nested at every dot, so a robot's own table "member.2.controller" is
    // {"member": {"2": {"controller": ...}}}, as TOML reads [member.2.controller]
    json* node = &j;
    std::string_view table = f.table;
    for (std::size_t dot; (dot = table.find('.')) != std::string_view::npos;
         table.remove_prefix(dot + 1)) {
      node = &(*node)[std::string(table.substr(0, dot))];
    }
    (*node)[std::string(table)][std::string(f.name)] =
        d && std::isinf(*d) ? json(format_number(*d)) : value_to_json(f.value);
  });
  return j.dump(2);
}

}  // namespace plumetrace
