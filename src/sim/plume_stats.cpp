#include "plumetrace/sim/plume_stats.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/math.hpp"
#include "plumetrace/core/parallel.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

SensorPath straight_path(Vec2 from, double heading, double length, double z, double speed,
                         double dt) {
  SensorPath path;
  const double step = speed * dt;
  const double c = math::cos(heading), s = math::sin(heading);
  // why: the count first, so that rounding never adds a point beyond length
  const auto n = static_cast<long>(std::floor(std::max(0.0, length) / step + 1e-9));
  path.points.reserve(static_cast<std::size_t>(n) + 1);
  path.arc.reserve(static_cast<std::size_t>(n) + 1);
  for (long k = 0; k <= n; ++k) {
    const double a = static_cast<double>(k) * step;
    path.points.push_back({from.x + a * c, from.y + a * s, z});
    path.arc.push_back(a);
  }
  return path;
}

namespace {

// the spiral's b (m/rad): r = b theta puts successive turns d_gap apart
double spiral_b(const SurgeSpiralParams& params) { return params.d_gap / (2.0 * kPi); }

}  // namespace

double spiral_turns(const SurgeSpiralParams& params, double arc) {
  const double b = spiral_b(params);
  const double theta0 = params.start_radius / b;
  const double offset = spiral_arc_length(b, theta0);
  return (spiral_angle_at(b, offset + arc, theta0) - theta0) / (2.0 * kPi);
}

SensorPath spiral_path(const Pose& start, int curl, const SurgeSpiralParams& params,
                       const RobotParams& robot, double z, double dt, double turns,
                       const ArenaParams* arena, bool* wall) {
  // why: the controller's own law (SurgeSpiral::step): at each step the curvature of r = b theta
  // at the path length covered, counted from the spiral's centre; the robot's wheels set the speed
  const double b = spiral_b(params);
  const double theta0 = params.start_radius / b;
  const double offset = spiral_arc_length(b, theta0);
  const double end = theta0 + 2.0 * kPi * turns;
  SensorPath path;
  RobotState state;
  state.pose = start;
  double theta = theta0;
  const auto clear = [&](const Pose& p) {
    const double r = robot.radius;
    return !arena || (p.x - r > arena->x_min && p.x + r < arena->x_max && p.y - r > arena->y_min &&
                      p.y + r < arena->y_max);
  };
  bool walled = false;
  for (;;) {
    if (!clear(state.pose)) {
      walled = true;
      break;
    }
    path.points.push_back({state.pose.x, state.pose.y, z});
    path.arc.push_back(state.odometer);
    theta = spiral_angle_at(b, offset + state.odometer, theta);
    if (theta >= end) break;
    step_robot(robot, Command::curve(curl * spiral_curvature(b, theta)), dt, state);
  }
  if (wall) *wall = walled;
  return path;
}

VirtualSensors::VirtualSensors(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                               double warmup)
    : scenario_(scenario), env_(make_environment(scenario, seed, trial)) {
  Scenario warm = scenario;
  if (!std::isnan(warmup)) warm.sim.warmup = warmup;
  warm_up(warm, env_);
}

std::size_t VirtualSensors::follow(SensorPath path) {
  sensors_.push_back({std::move(path), now_ + (read_ ? 1 : 0), {}});
  sensors_.back().odor.reserve(sensors_.back().path.points.size());
  return sensors_.size() - 1;
}

void VirtualSensors::stop(std::size_t i) {
  Sensor& s = sensors_.at(i);
  s.path.points.resize(s.odor.size());
  s.path.arc.resize(s.odor.size());
}

void VirtualSensors::read() {
  if (read_) return;
  for (auto& s : sensors_) {
    if (now_ < s.start) continue;
    const auto k = static_cast<std::size_t>(now_ - s.start);
    if (k >= s.path.points.size()) continue;
    s.odor.push_back(env_.odor->reaches(s.path.points[k], scenario_.odor.threshold) ? 1 : 0);
  }
  read_ = true;
}

void VirtualSensors::advance() {
  plumetrace::step(env_, scenario_.sim.dt);
  ++now_;
  read_ = false;
}

bool VirtualSensors::done() const {
  return std::all_of(sensors_.begin(), sensors_.end(),
                     [](const Sensor& s) { return s.odor.size() >= s.path.points.size(); });
}

