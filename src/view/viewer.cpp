#include "plumetrace/view/viewer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/env/wind.hpp"
#include "plumetrace/io/json_util.hpp"
#include "plumetrace/sim/probe.hpp"
#include "view_data.hpp"

namespace plumetrace {

namespace view {

namespace {

// distance (m) from p to the segment a-b
double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(px - (ax + t * dx), py - (ay + t * dy));
}

}  // namespace

std::vector<std::size_t> simplify(const std::vector<double>& x, const std::vector<double>& y,
                                  double tolerance) {
  const std::size_t n = x.size();
  if (n <= 2) {
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    return all;
  }
  std::vector<bool> keep(n, false);
  keep.front() = keep.back() = true;
  // why: an explicit stack, since a long run may nest deeper than the call stack allows
  std::vector<std::pair<std::size_t, std::size_t>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [a, b] = todo.back();
    todo.pop_back();
    double worst = -1.0;
    std::size_t at = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double d = segment_distance(x[i], y[i], x[a], y[a], x[b], y[b]);
      if (d > worst) worst = d, at = i;
    }
    if (worst > tolerance) {
      keep[at] = true;
      todo.push_back({a, at});
      todo.push_back({at, b});
    }
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i]) kept.push_back(i);
  }
  return kept;
}

std::vector<std::size_t> path_steps(const std::vector<TraceStep>& steps, double tolerance) {
  const std::size_t n = steps.size();
  if (n == 0) return {};
  std::vector<std::size_t> kept{0};
  std::size_t begin = 0;
  while (begin + 1 < n) {
    // one stretch: the segments ending at steps begin+1 .. end-1, all in the state of begin+1
    std::size_t end = begin + 1;
    while (end < n && steps[end].state == steps[begin + 1].state) ++end;
    std::vector<double> x, y;
    for (std::size_t k = begin; k < end; ++k) {
      x.push_back(steps[k].pose.x);
      y.push_back(steps[k].pose.y);
    }
    for (const std::size_t k : simplify(x, y, tolerance)) {
      if (begin + k != kept.back()) kept.push_back(begin + k);
    }
    begin = end - 1;
  }
  return kept;
}

std::vector<std::size_t> frame_steps(const std::vector<TraceStep>& steps, std::size_t max_frames) {
  const std::size_t n = steps.size();
  const std::size_t stride =
      std::max<std::size_t>(1, (n + max_frames - 1) / std::max<std::size_t>(1, max_frames));
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i) {
    const bool changed = i > 0 && steps[i].state != steps[i - 1].state;
    if (i % stride == 0 || i + 1 == n || changed) kept.push_back(i);
  }
  return kept;
}

std::vector<std::size_t> thin_evenly(std::size_t n, std::size_t max_count) {
  std::vector<std::size_t> kept;
  if (n == 0 || max_count == 0) return kept;
  if (n <= max_count) {
    for (std::size_t i = 0; i < n; ++i) kept.push_back(i);
    return kept;
  }
  if (max_count == 1) return {n - 1};
  for (std::size_t j = 0; j < max_count; ++j) {
    // why: integer arithmetic, so the first and last are exact and the picks strictly increase
    kept.push_back(j * (n - 1) / (max_count - 1));
  }
  return kept;
}

std::vector<std::size_t> detection_steps(const std::vector<TraceStep>& steps, double spacing) {
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (!steps[i].odor) continue;
    const bool onset = i == 0 || !steps[i - 1].odor;
    const bool far =
        kept.empty() || std::hypot(steps[i].pose.x - steps[kept.back()].pose.x,
                                   steps[i].pose.y - steps[kept.back()].pose.y) >= spacing;
    if (onset || far) kept.push_back(i);
  }
  return kept;
}

std::vector<std::string> state_colors(const std::vector<std::string>& names) {
  // why: the report's colours (python/plumetrace/report/figures.py, STATE_COLORS and
  // EXTRA_STATE_COLORS; python/tests/test_viewer_colors.py checks that they agree): moving
  // upwind in the plume is blue, searching orange or red; other states take the extras in turn
  static const std::map<std::string, std::string, std::less<>> kByName = {
      {"upwind", "#1f77b4"}, {"surge", "#1f77b4"}, {"crosswind", "#ff7f0e"},
      {"spiral", "#ff7f0e"}, {"cast1", "#ff7f0e"}, {"cast2", "#d62728"}};
  static const char* const kExtra[] = {"#2ca02c", "#9467bd", "#8c564b",
                                       "#e377c2", "#17becf", "#bcbd22"};
  std::vector<std::string> colors;
  std::size_t extra = 0;
  for (const auto& name : names) {
    const auto known = kByName.find(name);
    colors.push_back(known != kByName.end() ? known->second
                                            : kExtra[extra++ % (sizeof kExtra / sizeof *kExtra)]);
  }
  return colors;
}

std::string outcome_color(Outcome outcome) {
  // why: the report's OUTCOME_COLORS (python/plumetrace/report/figures.py)
  switch (outcome) {
    case Outcome::kSuccess:
      return "#4c9a4c";
    case Outcome::kWall:
      return "#d9534f";
    case Outcome::kTimeout:
      return "#f0ad4e";
    case Outcome::kGaveUp:
      return "#8c6bb1";
    case Outcome::kWrongDeclaration:
      return "#5b7fa6";
    case Outcome::kRunning:
      break;
  }
  return "#333333";
}

double nice_length(double at_least) {
  const double decade = std::pow(10.0, std::floor(std::log10(at_least)));
  for (const double k : {1.0, 2.0, 5.0, 10.0}) {
    if (k * decade >= at_least) return k * decade;
  }
  return 10.0 * decade;
}

