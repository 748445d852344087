#include "plumetrace/io/trace_io.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <string_view>
#include <type_traits>
#include <utility>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/json_util.hpp"
#include "plumetrace/io/scenario_io.hpp"

namespace plumetrace {

using detail::csv_text;
using detail::number_or_null;
using detail::quantized_base64;
using detail::Quantizer;
using detail::result_json;
using detail::unbase64;
using nlohmann::json;

void check_trace_path(const std::string& path) {
  if (!ends_with(path, ".csv") && !ends_with(path, ".json")) {
    throw ConfigError("--trace '" + path + "': the name must end in .csv or .json");
  }
  std::vector<std::string> files{path};
  if (ends_with(path, ".csv")) files.push_back(path.substr(0, path.size() - 4) + ".filaments.csv");
  for (const auto& f : files) check_writable(f);
}

namespace {

// the trace format written; read_trace reads it and every earlier one
constexpr int kTraceFormat = 2;

// the columns of every snapshot, in the order of the file's keys
constexpr std::array<std::pair<const char*, std::vector<double> FilamentSnapshot::*>, 4>
    kFilamentColumns{{{"w", &FilamentSnapshot::w},
                      {"x", &FilamentSnapshot::x},
                      {"y", &FilamentSnapshot::y},
                      {"z", &FilamentSnapshot::z}}};

// why: 1e-6 m/s is far below any wind sensor's noise, and halves the digits of a meander's field
double wind_rounded(double v) { return std::round(v * 1e6) / 1e6; }

json rounded_winds(const std::vector<double>& values) {
  json out = json::array();
  for (const double v : values) out.push_back(wind_rounded(v));
  return out;
}

// the 16-bit code of one filament column over every snapshot of the trace
Quantizer column_quantizer(const Trace& trace, std::vector<double> FilamentSnapshot::*column) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& snap : trace.snapshots) {
    for (const double v : snap.*column) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  return Quantizer::over(lo, hi, 0.0);
}

// format 2: the steps as the run computed them (states as indices into their names), the
// filaments in 16 bits each over their range, the wind grid to 1e-6 m/s
void write_json_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                      const RunResult& result, const RunInfo& info) {
  std::vector<std::string> names;
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
             {"wind_z_body", json::array()},
             {"true_wind_x", json::array()},
             {"true_wind_y", json::array()}};
  for (const auto& s : trace.steps) {
    auto name = std::find(names.begin(), names.end(), s.state);
    if (name == names.end()) name = names.insert(names.end(), s.state);
    steps["time"].push_back(s.time);
    steps["x"].push_back(s.pose.x);
    steps["y"].push_back(s.pose.y);
    steps["heading"].push_back(s.pose.heading);
    steps["odometer"].push_back(s.odometer);
    steps["state"].push_back(name - names.begin());
    steps["odor"].push_back(s.odor ? 1 : 0);
    steps["concentration"].push_back(s.concentration);
    steps["wind_samples"].push_back(s.wind_samples);
    const bool sampled = s.wind_samples > 0;
    steps["wind_x_body"].push_back(sampled ? json(s.wind_body.x) : json(nullptr));
    steps["wind_y_body"].push_back(sampled ? json(s.wind_body.y) : json(nullptr));
    steps["wind_z_body"].push_back(sampled ? json(s.wind_body.z) : json(nullptr));
    steps["true_wind_x"].push_back(number_or_null(s.true_wind.x));
    steps["true_wind_y"].push_back(number_or_null(s.true_wind.y));
  }
  steps["state_names"] = names;

  json encoding = json::object();
  std::array<Quantizer, kFilamentColumns.size()> codes;
  for (std::size_t c = 0; c < kFilamentColumns.size(); ++c) {
    codes[c] = column_quantizer(trace, kFilamentColumns[c].second);
    encoding[kFilamentColumns[c].first] = {{"origin", codes[c].origin}, {"unit", codes[c].unit}};
  }

  // why: written a snapshot at a time, as the dump of the whole document would be (keys in
  // nlohmann's order), since the snapshots are most of it and a document of them all held
  // several times the trace's memory
  OutputFile file(path);
  auto& out = file.stream();
  out << R"({"config":)" << json::parse(scenario_to_json(scenario)).dump()
      << R"(,"plumetrace_trace":)" << kTraceFormat << R"(,"result":)"
      << result_json(result, info).dump() << R"(,"snapshot_encoding":)" << encoding.dump()
      << R"(,"snapshots":[)";
  for (std::size_t i = 0; i < trace.snapshots.size(); ++i) {
    const auto& snap = trace.snapshots[i];
    if (i > 0) out << ',';
    json j{{"time", snap.time},
           {"wind_x", rounded_winds(snap.wind_x)},
           {"wind_y", rounded_winds(snap.wind_y)}};
    for (std::size_t c = 0; c < kFilamentColumns.size(); ++c) {
      j[kFilamentColumns[c].first] = quantized_base64(codes[c], snap.*kFilamentColumns[c].second);
    }
    out << j.dump();
  }
  const WindGrid& g = trace.wind_grid;
  out << R"(],"steps":)" << steps.dump() << R"(,"wind_grid":)"
      << json{{"x0", g.x0}, {"dx", g.dx}, {"nx", g.nx}, {"y0", g.y0},
              {"dy", g.dy}, {"ny", g.ny}, {"z", g.z}}
             .dump()
      << "}\n";
  file.commit();
}

}  // namespace

