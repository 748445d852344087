#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// One row of a trace: the state after a step.
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
};

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
  std::vector<TraceStep> steps;             ///< one row at release, then one per step
  std::vector<FilamentSnapshot> snapshots;  ///< filaments at the snapshot interval
  WindGrid wind_grid;                       ///< where each snapshot's wind was sampled
};

/// Records a World into a Trace; use as the StepObserver of run_once.
class TraceRecorder {
 public:
  /// Snapshots the filaments every `snapshot_interval` seconds (0: never).
  TraceRecorder(Trace& trace, double snapshot_interval, double dt);
  /// Appends the world's current state.
  void operator()(const World& world);

 private:
  Trace& trace_;
  long snapshot_every_;
  long calls_ = 0;
};

}  // namespace plumetrace
