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
  ReacquireSide reacquire_side = ReacquireSide::kAlternate;
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
