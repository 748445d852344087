#include "plumetrace/env/meander_wind.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/math.hpp"
#include "wind_loops.hpp"

namespace plumetrace {

namespace {

// e^(mu s) C(s) and e^(mu s) S(s), where exp(A s) = e^(mu s) (C(s) I + S(s) (A - mu I)) for the
// filter's matrix A = [[0, 1], [-omega^2, -2 zeta omega]]: mu = -zeta omega, and with
// q = omega^2 (zeta^2 - 1), C = cosh(sqrt(q) s), S = sinh(sqrt(q) s) / sqrt(q) (cos and sin when
// q < 0, 1 and s when q = 0). Written so that no factor overflows: when q > 0, mu + sqrt(q) < 0.
struct Response {
  double c;  // e^(mu s) C(s)
  double s;  // e^(mu s) S(s)
};

Response response(double mu, double q, double s) {
  if (q < 0.0) {
    const double w = std::sqrt(-q), e = math::exp(mu * s);
    return {e * math::cos(w * s), e * math::sin(w * s) / w};
  }
  if (q == 0.0) {
    const double e = math::exp(mu * s);
    return {e, e * s};
  }
  const double w = std::sqrt(q);
  const double a = math::exp((mu + w) * s), b = math::exp((mu - w) * s);
  // why: the difference of the two exponentials cancels for small w s, sinh does not
  const double sinh_part =
      w * s < 1.0 ? math::exp(mu * s) * math::sinh(w * s) / w : 0.5 * (a - b) / w;
  return {0.5 * (a + b), sinh_part};
}

// the grid's cells as the interpolation reads them
wind_loops::CellView cells_of(const WindRegion& r, double inv_dx, double inv_dy, int nx, int ny,
                              const std::vector<double>& coef) {
  return {r.x_min,
          r.y_min,
          inv_dx,
          inv_dy,
          static_cast<double>(nx - 1),
          static_cast<double>(ny - 1),
          nx - 1,
          nx - 2,
          ny - 2,
          coef.data()};
}

double mu_of(const ColouredNoiseParams& p) { return -p.damping * p.bandwidth; }
double q_of(const ColouredNoiseParams& p) {
  return p.bandwidth * p.bandwidth * (p.damping * p.damping - 1.0);
}

// 8-point Gauss-Legendre nodes and weights on [-1, 1] (positive half; symmetric)
constexpr double kGaussNodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                   0.9602898564975363};
constexpr double kGaussWeights[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                     0.1012285362903763};

}  // namespace

double coloured_noise_variance(const ColouredNoiseParams& p) {
  return p.gain * p.gain * p.bandwidth / (4.0 * p.damping);
}

double coloured_noise_rate_variance(const ColouredNoiseParams& p) {
  return p.gain * p.gain * p.bandwidth * p.bandwidth * p.bandwidth / (4.0 * p.damping);
}

double coloured_noise_correlation(const ColouredNoiseParams& p, double lag) {
  // R(lag) = phi(lag) P e1 . e1 = phi_11(lag) P_11, as the stationary P is diagonal
  const double mu = mu_of(p);
  const Response r = response(mu, q_of(p), std::abs(lag));
  return r.c - mu * r.s;
}

double coloured_noise_time_scale(const ColouredNoiseParams& p) {
  // the integral of phi_11 over [0, inf) is -(A^-1)_11 = 2 zeta omega / omega^2
  return 2.0 * p.damping / p.bandwidth;
}

ColouredNoiseTransition coloured_noise_transition(const ColouredNoiseParams& p, double dt) {
  const double mu = mu_of(p), q = q_of(p), omega2 = p.bandwidth * p.bandwidth;
  ColouredNoiseTransition t{};
  const Response end = response(mu, q, dt);
  t.phi[0][0] = end.c - mu * end.s;
  t.phi[0][1] = end.s;
  t.phi[1][0] = -omega2 * end.s;
  t.phi[1][1] = end.c + mu * end.s;
  // the covariance added in dt: Q = sigma^2 int_0^dt f f^T ds, f(s) = exp(A s) (0, 1) =
  // (e^(mu s) S, e^(mu s) (C + mu S)), sigma = G omega^2. Q_12 = sigma^2 f_1(dt)^2 / 2 exactly;
  // Q_11 and Q_22 by 8-point Gauss-Legendre on panels no longer than a quarter of the fastest
  // time scale (1 / (omega max(1, 2 zeta))), where the integrands are polynomial to rounding.
  // why: not P - phi P phi^T, which cancels to a few digits when dt is short
  const double sigma2 = p.gain * p.gain * omega2 * omega2;
  const double rate = p.bandwidth * std::max(1.0, 2.0 * p.damping);
  const double panels = std::clamp(std::ceil(dt * rate / 0.25), 1.0, 1e6);
  const double width = dt / panels;
  double q11 = 0.0, q22 = 0.0;
  for (double k = 0.0; k < panels; k += 1.0) {
    const double mid = (k + 0.5) * width;
    for (int n = 0; n < 4; ++n) {
      for (const double side : {-1.0, 1.0}) {
        const Response r = response(mu, q, mid + side * 0.5 * width * kGaussNodes[n]);
        const double f1 = r.s, f2 = r.c + mu * r.s;
        q11 += kGaussWeights[n] * f1 * f1;
        q22 += kGaussWeights[n] * f2 * f2;
      }
    }
  }
  q11 *= sigma2 * 0.5 * width;
  q22 *= sigma2 * 0.5 * width;
  const double q12 = sigma2 * end.s * end.s * 0.5;
  t.l11 = std::sqrt(q11);
  t.l21 = t.l11 > 0.0 ? q12 / t.l11 : 0.0;
  t.l22 = std::sqrt(std::max(0.0, q22 - t.l21 * t.l21));
  return t;
}

