#include "plumetrace/agent/controllers/random_walks.hpp"

#include <cmath>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

// the snapshot of a walk: its recent legs and the planned end of the current one
Snapshot walk_snapshot(const LegHistory& history, const Leg& leg, int legs) {
  Snapshot s;
  if (legs > 0) s.path = history.path(leg.end_point());
  return s;
}

}  // namespace

std::vector<Vec2> LegHistory::path(const Vec2& last) const {
  std::vector<Vec2> out;
  out.reserve(static_cast<std::size_t>(count_) + 1);
  for (int k = 0; k < count_; ++k) {
    out.push_back(points_[(next_ - count_ + k + kWalkHistory) % kWalkHistory]);
  }
  out.push_back(last);
  return out;
}

double levy_step(double mu, double l_min, double l_max, double u) {
  const double a = math::pow(l_min, 1.0 - mu);
  const double b = math::pow(l_max, 1.0 - mu);
  // F(l) = (a - l^(1-mu)) / (a - b) on [l_min, l_max]; solve F(l) = u
  const double l = math::pow(a - u * (a - b), 1.0 / (1.0 - mu));
  return std::fmin(std::fmax(l, l_min), l_max);
}

double levy_tail(double mu, double l_min, double l_max, double x) {
  if (x <= l_min) return 1.0;
  if (x >= l_max) return 0.0;
  const double a = math::pow(l_min, 1.0 - mu);
  const double b = math::pow(l_max, 1.0 - mu);
  return (math::pow(x, 1.0 - mu) - b) / (a - b);
}

double crw_mean_squared_displacement(int n, double mean_step, double mean_step2, double c) {
  const double pairs = c / (1.0 - c) * (n - (1.0 - math::pow(c, n)) / (1.0 - c));
  return n * mean_step2 + 2.0 * mean_step * mean_step * pairs;
}

Command Crw::step(const Observation& obs, WindProbe& wind) {
  if (legs_ == 0 || leg_.over(obs)) {
    // the direction the walk persists in: the last leg's heading (the release heading at
    // first), reversed after a blocked leg so that the walk turns away from what blocked it
    double previous = legs_ == 0 ? obs.odometry.heading : leg_.heading();
    if (legs_ > 0 && leg_.blocked()) previous = wrap_angle(previous + kPi);
    double mean = previous;
    if (params_.upwind_bias > 0.0) {
      // biased CRW: the mean heading weighs upwind against persistence (Codling et al. 2008)
      const double up = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
      const double w = params_.upwind_bias;
      mean = math::atan2(w * math::sin(up) + (1.0 - w) * math::sin(previous),
                         w * math::cos(up) + (1.0 - w) * math::cos(previous));
    }
    const double heading = wrap_angle(mean + wrapped_cauchy(params_.rho, rng_));
    const double length = params_.step_law == StepLaw::kFixed
                              ? params_.step
                              : -params_.step * math::log(rng_.uniform_open0());
    leg_.start(obs, heading, length);
    history_.add(leg_.start_point());
    ++legs_;
  }
  return leg_.command();
}

Snapshot Crw::snapshot() const { return walk_snapshot(history_, leg_, legs_); }

void Levy::check(const LevyParams& params) {
  if (params.l_max <= params.l_min) {
    throw ConfigError("levy.l_max: must be greater than levy.l_min (" + bound_text(params.l_min) +
                      " m), got " + bound_text(params.l_max));
  }
}

Command Levy::step(const Observation& obs, WindProbe& wind) {
  if (legs_ == 0 || leg_.over(obs)) {
    // isotropic headings, or Levy-taxis: wrapped Cauchy about upwind with mean cosine w
    double heading = 0.0;
    if (params_.upwind_bias > 0.0) {
      const double up = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
      heading = wrap_angle(up + wrapped_cauchy(params_.upwind_bias, rng_));
    } else {
      heading = wrap_angle(2.0 * kPi * rng_.uniform());
    }
    const double length = levy_step(params_.mu, params_.l_min, params_.l_max, rng_.uniform());
    leg_.start(obs, heading, length);
    history_.add(leg_.start_point());
    ++legs_;
  }
  return leg_.command();
}

Snapshot Levy::snapshot() const { return walk_snapshot(history_, leg_, legs_); }

}  // namespace plumetrace