void round_as_stored(Trace& trace) {
  for (const auto& [name, column] : kFilamentColumns) {
    const Quantizer code = column_quantizer(trace, column);
    for (auto& snap : trace.snapshots) {
      for (double& v : snap.*column) v = code.value(code(v));
    }
  }
  for (auto& snap : trace.snapshots) {
    for (double& v : snap.wind_x) v = wind_rounded(v);
    for (double& v : snap.wind_y) v = wind_rounded(v);
  }
}

void write_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                 const RunResult& result, const RunInfo& info) {
  if (ends_with(path, ".json")) {
    write_json_trace(path, trace, scenario, result, info);
    return;
  }
  if (!ends_with(path, ".csv")) {
    throw IoError("trace file '" + path + "': the name must end in .csv or .json");
  }
  OutputFile file(path);
  auto& out = file.stream();
  out << "time,x,y,heading,odometer,state,odor,concentration,wind_samples,wind_x_body,"
         "wind_y_body,wind_z_body\n";
  for (const auto& s : trace.steps) {
    out << s.time << ',' << s.pose.x << ',' << s.pose.y << ',' << s.pose.heading << ','
        << s.odometer << ',' << csv_text(s.state) << ',' << (s.odor ? 1 : 0) << ','
        << s.concentration << ',' << s.wind_samples << ',';
    if (s.wind_samples > 0) {
      out << s.wind_body.x << ',' << s.wind_body.y << ',' << s.wind_body.z << '\n';
    } else {
      out << ",,\n";
    }
  }
  const std::string snap_path = path.substr(0, path.size() - 4) + ".filaments.csv";
  OutputFile snap_file(snap_path);
  auto& snaps = snap_file.stream();
  snaps << "time,x,y,z,w\n";
  for (const auto& snap : trace.snapshots) {
    for (std::size_t i = 0; i < snap.x.size(); ++i) {
      snaps << snap.time << ',' << snap.x[i] << ',' << snap.y[i] << ',' << snap.z[i] << ','
            << snap.w[i] << '\n';
    }
  }
  // why: the two files are one trace: both are finished before either is put in place, so a
  // full disk leaves the previous pair (or none), never a trace without its filaments (F17)
  file.finish();
  snap_file.finish();
  snap_file.publish();
  try {
    file.publish();
  } catch (const IoError&) {
    std::remove(snap_path.c_str());
    throw;
  }
}