ColouredNoiseState stationary_coloured_noise(const ColouredNoiseParams& params, Rng& rng) {
  // the stationary covariance is diagonal: value and rate are independent at one instant
  ColouredNoiseState s;
  s.value = std::sqrt(coloured_noise_variance(params)) * rng.normal();
  s.rate = std::sqrt(coloured_noise_rate_variance(params)) * rng.normal();
  return s;
}

void step(const ColouredNoiseTransition& t, ColouredNoiseState& s, Rng& rng) {
  const double n1 = rng.normal(), n2 = rng.normal();
  const double value = t.phi[0][0] * s.value + t.phi[0][1] * s.rate + t.l11 * n1;
  const double rate = t.phi[1][0] * s.value + t.phi[1][1] * s.rate + (t.l21 * n1 + t.l22 * n2);
  s.value = value;
  s.rate = rate;
}

MeanderWind::MeanderWind(const MeanderParams& params, const Vec3& mean, const WindRegion& region,
                         Rng rng)
    : params_(params),
      region_(region),
      mean_(mean),
      rng_(rng),
      nx_(params.nx),
      ny_(params.ny),
      inv_dx_((nx_ - 1) / (region.x_max - region.x_min)),
      inv_dy_((ny_ - 1) / (region.y_max - region.y_min)),
      uniform_(steady(params)),
      noise_params_{params.gain, params.damping, params.bandwidth} {
  for (ColouredNoiseState& n : noise_) n = stationary_coloured_noise(noise_params_, rng_);
  const std::size_t nodes = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  u_.assign(nodes, 0.0);
  v_.assign(nodes, 0.0);
  // the inside starts as the bilinear interpolation of the corners: the steady state of the
  // diffusion between the edges, which are linear between the corners
  for (int k = 0; k < 2; ++k) {
    std::vector<double>& g = k == 0 ? u_ : v_;
    const auto [c00, c10, c01, c11] = corners(k);
    for (int j = 0; j < ny_; ++j) {
      const double s = static_cast<double>(j) / (ny_ - 1);
      for (int i = 0; i < nx_; ++i) {
        const double r = static_cast<double>(i) / (nx_ - 1);
        const double lo = c00 + r * (c10 - c00), hi = c01 + r * (c11 - c01);
        g[index(i, j)] = lo + s * (hi - lo);
      }
    }
  }
  set_edges();
  u2_ = u_;
  v2_ = v_;
  coef_.assign(8 * static_cast<std::size_t>(nx_ - 1) * static_cast<std::size_t>(ny_ - 1), 0.0);
  refresh_cells();
}

std::array<double, 4> MeanderWind::corners(int k) const {
  const double m = k == 0 ? mean_.x : mean_.y;
  return {m + noise_[4 * k].value, m + noise_[4 * k + 1].value, m + noise_[4 * k + 2].value,
          m + noise_[4 * k + 3].value};
}

void MeanderWind::set_edges() {
  for (int k = 0; k < 2; ++k) {
    std::vector<double>& g = k == 0 ? u_ : v_;
    const auto [c00, c10, c01, c11] = corners(k);
    for (int i = 0; i < nx_; ++i) {
      const double r = static_cast<double>(i) / (nx_ - 1);
      g[index(i, 0)] = c00 + r * (c10 - c00);
      g[index(i, ny_ - 1)] = c01 + r * (c11 - c01);
    }
    for (int j = 0; j < ny_; ++j) {
      const double s = static_cast<double>(j) / (ny_ - 1);
      g[index(0, j)] = c00 + s * (c01 - c00);
      g[index(nx_ - 1, j)] = c10 + s * (c11 - c10);
    }
    // the corners exactly (c00 + 1 (c10 - c00) need not round to c10)
    g[index(0, 0)] = c00;
    g[index(nx_ - 1, 0)] = c10;
    g[index(0, ny_ - 1)] = c01;
    g[index(nx_ - 1, ny_ - 1)] = c11;
  }
}

