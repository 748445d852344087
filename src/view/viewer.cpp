#include "plumetrace/view/viewer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "plumetrace/core/files.hpp"
#include "plumetrace/env/wind.hpp"
#include "plumetrace/io/json_util.hpp"
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

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b0 = bytes[i];
    const std::uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0;
    const std::uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const std::uint32_t v = (b0 << 16) | (b1 << 8) | b2;
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
  }
  return out;
}

std::string state_color(std::size_t index) {
  // why: Tableau 10 without its blue (the plume) and red (the robot), so layers stay apart
  static const char* const kPalette[] = {"#f28e2b", "#59a14f", "#b07aa1", "#9c755f",
                                         "#edc948", "#76b7b2", "#ff9da7", "#bab0ac"};
  return kPalette[index % (sizeof kPalette / sizeof kPalette[0])];
}

}  // namespace view

namespace {

using nlohmann::json;

// the colours every view shares (the page reads them from its data)
constexpr const char* kPlumeColor = "#4e79a7";
constexpr const char* kRobotColor = "#e15759";
constexpr const char* kDetectionColor = "#000000";
constexpr const char* kWindColor = "#555555";
constexpr const char* kTrueWindColor = "#aaaaaa";
constexpr const char* kWindFieldColor = "#c4c4c4";
// wind arrows: metres drawn per m/s
constexpr double kWindArrowScale = 0.25;

double rounded(double v, double unit) { return std::round(v / unit) * unit; }

// states in order of first appearance
std::vector<std::string> state_names(const Trace& trace) {
  std::vector<std::string> names;
  for (const auto& s : trace.steps) {
    if (std::find(names.begin(), names.end(), s.state) == names.end()) names.push_back(s.state);
  }
  return names;
}

std::size_t state_index(const std::vector<std::string>& names, const std::string& state) {
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), state) - names.begin());
}

// a wind sample: where it was taken and the measured and true wind in the world frame
struct WindSample {
  double time, x, y;
  Vec2 measured, truth;
};

// the true wind where the robot sampled it, as the trace recorded it. why: read from the trace's
// scenario, not from a wind field rebuilt here (a second copy of the run's wind); the one model,
// constant, blows its recorded velocity everywhere and always. A wind model that varies must
// record its truth in the trace, and the switch (-Wswitch) names this place when one is added.
Vec3 recorded_true_wind(const WindParams& wind) {
  switch (wind.model) {
    case WindModel::kConstant:
      return wind.velocity;
    case WindModel::kMeander:
      // why: the trace does not record the meandering field yet (issue 15, the viewer's part):
      // its mean is drawn, which the local wind departs from by the meander
      return wind.velocity;
  }
  return {NAN, NAN, NAN};
}

std::vector<WindSample> wind_samples(const RecordedRun& run) {
  const Vec3 v = recorded_true_wind(run.scenario.wind);
  std::vector<WindSample> out;
  for (const auto& s : run.trace.steps) {
    if (s.wind_samples <= 0) continue;
    const double c = std::cos(s.pose.heading), sn = std::sin(s.pose.heading);
    const Vec2 measured{c * s.wind_body.x - sn * s.wind_body.y,
                        sn * s.wind_body.x + c * s.wind_body.y};
    out.push_back({s.time, s.pose.x, s.pose.y, measured, {v.x, v.y}});
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

// quantises values into 16 bits over their range: v = origin + q * unit
struct Quantizer {
  double origin = 0.0, unit = 1.0;
  Quantizer(double lo, double hi, double finest) : origin(lo) {
    unit = std::max(finest, (hi - lo) / 65535.0);
  }
  std::uint16_t operator()(double v) const {
    return static_cast<std::uint16_t>(std::clamp(std::round((v - origin) / unit), 0.0, 65535.0));
  }
};

void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v & 0xff));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}

// the true wind at the trace's grid for each kept snapshot (none for a trace without one)
json wind_field_json(const RecordedRun& run, const std::vector<std::size_t>& kept) {
  const WindGrid& g = run.trace.wind_grid;
  json u = json::array(), v = json::array();
  for (const std::size_t i : kept) {
    const auto& s = run.trace.snapshots[i];
    json su = json::array(), sv = json::array();
    for (std::size_t k = 0; k < s.wind_x.size(); ++k) {
      su.push_back(rounded(s.wind_x[k], 1e-3));
      sv.push_back(rounded(s.wind_y[k], 1e-3));
    }
    u.push_back(std::move(su));
    v.push_back(std::move(sv));
  }
  return {{"x0", g.x0}, {"dx", g.dx}, {"nx", g.nx}, {"y0", g.y0},
          {"dy", g.dy}, {"ny", g.ny}, {"u", u},     {"v", v}};
}