namespace {

// a config JSON object (nested by table) as settings of one layer, in file order
std::vector<Setting> config_settings(const json& config, const std::string& origin) {
  std::vector<Setting> settings;
  for (const auto& [table, keys] : config.items()) {
    for (const auto& [name, v] : keys.items()) {
      const std::string key = table + "." + name;
      if (v.is_boolean()) {
        settings.push_back({key, v.get<bool>(), false, origin, Layer::kFile});
      } else if (v.is_number_integer() &&
                 (!v.is_number_unsigned() ||
                  v.get<std::uint64_t>() <=
                      static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))) {
        settings.push_back({key, v.get<std::int64_t>(), false, origin, Layer::kFile});
      } else if (v.is_number()) {
        settings.push_back({key, v.get<double>(), false, origin, Layer::kFile});
      } else {
        // why: strings are parsed for the key's type, as "inf" is written for infinite numbers
        settings.push_back({key, v.get<std::string>(), true, origin, Layer::kFile});
      }
    }
  }
  return settings;
}

// a whole-number field of a trace, checked to lie in [lo, hi]; why: get<int>() wraps a number
// that does not fit, and truncates 1.5 (issue 13, F18)
template <class T>
T trace_integer(const json& v, const std::string& path, const std::string& field, T lo, T hi) {
  bool ok = false;
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    ok = std::cmp_greater_equal(u, lo) && std::cmp_less_equal(u, hi);
  } else if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    ok = std::cmp_greater_equal(i, lo) && std::cmp_less_equal(i, hi);
  }
  if (!ok) {
    throw ConfigError("trace '" + path + "': " + field + " must be a whole number from " +
                      std::to_string(lo) + " to " + std::to_string(hi) + " (got " + v.dump() + ")");
  }
  return v.get<T>();
}

double number_or_nan(const json& v) {
  return v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
}

// the true wind of a trace that did not record it (format 1): the scenario's mean wind where its
// field is steady (the mean everywhere and always: its registration says), unknown (NaN)
// otherwise
Vec2 unrecorded_true_wind(const WindParams& wind) {
  if (!wind_is_steady(wind)) return {NAN, NAN};
  return {wind.velocity.x, wind.velocity.y};
}

void read_steps(const json& st, int format, const std::string& path, RecordedRun& run) {
  constexpr auto kInt = std::numeric_limits<int>::max();
  const std::size_t n = st.at("time").size();
  std::vector<std::string> columns{"x",           "y",           "heading",       "odometer",
                                   "state",       "odor",        "concentration", "wind_samples",
                                   "wind_x_body", "wind_y_body", "wind_z_body"};
  // why: format 1 has no true wind, and a trace of format 2 written from one may lack it too
  const bool true_wind = st.contains("true_wind_x") || st.contains("true_wind_y");
  if (true_wind) columns.insert(columns.end(), {"true_wind_x", "true_wind_y"});
  for (const auto& column : columns) {
    if (st.at(column).size() != n) {
      throw ConfigError("trace '" + path + "': column '" + column + "' has " +
                        std::to_string(st.at(column).size()) + " rows, 'time' has " +
                        std::to_string(n));
    }
  }
  if (n == 0) throw ConfigError("trace '" + path + "': no steps");
  std::vector<std::string> names;
  if (format >= 2) names = st.at("state_names").get<std::vector<std::string>>();
  // why: each step holds its state's name; a 1 MB name took 4.8 GB to view (issue 22, G8)
  const auto check_name = [&](const std::string& name, const std::string& field) {
    try {
      check_state_name(name);
    } catch (const ConfigError& e) {
      throw ConfigError("trace '" + path + "': " + field + ": " + e.what());
    }
  };
  for (std::size_t k = 0; k < names.size(); ++k) {
    check_name(names[k], "steps.state_names[" + std::to_string(k) + "]");
  }
  const Vec2 unrecorded = unrecorded_true_wind(run.scenario.wind);
  run.trace.steps.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::string row = "[";
    row += std::to_string(i);
    row += ']';
    TraceStep& s = run.trace.steps[i];
    // why: a number too large for a double parses as infinity; drawn, it overflows the page
    const auto finite = [&](const char* column) {
      const double v = st[column][i].get<double>();
      if (!std::isfinite(v)) {
        throw ConfigError("trace '" + path + "': steps." + column + row + " is not finite");
      }
      return v;
    };
    s.time = finite("time");
    s.pose = {finite("x"), finite("y"), finite("heading")};
    s.odometer = finite("odometer");
    if (format >= 2) {
      if (names.empty()) throw ConfigError("trace '" + path + "': steps.state_names is empty");
      s.state = names[trace_integer<std::size_t>(st["state"][i], path, "steps.state" + row, 0,
                                                 names.size() - 1)];
    } else {
      s.state = st["state"][i].get<std::string>();
      check_name(s.state, "steps.state" + row);
    }
    const json& odor = st["odor"][i];
    s.odor = odor.is_boolean() ? odor.get<bool>()
                               : trace_integer<int>(odor, path, "steps.odor" + row, 0, 1) == 1;
    s.concentration = st["concentration"][i].get<double>();
    s.wind_samples =
        trace_integer<int>(st["wind_samples"][i], path, "steps.wind_samples" + row, 0, kInt);
    if (s.wind_samples > 0) {
      s.wind_body = {st["wind_x_body"][i].get<double>(), st["wind_y_body"][i].get<double>(),
                     st["wind_z_body"][i].get<double>()};
    }
    s.true_wind =
        true_wind ? Vec2{number_or_nan(st["true_wind_x"][i]), number_or_nan(st["true_wind_y"][i])}
                  : unrecorded;
  }
}