double MeanderWind::max_substep(const MeanderParams& params, const WindRegion& region, double u_max,
                                double v_max) {
  const double dx = (region.x_max - region.x_min) / (params.nx - 1);
  const double dy = (region.y_max - region.y_min) / (params.ny - 1);
  const double diff_x = 0.5 * params.kx, diff_y = 0.5 * params.ky;
  // 4 (r_x + r_y) + C_x^2 / r_x + C_y^2 / r_y <= 2, with r = D h / d^2 and C = |u| h / d
  return 2.0 / (4.0 * (diff_x / (dx * dx) + diff_y / (dy * dy)) + u_max * u_max / diff_x +
                v_max * v_max / diff_y);
}

std::pair<double, double> MeanderWind::max_speeds(const MeanderParams& params,
                                                  const WindRegion& region) {
  const double dx = (region.x_max - region.x_min) / (params.nx - 1);
  const double dy = (region.y_max - region.y_min) / (params.ny - 1);
  // 2 D / d with D = K / 2
  return {params.kx / dx, params.ky / dy};
}

// why: the grid's update must stay bounded for every accepted combination of the keys (issue
// 22, G1: gain 10, bandwidth 100, damping 10 made the wind NaN). Both bounds of docs/model.md
// section 3.1 are checked at the mean wind plus 4 standard deviations of the boundary noise: the
// cell Peclet bound, without which centred differences overshoot and grow, and the substeps
// the time step needs, which bound the cost
void MeanderWind::check(const MeanderParams& m, const WindContext& context) {
  const double spread = 4.0 * std::sqrt(coloured_noise_variance({m.gain, m.damping, m.bandwidth}));
  const double u_max = std::abs(context.mean.x) + spread;
  const double v_max = std::abs(context.mean.y) + spread;
  const std::string noise = "meander.gain, meander.damping, meander.bandwidth";
  const auto [u_bound, v_bound] = max_speeds(m, context.region);
  const bool inside = m.gain > 0.0 && m.nx >= 3 && m.ny >= 3;  // else no node is computed
  const auto unstable = [&](const char* axis, const std::string& keys, double speed, double bound) {
    throw ConfigError(
        keys + ": the meandering wind would be unstable: its speed along " + axis + " reaches " +
        bound_text(speed) +
        " m/s (the mean wind plus 4 standard deviations of the "
        "boundary noise, 4 G sqrt(omega / (4 zeta)) = " +
        bound_text(spread) + " m/s), above the " + bound_text(bound) +
        " m/s its grid carries (2 D / spacing, D = K / "
        "2; docs/model.md section 3.1): lower the gain or the bandwidth, raise the damping or " +
        "the diffusivity, or add nodes");
  };
  if (inside && !(u_max <= u_bound)) {
    unstable("x", noise + ", wind.vx, meander.kx, meander.nx", u_max, u_bound);
  }
  if (inside && !(v_max <= v_bound)) {
    unstable("y", noise + ", wind.vy, meander.ky, meander.ny", v_max, v_bound);
  }
  const double substeps = std::ceil(context.dt / max_substep(m, context.region, u_max, v_max));
  if (!(substeps <= kMaxWindSubsteps)) {
    throw ConfigError(
        "meander.kx, meander.ky, meander.nx, meander.ny, meander.gain: the meandering wind's "
        "grid would need " +
        bound_text(substeps) + " substeps per step of sim.dt to stay stable (at most " +
        bound_text(kMaxWindSubsteps) +
        "): lower the diffusivities, the node counts, the gain or sim.dt");
  }
}

std::string MeanderWind::identity(const MeanderParams&, const WindRegion& region) {
  return "region.x_min=" + format_number(region.x_min) +
         "\nregion.x_max=" + format_number(region.x_max) +
         "\nregion.y_min=" + format_number(region.y_min) +
         "\nregion.y_max=" + format_number(region.y_max) + "\n";
}

void MeanderWind::step(double dt) {
  // the boundary: the corner noise advanced exactly over dt, the edges linear between corners
  if (dt != transition_dt_) {
    transition_ = coloured_noise_transition(noise_params_, dt);
    transition_dt_ = dt;
  }
  for (ColouredNoiseState& n : noise_) plumetrace::step(transition_, n, rng_);
  set_edges();
  if (nx_ < 3 || ny_ < 3) {
    substeps_ = 0;
    refresh_cells();
    return;
  }
  // the inside: as many equal substeps as the fastest node needs for stability
  double u_max = 0.0, v_max = 0.0;
  for (std::size_t k = 0; k < u_.size(); ++k) {
    // why: a comparison, not std::fmax (a call); NaN speeds are skipped
    const double a = std::abs(u_[k]), b = std::abs(v_[k]);
    u_max = a > u_max ? a : u_max;
    v_max = b > v_max ? b : v_max;
  }
  // why: a field gone infinite (which stays so) takes a bounded number of substeps, not 1 / 0;
  // check() (validate) keeps a scenario's field within kMaxWindSubsteps at 4 standard deviations
  const double n = std::ceil(dt / max_substep(params_, region_, u_max, v_max));
  substeps_ = n >= 1.0 ? static_cast<int>(std::min(n, 1e4)) : 1;
  const double h = dt / substeps_;
  for (int s = 0; s < substeps_; ++s) update_inside(h);
  refresh_cells();
}

