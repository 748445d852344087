#include "plumetrace/io/results_io.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/io/json_util.hpp"

namespace plumetrace {

using detail::csv_text;
using detail::number_or_null;
using detail::result_json;
using detail::stats_json;
using detail::team_stats_json;
using detail::value_to_json;
using nlohmann::json;

std::string result_to_json(const RunResult& result, const RunInfo& info) {
  return result_json(result, info).dump();
}

namespace {

json points_json(const std::vector<ProbeResult>& results) {
  json points = json::array();
  for (const auto& r : results) {
    points.push_back({{"x", r.point.x},
                      {"y", r.point.y},
                      {"z", r.point.z},
                      {"detect_fraction", r.detect_fraction},
                      {"mean_concentration", r.mean_concentration},
                      {"intermittency", r.detect_fraction},
                      {"samples", r.samples}});
  }
  return points;
}

}  // namespace

std::string probe_to_json(const std::vector<ProbeResult>& results) {
  return json{{"points", points_json(results)}}.dump();
}

std::string probe_to_json(const ProbeReport& report) {
  json centrelines = json::array();
  for (const auto& c : report.centrelines) {
    centrelines.push_back({{"x", c.x},
                           {"mean_y", number_or_null(c.mean_y)},
                           {"std_y", number_or_null(c.std_y)},
                           {"samples", c.samples},
                           {"empty", c.empty}});
  }
  return json{{"points", points_json(report.points)}, {"centrelines", centrelines}}.dump();
}

std::string plume_stats_to_json(const PlumeStats& stats) {
  return detail::plume_stats_json(stats).dump();
}

std::string detection_map_to_json(const MapGrid& grid,
                                  const std::vector<std::vector<double>>& fraction) {
  return json{{"x", grid.x}, {"y", grid.y}, {"z", grid.z}, {"fraction", fraction}}.dump() + "\n";
}

namespace {

std::vector<std::string> axis_keys(const std::vector<ExpandedSweep>& sweeps) {
  std::vector<std::string> keys;
  for (const auto& s : sweeps) {
    for (const auto& a : s.def.axes) {
      if (std::find(keys.begin(), keys.end(), a.key) == keys.end()) keys.push_back(a.key);
    }
  }
  return keys;
}

const ExpandedSweep* find_sweep(const std::vector<ExpandedSweep>& sweeps, const std::string& name) {
  for (const auto& s : sweeps) {
    if (s.def.name == name) return &s;
  }
  return nullptr;
}

// the names of the axis columns, each after a comma
std::string axis_names(const std::vector<std::string>& keys) {
  std::string names;
  for (const auto& k : keys) names += ',' + csv_text(k);
  return names;
}

// the first columns' names of a table of points: sweep, point, then one per axis key
std::string axis_header(const std::vector<std::string>& keys) {
  std::string header = "sweep,point";
  header += axis_names(keys);
  return header;
}

// the axis columns of one point: its value under each key, empty where the sweep lacks the key
std::string axis_cells(const ExpandedSweep& sweep, int point,
                       const std::vector<std::string>& keys) {
  std::string cells;
  for (const auto& key : keys) {
    cells += ',';
    for (std::size_t a = 0; a < sweep.def.axes.size(); ++a) {
      if (sweep.def.axes[a].key != key) continue;
      const ConfigValue& v = sweep.points[static_cast<std::size_t>(point)].values[a];
      cells += std::holds_alternative<std::string>(v) ? csv_text(std::get<std::string>(v))
                                                      : format_value(v);
    }
  }
  return cells;
}

std::string csv_number(double v) {
  if (!std::isfinite(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// the run key's columns (RunRow::key_fields) with the point's axis columns after `point`:
// their names, or a row's cells; `skip` leaves out a key member
template <class Cell>
std::string key_columns(const RunRow& r, std::string_view skip, Cell&& cell) {
  std::string text;
  RunRow::key_fields(r, [&](std::string_view name, const auto& value) {
    if (name == skip) return;
    if (!text.empty()) text += ',';
    text += cell(name, value);
  });
  return text;
}

// the header of the run key's columns, the axis keys after `point`
std::string key_header(const std::vector<std::string>& keys, std::string_view skip) {
  return key_columns(RunRow{}, skip, [&](std::string_view name, const auto&) {
    std::string column(name);
    if (name == "point") column += axis_names(keys);
    return column;
  });
}

// a row's cells of the run key's columns, its point's axis values after `point`
std::string key_cells(const RunRow& r, const ExpandedSweep& sweep,
                      const std::vector<std::string>& keys, std::string_view skip) {
  return key_columns(r, skip, [&](std::string_view name, const auto& value) {
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
      return csv_text(value);
    } else {
      std::string cell = std::to_string(value);
      if (name == "point") cell += axis_cells(sweep, r.point, keys);
      return cell;
    }
  });
}

}  // namespace

void write_runs_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                    const std::vector<RunRow>& rows) {
  const auto keys = axis_keys(sweeps);
  OutputFile file(path);
  auto& out = file.stream();
  out << key_header(keys, "") << ",seed,config_hash";
  for (const ResultField& f : kResultFields) out << ',' << f.name;
  out << '\n';
  for (const auto& r : rows) {
    const ExpandedSweep* sweep = find_sweep(sweeps, r.sweep);
    if (!sweep || r.point >= static_cast<int>(sweep->points.size())) continue;
    out << key_cells(r, *sweep, keys, "") << ',' << r.result.seed << ',' << csv_text(r.config_hash);
    RunResult::fields(r.result, [&](const ResultField&, const auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      out << ',';
      if constexpr (std::is_same_v<T, Outcome>) {
        out << csv_text(outcome_name(value));
      } else if constexpr (std::is_same_v<T, bool>) {
        out << (value ? 1 : 0);
      } else if constexpr (std::is_floating_point_v<T>) {
        out << csv_number(value);
      } else {
        out << value;
      }
    });
    out << '\n';
  }
  file.commit();
}

void write_teams_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                     const std::vector<RunRow>& rows) {
  const auto keys = axis_keys(sweeps);
  OutputFile file(path);
  auto& out = file.stream();
  out << key_header(keys, "agent");
  TeamOutcome::fields(TeamOutcome{},
                      [&](const ResultField& f, const auto&) { out << ',' << f.name; });
  out << '\n';
  for (const TeamOutcome& t : team_outcomes(rows)) {
    const ExpandedSweep* sweep = find_sweep(sweeps, t.sweep);
    if (!sweep || t.point >= static_cast<int>(sweep->points.size())) continue;
    RunRow run;
    run.sweep = t.sweep;
    run.point = t.point;
    run.trial = t.trial;
    out << key_cells(run, *sweep, keys, "agent");
    TeamOutcome::fields(t, [&](const ResultField&, const auto& value) {
      out << ',';
      if constexpr (std::is_floating_point_v<std::remove_cvref_t<decltype(value)>>) {
        out << csv_number(value);
      } else {
        out << value;
      }
    });
    out << '\n';
  }
  file.commit();
}

void write_summary_csv(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                       const std::vector<RunRow>& rows, int runs_override) {
  const auto keys = axis_keys(sweeps);
  OutputFile file(path);
  auto& out = file.stream();
  out << axis_header(keys)
      << ",runs,successes,walls,timeouts,gave_up,success_rate,success_lo,success_hi,overhead_n,"
         "overhead_mean,overhead_lo,overhead_hi,overhead_median,overhead_q1,overhead_q3,"
         "mean_time,mean_losses\n";
  for (const auto& sweep : sweeps) {
    const int runs = runs_per_point(sweep, runs_override);
    for (const auto& p : sweep.points) {
      const auto results = point_runs(rows, sweep.def.name, p.index, runs);
      const PointStats st = summarize(results);
      out << csv_text(sweep.def.name) << ',' << p.index << axis_cells(sweep, p.index, keys) << ','
          << st.runs << ',' << st.successes << ',' << st.walls << ',' << st.timeouts << ','
          << st.gave_up << ',' << csv_number(st.success_rate) << ',' << csv_number(st.success_ci.lo)
          << ',' << csv_number(st.success_ci.hi) << ',' << st.overhead.n << ','
          << csv_number(st.overhead.mean) << ',' << csv_number(st.overhead_bootstrap.lo) << ','
          << csv_number(st.overhead_bootstrap.hi) << ',' << csv_number(st.overhead_quartiles.median)
          << ',' << csv_number(st.overhead_quartiles.q1) << ','
          << csv_number(st.overhead_quartiles.q3) << ',' << csv_number(st.mean_time) << ','
          << csv_number(st.mean_losses) << '\n';
    }
  }
  file.commit();
}

void write_results_json(const std::string& path, const std::vector<ExpandedSweep>& sweeps,
                        const std::vector<RunRow>& rows, int runs_override) {
  const std::vector<TeamOutcome> teams = team_outcomes(rows);
  json doc_sweeps = json::array();
  for (const auto& sweep : sweeps) {
    const int runs = runs_per_point(sweep, runs_override);
    json axes = json::array();
    for (const auto& a : sweep.def.axes) {
      json values = json::array();
      for (const auto& v : a.values) values.push_back(value_to_json(v));
      axes.push_back({{"key", a.key},
                      {"label", a.label},
                      {"values", values},
                      {"fixed", a.fixed ? value_to_json(*a.fixed) : json(nullptr)}});
    }
    json points = json::array();
    for (const auto& p : sweep.points) {
      const auto results = point_runs(rows, sweep.def.name, p.index, runs);
      json values = json::array();
      for (const auto& v : p.values) values.push_back(value_to_json(v));
      json run_list = json::array();
      for (const auto& r : results) {
        run_list.push_back(
            result_json(r, {std::string(algorithm_name(p.scenario.controller.algorithm)), r.seed,
                            r.trial, r.agent}));
      }
      std::vector<TeamOutcome> point_teams;
      for (const TeamOutcome& t : teams) {
        if (t.sweep == sweep.def.name && t.point == p.index &&
            t.trial < static_cast<std::uint64_t>(runs)) {
          point_teams.push_back(t);
        }
      }
      points.push_back({{"index", p.index},
                        {"values", values},
                        {"config_hash", p.config_hash},
                        {"stats", stats_json(summarize(results))},
                        {"team", team_stats_json(summarize_teams(point_teams))},
                        {"runs", run_list}});
    }
    doc_sweeps.push_back({{"name", sweep.def.name},
                          {"title", sweep.def.title},
                          {"file", recorded_path(sweep.def.file)},
                          {"seed", sweep.def.seed},
                          {"runs_per_point", runs},
                          {"axes", axes},
                          {"points", points}});
  }
  OutputFile file(path);
  auto& out = file.stream();
  out << json{{"plumetrace_results", 1},
              {"version", std::string(version())},
              {"sweeps", doc_sweeps}}
             .dump(1)
      << "\n";
  file.commit();
}

}  // namespace plumetrace