void check_snapshot(const FilamentSnapshot& f, const std::string& path) {
  if (f.y.size() != f.x.size() || f.z.size() != f.x.size() || f.w.size() != f.x.size()) {
    throw ConfigError("trace '" + path + "': a filament snapshot has columns of unequal length");
  }
}

// format 1: every column a JSON array of numbers
void read_snapshots_1(const json& snapshots, const std::string& path, Trace& trace) {
  for (const auto& snap : snapshots) {
    FilamentSnapshot f;
    f.time = snap.at("time").get<double>();
    for (const auto& [name, column] : kFilamentColumns) {
      f.*column = snap.at(name).get<std::vector<double>>();
    }
    // why: traces of 0.3.0 carry no wind field
    if (snap.contains("wind_x")) {
      f.wind_x = snap.at("wind_x").get<std::vector<double>>();
      f.wind_y = snap.at("wind_y").get<std::vector<double>>();
    }
    check_snapshot(f, path);
    trace.snapshots.push_back(std::move(f));
  }
}

// format 2: each filament column 16-bit words in base64, decoded by the trace's encoding
void read_snapshots_2(const json& snapshots, const json& encoding, const std::string& path,
                      Trace& trace) {
  std::array<Quantizer, kFilamentColumns.size()> codes;
  for (std::size_t c = 0; c < kFilamentColumns.size(); ++c) {
    const json& e = encoding.at(kFilamentColumns[c].first);
    codes[c] = {e.at("origin").get<double>(), e.at("unit").get<double>()};
    // why: every code must decode to a finite number; unit 1e308 drew coordinates of infinity
    // (issue 22, G17)
    if (!std::isfinite(codes[c].origin) || !(codes[c].unit > 0.0) ||
        !std::isfinite(codes[c].value(0)) || !std::isfinite(codes[c].value(0xffff))) {
      throw ConfigError("trace '" + path + "': snapshot_encoding." + kFilamentColumns[c].first +
                        " must have a finite origin and a positive unit whose 65536 codes decode "
                        "to finite numbers");
    }
  }
  std::vector<std::uint8_t> bytes;
  for (const auto& snap : snapshots) {
    FilamentSnapshot f;
    f.time = snap.at("time").get<double>();
    for (std::size_t c = 0; c < kFilamentColumns.size(); ++c) {
      const auto& [name, column] = kFilamentColumns[c];
      if (!unbase64(snap.at(name).get<std::string>(), bytes) || bytes.size() % 2 != 0) {
        throw ConfigError("trace '" + path + "': a filament snapshot's '" + name +
                          "' is not base64 of 16-bit words");
      }
      auto& values = f.*column;
      values.resize(bytes.size() / 2);
      for (std::size_t k = 0; k < values.size(); ++k) {
        values[k] =
            codes[c].value(static_cast<std::uint16_t>(bytes[2 * k] | bytes[2 * k + 1] << 8));
      }
    }
    f.wind_x = snap.at("wind_x").get<std::vector<double>>();
    f.wind_y = snap.at("wind_y").get<std::vector<double>>();
    check_snapshot(f, path);
    trace.snapshots.push_back(std::move(f));
  }
}

}  // namespace

