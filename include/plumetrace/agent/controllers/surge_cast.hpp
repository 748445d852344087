#pragma once

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// Parameters of surge-cast (paper section 2.3).
struct SurgeCastParams {
  /// Length of the first cast (m); the second is twice as long.
  double d_cast = 0.27;
  /// Path length without odor after which the plume is lost (m).
  double d_lost = 0.614;

  /// The config keys (core/config.hpp), in the table "surge_cast".
  template <class V>
  void fields(V& v) {
    v("d_cast", d_cast, "length of the first cast (m)", kPositive);
    v("d_lost", d_lost, "path length without odor before the plume is lost (m)", kPositive);
  }
};

/// Surge-cast: straight upwind in the plume; once lost, a crosswind cast of d_cast toward the
/// guessed side, then 2 d_cast back the other way, then it gives up.
class SurgeCast final : public Controller {
 public:
  /// States of the machine.
  enum class State { kSurge, kCast1, kCast2 };

  /// Creates the controller; `rng` breaks side-guess ties.
  SurgeCast(const SurgeCastParams& params, Rng rng) : params_(params), rng_(rng) {}
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override;
  int losses() const override { return losses_; }
  /// Side of the current or last first cast: +1 left of upwind, -1 right.
  int cast_side() const { return side_; }

 private:
  SurgeCastParams params_;
  Rng rng_;
  State state_ = State::kSurge;
  bool started_ = false;
  double heading_ = 0.0;  // surge heading
  double upwind_ = 0.0;   // upwind measured at the loss
  int side_ = 1;
  double cast_start_ = 0.0;
  int losses_ = 0;
  LossTracker tracker_;
};

}  // namespace plumetrace
