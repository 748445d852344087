#pragma once

// The plume's and the wind's vectorised loops against the scalar formulas, bit for bit: shared
// by plume_test and wind_test (gtest) and by tests/bits/model_bits (run on every machine the
// suite builds for, 64-bit ARM under qemu included), so each vector instruction set is checked
// by the same comparisons.

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

/// "" when the plume's loops (loops::drift_walk_grow, both width growths; loops::kernels, both
/// kernels) give the scalar formulas' bits for filament counts of every remainder, else the
/// first difference.
inline std::string plume_loops_mismatch() {
  const auto differs = [](double a, double b) {
    return std::bit_cast<std::uint64_t>(a) != std::bit_cast<std::uint64_t>(b);
  };
  Rng rng(8);
  for (const std::int64_t n : {1, 2, 7, 64, 1001, 1600}) {
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
      loops::drift_walk_grow(x.data(), y.data(), z.data(), w.data(), h.data(), n, d, 0xabcdef + n,
                             0.0032, 4e-7, area);
      scalar_step(sx, sy, sz, sw, d, 0xabcdef + n, 0.0032, 4e-7, area);
      for (std::int64_t i = 0; i < n; ++i) {
        if (differs(x[i], sx[i]) || differs(y[i], sy[i]) || differs(z[i], sz[i]) ||
            differs(w[i], sw[i]) || differs(h[i], 1.0 / sw[i])) {
          return "drift_walk_grow: n " + std::to_string(n) + " filament " + std::to_string(i) +
                 " area " + std::to_string(area);
        }
      }
    }
    // kernels at a point, per filament, for both kernels
    for (const PlumePreset preset : {PlumePreset::kLochmatter2008, PlumePreset::kPaperLiteral}) {
      const PlumeParams params = plume_preset(preset);
      const Vec3 u{8.0, 0.1, 0.0};
      std::vector<double> out(n);
      const double scale = kernel_value(params, 1.0, 0.0);  // amount factor: w = 1 at d = 0
      loops::kernels(u, x.data(), y.data(), z.data(), h.data(), n, scale, params.kernel,
                     params.cutoff * params.cutoff, out.data());
      for (std::int64_t i = 0; i < n; ++i) {
        const double d2 = distance_squared(u, {x[i], y[i], z[i]});
        if (differs(out[i], kernel_value(params, w[i], d2))) {
          return "kernels: n " + std::to_string(n) + " filament " + std::to_string(i);
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