void VirtualSensors::run() {
  while (!done()) step();
}

std::vector<std::vector<std::uint8_t>> sense_paths(const Scenario& scenario, std::uint64_t seed,
                                                   std::uint64_t trial,
                                                   const std::vector<SensorPath>& paths,
                                                   double warmup) {
  VirtualSensors sensors(scenario, seed, trial, warmup);
  for (const auto& p : paths) sensors.follow(p);
  sensors.run();
  std::vector<std::vector<std::uint8_t>> out;
  for (std::size_t i = 0; i < paths.size(); ++i) out.push_back(sensors.odor(i));
  return out;
}

GapAnalysis analyse_gaps(const std::vector<std::uint8_t>& odor, const std::vector<double>& arc) {
  GapAnalysis g;
  g.samples = static_cast<long>(odor.size());
  long last = -1;  // the last detection so far
  for (std::size_t k = 0; k < odor.size(); ++k) {
    if (!odor[k]) continue;
    ++g.detections;
    if (last < 0) {
      g.first = arc[k];
      g.leading = k == 0 ? 0.0 : arc[k - 1] - arc[0];
    } else if (static_cast<long>(k) > last + 1) {
      g.gaps.push_back(arc[k - 1] - arc[static_cast<std::size_t>(last)]);
    }
    last = static_cast<long>(k);
  }
  if (last < 0) {
    g.leading = arc.empty() ? 0.0 : arc.back() - arc.front();
  } else {
    g.last = arc[static_cast<std::size_t>(last)];
    g.trailing = arc.back() - g.last;
  }
  return g;
}

double sorted_quantile(const std::vector<double>& ascending, double q) {
  if (ascending.empty()) return NAN;
  const double h = q * static_cast<double>(ascending.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, ascending.size() - 1);
  return ascending[lo] + (h - static_cast<double>(lo)) * (ascending[hi] - ascending[lo]);
}

namespace {

// the median of values in any order (NaN when empty)
double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return sorted_quantile(v, 0.5);
}

GapStats pool(const std::vector<const GapAnalysis*>& analyses, double d_lost) {
  GapStats st;
  for (const GapAnalysis* g : analyses) {
    ++st.paths;
    st.paths_with_odor += g->detections > 0;
    st.samples += g->samples;
    st.detections += g->detections;
    st.gaps.insert(st.gaps.end(), g->gaps.begin(), g->gaps.end());
  }
  std::sort(st.gaps.begin(), st.gaps.end());
  if (st.gaps.empty()) return st;
  st.median = sorted_quantile(st.gaps, 0.5);
  st.p90 = sorted_quantile(st.gaps, 0.9);
  st.longest = st.gaps.back();
  st.longer_than_d_lost = st.gaps.end() - std::lower_bound(st.gaps.begin(), st.gaps.end(), d_lost);
  st.fraction_longer =
      static_cast<double>(st.longer_than_d_lost) / static_cast<double>(st.gaps.size());
  return st;
}

// one spiral's outcome
struct SpiralRun {
  double loss_x = NAN;
  bool detected = false;
  bool wall = false;   // its path ended at a wall
  double arc = NAN;    // path length to the detection (m)
  double turns = NAN;  // turns to the detection
};

// everything measured in one trial (one plume)
struct TrialStats {
  std::vector<GapAnalysis> along, across;
  GapAnalysis release;
  int surges = 0;
  std::vector<SpiralRun> spirals;  // one per surge that lost the plume
};

// the wind sensor read as the robot reads it at `pose` (its own model), as an upwind heading
double measured_upwind(const Scenario& scenario, const Environment& env, const Pose& pose,
                       Rng& rng) {
  const Vec3 w = sense_wind_body(scenario.wind_sensor, *env.wind, pose, scenario.odor.height, rng);
  return upwind_heading({w.x, w.y}, pose.heading);
}

// path length (m) from p along heading before the robot's body would touch a wall, or before x
// passes `x_end` going upwind
double room_ahead(const Scenario& scenario, Vec2 p, double heading, double x_end) {
  const auto& a = scenario.arena;
  const double r = scenario.robot.radius;
  const double c = math::cos(heading), s = math::sin(heading);
  double length = INFINITY;
  if (c < 0.0) length = std::min(length, (std::max(x_end, a.x_min + r) - p.x) / c);
  if (c > 0.0) length = std::min(length, (a.x_max - r - p.x) / c);
  if (s < 0.0) length = std::min(length, (a.y_min + r - p.y) / s);
  if (s > 0.0) length = std::min(length, (a.y_max - r - p.y) / s);
  return std::max(0.0, length);
}

