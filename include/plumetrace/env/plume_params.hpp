#pragma once

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"

namespace plumetrace {

/// The largest plume.release_rate (1/s): 1e6, 10^4 times the paper's 100/s. why: every released
/// filament is stepped, and kept until it leaves under plume.lifetime = leave_arena; at 1e20 a
/// run never ends (issue 13, F9).
inline constexpr double kMaxReleaseRate = 1e6;

/// The largest plume.capacity (filaments): 1e7, 6250 times the default 1600. why: the ring is
/// reserved at the start of every run, 40 bytes a filament (400 MB at the limit, per thread).
inline constexpr int kMaxCapacity = 10'000'000;

/// Named sets of plume parameters (docs/model.md section 11).
/// Which odor model: its place in odor_field_registry() (env/odor.hpp); the built-in one.
enum class OdorModel : int {
  kFilament = 0,  ///< the filament plume of the paper (docs/model.md section 4)
};

/// The registered odor models' names, in the order of odor_field_registry().
Choices odor_model_names();

enum class PlumePreset {
  /// the default: the plume of the default reading (docs/fidelity.md, "Which reading won"),
  /// the plugin's plume with the amount never applied (s = 1), sigma_p = 0.02, printed kernel
  kLochmatter2008,
  kPaperLiteral,  ///< the equations as printed in the paper
};

/// Where new filaments appear around the source centre.
enum class ReleaseShape { kBall, kDisc };

/// How the random-walk standard deviation per step scales with dt.
enum class NoiseMode {
  kVelocity,  ///< std sigma_p * dt (sigma_p in m/s), the plugin's choice
  kPerStep,   ///< std sigma_p (sigma_p in m), paper eq. 2 as printed
  kWiener,    ///< std sigma_p * sqrt(dt) (sigma_p in m/sqrt(s)), time-step consistent
};

/// How filaments spread relative to the wind (docs/model.md section 4.3).
enum class Dispersion {
  /// the paper's eqs. 2-3: a random walk of plume.sigma_p scaled by plume.noise_mode, and
  /// w += plume.gamma / (2 w) per step
  kPaper,
  /// Farrell et al. (2002)'s relative dispersion: each centre takes a white-noise velocity of
  /// diffusivity plume.relative_diffusivity, and w^2 grows at plume.spread_rate
  kFarrell,
};

/// How filaments leave the simulation.
enum class Lifetime {
  kRing,        ///< fixed ring buffer of `capacity` filaments; a new one overwrites the oldest
  kLeaveArena,  ///< removed once downwind of the arena's far end; no cap
};

/// The concentration contributed by one filament.
enum class Kernel {
  kGaussian,  ///< s / (sqrt(8 pi^3) w^3) exp(-d^2 / w^2), the plugin's
  kPrinted,   ///< s / w^3 exp(-d / w^2), paper eq. 5 as printed
};

/// The odor source: a disc/ball around its centre.
struct SourceParams {
  /// Centre of the source (m).
  Vec3 center{1.0, 0.0, 0.0};
  /// Radius of the source (m); filaments are released within it.
  double radius = 0.12;
  /// Radius of a solid cylinder at the centre that the robot cannot enter (m); 0: none.
  /// The plume does not see it. why: the 2008 wind-tunnel world's collidable source cylinder
  /// (docs/fidelity.md, unknown 7).
  double solid_radius = 0.05;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("x", center.x, "source centre x (m)", kAnyNumber);
    v("y", center.y, "source centre y (m)", kAnyNumber);
    v("z", center.z, "source centre z (m)", kAnyNumber);
    v("radius", radius, "source radius, filaments are released within it (m)", kPositive);
    v("solid_radius", solid_radius,
      "radius of a solid source cylinder the robot stops at (m, 0: none)",
      NumberSpec{.min = 0.0, .max = 1.0});
  }
};

