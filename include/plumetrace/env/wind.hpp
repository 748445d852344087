#pragma once

#include <memory>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/registry.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

/// Which wind field a scenario uses: its place in wind_field_registry(). The built-ins are named
/// here, in the order they are registered.
enum class WindModel { kConstant };

/// The names of the registered wind fields, in registry order: the choices of wind.model.
Choices wind_model_names();

/// Parameters of the wind field.
struct WindParams {
  /// Which field.
  WindModel model = WindModel::kConstant;
  /// Constant wind velocity (m/s); paper eq. 1. why: 0.9, the plugin's hard-coded wind, not
  /// the printed 1 (docs/fidelity.md, unknown 9).
  Vec3 velocity{0.9, 0.0, 0.0};

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("model", model, "wind field", wind_model_names());
    v("vx", velocity.x, "constant wind velocity, x component (m/s)", kAnyNumber);
    v("vy", velocity.y, "constant wind velocity, y component (m/s)", kAnyNumber);
    v("vz", velocity.z, "constant wind velocity, z component (m/s)", kAnyNumber);
  }
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
};

/// Laminar wind with the same velocity everywhere and always (paper eq. 1).
class ConstantWind final : public WindField {
 public:
  /// Builds the field from its velocity (m/s).
  explicit ConstantWind(const Vec3& velocity) : velocity_(velocity) {}
  /// Builds the field from a scenario's wind; a constant wind never draws from its stream.
  ConstantWind(const WindParams& params, Rng) : velocity_(params.velocity) {}
  /// Nothing changes.
  void step(double) override {}
  Vec3 velocity(const Vec3&) const override { return velocity_; }
  bool uniform_in_space() const override { return true; }

 private:
  Vec3 velocity_;
};

/// The wind fields, chosen by wind.model: made from the scenario's WindParams and the field's own
/// random stream (Stream::kWind).
using WindRegistry = Registry<WindField, Rng>;

/// The registered wind fields (src/env/models.cpp: one line each).
WindRegistry& wind_field_registry();

/// Builds the wind field a scenario asks for; `rng` is its own random stream (Stream::kWind),
/// which a constant wind never draws from.
std::unique_ptr<WindField> make_wind_field(const WindParams& params, Rng rng);

}  // namespace plumetrace
