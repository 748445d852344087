#pragma once

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// Which side the upwind leg takes after a crosswind leg finds the plume again.
enum class ReacquireSide {
  kAlternate,  ///< UPWIND(-s): the zigzag of the paper's state machine
  kSame,       ///< UPWIND(s): the side held before the loss
};

/// Parameters of casting (paper section 2.1).
struct CastingParams {
  /// Angle of the upwind legs to the measured upwind direction (rad).
  double beta = deg_to_rad(25.0);
  /// Path length without odor after which the plume is lost (m).
  double d_lost = 0.614;
  /// Side of the upwind leg after reacquisition; the next crosswind leg still goes toward -s.
  /// why: same, the paper's "moves upwind with angle beta again" (docs/fidelity.md, unknown 13
  /// and "Which reading won").
  ReacquireSide reacquire_side = ReacquireSide::kSame;

  /// The config keys (core/config.hpp), in the table "casting".
  template <class V>
  void fields(V& v) {
    const double deg = kPi / 180.0;
    v("beta_deg", beta, "upwind leg angle to the measured upwind direction (deg)",
      NumberSpec{.min = 0.0, .max = 90.0 * deg, .max_open = true, .scale = deg});
    v("d_lost", d_lost, "path length without odor before the plume is lost (m)", kPositive);
    v("reacquire_side", reacquire_side, "upwind side after a crosswind leg finds odor",
      {"alternate", "same"});
  }
};

/// Casting: upwind at +-beta while in the plume, crosswind back into it once lost; zigzags.
class Casting final : public Controller {
 public:
  /// States of the machine.
  enum class State { kUpwind, kCrosswind };

  /// Creates the controller; `rng` chooses the first side.
  Casting(const CastingParams& params, Rng rng) : params_(params), rng_(rng) {}
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override;
  int losses() const override { return losses_; }
  /// Current side s (+1 or -1) of the upwind leg.
  int side() const { return side_; }

 private:
  CastingParams params_;
  Rng rng_;
  State state_ = State::kUpwind;
  bool started_ = false;
  int side_ = 1;
  double heading_ = 0.0;
  int losses_ = 0;
  LossTracker tracker_;
};

}  // namespace plumetrace
