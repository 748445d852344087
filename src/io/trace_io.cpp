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
  if (ends_with(path, ".csv")) {
    const std::string stem = path.substr(0, path.size() - 4);
    files.push_back(stem + ".filaments.csv");
    files.push_back(stem + ".controller.csv");
  }
  for (const auto& f : files) check_writable(f);
}

namespace {

// the trace format written; read_trace reads it and every earlier one
constexpr int kTraceFormat = 3;

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

// one robot's steps as columns (TraceStep::fields), exactly as the run computed them; a state is
// an index into "state_names"
json steps_json(const std::vector<TraceStep>& steps) {
  json table = json::object();
  for (const TraceField& f : trace_fields()) table[std::string(f.name)] = json::array();
  std::vector<std::string> names;
  for (const auto& s : steps) {
    TraceStep::fields(s, [&](const TraceField& f, const auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      json& column = table[std::string(f.name)];
      if constexpr (std::is_same_v<T, std::string>) {
        auto name = std::find(names.begin(), names.end(), value);
        if (name == names.end()) name = names.insert(names.end(), value);
        column.push_back(name - names.begin());
      } else if constexpr (std::is_same_v<T, bool>) {
        column.push_back(value ? 1 : 0);
      } else if constexpr (std::is_floating_point_v<T>) {
        if (f.sampled && s.wind_samples <= 0) {
          column.push_back(nullptr);
        } else {
          column.push_back(f.nullable ? number_or_null(value) : json(value));
        }
      } else {
        column.push_back(value);
      }
    });
  }
  table["state_names"] = names;
  return table;
}

json pose_json(const Pose& p) { return {{"x", p.x}, {"y", p.y}, {"heading", p.heading}}; }

json declared_json(const Vec2& d) {
  return std::isfinite(d.x) && std::isfinite(d.y) ? json::array({d.x, d.y}) : json(nullptr);
}

// a robot's result, with its index in the team and, in a mixed team, its own algorithm
json agent_result_json(const RunResult& result, const RunInfo& info, int agent,
                       const Scenario& scenario) {
  json r = result_json(result, info);
  r["agent"] = agent;
  if (std::string own = own_algorithm(scenario, agent); !own.empty()) r["algorithm"] = own;
  return r;
}

json points_json(const std::vector<Vec2>& points) {
  json x = json::array(), y = json::array();
  for (const Vec2& p : points) x.push_back(number_or_null(p.x)), y.push_back(number_or_null(p.y));
  return {{"x", std::move(x)}, {"y", std::move(y)}};
}

json numbers_json(const std::vector<double>& values) {
  json out = json::array();
  for (const double v : values) out.push_back(number_or_null(v));
  return out;
}

// a controller's snapshot: the parts it has, the start pose left to its robot's table
json controller_snapshot_json(const ControllerSnapshot& c) {
  const Snapshot& s = c.snapshot;
  json j{{"time", c.time}, {"agent", c.agent}};
  if (!s.points.empty()) j["points"] = points_json(s.points);
  if (!s.weights.empty()) j["weights"] = numbers_json(s.weights);
  if (!s.path.empty()) j["path"] = points_json(s.path);
  if (!s.grid.empty()) {
    j["grid"] = {{"x0", s.x0},
                 {"y0", s.y0},
                 {"dx", s.dx},
                 {"dy", s.dy},
                 {"nx", s.nx},
                 {"ny", s.ny},
                 {"values", numbers_json(s.grid)}};
  }
  if (s.has_estimate) j["estimate"] = {number_or_null(s.estimate.x), number_or_null(s.estimate.y)};
  return j;
}

// format 3: robot 0's table at the top (as formats 1 and 2), its teammates' in "teammates", the
// steps as the run computed them, the filaments in 16 bits each over their range, the wind grid
// to 1e-6 m/s, the controllers' snapshots as numbers
void write_json_trace(const std::string& path, const Trace& trace, const Scenario& scenario,
                      const RunResult& result, const RunInfo& info) {
  static const AgentTrace kNobody;
  const AgentTrace& first = trace.agents.empty() ? kNobody : trace.agents.front();
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
      << R"(,"controller_snapshots":[)";
  for (std::size_t i = 0; i < trace.controller_snapshots.size(); ++i) {
    if (i > 0) out << ',';
    out << controller_snapshot_json(trace.controller_snapshots[i]).dump();
  }
  out << R"(],"declared":)" << declared_json(first.declared).dump() << R"(,"plumetrace_trace":)"
      << kTraceFormat << R"(,"result":)"
      << agent_result_json(result, info, result.agent, scenario).dump()
      << R"(,"snapshot_encoding":)" << encoding.dump() << R"(,"snapshots":[)";
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
  out << R"(],"start":)" << pose_json(first.start).dump() << R"(,"steps":)"
      << steps_json(first.steps).dump() << R"(,"teammates":[)";
  for (std::size_t k = 1; k < trace.agents.size(); ++k) {
    const AgentTrace& a = trace.agents[k];
    if (k > 1) out << ',';
    out << json{{"agent", a.index},
                {"declared", declared_json(a.declared)},
                {"result", agent_result_json(a.result, info, a.index, scenario)},
                {"start", pose_json(a.start)},
                {"steps", steps_json(a.steps)}}
               .dump();
  }
  const WindGrid& g = trace.wind_grid;
  out << R"(],"wind_grid":)"
      << json{{"x0", g.x0}, {"dx", g.dx}, {"nx", g.nx}, {"y0", g.y0},
              {"dy", g.dy}, {"ny", g.ny}, {"z", g.z}}
             .dump()
      << "}\n";
  file.commit();
}

// a CSV field of a step column: empty where the value is null in JSON
void write_csv_field(std::ostream& out, const TraceField& f, const TraceStep& s, double v) {
  if ((f.sampled && s.wind_samples <= 0) || (f.nullable && !std::isfinite(v))) return;
  out << v;
}

// the steps of every robot as one table, robot by robot: its index, then the step columns
void write_csv_steps(std::ostream& out, const Trace& trace) {
  out << "agent";
  for (const TraceField& f : trace_fields()) out << ',' << f.name;
  out << '\n';
  for (const AgentTrace& a : trace.agents) {
    for (const TraceStep& s : a.steps) {
      out << a.index;
      TraceStep::fields(s, [&](const TraceField& f, const auto& value) {
        using T = std::remove_cvref_t<decltype(value)>;
        out << ',';
        if constexpr (std::is_same_v<T, std::string>) {
          out << csv_text(value);
        } else if constexpr (std::is_same_v<T, bool>) {
          out << (value ? 1 : 0);
        } else if constexpr (std::is_floating_point_v<T>) {
          write_csv_field(out, f, s, value);
        } else {
          out << value;
        }
      });
      out << '\n';
    }
  }
}

// the controllers' snapshots, one row a number pair: points (value: the weight), path vertices,
// grid cells (at their centres in the world frame; value: the cell's) and estimates
void write_csv_controller_snapshots(std::ostream& out, const Trace& trace) {
  out << "time,agent,layer,x,y,value\n";
  for (const ControllerSnapshot& c : trace.controller_snapshots) {
    const Snapshot& s = c.snapshot;
    const auto row = [&](const char* layer, const Vec2& p, double value) {
      out << c.time << ',' << c.agent << ',' << layer << ',' << p.x << ',' << p.y << ',';
      if (std::isfinite(value)) out << value;
      out << '\n';
    };
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      row("point", s.points[i], s.weights.empty() ? NAN : s.weights[i]);
    }
    for (const Vec2& p : s.path) row("path", p, NAN);
    for (int j = 0; j < s.ny; ++j) {
      for (int i = 0; i < s.nx; ++i) {
        const Vec2 d = rotate({s.x0 + i * s.dx, s.y0 + j * s.dy}, c.start.heading);
        row("grid", {c.start.x + d.x, c.start.y + d.y},
            s.grid[static_cast<std::size_t>(j) * static_cast<std::size_t>(s.nx) +
                   static_cast<std::size_t>(i)]);
      }
    }
    if (s.has_estimate) row("estimate", s.estimate, NAN);
  }
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
  const std::string stem = path.substr(0, path.size() - 4);
  OutputFile file(path);
  write_csv_steps(file.stream(), trace);
  OutputFile snap_file(stem + ".filaments.csv");
  auto& snaps = snap_file.stream();
  snaps << "time,x,y,z,w\n";
  for (const auto& snap : trace.snapshots) {
    for (std::size_t i = 0; i < snap.x.size(); ++i) {
      snaps << snap.time << ',' << snap.x[i] << ',' << snap.y[i] << ',' << snap.z[i] << ','
            << snap.w[i] << '\n';
    }
  }
  OutputFile controller_file(stem + ".controller.csv");
  write_csv_controller_snapshots(controller_file.stream(), trace);
  // why: the three files are one trace: all are finished before any is put in place, so a full
  // disk leaves the previous set (or none), never a trace without its filaments (F17)
  file.finish();
  snap_file.finish();
  controller_file.finish();
  snap_file.publish();
  try {
    controller_file.publish();
    file.publish();
  } catch (const IoError&) {
    std::remove((stem + ".filaments.csv").c_str());
    std::remove((stem + ".controller.csv").c_str());
    throw;
  }
}

