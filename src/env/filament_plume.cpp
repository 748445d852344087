#include "plumetrace/env/filament_plume.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "../core/simd_targets.hpp"
#include "plume_loops.hpp"
#include "plumetrace/core/math.hpp"
#include "plumetrace/core/simd.hpp"
#include "vector_math.hpp"

namespace plumetrace {

namespace {

// the kernel's amount over w^3, without the exponential
double kernel_scale(const PlumeParams& params) {
  // why: the plugin normalises the 3-D Gaussian and squares the distance
  // (docs/model.md section 4.6)
  static const double kNorm = std::sqrt(8.0 * kPi * kPi * kPi);
  return params.kernel == Kernel::kGaussian ? params.amount / kNorm : params.amount;
}

// one filament's concentration at squared distance d2, given h = 1 / w; 0 at or beyond the
// cut-off (no division, so that the query vectorises cheaply)
template <Kernel kKernel>
double kernel_at(double scale, double cut2, double h, double d2) {
  const double h2 = h * h;
  const double arg = kKernel == Kernel::kGaussian ? d2 * h2 : std::sqrt(d2) * h2;
  const double v = scale * (h2 * h) * vmath::exp_neg(-arg);
  return d2 < cut2 ? v : 0.0;
}

// The most one filament with 1 / w in [h_lo, h_hi] can add at squared horizontal distance
// e2 or more from the query: scale h^3 exp(-e2 h^2) (Gaussian) or scale h^3 exp(-sqrt(e2) h^2)
// (printed) at the h that maximises it in the range (h^2 = 3 / (2 e2), or 3 / (2 e)).
template <Kernel kKernel>
double kernel_bound(double scale, double e2, double h_lo, double h_hi) {
  const double e = kKernel == Kernel::kGaussian ? e2 : std::sqrt(e2);
  const double h = e > 0.0 ? std::clamp(std::sqrt(1.5 / e), h_lo, h_hi) : h_hi;
  return scale * h * h * h * vmath::exp_neg(-e * h * h);
}

// what each of `count` blocks can add at most, given its squared horizontal distance e2 from
// the query, its filaments' least and greatest 1 / w and their number m
template <Kernel kKernel>
[[gnu::always_inline]] inline void most_loop(const double* __restrict e2,
                                             const double* __restrict h_lo,
                                             const double* __restrict h_hi,
                                             const double* __restrict m, std::int64_t count,
                                             double scale, double* __restrict most) {
  for (std::int64_t c = 0; c < count; ++c) {
    most[c] = m[c] * kernel_bound<kKernel>(scale, e2[c], h_lo[c], h_hi[c]);
  }
}

// the concentrations of m filaments at u, one per filament
template <Kernel kKernel>
[[gnu::always_inline]] inline void kernel_loop(const Vec3& u, const double* __restrict x,
                                               const double* __restrict y,
                                               const double* __restrict z,
                                               const double* __restrict h, std::int64_t m,
                                               double scale, double cut2, double* __restrict out) {
  const double ux = u.x, uy = u.y, uz = u.z;
  for (std::int64_t k = 0; k < m; ++k) {
    const double dx = ux - x[k], dy = uy - y[k], dz = uz - z[k];
    out[k] = kernel_at<kKernel>(scale, cut2, h[k], dx * dx + dy * dy + dz * dz);
  }
}

// why: the vector lambdas below are inlined and never cross a call boundary, so GCC's note that
// passing 64-byte vectors changes the ABI between targets does not apply
#pragma GCC diagnostic ignored "-Wpsabi"

// GCC's vector type of kBytes bytes of doubles
template <std::size_t kBytes>
struct DoubleVector;
template <>
struct DoubleVector<16> {
  using type = double __attribute__((vector_size(16)));
};
template <>
struct DoubleVector<32> {
  using type = double __attribute__((vector_size(32)));
};
template <>
struct DoubleVector<64> {
  using type = double __attribute__((vector_size(64)));
};

// The bounds of each block of `block` filaments: the x and y range as (x min, x max, y min,
// y max) in `boxes`, the range of h as (min, max) in `h_range`. min and max are exact, so any
// grouping gives the same.
template <simd::Path kPath>
[[gnu::always_inline]] inline void block_ranges_body(const double* x, const double* y,
                                                     const double* h, std::size_t n,
                                                     std::size_t block, double* boxes,
                                                     double* h_range) {
  // why: GCC's vector types, as wide as the path's registers (2, 4 or 8 doubles); vectors wider
  // than the registers are lowered to a compare and a store per lane (with 8 doubles on AVX2
  // this loop cost as much as the whole walk). The scalar path has none (kWidth 1: the loop at
  // the end does it all).
  constexpr std::size_t kBytes = kPath == simd::Path::kAvx512 ? 64
                                 : kPath == simd::Path::kAvx2 ? 32
                                                              : 16;
  using V = typename DoubleVector<kBytes>::type;
  constexpr std::size_t kWidth = kPath == simd::Path::kScalar ? 1 : kBytes / sizeof(double);
  const auto load = [](V& v, const double* p) { std::memcpy(&v, p, sizeof(V)); };
  // the extreme of the lanes and `r`
  const auto fold = [](const V& v, double r, auto smaller) {
    for (std::size_t l = 0; l < kWidth; ++l) r = smaller(v[l], r) ? v[l] : r;
    return r;
  };
  const auto below = [](double a, double b) { return a < b; };
  const auto above = [](double a, double b) { return a > b; };
  for (std::size_t start = 0, b = 0; start < n; start += block, ++b) {
    const std::size_t end = std::min(n, start + block);
    double* box = boxes + 4 * b;
    double* range = h_range + 2 * b;
    std::size_t k = start;
    box[0] = box[1] = x[start];
    box[2] = box[3] = y[start];
    range[0] = range[1] = h[start];
    if constexpr (kWidth > 1) {
      if (end - start >= kWidth) {
        V xlo, ylo, hlo;
        load(xlo, x + k);
        load(ylo, y + k);
        load(hlo, h + k);
        V xhi = xlo, yhi = ylo, hhi = hlo;
        for (k += kWidth; k + kWidth <= end; k += kWidth) {
          V vx, vy, vh;
          load(vx, x + k);
          load(vy, y + k);
          load(vh, h + k);
          xlo = vx < xlo ? vx : xlo;
          xhi = vx > xhi ? vx : xhi;
          ylo = vy < ylo ? vy : ylo;
          yhi = vy > yhi ? vy : yhi;
          hlo = vh < hlo ? vh : hlo;
          hhi = vh > hhi ? vh : hhi;
        }
        box[0] = fold(xlo, box[0], below);
        box[1] = fold(xhi, box[1], above);
        box[2] = fold(ylo, box[2], below);
        box[3] = fold(yhi, box[3], above);
        range[0] = fold(hlo, range[0], below);
        range[1] = fold(hhi, range[1], above);
      }
    }
    for (; k < end; ++k) {
      box[0] = std::min(box[0], x[k]);
      box[1] = std::max(box[1], x[k]);
      box[2] = std::min(box[2], y[k]);
      box[3] = std::max(box[3], y[k]);
      range[0] = std::min(range[0], h[k]);
      range[1] = std::max(range[1], h[k]);
    }
  }
}

PLUMETRACE_SIMD_VERSIONS(block_ranges,
                         (const double* x, const double* y, const double* h, std::size_t n,
                          std::size_t block, double* boxes, double* h_range),
                         (x, y, h, n, block, boxes, h_range))

}  // namespace

namespace loops {

namespace {

// the drift, walk and growth of x, y and w; inlined into each version of drift_walk_grow
template <bool kArea>
[[gnu::always_inline]] inline void walk_grow(double* __restrict x, double* __restrict y,
                                             double* __restrict w, double* __restrict h,
                                             std::int64_t n, double dx, double dy,
                                             std::uint64_t key, double stddev, double gamma) {
  const double half_gamma = 0.5 * gamma;
  // why: counter 2i's hash input key + 2i kGamma kept by one addition a filament (wrapping as
  // the product does, so the same values), not a 64-bit multiply: AVX2 and SSE2 have no vector
  // one and build each from three 32-bit multiplies
  std::uint64_t input = key;
  for (std::int64_t i = 0; i < n; ++i) {
    float a, b;
    vmath::normal_pair(vmath::mix64(input), a, b);
    input += 2 * vmath::kGamma;
    x[i] += dx + stddev * static_cast<double>(a);
    y[i] += dy + stddev * static_cast<double>(b);
    if constexpr (kArea) {
      w[i] = std::sqrt(w[i] * w[i] + gamma);
    } else {
      w[i] += half_gamma * h[i];
    }
    h[i] = 1.0 / w[i];
  }
}

template <simd::Path kPath>
[[gnu::always_inline]] inline void drift_walk_grow_body(double* __restrict x, double* __restrict y,
                                                        double* __restrict z, double* __restrict w,
                                                        double* __restrict h, std::int64_t n,
                                                        const Vec3& d, std::uint64_t key,
                                                        double stddev, double gamma, bool area) {
  const double dz = d.z;
  if (area) {
    walk_grow<true>(x, y, w, h, n, d.x, d.y, key, stddev, gamma);
  } else {
    walk_grow<false>(x, y, w, h, n, d.x, d.y, key, stddev, gamma);
  }
  const std::int64_t half = n / 2;
  double* __restrict z2 = z + half;
  std::uint64_t input = key + vmath::kGamma;  // counter 2j + 1's, as above
  for (std::int64_t j = 0; j < half; ++j) {
    float a, b;
    vmath::normal_pair(vmath::mix64(input), a, b);
    input += 2 * vmath::kGamma;
    z[j] += dz + stddev * static_cast<double>(a);
    z2[j] += dz + stddev * static_cast<double>(b);
  }
  if (n % 2 == 1) {
    float a, b;
    vmath::normal_pair(vmath::counter_bits(key, static_cast<std::uint64_t>(n)), a, b);
    z[n - 1] += dz + stddev * static_cast<double>(a);
  }
}

template <simd::Path kPath>
[[gnu::always_inline]] inline void kernels_body(const Vec3& u, const double* __restrict x,
                                                const double* __restrict y,
                                                const double* __restrict z,
                                                const double* __restrict h, std::int64_t m,
                                                double scale, Kernel kernel, double cut2,
                                                double* __restrict out) {
  if (kernel == Kernel::kGaussian) {
    kernel_loop<Kernel::kGaussian>(u, x, y, z, h, m, scale, cut2, out);
  } else {
    kernel_loop<Kernel::kPrinted>(u, x, y, z, h, m, scale, cut2, out);
  }
}

template <simd::Path kPath>
[[gnu::always_inline]] inline void block_most_body(const double* __restrict e2,
                                                   const double* __restrict h_lo,
                                                   const double* __restrict h_hi,
                                                   const double* __restrict m, std::int64_t count,
                                                   double scale, Kernel kernel,
                                                   double* __restrict most) {
  if (kernel == Kernel::kGaussian) {
    most_loop<Kernel::kGaussian>(e2, h_lo, h_hi, m, count, scale, most);
  } else {
    most_loop<Kernel::kPrinted>(e2, h_lo, h_hi, m, count, scale, most);
  }
}

}  // namespace

PLUMETRACE_SIMD_VERSIONS(drift_walk_grow,
                         (double* __restrict x, double* __restrict y, double* __restrict z,
                          double* __restrict w, double* __restrict h, std::int64_t n, const Vec3& d,
                          std::uint64_t key, double stddev, double gamma, bool area),
                         (x, y, z, w, h, n, d, key, stddev, gamma, area))

PLUMETRACE_SIMD_VERSIONS(kernels,
                         (const Vec3& u, const double* __restrict x, const double* __restrict y,
                          const double* __restrict z, const double* __restrict h, std::int64_t m,
                          double scale, Kernel kernel, double cut2, double* __restrict out),
                         (u, x, y, z, h, m, scale, kernel, cut2, out))

PLUMETRACE_SIMD_VERSIONS(block_most,
                         (const double* __restrict e2, const double* __restrict h_lo,
                          const double* __restrict h_hi, const double* __restrict m,
                          std::int64_t count, double scale, Kernel kernel, double* __restrict most),
                         (e2, h_lo, h_hi, m, count, scale, kernel, most))

}  // namespace loops

PlumeParams plume_preset(PlumePreset preset) {
  PlumeParams p;
  p.preset = preset;
  if (preset == PlumePreset::kPaperLiteral) {
    // the plume as printed (paper sections 3.3-3.4; the lifetime is ours); the defaults are
    // the default reading's
    p.amount = 8.3e9;
    p.sigma_p = 0.1;
    p.release_shape = ReleaseShape::kDisc;
    p.noise_mode = NoiseMode::kPerStep;
    p.lifetime = Lifetime::kLeaveArena;
    p.kernel = Kernel::kPrinted;
    p.cutoff = INFINITY;
  }
  return p;
}

double walk_stddev(const PlumeParams& params, double dt) {
  // why: a white-noise velocity of diffusivity D moves a point by a normal of variance 2 D dt
  // per axis in dt (Farrell et al. 2002; docs/model.md section 4.3)
  if (params.dispersion == Dispersion::kFarrell)
    return std::sqrt(2.0 * params.relative_diffusivity * dt);
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

double width_growth(const PlumeParams& params, double dt) {
  return params.dispersion == Dispersion::kFarrell ? params.spread_rate * dt : params.gamma;
}

double kernel_value(const PlumeParams& params, double w, double d2) {
  const double scale = kernel_scale(params), cut2 = params.cutoff * params.cutoff;
  const double h = 1.0 / w;
  return params.kernel == Kernel::kGaussian ? kernel_at<Kernel::kGaussian>(scale, cut2, h, d2)
                                            : kernel_at<Kernel::kPrinted>(scale, cut2, h, d2);
}

double kernel_reach(const PlumeParams& params, double w, double floor) {
  // the peak over the floor, whose log the kernel's exponent must not exceed
  const double ratio = math::log(kernel_scale(params) / (w * w * w * floor));
  if (!(ratio >= 0.0)) return 0.0;
  const double d = params.kernel == Kernel::kGaussian ? w * std::sqrt(ratio) : w * w * ratio;
  return std::min(d, params.cutoff);
}

FilamentPlume::FilamentPlume(const PlumeParams& params, const SourceParams& source,
                             double removal_x, std::uint64_t seed)
    : params_(params), source_(source), removal_x_(removal_x), rng_(seed) {
  // why: reserve once so the step never allocates (a leave-arena plume may still grow past this)
  const std::size_t reserve = static_cast<std::size_t>(params.capacity);
  x_.reserve(reserve);
  y_.reserve(reserve);
  z_.reserve(reserve);
  w_.reserve(reserve);
  h_.reserve(reserve);
}

void FilamentPlume::step(const WindField& wind, double dt) {
  move(wind, dt);
  release(dt);
  update_bounds();
}

OdorSnapshot FilamentPlume::snapshot() const {
  OdorSnapshot s;
  s.kind = OdorSnapshotKind::kFilaments;
  s.filaments = {x_, y_, z_, w_};
  return s;
}

void FilamentPlume::update_bounds() {
  const std::size_t n = x_.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  bounds_.resize(4 * blocks);  // allocates only past the capacity
  h_range_.resize(2 * blocks);
  block_ranges(simd::active(), x_.data(), y_.data(), h_.data(), n, kBlock, bounds_.data(),
               h_range_.data());
}

void FilamentPlume::move(const WindField& wind, double dt) {
  const std::size_t n = x_.size();
  // advection by the wind (paper eq. 2, first term): one displacement for a uniform wind,
  // else each filament moved here by the wind at its position
  Vec3 drift{0.0, 0.0, 0.0};
  if (wind.uniform_in_space()) {
    const Vec3 a = wind.velocity(source_.center);
    drift = {a.x * dt, a.y * dt, a.z * dt};
  } else {
    wind.advect(x_, y_, z_, dt);
  }
  // random walk (second term) and width growth (eq. 3); the walk's normals come from a
  // counter-based stream so that the loop vectorises, keyed by a draw of the plume's generator
  const std::uint64_t key = rng_.next_u64();
  loops::drift_walk_grow(simd::active(), x_.data(), y_.data(), z_.data(), w_.data(), h_.data(),
                         static_cast<std::int64_t>(n), drift, key, walk_stddev(params_, dt),
                         width_growth(params_, dt), params_.dispersion == Dispersion::kFarrell);
  if (params_.lifetime == Lifetime::kLeaveArena) {
    // stable compaction keeps the order, so sums stay reproducible
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (x_[i] > removal_x_) continue;
      x_[kept] = x_[i];
      y_[kept] = y_[i];
      z_[kept] = z_[i];
      w_[kept] = w_[i];
      h_[kept] = h_[i];
      ++kept;
    }
    x_.resize(kept);
    y_.resize(kept);
    z_.resize(kept);
    w_.resize(kept);
    h_.resize(kept);
  }
}

void FilamentPlume::release(double dt) {
  // why: deterministic release, the accumulated fraction is emitted whole (3 or 4 per step)
  release_debt_ += params_.release_rate * dt;
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
      h_.push_back(1.0 / params_.initial_width);
    }
    ++released_;
  }
}

