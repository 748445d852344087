#pragma once

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// Parameters of surge-spiral (paper section 2.2).
struct SurgeSpiralParams {
  /// Gap between successive turns of the spiral (m).
  double d_gap = 0.222;
  /// Path length without odor after which the plume is lost (m).
  double d_lost = 0.614;
  /// Radius (m) on the spiral r = b theta at which the robot starts: it follows the curvature
  /// profile from theta0 = start_radius / b on (0: from the centre). why: 0.049, the Khepera III
  /// toolbox's spiral (docs/fidelity.md, unknown 10).
  double start_radius = 0.049;

  /// The config keys (core/config.hpp), in the table "surge_spiral".
  template <class V>
  void fields(V& v) {
    v("d_gap", d_gap, "gap between spiral turns (m)", kPositive);
    v("d_lost", d_lost, "path length without odor before the plume is lost (m)", kPositive);
    v("start_radius", start_radius, "radius on the spiral r = b theta where spiralling starts (m)",
      NumberSpec{.min = 0.0, .max = 5.0});
  }
};

/// Surge-spiral: straight upwind in the plume; once lost, an Archimedean spiral that starts
/// upwind and curls toward the guessed plume side.
class SurgeSpiral final : public Controller {
 public:
  /// States of the machine.
  enum class State { kSurge, kSpiral };

  /// Creates the controller; `rng` breaks side-guess ties.
  SurgeSpiral(const SurgeSpiralParams& params, Rng rng) : params_(params), rng_(rng) {}
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override;
  int losses() const override { return losses_; }
  /// Direction the current spiral curls: +1 counter-clockwise (left), -1 clockwise.
  int curl() const { return spiral_.curl(); }

 private:
  SurgeSpiralParams params_;
  Rng rng_;
  State state_ = State::kSurge;
  bool started_ = false;
  double heading_ = 0.0;  // surge heading, or the spiral's start heading
  bool aligned_ = false;  // spiral: turned to its start heading
  SpiralPath spiral_;
  int losses_ = 0;
  LossTracker tracker_;
};

}  // namespace plumetrace