MapGrid detection_grid(const Scenario& scenario) {
  const auto& a = scenario.arena;
  // why: 5 cm, a sixth of the region's narrowest parts; coarser on arenas over 40 m, so that a
  // snapshot's grid stays under about 10^5 cells
  const double cell = std::max(0.05, std::max(a.x_max - a.x_min, a.y_max - a.y_min) / 800.0);
  return arena_grid(scenario, cell, cell);
}

std::vector<std::size_t> mask_runs(const std::vector<std::uint8_t>& mask) {
  std::vector<std::size_t> runs;
  std::size_t i = 0;
  while (i < mask.size()) {
    std::size_t off = 0, on = 0;
    while (i < mask.size() && !mask[i]) ++off, ++i;
    while (i < mask.size() && mask[i]) ++on, ++i;
    if (on == 0) break;
    runs.push_back(off);
    runs.push_back(on);
  }
  return runs;
}

}  // namespace view

namespace {

using detail::Quantizer;
using nlohmann::json;

// the colours every view shares (the page reads them from its data). why: the plume is grey and
// the robot dark, as in the report's figures, so that the states' blue, orange and red stand
// out; the detection region is gold, a colour no state takes
constexpr const char* kPlumeColor = "#8c8c8c";
constexpr const char* kRegionColor = "#f5d000";
constexpr const char* kRobotColor = "#333333";
constexpr const char* kDetectionColor = "#000000";
constexpr const char* kWindColor = "#555555";
constexpr const char* kTrueWindColor = "#aaaaaa";
constexpr const char* kWindFieldColor = "#c4c4c4";
// the robots' colours, robot k taking colour k (mod 10); why: robot 0 keeps the dark grey a
// robot alone always had; the others are ColorBrewer's Dark2 and two more, dark enough to read
// on the light floor, none of them the gold of the detection region
constexpr std::array<const char*, 10> kRobotColors{"#333333", "#1b9e77", "#d95f02", "#7570b3",
                                                   "#e7298a", "#66a61e", "#a6761d", "#1f78b4",
                                                   "#b15928", "#6a3d9a"};
// fill opacity of the detection region
constexpr double kRegionOpacity = 0.6;
// wind arrows: metres drawn per m/s
constexpr double kWindArrowScale = 0.25;

double rounded(double v, double unit) { return std::round(v / unit) * unit; }

// a rounded number, or null where it is not finite (an unrecorded true wind)
json rounded_or_null(double v, double unit) {
  return std::isfinite(v) ? json(rounded(v, unit)) : json(nullptr);
}

// states in order of first appearance, robot by robot
std::vector<std::string> state_names(const Trace& trace) {
  std::vector<std::string> names;
  for (const auto& a : trace.agents) {
    for (const auto& s : a.steps) {
      if (std::find(names.begin(), names.end(), s.state) == names.end()) names.push_back(s.state);
    }
  }
  return names;
}

// robot k's colour
std::string robot_color(std::size_t k) { return kRobotColors[k % kRobotColors.size()]; }

// robot k's result: robot 0's is the run's
const RunResult& robot_result(const RecordedRun& run, std::size_t k) {
  return k == 0 ? run.result : run.trace.agents[k].result;
}

// the run's information as robot `index` of its team ran: in a mixed team, its own algorithm
RunInfo robot_info(const RecordedRun& run, int index) {
  RunInfo info = run.info;
  info.agent = index;
  if (std::string own = own_algorithm(run.scenario, index); !own.empty()) {
    info.algorithm = std::move(own);
  }
  return info;
}

std::size_t state_index(const std::vector<std::string>& names, const std::string& state) {
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), state) - names.begin());
}

// a wind sample: where it was taken and the measured and true wind in the world frame
struct WindSample {
  double time, x, y;
  Vec2 measured, truth;
};

// the true wind is the trace's, recorded at the robot at every step (NaN where the trace could
// not know it: format 1 in a wind that varies)
std::vector<WindSample> wind_samples(const std::vector<TraceStep>& steps) {
  std::vector<WindSample> out;
  for (const auto& s : steps) {
    if (s.wind_samples <= 0) continue;
    const double c = std::cos(s.pose.heading), sn = std::sin(s.pose.heading);
    const Vec2 measured{c * s.wind_body.x - sn * s.wind_body.y,
                        sn * s.wind_body.x + c * s.wind_body.y};
    out.push_back({s.time, s.pose.x, s.pose.y, measured, s.true_wind});
  }
  return out;
}

// the snapshot shown at time t: the last one at or before it (the first if none)
std::size_t snapshot_at(const Trace& trace, double t) {
  std::size_t at = 0;
  for (std::size_t i = 0; i < trace.snapshots.size(); ++i) {
    if (trace.snapshots[i].time <= t) at = i;
  }
  return at;
}

// log10 of a filament's own peak concentration, the quantity its shade shows
double log_peak(const RecordedRun& run, double w) {
  return std::log10(
      std::max(kernel_value(run.scenario.plume, w, 0.0), std::numeric_limits<double>::min()));
}

struct ShadeRange {
  double lo = 0.0, hi = 0.0;  // log10 of peak concentrations
  double shade(double log_peak) const {
    return hi > lo ? std::clamp((log_peak - lo) / (hi - lo), 0.0, 1.0) : 1.0;
  }
};

ShadeRange shade_range(const RecordedRun& run, const std::vector<std::size_t>& snapshots) {
  double wmin = INFINITY, wmax = -INFINITY;
  for (const std::size_t i : snapshots) {
    for (const double w : run.trace.snapshots[i].w)
      wmin = std::min(wmin, w), wmax = std::max(wmax, w);
  }
  if (!(wmin <= wmax)) return {};
  const double a = log_peak(run, wmin), b = log_peak(run, wmax);
  return {std::min(a, b), std::max(a, b)};
}