/// Every row of the plume's preset table (docs/model.md); defaults are the `lochmatter2008`
/// preset, the plume of the default reading (docs/fidelity.md).
struct PlumeParams {
  /// Preset the rows below started from.
  /// Odor model. why: the paper's filament plume is the one registered (issue 24: every model
  /// family is chosen by a key).
  OdorModel model = OdorModel::kFilament;
  PlumePreset preset = PlumePreset::kLochmatter2008;
  /// Filaments released per second (1/s).
  double release_rate = 100.0;
  /// Shape of the release region (radius: the source radius).
  ReleaseShape release_shape = ReleaseShape::kBall;
  /// Width of a new filament (m).
  double initial_width = 0.10;
  /// Amount of odor in one filament (molecules). why: 1, not the printed 8.3e9: the oldest
  /// public copy of the plugin never applies the configured amount (docs/fidelity.md, unknown 1).
  double amount = 1.0;
  /// Scaling of the random walk with dt.
  NoiseMode noise_mode = NoiseMode::kVelocity;
  /// Random-walk intensity (m/s, m or m/sqrt(s) depending on noise_mode). why: the plugin
  /// copies' 0.02 (docs/fidelity.md, unknown 3).
  double sigma_p = 0.02;
  /// Width growth constant per step (m^2): w += gamma / (2 w).
  double gamma = 4e-7;
  /// Which relative dispersion moves and widens the filaments: the paper's rows above (sigma_p,
  /// noise_mode, gamma) or Farrell et al.'s (the two rows below).
  Dispersion dispersion = Dispersion::kPaper;
  /// Farrell: diffusivity of each centre's white-noise velocity (m^2/s); one step moves it by a
  /// normal of standard deviation sqrt(2 D dt) per axis. why: 6.4e-6, the paper rows' walk at
  /// the default sim.dt 0.032 s, (0.02 m/s x 0.032 s)^2 / (2 x 0.032 s) (docs/model.md 4.3).
  double relative_diffusivity = 6.4e-6;
  /// Farrell: growth rate of the squared width (m^2/s); one step sets w = sqrt(w^2 + rate dt).
  /// why: 1.25e-5, the paper rows' gamma at the default sim.dt, 4e-7 m^2 / 0.032 s.
  double spread_rate = 1.25e-5;
  /// How filaments leave.
  Lifetime lifetime = Lifetime::kRing;
  /// Ring-buffer size (filaments), used with Lifetime::kRing; derived unless set
  /// (derive_scenario, sim/scenario.hpp).
  int capacity = 1600;
  /// plume.capacity is "auto": derived from the release rate, the arena's length and the wind.
  bool capacity_auto = true;
  /// Concentration kernel. why: paper eq. 5 as printed (docs/fidelity.md, unknown 4).
  Kernel kernel = Kernel::kPrinted;
  /// Filaments farther than this from a query point contribute nothing (m); may be infinite.
  double cutoff = 1.0;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("model", model, "odor model (the rows below are the filament plume's)", odor_model_names());
    v("preset", preset, "preset the plume rows start from", {"lochmatter2008", "paper-literal"});
    v("release_rate", release_rate, "filaments released per second (1/s)",
      NumberSpec{.min = 0.0, .max = kMaxReleaseRate, .min_open = true});
    v("release_shape", release_shape, "release region around the source centre", {"ball", "disc"});
    v("initial_width", initial_width, "width of a new filament (m)", kPositive);
    v("amount", amount, "odor amount per filament (molecules)", kPositive);
    v("noise_mode", noise_mode, "random-walk scaling with dt", {"velocity", "per_step", "wiener"});
    v("sigma_p", sigma_p, "random-walk intensity (m/s, m or m/sqrt(s) by noise_mode)",
      kNonNegative);
    v("gamma", gamma, "width growth per step: w += gamma / (2 w) (m^2)", kNonNegative);
    v("dispersion", dispersion,
      "relative dispersion: paper (sigma_p, noise_mode, gamma) or farrell "
      "(relative_diffusivity, spread_rate)",
      {"paper", "farrell"});
    v("relative_diffusivity", relative_diffusivity,
      "dispersion = farrell: diffusivity of each filament centre's white-noise velocity (m^2/s)",
      NumberSpec{.min = 0.0, .max = 100.0});
    v("spread_rate", spread_rate,
      "dispersion = farrell: growth rate of a filament's squared width (m^2/s)",
      NumberSpec{.min = 0.0, .max = 100.0});
    v("lifetime", lifetime, "how filaments leave", {"ring", "leave_arena"});
    v("capacity", capacity, "ring-buffer size (filaments), lifetime = ring",
      IntegerSpec{1, kMaxCapacity}, capacity_auto);
    v("kernel", kernel, "concentration kernel", {"gaussian", "printed"});
    v("cutoff", cutoff, "filaments farther than this contribute nothing (m, may be inf)",
      NumberSpec{.min = 0.0, .min_open = true, .allow_infinite = true});
  }
};

/// The parameters of a preset.
PlumeParams plume_preset(PlumePreset preset);

/// Standard deviation (m) of one random-walk component per step.
double walk_stddev(const PlumeParams& params, double dt);

/// How much one step of dt (s) widens a filament: gamma (m^2) of w += gamma / (2 w) for the
/// paper's dispersion, rate dt (m^2) of w = sqrt(w^2 + rate dt) for Farrell's.
double width_growth(const PlumeParams& params, double dt);

/// Concentration contributed by one filament of width w (m) at squared distance d2 (m^2).
double kernel_value(const PlumeParams& params, double w, double d2);

/// The distance (m) within which one filament of width w (m) contributes at least `floor` (> 0):
/// kernel_value is below `floor` beyond it; 0 when even its peak is below, at most the cut-off.
double kernel_reach(const PlumeParams& params, double w, double floor);

}  // namespace plumetrace
