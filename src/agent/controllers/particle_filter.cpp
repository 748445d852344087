#include "plumetrace/agent/controllers/particle_filter.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/math.hpp"

namespace plumetrace {

void make_puffs(std::span<const Vec2> wind, double dt, double diffusivity, double mu,
                double sensor_area, std::span<Puff> puffs) {
  const std::size_t n = wind.size();
  // the history's spread per axis, floored by the diffusivity
  Vec2 mean;
  for (const Vec2& w : wind) {
    mean.x += w.x / static_cast<double>(n);
    mean.y += w.y / static_cast<double>(n);
  }
  Vec2 var;
  for (const Vec2& w : wind) {
    var.x += (w.x - mean.x) * (w.x - mean.x) / static_cast<double>(n);
    var.y += (w.y - mean.y) * (w.y - mean.y) / static_cast<double>(n);
  }
  const double rate_x = std::max(var.x, 2.0 * diffusivity);
  const double rate_y = std::max(var.y, 2.0 * diffusivity);
  // newest first: puff i left at the midpoint of interval i and rode every later interval
  Vec2 later;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = n - 1 - k;
    const double age = (static_cast<double>(k) + 0.5) * dt;
    const double vx = rate_x * age;
    const double vy = rate_y * age;
    Puff& p = puffs[i];
    p.offset = {later.x + 0.5 * wind[i].x * dt, later.y + 0.5 * wind[i].y * dt};
    p.inv_2vx = 1.0 / (2.0 * vx);
    p.inv_2vy = 1.0 / (2.0 * vy);
    p.density0 = mu * sensor_area / (2.0 * kPi * std::sqrt(vx * vy));
    later.x += wind[i].x * dt;
    later.y += wind[i].y * dt;
  }
}

double no_hit_probability(const Vec2& source, const Vec2& robot, std::span<const Puff> puffs) {
  const double rx = robot.x - source.x;
  const double ry = robot.y - source.y;
  double total = 1.0;
  for (const Puff& p : puffs) {
    const double dx = rx - p.offset.x;
    const double dy = ry - p.offset.y;
    const double arg = -dx * dx * p.inv_2vx - dy * dy * p.inv_2vy;
    // why: e^-38 < 2^-54, so with density0 <= 1 the factor 1 - detect rounds to 1 exactly; most
    // puffs are that far from the robot, and skipping their exp gives the same bits
    if (arg < -38.0 && p.density0 <= 1.0) continue;
    const double detect = p.density0 * math::exp(arg);
    // why: check() keeps density0 <= 1; min() guards a probability all the same
    total *= 1.0 - std::min(1.0, detect);
  }
  return total;
}

double effective_count(std::span<const double> weights) {
  double sum_sq = 0.0;
  for (const double w : weights) sum_sq += w * w;
  return 1.0 / sum_sq;
}

void systematic_resample(std::span<const double> weights, double u, std::span<int> indices) {
  const std::size_t n = indices.size();
  const int last = static_cast<int>(weights.size()) - 1;
  double cumulative = weights.empty() ? 0.0 : weights[0];
  int j = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double target = (u + static_cast<double>(k)) / static_cast<double>(n);
    // why: rounding may leave the total a little under 1; the last particle takes the rest
    while (target >= cumulative && j < last) cumulative += weights[static_cast<std::size_t>(++j)];
    indices[k] = j;
  }
}

Agreement agreement(std::span<const Vec2> points, double radius) {
  Agreement a;
  if (points.empty()) return a;
  const double n = static_cast<double>(points.size());
  for (const Vec2& p : points) {
    a.mean.x += p.x / n;
    a.mean.y += p.y / n;
  }
  a.agree = std::all_of(points.begin(), points.end(), [&](const Vec2& p) {
    return math::hypot(p.x - a.mean.x, p.y - a.mean.y) <= radius;
  });
  return a;
}

