#include "plumetrace/plume.hpp"

#include <algorithm>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <cmath>

namespace plumetrace {

namespace {

void squared_distances(const Vec3& u, const double* __restrict x, const double* __restrict y,
                       const double* __restrict z, std::size_t m, double* __restrict d2) {
  for (std::size_t k = 0; k < m; ++k) {
    const double dx = u.x - x[k], dy = u.y - y[k], dz = u.z - z[k];
    d2[k] = dx * dx + dy * dy + dz * dz;
  }
}

// smallest and largest of x[0..m) (m >= 1); min and max are exact, so any order gives the same
void x_range(const double* x, std::size_t m, double& lo, double& hi) {
#ifdef __SSE2__
  __m128d vlo = _mm_set1_pd(x[0]), vhi = vlo;
  std::size_t k = 0;
  for (; k + 2 <= m; k += 2) {
    const __m128d v = _mm_loadu_pd(x + k);
    vlo = _mm_min_pd(vlo, v);
    vhi = _mm_max_pd(vhi, v);
  }
  double l[2], h[2];
  _mm_storeu_pd(l, vlo);
  _mm_storeu_pd(h, vhi);
  lo = std::min(l[0], l[1]);
  hi = std::max(h[0], h[1]);
  for (; k < m; ++k) {
    lo = std::min(lo, x[k]);
    hi = std::max(hi, x[k]);
  }
#else
  lo = hi = x[0];
  for (std::size_t k = 1; k < m; ++k) {
    lo = std::min(lo, x[k]);
    hi = std::max(hi, x[k]);
  }
#endif
}

}  // namespace

PlumeParams plume_preset(PlumePreset preset) {
  PlumeParams p;
  p.preset = preset;
  if (preset == PlumePreset::kPaperLiteral) {
    p.release_shape = ReleaseShape::kDisc;
    p.noise_mode = NoiseMode::kPerStep;
    p.lifetime = Lifetime::kLeaveArena;
    p.kernel = Kernel::kPrinted;
    p.cutoff = INFINITY;
  }
  return p;
}

double walk_stddev(const PlumeParams& params, double dt) {
  switch (params.noise_mode) {
    case NoiseMode::kVelocity:
      return params.sigma_p * dt;
    case NoiseMode::kPerStep:
      return params.sigma_p;
    case NoiseMode::kWiener:
      return params.sigma_p * std::sqrt(dt);
  }
  return 0.0;
}

double kernel_value(const PlumeParams& params, double w, double d2) {
  if (d2 >= params.cutoff * params.cutoff) return 0.0;
  const double w2 = w * w;
  if (params.kernel == Kernel::kGaussian) {
    // why: the plugin normalises the 3-D Gaussian and squares the distance (SPEC section 2)
    static const double kNorm = std::sqrt(8.0 * kPi * kPi * kPi);
    return params.amount / (kNorm * w2 * w) * std::exp(-d2 / w2);
  }
  return params.amount / (w2 * w) * std::exp(-std::sqrt(d2) / w2);
}

Plume::Plume(const PlumeParams& params, const SourceParams& source, double dt, double removal_x,
             std::uint64_t seed)
    : params_(params),
      source_(source),
      dt_(dt),
      removal_x_(removal_x),
      walk_std_(walk_stddev(params, dt)),
      rng_(seed) {
  // why: reserve once so the step never allocates (a leave-arena plume may still grow past this)
  const std::size_t reserve = static_cast<std::size_t>(params.capacity);
  x_.reserve(reserve);
  y_.reserve(reserve);
  z_.reserve(reserve);
  w_.reserve(reserve);
}

void Plume::step(const WindField& wind, double t) {
  move(wind, t);
  release();
  update_bounds();
}

void Plume::update_bounds() {
  const std::size_t n = x_.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  bounds_.resize(2 * blocks);  // allocates only when the plume grows past its capacity
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t start = b * kBlock, end = std::min(n, start + kBlock);
    x_range(x_.data() + start, end - start, bounds_[2 * b], bounds_[2 * b + 1]);
  }
}
void Plume::move(const WindField& wind, double t) {
  const std::size_t n = x_.size();
  const bool uniform = wind.uniform_in_space();
  const Vec3 a0 = wind.velocity(source_.center, t);
  for (std::size_t i = 0; i < n; ++i) {
    // advection plus random walk (paper eq. 2), then width growth (eq. 3)
    const Vec3 a = uniform ? a0 : wind.velocity({x_[i], y_[i], z_[i]}, t);
    x_[i] += a.x * dt_ + walk_std_ * rng_.normal();
    y_[i] += a.y * dt_ + walk_std_ * rng_.normal();
    z_[i] += a.z * dt_ + walk_std_ * rng_.normal();
    w_[i] += params_.gamma / (2.0 * w_[i]);
  }
  if (params_.lifetime == Lifetime::kLeaveArena) {
    // stable compaction keeps the order, so sums stay reproducible
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (x_[i] > removal_x_) continue;
      x_[kept] = x_[i];
      y_[kept] = y_[i];
      z_[kept] = z_[i];
      w_[kept] = w_[i];
      ++kept;
    }
    x_.resize(kept);
    y_.resize(kept);
    z_.resize(kept);
    w_.resize(kept);
  }
}

