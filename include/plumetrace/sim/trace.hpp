#pragma once

#include <cmath>
#include <concepts>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// What the formats need to know of a step column besides its value's type.
struct TraceField {
  std::string_view name = {};  ///< column (CSV, JSON, the viewer's frames) name
  std::string_view unit = {};  ///< SI unit, "" for a name, a count or a flag
  bool nullable = false;       ///< may be NaN: written as null (JSON), "" (CSV)
  bool sampled = false;        ///< meaningful only when wind_samples > 0: null or "" otherwise
};

/// One row of a trace: the state of one robot after a step.
struct TraceStep {
  /// Time since release (s).
  double time = 0.0;
  /// True robot pose (m, rad).
  Pose pose;
  /// Path length so far (m).
  double odometer = 0.0;
  /// Controller state after its decision.
  std::string state;
  /// Odor perceived at this step.
  bool odor = false;
  /// Concentration at the sensor.
  double concentration = 0.0;
  /// Wind samples the controller took this step (0 or more).
  int wind_samples = 0;
  /// Last wind sample of this step in the robot frame (m/s); meaningful when wind_samples > 0.
  Vec3 wind_body;
  /// True wind at the robot's sensor after the step, world frame, x and y (m/s); NaN where a
  /// trace did not record it (format 1 in a wind that varies).
  Vec2 true_wind;

  /// The one list of a trace's step columns, in column order: calls `v(TraceField, value)` for
  /// each (a double, std::string, bool or int member). The recorder fills them, the CSV and JSON
  /// traces write and read them, and the viewer's frames carry them. wind_samples comes before
  /// the columns it makes meaningful.
  template <class Self, class Visitor>
  requires std::same_as<std::remove_const_t<Self>, TraceStep>
  static constexpr void fields(Self& s, Visitor&& v) {
    v({.name = "time", .unit = "s"}, s.time);
    v({.name = "x", .unit = "m"}, s.pose.x);
    v({.name = "y", .unit = "m"}, s.pose.y);
    v({.name = "heading", .unit = "rad"}, s.pose.heading);
    v({.name = "odometer", .unit = "m"}, s.odometer);
    v({.name = "state"}, s.state);
    v({.name = "odor"}, s.odor);
    v({.name = "concentration"}, s.concentration);
    v({.name = "wind_samples"}, s.wind_samples);
    v({.name = "wind_x_body", .unit = "m/s", .sampled = true}, s.wind_body.x);
    v({.name = "wind_y_body", .unit = "m/s", .sampled = true}, s.wind_body.y);
    v({.name = "wind_z_body", .unit = "m/s", .sampled = true}, s.wind_body.z);
    v({.name = "true_wind_x", .unit = "m/s", .nullable = true}, s.true_wind.x);
    v({.name = "true_wind_y", .unit = "m/s", .nullable = true}, s.true_wind.y);
  }
};

/// Every step column's description, in TraceStep::fields order (for headers and schemas).
const std::vector<TraceField>& trace_fields();

/// One robot of a trace: who it is, where it started, how it ended and its steps.
struct AgentTrace {
  /// Its index in its team.
  int index = 0;
  /// Its release pose (m, rad): the origin of its odometry frame.
  Pose start;
  /// Where it declared the source (m, world frame); NaN when it did not.
  Vec2 declared{NAN, NAN};
  /// Its metrics at the last step recorded.
  RunResult result;
  /// One row at release, then one per step while it runs.
  std::vector<TraceStep> steps;
};

/// A controller's snapshot (Controller::snapshot) at one instant, moved to the world frame.
struct ControllerSnapshot {
  /// Time since release (s).
  double time = 0.0;
  /// The agent whose controller it is (its index in the team).
  int agent = 0;
  /// The agent's release pose (m, rad): the origin of the odometry frame its grid is in.
  Pose start;
  /// Points, path and estimate in the world frame (m); the grid as the controller gave it, in
  /// the odometry frame (x0, y0, dx, dy), to be drawn rotated by start.heading about start.
  Snapshot snapshot;
};

/// The numbers a snapshot holds, as kMaxSnapshotValues counts them: 2 a point, 1 a weight, 2 a
/// path vertex, 1 a grid cell.
std::size_t snapshot_values(const Snapshot& snapshot);

/// A snapshot in the odometry frame of a robot released at `start`, moved to the world frame:
/// points, path and estimate rotated by start.heading and moved by the start position; the grid
/// is left in the odometry frame.
Snapshot snapshot_in_world(const Snapshot& odometry, const Pose& start);

/// Positions and widths of every filament at one instant.
struct FilamentSnapshot {
  /// Time since release (s); the first snapshot is at release.
  double time = 0.0;
  std::vector<double> x;  ///< positions x (m)
  std::vector<double> y;  ///< positions y (m)
  std::vector<double> z;  ///< positions z (m)
  std::vector<double> w;  ///< widths (m)
  /// The true wind at the nodes of the trace's wind grid, x and y components (m/s), row-major by
  /// y; empty when the trace has no wind grid.
  std::vector<double> wind_x, wind_y;
};

/// Where a trace samples the true wind field at each snapshot: nx by ny nodes at (x0 + i dx,
/// y0 + j dy, z), so a viewer can draw the air the plume moves in.
struct WindGrid {
  double x0 = 0.0;  ///< first node x (m)
  double dx = 1.0;  ///< node spacing along x (m)
  int nx = 0;       ///< nodes along x
  double y0 = 0.0;  ///< first node y (m)
  double dy = 0.5;  ///< node spacing along y (m)
  int ny = 0;       ///< nodes along y
  double z = 0.0;   ///< height (m)
  /// Number of nodes.
  std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
};

/// The wind grid of a trace of the scenario: nodes every 1 m along x and 0.5 m along y, at the
/// centres of those cells of the arena, at the odor sensor's height.
WindGrid trace_wind_grid(const Scenario& scenario);

/// Everything recorded about one run, for plots and viewers.
struct Trace {
  /// Every robot of robot 0's team, robot 0 first; an empty trace has none.
  std::vector<AgentTrace> agents;
  std::vector<FilamentSnapshot> snapshots;  ///< filaments at the snapshot interval
  /// The controllers' snapshots at the snapshot interval and at each robot's end, in time order
  /// (robots in order at one time); a controller that shows nothing has none.
  std::vector<ControllerSnapshot> controller_snapshots;
  WindGrid wind_grid;  ///< where each snapshot's wind was sampled
};

/// Records a World into a Trace: every robot of robot 0's team; use as the StepObserver of
/// run_once or run_team.
class TraceRecorder {
 public:
  /// Snapshots the filaments and the controllers every `snapshot_interval` seconds (0: never).
  TraceRecorder(Trace& trace, double snapshot_interval, double dt);
  /// Appends the world's current state; throws ConfigError naming the controller when its state
  /// name or its snapshot is too large for a trace.
  void operator()(const World& world);

 private:
  Trace& trace_;
  long snapshot_every_;
  long calls_ = 0;
};

}  // namespace plumetrace