ParticleFilter::ParticleFilter(const ParticleFilterParams& params, Rng rng)
    : params_(params),
      // why: the motion breaks its ties with a stream of its own, drawn from the controller's
      motion_(params.motion, Rng(rng.next_u64())),
      rng_(rng) {
  const auto n = static_cast<std::size_t>(params.particles);
  const auto h = static_cast<std::size_t>(params.wind_history);
  particles_.resize(n);
  weights_.assign(n, 1.0 / static_cast<double>(n));
  scratch_.resize(n);
  indices_.resize(n);
  wind_.resize(h);
  wind_ordered_.resize(h);
  puffs_.resize(h);
  estimates_.resize(static_cast<std::size_t>(params.estimates));
}

void ParticleFilter::check(const ParticleFilterParams& p) {
  // the youngest puff is the narrowest: its centre must not detect with probability above 1
  const double youngest = 0.5 * p.update_interval;
  const double peak = p.mu * p.sensor_area / (2.0 * kPi * 2.0 * p.diffusivity * youngest);
  if (peak > 1.0) {
    throw ConfigError(
        "particle_filter.sensor_area: mu * sensor_area / (2 pi * diffusivity * update_interval)"
        " must be at most 1, a probability of detection at the youngest puff's centre (got " +
        std::to_string(peak) + "); lower sensor_area or mu, or raise diffusivity");
  }
  const std::int64_t terms =
      static_cast<std::int64_t>(p.particles) * static_cast<std::int64_t>(p.wind_history);
  if (terms > kMaxParticleTerms) {
    throw ConfigError(
        "particle_filter.particles: particles x particle_filter.wind_history must "
        "be at most " +
        std::to_string(kMaxParticleTerms) + " (got " + std::to_string(terms) + ")");
  }
}

void ParticleFilter::push_wind(const Vec2& wind) {
  if (!wind_filled_) {
    std::fill(wind_.begin(), wind_.end(), wind);
    wind_filled_ = true;
    return;
  }
  wind_[wind_head_] = wind;
  wind_head_ = (wind_head_ + 1) % wind_.size();
}

void ParticleFilter::draw_from_back_trajectory(const Vec2& robot, std::span<Vec2> out) {
  // p_0 = robot, p_k = p_(k-1) - w_(n-k) dt: where a puff now at the robot was k intervals ago
  // from puffs_, which update() has made of the current history
  const std::size_t h = puffs_.size();
  for (Vec2& p : out) {
    const auto k =
        std::min(h, static_cast<std::size_t>(rng_.uniform() * static_cast<double>(h + 1)));
    Vec2 centre = robot;
    // why: 0.1 m at the robot, MAPIR's spread of p_0; the puff model's spread further back
    double sx = 0.1, sy = 0.1;
    if (k > 0) {
      const Puff& puff = puffs_[h - k];
      centre = {robot.x - puff.offset.x, robot.y - puff.offset.y};
      sx = std::sqrt(0.5 / puff.inv_2vx);
      sy = std::sqrt(0.5 / puff.inv_2vy);
    }
    p.x = centre.x + sx * rng_.normal();
    p.y = centre.y + sy * rng_.normal();
  }
}

void ParticleFilter::resample(const Vec2& robot) {
  ++resamplings_;
  const std::size_t n = particles_.size();
  const auto fresh =
      std::min(n, static_cast<std::size_t>(std::llround(params_.refill * static_cast<double>(n))));
  const std::size_t kept = n - fresh;
  const std::span<int> picks(indices_.data(), kept);
  systematic_resample(weights_, rng_.uniform(), picks);
  for (std::size_t k = 0; k < kept; ++k) {
    const Vec2& p = particles_[static_cast<std::size_t>(picks[k])];
    scratch_[k] = {p.x + params_.jitter * rng_.normal(), p.y + params_.jitter * rng_.normal()};
  }
  draw_from_back_trajectory(robot, std::span<Vec2>(scratch_).subspan(kept));
  particles_.swap(scratch_);
  std::fill(weights_.begin(), weights_.end(), 1.0 / static_cast<double>(n));
}

