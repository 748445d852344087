#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/controllers/surge_spiral.hpp"

namespace plumetrace {

/// The most particles particle_filter.particles may ask for. why: a decision costs particles x
/// wind_history Gaussian terms, and a snapshot 3 numbers a particle (kMaxSnapshotValues).
inline constexpr std::int64_t kMaxParticles = 20'000;

/// The most particle-puff terms (particles x wind_history) one update may cost. why: keeps one
/// decision under about 10 ms whatever the two keys are.
inline constexpr std::int64_t kMaxParticleTerms = 2'000'000;

/// Parameters of the particle-filter source estimator (docs/algorithms.md, "particle-filter"):
/// MAPIR's GasSourceLocalization particle filter (after Li et al. 2011) riding on surge-spiral.
struct ParticleFilterParams {
  /// Number of particles (candidate source positions). why: 500, MAPIR's numberOfParticles.
  int particles = 500;
  /// Time between two filter updates, the puff spacing of the model (s). why: 1, MAPIR's deltaT.
  double update_interval = 1.0;
  /// Wind means kept, one per update: the puffs the model follows. why: 30, MAPIR's
  /// numberOfWindObs.
  int wind_history = 30;
  /// Probability that a puff at the sensor is detected. why: 0.9, MAPIR's mu.
  double mu = 0.9;
  /// Sensor area S_p (m^2). why: 0.01, MAPIR's Sp.
  double sensor_area = 0.01;
  /// Floor of the puff spread rate: sigma^2 = max(sd_wind^2, 2 K) tau per axis (m^2/s). why:
  /// in the laminar tunnel sd_wind ~ 0 and MAPIR's spread vanishes (docs/algorithms.md).
  double diffusivity = 0.04;
  /// Resample when N_eff < this fraction of the particles. why: 0.25, MAPIR's test.
  double resample_below = 0.25;
  /// Standard deviation of the offset given to each resampled particle (m). why: 0.05, the
  /// offset of MAPIR's children (2019 version).
  double jitter = 0.05;
  /// Fraction of the particles drawn afresh from the wind back-trajectory at each resampling.
  /// why: MAPIR refills a variable share; 0.1 chosen (docs/algorithms.md).
  double refill = 0.1;
  /// An estimate counts once the particles' weighted RMS radius is at most this (m). why: 0.5,
  /// MAPIR's Rconv.
  double r_conv = 0.5;
  /// Counted estimates kept; the source is declared when all lie within estimate_radius of
  /// their mean. why: 20, MAPIR's maxEstimations.
  int estimates = 20;
  /// Radius within which the kept estimates must agree (m). why: 0.5, MAPIR's convergenceThr.
  double estimate_radius = 0.5;
  /// The motion the filter rides on: the paper's surge-spiral (model.md section 7.3).
  SurgeSpiralParams motion;

