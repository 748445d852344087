#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace plumetrace {

/// How a run ended (docs/model.md section 8).
enum class Outcome { kRunning, kSuccess, kWall, kTimeout, kGaveUp };

/// Name of an outcome: "running", "success", "wall", "timeout", "gave_up".
std::string_view outcome_name(Outcome outcome);

/// The metrics of one run (docs/model.md section 9).
struct RunResult {
  /// How the run ended.
  Outcome outcome = Outcome::kRunning;
  /// Simulated time from release to the end (s).
  double time = 0.0;
  /// Path length of the robot centre (m).
  double d_t = 0.0;
  /// Upwind displacement, start x minus end x (m).
  double d_u = 0.0;
  /// d_t / d_u; NaN when d_u <= 0.
  double overhead = 0.0;
  /// Times the plume was declared lost.
  int losses = 0;
  /// Fraction of steps with odor perceived.
  double odor_fraction = 0.0;
  /// Steps run after release.
  std::int64_t steps = 0;
  /// Wind samples the controller took.
  std::int64_t wind_samples = 0;
  /// Master seed that, with the trial index, replays the run.
  std::uint64_t seed = 0;
  /// Trial index.
  std::uint64_t trial = 0;
};

/// Identifies a run: what the trace and the JSON output carry besides the result.
struct RunInfo {
  std::string algorithm;    ///< algorithm name
  std::uint64_t seed = 0;   ///< master seed
  std::uint64_t trial = 0;  ///< trial index
};

}  // namespace plumetrace