Agreement ParticleFilter::update(const Vec2& robot, bool hit) {
  // the history oldest first
  const std::size_t h = wind_.size();
  for (std::size_t k = 0; k < h; ++k) wind_ordered_[k] = wind_[(wind_head_ + k) % h];
  if (!started_ && !hit) return {};
  make_puffs(wind_ordered_, params_.update_interval, params_.diffusivity, params_.mu,
             params_.sensor_area, puffs_);
  if (!started_) {
    // why: MAPIR draws its particles at the first hit; before it there is nothing to weigh
    started_ = true;
    draw_from_back_trajectory(robot, particles_);
  }
  // weigh each particle by the probability of this interval's hit or miss
  double sum = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const double miss = no_hit_probability(particles_[i], robot, puffs_);
    weights_[i] *= hit ? 1.0 - miss : miss;
    sum += weights_[i];
  }
  const double n = static_cast<double>(particles_.size());
  const bool degenerate = !(sum > 0.0) || !std::isfinite(sum);
  for (double& w : weights_) w = degenerate ? 1.0 / n : w / sum;
  // why: a degenerate sum is MAPIR's NaN case, no particle explains the data: resample anew
  if (degenerate || effective_count(weights_) < params_.resample_below * n) resample(robot);
  // count the estimate once the cloud is tight; declare when the counted ones agree
  if (spread() > params_.r_conv) return {};
  estimates_[estimates_head_] = estimate();
  estimates_head_ = (estimates_head_ + 1) % estimates_.size();
  estimates_count_ = std::min(estimates_count_ + 1, estimates_.size());
  if (estimates_count_ < estimates_.size()) return {};
  return agreement(estimates_, params_.estimate_radius);
}

Command ParticleFilter::step(const Observation& obs, WindProbe& wind) {
  // the air's motion in the odometry frame, averaged over the interval
  const Vec2 w = rotate(wind.measure_wind_body(), obs.odometry.heading);
  wind_sum_.x += w.x;
  wind_sum_.y += w.y;
  ++wind_samples_;
  hit_ = hit_ || obs.odor;
  // why: a small tolerance so that an interval of k steps is not taken for k - 1 by rounding
  if (obs.time - interval_start_ >= params_.update_interval - 1e-9) {
    const double n = static_cast<double>(wind_samples_);
    push_wind({wind_sum_.x / n, wind_sum_.y / n});
    const Agreement found = update({obs.odometry.x, obs.odometry.y}, hit_);
    interval_start_ = obs.time;
    wind_sum_ = {};
    wind_samples_ = 0;
    hit_ = false;
    if (found.agree) return Command::declare_source(found.mean);
  }
  return motion_.step(obs, wind);
}

Vec2 ParticleFilter::estimate() const {
  Vec2 m;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    m.x += weights_[i] * particles_[i].x;
    m.y += weights_[i] * particles_[i].y;
  }
  return m;
}

double ParticleFilter::spread() const {
  const Vec2 m = estimate();
  double sum = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const double dx = particles_[i].x - m.x, dy = particles_[i].y - m.y;
    sum += weights_[i] * (dx * dx + dy * dy);
  }
  return std::sqrt(sum);
}

void ParticleFilter::set_particles(std::span<const Vec2> points, std::span<const double> weights) {
  std::copy(points.begin(), points.end(), particles_.begin());
  std::copy(weights.begin(), weights.end(), weights_.begin());
  started_ = true;
}

Snapshot ParticleFilter::snapshot() const {
  Snapshot s;
  if (!started_) return s;
  s.points = particles_;
  s.weights = weights_;
  // the counted estimates, oldest first
  for (std::size_t k = 0; k < estimates_count_; ++k) {
    const std::size_t first = estimates_count_ < estimates_.size() ? 0 : estimates_head_;
    s.path.push_back(estimates_[(first + k) % estimates_.size()]);
  }
  s.has_estimate = true;
  s.estimate = estimate();
  return s;
}

}  // namespace plumetrace
