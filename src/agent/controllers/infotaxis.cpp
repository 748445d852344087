#include "plumetrace/agent/controllers/infotaxis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

// I0(x) for |x| <= 3.75: Abramowitz & Stegun 9.8.1 (error below 1.6e-7)
double bessel_i0_small(double x) {
  const double t = (x / 3.75) * (x / 3.75);
  return 1.0 + t * (3.5156229 +
                    t * (3.0899424 +
                         t * (1.2067492 + t * (0.2659732 + t * (0.0360768 + t * 0.0045813)))));
}

// sqrt(x) e^x K0(x) for x >= 2: Abramowitz & Stegun 9.8.6 (error below 1.9e-7)
double scaled_k0_large(double x) {
  const double y = 2.0 / x;
  return 1.25331414 +
         y * (-0.07832358 +
              y * (0.02189568 +
                   y * (-0.01062446 + y * (0.00587872 + y * (-0.00251540 + y * 0.00053208)))));
}

// K0(x) for 0 < x <= 2: Abramowitz & Stegun 9.8.5 (error below 1e-8)
double k0_small(double x) {
  const double y = x * x / 4.0;
  return -math::log(x / 2.0) * bessel_i0_small(x) +
         (-0.57721566 +
          y * (0.42278420 +
               y * (0.23069756 +
                    y * (0.03488590 + y * (0.00262698 + y * (0.00010750 + y * 0.0000074))))));
}

// -q0 ln q0 - q1 ln q1 for q0 = exp(-mu), the entropy (nats) of hit / no hit at mean mu
double hit_entropy(double mu, double q0, double q1) {
  return q1 > 0.0 ? q0 * mu - q1 * math::log(q1) : 0.0;
}

double xlogx(double x) { return x > 0.0 ? x * math::log(x) : 0.0; }

}  // namespace

double bessel_k0(double x) {
  if (x <= 2.0) return k0_small(x);
  return math::exp(-x) / std::sqrt(x) * scaled_k0_large(x);
}

double log_bessel_k0(double x) {
  if (x <= 2.0) return math::log(k0_small(x));
  return -x - 0.5 * math::log(x) + math::log(scaled_k0_large(x));
}

double infotaxis_lambda(double diffusivity, double lifetime, double wind_speed) {
  return std::sqrt(diffusivity * lifetime /
                   (1.0 + wind_speed * wind_speed * lifetime / (4.0 * diffusivity)));
}

double log_encounter_rate(const InfotaxisParams& p, double d, double s) {
  const double lambda = infotaxis_lambda(p.diffusivity, p.lifetime, p.wind_speed);
  // why: the formula holds for d >> a; the searcher's own cell, where d -> 0, is never used
  // (the update removes it), so any finite value there does
  const double r = std::max(d, p.detector_size);
  return math::log(p.emission_rate) - math::log(math::log(lambda / p.detector_size)) +
         p.wind_speed * s / (2.0 * p.diffusivity) + log_bessel_k0(r / lambda);
}

InfotaxisBelief::InfotaxisBelief(const InfotaxisParams& p, int nx, int ny, Vec2 downwind)
    : nx_(nx),
      ny_(ny),
      p_(static_cast<std::size_t>(nx) * ny, 1.0 / (static_cast<double>(nx) * ny)),
      rate_(static_cast<std::size_t>(2 * nx - 1) * (2 * ny - 1)),
      scratch_(p_.size()) {
  // the rate depends only on the displacement agent - source: one table, (2 nx - 1) (2 ny - 1)
  for (int dj = -(ny - 1); dj <= ny - 1; ++dj) {
    for (int di = -(nx - 1); di <= nx - 1; ++di) {
      const Vec2 r{di * p.cell, dj * p.cell};
      const double s = r.x * downwind.x + r.y * downwind.y;
      rate_[displacement(di, dj)] = math::exp(log_encounter_rate(p, math::hypot(r.x, r.y), s));
    }
  }
}

double InfotaxisBelief::entropy() const {
  double s = 0.0;
  for (const double q : p_) s -= xlogx(q);
  return s;
}

void InfotaxisBelief::update(int i, int j, bool hit, double duration) {
  // not found: the source is not where the searcher stands
  p_[static_cast<std::size_t>(j) * nx_ + i] = 0.0;
  double prior = 0.0, posterior = 0.0;
  // why: the terms made for choose_move serve when the interval was as long (the same values)
  const bool cached = terms_.size() == rate_.size() && terms_duration_ == duration;
  for (int l = 0; l < ny_; ++l) {
    for (int k = 0; k < nx_; ++k) {
      const std::size_t x = static_cast<std::size_t>(l) * nx_ + k;
      double like;
      if (cached) {
        const Terms& t = terms_[displacement(i - k, j - l)];
        like = hit ? t.q1 : t.q0;
      } else {
        const double mu = rate(i, j, k, l) * duration;
        like = hit ? -math::expm1(-mu) : math::exp(-mu);
      }
      scratch_[x] = p_[x] * like;
      prior += p_[x];
      posterior += scratch_[x];
    }
  }
  // why: an observation the model calls impossible (a hit where no source could be felt) would
  // empty the belief; it is ignored
  if (posterior > 0.0) {
    p_.swap(scratch_);
  } else {
    posterior = prior;
  }
  if (posterior > 0.0) {
    for (double& q : p_) q /= posterior;
  }
}