void Plume::release() {
  // why: deterministic release, the accumulated fraction is emitted whole (3 or 4 per step)
  release_debt_ += params_.release_rate * dt_;
  const auto count = static_cast<std::uint64_t>(std::floor(release_debt_ + 1e-9));
  release_debt_ -= static_cast<double>(count);
  for (std::uint64_t k = 0; k < count; ++k) {
    const Vec3 p = release_position();
    const auto capacity = static_cast<std::size_t>(params_.capacity);
    if (params_.lifetime == Lifetime::kRing && x_.size() == capacity) {
      store(oldest_, p, params_.initial_width);
      oldest_ = (oldest_ + 1) % capacity;
    } else {
      x_.push_back(p.x);
      y_.push_back(p.y);
      z_.push_back(p.z);
      w_.push_back(params_.initial_width);
    }
    ++released_;
  }
}

Vec3 Plume::release_position() {
  // uniform in the ball or disc by rejection from the enclosing cube or square
  const double r = source_.radius;
  for (;;) {
    const double dx = (2.0 * rng_.uniform() - 1.0) * r;
    const double dy = (2.0 * rng_.uniform() - 1.0) * r;
    const double dz =
        params_.release_shape == ReleaseShape::kBall ? (2.0 * rng_.uniform() - 1.0) * r : 0.0;
    if (dx * dx + dy * dy + dz * dz <= r * r) {
      return {source_.center.x + dx, source_.center.y + dy, source_.center.z + dz};
    }
  }
}

void Plume::store(std::size_t i, const Vec3& p, double w) {
  x_[i] = p.x;
  y_[i] = p.y;
  z_[i] = p.z;
  w_[i] = w;
}

double Plume::concentration(const Vec3& u) const { return sum_kernels(u, INFINITY); }

bool Plume::reaches(const Vec3& u, double threshold) const {
  return sum_kernels(u, threshold) >= threshold;
}

double Plume::sum_kernels(const Vec3& u, double stop_at) const {
  // why: squared distances of a block in a loop the compiler vectorises, then the kernels of
  // the filaments within the cut-off in index order: the same sum as adding every filament
  // (the others add exactly 0), and partial sums of non-negative terms never decrease, so
  // stopping at `stop_at` answers "does it reach" exactly
  double d2[kBlock];
  const double cut2 = params_.cutoff * params_.cutoff;
  const std::size_t n = x_.size();
  double c = 0.0;
  for (std::size_t start = 0; start < n; start += kBlock) {
    // why: rounding is monotonic, so no filament of a block is nearer than its box; a box at or
    // beyond the cut-off holds only filaments that add exactly 0
    const double* box = bounds_.data() + 2 * (start / kBlock);
    const double ex = std::max({box[0] - u.x, 0.0, u.x - box[1]});
    if (ex * ex >= cut2) continue;
    const std::size_t m = std::min(kBlock, n - start);
    squared_distances(u, x_.data() + start, y_.data() + start, z_.data() + start, m, d2);
    for (std::size_t k = 0; k < m; ++k) {
      if (d2[k] >= cut2) continue;
      c += kernel_value(params_, w_[start + k], d2[k]);
      if (c >= stop_at) return c;
    }
  }
  return c;
}

}  // namespace plumetrace