void MeanderWind::update_inside(double h) {
  // Farrell et al. (2002): du/dt = -(u du/dx + v du/dy) + K_x/2 d2u/dx2 + K_y/2 d2u/dy2, the same
  // for v; centred differences, forward Euler, every node from the old values
  const double ax = 0.5 * params_.kx * inv_dx_ * inv_dx_, ay = 0.5 * params_.ky * inv_dy_ * inv_dy_;
  const double cx = 0.5 * inv_dx_, cy = 0.5 * inv_dy_;
  const std::size_t row = static_cast<std::size_t>(nx_);
  const double* u = u_.data();
  const double* v = v_.data();
  for (int j = 1; j < ny_ - 1; ++j) {
    for (int i = 1; i < nx_ - 1; ++i) {
      const std::size_t k = index(i, j);
      const double uc = u[k], vc = v[k];
      // why: (e - 2 c) + w and the differences are exactly 0 for a constant field, so zero gain
      // keeps the mean wind bit for bit
      const double u_diff =
          ax * (u[k + 1] - 2.0 * uc + u[k - 1]) + ay * (u[k + row] - 2.0 * uc + u[k - row]);
      const double v_diff =
          ax * (v[k + 1] - 2.0 * vc + v[k - 1]) + ay * (v[k + row] - 2.0 * vc + v[k - row]);
      const double u_adv =
          uc * ((u[k + 1] - u[k - 1]) * cx) + vc * ((u[k + row] - u[k - row]) * cy);
      const double v_adv =
          uc * ((v[k + 1] - v[k - 1]) * cx) + vc * ((v[k + row] - v[k - row]) * cy);
      u2_[k] = uc + h * (u_diff - u_adv);
      v2_[k] = vc + h * (v_diff - v_adv);
    }
  }
  for (int j = 1; j < ny_ - 1; ++j) {
    const std::size_t first = index(1, j), last = index(nx_ - 1, j);
    std::copy(u2_.begin() + static_cast<std::ptrdiff_t>(first),
              u2_.begin() + static_cast<std::ptrdiff_t>(last),
              u_.begin() + static_cast<std::ptrdiff_t>(first));
    std::copy(v2_.begin() + static_cast<std::ptrdiff_t>(first),
              v2_.begin() + static_cast<std::ptrdiff_t>(last),
              v_.begin() + static_cast<std::ptrdiff_t>(first));
  }
}

void MeanderWind::refresh_cells() {
  const int cells_x = nx_ - 1;
  for (int j = 0; j + 1 < ny_; ++j) {
    for (int i = 0; i + 1 < nx_; ++i) {
      double* c = coef_.data() + 8 * static_cast<std::size_t>(i + cells_x * j);
      for (const std::vector<double>* g : {&u_, &v_}) {
        const double g00 = (*g)[index(i, j)], g10 = (*g)[index(i + 1, j)];
        const double g01 = (*g)[index(i, j + 1)], g11 = (*g)[index(i + 1, j + 1)];
        c[0] = g00;
        c[1] = g10 - g00;
        c[2] = g01 - g00;
        c[3] = (g11 - g01) - (g10 - g00);
        c += 4;
      }
    }
  }
}

Vec3 MeanderWind::velocity(const Vec3& p) const {
  const wind_loops::CellView g = cells_of(region_, inv_dx_, inv_dy_, nx_, ny_, coef_);
  int k;
  double tx, ty, u, v;
  wind_loops::locate(g, p.x, p.y, k, tx, ty);
  wind_loops::evaluate(wind_loops::cell_coef(g, k), tx, ty, u, v);
  return {u, v, mean_.z};
}

void MeanderWind::advect(std::span<double> x, std::span<double> y, std::span<double> z,
                         double dt) const {
  // velocity(p) * dt at every point, to the bit (wind_loops.hpp)
  wind_loops::advect(simd::active(), cells_of(region_, inv_dx_, inv_dy_, nx_, ny_, coef_), x.data(),
                     y.data(), z.data(), 0, static_cast<std::int64_t>(x.size()), dt, mean_.z * dt);
}

}  // namespace plumetrace
