#pragma once

// The plume's and the wind's vectorised loops against the scalar formulas, bit for bit: shared
// by plume_test and wind_test (gtest) and by tests/bits/model_bits (run on every machine the
// suite builds for, 64-bit ARM under qemu included), so each vector instruction set is checked
// by the same comparisons.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "env/plume_loops.hpp"
#include "env/vector_math.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace::testing {

/// The scalar formulas of the plume's loops, one filament at a time and never vectorised.
[[gnu::optimize("no-tree-vectorize")]] inline void scalar_step(
    std::vector<double>& x, std::vector<double>& y, std::vector<double>& z, std::vector<double>& w,
    const Vec3& d, std::uint64_t key, double stddev, double gamma, bool area = false) {
  const auto n = static_cast<std::int64_t>(x.size());
  const auto normals = [key](std::int64_t counter) {
    float a, b;
    vmath::normal_pair(vmath::counter_bits(key, static_cast<std::uint64_t>(counter)), a, b);
    return std::pair<double, double>(a, b);
  };
  for (std::int64_t i = 0; i < n; ++i) {
    const auto [a, b] = normals(2 * i);
    x[i] += d.x + stddev * a;
    y[i] += d.y + stddev * b;
    w[i] = area ? std::sqrt(w[i] * w[i] + gamma) : w[i] + (gamma / 2.0) * (1.0 / w[i]);
  }
  for (std::int64_t j = 0; j < n / 2; ++j) {
    const auto [a, b] = normals(2 * j + 1);
    z[j] += d.z + stddev * a;
    z[j + n / 2] += d.z + stddev * b;
  }
  if (n % 2 == 1) z[n - 1] += d.z + stddev * normals(n).first;
}

/// The scalar formula of what a block of filaments can add at most (FilamentPlume::sum_kernels).
inline double block_bound(const PlumeParams& params, double scale, double e2, double m, double h_lo,
                          double h_hi) {
  const double e = params.kernel == Kernel::kGaussian ? e2 : std::sqrt(e2);
  const double h = e > 0.0 ? std::clamp(std::sqrt(1.5 / e), h_lo, h_hi) : h_hi;
  return m * (scale * h * h * h * vmath::exp_neg(-e * h * h));
}

/// "" when every path this machine runs (simd::available(): scalar, the baseline, AVX2,
/// AVX-512) gives the scalar formulas' bits in the plume's loops (loops::drift_walk_grow, both
/// width growths; loops::kernels and loops::block_most, both kernels), at lengths that leave
/// every remainder of every vector width; else the first difference. `tested` gets the names of
/// the paths compared.
inline std::string plume_loops_mismatch(std::string* tested = nullptr) {
  const auto differs = [](double a, double b) {
    return std::bit_cast<std::uint64_t>(a) != std::bit_cast<std::uint64_t>(b);
  };
  for (const simd::Path path : simd::available()) {
    if (tested != nullptr) *tested += ' ' + std::string(simd::name(path));
    const auto on = [path](std::int64_t n) {
      return "path " + std::string(simd::name(path)) + " n " + std::to_string(n);
    };
    Rng rng(8);
    for (const std::int64_t n : {1, 2, 7, 13, 64, 1001, 1600}) {
      std::vector<double> x(n), y(n), z(n), w(n), h(n);
      for (std::int64_t i = 0; i < n; ++i) {
        x[i] = 16.0 * rng.uniform();
        y[i] = rng.uniform() - 0.5;
        z[i] = 0.1 * rng.uniform();
        w[i] = 0.1 + 0.05 * rng.uniform();
        h[i] = 1.0 / w[i];
      }
      // one step of each width growth (the paper's, then Farrell's)
      for (const bool area : {false, true}) {
        auto sx = x, sy = y, sz = z, sw = w;
        const Vec3 d{0.032, -0.001, 0.0005};
        loops::drift_walk_grow(path, x.data(), y.data(), z.data(), w.data(), h.data(), n, d,
                               0xabcdef + n, 0.0032, 4e-7, area);
        scalar_step(sx, sy, sz, sw, d, 0xabcdef + n, 0.0032, 4e-7, area);
        for (std::int64_t i = 0; i < n; ++i) {
          if (differs(x[i], sx[i]) || differs(y[i], sy[i]) || differs(z[i], sz[i]) ||
              differs(w[i], sw[i]) || differs(h[i], 1.0 / sw[i])) {
            return "drift_walk_grow: " + on(n) + " filament " + std::to_string(i) + " area " +
                   std::to_string(area);
          }
        }
      }
      // kernels at a point, per filament, for both kernels; what blocks at various distances
      // can add at most
      for (const PlumePreset preset : {PlumePreset::kLochmatter2008, PlumePreset::kPaperLiteral}) {
        const PlumeParams params = plume_preset(preset);
        const Vec3 u{8.0, 0.1, 0.0};
        std::vector<double> out(n);
        const double scale = kernel_value(params, 1.0, 0.0);  // amount factor: w = 1 at d = 0
        loops::kernels(path, u, x.data(), y.data(), z.data(), h.data(), n, scale, params.kernel,
                       params.cutoff * params.cutoff, out.data());
        for (std::int64_t i = 0; i < n; ++i) {
          const double d2 = distance_squared(u, {x[i], y[i], z[i]});
          if (differs(out[i], kernel_value(params, w[i], d2))) {
            return "kernels: " + on(n) + " filament " + std::to_string(i);
          }
        }
        std::vector<double> e2(n), lo(n), hi(n), m(n), most(n);
        for (std::int64_t c = 0; c < n; ++c) {
          e2[c] = c % 5 == 0 ? 0.0 : x[c] * x[c] * 0.01;
          lo[c] = std::min(h[c], 1.0 / (w[c] + 0.02));
          hi[c] = h[c];
          m[c] = static_cast<double>(1 + c % 64);
        }
        loops::block_most(path, e2.data(), lo.data(), hi.data(), m.data(), n, scale, params.kernel,
                          most.data());
        for (std::int64_t c = 0; c < n; ++c) {
          if (differs(most[c], block_bound(params, scale, e2[c], m[c], lo[c], hi[c]))) {
            return "block_most: " + on(n) + " block " + std::to_string(c);
          }
        }
      }
    }
  }
  return "";
}