const std::vector<InfotaxisBelief::Terms>& InfotaxisBelief::terms(double duration) const {
  if (terms_.size() != rate_.size() || terms_duration_ != duration) {
    terms_.resize(rate_.size());
    for (std::size_t d = 0; d < rate_.size(); ++d) {
      const double mu = rate_[d] * duration;
      const double q0 = math::exp(-mu), q1 = -math::expm1(-mu);
      terms_[d] = {q0, q1, hit_entropy(mu, q0, q1)};
    }
    terms_duration_ = duration;
  }
  return terms_;
}

double InfotaxisBelief::expected_entropy(int i, int j, double duration) const {
  return expected_entropy(i, j, duration, entropy());
}

double InfotaxisBelief::expected_entropy(int i, int j, double duration, double entropy) const {
  if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return std::numeric_limits<double>::infinity();
  // E = (1 - P) (S(p') - I), p' the belief without cell (i, j), I the information of the
  // observation; expanded so that one pass over the cells serves:
  // E = S + P ln P + (1 - P) ln(1 - P) - (1 - P) H(rho) + sum_x p(x) h(x)
  const std::size_t here = static_cast<std::size_t>(j) * nx_ + i;
  const double found = p_[here];
  const std::vector<Terms>& terms = this->terms(duration);
  double rho0 = 0.0, rho1 = 0.0, sum_h = 0.0;
  for (int l = 0; l < ny_; ++l) {
    // the terms of (i - k, j - l) for k = 0, 1, ...: rate()'s index, falling with k
    const Terms* row = terms.data() + displacement(i, j - l);
    for (int k = 0; k < nx_; ++k) {
      const std::size_t x = static_cast<std::size_t>(l) * nx_ + k;
      const double q = p_[x];
      if (x == here || q == 0.0) continue;
      const Terms& t = *(row - k);
      rho0 += q * t.q0;
      rho1 += q * t.q1;
      sum_h += q * t.h;
    }
  }
  const double rest = rho0 + rho1;  // 1 - P, summed
  const double h_rho = rest > 0.0 ? -xlogx(rho0 / rest) - xlogx(rho1 / rest) : 0.0;
  return entropy + xlogx(found) + xlogx(rest) - rest * h_rho + sum_h;
}

int InfotaxisBelief::choose_move(int i, int j, double duration,
                                 const std::vector<char>& blocked) const {
  const double s = entropy();
  int best = -1;
  double best_entropy = std::numeric_limits<double>::infinity();
  for (int m = 0; m < static_cast<int>(kMoves.size()); ++m) {
    const int k = i + kMoves[m][0], l = j + kMoves[m][1];
    if (k < 0 || l < 0 || k >= nx_ || l >= ny_) continue;
    const std::size_t x = static_cast<std::size_t>(l) * nx_ + k;
    if (!blocked.empty() && blocked[x] != 0) continue;
    if (p_[x] > 1.0 - 1e-10) return m;
    const double e = expected_entropy(k, l, duration, s);
    // why: ties (within rounding) go to the first move in kMoves, as in OTTO
    if (best < 0 || e < best_entropy - 1e-12) {
      best = m;
      best_entropy = e;
    }
  }
  return best;
}

std::array<int, 2> InfotaxisBelief::mode() const {
  const auto it = std::max_element(p_.begin(), p_.end());
  const int x = static_cast<int>(it - p_.begin());
  return {x % nx_, x / nx_};
}

double InfotaxisBelief::mass_within(int i, int j, double radius) const {
  double mass = 0.0;
  const double r2 = radius * radius * (1.0 + 1e-12);
  for (int l = 0; l < ny_; ++l) {
    for (int k = 0; k < nx_; ++k) {
      const double d2 = static_cast<double>((k - i) * (k - i) + (l - j) * (l - j));
      if (d2 <= r2) mass += p_[static_cast<std::size_t>(l) * nx_ + k];
    }
  }
  return mass;
}

void Infotaxis::check(const InfotaxisParams& p) {
  const double lambda = infotaxis_lambda(p.diffusivity, p.lifetime, p.wind_speed);
  if (!(p.detector_size < lambda)) {
    throw ConfigError("infotaxis.detector_size: must be below the correlation length lambda = " +
                      bound_text(lambda) +
                      " m of infotaxis.diffusivity, infotaxis.lifetime and infotaxis.wind_speed "
                      "(the encounter rate divides by ln(lambda / a))");
  }
  const double cells = (static_cast<double>(p.cells_upwind) + p.cells_downwind + 1.0) *
                       (2.0 * p.cells_crosswind + 1.0);
  if (!(cells <= kMaxInfotaxisCells)) {
    throw ConfigError(
        "infotaxis.cells_upwind, infotaxis.cells_downwind, infotaxis.cells_crosswind: the grid "
        "would have " +
        bound_text(cells) + " cells, more than " + bound_text(kMaxInfotaxisCells));
  }
}