// a column of numbers in [lo, hi] to steps of `finest`, each in as few bits as its range needs
// (at most 16, with coarser steps where 16 bits of `finest` do not span it), packed into bytes
// from the lowest bit up; value = origin + unit * step
json column_json(double lo, double hi, double finest, const std::vector<double>& values) {
  int bits = 1;
  while (bits < 16 && (hi - lo) / finest > static_cast<double>((1 << bits) - 1)) ++bits;
  const double top = static_cast<double>((1 << bits) - 1);
  const double unit = std::max(finest, (hi - lo) / top);
  std::vector<std::uint8_t> bytes;
  bytes.reserve((values.size() * static_cast<std::size_t>(bits) + 7) / 8);
  std::uint32_t pending = 0;
  int held = 0;
  for (const double v : values) {
    pending |= static_cast<std::uint32_t>(std::clamp(std::round((v - lo) / unit), 0.0, top))
               << held;
    for (held += bits; held >= 8; held -= 8, pending >>= 8) {
      bytes.push_back(static_cast<std::uint8_t>(pending & 0xff));
    }
  }
  if (held > 0) bytes.push_back(static_cast<std::uint8_t>(pending & 0xff));
  return {{"origin", lo}, {"unit", unit}, {"bits", bits}, {"data", detail::base64(bytes)}};
}

// the true wind at the trace's grid for each kept snapshot (none for a trace without one); null
// for a snapshot whose field is the one before it (a steady wind's, after the first)
json wind_field_json(const RecordedRun& run, const std::vector<std::size_t>& kept) {
  const WindGrid& g = run.trace.wind_grid;
  json u = json::array(), v = json::array();
  json last_u, last_v;
  for (const std::size_t i : kept) {
    const auto& s = run.trace.snapshots[i];
    json su = json::array(), sv = json::array();
    for (std::size_t k = 0; k < s.wind_x.size(); ++k) {
      su.push_back(rounded(s.wind_x[k], 1e-3));
      sv.push_back(rounded(s.wind_y[k], 1e-3));
    }
    const bool same = su == last_u && sv == last_v;
    last_u = su, last_v = sv;
    u.push_back(same ? json(nullptr) : std::move(su));
    v.push_back(same ? json(nullptr) : std::move(sv));
  }
  return {{"x0", g.x0}, {"dx", g.dx}, {"nx", g.nx}, {"y0", g.y0},
          {"dy", g.dy}, {"ny", g.ny}, {"u", u},     {"v", v}};
}

// where odor was perceivable at each kept snapshot: the grid and each snapshot's cells as runs
json detection_json(const RecordedRun& run, const std::vector<std::size_t>& kept) {
  const MapGrid grid = view::detection_grid(run.scenario);
  json runs = json::array();
  for (const std::size_t i : kept) {
    runs.push_back(view::mask_runs(detection_mask(run.scenario, run.trace.snapshots[i], grid)));
  }
  const auto step = [](const std::vector<double>& c) { return c.size() > 1 ? c[1] - c[0] : 0.0; };
  return {{"x0", grid.x.empty() ? 0.0 : grid.x.front()},
          {"dx", step(grid.x)},
          {"nx", grid.x.size()},
          {"y0", grid.y.empty() ? 0.0 : grid.y.front()},
          {"dy", step(grid.y)},
          {"ny", grid.y.size()},
          {"z", grid.z},
          {"threshold", run.scenario.odor.threshold},
          {"runs", runs}};
}

json snapshots_json(const RecordedRun& run, const std::vector<std::size_t>& kept,
                    const ShadeRange& range) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  std::vector<double> xs, ys, ws;
  json times = json::array(), counts = json::array();
  for (const std::size_t i : kept) {
    const auto& s = run.trace.snapshots[i];
    times.push_back(rounded(s.time, 1e-3));
    counts.push_back(s.x.size());
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const double v[3] = {s.x[k], s.y[k], s.w[k]};
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], v[c]), hi[c] = std::max(hi[c], v[c]);
      xs.push_back(s.x[k]);
      ys.push_back(s.y[k]);
      ws.push_back(s.w[k]);
    }
  }
  for (int c = 0; c < 3; ++c) {
    if (!(lo[c] <= hi[c])) lo[c] = hi[c] = 0.0;
  }
  // why: 1 mm positions and 0.01 mm widths are below a pixel at any sensible zoom. A filament's
  // shade is its peak on a log scale, and every kernel's peak is a constant over w^3
  // (Viewer.EveryKernelsPeakFallsAsTheWidthCubed), so the page finds it from the width
  return {{"time", times},
          {"count", counts},
          {"x", column_json(lo[0], hi[0], 1e-3, xs)},
          {"y", column_json(lo[1], hi[1], 1e-3, ys)},
          {"w", column_json(lo[2], hi[2], 1e-5, ws)},
          {"shade", {{"w_min", lo[2]}, {"w_max", hi[2]}}},
          {"peak_lo", std::pow(10.0, range.lo)},
          {"peak_hi", std::pow(10.0, range.hi)},
          {"wind_field", wind_field_json(run, kept)},
          {"detection", detection_json(run, kept)}};
}

// what rounding a step column takes in the page, by its unit: 0.1 ms, 0.01 mm, 1e-5 rad and
// m/s; numbers without a unit as they are
double column_unit(const TraceField& f) {
  if (f.unit == "s") return 1e-4;
  return f.unit.empty() ? 0.0 : 1e-5;
}