RecordedRun read_trace(const std::string& path) {
  if (ends_with(path, ".csv")) {
    throw ConfigError("trace '" + path +
                      "': a CSV trace carries no configuration; write the trace as .json "
                      "(plumetrace run --trace run.json)");
  }
  std::string text, why;
  if (!read_regular_file(path, text, why, kMaxTraceBytes)) {
    throw IoError("cannot read trace '" + path + "': " + why);
  }
  RecordedRun run;
  try {
    const json doc = json::parse(text);
    if (!doc.is_object() || !doc.contains("plumetrace_trace")) {
      throw ConfigError("trace '" + path + "': not a plumetrace trace (no 'plumetrace_trace' key)");
    }
    const int format = trace_integer<int>(doc.at("plumetrace_trace"), path, "plumetrace_trace", 1,
                                          std::numeric_limits<int>::max());
    if (format > kTraceFormat) {
      throw ConfigError("trace '" + path + "': trace format " + std::to_string(format) +
                        " is newer than plumetrace " + std::string(version()) + " reads (1 to " +
                        std::to_string(kTraceFormat) + ")");
    }
    run.scenario = build_scenario(config_settings(doc.at("config"), path));

    const json& r = doc.at("result");
    constexpr auto kU64 = std::numeric_limits<std::uint64_t>::max();
    run.info = {r.at("algorithm").get<std::string>(),
                trace_integer<std::uint64_t>(r.at("seed"), path, "result.seed", 0, kU64),
                trace_integer<std::uint64_t>(r.at("trial"), path, "result.trial", 0, kU64)};
    run.version = r.at("version").get<std::string>();
    RunResult::fields(run.result, [&](const ResultField& f, auto&& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if constexpr (!kDerivedField<decltype(value)>) {
        const json& v = r.at(std::string(f.name));
        if constexpr (std::is_same_v<T, Outcome>) {
          value = parse_outcome(v.get<std::string>());
        } else if constexpr (std::is_floating_point_v<T>) {
          value = f.nullable ? number_or_nan(v) : v.get<double>();
        } else {
          value = trace_integer<T>(v, path, "result." + std::string(f.name), 0,
                                   std::numeric_limits<T>::max());
        }
      }
    });
    run.result.seed = run.info.seed;
    run.result.trial = run.info.trial;

    read_steps(doc.at("steps"), format, path, run);
    if (format == 1) {
      read_snapshots_1(doc.at("snapshots"), path, run.trace);
    } else {
      read_snapshots_2(doc.at("snapshots"), doc.at("snapshot_encoding"), path, run.trace);
    }
    if (doc.contains("wind_grid")) {
      const json& g = doc.at("wind_grid");
      WindGrid& grid = run.trace.wind_grid;
      grid.x0 = g.at("x0").get<double>();
      grid.dx = g.at("dx").get<double>();
      grid.y0 = g.at("y0").get<double>();
      grid.dy = g.at("dy").get<double>();
      grid.z = g.at("z").get<double>();
      for (const double v : {grid.x0, grid.dx, grid.y0, grid.dy, grid.z}) {
        if (!std::isfinite(v)) throw ConfigError("wind_grid: x0, dx, y0, dy and z must be finite");
      }
      // why: a viewer loops over the nodes; a damaged count must not make it loop for ever
      grid.nx = trace_integer<int>(g.at("nx"), path, "wind_grid.nx", 0, 100000);
      grid.ny = trace_integer<int>(g.at("ny"), path, "wind_grid.ny", 0, 100000);
    }
    for (const auto& f : run.trace.snapshots) {
      if (f.wind_y.size() != f.wind_x.size() ||
          (!f.wind_x.empty() && f.wind_x.size() != run.trace.wind_grid.size())) {
        throw ConfigError("trace '" + path +
                          "': a snapshot's wind does not match the trace's wind_grid");
      }
    }
  } catch (const json::exception& e) {
    throw ConfigError("trace '" + path + "': not a valid plumetrace trace (" + e.what() + ")");
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    if (what.rfind("trace '", 0) == 0) throw;
    throw ConfigError("trace '" + path + "': " + what);
  }
  return run;
}

}  // namespace plumetrace
