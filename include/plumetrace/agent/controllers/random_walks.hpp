#pragma once

#include <array>

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// How a correlated random walk draws its step lengths.
enum class StepLaw {
  kFixed,        ///< every step has the mean length
  kExponential,  ///< exponential lengths of that mean
};

/// Parameters of the correlated random walk (docs/algorithms.md, "crw"): a null model that uses
/// no odor, only (with a bias) the wind.
struct CrwParams {
  /// Mean step length (m). why: 0.5 m, chosen: a few body lengths, the run length of
  /// chemotaxis, so the two walks differ only in what chemotaxis reads.
  double step = 0.5;
  /// How step lengths are drawn.
  StepLaw step_law = StepLaw::kFixed;
  /// Mean cosine of the wrapped Cauchy turning angle (0: uniform turns, 1: straight). why: 0.5,
  /// chosen: halfway between a simple random walk and a straight line.
  double rho = 0.5;
  /// Weight of the upwind direction in each step's mean heading (0: no bias, a CRW; 1: a
  /// biased random walk around upwind).
  double upwind_bias = 0.0;

  /// The config keys (core/config.hpp), in the table "crw".
  template <class V>
  void fields(V& v) {
    v("step", step, "mean step length (m)", NumberSpec{.min = 0.0, .max = 100.0, .min_open = true});
    v("step_law", step_law, "step lengths: all the mean ('fixed') or exponential of that mean",
      {"fixed", "exponential"});
    v("rho", rho, "mean cosine of the wrapped Cauchy turning angle, 0 (uniform) to 1 (straight)",
      NumberSpec{.min = 0.0, .max = 1.0});
    v("upwind_bias", upwind_bias,
      "weight of the measured upwind direction in each step's mean heading, 0 (none) to 1",
      NumberSpec{.min = 0.0, .max = 1.0});
  }
};

/// Parameters of the Levy walk (docs/algorithms.md, "levy"): a null model that uses no odor,
/// only (with a bias) the wind.
struct LevyParams {
  /// Exponent mu of the step-length density p(l) ~ l^-mu, in (1, 3]. why: 2, the optimum of
  /// Viswanathan et al. 1999 (Nature 401:911) for sparse targets that can be revisited.
  double mu = 2.0;
  /// Shortest step (m). why: 0.185 m, the supervisor's success radius, the distance at which a
  /// target counts as found (Viswanathan et al. take the shortest step as the detection radius).
  double l_min = 0.185;
  /// Longest step (m): the power law is truncated there. why: 16.5 m, the diagonal of the
  /// paper's 16 m by 4 m arena: no straight step inside it is longer.
  double l_max = 16.5;
  /// Mean cosine of each step's heading about the measured upwind direction (0: uniform
  /// headings, no bias; 1: straight upwind); Levy-taxis when above 0.
  double upwind_bias = 0.0;

  /// The config keys (core/config.hpp), in the table "levy".
  template <class V>
  void fields(V& v) {
    v("mu", mu, "exponent of the step-length density l^-mu, in (1, 3]",
      NumberSpec{.min = 1.0, .max = 3.0, .min_open = true});
    v("l_min", l_min, "shortest step (m)", NumberSpec{.min = 0.0, .max = 100.0, .min_open = true});
    v("l_max", l_max, "longest step: the power law is truncated there (m)",
      NumberSpec{.min = 0.0, .max = 1000.0, .min_open = true});
    v("upwind_bias", upwind_bias,
      "mean cosine of each heading about the measured upwind direction, 0 (none) to 1",
      NumberSpec{.min = 0.0, .max = 1.0});
  }
};

/// The most recent legs a walk's snapshot shows.
inline constexpr int kWalkHistory = 64;

/// The legs a walk drove, newest last, for its snapshot: a ring of leg start points.
class LegHistory {
 public:
  /// Records the start of a leg (m, odometry frame).
  void add(const Vec2& p) {
    points_[next_] = p;
    next_ = (next_ + 1) % kWalkHistory;
    if (count_ < kWalkHistory) ++count_;
  }
  /// The recorded points, oldest first, then `last`: the path of the walk up to now.
  std::vector<Vec2> path(const Vec2& last) const;

 private:
  std::array<Vec2, kWalkHistory> points_{};
  int next_ = 0;
  int count_ = 0;
};

/// Draws a step length (m) from the power law p(l) = C l^-mu on [l_min, l_max] (truncated and
/// renormalised) by inverting its distribution function at `u` in [0, 1).
double levy_step(double mu, double l_min, double l_max, double u);

/// P(l > x) for the truncated power law of levy_step: the step-length law's tail.
double levy_tail(double mu, double l_min, double l_max, double x);

/// Mean squared net displacement (m^2) after n steps of a correlated random walk with mean step
/// E[l], mean squared step E[l^2] and mean turning cosine c < 1 (zero mean sine), independent
/// steps and turns (Kareiva & Shigesada 1983, restated by Codling et al. 2008):
///   n E[l^2] + 2 E[l]^2 c / (1 - c) (n - (1 - c^n) / (1 - c)).
double crw_mean_squared_displacement(int n, double mean_step, double mean_step2, double c);

/// The correlated random walk: straight steps, each turned from the last by a wrapped Cauchy
/// angle; with an upwind bias, around a mean heading that weighs the measured upwind direction
/// against the last heading (a biased correlated random walk). A blocked step ends and the next
/// begins. Never gives up.
class Crw final : public Controller {
 public:
  /// Creates the walk; `rng` draws its first heading, turns and step lengths.
  Crw(const CrwParams& params, Rng rng) : params_(params), rng_(rng) {}
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override { return "walk"; }
  int losses() const override { return 0; }
  /// The path of its recent legs, ending at the planned end of the current one.
  Snapshot snapshot() const override;
  /// Number of legs begun so far.
  int legs() const { return legs_; }
  /// The current leg.
  const Leg& leg() const { return leg_; }

 private:
  CrwParams params_;
  Rng rng_;
  Leg leg_;
  LegHistory history_;
  int legs_ = 0;
};

/// The Levy walk: straight steps of power-law lengths on headings drawn uniformly, or, with an
/// upwind bias, from a wrapped Cauchy law about the measured upwind direction (Levy-taxis). A
/// blocked step ends and the next begins. Never gives up.
class Levy final : public Controller {
 public:
  /// Creates the walk; `rng` draws its headings and step lengths.
  Levy(const LevyParams& params, Rng rng) : params_(params), rng_(rng) {}
  /// Refuses l_max below l_min (ConfigError naming levy.l_max).
  static void check(const LevyParams& params);
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override { return "walk"; }
  int losses() const override { return 0; }
  /// The path of its recent legs, ending at the planned end of the current one.
  Snapshot snapshot() const override;
  /// Number of legs begun so far.
  int legs() const { return legs_; }
  /// The current leg.
  const Leg& leg() const { return leg_; }

 private:
  LevyParams params_;
  Rng rng_;
  Leg leg_;
  LegHistory history_;
  int legs_ = 0;
};

}  // namespace plumetrace
