#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// What counts as a hit in a decision interval.
enum class InfotaxisHits {
  kBinary,         ///< a step with the binary odor (obs.odor)
  kConcentration,  ///< a step whose concentration reading reaches infotaxis.hit_threshold
};

/// The most cells the belief grid may have: the cost of a decision grows with the cells (about
/// 0.1 microsecond each per candidate move) and the kernel table holds four times as many.
inline constexpr int kMaxInfotaxisCells = 40'000;

/// Parameters of infotaxis (Vergassola, Villermaux & Shraiman 2007; docs/algorithms.md,
/// "infotaxis", says where each default comes from).
struct InfotaxisParams {
  /// Effective diffusivity D of the odor particles (m^2/s).
  double diffusivity = 0.01;
  /// Particle lifetime tau (s).
  double lifetime = 30.0;
  /// Mean wind speed V the model assumes (m/s); its direction is measured.
  double wind_speed = 1.0;
  /// Emission rate R of the source (particles/s).
  double emission_rate = 300.0;
  /// Linear size a of the detector (m); must be below the correlation length lambda.
  double detector_size = 0.001;
  /// Side of a grid cell (m): the length of one move.
  double cell = 0.25;
  /// Cells of the grid upwind of the start cell.
  int cells_upwind = 61;
  /// Cells of the grid downwind of the start cell.
  int cells_downwind = 1;
  /// Cells of the grid on each side of the start cell, across the wind.
  int cells_crosswind = 7;
  /// Wind samples averaged at release to orient the grid and the model's wind.
  int wind_samples = 10;
  /// Speed the model assumes to predict how long a move lasts (m/s).
  double speed = 0.106;
  /// What counts as a hit.
  InfotaxisHits hits = InfotaxisHits::kBinary;
  /// Concentration at or above which a step is a hit when hits = concentration.
  double hit_threshold = 100.0;
  /// The source is declared once the belief within declare_radius of its mode reaches this.
  double declare_probability = 1.0;
  /// Radius around the belief's mode whose mass decides the declaration (m).
  double declare_radius = 0.25;

  /// The config keys (core/config.hpp), in the table "infotaxis".
  template <class V>
  void fields(V& v) {
    v("diffusivity", diffusivity, "effective diffusivity D of the odor particles (m^2/s)",
      kPositive);
    v("lifetime", lifetime, "particle lifetime tau (s)", kPositive);
    v("wind_speed", wind_speed, "mean wind speed V of the model (m/s); direction is measured",
      kNonNegative);
    v("emission_rate", emission_rate, "emission rate R of the source (particles/s)", kPositive);
    v("detector_size", detector_size,
      "linear size a of the detector (m); below the correlation length lambda", kPositive);
    v("cell", cell, "side of a grid cell and length of one move (m)",
      NumberSpec{.min = 0.01, .max = 10.0});
    v("cells_upwind", cells_upwind, "grid cells upwind of the start cell", IntegerSpec{0, 1000});
    v("cells_downwind", cells_downwind, "grid cells downwind of the start cell",
      IntegerSpec{0, 1000});
    v("cells_crosswind", cells_crosswind, "grid cells on each side of the start, across the wind",
      IntegerSpec{0, 1000});
    v("wind_samples", wind_samples, "wind samples averaged at release to orient the grid",
      IntegerSpec{1, 1000});
    v("speed", speed, "speed assumed to predict a move's duration (m/s)", kPositive);
    v("hits", hits, "what counts as a hit: binary odor, or concentration >= hit_threshold",
      {"binary", "concentration"});
    v("hit_threshold", hit_threshold, "concentration counted as a hit (hits = concentration)",
      kPositive);
    v("declare_probability", declare_probability,
      "belief mass within declare_radius of the mode that declares the source",
      NumberSpec{.min = 0.0, .max = 1.0, .min_open = true});
    v("declare_radius", declare_radius, "radius around the belief's mode for declaring (m)",
      kNonNegative);
  }
};

/// Modified Bessel function of the second kind of order 0, K0(x) for x > 0 (Abramowitz & Stegun
/// 9.8.5 and 9.8.6: absolute error below 1e-8 for x <= 2, relative below 2e-7 beyond).
double bessel_k0(double x);

/// ln K0(x) for x > 0, without underflow for large x (A&S 9.8.6 in log form beyond x = 2).
double log_bessel_k0(double x);

/// The correlation length lambda = sqrt(D tau / (1 + V^2 tau / (4 D))) (m) of the model.
double infotaxis_lambda(double diffusivity, double lifetime, double wind_speed);

/// ln of the mean rate of encounters (1/s) of a detector at displacement `d` (m) from the
/// source, `s` (m) of it along the wind (downwind positive), in 2-D:
/// R(r|r0) = R / ln(lambda/a) exp(V s / (2 D)) K0(d / lambda). d is clamped to at least a.
double log_encounter_rate(const InfotaxisParams& p, double d, double s);

/// The belief of infotaxis over source positions on a grid of nx by ny cells (row-major by y),
/// with the encounter-rate model tabulated once by displacement in cells. The rules of the
/// algorithm (the Bayes update, the expected entropy of a move) are its members, so that a test
/// world can drive them without a robot.
class InfotaxisBelief {
 public:
  /// The four moves, in the order ties are broken: -x, +x, -y, +y (OTTO's).
  static constexpr std::array<std::array<int, 2>, 4> kMoves{{{-1, 0}, {1, 0}, {0, -1}, {0, 1}}};

