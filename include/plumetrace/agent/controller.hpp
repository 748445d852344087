#pragma once

#include <cmath>
#include <cstddef>
#include <string_view>
#include <vector>

#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/math.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

/// What a controller shows of its internal state for traces and the viewer (docs/agents.md,
/// "Snapshots"): points with weights (particles, waypoints), a path, a grid of values (a belief
/// map) and a point estimate, all in the controller's odometry frame. Empty by default.
struct Snapshot {
  /// Points (m, odometry frame): particles, candidate sources.
  std::vector<Vec2> points;
  /// One weight per point, or empty (equal weights).
  std::vector<double> weights;
  /// A polyline (m, odometry frame): a planned path.
  std::vector<Vec2> path;
  /// A grid of nx by ny values, row-major by y, cell (i, j) centred at (x0 + i dx, y0 + j dy)
  /// in the odometry frame; empty when there is none.
  std::vector<double> grid;
  double x0 = 0.0;  ///< grid: first cell centre x (m)
  double y0 = 0.0;  ///< grid: first cell centre y (m)
  double dx = 1.0;  ///< grid: cell size along x (m)
  double dy = 1.0;  ///< grid: cell size along y (m)
  int nx = 0;       ///< grid: cells along x
  int ny = 0;       ///< grid: cells along y
  /// The controller's estimate of the source (m, odometry frame), when it has one.
  bool has_estimate = false;
  Vec2 estimate;  ///< the estimate when has_estimate

  /// True when there is nothing to draw.
  bool empty() const { return points.empty() && path.empty() && grid.empty() && !has_estimate; }
};

/// The most numbers one snapshot may hold (points count 2, grid cells 1). why: traces record a
/// snapshot at every filament snapshot; a grid of a million cells a frame would make traces of
/// gigabytes.
inline constexpr std::size_t kMaxSnapshotValues = 200'000;

/// A plume-tracking algorithm: turns measurements into motion commands.
/// why: controllers include only geometry and measurement (and config, for their params' keys),
/// so they cannot peek at the world.
class Controller {
 public:
  virtual ~Controller() = default;
  /// Decides this step's command; may sample the wind through `wind` (at state switches only).
  virtual Command step(const Observation& obs, WindProbe& wind) = 0;
  /// Name of the current state, for traces.
  virtual std::string_view state() const = 0;
  /// Number of times the plume was declared lost so far.
  virtual int losses() const = 0;
  /// What the controller reads besides the binary odor, time, odometry and the wind probe
  /// (Reads flags); the paper's controllers read nothing more.
  virtual unsigned reads() const { return kReadsBinary; }
  /// Its internal state for traces and the viewer; called only when a trace records it.
  virtual Snapshot snapshot() const { return {}; }
};

/// The longest state name a controller may report (bytes). why: traces store the name of every
/// step, and the viewer copies it per frame: a 1 MB name made a 5.8 MB trace take 4.8 GB to view
/// (issue 22, G8).
inline constexpr std::size_t kMaxStateName = 64;

/// Throws ConfigError saying why when `name` is not a state name: longer than kMaxStateName, or
/// holding a control character.
void check_state_name(std::string_view name);

/// Tracks the path length since the last odor detection; the robot starts in the plume.
class LossTracker {
 public:
  /// Records this step's odor flag and odometer.
  void observe(const Observation& obs) {
    if (obs.odor) last_odor_odometer_ = obs.odometer;
  }
  /// True once the robot has travelled d_lost (m) since the last detection.
  bool lost(const Observation& obs, double d_lost) const {
    return obs.odometer - last_odor_odometer_ >= d_lost;
  }

 private:
  double last_odor_odometer_ = 0.0;
};