// a virtual surge: a straight line at a measured upwind heading, with the controllers' loss test
struct Surge {
  std::size_t sensor = 0;
  double heading = 0.0;  // rad
  LossTracker tracker;
  bool over = false;  // lost the plume, or reached its path's end
};

TrialStats measure_trial(const Scenario& scenario, const PlumeStatsOptions& options,
                         std::uint64_t trial) {
  const double dt = scenario.sim.dt, z = scenario.odor.height, v = scenario.robot.wheel_speed;
  const Vec3& src = scenario.source.center;
  const Pose& start = scenario.robot.start;
  const auto& spiral = scenario.controller.get<SurgeSpiralParams>();
  Rng rng(derive_seed(options.seed, trial, Stream::kVirtualSensor));

  // lines along and across the plume, the release, the surges: all start at release
  VirtualSensors sensors(scenario, options.seed, trial, options.warmup);
  std::vector<std::size_t> along, across;
  for (const double dy : options.offsets) {
    along.push_back(
        sensors.follow(straight_path({start.x, src.y + dy}, kPi, start.x - src.x, z, v, dt)));
  }
  const auto& a = scenario.arena;
  const double r = scenario.robot.radius;
  for (const double d : options.across) {
    across.push_back(sensors.follow(
        straight_path({src.x + d, a.y_min + r}, kPi / 2.0, a.y_max - a.y_min - 2.0 * r, z, v, dt)));
  }
  const std::size_t release =
      sensors.follow(straight_path({start.x, start.y}, kPi, spiral.d_lost, z, v, dt));
  std::vector<Surge> surges(static_cast<std::size_t>(options.surges));
  for (auto& s : surges) {
    s.heading = measured_upwind(scenario, sensors.environment(), start, rng);
    s.sensor = sensors.follow(
        straight_path({start.x, start.y}, s.heading,
                      room_ahead(scenario, {start.x, start.y}, s.heading, src.x), z, v, dt));
  }

  TrialStats t;
  std::vector<std::size_t> spirals;
  while (!sensors.done()) {
    sensors.read();
    // a spiral ends at its first detection: only that one counts
    for (const std::size_t i : spirals) {
      const auto& odor = sensors.odor(i);
      if (!odor.empty() && odor.back() && odor.size() < sensors.path(i).points.size()) {
        sensors.stop(i);
      }
    }
    for (auto& s : surges) {
      if (s.over) continue;
      const auto& odor = sensors.odor(s.sensor);
      const auto& path = sensors.path(s.sensor);
      const std::size_t k = odor.size() - 1;
      Observation obs;
      obs.odor = odor[k] != 0;
      obs.odometer = path.arc[k];
      s.tracker.observe(obs);
      if (!s.tracker.lost(obs, spiral.d_lost)) {
        s.over = k + 1 == path.points.size();
        continue;
      }
      // why: as SurgeSpiral::step at a loss: measure the wind, guess the side; the spiral starts
      // upwind at the next step, after the turn on the spot
      s.over = true;
      sensors.stop(s.sensor);
      const Vec3 p = path.points[k];
      const double upwind =
          measured_upwind(scenario, sensors.environment(), {p.x, p.y, s.heading}, rng);
      const int curl = guess_plume_side(s.heading, upwind, rng);
      bool wall = false;
      spirals.push_back(sensors.follow(spiral_path({p.x, p.y, upwind}, curl, spiral, scenario.robot,
                                                   z, dt, options.turns, &scenario.arena, &wall)));
      t.spirals.push_back({p.x, false, wall});
    }
    sensors.advance();
  }

  for (const std::size_t i : along) {
    t.along.push_back(analyse_gaps(sensors.odor(i), sensors.path(i).arc));
  }
  for (const std::size_t i : across) {
    t.across.push_back(analyse_gaps(sensors.odor(i), sensors.path(i).arc));
  }
  t.release = analyse_gaps(sensors.odor(release), sensors.path(release).arc);
  t.surges = options.surges;
  for (std::size_t j = 0; j < spirals.size(); ++j) {
    const auto& odor = sensors.odor(spirals[j]);
    const auto hit = std::find(odor.begin(), odor.end(), std::uint8_t{1});
    if (hit == odor.end()) continue;
    SpiralRun& s = t.spirals[j];
    s.detected = true;
    s.arc = sensors.path(spirals[j]).arc[static_cast<std::size_t>(hit - odor.begin())];
    s.turns = spiral_turns(spiral, s.arc);
  }
  return t;
}

