#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <vector>

#include "plumetrace/agent/controllers/surge_spiral.hpp"
#include "plumetrace/agent/robot.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// Where a virtual odor sensor is at each of its samples, one time step apart, and how far it
/// has come (docs/plume-statistics.md).
struct SensorPath {
  std::vector<Vec3> points;  ///< the sensor's position at each sample (m)
  std::vector<double> arc;   ///< path length from the first point to each point (m)
};

/// A straight path from `from` along `heading` (rad) for `length` (m) at height `z`, one point
/// every `speed * dt` (m/s, s): the first at `from`, the last the last whole step within length.
SensorPath straight_path(Vec2 from, double heading, double length, double z, double speed,
                         double dt);

/// The surge-spiral controller's Archimedes spiral (agent/controllers/surge_spiral.hpp) as the
/// robot drives it from `start`, curling counter-clockwise for curl = +1 (clockwise for -1):
/// entered at `params.start_radius`, the centre slowed on curves as the robot's wheels slow it
/// (step_robot), one point per step of `dt`, for `turns` turns of the spiral angle; with
/// `arena`, it ends before the robot's body would touch a wall, where a run would end; `wall`
/// (when given) says whether it did.
SensorPath spiral_path(const Pose& start, int curl, const SurgeSpiralParams& params,
                       const RobotParams& robot, double z, double dt, double turns,
                       const ArenaParams* arena = nullptr, bool* wall = nullptr);

/// The turns of the spiral angle done after `arc` (m) of a spiral_path with `params`.
double spiral_turns(const SurgeSpiralParams& params, double arc);

/// Virtual odor sensors moving along paths through the plume of one trial: the scenario's
/// environment (wind and odor, streams from (seed, trial), as a run's), warmed up, then stepped
/// while each sensor reads the binary odor at its path's points, one per step. No robot, no
/// controller, no walls: a sensor only samples, so the paths never change the plume.
class VirtualSensors {
 public:
  /// The environment of (seed, trial) after `warmup` (s; NaN: the scenario's sim.warmup).
  VirtualSensors(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                 double warmup = NAN);

  /// Starts a sensor on `path`: its first point is read at the next read(), at release for a
  /// sensor started before the first step, as a robot reads its sensor at release. Returns the
  /// sensor's index.
  std::size_t follow(SensorPath path);
  /// Ends sensor `i`'s path at the points it has read.
  void stop(std::size_t i);
  /// Reads every sensor still on its path at the current step (once per step).
  void read();
  /// Advances the environment one step.
  void advance();
  /// read(), then advance().
  void step() {
    read();
    advance();
  }
  /// True once every sensor has read its whole path.
  bool done() const;
  /// Steps until done().
  void run();

  /// Steps since release (the first read is at 0).
  long steps() const { return now_; }
  /// The environment now (the wind a sensor at a state switch would measure).
  const Environment& environment() const { return env_; }
  /// The odor flags read so far by sensor `i` (1: the concentration reached odor.threshold); the
  /// reference stays valid while sensors are added.
  const std::vector<std::uint8_t>& odor(std::size_t i) const { return sensors_.at(i).odor; }
  /// The path of sensor `i`.
  const SensorPath& path(std::size_t i) const { return sensors_.at(i).path; }

 private:
  struct Sensor {
    SensorPath path;
    long start = 0;
    std::vector<std::uint8_t> odor;
  };
  const Scenario& scenario_;
  Environment env_;
  long now_ = 0;
  bool read_ = false;  // the current step has been read
  // why: a deque, so that a sensor's path and flags stay where they are when another starts
  std::deque<Sensor> sensors_;
};

/// The odor flags of sensors on `paths`, all started at release in the plume of (seed, trial).
std::vector<std::vector<std::uint8_t>> sense_paths(const Scenario& scenario, std::uint64_t seed,
                                                   std::uint64_t trial,
                                                   const std::vector<SensorPath>& paths,
                                                   double warmup = NAN);

/// What one sensor read along its path, as the controllers' loss test sees it
/// (docs/plume-statistics.md).
struct GapAnalysis {
  /// The gaps between detections: for each two successive detections with no odor between
  /// them, the path length from the first to the last sample before the second (m): the
  /// longest distance since the last detection a sensor reaches inside the gap, the distance a
  /// controller compares with d_lost. A sensor misses the plume for d_lost inside a gap iff
  /// the gap is at least d_lost.
  std::vector<double> gaps;
  /// The path length from the first point to the last sample before the first detection (m;
  /// 0 when the first sample detects, the whole path when none does).
  double leading = 0.0;
  /// The path length from the last detection to the path's end (m; NaN when none).
  double trailing = NAN;
  /// Path length at the first and the last detection (m; NaN when none): the detection band.
  double first = NAN, last = NAN;
  /// Samples, and those with odor.
  long samples = 0, detections = 0;
};

/// The gaps of one sensor's odor flags along path lengths `arc` (same size).
GapAnalysis analyse_gaps(const std::vector<std::uint8_t>& odor, const std::vector<double>& arc);

