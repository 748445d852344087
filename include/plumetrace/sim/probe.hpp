#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// How to sample a plume without a robot.
struct ProbeOptions {
  /// Plume-only time before sampling starts (s); NaN: the scenario's sim.warmup.
  double warmup = NAN;
  /// Time over which samples are taken (s).
  double duration = 60.0;
  /// Time between samples (s), rounded to whole steps (at least one).
  double interval = 0.32;
  /// Master seed; the plume stream of trial 0 is used.
  std::uint64_t seed = 1;
};

/// What the plume looks like at one point.
struct ProbeResult {
  /// The point (m).
  Vec3 point;
  /// Fraction of sampled instants with concentration >= the odor threshold.
  double detect_fraction = 0.0;
  /// Mean concentration over the sampled instants.
  double mean_concentration = 0.0;
  /// Number of sampled instants.
  long samples = 0;
};

/// Checks that the options take at least one sample and at most kMaxSteps steps; throws ConfigError
/// naming the option.
void check_probe_options(const ProbeOptions& options, const Scenario& scenario);

/// Runs the scenario's plume alone and samples the concentration at each point.
std::vector<ProbeResult> probe_plume(const Scenario& scenario, const std::vector<Vec3>& points,
                                     const ProbeOptions& options);

}  // namespace plumetrace