void check_options(const Scenario& scenario, const PlumeStatsOptions& o) {
  if (o.trials < 1 || o.trials > 1000) throw ConfigError("--trials: must be 1 to 1000");
  if (o.threads < 1 || o.threads > 1024) throw ConfigError("--threads: must be 1 to 1024");
  if (o.surges < 0 || o.surges > 1000) throw ConfigError("--surges: must be 0 to 1000");
  if (!(o.turns > 0.0 && o.turns <= 100.0)) {
    throw ConfigError("--turns: must be a number of turns above 0 and at most 100");
  }
  if (!std::isnan(o.warmup) && !(o.warmup >= 0.0 && o.warmup / scenario.sim.dt <= kMaxSteps)) {
    throw ConfigError("--warmup: must be at least 0 and at most 1e7 steps of sim.dt");
  }
  const auto finite_all = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!finite_all(o.offsets) || o.offsets.size() > 100) {
    throw ConfigError("--offsets: at most 100 finite numbers (m)");
  }
  if (!finite_all(o.across) || o.across.size() > 100) {
    throw ConfigError("--across: at most 100 finite numbers (m)");
  }
  if (!(scenario.robot.start.x > scenario.source.center.x)) {
    throw ConfigError("robot.start_x: the plume statistics need the robot downwind of source.x");
  }
}

}  // namespace

PlumeStats plume_stats(const Scenario& scenario, const PlumeStatsOptions& options) {
  check_options(scenario, options);
  std::vector<TrialStats> trials(static_cast<std::size_t>(options.trials));
  parallel_for(trials.size(), options.threads,
               [&](std::size_t k) { trials[k] = measure_trial(scenario, options, k); });

  PlumeStats st;
  st.trials = options.trials;
  st.seed = options.seed;
  st.d_lost = scenario.controller.get<SurgeSpiralParams>().d_lost;
  st.speed = scenario.robot.wheel_speed;
  st.turns = options.turns;
  for (std::size_t i = 0; i < options.offsets.size(); ++i) {
    std::vector<const GapAnalysis*> all;
    std::vector<double> leading;
    for (const auto& t : trials) {
      all.push_back(&t.along[i]);
      leading.push_back(t.along[i].leading);
    }
    st.along.push_back({options.offsets[i], pool(all, st.d_lost), median_of(leading)});
  }
  for (std::size_t i = 0; i < options.across.size(); ++i) {
    Crossing c;
    c.distance = options.across[i];
    std::vector<const GapAnalysis*> all;
    for (const auto& t : trials) {
      all.push_back(&t.across[i]);
      if (t.across[i].detections > 0) c.band_widths.push_back(t.across[i].last - t.across[i].first);
    }
    c.gaps = pool(all, st.d_lost);
    c.band_median = median_of(c.band_widths);
    if (!c.band_widths.empty()) {
      c.band_max = *std::max_element(c.band_widths.begin(), c.band_widths.end());
    }
    st.across.push_back(std::move(c));
  }
  auto& sp = st.spirals;
  for (const auto& t : trials) {
    ++st.release.trials;
    st.release.in_odor += t.release.first == 0.0;
    st.release.within_d_lost += t.release.detections > 0;
    sp.surges += t.surges;
    for (const auto& s : t.spirals) {
      ++sp.lost;
      sp.loss_x.push_back(s.loss_x);
      if (!s.detected) {
        sp.walls += s.wall;
        sp.out_of_turns += !s.wall;
        continue;
      }
      ++sp.reacquired;
      sp.within_one_turn += s.turns <= 1.0;
      sp.distances.push_back(s.arc);
      sp.turns_to_odor.push_back(s.turns);
    }
  }
  sp.distance_median = median_of(sp.distances);
  return st;
}

}  // namespace plumetrace