  /// The config keys (core/config.hpp), in the table "particle_filter".
  template <class V>
  void fields(V& v) {
    v("particles", particles, "number of particles (candidate source positions)",
      IntegerSpec{1, kMaxParticles});
    v("update_interval", update_interval, "time between filter updates, the puff spacing (s)",
      NumberSpec{.min = 0.0, .max = 60.0, .min_open = true});
    v("wind_history", wind_history, "wind means kept, one per update (the puffs followed)",
      IntegerSpec{1, 600});
    v("mu", mu, "probability that a puff at the sensor is detected",
      NumberSpec{.min = 0.0, .max = 1.0, .min_open = true});
    v("sensor_area", sensor_area, "sensor area S_p in the hit likelihood (m^2)",
      NumberSpec{.min = 0.0, .max = 1.0, .min_open = true});
    v("diffusivity", diffusivity,
      "floor of the puff spread: sigma^2 = max(sd_wind^2, 2 K) tau per axis (m^2/s)",
      NumberSpec{.min = 0.0, .max = 100.0, .min_open = true});
    v("resample_below", resample_below,
      "resample when the effective particle count falls below this fraction of them",
      NumberSpec{.min = 0.0, .max = 1.0});
    v("jitter", jitter, "standard deviation of the offset of each resampled particle (m)",
      NumberSpec{.min = 0.0, .max = 10.0});
    v("refill", refill,
      "fraction of particles drawn afresh from the wind back-trajectory "
      "at each resampling",
      NumberSpec{.min = 0.0, .max = 1.0});
    v("r_conv", r_conv, "an estimate counts once the particles' RMS radius is at most this (m)",
      kPositive);
    v("estimates", estimates, "counted estimates that must agree before declaring",
      IntegerSpec{1, 1000});
    v("estimate_radius", estimate_radius,
      "radius within which the kept estimates must agree to declare (m)", kPositive);
    motion.fields(v);
  }
};

/// One puff of the model, as seen from its release point: where the wind has carried it since
/// (m, odometry frame), and its spread (docs/algorithms.md, "particle-filter").
struct Puff {
  Vec2 offset;          ///< displacement from the source since release (m)
  double inv_2vx = 0;   ///< 1 / (2 sigma_x^2) (1/m^2)
  double inv_2vy = 0;   ///< 1 / (2 sigma_y^2) (1/m^2)
  double density0 = 0;  ///< mu S_p / (2 pi sigma_x sigma_y): detection probability at its centre
};

/// The puffs of a wind history (oldest first, m/s, direction the air moves): puff i left the
/// source at the midpoint of interval i, so its age is (n - i - 1/2) dt and its offset the wind
/// since then; its variance per axis is max(sd_axis^2, 2 K) times its age, sd the population
/// standard deviation of the history. Writes puffs.size() == wind.size() entries.
void make_puffs(std::span<const Vec2> wind, double dt, double diffusivity, double mu,
                double sensor_area, std::span<Puff> puffs);

/// Probability of no hit at `robot` during one interval if the source is at `source`:
/// the product over puffs of (1 - min(1, density0 exp(-dx^2 inv_2vx - dy^2 inv_2vy))).
double no_hit_probability(const Vec2& source, const Vec2& robot, std::span<const Puff> puffs);

/// Effective particle count 1 / sum w^2 of normalised weights.
double effective_count(std::span<const double> weights);

/// Systematic resampling: indices[k] is the particle that holds the cumulative weight
/// (u + k) / n, n = indices.size(), u in [0, 1); weights are normalised.
void systematic_resample(std::span<const double> weights, double u, std::span<int> indices);

/// The mean of `points` when every one lies within `radius` of it; else nothing (has false).
struct Agreement {
  bool agree = false;  ///< all points within radius of their mean
  Vec2 mean;           ///< their mean
};
/// Whether the points agree within `radius` of their mean (MAPIR's declaration test).
Agreement agreement(std::span<const Vec2> points, double radius);

/// Particle-filter source estimator (MAPIR GasSourceLocalization, 2019; Li et al. 2011): it
/// rides on surge-spiral, updates its particles from hits and misses every update_interval, and
/// declares the source when its converged estimates agree.
class ParticleFilter final : public Controller {
 public:
  /// Creates the controller; `rng` draws the particles and the motion's tie breaks.
  ParticleFilter(const ParticleFilterParams& params, Rng rng);
  /// Refuses relations of the keys: a detection probability above 1 at a puff's centre, or
  /// more particle-puff terms per update than kMaxParticleTerms.
  static void check(const ParticleFilterParams& params);

  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override { return motion_.state(); }
  int losses() const override { return motion_.losses(); }
  Snapshot snapshot() const override;

  /// Whether the particles have been drawn (at the first update with a hit).
  bool started() const { return started_; }
  /// The particles (m, odometry frame).
  std::span<const Vec2> particles() const { return particles_; }
  /// Their normalised weights.
  std::span<const double> weights() const { return weights_; }
  /// The weighted mean of the particles (m, odometry frame).
  Vec2 estimate() const;
  /// The weighted RMS distance of the particles from their mean (m).
  double spread() const;
  /// Number of resamplings so far.
  int resamplings() const { return resamplings_; }

  /// Replaces the particles and weights (tests); sizes must equal params.particles.
  void set_particles(std::span<const Vec2> points, std::span<const double> weights);
  /// One filter update at `robot` with a hit or a miss, the wind history as it stands; returns
  /// the declared source when the estimates now agree (tests and step()).
  Agreement update(const Vec2& robot, bool hit);
  /// Appends one interval's mean wind (m/s, odometry frame) to the history; the first call
  /// fills the whole history with it (the wind before release taken as steady).
  void push_wind(const Vec2& wind);

 private:
  void draw_from_back_trajectory(const Vec2& robot, std::span<Vec2> out);
  void resample(const Vec2& robot);

  ParticleFilterParams params_;
  SurgeSpiral motion_;
  Rng rng_;
  bool started_ = false;
  std::vector<Vec2> particles_;
  std::vector<double> weights_;
  std::vector<Vec2> scratch_;
  std::vector<int> indices_;
  std::vector<Vec2> wind_;  // ring of wind means, oldest at wind_head_
  std::vector<Vec2> wind_ordered_;
  std::size_t wind_head_ = 0;
  bool wind_filled_ = false;
  std::vector<Puff> puffs_;
  std::vector<Vec2> estimates_;  // ring of counted estimates
  std::size_t estimates_count_ = 0;
  std::size_t estimates_head_ = 0;
  // the interval being accumulated
  double interval_start_ = 0.0;
  Vec2 wind_sum_;
  int wind_samples_ = 0;
  bool hit_ = false;
  int resamplings_ = 0;
};

}  // namespace plumetrace