// a robot's animation frames: the step columns (TraceStep::fields) but for the wind samples
// (drawn from their own list), states as indices into `names`
json frames_json(const std::vector<TraceStep>& steps, const std::vector<std::string>& names,
                 std::size_t max_frames) {
  json frames{{"step", json::array()}};
  for (const TraceField& f : trace_fields()) {
    if (!f.sampled) frames[std::string(f.name)] = json::array();
  }
  for (const std::size_t i : view::frame_steps(steps, max_frames)) {
    frames["step"].push_back(i);
    TraceStep::fields(steps[i], [&](const TraceField& f, const auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if (f.sampled) return;
      json& column = frames[std::string(f.name)];
      if constexpr (std::is_same_v<T, std::string>) {
        column.push_back(state_index(names, value));
      } else if constexpr (std::is_same_v<T, bool>) {
        column.push_back(value ? 1 : 0);
      } else if constexpr (std::is_floating_point_v<T>) {
        const double unit = column_unit(f);
        column.push_back(unit > 0.0 ? rounded_or_null(value, unit) : json(value));
      } else {
        column.push_back(value);
      }
    });
  }
  return frames;
}

// a controller's grid for the page: its geometry (odometry frame) and its values in 8 bits over
// their range, 255 where a value is not a number
json grid_json(const Snapshot& s) {
  double lo = INFINITY, hi = -INFINITY;
  for (const double v : s.grid) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  if (!(lo <= hi)) lo = hi = 0.0;
  std::vector<std::uint8_t> bytes;
  bytes.reserve(s.grid.size());
  for (const double v : s.grid) {
    bytes.push_back(!std::isfinite(v) ? 255
                    : hi > lo ? static_cast<std::uint8_t>(std::lround((v - lo) / (hi - lo) * 254.0))
                              : 254);
  }
  return {{"x0", s.x0}, {"y0", s.y0}, {"dx", s.dx},
          {"dy", s.dy}, {"nx", s.nx}, {"ny", s.ny},
          {"lo", lo},   {"hi", hi},   {"data", detail::base64(bytes)}};
}

// points as columns to 0.1 mm
json points_json(const std::vector<Vec2>& points) {
  json x = json::array(), y = json::array();
  for (const Vec2& p : points) {
    x.push_back(rounded_or_null(p.x, 1e-4));
    y.push_back(rounded_or_null(p.y, 1e-4));
  }
  return {{"x", std::move(x)}, {"y", std::move(y)}};
}

// one controller snapshot as the page draws it: points with their weights over the largest
// (1 when equal), the path, the grid and the estimate, where the controller gave them
json layer_json(const ControllerSnapshot& c) {
  const Snapshot& s = c.snapshot;
  json out{{"time", rounded(c.time, 1e-4)}};
  if (!s.points.empty()) {
    out["points"] = points_json(s.points);
    double top = 0.0;
    for (const double w : s.weights) {
      if (std::isfinite(w)) top = std::max(top, w);
    }
    json w = json::array();
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      const double v = s.weights.empty() ? 1.0 : top > 0.0 ? s.weights[i] / top : 0.0;
      w.push_back(std::isfinite(v) ? rounded(std::max(0.0, v), 1e-3) : 0.0);
    }
    out["points"]["w"] = std::move(w);
  }
  if (!s.path.empty()) out["path"] = points_json(s.path);
  if (!s.grid.empty()) out["grid"] = grid_json(s);
  if (s.has_estimate) {
    out["estimate"] = {rounded_or_null(s.estimate.x, 1e-4), rounded_or_null(s.estimate.y, 1e-4)};
  }
  return out;
}

// one robot as the page draws it
json robot_json(const RecordedRun& run, std::size_t k, const std::vector<std::string>& names,
                const ViewerOptions& options) {
  const AgentTrace& agent = run.trace.agents[k];
  const auto& steps = agent.steps;
  json path{{"time", json::array()},
            {"x", json::array()},
            {"y", json::array()},
            {"state", json::array()}};
  for (const std::size_t i : view::path_steps(steps, options.path_tolerance)) {
    path["time"].push_back(rounded(steps[i].time, 1e-4));
    path["x"].push_back(rounded(steps[i].pose.x, 1e-5));
    path["y"].push_back(rounded(steps[i].pose.y, 1e-5));
    path["state"].push_back(state_index(names, steps[i].state));
  }

  json detections{{"time", json::array()}, {"x", json::array()}, {"y", json::array()}};
  for (const std::size_t i : view::detection_steps(steps, options.detection_spacing)) {
    detections["time"].push_back(rounded(steps[i].time, 1e-4));
    detections["x"].push_back(rounded(steps[i].pose.x, 1e-5));
    detections["y"].push_back(rounded(steps[i].pose.y, 1e-5));
  }

  json wind{{"time", json::array()},  {"x", json::array()}, {"y", json::array()},
            {"u", json::array()},     {"v", json::array()}, {"true_u", json::array()},
            {"true_v", json::array()}};
  for (const auto& w : wind_samples(steps)) {
    wind["time"].push_back(rounded(w.time, 1e-4));
    wind["x"].push_back(rounded(w.x, 1e-5));
    wind["y"].push_back(rounded(w.y, 1e-5));
    wind["u"].push_back(rounded(w.measured.x, 1e-5));
    wind["v"].push_back(rounded(w.measured.y, 1e-5));
    wind["true_u"].push_back(rounded_or_null(w.truth.x, 1e-5));
    wind["true_v"].push_back(rounded_or_null(w.truth.y, 1e-5));
  }

  // the controller's snapshots, thinned as the filaments are
  std::vector<const ControllerSnapshot*> mine;
  for (const auto& c : run.trace.controller_snapshots) {
    if (c.agent == agent.index) mine.push_back(&c);
  }
  json layers = json::array();
  for (const std::size_t i : view::thin_evenly(mine.size(), options.max_snapshots)) {
    layers.push_back(layer_json(*mine[i]));
  }

  const bool declared = std::isfinite(agent.declared.x) && std::isfinite(agent.declared.y);
  return {{"agent", agent.index},
          {"color", robot_color(k)},
          {"result", detail::result_json(robot_result(run, k), robot_info(run, agent.index))},
          {"start",
           {{"x", rounded(agent.start.x, 1e-5)},
            {"y", rounded(agent.start.y, 1e-5)},
            {"heading", rounded(agent.start.heading, 1e-5)}}},
          {"declared", declared ? json::array({rounded(agent.declared.x, 1e-5),
                                               rounded(agent.declared.y, 1e-5)})
                                : json(nullptr)},
          {"steps", steps.size()},
          {"frames", frames_json(steps, names, options.max_frames)},
          {"path", path},
          {"detections", detections},
          {"wind", wind},
          {"layers", layers}};
}

