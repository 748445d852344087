#pragma once

#include <cstddef>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// When the switching wind's later switches come (switching.timing).
enum class SwitchTiming {
  kFixed,   ///< every switching.interval, each moved by up to switching.jitter of it
  kRandom,  ///< exponential gaps of mean switching.interval (a Poisson process)
};

/// How each new direction is drawn (switching.draw), as an angle from the initial direction.
enum class SwitchDraw {
  kSign,     ///< + or - switching.angle_deg, a fair coin each switch (switch-once)
  kNormal,   ///< normal of std angle_deg / 2, clipped to +-angle_deg (Singh et al.'s switch-many)
  kUniform,  ///< uniform in [-angle_deg, +angle_deg]
};

/// The switching wind's keys (wind.model = "switching"; docs/model.md section 3.2), in its own
/// table: `[switching] count = ...`. A spatially uniform wind of constant speed whose direction
/// jumps (or turns) at switch times, as in Singh et al. (2023). Defaults: the `switch-once`
/// scenario (scenarios/switch-once.toml).
struct SwitchingParams {
  /// Switches in a run; 0: the constant wind, bit for bit. why: 1, Singh et al.'s switch-once.
  int count = 1;
  /// Time of the first switch after the robot's release, sim.warmup (s); negative: before it
  /// (a switch before the plume starts takes effect at its first step). why: 45 s, when a
  /// robot going straight upwind at full speed would have come a third of its 14.5 m (docs/
  /// model.md section 3.2: Singh et al.'s switch comes 1 to 2 s into the episode).
  double first = 45.0;
  /// Time between switches, or its mean for random timing (s). why: Singh et al.'s switch-many,
  /// 3 s.
  double interval = 3.0;
  /// When the later switches come. why: Singh et al.'s switch-many, a fixed interval.
  SwitchTiming timing = SwitchTiming::kFixed;
  /// With fixed timing, switch k >= 1 comes at first + k interval + u interval, u uniform in
  /// [-jitter, jitter] (a fraction of the interval). why: Singh et al.'s +-10%.
  double jitter = 0.1;
  /// The angle of a switch from the initial direction (deg). why: Singh et al.'s switch-once,
  /// 45 degrees.
  double angle_deg = 45.0;
  /// How each new direction is drawn. why: switch-once turns by the whole angle, either way.
  SwitchDraw draw = SwitchDraw::kSign;
  /// Time over which the direction turns linearly from the old to the new one (s); 0: a jump.
  /// why: 0, Singh et al.'s jumps.
  double transition = 0.0;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("count", count, "switches of the wind's direction in a run; 0: the constant wind",
      IntegerSpec{0, 100000});
    v("first", first,
      "time of the first switch after the robot's release, sim.warmup (s); negative: before it",
      NumberSpec{.min = -1e6, .max = 1e6});
    v("interval", interval, "time between switches, or its mean for random timing (s)",
      NumberSpec{.min = 0.0, .max = 1e6, .min_open = true});
    v("timing", timing, "fixed: every interval (with jitter); random: exponential gaps",
      {"fixed", "random"});
    v("jitter", jitter, "fixed timing: each later switch moved by up to this fraction of interval",
      NumberSpec{.min = 0.0, .max = 0.5, .max_open = true});
    v("angle_deg", angle_deg, "angle of a switch from the initial direction (deg); 0: none",
      NumberSpec{.min = 0.0, .max = 180.0});
    v("draw", draw,
      "new direction: sign (+-angle), normal (std angle/2, clipped to +-angle) or uniform "
      "(within +-angle)",
      {"sign", "normal", "uniform"});
    v("transition", transition, "time over which the direction turns to the new one (s); 0: a jump",
      NumberSpec{.min = 0.0, .max = 1e6});
  }
};

/// One switch of the wind's direction: from when, and to which angle from the initial direction.
struct WindSwitch {
  double time;   ///< when it starts, on the field's clock (s since the plume started)
  double from;   ///< the angle it turns from: the direction just before it (rad)
  double angle;  ///< the angle it turns to (rad), counterclockwise from the initial direction
};

/// The switching wind (docs/model.md section 3.2): the mean wind (wind.vx, wind.vy, wind.vz)
/// turned about the vertical by an angle that changes at switch times, the same everywhere. Its
/// switches are drawn when it is built, from its own stream (Stream::kWind), so every reader of
/// one run's field (the plume, each robot's wind sensor) meets the same ones.
class SwitchingWind final : public WindField {
 public:
  /// Draws the switches over the field's life around the mean wind `context.mean` (m/s), the
  /// first one context.release + params.first after the field's start (s).
  SwitchingWind(const SwitchingParams& params, const WindContext& context, Rng rng);

  /// Advances the clock by dt (s) and sets the wind to the direction at the new time.
  void step(double dt) override;
  /// The wind now, the same at every point (m/s).
  Vec3 velocity(const Vec3&) const override { return velocity_; }
  bool uniform_in_space() const override { return true; }

  /// The field's clock (s since it started).
  double time() const { return time_; }
  /// The angle of the wind now from the initial direction (rad, counterclockwise): that of the
  /// last switch started, partway through its transition.
  double angle() const { return angle_; }
  /// Every switch of the field's life, in time order.
  const std::vector<WindSwitch>& switches() const { return switches_; }
  /// Switches started so far. A switch starts at the step boundary nearest its time: from there
  /// on the steps (each reading the wind at its end) move the plume in the new wind.
  std::size_t started() const { return next_; }

  /// True when there is no switch (count 0) or no angle: the mean wind, exactly
  /// (WindHooks::steady).
  static bool steady(const SwitchingParams& params) {
    return params.count == 0 || params.angle_deg == 0.0;
  }

 private:
  SwitchingParams params_;
  Vec3 mean_;
  std::vector<WindSwitch> switches_;
  std::size_t next_ = 0;  // the first switch not yet started
  double time_ = 0.0;
  double angle_ = 0.0;
  Vec3 velocity_;
};

}  // namespace plumetrace
