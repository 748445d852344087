#include "lochmatter2008/summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/core/parallel.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/io/json_util.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/plume_stats.hpp"
#include "plumetrace/sim/probe.hpp"
#include "plumetrace/sim/trace.hpp"

namespace plumetrace {

namespace {

using detail::json;
using detail::number_or_null;
using detail::stats_json;
using detail::value_to_json;

double as_number(const ConfigValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return NAN;
}

// the last part of a dotted key: "supervisor.success_radius" -> "success_radius"
std::string short_key(const std::string& key) { return key.substr(key.rfind('.') + 1); }

std::string as_text(const ConfigValue& v) {
  return std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : format_value(v);
}

const ExpandedSweep* find(const std::vector<ExpandedSweep>& sweeps, const std::string& name) {
  for (const auto& s : sweeps) {
    if (s.def.name == name) return &s;
  }
  return nullptr;
}

// the first experiment set under a reading (its scenario gives the detection map)
const ExpandedSweep* first_set(const std::vector<ExpandedSweep>& sweeps, const ReproduceInfo& info,
                               const std::string& reading, bool main) {
  return info.sets.empty() ? nullptr
                           : find(sweeps, reading_sweep_name(reading, main, info.sets.front()));
}

bool is_trajectory_set(const ReproduceInfo& info, const std::string& set) {
  return std::find(info.trajectory_sets.begin(), info.trajectory_sets.end(), set) !=
         info.trajectory_sets.end();
}

json point_json(const PointStats& st, const SweepPoint& p) {
  json j = stats_json(st);
  j["config_hash"] = p.config_hash;
  return j;
}

// the first run of the set's fixed point that succeeded (or, with `success` false, failed),
// re-run with a trace (Fig. 6)
json trajectory(const ExpandedSweep& sweep, const std::vector<RunRow>& rows, int runs,
                bool success) {
  const SetStats st = set_stats(sweep, rows, runs);
  if (st.fixed_index < 0) return nullptr;
  const SweepPoint& p = sweep.points[static_cast<std::size_t>(st.fixed_index)];
  for (const auto& r : point_runs(rows, sweep.def.name, p.index, runs)) {
    if ((r.outcome == Outcome::kSuccess) != success) continue;
    Trace trace;
    // why: an interval beyond any run takes the one snapshot at release, for its wind field
    const double once = 2.0 * kMaxSteps * p.scenario.sim.dt;
    const RunResult again =
        run_once(p.scenario, r.seed, r.trial, TraceRecorder(trace, once, p.scenario.sim.dt));
    json wind = nullptr;
    if (!trace.snapshots.empty() && !trace.snapshots[0].wind_x.empty()) {
      const WindGrid& g = trace.wind_grid;
      json u = json::array(), v = json::array();
      for (std::size_t k = 0; k < g.size(); ++k) {
        u.push_back(std::round(trace.snapshots[0].wind_x[k] * 1e3) / 1e3);
        v.push_back(std::round(trace.snapshots[0].wind_y[k] * 1e3) / 1e3);
      }
      wind = {{"x0", g.x0}, {"dx", g.dx}, {"nx", g.nx}, {"y0", g.y0},
              {"dy", g.dy}, {"ny", g.ny}, {"u", u},     {"v", v}};
    }
    json x = json::array(), y = json::array(), state = json::array(), odor = json::array();
    const Vec3& c = p.scenario.source.center;
    double closest = INFINITY;
    const std::vector<TraceStep>& steps = trace.agents.front().steps;
    for (const auto& s : steps) {
      closest = std::min(closest, std::hypot(s.pose.x - c.x, s.pose.y - c.y));
    }
    // every other step is plenty for a figure
    for (std::size_t i = 0; i < steps.size(); i += 2) {
      const auto& s = steps[i];
      x.push_back(s.pose.x);
      y.push_back(s.pose.y);
      state.push_back(s.state);
      odor.push_back(s.odor ? 1 : 0);
    }
    return {{"algorithm", st.algorithm},
            {"set", sweep.def.name},
            {"trial", r.trial},
            {"seed", r.seed},
            {"x", x},
            {"y", y},
            {"state", state},
            {"odor", odor},
            {"outcome", std::string(outcome_name(again.outcome))},
            {"overhead", number_or_null(again.overhead)},
            {"time_s", again.time},
            {"closest_m", number_or_null(closest)},
            {"wind_field", wind}};
  }
  return nullptr;
}

// where a failed run ended and how close it came to the source, from a re-run
struct FailedRun {
  Outcome outcome = Outcome::kRunning;
  double end_x = NAN;         // m
  double end_y = NAN;         // m
  double closest = INFINITY;  // smallest distance of the robot centre to the source (m)
  double min_x = INFINITY;    // most upwind x reached (m)
};

FailedRun rerun_failed(const Scenario& scenario, const RunResult& r) {
  FailedRun f;
  const Vec3& c = scenario.source.center;
  const RunResult again = run_once(scenario, r.seed, r.trial, [&](const World& world) {
    const Pose& p = world.robot().pose;
    f.closest = std::min(f.closest, std::hypot(p.x - c.x, p.y - c.y));
    f.min_x = std::min(f.min_x, p.x);
    f.end_x = p.x;
    f.end_y = p.y;
  });
  f.outcome = again.outcome;
  return f;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// the failed runs of each algorithm at its fixed values (the trajectory sets): counts by
// outcome over all of them, and where the first kFailuresExamined (by trial) end, re-run on
// `threads` threads
json failures_json(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                   const ReproduceInfo& info) {
  struct Job {
    const Scenario* scenario;
    RunResult run;
    std::size_t algorithm;
  };
  std::vector<Job> jobs;
  json algorithms = json::array();
  for (const std::string& name : info.trajectory_sets) {
    const ExpandedSweep* sweep = find(sweeps, name);
    if (!sweep) continue;
    const int runs = runs_per_point(*sweep, info.runs_override);
    const SetStats st = set_stats(*sweep, rows, runs);
    if (st.fixed_index < 0) continue;
    const SweepPoint& p = sweep->points[static_cast<std::size_t>(st.fixed_index)];
    const PointStats& ps = st.points[static_cast<std::size_t>(st.fixed_index)];
    int examined = 0;
    for (const auto& r : point_runs(rows, sweep->def.name, p.index, runs)) {
      if (r.outcome == Outcome::kSuccess || examined >= kFailuresExamined) continue;
      jobs.push_back({&p.scenario, r, algorithms.size()});
      ++examined;
    }
    const Vec3& c = p.scenario.source.center;
    algorithms.push_back({{"algorithm", st.algorithm},
                          {"set", name},
                          {"runs", ps.runs},
                          {"failed", ps.runs - ps.successes},
                          {"walls", ps.walls},
                          {"timeouts", ps.timeouts},
                          {"gave_up", ps.gave_up},
                          {"examined", examined},
                          {"source_x", c.x},
                          {"source_y", c.y}});
  }
  // the re-runs, in parallel; each result lands in its own slot
  std::vector<FailedRun> done(jobs.size());
  parallel_for(jobs.size(), info.threads,
               [&](std::size_t i) { done[i] = rerun_failed(*jobs[i].scenario, jobs[i].run); });

  for (std::size_t a = 0; a < algorithms.size(); ++a) {
    const double sx = algorithms[a]["source_x"], sy = algorithms[a]["source_y"];
    int upwind = 0, upwind_wall = 0, near = 0, passed = 0, close = 0;
    std::vector<double> closest, end_distance;
    json ends = json::array();
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      if (jobs[i].algorithm != a) continue;
      const FailedRun& f = done[i];
      ends.push_back({{"trial", jobs[i].run.trial},
                      {"outcome", std::string(outcome_name(f.outcome))},
                      {"x", f.end_x},
                      {"y", f.end_y},
                      {"closest_m", f.closest}});
      const double d = std::hypot(f.end_x - sx, f.end_y - sy);
      upwind += f.end_x < sx;
      upwind_wall += f.end_x < sx && f.outcome == Outcome::kWall;
      near += d <= 1.0;
      passed += f.min_x < sx;
      close += f.closest <= 0.5;
      closest.push_back(f.closest);
      end_distance.push_back(d);
    }
    json& j = algorithms[a];
    j["end_upwind"] = upwind;
    j["end_upwind_wall"] = upwind_wall;
    j["end_within_1m"] = near;
    j["passed_source"] = passed;
    j["came_within_0_5m"] = close;
    j["closest_median_m"] = number_or_null(median(closest));
    j["end_distance_median_m"] = number_or_null(median(end_distance));
    j["ends"] = ends;
  }
  return {{"examined_max", kFailuresExamined}, {"algorithms", algorithms}};
}

// fraction of instants with odor on a grid over the arena (the background of Fig. 6)
json detection_map_json(const Scenario& scenario, std::uint64_t seed) {
  const MapGrid grid = arena_grid(scenario);
  ProbeOptions options;
  options.duration = 20.0;
  options.interval = 0.32;
  options.seed = seed;
  return {{"x", grid.x}, {"y", grid.y}, {"fraction", detection_map(scenario, grid, options)}};
}

// the plume's own statistics (docs/plume-statistics.md) over kPlumeStatsTrials plumes, the
// plumes of the runs' first trials: what the report compares with the paper's sentences about
// the plume; of the gap lengths only the centreline's are kept (the report draws them)
json plume_stats_summary(const Scenario& scenario, std::uint64_t seed, int threads) {
  PlumeStatsOptions options;
  options.seed = seed;
  options.trials = kPlumeStatsTrials;
  options.threads = std::max(1, threads);
  json j = detail::plume_stats_json(plume_stats(scenario, options));
  for (std::size_t i = 0; i < j["along"].size(); ++i) {
    if (j["along"][i]["offset"] != 0.0) j["along"][i].erase("lengths");
  }
  for (auto& c : j["across"]) c.erase("lengths");
  return j;
}

json sweep_definition_json(const SweepDef& def) {
  json axes = json::array();
  for (const auto& ax : def.axes) {
    json values = json::array();
    for (const auto& v : ax.values) values.push_back(value_to_json(v));
    axes.push_back({{"key", ax.key}, {"label", ax.label}, {"values", values}});
  }
  json settings = json::object();
  for (const auto& s : def.settings) settings[s.key] = value_to_json(s.value);
  return {{"name", def.name}, {"title", def.title}, {"scenario", recorded_path(def.scenario_path)},
          {"set", settings},  {"axes", axes},       {"runs", def.runs},
          {"seed", def.seed}};
}

// a claim as JSON: id, text, verdict, margin, evidence and its parts' figures
json claim_json(const ClaimResult& c) {
  json parts = json::array();
  for (const ClaimPart& p : c.parts) {
    parts.push_back({{"support", p.support == Verdict::kHolds         ? "yes"
                                 : p.support == Verdict::kDoesNotHold ? "no"
                                                                      : "unclear"},
                     {"margin", number_or_null(p.margin)},
                     {"estimate", number_or_null(p.estimate)},
                     {"lo", number_or_null(p.lo)},
                     {"hi", number_or_null(p.hi)},
                     {"threshold", number_or_null(p.threshold)},
                     {"text", p.text}});
  }
  return {{"id", c.id},
          {"text", c.text},
          {"verdict", std::string(verdict_name(c.verdict))},
          {"margin", number_or_null(c.margin)},
          {"evidence", c.evidence},
          {"parts", parts}};
}

// The verdicts of the sets under one rule set: "claims", "held", "not_held", "unclear".
json verdicts_json(const std::map<std::string, SetStats>& sets, ClaimRules rules) {
  json claims = json::array();
  int held = 0, not_held = 0, unclear = 0;
  for (const auto& c : evaluate_claims(sets, rules)) {
    claims.push_back(claim_json(c));
    held += c.verdict == Verdict::kHolds;
    not_held += c.verdict == Verdict::kDoesNotHold;
    unclear += c.verdict == Verdict::kUnclear;
  }
  return {{"held", held}, {"not_held", not_held}, {"unclear", unclear}, {"claims", claims}};
}

// Adds the verdicts under the default rules ("rules", "claims" and the counts) and those under
// rules 0.3.0 beside them ("rules_030"), so that no change of rule hides a change of verdict
// (docs/claims.md, "Two rule sets").
void add_verdicts(json& doc, const std::map<std::string, SetStats>& sets) {
  doc["rules"] = std::string(rules_name(kDefaultRules));
  doc.update(verdicts_json(sets, kDefaultRules));
  json old = verdicts_json(sets, ClaimRules::kRules030);
  old["rules"] = std::string(rules_name(ClaimRules::kRules030));
  doc["rules_030"] = std::move(old);
}

// one reading: its settings, claims, fixed-value statistics and detection map (maps are shared
// between readings whose plume and sensor height are the same)
json reading_json(const Reading& reading, bool main, const std::vector<ExpandedSweep>& sweeps,
                  const std::vector<RunRow>& rows, const ReproduceInfo& info,
                  const std::set<std::string>& compared_keys, std::map<std::string, json>& maps);

}  // namespace

std::string reading_sweep_name(const std::string& reading, bool main, const std::string& set) {
  return main ? set : reading + "/" + set;
}

std::vector<ExpandedSweep> reading_sets(const std::vector<SweepDef>& sets, const Reading& reading,
                                        bool main) {
  std::vector<ExpandedSweep> out;
  for (SweepDef def : sets) {
    def.name = reading_sweep_name(reading.name, main, def.name);
    out.push_back(expand_sweep(def, reading.settings));
  }
  return out;
}

namespace {

json reading_json(const Reading& reading, bool main, const std::vector<ExpandedSweep>& sweeps,
                  const std::vector<RunRow>& rows, const ReproduceInfo& info,
                  const std::set<std::string>& compared_keys, std::map<std::string, json>& maps) {
  json settings = json::object();
  for (const auto& s : reading.settings) settings[s.key] = value_to_json(s.value);
  std::map<std::string, SetStats> by_name;
  json fixed = json::array();
  for (const std::string& set : info.sets) {
    const ExpandedSweep* sweep = find(sweeps, reading_sweep_name(reading.name, main, set));
    if (!sweep) continue;
    const SetStats st = set_stats(*sweep, rows, runs_per_point(*sweep, info.runs_override));
    by_name[set] = st;
    if (is_trajectory_set(info, set) && st.fixed_index >= 0) {
      const auto i = static_cast<std::size_t>(st.fixed_index);
      json p = point_json(st.points[i], sweep->points[i]);
      p["algorithm"] = st.algorithm;
      p["set"] = set;
      p["value"] = st.values[i];
      fixed.push_back(p);
    }
  }
  json doc{{"name", reading.name},
           {"main", main},
           {"file", reading.file.empty()
                        ? json(nullptr)
                        : json(std::filesystem::path(reading.file).filename().string())},
           {"settings", settings},
           {"fixed", fixed}};
  add_verdicts(doc, by_name);
  if (const ExpandedSweep* a = first_set(sweeps, info, reading.name, main)) {
    const Scenario& sc = a->points.at(0).scenario;
    const std::string key = plume_key(sc) + "|" + format_number(sc.odor.height);
    if (!maps.count(key)) maps[key] = detection_map_json(sc, a->def.seed);
    doc["detection_map"] = maps[key];
    doc["plume_stats"] = plume_stats_summary(sc, a->def.seed, info.threads);
    doc["success_radius"] = sc.supervisor.success_radius;
    // the value every compared key takes under this reading, preset or built-in default
    json values = json::object();
    for (const auto& k : compared_keys) values[k] = value_to_json(get_field(sc, k));
    doc["values"] = values;
  }
  return doc;
}

// one axis reading under the main reading: the sets it changes, with their points, and the
// claims of the main sets with those sets replaced (docs/fidelity.md, "The axes")
json axis_reading_json(const AxisReading& axes, const std::vector<ExpandedSweep>& sweeps,
                       const std::vector<RunRow>& rows, const ReproduceInfo& info) {
  std::map<std::string, SetStats> by_name;
  json changed = json::array();
  for (const std::string& set : info.sets) {
    const bool moved = axes.axes.count(set) > 0;
    const ExpandedSweep* sweep = find(sweeps, moved ? axis_sweep_name(axes.name, set) : set);
    if (!sweep) continue;
    SetStats st = set_stats(*sweep, rows, runs_per_point(*sweep, info.runs_override));
    st.name = set;
    if (moved) {
      json points = json::array();
      for (std::size_t i = 0; i < st.points.size(); ++i) {
        json p = point_json(st.points[i], sweep->points[i]);
        p["value"] = st.values[i];
        points.push_back(p);
      }
      changed.push_back(
          {{"set", set}, {"key", st.key}, {"fixed_index", st.fixed_index}, {"points", points}});
    }
    by_name[set] = std::move(st);
  }
  json doc{{"name", axes.name},
           {"title", axes.title},
           {"file", axes.file.empty() ? json(nullptr)
                                      : json(std::filesystem::path(axes.file).filename().string())},
           {"sets", changed}};
  add_verdicts(doc, by_name);
  return doc;
}

}  // namespace

SetStats set_stats(const ExpandedSweep& sweep, const std::vector<RunRow>& rows, int runs,
                   const std::vector<int>& points, std::size_t axis) {
  SetStats st;
  st.name = sweep.def.name;
  st.key = sweep.def.axes.at(axis).key;
  std::vector<int> selected = points;
  if (selected.empty()) {
    for (const auto& p : sweep.points) selected.push_back(p.index);
  }
  for (const int index : selected) {
    const SweepPoint& p = sweep.points.at(static_cast<std::size_t>(index));
    st.algorithm = std::string(algorithm_name(p.scenario.controller.algorithm));
    const double value = as_number(p.values.at(axis));
    const auto& fixed = sweep.def.axes[axis].fixed;
    if (fixed && std::fabs(as_number(*fixed) - value) < 1e-12) {
      st.fixed_index = static_cast<int>(st.values.size());
    }
    st.values.push_back(value);
    st.points.push_back(summarize(point_runs(rows, sweep.def.name, index, runs)));
  }
  return st;
}

std::string build_summary(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows,
                          const ReproduceInfo& info) {
  json doc;
  doc["plumetrace_summary"] = 1;
  doc["version"] = std::string(version());
  doc["generated_by"] = info.command;
  doc["preset"] = info.preset;
  doc["threads"] = info.threads;
  doc["elapsed_s"] = info.elapsed;
  if (info.computed >= 0) doc["computed_runs"] = info.computed;
  doc["config_toml"] = info.base_config;
  std::int64_t total = 0;
  for (const auto& s : sweeps) {
    total += static_cast<std::int64_t>(s.points.size()) * runs_per_point(s, info.runs_override);
  }
  doc["total_runs"] = total;

  // the nine sets and the claims
  json sets = json::array();
  std::map<std::string, SetStats> by_name;
  for (const std::string& name : info.sets) {
    const ExpandedSweep* sweep = find(sweeps, name);
    if (!sweep) continue;
    const int runs = runs_per_point(*sweep, info.runs_override);
    doc["seed"] = sweep->def.seed;
    doc["runs_per_point"] = runs;
    const SetStats st = set_stats(*sweep, rows, runs);
    json points = json::array();
    for (std::size_t i = 0; i < st.points.size(); ++i) {
      json p = point_json(st.points[i], sweep->points[i]);
      p["value"] = st.values[i];
      points.push_back(p);
    }
    sets.push_back({{"name", st.name},
                    {"title", sweep->def.title},
                    {"algorithm", st.algorithm},
                    {"key", st.key},
                    {"label", sweep->def.axes[0].label},
                    {"values", st.values},
                    {"fixed_index", st.fixed_index},
                    {"points", points}});
    by_name[name] = st;
  }
  doc["sets"] = sets;
  // the main reading's verdicts under both rule sets
  add_verdicts(doc, by_name);

  // the three algorithms at their fixed values under other success radii
  json variants = json::array(), sens_rows = json::array();
  const auto add_variant = [&](const std::string& v) {
    if (std::find(variants.begin(), variants.end(), json(v)) == variants.end()) {
      variants.push_back(v);
    }
  };
  if (const ExpandedSweep* radius = find(sweeps, info.radius)) {
    const int runs = runs_per_point(*radius, info.runs_override);
    const std::string varied = short_key(radius->def.axes.at(1).key);
    for (const auto& p : radius->points) {
      const std::string variant = varied + "=" + as_text(p.values.at(1));
      add_variant(variant);
      json row = point_json(summarize(point_runs(rows, radius->def.name, p.index, runs)), p);
      row["algorithm"] = as_text(p.values.at(0));
      row["variant"] = variant;
      sens_rows.push_back(row);
    }
  }
  doc["sensitivity"] = {{"variants", variants}, {"rows", sens_rows}};

  // Fig. 6: one successful and one failed run per algorithm at the fixed values, over the
  // detection map
  json trajectories = json::array(), missing = json::array();
  for (const std::string& name : info.trajectory_sets) {
    const ExpandedSweep* sweep = find(sweeps, name);
    if (!sweep) continue;
    const int runs = runs_per_point(*sweep, info.runs_override);
    json t = trajectory(*sweep, rows, runs, true);
    if (t.is_null()) {
      missing.push_back(
          std::string(algorithm_name(sweep->points[0].scenario.controller.algorithm)));
    } else {
      trajectories.push_back(t);
    }
    json failed = trajectory(*sweep, rows, runs, false);
    if (!failed.is_null()) trajectories.push_back(failed);
  }
  doc["trajectories"] = trajectories;
  doc["trajectories_missing"] = missing;
  doc["failures"] = failures_json(sweeps, rows, info);

  // each reading's claims, fixed values and detection map; the main one's map is shared
  std::map<std::string, json> maps;
  std::set<std::string> compared_keys;
  for (const auto& r : info.readings) {
    for (const auto& s : r.settings) compared_keys.insert(s.key);
  }
  json readings = json::array();
  for (std::size_t i = 0; i < info.readings.size(); ++i) {
    readings.push_back(
        reading_json(info.readings[i], i == 0, sweeps, rows, info, compared_keys, maps));
  }
  doc["readings"] = readings;
  json axis_readings = json::array();
  for (const auto& a : info.axis_readings) {
    axis_readings.push_back(axis_reading_json(a, sweeps, rows, info));
  }
  doc["axis_readings"] = axis_readings;
  if (const ExpandedSweep* a = first_set(sweeps, info, "", true)) {
    const Scenario& s = a->points.at(0).scenario;
    if (!readings.empty() && readings[0].contains("detection_map")) {
      doc["detection_map"] = readings[0]["detection_map"];
    } else {
      doc["detection_map"] = detection_map_json(s, a->def.seed);
    }
    doc["arena"] = {{"x_min", s.arena.x_min},
                    {"x_max", s.arena.x_max},
                    {"y_min", s.arena.y_min},
                    {"y_max", s.arena.y_max}};
    doc["source"] = {{"x", s.source.center.x},
                     {"y", s.source.center.y},
                     {"radius", s.source.radius},
                     {"success_radius", s.supervisor.success_radius}};
    doc["wind"] = {{"vx", s.wind.velocity.x}, {"vy", s.wind.velocity.y}};
  }
  // the main reading's sweeps (the other readings' are the same files with their settings)
  json defs = json::array();
  for (const auto& s : sweeps) {
    if (s.def.name.find('/') != std::string::npos) continue;
    defs.push_back({{"name", s.def.name},
                    {"file", recorded_path(s.def.file)},
                    {"definition", sweep_definition_json(s.def)}});
  }
  doc["sweeps"] = defs;
  return doc.dump(1);
}

std::vector<SweepDef> sensitivity_sweeps(const std::vector<SweepDef>& sets,
                                         const std::vector<Axis>& front, int runs) {
  std::vector<SweepDef> out;
  for (SweepDef def : sets) {
    std::vector<Axis> axes = front;
    axes.insert(axes.end(), def.axes.begin(), def.axes.end());
    def.axes = axes;
    def.runs = runs;
    out.push_back(def);
  }
  return out;
}

SensitivityMatrix sensitivity_matrix(const std::vector<ExpandedSweep>& sweeps,
                                     const std::vector<RunRow>& rows, int runs, std::size_t front) {
  SensitivityMatrix matrix;
  if (sweeps.empty()) return matrix;
  const auto& axes = sweeps.front().def.axes;
  matrix.axes.assign(axes.begin(), axes.begin() + static_cast<std::ptrdiff_t>(front));
  // every combination of the front axes' values, the first axis varying slowest
  std::vector<std::size_t> at(front, 0);
  for (bool more = front > 0; more;) {
    SensitivityRow row;
    for (std::size_t a = 0; a < front; ++a) row.values.push_back(axes[a].values[at[a]]);
    // each set restricted to the points of this combination, varied along its own axis
    std::map<std::string, SetStats> sets;
    for (const auto& sweep : sweeps) {
      std::vector<int> selected;
      for (const auto& p : sweep.points) {
        if (std::equal(row.values.begin(), row.values.end(), p.values.begin(),
                       [](const ConfigValue& a, const ConfigValue& b) {
                         return std::holds_alternative<std::string>(a)
                                    ? as_text(a) == as_text(b)
                                    : as_number(a) == as_number(b);
                       })) {
          selected.push_back(p.index);
        }
      }
      sets[sweep.def.name] = set_stats(sweep, rows, runs, selected, front);
    }
    row.claims = evaluate_claims(sets);
    matrix.rows.push_back(std::move(row));
    // the next combination
    more = false;
    for (std::size_t a = front; a-- > 0;) {
      if (++at[a] < axes[a].values.size()) {
        more = true;
        break;
      }
      at[a] = 0;
    }
  }
  return matrix;
}

std::string sensitivity_json(const SensitivityMatrix& matrix, int runs, double elapsed) {
  json claims = json::array(), out_rows = json::array();
  if (!matrix.rows.empty()) {
    for (const auto& c : matrix.rows.front().claims) {
      claims.push_back({{"id", c.id}, {"text", c.text}});
    }
  }
  for (const auto& row : matrix.rows) {
    json verdicts = json::array();
    int held = 0;
    for (const auto& c : row.claims) {
      verdicts.push_back(std::string(verdict_name(c.verdict)));
      held += c.verdict == Verdict::kHolds;
    }
    json r{{"verdicts", verdicts}, {"held", held}};
    for (std::size_t a = 0; a < matrix.axes.size(); ++a) {
      r[short_key(matrix.axes[a].key)] = value_to_json(row.values[a]);
    }
    out_rows.push_back(r);
  }
  return json{{"plumetrace_sensitivity", 1},
              {"version", std::string(version())},
              {"runs_per_point", runs},
              {"elapsed_s", elapsed},
              {"rules", std::string(rules_name(kDefaultRules))},
              {"claims", claims},
              {"rows", out_rows}}
      .dump(1);
}

std::string sensitivity_markdown(const SensitivityMatrix& matrix, int runs, double elapsed) {
  std::ostringstream md;
  std::string names;
  for (std::size_t a = 0; a < matrix.axes.size(); ++a) {
    std::string name = short_key(matrix.axes[a].key);
    std::replace(name.begin(), name.end(), '_', ' ');
    names += (a == 0 ? "" : a + 1 == matrix.axes.size() ? " and " : ", ") + name;
  }
  md << "# Sensitivity study: which claims hold under which model reading\n\n"
     << "Each row reruns the nine experiment sets (docs/experiments.md) with " << runs
     << " runs per value under one combination of " << names
     << " (docs/experiments.md, `plumetrace sensitivity`). Cells: H holds, - does not hold, "
        "? unclear (rules "
     << rules_name(kDefaultRules) << " in docs/claims.md). Computed in "
     << static_cast<long>(elapsed) << " s.\n\n|";
  for (const auto& axis : matrix.axes) {
    std::string name = short_key(axis.key);
    std::replace(name.begin(), name.end(), '_', ' ');
    md << " " << name << " |";
  }
  const auto& first = matrix.rows.empty() ? std::vector<ClaimResult>{} : matrix.rows.front().claims;
  for (const auto& c : first) md << " " << c.id << " |";
  md << " held |\n|";
  for (std::size_t i = 0; i < matrix.axes.size() + first.size() + 1; ++i) md << "---|";
  md << "\n";
  for (const auto& row : matrix.rows) {
    int held = 0;
    md << "|";
    for (const auto& v : row.values) {
      md << " ";
      if (const auto* d = std::get_if<double>(&v)) {
        md << *d;
      } else {
        md << as_text(v);
      }
      md << " |";
    }
    for (const auto& c : row.claims) {
      md << " "
         << (c.verdict == Verdict::kHolds         ? "H"
             : c.verdict == Verdict::kDoesNotHold ? "-"
                                                  : "?")
         << " |";
      held += c.verdict == Verdict::kHolds;
    }
    md << " " << held << " |\n";
  }
  if (!first.empty()) {
    md << "\nClaims:\n\n";
    for (const auto& c : first) md << c.id << ". " << c.text << "\n";
  }
  return md.str();
}

}  // namespace plumetrace
