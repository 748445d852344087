#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// The meandering wind's perturbation (wind.model = "meander", Farrell et al. 2002; docs/model.md
/// section 3.1), in its own table: `[meander] gain = ...`. Defaults: the `meander-strong`
/// scenario (scenarios/meander-strong.toml).
struct MeanderParams {
  /// Gain G of the boundary noise filter (m/s^0.5); 0: the constant wind, bit for bit. why:
  /// 0.14 gives the centreline a 0.6 m standard deviation at the robot's start (docs/model.md
  /// section 3.1); Farrell's G = 20 is of a time-step-dependent update and does not carry over.
  double gain = 0.14;
  /// Damping ratio zeta of the filter. why: Farrell et al.'s large-amplitude meander, 0.1.
  double damping = 0.1;
  /// Bandwidth omega (undamped natural frequency) of the filter (rad/s). why: Farrell et al.'s
  /// large-amplitude meander, 0.2.
  double bandwidth = 0.2;
  /// Diffusivity K_x of the interior update (m^2/s). why: inside Farrell et al.'s [1, 30].
  double kx = 10.0;
  /// Diffusivity K_y of the interior update (m^2/s). why: inside Farrell et al.'s [1, 30].
  double ky = 10.0;
  /// Grid nodes along x, walls included. why: 1 m spacing on the default 16 m arena.
  int nx = 17;
  /// Grid nodes along y, walls included. why: 1.33 m spacing on the default 4 m arena; an even
  /// count keeps a node row off the centreline y = 0, so that neighbouring filaments mostly
  /// share a cell, which the vectorised interpolation is fastest for (docs/performance.md).
  int ny = 4;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("gain", gain, "gain G of the boundary noise (m/s^0.5); 0: the constant wind",
      NumberSpec{.min = 0.0, .max = 10.0});
    v("damping", damping, "damping ratio zeta of the boundary noise",
      NumberSpec{.min = 0.0, .max = 10.0, .min_open = true});
    v("bandwidth", bandwidth, "bandwidth omega of the boundary noise (rad/s)",
      NumberSpec{.min = 0.0, .max = 100.0, .min_open = true});
    v("kx", kx, "diffusivity K_x of the wind grid (m^2/s)",
      NumberSpec{.min = 0.0, .max = 1000.0, .min_open = true});
    v("ky", ky, "diffusivity K_y of the wind grid (m^2/s)",
      NumberSpec{.min = 0.0, .max = 1000.0, .min_open = true});
    v("nx", nx, "wind grid nodes along x, walls included", IntegerSpec{2, 201});
    v("ny", ny, "wind grid nodes along y, walls included", IntegerSpec{2, 201});
  }
};

/// The most substeps the meandering wind's grid may need per step of sim.dt: 1000. why: its cost
/// grows with K / spacing^2 and the wind speed squared; beyond this a run would crawl.
inline constexpr double kMaxWindSubsteps = 1000.0;

/// A second-order filter driven by white noise (Farrell et al. 2002; docs/model.md section 3.1):
/// x'' + 2 zeta omega x' + omega^2 x = G omega^2 xi(t), xi unit white noise.
struct ColouredNoiseParams {
  double gain;       ///< G (m/s^0.5)
  double damping;    ///< zeta, > 0
  double bandwidth;  ///< omega (rad/s), > 0
};

/// The filter's state: its output x (m/s) and its rate x' (m/s^2).
struct ColouredNoiseState {
  double value = 0.0;  ///< x (m/s)
  double rate = 0.0;   ///< x' (m/s^2)
};

/// The exact discrete step of the filter over one dt: state <- phi * state + L * (n1, n2), with
/// n1, n2 independent standard normals and L L^T the covariance the noise adds in dt.
struct ColouredNoiseTransition {
  double phi[2][2];  ///< exp(A dt)
  double l11;        ///< Cholesky factor of the added covariance: (0, 0)
  double l21;        ///< (1, 0)
  double l22;        ///< (1, 1)
};

/// Stationary variance of the output x: G^2 omega / (4 zeta) ((m/s)^2).
double coloured_noise_variance(const ColouredNoiseParams& params);
/// Stationary variance of the rate x': G^2 omega^3 / (4 zeta) ((m/s^2)^2).
double coloured_noise_rate_variance(const ColouredNoiseParams& params);
/// Autocorrelation of the stationary output at a lag (s): phi_11(lag).
double coloured_noise_correlation(const ColouredNoiseParams& params, double lag);
/// Integral time scale of the output, the integral of its autocorrelation over lags >= 0 (s):
/// 2 zeta / omega.
double coloured_noise_time_scale(const ColouredNoiseParams& params);
/// The exact step over dt (s) (docs/model.md section 3.1: phi in closed form, the added
/// covariance by Gauss-Legendre quadrature of its defining integral).
ColouredNoiseTransition coloured_noise_transition(const ColouredNoiseParams& params, double dt);
/// A state drawn from the stationary law (two normals: value, then rate).
ColouredNoiseState stationary_coloured_noise(const ColouredNoiseParams& params, Rng& rng);
/// Advances the state by one step of `transition` (two normals).
void step(const ColouredNoiseTransition& transition, ColouredNoiseState& state, Rng& rng);

