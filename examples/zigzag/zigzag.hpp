// A controller registered from outside the library: zigzags upwind. Its params struct declares
// its own config keys; zigzag.cpp registers it in one line.
#pragma once

#include "plumetrace/agent/controller.hpp"

namespace zigzag {

/// Parameters of the zigzag: config keys in the table "zigzag" (zigzag.leg, zigzag.angle_deg).
struct ZigzagParams {
  /// Path length of each leg (m).
  double leg = 1.0;
  /// Angle of the legs to the measured upwind direction (rad).
  double angle = plumetrace::deg_to_rad(45.0);

  /// The config keys (plumetrace/core/config.hpp).
  template <class V>
  void fields(V& v) {
    const double deg = plumetrace::kPi / 180.0;
    v("leg", leg, "path length of each leg of the zigzag (m)",
      plumetrace::NumberSpec{.min = 0.0, .max = 10.0, .min_open = true});
    v("angle_deg", angle, "leg angle to the measured upwind direction (deg)",
      plumetrace::NumberSpec{
          .min = 0.0, .max = 90.0 * deg, .min_open = true, .max_open = true, .scale = deg});
  }
};

/// Zigzags upwind: legs of `leg` metres at +-angle to the upwind direction, measured anew at
/// each turn. It never gives up: the run ends at the source, at a wall or at the timeout.
class Zigzag final : public plumetrace::Controller {
 public:
  /// Creates the controller; `rng` chooses the side of the first leg.
  Zigzag(const ZigzagParams& params, plumetrace::Rng rng) : params_(params), rng_(rng) {}
  plumetrace::Command step(const plumetrace::Observation& obs,
                           plumetrace::WindProbe& wind) override;
  std::string_view state() const override { return side_ > 0 ? "left" : "right"; }
  int losses() const override { return 0; }

 private:
  ZigzagParams params_;
  plumetrace::Rng rng_;
  bool started_ = false;
  int side_ = 1;
  double heading_ = 0.0;
  double leg_start_ = 0.0;  // odometer at the start of the leg (m)
};

}  // namespace zigzag