Vec3 FilamentPlume::release_position() {
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

void FilamentPlume::store(std::size_t i, const Vec3& p, double w) {
  x_[i] = p.x;
  y_[i] = p.y;
  z_[i] = p.z;
  w_[i] = w;
  h_[i] = 1.0 / w;
}

double FilamentPlume::concentration(const Vec3& u) const { return sum_kernels(u, INFINITY); }

bool FilamentPlume::reaches(const Vec3& u, double threshold) const {
  return sum_kernels(u, threshold) >= threshold;
}

namespace {

// A vector of trivial values that keeps its first N on the stack.
template <class T, std::size_t N>
class SmallVector {
 public:
  void push_back(T v) {
    if (size_ < N) {
      fixed_[size_] = v;
    } else {
      if (size_ == N) spill_.assign(fixed_.begin(), fixed_.end());
      spill_.push_back(v);
    }
    ++size_;
  }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return size_ <= N ? fixed_[i] : spill_[i]; }
  T* data() { return size_ <= N ? fixed_.data() : spill_.data(); }

 private:
  std::array<T, N> fixed_;
  std::vector<T> spill_;
  std::size_t size_ = 0;
};

// the filaments as sum_as_defined reads them
struct Filaments {
  const double *x, *y, *z, *h;
  std::size_t n;
  const double* bounds;  // each block's (x min, x max, y min, y max)
  double scale, cut2;
  Kernel kernel;
  loops::KernelsLoop kernels;
};

constexpr std::size_t kLanes = 8;

// The sum as defined (FilamentPlume::sum_kernels): the terms of the blocks of `block` filaments
// within the cut-off, in index order, filament i into partial sum i mod kLanes, the partial sums
// added pairwise; it stops once that total reaches stop_at.
// why: a function of its own, kept out of sum_kernels: there, beside the threshold test's state,
// GCC kept this loop's counters on the stack (3% of a concentration query)
[[gnu::noinline]] double sum_as_defined(const Filaments& f, std::size_t block, const Vec3& u,
                                        double stop_at) {
  double v[FilamentPlume::kBlock];
  double acc[kLanes] = {};
  const auto total = [&acc] {
    return ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
  };
  const std::size_t blocks = (f.n + block - 1) / block;
  for (std::size_t b = 0; b < blocks; ++b) {
    // why: rounding is monotonic, so no filament of a block is nearer than its box in (x, y);
    // a box at or beyond the cut-off holds only filaments that add exactly 0
    const double* box = f.bounds + 4 * b;
    const double ex = std::max({box[0] - u.x, 0.0, u.x - box[1]});
    const double ey = std::max({box[2] - u.y, 0.0, u.y - box[3]});
    if (ex * ex + ey * ey >= f.cut2) continue;
    const std::size_t start = b * block;
    const std::size_t m = std::min(block, f.n - start);
    f.kernels(u, f.x + start, f.y + start, f.z + start, f.h + start, static_cast<std::int64_t>(m),
              f.scale, f.kernel, f.cut2, v);
    std::size_t k = 0;
    for (; k + kLanes <= m; k += kLanes) {
      for (std::size_t l = 0; l < kLanes; ++l) acc[l] += v[k + l];
    }
    for (; k < m; ++k) acc[k % kLanes] += v[k];
    if (total() >= stop_at) break;
  }
  return total();
}

}  // namespace

