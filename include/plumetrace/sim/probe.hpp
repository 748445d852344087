#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"

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
  /// Downwind positions x (m) at which the plume's centreline is measured (may be empty).
  std::vector<double> centreline_x;
  /// Width along x of the slab of filaments whose mean y is the centreline at an x (m).
  double centreline_slab = 0.2;
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

/// The plume's centreline at one downwind position x: at every sampled instant, the mean lateral
/// position y of the filaments whose centres lie within centreline_slab / 2 of x; then the mean
/// and spread of that position over the instants (docs/model.md, "Plume statistics").
struct CentrelineResult {
  /// The downwind position (m).
  double x = 0.0;
  /// Mean over the instants of the centreline's y (m); NaN when no instant had a filament there.
  double mean_y = NAN;
  /// Sample standard deviation of the centreline's y over the instants (m); NaN below two.
  double std_y = NAN;
  /// Instants with at least one filament in the slab.
  long samples = 0;
  /// Instants with none (the plume did not reach x, or the odor model draws no filaments).
  long empty = 0;
};

/// A probe's results: each point's statistics, then each centreline.
struct ProbeReport {
  std::vector<ProbeResult> points;            ///< per point, in the order given
  std::vector<CentrelineResult> centrelines;  ///< per ProbeOptions::centreline_x
};

/// A grid of points at one height: x and y centres, row-major by y.
struct MapGrid {
  std::vector<double> x;  ///< column centres (m)
  std::vector<double> y;  ///< row centres (m)
  double z = 0.0;         ///< height (m)
};

/// The grid of the detection map: cells of dx by dy (m) over the arena, at the odor sensor's
/// height.
MapGrid arena_grid(const Scenario& scenario, double dx = 0.2, double dy = 0.05);

/// The detection map: the fraction of sampled instants with odor perceived at every cell centre
/// of `grid`, as fraction[j][i] for y[j], x[i] (the intermittency at each point).
std::vector<std::vector<double>> detection_map(const Scenario& scenario, const MapGrid& grid,
                                               const ProbeOptions& options);

/// Where the robot's odor sensor would have perceived odor at the instant of a filament snapshot:
/// for each cell centre of `grid` (row-major by y, x fastest), 1 when the concentration of the
/// snapshot's filaments there (the scenario's kernel and cut-off) reaches odor.threshold, else 0.
/// Contributions below 1e-9 of the threshold are left out, so only a cell within that much of
/// the threshold can read otherwise than the model's concentration().
std::vector<std::uint8_t> detection_mask(const Scenario& scenario, const FilamentSnapshot& snapshot,
                                         const MapGrid& grid);

/// Checks that the options take at least one sample and at most kMaxSteps steps; throws ConfigError
/// naming the option.
void check_probe_options(const ProbeOptions& options, const Scenario& scenario);

/// Runs the scenario's plume alone and samples the concentration at each point.
std::vector<ProbeResult> probe_plume(const Scenario& scenario, const std::vector<Vec3>& points,
                                     const ProbeOptions& options);

/// probe_plume, and the centrelines at options.centreline_x from the same instants.
ProbeReport probe_report(const Scenario& scenario, const std::vector<Vec3>& points,
                         const ProbeOptions& options);

}  // namespace plumetrace