// everything the page draws, thinned as the options say
json view_json(const RecordedRun& run, const ViewerOptions& options) {
  const Scenario& sc = run.scenario;
  const auto names = state_names(run.trace);

  json outcomes = json::object();
  for (std::size_t i = 1; i < kOutcomeNames.size(); ++i) {
    outcomes[std::string(kOutcomeNames[i])] = view::outcome_color(static_cast<Outcome>(i));
  }
  json robots = json::array(), robot_colors = json::array();
  for (std::size_t k = 0; k < run.trace.agents.size(); ++k) {
    robots.push_back(robot_json(run, k, names, options));
    robot_colors.push_back(robot_color(k));
  }
  const json style{{"plume", kPlumeColor},
                   {"region", kRegionColor},
                   {"region_opacity", kRegionOpacity},
                   {"robot", kRobotColor},
                   {"robots", robot_colors},
                   {"detection", kDetectionColor},
                   {"wind", kWindColor},
                   {"true_wind", kTrueWindColor},
                   {"wind_arrow_scale", kWindArrowScale},
                   {"wind_field", kWindFieldColor},
                   {"states", view::state_colors(names)},
                   {"outcomes", outcomes}};

  const auto kept_snaps = view::thin_evenly(run.trace.snapshots.size(), options.max_snapshots);
  return {
      {"plumetrace_view", 2},
      {"version", run.version},
      {"result", detail::result_json(run.result, run.info)},
      {"arena",
       {{"x_min", sc.arena.x_min},
        {"x_max", sc.arena.x_max},
        {"y_min", sc.arena.y_min},
        {"y_max", sc.arena.y_max}}},
      {"source",
       {{"x", sc.source.center.x}, {"y", sc.source.center.y}, {"radius", sc.source.radius}}},
      {"success_radius", sc.supervisor.success_radius},
      {"robot",
       {{"radius", sc.robot.radius}, {"start_x", sc.robot.start.x}, {"start_y", sc.robot.start.y}}},
      {"threshold", sc.odor.threshold},
      {"steps", run.trace.agents.empty() ? 0 : run.trace.agents.front().steps.size()},
      {"states", names},
      {"style", style},
      {"robots", robots},
      {"snapshots", snapshots_json(run, kept_snaps, shade_range(run, kept_snaps))}};
}

