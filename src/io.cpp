#include "plumetrace/io.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "plumetrace/version.hpp"

namespace plumetrace {

namespace {

using nlohmann::json;

void flatten(const toml::table& table, const std::string& prefix, const std::string& path,
             std::vector<Setting>& out) {
  for (const auto& [k, node] : table) {
    const std::string key = prefix + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      flatten(*sub, key + ".", path, out);
    } else if (const auto* i = node.as_integer()) {
      out.push_back({key, static_cast<std::int64_t>(i->get()), false, path});
    } else if (const auto* d = node.as_floating_point()) {
      out.push_back({key, d->get(), false, path});
    } else if (const auto* s = node.as_string()) {
      out.push_back({key, s->get(), false, path});
    } else if (const auto* b = node.as_boolean()) {
      out.push_back({key, b->get(), false, path});
    } else {
      // why: let the key's own check reject it, so the message names the key and its range
      // (or says the key is unknown)
      out.push_back(
          {key, std::string(node.is_array() ? "<array>" : "<date or time>"), false, path});
    }
  }
}

json value_to_json(const ConfigValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::ofstream open_for_writing(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw IoError("cannot write '" + path + "'");
  out.precision(17);
  return out;
}

void check_written(std::ofstream& out, const std::string& path) {
  out.flush();
  if (!out) throw IoError("error while writing '" + path + "'");
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

json result_json(const RunResult& r, const RunInfo& info) {
  return json{{"algorithm", info.algorithm},
              {"outcome", std::string(outcome_name(r.outcome))},
              {"success", r.outcome == Outcome::kSuccess},
              {"time_s", r.time},
              {"d_t", r.d_t},
              {"d_u", r.d_u},
              {"overhead", number_or_null(r.overhead)},
              {"losses", r.losses},
              {"odor_fraction", r.odor_fraction},
              {"steps", r.steps},
              {"wind_samples", r.wind_samples},
              {"seed", info.seed},
              {"trial", info.trial},
              {"version", std::string(version())}};
}

}  // namespace

std::string_view version() { return kVersion; }

std::vector<Setting> read_scenario_file(const std::string& path) {
  std::error_code ec;
  std::ifstream in(path);
  if (!std::filesystem::is_regular_file(path, ec) || !in) {
    throw ConfigError("cannot read scenario file '" + path + "'");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw ConfigError("cannot read scenario file '" + path + "'");
  toml::table table;
  try {
    table = toml::parse(buffer.str(), path);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << path << ":" << e.source().begin.line << ":" << e.source().begin.column
        << ": invalid TOML: " << e.description();
    throw ConfigError(msg.str());
  }
  std::vector<Setting> settings;
  flatten(table, "", path, settings);
  return settings;
}

Scenario load_scenario(const std::string& path, const std::vector<Setting>& overrides) {
  std::vector<Setting> settings;
  if (!path.empty()) settings = read_scenario_file(path);
  settings.insert(settings.end(), overrides.begin(), overrides.end());
  return build_scenario(settings);
}

std::string scenario_to_toml(const Scenario& scenario) {
  Scenario copy = scenario;
  std::ostringstream out;
  std::string table;
  for (const auto& f : scenario_fields(copy)) {
    const auto dot = f.key.find('.');
    const std::string t = f.key.substr(0, dot);
    if (t != table) {
      out << (table.empty() ? "" : "\n") << "[" << t << "]\n";
      table = t;
    }
    const ConfigValue v = get_field(scenario, f.key);
    std::string text = std::holds_alternative<std::string>(v)
                           ? "\"" + std::get<std::string>(v) + "\""
                           : format_value(v);
    out << f.key.substr(dot + 1) << " = " << text << "  # " << f.help << "\n";
  }
  return out.str();
}

std::string scenario_to_json(const Scenario& scenario) {
  Scenario copy = scenario;
  json j = json::object();
  for (const auto& f : scenario_fields(copy)) {
    const auto dot = f.key.find('.');
    const ConfigValue v = get_field(scenario, f.key);
    const double* d = std::get_if<double>(&v);
    j[f.key.substr(0, dot)][f.key.substr(dot + 1)] =
        d && std::isinf(*d) ? json(format_number(*d)) : value_to_json(v);
  }
  return j.dump(2);
}

std::string result_to_json(const RunResult& result, const RunInfo& info) {
  return result_json(result, info).dump();
}

std::string probe_to_json(const std::vector<ProbeResult>& results) {
  json points = json::array();
  for (const auto& r : results) {
    points.push_back({{"x", r.point.x},
                      {"y", r.point.y},
                      {"z", r.point.z},
                      {"detect_fraction", r.detect_fraction},
                      {"mean_concentration", r.mean_concentration},
                      {"samples", r.samples}});
  }
  return json{{"points", points}}.dump();
}

void check_trace_path(const std::string& path) {
  if (!ends_with(path, ".csv") && !ends_with(path, ".json")) {
    throw ConfigError("--trace '" + path + "': the name must end in .csv or .json");
  }
  std::vector<std::string> files{path};
  if (ends_with(path, ".csv")) files.push_back(path.substr(0, path.size() - 4) + ".filaments.csv");
  for (const auto& f : files) open_for_writing(f);
}

void write_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                 const RunResult& result, const RunInfo& info) {
  if (ends_with(path, ".json")) {
    json steps{{"time", json::array()},
               {"x", json::array()},
               {"y", json::array()},
               {"heading", json::array()},
               {"odometer", json::array()},
               {"state", json::array()},
               {"odor", json::array()},
               {"concentration", json::array()},
               {"wind_samples", json::array()},
               {"wind_x_body", json::array()},
               {"wind_y_body", json::array()},
               {"wind_z_body", json::array()}};
    for (const auto& s : trace.steps) {
      steps["time"].push_back(s.time);
      steps["x"].push_back(s.pose.x);
      steps["y"].push_back(s.pose.y);
      steps["heading"].push_back(s.pose.heading);
      steps["odometer"].push_back(s.odometer);
      steps["state"].push_back(s.state);
      steps["odor"].push_back(s.odor);
      steps["concentration"].push_back(s.concentration);
      steps["wind_samples"].push_back(s.wind_samples);
      const bool sampled = s.wind_samples > 0;
      steps["wind_x_body"].push_back(sampled ? json(s.wind_body.x) : json(nullptr));
      steps["wind_y_body"].push_back(sampled ? json(s.wind_body.y) : json(nullptr));
      steps["wind_z_body"].push_back(sampled ? json(s.wind_body.z) : json(nullptr));
    }
    json snapshots = json::array();
    for (const auto& snap : trace.snapshots) {
      snapshots.push_back(
          {{"time", snap.time}, {"x", snap.x}, {"y", snap.y}, {"z", snap.z}, {"w", snap.w}});
    }
    const json doc{{"plumetrace_trace", 1},
                   {"config", json::parse(scenario_to_json(scenario))},
                   {"result", result_json(result, info)},
                   {"steps", steps},
                   {"snapshots", snapshots}};
    auto out = open_for_writing(path);
    out << doc.dump() << "\n";
    check_written(out, path);
    return;
  }
  if (!ends_with(path, ".csv")) {
    throw IoError("trace file '" + path + "': the name must end in .csv or .json");
  }
  auto out = open_for_writing(path);
  out << "time,x,y,heading,odometer,state,odor,concentration,wind_samples,wind_x_body,"
         "wind_y_body,wind_z_body\n";
  for (const auto& s : trace.steps) {
    out << s.time << ',' << s.pose.x << ',' << s.pose.y << ',' << s.pose.heading << ','
        << s.odometer << ',' << s.state << ',' << (s.odor ? 1 : 0) << ',' << s.concentration << ','
        << s.wind_samples << ',';
    if (s.wind_samples > 0) {
      out << s.wind_body.x << ',' << s.wind_body.y << ',' << s.wind_body.z << '\n';
    } else {
      out << ",,\n";
    }
  }
  check_written(out, path);

  const std::string snap_path = path.substr(0, path.size() - 4) + ".filaments.csv";
  auto snaps = open_for_writing(snap_path);
  snaps << "time,x,y,z,w\n";
  for (const auto& snap : trace.snapshots) {
    for (std::size_t i = 0; i < snap.x.size(); ++i) {
      snaps << snap.time << ',' << snap.x[i] << ',' << snap.y[i] << ',' << snap.z[i] << ','
            << snap.w[i] << '\n';
    }
  }
  check_written(snaps, snap_path);
}

}  // namespace plumetrace
