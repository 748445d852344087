#pragma once

#include <memory>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"

namespace plumetrace {

/// Which wind field a scenario uses.
enum class WindModel { kConstant };

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
    v("model", model, "wind field", {"constant"});
    v("vx", velocity.x, "constant wind velocity, x component (m/s)", kAnyNumber);
    v("vy", velocity.y, "constant wind velocity, y component (m/s)", kAnyNumber);
    v("vz", velocity.z, "constant wind velocity, z component (m/s)", kAnyNumber);
  }
};

/// A wind field: answers "what is the air velocity at point p and time t".
class WindField {
 public:
  virtual ~WindField() = default;
  /// Air velocity (m/s) at point p (m) and time t (s).
  virtual Vec3 velocity(const Vec3& p, double t) const = 0;
  /// True when the velocity is the same at every point (lets the plume query it once per step).
  virtual bool uniform_in_space() const { return false; }
};

/// Laminar wind with the same velocity everywhere and always (paper eq. 1).
class ConstantWind final : public WindField {
 public:
  /// Builds the field from its velocity (m/s).
  explicit ConstantWind(const Vec3& velocity) : velocity_(velocity) {}
  Vec3 velocity(const Vec3&, double) const override { return velocity_; }
  bool uniform_in_space() const override { return true; }

 private:
  Vec3 velocity_;
};

/// Builds the wind field a scenario asks for.
std::unique_ptr<WindField> make_wind_field(const WindParams& params);

}  // namespace plumetrace