  InfotaxisBelief() = default;
  /// A uniform belief on nx by ny cells of side `cell` (m); the model's wind blows toward
  /// `downwind` (a unit vector in the grid's frame).
  InfotaxisBelief(const InfotaxisParams& p, int nx, int ny, Vec2 downwind);

  int nx() const { return nx_; }  ///< cells along x
  int ny() const { return ny_; }  ///< cells along y
  /// The belief, row-major by y: p(i, j) = probability()[j * nx + i].
  const std::vector<double>& probability() const { return p_; }
  /// Replaces the belief (normalised by the caller); for tests.
  void set_probability(const std::vector<double>& p) { p_ = p; }
  /// The model's mean encounter rate (1/s) at cell (i, j) for a source at cell (k, l).
  double rate(int i, int j, int k, int l) const { return rate_[displacement(i - k, j - l)]; }
  /// Entropy of the belief (nats).
  double entropy() const;

  /// Bayes update for the searcher at cell (i, j) after an interval of `duration` (s) with a hit
  /// (any encounter) or none: the source is not at (i, j); p(x) *= 1 - exp(-mu) or exp(-mu),
  /// mu = rate * duration; then normalised. An observation the model gives probability 0
  /// everywhere leaves the belief with only the not-found update.
  void update(int i, int j, bool hit, double duration);

  /// Expected entropy after moving to cell (i, j) and observing for `duration` (s): the source
  /// is found there with probability p(i, j) (entropy 0), else the entropy of the posterior
  /// averaged over hit and no hit. +inf off the grid.
  double expected_entropy(int i, int j, double duration) const;

  /// Index in kMoves of the move from (i, j) with the least expected entropy among those whose
  /// cell is on the grid and not `blocked`; -1 when there is none. A move onto a cell holding
  /// the source with probability above 1 - 1e-10 is taken at once.
  int choose_move(int i, int j, double duration, const std::vector<char>& blocked) const;

  /// The cell of largest probability (the lowest index among equals).
  std::array<int, 2> mode() const;
  /// Probability within `radius` cells (Euclidean, between centres) of cell (i, j).
  double mass_within(int i, int j, double radius) const;

 private:
  // the index in rate_ (and terms_) of the displacement (di, dj) = agent - source, in cells
  std::size_t displacement(int di, int dj) const {
    return static_cast<std::size_t>(dj + ny_ - 1) * (2 * nx_ - 1) + (di + nx_ - 1);
  }
  // expected_entropy with the belief's entropy already computed
  double expected_entropy(int i, int j, double duration, double entropy) const;

  int nx_ = 0;
  int ny_ = 0;
  std::vector<double> p_;
  std::vector<double> rate_;     // by displacement (agent - source) in cells
  std::vector<double> scratch_;  // the posterior being formed
  // e^-mu, 1 - e^-mu and the hit entropy of mu = rate * duration by displacement, as rate_, for
  // the duration they were last made for
  struct Terms {
    double q0 = 0.0, q1 = 0.0, h = 0.0;
  };
  const std::vector<Terms>& terms(double duration) const;
  // why: mutable, a cache: choose_move asks every cell's terms for each of 4 moves at each cell
  // the searcher reaches, always for the same duration; they are made once per duration, from
  // the same expressions, so expected_entropy gives the same bits as without them
  mutable std::vector<Terms> terms_;
  mutable double terms_duration_ = -1.0;
};

/// Infotaxis (Vergassola, Villermaux & Shraiman 2007): at release it averages wind_samples wind
/// samples and lays its grid in the odometry frame, upwind along the axis nearest the measured
/// upwind; then, at each cell reached, it updates its belief with whether it met odor on the way
/// there and moves to the neighbour cell that minimises the expected entropy, until the belief
/// is concentrated enough to declare the source at its mode.
class Infotaxis final : public Controller {
 public:
  /// Creates the controller; it draws no random numbers (ties go to a fixed order).
  Infotaxis(const InfotaxisParams& params, Rng /*rng*/) : params_(params) {}
  /// Refuses a detector not smaller than lambda and a grid of more than kMaxInfotaxisCells.
  static void check(const InfotaxisParams& params);
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override;
  int losses() const override { return 0; }
  unsigned reads() const override {
    return params_.hits == InfotaxisHits::kConcentration ? kReadsConcentration : kReadsBinary;
  }
  Snapshot snapshot() const override;
  /// The belief (empty before the first step).
  const InfotaxisBelief& belief() const { return belief_; }
  /// The cell the searcher stands on or last left.
  std::array<int, 2> cell() const { return {ci_, cj_}; }
  /// Decisions taken so far.
  int decisions() const { return decisions_; }

 private:
  void start(const Observation& obs, WindProbe& wind);
  Vec2 centre(int i, int j) const;
  // updates the belief at the current cell, then declares or chooses the next target
  Command decide(const Observation& obs);

  InfotaxisParams params_;
  bool started_ = false;
  bool moving_ = false;
  InfotaxisBelief belief_;
  std::vector<char> blocked_;
  int i0_ = 0, j0_ = 0;  // start cell
  int ci_ = 0, cj_ = 0;  // current cell
  int ti_ = 0, tj_ = 0;  // target cell
  double window_start_ = 0.0;
  bool window_hit_ = false;
  double last_odometer_ = 0.0;
  double last_heading_ = 0.0;
  double commanded_ = 0.0;
  bool commanded_go_ = false;
  double move_start_ = 0.0;
  int decisions_ = 0;
  bool declared_ = false;
};

}  // namespace plumetrace