/// A straight leg of a walk: a heading and a path length to drive. It is over when the odometer
/// has advanced its length since it began, or when the robot is blocked: a step on which it was
/// told to go, neither turned nor moved (a wall under supervisor.walls = "block", or a teammate:
/// docs/agents.md, "Walls"). why: a robot pressing a wall never advances its odometer, so a walk
/// that waits for its length would push for ever; ending the leg lets the walk turn away.
class Leg {
 public:
  /// Starts a leg at this observation: drive `length` (m) on `heading` (rad, odometry frame).
  void start(const Observation& obs, double heading, double length) {
    heading_ = heading;
    length_ = length;
    start_odometer_ = obs.odometer;
    start_ = {obs.odometry.x, obs.odometry.y};
    last_ = obs.odometry;
    last_odometer_ = obs.odometer;
    steps_ = 0;
    blocked_ = false;
  }
  /// Takes this step's observation (the leg's command was obeyed since the last); true when the
  /// leg is over, driven to its length or blocked.
  bool over(const Observation& obs) {
    if (steps_ > 0 && obs.odometer == last_odometer_ && obs.odometry.heading == last_.heading) {
      blocked_ = true;
    }
    last_ = obs.odometry;
    last_odometer_ = obs.odometer;
    return blocked_ || obs.odometer - start_odometer_ >= length_;
  }
  /// The command that drives the leg this step.
  Command command() {
    ++steps_;
    return Command::go(heading_);
  }
  /// Whether the leg ended because the robot was blocked.
  bool blocked() const { return blocked_; }
  /// The leg's heading (rad, odometry frame).
  double heading() const { return heading_; }
  /// The leg's length (m).
  double length() const { return length_; }
  /// Path length driven on this leg so far (m).
  double driven(const Observation& obs) const { return obs.odometer - start_odometer_; }
  /// Where the leg began (m, odometry frame).
  Vec2 start_point() const { return start_; }
  /// Where the leg ends if it is driven to its length (m, odometry frame).
  Vec2 end_point() const {
    return {start_.x + length_ * math::cos(heading_), start_.y + length_ * math::sin(heading_)};
  }

 private:
  double heading_ = 0.0;
  double length_ = 0.0;
  double start_odometer_ = 0.0;
  Vec2 start_;
  Pose last_;
  double last_odometer_ = 0.0;
  int steps_ = 0;
  bool blocked_ = false;
};

/// Draws a turning angle (rad, in [-pi, pi]) from the wrapped Cauchy law WC(0, rho), 0 <= rho
/// <= 1, whose mean cosine is rho: uniform at rho = 0, no turn at rho = 1 (Codling, Plank &
/// Benhamou 2008, J. R. Soc. Interface 5:813; docs/algorithms.md, "crw").
double wrapped_cauchy(double rho, Rng& rng);

/// Path length (m) of the Archimedean spiral r = b theta from its centre to angle theta (rad).
double spiral_arc_length(double b, double theta);

/// Angle theta (rad) at which the spiral r = b theta has path length s (m); Newton from `guess`.
double spiral_angle_at(double b, double s, double guess);

/// Curvature (1/m) of the spiral r = b theta at angle theta (rad).
double spiral_curvature(double b, double theta);

/// Follows the Archimedean spiral r = b theta, b = d_gap / (2 pi), by its curvature at the path
/// length driven (docs/model.md section 7.3): surge-spiral's and hayes' spirals.
class SpiralPath {
 public:
  /// A spiral of gap `d_gap` (m) entered at radius `start_radius` (m) on it, curling `curl`
  /// (+1 counter-clockwise, -1 clockwise); its path length counts from anchor().
  void start(double d_gap, double start_radius, int curl);
  /// Fixes where the spiral's path starts: the odometer (m) at its first step.
  void anchor(double odometer) { s0_ = odometer; }
  /// The curvature (1/m, signed by the curl) to drive at odometer reading `odometer` (m).
  double curvature(double odometer);
  /// Direction it curls: +1 counter-clockwise (left), -1 clockwise.
  int curl() const { return curl_; }

 private:
  double b_ = 1.0;           // r = b theta (m/rad)
  double theta_ = 0.0;       // angle reached (rad)
  double arc_offset_ = 0.0;  // path length from the centre to the start radius (m)
  double s0_ = 0.0;          // odometer at the anchor (m)
  int curl_ = 1;
};

/// Guesses the plume side (+1 left of upwind, -1 right) after a loss: the robot drifted to the side
/// its surge heading erred toward, so the plume is on the other side; a tie is broken at random.
int guess_plume_side(double surge_heading, double upwind_now, Rng& rng);

}  // namespace plumetrace