namespace {

// a config JSON object (nested by table; a robot's own tables nest deeper: member.2.controller)
// as settings of one layer, in file order
void add_config_settings(const json& config, const std::string& prefix, const std::string& origin,
                         std::vector<Setting>& settings, int depth = 0) {
  for (const auto& [name, v] : config.items()) {
    const std::string key = prefix + name;
    if (v.is_object()) {
      // why: the deepest key is member.K.TABLE.KEY; a file nested deeper is not a config
      if (depth >= 3) throw ConfigError(origin + ": config key '" + key + "' nests too deep");
      add_config_settings(v, key + ".", origin, settings, depth + 1);
      continue;
    }
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

std::vector<Setting> config_settings(const json& config, const std::string& origin) {
  std::vector<Setting> settings;
  add_config_settings(config, "", origin, settings);
  return settings;
}

// a whole-number field of a trace, checked to lie in [lo, hi]; why: get<int>() wraps a number
// that does not fit, and truncates 1.5 (issue 13, F18)
template <class T>
T trace_integer(const json& v, const std::string& field, T lo, T hi) {
  bool ok = false;
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    ok = std::cmp_greater_equal(u, lo) && std::cmp_less_equal(u, hi);
  } else if (v.is_number_integer()) {
    const auto i = v.get<std::int64_t>();
    ok = std::cmp_greater_equal(i, lo) && std::cmp_less_equal(i, hi);
  }
  if (!ok) {
    throw ConfigError(field + " must be a whole number from " + std::to_string(lo) + " to " +
                      std::to_string(hi) + " (got " + v.dump() + ")");
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

// one robot's steps (TraceStep::fields) from their columns; `unrecorded` is the true wind of a
// trace without it
std::vector<TraceStep> read_steps(const json& st, int format, const std::string& path,
                                  const std::string& table, const Vec2& unrecorded) {
  constexpr auto kInt = std::numeric_limits<int>::max();
  const std::string where = "trace '" + path + "': " + table;
  const std::size_t n = st.at("time").size();
  // why: format 1 has no true wind, and a trace of format 2 written from one may lack it too;
  // every other column must be there, as long as 'time'
  for (const TraceField& f : trace_fields()) {
    const std::string column(f.name);
    if (f.nullable && !st.contains(column)) continue;
    if (st.at(column).size() != n) {
      throw ConfigError(where + "column '" + column + "' has " +
                        std::to_string(st.at(column).size()) + " rows, 'time' has " +
                        std::to_string(n));
    }
  }
  if (n == 0) throw ConfigError(where + "no steps");
  std::vector<std::string> names;
  if (format >= 2) names = st.at("state_names").get<std::vector<std::string>>();
  // why: each step holds its state's name; a 1 MB name took 4.8 GB to view (issue 22, G8)
  const auto check_name = [&](const std::string& name, const std::string& field) {
    try {
      check_state_name(name);
    } catch (const ConfigError& e) {
      throw ConfigError(where + field + ": " + e.what());
    }
  };
  for (std::size_t k = 0; k < names.size(); ++k) {
    check_name(names[k], "steps.state_names[" + std::to_string(k) + "]");
  }
  if (format >= 2 && names.empty()) throw ConfigError(where + "steps.state_names is empty");
  std::vector<TraceStep> steps(n);
  for (std::size_t i = 0; i < n; ++i) {
    // why: built so, not as "[" + to_string(i) + "]", which GCC 12 warns of (-Wrestrict)
    std::string row = "[";
    row += std::to_string(i);
    row += ']';
    TraceStep& s = steps[i];
    s.true_wind = unrecorded;
    TraceStep::fields(s, [&](const TraceField& f, auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      const std::string column(f.name), field = "steps." + column + row;
      if (f.nullable && !st.contains(column)) return;
      const json& v = st[column][i];
      if constexpr (std::is_same_v<T, std::string>) {
        if (format >= 2) {
          value = names[trace_integer<std::size_t>(v, where + field, 0, names.size() - 1)];
        } else {
          value = v.template get<std::string>();
          check_name(value, field);
        }
      } else if constexpr (std::is_same_v<T, bool>) {
        value = v.is_boolean() ? v.template get<bool>()
                               : trace_integer<int>(v, where + field, 0, 1) == 1;
      } else if constexpr (std::is_floating_point_v<T>) {
        if (f.sampled && s.wind_samples <= 0) return;
        value = f.nullable ? number_or_nan(v) : v.template get<double>();
        // why: a number too large for a double parses as infinity; drawn, it overflows the page
        if (!f.nullable && !f.sampled && !std::isfinite(value)) {
          throw ConfigError(where + field + " is not finite");
        }
      } else {
        value = trace_integer<T>(v, where + field, 0, kInt);
      }
    });
  }
  return steps;
}

// a run's result (RunResult::fields), its seed and trial those of `info`; in a trace of format
// 1 or 2 a field that may be NaN may be missing (NaN): it was added later
RunResult read_result(const json& r, int format, const std::string& where, const RunInfo& info) {
  RunResult result;
  RunResult::fields(result, [&](const ResultField& f, auto&& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (!kDerivedField<decltype(value)>) {
      // why: traces of 0.4.0 before teams have no t_first_odor, d_first_odor, declaration_error
      if (format < 3 && f.nullable && !r.contains(std::string(f.name))) {
        if constexpr (std::is_floating_point_v<T>) value = NAN;
        return;
      }
      const json& v = r.at(std::string(f.name));
      if constexpr (std::is_same_v<T, Outcome>) {
        value = parse_outcome(v.template get<std::string>());
      } else if constexpr (std::is_floating_point_v<T>) {
        value = f.nullable ? number_or_nan(v) : v.template get<double>();
      } else {
        value = trace_integer<T>(v, where + "result." + std::string(f.name), 0,
                                 std::numeric_limits<T>::max());
      }
    }
  });
  result.seed = info.seed;
  result.trial = info.trial;
  return result;
}

// a finite number (m, rad) of a trace
double finite_number(const json& v, const std::string& where) {
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw ConfigError(where + " is not finite");
  return x;
}

Pose read_pose(const json& p, const std::string& where) {
  return {finite_number(p.at("x"), where + ".x"), finite_number(p.at("y"), where + ".y"),
          finite_number(p.at("heading"), where + ".heading")};
}

Vec2 read_declared(const json& d, const std::string& where) {
  if (d.is_null()) return {NAN, NAN};
  if (!d.is_array() || d.size() != 2) throw ConfigError(where + " must be [x, y] or null");
  return {finite_number(d[0], where + "[0]"), finite_number(d[1], where + "[1]")};
}

// numbers of a controller snapshot: finite, or null (NaN)
std::vector<double> read_numbers(const json& values, const std::string& where) {
  std::vector<double> out;
  out.reserve(values.size());
  for (const json& v : values) {
    out.push_back(number_or_nan(v));
    if (std::isinf(out.back())) throw ConfigError(where + " holds a number that is not finite");
  }
  return out;
}

std::vector<Vec2> read_points(const json& p, const std::string& where) {
  const std::vector<double> x = read_numbers(p.at("x"), where + ".x");
  const std::vector<double> y = read_numbers(p.at("y"), where + ".y");
  if (x.size() != y.size()) throw ConfigError(where + ": x and y have unequal lengths");
  std::vector<Vec2> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = {x[i], y[i]};
  return out;
}

// a controller snapshot of format 3, its robot's start pose from `agents`
ControllerSnapshot read_controller_snapshot(const json& j, const std::string& where,
                                            const std::vector<AgentTrace>& agents) {
  ControllerSnapshot c;
  c.time = finite_number(j.at("time"), where + ".time");
  c.agent = trace_integer<int>(j.at("agent"), where + ".agent", 0, kMaxTeam - 1);
  const auto robot = std::find_if(agents.begin(), agents.end(),
                                  [&](const AgentTrace& a) { return a.index == c.agent; });
  if (robot == agents.end()) {
    throw ConfigError(where + ".agent: no robot " + std::to_string(c.agent) + " in the trace");
  }
  c.start = robot->start;
  Snapshot& s = c.snapshot;
  if (j.contains("points")) s.points = read_points(j.at("points"), where + ".points");
  if (j.contains("weights")) s.weights = read_numbers(j.at("weights"), where + ".weights");
  if (!s.weights.empty() && s.weights.size() != s.points.size()) {
    throw ConfigError(where + ": " + std::to_string(s.weights.size()) + " weights for " +
                      std::to_string(s.points.size()) + " points");
  }
  if (j.contains("path")) s.path = read_points(j.at("path"), where + ".path");
  if (j.contains("grid")) {
    const json& g = j.at("grid");
    s.x0 = finite_number(g.at("x0"), where + ".grid.x0");
    s.y0 = finite_number(g.at("y0"), where + ".grid.y0");
    s.dx = finite_number(g.at("dx"), where + ".grid.dx");
    s.dy = finite_number(g.at("dy"), where + ".grid.dy");
    constexpr int kMaxCells = static_cast<int>(kMaxSnapshotValues);
    s.nx = trace_integer<int>(g.at("nx"), where + ".grid.nx", 0, kMaxCells);
    s.ny = trace_integer<int>(g.at("ny"), where + ".grid.ny", 0, kMaxCells);
    s.grid = read_numbers(g.at("values"), where + ".grid.values");
    if (s.grid.size() != static_cast<std::size_t>(s.nx) * static_cast<std::size_t>(s.ny)) {
      throw ConfigError(where + ".grid: " + std::to_string(s.grid.size()) + " values for nx = " +
                        std::to_string(s.nx) + ", ny = " + std::to_string(s.ny));
    }
    if (!(s.dx > 0.0) || !(s.dy > 0.0)) {
      throw ConfigError(where + ".grid: dx and dy must be positive");
    }
  }
  if (j.contains("estimate")) {
    const std::vector<double> e = read_numbers(j.at("estimate"), where + ".estimate");
    if (e.size() != 2) throw ConfigError(where + ".estimate must be [x, y]");
    s.has_estimate = true;
    s.estimate = {e[0], e[1]};
  }
  // why: the recorder's bound; a viewer draws every number of every snapshot it keeps
  if (snapshot_values(s) > kMaxSnapshotValues) {
    throw ConfigError(where + " holds more than " + std::to_string(kMaxSnapshotValues) +
                      " numbers");
  }
  return c;
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
    const std::string where = "trace '" + path + "': ";
    const int format = trace_integer<int>(doc.at("plumetrace_trace"), where + "plumetrace_trace", 1,
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
                trace_integer<std::uint64_t>(r.at("seed"), where + "result.seed", 0, kU64),
                trace_integer<std::uint64_t>(r.at("trial"), where + "result.trial", 0, kU64)};
    run.version = r.at("version").get<std::string>();
    // a robot's table: its index, result and steps (robot 0's at the top, as formats 1 and 2
    // hold the run's one robot)
    const Vec2 unrecorded = unrecorded_true_wind(run.scenario.wind);
    const auto read_agent = [&](const json& table, const json& result, int index,
                                const std::string& name) {
      AgentTrace a;
      a.index = index;
      a.result = read_result(result, format, where + name, run.info);
      if (result.contains("agent") &&
          trace_integer<int>(result.at("agent"), where + name + "result.agent", 0, kMaxTeam - 1) !=
              index) {
        throw ConfigError(where + name + "result.agent is not the robot's index " +
                          std::to_string(index));
      }
      a.result.agent = index;
      a.steps = read_steps(table.at("steps"), format, path, name, unrecorded);
      // why: formats 1 and 2 have no start: a trace's first row is at release
      a.start =
          format >= 3 ? read_pose(table.at("start"), where + name + "start") : a.steps.front().pose;
      if (format >= 3) a.declared = read_declared(table.at("declared"), where + name + "declared");
      run.trace.agents.push_back(std::move(a));
    };
    read_agent(doc, r,
               r.contains("agent")
                   ? trace_integer<int>(r.at("agent"), where + "result.agent", 0, kMaxTeam - 1)
                   : 0,
               "");
    run.result = run.trace.agents.front().result;
    run.info.agent = run.result.agent;
    if (format >= 3) {
      const json& mates = doc.at("teammates");
      if (!mates.is_array() || mates.size() >= static_cast<std::size_t>(kMaxTeam)) {
        throw ConfigError(where + "teammates must be a list of at most " +
                          std::to_string(kMaxTeam - 1) + " robots");
      }
      for (std::size_t k = 0; k < mates.size(); ++k) {
        const std::string name = "teammates[" + std::to_string(k) + "]: ";
        const int index =
            trace_integer<int>(mates[k].at("agent"), where + name + "agent", 0, kMaxTeam - 1);
        for (const AgentTrace& a : run.trace.agents) {
          if (a.index == index) {
            throw ConfigError(where + name + "robot " + std::to_string(index) + " is listed twice");
          }
        }
        read_agent(mates[k], mates[k].at("result"), index, name);
      }
      const json& snaps = doc.at("controller_snapshots");
      for (std::size_t i = 0; i < snaps.size(); ++i) {
        run.trace.controller_snapshots.push_back(read_controller_snapshot(
            snaps[i], where + "controller_snapshots[" + std::to_string(i) + "]", run.trace.agents));
      }
    }

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
      grid.nx = trace_integer<int>(g.at("nx"), where + "wind_grid.nx", 0, 100000);
      grid.ny = trace_integer<int>(g.at("ny"), where + "wind_grid.ny", 0, 100000);
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
