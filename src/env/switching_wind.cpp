#include "plumetrace/env/switching_wind.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

// the mean wind turned by `angle` (rad) about the vertical
Vec3 turned(const Vec3& mean, double angle) {
  const double c = math::cos(angle), s = math::sin(angle);
  return {mean.x * c - mean.y * s, mean.x * s + mean.y * c, mean.z};
}

// the angle a switch turns to, from the initial direction (rad)
double draw_angle(SwitchDraw draw, double angle, Rng& rng) {
  switch (draw) {
    case SwitchDraw::kSign:
      return rng.uniform() < 0.5 ? -angle : angle;
    case SwitchDraw::kNormal:
      // why: Singh et al.'s switch-many draws N(0, (60 deg / 2)^2), clipped to +-60 deg
      // (docs/model.md section 3.2)
      return std::clamp(0.5 * angle * rng.normal(), -angle, angle);
    case SwitchDraw::kUniform:
      return (2.0 * rng.uniform() - 1.0) * angle;
  }
  return 0.0;
}

// the angle of switch `s` (rad) `elapsed` s after it started, turning over `transition` s;
// exactly its angle once turned
double angle_after(const WindSwitch& s, double elapsed, double transition) {
  const double done = transition > 0.0 ? std::clamp(elapsed / transition, 0.0, 1.0) : 1.0;
  return done >= 1.0 ? s.angle : s.from + (s.angle - s.from) * done;
}

}  // namespace

SwitchingWind::SwitchingWind(const SwitchingParams& params, const WindContext& context, Rng rng)
    : params_(params), mean_(context.mean), velocity_(context.mean) {
  if (steady(params)) return;  // the mean wind, exactly; nothing drawn
  const double angle = params.angle_deg * kRadiansPerDegree;
  const double start = context.release + params.first;
  switches_.reserve(static_cast<std::size_t>(params.count));
  double time = start;
  for (int k = 0; k < params.count; ++k) {
    // when: the first exactly; later ones on a grid with jitter, or after exponential gaps
    if (k > 0 && params.timing == SwitchTiming::kFixed) {
      time = start + k * params.interval +
             (2.0 * rng.uniform() - 1.0) * params.jitter * params.interval;
    } else if (k > 0) {
      time += -math::log(rng.uniform_open0()) * params.interval;
    }
    // from where: the direction just before it, partway through the last turn
    const double from =
        k > 0 ? angle_after(switches_.back(), time - switches_.back().time, params.transition)
              : 0.0;
    switches_.push_back({time, from, draw_angle(params.draw, angle, rng)});
  }
}

void SwitchingWind::step(double dt) {
  time_ += dt;
  // a switch starts at the step boundary nearest its time: this step, ending at time_, moves the
  // plume in the new wind when the switch came before its middle
  while (next_ < switches_.size() && switches_[next_].time < time_ - 0.5 * dt) ++next_;
  if (next_ == 0) return;  // none yet: the mean wind, exactly
  const WindSwitch& s = switches_[next_ - 1];
  angle_ = angle_after(s, time_ - s.time, params_.transition);
  velocity_ = turned(mean_, angle_);
}

}  // namespace plumetrace