/// "" when MeanderWind::advect moves every point by velocity() * dt to the bit (points in one
/// cell, across an edge, in several cells, on nodes and edges, outside the arena, a NaN; blocks
/// of every alignment), after `steps` steps of the default scenario's meandering wind, else the
/// first difference.
inline std::string wind_advect_mismatch(int steps = 200) {
  const auto differs = [](double a, double b) {
    return std::bit_cast<std::uint64_t>(a) != std::bit_cast<std::uint64_t>(b);
  };
  constexpr double kDt = 0.032;
  Scenario s;
  s.wind.model = WindModel::kMeander;
  validate(s);
  MeanderWind wind(s.wind.get<MeanderParams>(), s.wind.velocity, wind_region(s.arena), Rng(11));
  for (int k = 0; k < steps; ++k) wind.step(kDt);
  Rng rng(2);
  std::vector<double> x, y, z;
  for (int k = 0; k < 3001; ++k) {
    double px, py;
    switch (k % 7) {
      case 0:
      case 1:
      case 2:  // a plume-like run along x near the centreline
        px = 1.0 + 15.0 * static_cast<double>(k) / 3001.0 + 0.1 * rng.uniform();
        py = -0.2 + 0.4 * rng.uniform();
        break;
      case 3:  // anywhere, and beyond
        px = -2.0 + 20.0 * rng.uniform();
        py = -3.0 + 6.0 * rng.uniform();
        break;
      case 4:  // on nodes and the arena's edges
        px = std::round(16.0 * rng.uniform());
        py = rng.uniform() < 0.5 ? s.arena.y_min : s.arena.y_max;
        break;
      case 5:
        px = 16.0;
        py = -2.0 + 4.0 / 3.0 * std::round(3.0 * rng.uniform());
        break;
      default:
        px = k % 2 ? std::numeric_limits<double>::quiet_NaN() : 1e300;
        py = k % 3 ? -1e300 : 0.5;
    }
    x.push_back(px);
    y.push_back(py);
    z.push_back(rng.uniform());
  }
  for (std::size_t offset : {0u, 1u, 3u, 5u}) {
    std::vector<double> ax(x.begin() + offset, x.end()), ay(y.begin() + offset, y.end()),
        az(z.begin() + offset, z.end());
    wind.advect(ax, ay, az, kDt);
    for (std::size_t i = 0; i < ax.size(); ++i) {
      const Vec3 a = wind.velocity({x[i + offset], y[i + offset], z[i + offset]});
      if (differs(ax[i], x[i + offset] + a.x * kDt) || differs(ay[i], y[i + offset] + a.y * kDt) ||
          differs(az[i], z[i + offset] + a.z * kDt)) {
        return "advect: offset " + std::to_string(offset) + " point " + std::to_string(i);
      }
    }
  }
  return "";
}

}  // namespace plumetrace::testing