void Infotaxis::start(const Observation& obs, WindProbe& wind) {
  // the mean of wind_samples samples gives the upwind direction
  Vec2 sum{0.0, 0.0};
  for (int n = 0; n < params_.wind_samples; ++n) {
    const Vec2 w = wind.measure_wind_body();
    sum.x += w.x;
    sum.y += w.y;
  }
  const double upwind = upwind_heading(sum, obs.odometry.heading);
  // the grid's upwind axis: the odometry axis nearest the measured upwind (0 +x, 1 +y, 2 -x,
  // 3 -y), so the grid stays aligned with the odometry frame the snapshot draws in
  const int axis = static_cast<int>(((std::lround(upwind / (kPi / 2.0)) % 4) + 4) % 4);
  const int up = params_.cells_upwind, down = params_.cells_downwind;
  const int across = params_.cells_crosswind;
  const int along = up + down + 1, wide = 2 * across + 1;
  const bool on_x = axis % 2 == 0;
  const int nx = on_x ? along : wide, ny = on_x ? wide : along;
  const int behind = axis < 2 ? down : up;  // cells before the start on the upwind axis
  i0_ = on_x ? behind : across;
  j0_ = on_x ? across : behind;
  // the model's wind: the measured direction itself, not the grid's axis
  belief_ = InfotaxisBelief(params_, nx, ny, {-math::cos(upwind), -math::sin(upwind)});
  blocked_.assign(static_cast<std::size_t>(nx) * ny, 0);
  ci_ = i0_;
  cj_ = j0_;
  window_start_ = 0.0;  // the first interval runs from release
  started_ = true;
}

Vec2 Infotaxis::centre(int i, int j) const {
  return {(i - i0_) * params_.cell, (j - j0_) * params_.cell};
}

Command Infotaxis::decide(const Observation& obs) {
  belief_.update(ci_, cj_, window_hit_, obs.time - window_start_);
  window_start_ = obs.time;
  window_hit_ = false;
  ++decisions_;
  const auto [mi, mj] = belief_.mode();
  if (belief_.mass_within(mi, mj, params_.declare_radius / params_.cell) >=
      params_.declare_probability) {
    declared_ = true;
    return Command::declare_source(centre(mi, mj));
  }
  const int m = belief_.choose_move(ci_, cj_, params_.cell / params_.speed, blocked_);
  if (m < 0) return Command::abandon();  // every neighbour is off the grid or blocked
  ti_ = ci_ + InfotaxisBelief::kMoves[m][0];
  tj_ = cj_ + InfotaxisBelief::kMoves[m][1];
  moving_ = true;
  move_start_ = obs.time;
  return Command::stop();  // replaced by the caller's go toward the target
}

Command Infotaxis::step(const Observation& obs, WindProbe& wind) {
  if (!started_) start(obs, wind);
  window_hit_ = window_hit_ || (params_.hits == InfotaxisHits::kBinary
                                    ? obs.odor
                                    : obs.concentration >= params_.hit_threshold);
  const Vec2 pos{obs.odometry.x, obs.odometry.y};
  if (moving_) {
    const Vec2 target = centre(ti_, tj_);
    const double travelled = obs.odometer - last_odometer_;
    const double dist = math::hypot(target.x - pos.x, target.y - pos.y);
    // arrived: the next step would overshoot the centre by more than it now falls short
    const bool arrived = dist <= 0.5 * travelled || dist < 1e-9;
    // blocked: told to drive on the heading it already had, it did not move (a wall, a
    // teammate); or a move lasting far beyond its predicted time
    const bool stalled = commanded_go_ && travelled <= 0.0 &&
                         std::fabs(wrap_angle(last_heading_ - commanded_)) < 1e-9;
    const bool overdue = obs.time - move_start_ > 4.0 * params_.cell / params_.speed + 5.0;
    if (arrived) {
      ci_ = ti_;
      cj_ = tj_;
      moving_ = false;
    } else if (stalled || overdue) {
      blocked_[static_cast<std::size_t>(tj_) * belief_.nx() + ti_] = 1;
      moving_ = false;
    }
  }
  if (!moving_) {
    const Command c = decide(obs);
    if (!moving_) return c;  // declared or abandoned
  }
  const Vec2 target = centre(ti_, tj_);
  commanded_ = math::atan2(target.y - pos.y, target.x - pos.x);
  commanded_go_ = true;
  last_heading_ = obs.odometry.heading;
  last_odometer_ = obs.odometer;
  return Command::go(commanded_);
}

std::string_view Infotaxis::state() const {
  if (declared_) return "declared";
  return moving_ ? "move" : "decide";
}

Snapshot Infotaxis::snapshot() const {
  Snapshot s;
  if (!started_) return s;
  s.grid = belief_.probability();
  s.nx = belief_.nx();
  s.ny = belief_.ny();
  s.x0 = -i0_ * params_.cell;
  s.y0 = -j0_ * params_.cell;
  s.dx = params_.cell;
  s.dy = params_.cell;
  const auto [mi, mj] = belief_.mode();
  s.has_estimate = true;
  s.estimate = centre(mi, mj);
  return s;
}

}  // namespace plumetrace