/// Farrell et al.'s (2002) meandering wind over the arena: the mean wind plus a perturbation on a
/// grid of nx by ny nodes spanning the region, walls included (docs/model.md section 3.1). On
/// the grid's edges (u, v) follow the mean plus coloured noise at the four corners, linear along
/// each edge; inside, Farrell's advection-diffusion update; between nodes, bilinear
/// interpolation (clamped to the grid outside it). The vertical wind is the mean's vz.
class MeanderWind final : public WindField {
 public:
  /// Builds the field around the mean wind `mean` (m/s) over `region`, drawing the noise's
  /// first state from the stationary law; the inside starts as the bilinear interpolation of the
  /// four corners.
  MeanderWind(const MeanderParams& params, const Vec3& mean, const WindRegion& region, Rng rng);
  /// Builds the field from a scenario's wind: around context.mean over context.region.
  MeanderWind(const MeanderParams& params, const WindContext& context, Rng rng)
      : MeanderWind(params, context.mean, context.region, rng) {}

  /// Advances the corner noise exactly, sets the edges, then updates the inside in
  /// `substeps()` equal substeps of Farrell's scheme (forward Euler, centred differences).
  void step(double dt) override;
  /// Bilinear interpolation of the grid at p (x, y clamped to the region); z: the mean vz.
  Vec3 velocity(const Vec3& p) const override;
  /// True when the gain is 0: the field is then the mean wind, exactly, everywhere and always.
  bool uniform_in_space() const override { return uniform_; }
  /// velocity() at every point, in one loop.
  void advect(std::span<double> x, std::span<double> y, std::span<double> z,
              double dt) const override;

  /// Nodes along x.
  int nx() const { return nx_; }
  /// Nodes along y.
  int ny() const { return ny_; }
  /// The x component at node (i, j), at x_min + i dx, y_min + j dy (m/s).
  double u(int i, int j) const { return u_[index(i, j)]; }
  /// The y component at node (i, j) (m/s).
  double v(int i, int j) const { return v_[index(i, j)]; }
  /// Substeps the last step took.
  int substeps() const { return substeps_; }

  /// The longest substep (s) for which the inside update is stable at speeds up to |u| <= u_max
  /// and |v| <= v_max (m/s), by the von Neumann bound of docs/model.md section 3.1.
  static double max_substep(const MeanderParams& params, const WindRegion& region, double u_max,
                            double v_max);

  /// The fastest |u| (first) and |v| (second), in m/s, that the centred differences carry
  /// without overshoot: the cell Péclet bound |u| dx <= 2 D_x, |v| dy <= 2 D_y (D = K / 2), under
  /// which every substep makes each inside node a weighted mean of its old neighbourhood, so no
  /// value outgrows the edges (docs/model.md section 3.1).
  static std::pair<double, double> max_speeds(const MeanderParams& params,
                                              const WindRegion& region);

  /// Refuses params with which the grid's update could grow without bound or crawl (WindHooks::
  /// check): both bounds of docs/model.md section 3.1 at the mean wind plus 4 standard
  /// deviations of the boundary noise, the cell Péclet bound (max_speeds) and at most
  /// kMaxWindSubsteps substeps per step of context.dt. Throws ConfigError naming the keys.
  static void check(const MeanderParams& params, const WindContext& context);
  /// True when the gain is 0: the field is then the mean wind (WindHooks::steady).
  static bool steady(const MeanderParams& params) { return params.gain == 0.0; }
  /// The region its grid spans (WindHooks::identity): two fields of the same keys over other
  /// regions differ.
  static std::string identity(const MeanderParams& params, const WindRegion& region);

 private:
  std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(nx_) * static_cast<std::size_t>(j);
  }
  /// The corners of component k (0: u, 1: v) now, mean plus noise: (x_min, y_min),
  /// (x_max, y_min), (x_min, y_max), (x_max, y_max).
  std::array<double, 4> corners(int k) const;
  void set_edges();
  void update_inside(double h);
  void refresh_cells();

  MeanderParams params_;
  WindRegion region_;
  Vec3 mean_;
  Rng rng_;
  int nx_, ny_;
  double inv_dx_, inv_dy_;  // 1 / spacing (1/m)
  bool uniform_;
  ColouredNoiseParams noise_params_;
  // the corner noise: u at corners 0-3, then v; corners (x_min, y_min), (x_max, y_min),
  // (x_min, y_max), (x_max, y_max)
  ColouredNoiseState noise_[8];
  double transition_dt_ = -1.0;  // the dt `transition_` was made for
  ColouredNoiseTransition transition_{};
  int substeps_ = 0;
  std::vector<double> u_, v_;    // node values, x fastest
  std::vector<double> u2_, v2_;  // the next substep's values
  // each cell's bilinear coefficients (src/env/wind_loops.hpp)
  std::vector<double> coef_;
};

}  // namespace plumetrace