// the data as the text of a <script type="application/json"> element
std::string script_safe(const json& data) {
  // why: "</script" would end the element and "<!--" changes how the parser looks for its end;
  // '<' can only stand in JSON strings, where "\u003c" is the same character
  std::string out;
  for (const char c : data.dump()) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string num(double v, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// a number in at most 6 significant digits, without trailing zeros
std::string short_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// a tick label: as many decimals as the step needs
std::string tick_label(double v, double step) {
  const int digits = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  const std::string s = num(v, digits);
  return s == "-0" ? "0" : s;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string run_caption(const RecordedRun& run) {
  const RunResult& r = run.result;
  std::string caption = "plumetrace " + run.version + " \u00b7 " + run.info.algorithm +
                        " \u00b7 seed " + std::to_string(run.info.seed) + " \u00b7 trial " +
                        std::to_string(run.info.trial) + " \u00b7 " +
                        std::string(outcome_name(r.outcome)) + " at " + num(r.time, 1) +
                        " s \u00b7 d_t " + num(r.d_t) + " m \u00b7 d_u " + num(r.d_u) + " m";
  if (std::isfinite(r.overhead)) caption += " \u00b7 overhead " + num(r.overhead);
  return caption;
}

}  // namespace

void check_view_path(const std::string& path, const std::string& option) {
  if (!ends_with(path, ".html") && !ends_with(path, ".svg")) {
    throw ConfigError(option + " '" + path + "': the name must end in .html or .svg");
  }
  check_writable(path);
}

std::string viewer_html(const RecordedRun& run, const ViewerOptions& options) {
  const std::string_view page = view::page_template();
  const std::string_view marker = "/*PLUMETRACE_DATA*/";
  const std::size_t at = page.find(marker);
  std::string html(page.substr(0, at));
  html += script_safe(view_json(run, options));
  html += page.substr(at + marker.size());
  return html;
}

std::string figure_svg(const RecordedRun& run, const ViewerOptions& options) {
  const Scenario& sc = run.scenario;
  const auto& agents = run.trace.agents;
  // why: a robot alone's path shows its states; a team's paths each take their robot's colour,
  // so that one can tell them apart
  const bool team = agents.size() > 1;
  const auto names = state_names(run.trace);
  const auto colors = view::state_colors(names);
  const double width_m = sc.arena.x_max - sc.arena.x_min;
  const double height_m = sc.arena.y_max - sc.arena.y_min;
  // why: the figure, axes and legend fit a 900 px window, at most 60 px per m
  constexpr double kMaxWidth = 900.0;
  const double left = 52.0, right = 16.0, top = 40.0;
  const double scale = std::min(60.0, (kMaxWidth - left - right) / width_m);  // px per m
  const double w_px = std::ceil(left + width_m * scale + right);
  const double arena_bottom = top + height_m * scale;
  const auto px = [&](double x) { return num(left + (x - sc.arena.x_min) * scale); };
  const auto py = [&](double y) { return num(top + (sc.arena.y_max - y) * scale); };
  const auto len = [&](double m) { return num(m * scale); };

  // the legend's entries, laid out in rows within the figure's width
  struct Entry {
    std::string swatch, label;
  };
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < names.size() && !team; ++i) {
    entries.push_back({"<line x1=\"0\" y1=\"0\" x2=\"14\" y2=\"0\" stroke=\"" + colors[i] +
                           "\" stroke-width=\"3\"/>",
                       names[i].empty() ? "(no state)" : names[i]});
  }
  // a mixed team: a robot runs an algorithm of its own
  bool mixed = false;
  for (const auto& a : agents) mixed = mixed || !own_algorithm(run.scenario, a.index).empty();
  for (std::size_t k = 0; k < agents.size() && team; ++k) {
    const RunResult& r = robot_result(run, k);
    entries.push_back(
        {"<line x1=\"0\" y1=\"0\" x2=\"14\" y2=\"0\" stroke=\"" + robot_color(k) +
             "\" stroke-width=\"3\"/>",
         "robot " + std::to_string(agents[k].index) +
             // a mixed team: each robot's own algorithm
             (mixed ? " (" + robot_info(run, agents[k].index).algorithm + ")" : std::string()) +
             ": " + std::string(outcome_name(r.outcome)) + " at " + num(r.time, 1) + " s"});
  }
  if (!run.trace.snapshots.empty()) {
    entries.push_back({std::string("<circle cx=\"7\" cy=\"0\" r=\"6\" fill=\"") + kPlumeColor +
                           "\" fill-opacity=\"0.4\"/>",
                       "filament (radius = width)"});
    entries.push_back(
        {std::string("<rect x=\"0\" y=\"-6\" width=\"14\" height=\"12\" fill=\"") + kRegionColor +
             "\" fill-opacity=\"" + num(kRegionOpacity) + "\"/>",
         "odor perceivable (concentration \u2265 " + short_number(sc.odor.threshold) + ")"});
  }
  entries.push_back(
      {std::string("<circle cx=\"7\" cy=\"0\" r=\"2.5\" fill-opacity=\"0.6\" fill=\"") +
           kDetectionColor + "\"/>",
       "odor detected by the robot"});
  entries.push_back(
      {"<circle cx=\"7\" cy=\"0\" r=\"5\" fill=\"#bbbbbb\" stroke=\"#333333\"/>", "source"});
  entries.push_back(
      {"<circle cx=\"7\" cy=\"0\" r=\"6\" fill=\"none\" stroke=\"#444444\" "
       "stroke-dasharray=\"4 3\"/>",
       "success radius"});
  entries.push_back({std::string("<line x1=\"0\" y1=\"0\" x2=\"14\" y2=\"0\" stroke=\"") +
                         kWindColor + "\" marker-end=\"url(#arrow)\"/>",
                     "wind sample (measured)"});
  entries.push_back(
      {"<circle cx=\"7\" cy=\"0\" r=\"4\" fill=\"none\" stroke=\"#333333\"/>", "start"});
  entries.push_back({std::string("<circle cx=\"7\" cy=\"0\" r=\"6\" fill=\"") + kRobotColor +
                         "\" stroke=\"#ffffff\"/>",
                     team ? "robots at the end" : "robot at the end"});
  bool any_declared = false;
  for (const auto& a : agents) any_declared |= std::isfinite(a.declared.x);
  if (any_declared) {
    entries.push_back(
        {"<path d=\"M7,-6 L13,0 L7,6 L1,0 z\" fill=\"#ffffff\" stroke=\"#333333\" "
         "stroke-width=\"2\"/>",
         "declared source"});
  }
  // why: about 6.5 px a character in a 12 px sans-serif
  const auto entry_width = [](const Entry& e) {
    return 30.0 + 6.5 * static_cast<double>(e.label.size());
  };
  const double legend_top = arena_bottom + 62.0, row_h = 20.0;
  std::vector<std::pair<double, double>> at;  // each entry's x and y
  {
    double lx = left, ly = legend_top;
    for (const auto& e : entries) {
      if (lx > left && lx + entry_width(e) > w_px - right) lx = left, ly += row_h;
      at.push_back({lx, ly});
      lx += entry_width(e);
    }
  }
  const double h_px = std::ceil(at.back().second + 16.0);

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(w_px, 0) << "\" height=\""
      << num(h_px, 0) << "\" viewBox=\"0 0 " << num(w_px, 0) << " " << num(h_px, 0)
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" "
         "markerWidth=\"5\" markerHeight=\"5\" orient=\"auto-start-reverse\">"
         "<path d=\"M0,0 L10,5 L0,10 z\" fill=\""
      << kWindColor << "\"/></marker>"
      << "<clipPath id=\"arena-clip\"><rect x=\"" << px(sc.arena.x_min) << "\" y=\""
      << py(sc.arena.y_max) << "\" width=\"" << len(width_m) << "\" height=\"" << len(height_m)
      << "\"/></clipPath></defs>\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n"
      << "<text x=\"" << num(left) << "\" y=\"24\">" << xml_escape(run_caption(run)) << "</text>\n";

  // arena floor
  svg << "<rect id=\"floor\" x=\"" << px(sc.arena.x_min) << "\" y=\"" << py(sc.arena.y_max)
      << "\" width=\"" << len(width_m) << "\" height=\"" << len(height_m)
      << "\" fill=\"#fafafa\"/>\n";

  // filaments and the detection region at the figure's time, clipped to the arena
  if (!run.trace.snapshots.empty()) {
    const double t = options.figure_time < 0.0 ? INFINITY : options.figure_time;
    const std::size_t i = snapshot_at(run.trace, t);
    const ShadeRange range = shade_range(run, {i});
    const auto& s = run.trace.snapshots[i];
    svg << "<g id=\"plume\" fill=\"" << kPlumeColor << "\" clip-path=\"url(#arena-clip)\">\n";
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      svg << "<circle cx=\"" << px(s.x[k]) << "\" cy=\"" << py(s.y[k]) << "\" r=\"" << len(s.w[k])
          << "\" fill-opacity=\"" << num(0.05 + 0.2 * range.shade(log_peak(run, s.w[k])), 3)
          << "\"/>\n";
    }
    svg << "</g>\n";
    // the region as one path: a rectangle per run of cells in a row
    const MapGrid grid = view::detection_grid(sc);
    const auto mask = detection_mask(sc, s, grid);
    const std::size_t nx = grid.x.size();
    const double cx = nx > 1 ? grid.x[1] - grid.x[0] : 0.0;
    const double cy = grid.y.size() > 1 ? grid.y[1] - grid.y[0] : 0.0;
    svg << "<path id=\"region\" fill=\"" << kRegionColor << "\" fill-opacity=\""
        << num(kRegionOpacity) << "\" clip-path=\"url(#arena-clip)\" d=\"";
    for (std::size_t j = 0; j < grid.y.size(); ++j) {
      for (std::size_t a = 0; a < nx;) {
        if (!mask[j * nx + a]) {
          ++a;
          continue;
        }
        std::size_t b = a;
        while (b < nx && mask[j * nx + b]) ++b;
        svg << "M" << px(grid.x[a] - cx / 2) << "," << py(grid.y[j] + cy / 2) << "h"
            << len(static_cast<double>(b - a) * cx) << "v" << len(cy) << "h-"
            << len(static_cast<double>(b - a) * cx) << "z";
        a = b;
      }
    }
    svg << "\"/>\n";
  }

  // walls
  svg << "<rect id=\"arena\" x=\"" << px(sc.arena.x_min) << "\" y=\"" << py(sc.arena.y_max)
      << "\" width=\"" << len(width_m) << "\" height=\"" << len(height_m)
      << "\" fill=\"none\" stroke=\"#333333\" stroke-width=\"3\"/>\n";

  // axes: ticks in metres every 1, 2 or 5 times a power of ten, at least 40 px apart
  const double step = view::nice_length(40.0 / scale);
  svg << "<g id=\"axes\" stroke=\"#333333\" fill=\"#333333\">\n";
  for (double x = std::ceil(sc.arena.x_min / step - 1e-9) * step; x <= sc.arena.x_max + 1e-9;
       x += step) {
    svg << "<line x1=\"" << px(x) << "\" y1=\"" << num(arena_bottom + 2) << "\" x2=\"" << px(x)
        << "\" y2=\"" << num(arena_bottom + 8) << "\"/><text x=\"" << px(x) << "\" y=\""
        << num(arena_bottom + 21) << "\" text-anchor=\"middle\" stroke=\"none\">"
        << tick_label(x, step) << "</text>\n";
  }
  for (double y = std::ceil(sc.arena.y_min / step - 1e-9) * step; y <= sc.arena.y_max + 1e-9;
       y += step) {
    svg << "<line x1=\"" << num(left - 8) << "\" y1=\"" << py(y) << "\" x2=\"" << num(left - 2)
        << "\" y2=\"" << py(y) << "\"/><text x=\"" << num(left - 11) << "\" y=\""
        << num(top + (sc.arena.y_max - y) * scale + 4) << "\" text-anchor=\"end\" stroke=\"none\">"
        << tick_label(y, step) << "</text>\n";
  }
  svg << "<text x=\"" << num(left + width_m * scale / 2) << "\" y=\"" << num(arena_bottom + 38)
      << "\" text-anchor=\"middle\" stroke=\"none\">x (m), wind along +x</text>\n"
      << "<text transform=\"translate(14," << num(top + height_m * scale / 2)
      << ") rotate(-90)\" text-anchor=\"middle\" stroke=\"none\">y (m)</text>\n"
      << "</g>\n";
  // scale bar, under the arena's right end
  const double bar = view::nice_length(width_m / 10.0);
  const double bar_right = left + width_m * scale, bar_y = arena_bottom + 34;
  svg << "<g id=\"scale-bar\" stroke=\"#000000\" stroke-width=\"2\">"
      << "<line x1=\"" << num(bar_right - bar * scale) << "\" y1=\"" << num(bar_y) << "\" x2=\""
      << num(bar_right) << "\" y2=\"" << num(bar_y) << "\"/>"
      << "<line x1=\"" << num(bar_right - bar * scale) << "\" y1=\"" << num(bar_y - 4) << "\" x2=\""
      << num(bar_right - bar * scale) << "\" y2=\"" << num(bar_y + 4) << "\"/>"
      << "<line x1=\"" << num(bar_right) << "\" y1=\"" << num(bar_y - 4) << "\" x2=\""
      << num(bar_right) << "\" y2=\"" << num(bar_y + 4) << "\"/>"
      << "<text x=\"" << num(bar_right - bar * scale - 6) << "\" y=\"" << num(bar_y + 4)
      << "\" text-anchor=\"end\" stroke=\"none\">" << short_number(bar) << " m</text></g>\n";

  // source and success radius
  svg << "<circle id=\"source\" cx=\"" << px(sc.source.center.x) << "\" cy=\""
      << py(sc.source.center.y) << "\" r=\"" << len(sc.source.radius)
      << "\" fill=\"#bbbbbb\" stroke=\"#333333\"/>\n"
      << "<circle id=\"success\" cx=\"" << px(sc.source.center.x) << "\" cy=\""
      << py(sc.source.center.y) << "\" r=\"" << len(sc.supervisor.success_radius)
      << "\" fill=\"none\" stroke=\"#444444\" stroke-dasharray=\"4 3\"/>\n";

  // odor detections, under the paths: a dark edge along them wherever a robot smelled odor
  svg << "<g id=\"detections\" fill=\"" << kDetectionColor << "\" fill-opacity=\"0.6\">\n";
  for (const auto& a : agents) {
    for (const std::size_t i : view::detection_steps(a.steps, options.detection_spacing)) {
      svg << "<circle cx=\"" << px(a.steps[i].pose.x) << "\" cy=\"" << py(a.steps[i].pose.y)
          << "\" r=\"2.5\"/>\n";
    }
  }
  svg << "</g>\n";

  // trajectories, one polyline per stretch of one state
  svg << "<g id=\"path\" fill=\"none\" stroke-width=\"2\" stroke-linejoin=\"round\">\n";
  for (std::size_t k = 0; k < agents.size(); ++k) {
    const auto& steps = agents[k].steps;
    const auto vertices = view::path_steps(steps, options.path_tolerance);
    for (std::size_t j = 1; j < vertices.size();) {
      const std::string& state = steps[vertices[j]].state;
      svg << "<polyline stroke=\"" << (team ? robot_color(k) : colors[state_index(names, state)])
          << "\" points=\"" << px(steps[vertices[j - 1]].pose.x) << ","
          << py(steps[vertices[j - 1]].pose.y);
      for (; j < vertices.size() && steps[vertices[j]].state == state; ++j) {
        svg << " " << px(steps[vertices[j]].pose.x) << "," << py(steps[vertices[j]].pose.y);
      }
      svg << "\"/>\n";
    }
  }
  svg << "</g>\n";

  svg << "<g id=\"wind\" stroke=\"" << kWindColor << "\" stroke-width=\"1\">\n";
  for (const auto& a : agents) {
    for (const auto& w : wind_samples(a.steps)) {
      svg << "<line x1=\"" << px(w.x) << "\" y1=\"" << py(w.y) << "\" x2=\""
          << px(w.x + kWindArrowScale * w.measured.x) << "\" y2=\""
          << py(w.y + kWindArrowScale * w.measured.y) << "\" marker-end=\"url(#arrow)\"/>\n";
    }
  }
  svg << "</g>\n";

  // each robot's start, where it declared the source, and the robot at its last pose
  for (std::size_t k = 0; k < agents.size(); ++k) {
    const auto& a = agents[k];
    if (a.steps.empty()) continue;
    const std::string color = robot_color(k);
    // why: appended, not "-" + to_string(index), which GCC 12 warns of (-Wrestrict)
    std::string id;
    if (k > 0) id.append("-").append(std::to_string(a.index));
    const Pose& start = a.steps.front().pose;
    const Pose& end = a.steps.back().pose;
    const double r = std::max(4.0, sc.robot.radius * scale);
    const double ex = left + (end.x - sc.arena.x_min) * scale;
    const double ey = top + (sc.arena.y_max - end.y) * scale;
    svg << "<circle id=\"start" << id << "\" cx=\"" << px(start.x) << "\" cy=\"" << py(start.y)
        << "\" r=\"4\" fill=\"none\" stroke=\"" << color << "\"/>\n";
    if (std::isfinite(a.declared.x) && std::isfinite(a.declared.y)) {
      const double dx = left + (a.declared.x - sc.arena.x_min) * scale;
      const double dy = top + (sc.arena.y_max - a.declared.y) * scale;
      svg << "<path id=\"declared" << id << "\" d=\"M" << num(dx) << "," << num(dy - 7) << " L"
          << num(dx + 7) << "," << num(dy) << " L" << num(dx) << "," << num(dy + 7) << " L"
          << num(dx - 7) << "," << num(dy) << " z\" fill=\"#ffffff\" stroke=\"" << color
          << "\" stroke-width=\"2\"/>\n";
    }
    svg << "<g id=\"robot" << id << "\"><circle cx=\"" << num(ex) << "\" cy=\"" << num(ey)
        << "\" r=\"" << num(r) << "\" fill=\"" << color << "\" stroke=\"#ffffff\"/>"
        << "<line x1=\"" << num(ex) << "\" y1=\"" << num(ey) << "\" x2=\""
        << num(ex + 1.6 * r * std::cos(end.heading)) << "\" y2=\""
        << num(ey - 1.6 * r * std::sin(end.heading)) << "\" stroke=\"" << color
        << "\" stroke-width=\"2\"/></g>\n";
  }

  svg << "<g id=\"legend\">\n";
  for (std::size_t i = 0; i < entries.size(); ++i) {
    svg << "<g transform=\"translate(" << num(at[i].first) << "," << num(at[i].second) << ")\">"
        << entries[i].swatch << "<text x=\"18\" y=\"4\">" << xml_escape(entries[i].label)
        << "</text></g>\n";
  }
  svg << "</g>\n</svg>\n";
  return svg.str();
}

void write_view(const std::string& path, const RecordedRun& run, const ViewerOptions& options) {
  check_view_path(path, "view");
  const std::string text =
      ends_with(path, ".svg") ? figure_svg(run, options) : viewer_html(run, options);
  write_text_file(path, text);
}

}  // namespace plumetrace