double FilamentPlume::sum_kernels(const Vec3& u, double stop_at) const {
  // why: the sum is defined as kLanes partial sums, filament i going to sum i mod kLanes in
  // index order, added pairwise at the end; so its terms are computed in vector loops and the
  // result is the same bits at every vector width. Queries away from the plume's core end at
  // once; the answer is the same.
  //
  // A test against a threshold needs only the answer, and settles it with a margin of a
  // relative 1e-9 + 4 n eps, beyond the rounding of any sum of the n terms in any order (at
  // most (n - 1) eps of it, the terms being non-negative) and of the exponential in the bounds
  // (1e-14). It sums the nearby blocks in the order of what each can add at most, largest
  // first, each block's terms in any order: once that partial sum reaches the threshold by the
  // margin, the sum as defined reaches it too (its terms are the same non-negative values; any
  // order of summing rounds within n eps); once the partial sum plus the bound on the blocks
  // left stays below it by the margin, the sum as defined does too. Only a sum within the
  // margin of the threshold is summed as defined to decide (docs/model.md section 4.6).
  static_assert(kBlock % kLanes == 0);
  double v[kBlock];
  const double cut2 = params_.cutoff * params_.cutoff;
  const double scale = kernel_scale(params_);
  const std::size_t n = x_.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const double margin = 1.0 + 1e-9 + 4.0 * static_cast<double>(n) * 0x1p-52;
  const simd::Path path = simd::active();
  const loops::KernelsLoop kernels = loops::kernels_for(path);
  const Filaments filaments{x_.data(),      y_.data(), z_.data(), h_.data(),      n,
                            bounds_.data(), scale,     cut2,      params_.kernel, kernels};
  if (!std::isfinite(stop_at)) return sum_as_defined(filaments, kBlock, u, stop_at);
  const auto block_terms = [&](std::size_t b) {
    const std::size_t start = b * kBlock;
    const std::size_t m = std::min(kBlock, n - start);
    kernels(u, x_.data() + start, y_.data() + start, z_.data() + start, h_.data() + start,
            static_cast<std::int64_t>(m), scale, params_.kernel, cut2, v);
    return m;
  };
  // the blocks within the cut-off, in index order, and what each can add at most
  // why: on the stack for the usual few candidates (a query meets the blocks within the
  // cut-off, about 3 of the default 25), on the heap past that
  constexpr std::size_t kOnStack = 32;
  SmallVector<std::size_t, kOnStack> near;
  SmallVector<double, kOnStack> most;
  double bound = 0.0;
  SmallVector<double, kOnStack> e2, h_lo, h_hi, count;
  for (std::size_t b = 0; b < blocks; ++b) {
    // why: rounding is monotonic, so no filament of a block is nearer than its box in (x, y);
    // a box at or beyond the cut-off holds only filaments that add exactly 0
    const double* box = bounds_.data() + 4 * b;
    const double ex = std::max({box[0] - u.x, 0.0, u.x - box[1]});
    const double ey = std::max({box[2] - u.y, 0.0, u.y - box[3]});
    const double d2 = ex * ex + ey * ey;
    if (d2 >= cut2) continue;
    near.push_back(b);
    e2.push_back(d2);
    h_lo.push_back(h_range_[2 * b]);
    h_hi.push_back(h_range_[2 * b + 1]);
    count.push_back(static_cast<double>(std::min(kBlock, n - b * kBlock)));
    most.push_back(0.0);
  }
  // what each can add at most, in a vector loop
  loops::block_most_for(path)(e2.data(), h_lo.data(), h_hi.data(), count.data(),
                              static_cast<std::int64_t>(near.size()), scale, params_.kernel,
                              most.data());
  for (std::size_t c = 0; c < near.size(); ++c) bound += most[c];
  if (bound * margin < stop_at) return bound;
  // the candidates by what each can add, largest first (insertion sort: a few), and what
  // those after each can add, summed from the last
  SmallVector<std::size_t, kOnStack> order;
  SmallVector<double, kOnStack + 1> after;
  for (std::size_t c = 0; c < near.size(); ++c) {
    order.push_back(c);
    after.push_back(0.0);
    for (std::size_t j = c; j > 0 && most[order[j - 1]] < most[order[j]]; --j) {
      std::swap(order[j - 1], order[j]);
    }
  }
  after.push_back(0.0);
  for (std::size_t j = near.size(); j-- > 0;) after[j] = after[j + 1] + most[order[j]];
  double partial = 0.0;
  for (std::size_t j = 0; j < near.size(); ++j) {
    const std::size_t m = block_terms(near[order[j]]);
    // why: in lanes, so that the adds do not wait on each other (any order will do here)
    double lanes[kLanes] = {};
    std::size_t k = 0;
    for (; k + kLanes <= m; k += kLanes) {
      for (std::size_t l = 0; l < kLanes; ++l) lanes[l] += v[k + l];
    }
    for (; k < m; ++k) lanes[k % kLanes] += v[k];
    for (const double lane : lanes) partial += lane;
    if (partial >= stop_at * margin) return partial;
    if ((partial + after[j + 1]) * margin < stop_at) return partial + after[j + 1];
  }
  // within the margin: the sum as defined decides
  return sum_as_defined(filaments, kBlock, u, stop_at);
}

}  // namespace plumetrace
