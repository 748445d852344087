#pragma once

#include <cstddef>
#include <memory>
#include <span>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/registry.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

/// Which wind field a scenario uses: its place in wind_field_registry(). The built-ins are named
/// here, in the order they are registered.
enum class WindModel { kConstant, kMeander };

/// The names of the registered wind fields, in registry order: the choices of wind.model.
Choices wind_model_names();

/// The meandering wind's perturbation (wind.model = "meander", Farrell et al. 2002; docs/model.md
/// section 3.1). Defaults: the `meander-strong` scenario (scenarios/meander-strong.toml).
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
};

/// Parameters of the wind field.
struct WindParams {
  /// Which field.
  WindModel model = WindModel::kConstant;
  /// Constant wind velocity (m/s); paper eq. 1; the mean of a meandering wind. why: 1, the
  /// paper's "constant wind field of 1 m/s" (docs/fidelity.md, unknown 9 and "Which reading won").
  Vec3 velocity{1.0, 0.0, 0.0};
  /// The meandering wind's perturbation (model "meander").
  MeanderParams meander;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("model", model, "wind field", wind_model_names());
    v("vx", velocity.x, "constant (or mean) wind velocity, x component (m/s)", kAnyNumber);
    v("vy", velocity.y, "constant (or mean) wind velocity, y component (m/s)", kAnyNumber);
    v("vz", velocity.z, "constant (or mean) wind velocity, z component (m/s)", kAnyNumber);
    v("meander_gain", meander.gain,
      "meander: gain G of the boundary noise (m/s^0.5); 0: the constant wind",
      NumberSpec{.min = 0.0, .max = 10.0});
    v("meander_damping", meander.damping, "meander: damping ratio zeta of the boundary noise",
      NumberSpec{.min = 0.0, .max = 10.0, .min_open = true});
    v("meander_bandwidth", meander.bandwidth,
      "meander: bandwidth omega of the boundary noise (rad/s)",
      NumberSpec{.min = 0.0, .max = 100.0, .min_open = true});
    v("meander_kx", meander.kx, "meander: diffusivity K_x of the wind grid (m^2/s)",
      NumberSpec{.min = 0.0, .max = 1000.0, .min_open = true});
    v("meander_ky", meander.ky, "meander: diffusivity K_y of the wind grid (m^2/s)",
      NumberSpec{.min = 0.0, .max = 1000.0, .min_open = true});
    v("meander_nx", meander.nx, "meander: wind grid nodes along x, walls included",
      IntegerSpec{2, 201});
    v("meander_ny", meander.ny, "meander: wind grid nodes along y, walls included",
      IntegerSpec{2, 201});
  }
};

/// The rectangle a wind field covers (m): the arena's walls, handed over by the sim layer
/// (make_environment), so that a field with a grid knows where it lies.
struct WindRegion {
  double x_min;  ///< upwind edge (m)
  double x_max;  ///< downwind edge (m)
  double y_min;  ///< right-hand edge (m)
  double y_max;  ///< left-hand edge (m)
};

/// A wind field: the air velocity at every point, now. The field carries its own state and time
/// and advances through step(), so every reader (the plume, each wind sensor) of one field sees
/// the same air.
class WindField {
 public:
  virtual ~WindField() = default;
  /// Advances the field by dt (s).
  virtual void step(double dt) = 0;
  /// Air velocity (m/s) at point p (m), at the field's current time.
  virtual Vec3 velocity(const Vec3& p) const = 0;
  /// True when the velocity is the same at every point (lets the plume query it once per step).
  virtual bool uniform_in_space() const { return false; }
  /// Moves each point i, in index order, by the velocity there times dt (s):
  /// x[i] += velocity(p_i).x * dt, and so on; the spans have equal sizes. A field may do it with
  /// a faster loop of its own, giving the same bits.
  virtual void advect(std::span<double> x, std::span<double> y, std::span<double> z,
                      double dt) const {
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Vec3 a = velocity({x[i], y[i], z[i]});
      x[i] += a.x * dt;
      y[i] += a.y * dt;
      z[i] += a.z * dt;
    }
  }
};

/// Laminar wind with the same velocity everywhere and always (paper eq. 1).
class ConstantWind final : public WindField {
 public:
  /// Builds the field from its velocity (m/s).
  explicit ConstantWind(const Vec3& velocity) : velocity_(velocity) {}
  /// Builds the field from a scenario's wind; a constant wind never draws from its stream.
  ConstantWind(const WindParams& params, const WindRegion&, Rng) : velocity_(params.velocity) {}
  /// Nothing changes.
  void step(double) override {}
  Vec3 velocity(const Vec3&) const override { return velocity_; }
  bool uniform_in_space() const override { return true; }

 private:
  Vec3 velocity_;
};

/// The wind fields, chosen by wind.model: made from the scenario's WindParams, the region it
/// covers (the arena) and the field's own random stream (Stream::kWind).
using WindRegistry = Registry<WindField, const WindRegion&, Rng>;

/// The registered wind fields (src/env/models.cpp: one line each).
WindRegistry& wind_field_registry();

/// Builds the wind field a scenario asks for over `region` (the arena); `rng` is its own random
/// stream (Stream::kWind), which a constant wind never draws from.
std::unique_ptr<WindField> make_wind_field(const WindParams& params, const WindRegion& region,
                                           Rng rng);

}  // namespace plumetrace