json snapshots_json(const RecordedRun& run, const std::vector<std::size_t>& kept,
                    const ShadeRange& range) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const std::size_t i : kept) {
    const auto& s = run.trace.snapshots[i];
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const double v[3] = {s.x[k], s.y[k], s.w[k]};
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], v[c]), hi[c] = std::max(hi[c], v[c]);
    }
  }
  for (int c = 0; c < 3; ++c) {
    if (!(lo[c] <= hi[c])) lo[c] = hi[c] = 0.0;
  }
  // why: 1 mm positions and 0.01 mm widths are below a pixel at any sensible zoom
  const Quantizer qx(lo[0], hi[0], 1e-3), qy(lo[1], hi[1], 1e-3), qw(lo[2], hi[2], 1e-5);
  std::vector<std::uint8_t> xs, ys, ws, shades;
  json times = json::array(), counts = json::array();
  for (const std::size_t i : kept) {
    const auto& s = run.trace.snapshots[i];
    times.push_back(rounded(s.time, 1e-3));
    counts.push_back(s.x.size());
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      put_u16(xs, qx(s.x[k]));
      put_u16(ys, qy(s.y[k]));
      put_u16(ws, qw(s.w[k]));
      shades.push_back(
          static_cast<std::uint8_t>(std::lround(255.0 * range.shade(log_peak(run, s.w[k])))));
    }
  }
  return {{"time", times},
          {"count", counts},
          {"x", {{"origin", qx.origin}, {"unit", qx.unit}, {"data", view::base64(xs)}}},
          {"y", {{"origin", qy.origin}, {"unit", qy.unit}, {"data", view::base64(ys)}}},
          {"w", {{"origin", qw.origin}, {"unit", qw.unit}, {"data", view::base64(ws)}}},
          {"shade", view::base64(shades)},
          {"peak_lo", std::pow(10.0, range.lo)},
          {"peak_hi", std::pow(10.0, range.hi)},
          {"wind_field", wind_field_json(run, kept)}};
}