/// Gap lengths of several sensors pooled, with their summary (docs/plume-statistics.md).
struct GapStats {
  int paths = 0;                 ///< sensors pooled
  int paths_with_odor = 0;       ///< sensors with at least one detection
  long samples = 0;              ///< samples read
  long detections = 0;           ///< samples with odor
  std::vector<double> gaps;      ///< every gap, ascending (m)
  double median = NAN;           ///< median gap (m; NaN without gaps)
  double p90 = NAN;              ///< 90th percentile of the gaps (m)
  double longest = NAN;          ///< longest gap (m)
  long longer_than_d_lost = 0;   ///< gaps at least d_lost long
  double fraction_longer = NAN;  ///< longer_than_d_lost over the gaps (NaN without gaps)
};

/// One line straight upwind at a lateral offset from the source, from the robot's start to the
/// source's x.
struct AlongLine {
  double offset = 0.0;  ///< y - source.y (m)
  GapStats gaps;        ///< pooled over the trials
  /// Median over the trials of the path length before the first detection (m).
  double leading_median = NAN;
};

/// One line crosswind, wall to wall, at a distance downwind of the source.
struct Crossing {
  double distance = 0.0;            ///< x - source.x (m)
  GapStats gaps;                    ///< gaps inside the detection band, pooled over the trials
  std::vector<double> band_widths;  ///< per trial with odor: last minus first detection (m)
  double band_median = NAN;         ///< median band width (m)
  double band_max = NAN;            ///< widest band (m)
};

/// Whether the robot is released in odor: a sensor at the robot's start, moving upwind.
struct ReleaseStats {
  int trials = 0;         ///< trials
  int in_odor = 0;        ///< odor at the start at release (t = 0 after the warm-up)
  int within_d_lost = 0;  ///< odor before d_lost of travel upwind (no loss at the start)
};

/// Whether "a spiral of increasing radius will always reacquire the plume": virtual surges from
/// the robot's start at a measured upwind heading, and the surge-spiral's spiral from where each
/// loses the plume, followed until it detects odor, meets a wall or has done its turns.
struct SpiralStats {
  int surges = 0;                     ///< virtual surges
  int lost = 0;                       ///< surges that lost the plume (each starts a spiral)
  std::vector<double> loss_x;         ///< x of each loss (m), in trial and surge order
  int within_one_turn = 0;            ///< spirals that detected odor within one turn
  int reacquired = 0;                 ///< spirals that detected odor at all
  int walls = 0;                      ///< spirals that met a wall without odor
  int out_of_turns = 0;               ///< spirals that did all their turns without odor
  std::vector<double> distances;      ///< path length to the detection, per detecting spiral (m)
  double distance_median = NAN;       ///< median of distances (m)
  std::vector<double> turns_to_odor;  ///< turns to the detection, per detecting spiral
};

/// How to measure a plume's statistics (docs/plume-statistics.md).
struct PlumeStatsOptions {
  /// Plume-only time before release (s); NaN: the scenario's sim.warmup.
  double warmup = NAN;
  /// Master seed; trial k uses the plume of (seed, k), the plume a run's trial k meets.
  std::uint64_t seed = 1;
  /// Trials (plumes), 1 to 1000. why: every trial's gaps are kept until they are pooled (some 30 kB
  /// each for the default plume), and a thousand plumes take minutes.
  int trials = 20;
  /// Worker threads (results do not depend on them).
  int threads = 1;
  /// Lateral offsets of the upwind lines from the source (m).
  std::vector<double> offsets{0.0, 0.1, -0.1, 0.2, -0.2};
  /// Distances downwind of the source of the crosswind lines (m).
  std::vector<double> across{2.0, 8.0, 14.0};
  /// Virtual surges per trial, 0 to 1000.
  int surges = 8;
  /// Turns of each spiral followed at most (it ends earlier at a wall), > 0 and at most 100.
  double turns = 10.0;
};

/// A plume's statistics (docs/plume-statistics.md).
struct PlumeStats {
  int trials = 0;          ///< trials pooled
  std::uint64_t seed = 0;  ///< master seed
  double d_lost = 0.0;     ///< surge_spiral.d_lost: the loss distance compared with (m)
  double speed = 0.0;      ///< robot.wheel_speed: every sensor's speed on straight lines (m/s)
  double turns = 0.0;      ///< turns of each spiral followed at most
  std::vector<AlongLine> along;  ///< per offset
  std::vector<Crossing> across;  ///< per distance
  ReleaseStats release;          ///< released in odor
  SpiralStats spirals;           ///< spiral reacquisition
};

/// Checks the options (ConfigError naming the option); then measures the statistics over
/// options.trials plumes of the scenario, on options.threads threads.
PlumeStats plume_stats(const Scenario& scenario, const PlumeStatsOptions& options);

/// The type-7 quantile q in [0, 1] of ascending values (NaN when empty).
double sorted_quantile(const std::vector<double>& ascending, double q);

}  // namespace plumetrace