// everything the page draws, thinned as the options say
json view_json(const RecordedRun& run, const ViewerOptions& options) {
  const Scenario& sc = run.scenario;
  const auto& steps = run.trace.steps;
  const auto names = state_names(run.trace);

  json style{{"plume", kPlumeColor},         {"robot", kRobotColor},
             {"detection", kDetectionColor}, {"wind", kWindColor},
             {"true_wind", kTrueWindColor},  {"wind_arrow_scale", kWindArrowScale},
             {"wind_field", kWindFieldColor},
             {"states", json::array()}};
  for (std::size_t i = 0; i < names.size(); ++i) style["states"].push_back(view::state_color(i));

  json frames{{"step", json::array()}, {"time", json::array()},          {"x", json::array()},
              {"y", json::array()},    {"heading", json::array()},       {"state", json::array()},
              {"d_t", json::array()},  {"concentration", json::array()}, {"odor", json::array()}};
  for (const std::size_t i : view::frame_steps(steps, options.max_frames)) {
    const TraceStep& s = steps[i];
    frames["step"].push_back(i);
    frames["time"].push_back(rounded(s.time, 1e-4));
    frames["x"].push_back(rounded(s.pose.x, 1e-5));
    frames["y"].push_back(rounded(s.pose.y, 1e-5));
    frames["heading"].push_back(rounded(s.pose.heading, 1e-5));
    frames["state"].push_back(state_index(names, s.state));
    frames["d_t"].push_back(rounded(s.odometer, 1e-5));
    frames["concentration"].push_back(s.concentration);
    frames["odor"].push_back(s.odor ? 1 : 0);
  }

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
  for (const auto& w : wind_samples(run)) {
    wind["time"].push_back(rounded(w.time, 1e-4));
    wind["x"].push_back(rounded(w.x, 1e-5));
    wind["y"].push_back(rounded(w.y, 1e-5));
    wind["u"].push_back(rounded(w.measured.x, 1e-5));
    wind["v"].push_back(rounded(w.measured.y, 1e-5));
    wind["true_u"].push_back(rounded(w.truth.x, 1e-5));
    wind["true_v"].push_back(rounded(w.truth.y, 1e-5));
  }

  const auto kept_snaps = view::thin_evenly(run.trace.snapshots.size(), options.max_snapshots);
  return {
      {"plumetrace_view", 1},
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
      {"steps", steps.size()},
      {"states", names},
      {"style", style},
      {"frames", frames},
      {"path", path},
      {"detections", detections},
      {"wind", wind},
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
  const auto& steps = run.trace.steps;
  const auto names = state_names(run.trace);
  const double width_m = sc.arena.x_max - sc.arena.x_min;
  const double height_m = sc.arena.y_max - sc.arena.y_min;
  const double scale = std::min(60.0, 1100.0 / width_m);  // px per m
  const double margin = 20.0, top = 40.0;
  const double legend_h = 48.0;
  const double w_px = width_m * scale + 2 * margin;
  const double h_px = height_m * scale + top + margin + legend_h;
  const auto px = [&](double x) { return num(margin + (x - sc.arena.x_min) * scale); };
  const auto py = [&](double y) { return num(top + (sc.arena.y_max - y) * scale); };
  const auto len = [&](double m) { return num(m * scale); };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(w_px, 0) << "\" height=\""
      << num(h_px, 0) << "\" viewBox=\"0 0 " << num(w_px, 0) << " " << num(h_px, 0)
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" "
         "markerWidth=\"5\" markerHeight=\"5\" orient=\"auto-start-reverse\">"
         "<path d=\"M0,0 L10,5 L0,10 z\" fill=\""
      << kWindColor << "\"/></marker></defs>\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n"
      << "<text x=\"" << num(margin) << "\" y=\"24\">" << xml_escape(run_caption(run))
      << "</text>\n";

  // arena floor and walls
  svg << "<rect id=\"arena\" x=\"" << px(sc.arena.x_min) << "\" y=\"" << py(sc.arena.y_max)
      << "\" width=\"" << len(width_m) << "\" height=\"" << len(height_m)
      << "\" fill=\"#fafafa\" stroke=\"#333333\" stroke-width=\"3\"/>\n";

  // filaments at the figure's time
  if (!run.trace.snapshots.empty()) {
    const double t = options.figure_time < 0.0 ? INFINITY : options.figure_time;
    const std::size_t i = snapshot_at(run.trace, t);
    const ShadeRange range = shade_range(run, {i});
    const auto& s = run.trace.snapshots[i];
    svg << "<g id=\"plume\" fill=\"" << kPlumeColor << "\">\n";
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      svg << "<circle cx=\"" << px(s.x[k]) << "\" cy=\"" << py(s.y[k]) << "\" r=\"" << len(s.w[k])
          << "\" fill-opacity=\"" << num(0.05 + 0.2 * range.shade(log_peak(run, s.w[k])), 3)
          << "\"/>\n";
    }
    svg << "</g>\n";
  }

  // source and success radius
  svg << "<circle id=\"source\" cx=\"" << px(sc.source.center.x) << "\" cy=\""
      << py(sc.source.center.y) << "\" r=\"" << len(sc.source.radius)
      << "\" fill=\"#bbbbbb\" stroke=\"#333333\"/>\n"
      << "<circle id=\"success\" cx=\"" << px(sc.source.center.x) << "\" cy=\""
      << py(sc.source.center.y) << "\" r=\"" << len(sc.supervisor.success_radius)
      << "\" fill=\"none\" stroke=\"#444444\" stroke-dasharray=\"4 3\"/>\n";

  // odor detections, under the path: a dark edge along it wherever the robot smelled odor
  svg << "<g id=\"detections\" fill=\"" << kDetectionColor << "\" fill-opacity=\"0.6\">\n";
  for (const std::size_t i : view::detection_steps(steps, options.detection_spacing)) {
    svg << "<circle cx=\"" << px(steps[i].pose.x) << "\" cy=\"" << py(steps[i].pose.y)
        << "\" r=\"2.5\"/>\n";
  }
  svg << "</g>\n";

  // trajectory, one polyline per stretch of one state
  const auto vertices = view::path_steps(steps, options.path_tolerance);
  svg << "<g id=\"path\" fill=\"none\" stroke-width=\"2\" stroke-linejoin=\"round\">\n";
  for (std::size_t j = 1; j < vertices.size();) {
    const std::string& state = steps[vertices[j]].state;
    svg << "<polyline stroke=\"" << view::state_color(state_index(names, state)) << "\" points=\""
        << px(steps[vertices[j - 1]].pose.x) << "," << py(steps[vertices[j - 1]].pose.y);
    for (; j < vertices.size() && steps[vertices[j]].state == state; ++j) {
      svg << " " << px(steps[vertices[j]].pose.x) << "," << py(steps[vertices[j]].pose.y);
    }
    svg << "\"/>\n";
  }
  svg << "</g>\n";

  svg << "<g id=\"wind\" stroke=\"" << kWindColor << "\" stroke-width=\"1\">\n";
  for (const auto& w : wind_samples(run)) {
    svg << "<line x1=\"" << px(w.x) << "\" y1=\"" << py(w.y) << "\" x2=\""
        << px(w.x + kWindArrowScale * w.measured.x) << "\" y2=\""
        << py(w.y + kWindArrowScale * w.measured.y) << "\" marker-end=\"url(#arrow)\"/>\n";
  }
  svg << "</g>\n";

  // start and the robot at its last pose
  if (!steps.empty()) {
    const Pose& start = steps.front().pose;
    const Pose& end = steps.back().pose;
    const double r = std::max(4.0, sc.robot.radius * scale);
    const double ex = margin + (end.x - sc.arena.x_min) * scale;
    const double ey = top + (sc.arena.y_max - end.y) * scale;
    svg << "<circle id=\"start\" cx=\"" << px(start.x) << "\" cy=\"" << py(start.y)
        << "\" r=\"4\" fill=\"none\" stroke=\"#333333\"/>\n"
        << "<g id=\"robot\"><circle cx=\"" << num(ex) << "\" cy=\"" << num(ey) << "\" r=\""
        << num(r) << "\" fill=\"" << kRobotColor << "\" stroke=\"#222222\"/>"
        << "<line x1=\"" << num(ex) << "\" y1=\"" << num(ey) << "\" x2=\""
        << num(ex + 1.6 * r * std::cos(end.heading)) << "\" y2=\""
        << num(ey - 1.6 * r * std::sin(end.heading)) << "\" stroke=\"#222222\" "
        << "stroke-width=\"2\"/></g>\n";
  }

  // legend
  double lx = margin;
  const double ly = top + height_m * scale + margin + 14.0;
  svg << "<g id=\"legend\">\n";
  const auto entry = [&](const std::string& swatch, const std::string& label) {
    svg << "<g transform=\"translate(" << num(lx) << "," << num(ly) << ")\">" << swatch
        << "<text x=\"18\" y=\"4\">" << xml_escape(label) << "</text></g>\n";
    lx += 30.0 + 7.0 * static_cast<double>(label.size());
  };
  for (std::size_t i = 0; i < names.size(); ++i) {
    entry("<line x1=\"0\" y1=\"0\" x2=\"14\" y2=\"0\" stroke=\"" + view::state_color(i) +
              "\" stroke-width=\"3\"/>",
          names[i].empty() ? "(no state)" : names[i]);
  }
  entry(std::string("<circle cx=\"7\" cy=\"0\" r=\"6\" fill=\"") + kPlumeColor +
            "\" fill-opacity=\"0.4\"/>",
        "filament (radius = width)");
  entry(std::string("<circle cx=\"7\" cy=\"0\" r=\"2.5\" fill-opacity=\"0.6\" fill=\"") +
            kDetectionColor + "\"/>",
        "odor detected (dark edge of the path)");
  entry("<circle cx=\"7\" cy=\"0\" r=\"5\" fill=\"#bbbbbb\" stroke=\"#333333\"/>", "source");
  entry(std::string("<line x1=\"0\" y1=\"0\" x2=\"14\" y2=\"0\" stroke=\"") + kWindColor +
            "\" marker-end=\"url(#arrow)\"/>",
        "wind sample");
  entry(std::string("<circle cx=\"7\" cy=\"0\" r=\"6\" fill=\"") + kRobotColor +
            "\" stroke=\"#222222\"/>",
        "robot");
  entry(
      "<circle cx=\"7\" cy=\"0\" r=\"6\" fill=\"none\" stroke=\"#444444\" "
      "stroke-dasharray=\"4 3\"/>",
      "success radius");
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
