#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/registry.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

/// Which wind field a scenario uses: its place in wind_field_registry(). The built-ins are named
/// here, in the order they are registered.
enum class WindModel { kConstant, kMeander, kSwitching };

/// The names of the registered wind fields, in registry order: the choices of wind.model.
Choices wind_model_names();

/// The rectangle a wind field covers (m): the arena's walls, handed over by the sim layer
/// (make_environment), so that a field with a grid knows where it lies.
struct WindRegion {
  double x_min;  ///< upwind edge (m)
  double x_max;  ///< downwind edge (m)
  double y_min;  ///< right-hand edge (m)
  double y_max;  ///< left-hand edge (m)
};

/// Where and when a wind field runs: what it is built from and its params are checked against
/// besides their own ranges (WindHooks::check). The sim layer makes it from a scenario
/// (wind_context, sim/scenario.hpp).
struct WindContext {
  Vec3 mean;             ///< the mean wind: wind.vx, wind.vy, wind.vz (m/s)
  WindRegion region;     ///< the region the field covers: the arena (m)
  double dt;             ///< the time step it is advanced by: sim.dt (s)
  double release = 0.0;  ///< when the robots are released, on the field's clock: sim.warmup (s)
};

/// What a wind field's registration carries besides its factory (Registry::Entry::hooks), so
/// that scenario, sweep and trace code ask the registry instead of knowing the model. Each may
/// be empty; wind_hooks<Model, Params>() fills them from the model's static members.
struct WindHooks {
  /// Refuses params (an AnyParams holding the model's params struct) with which the field
  /// cannot run in `context`, throwing ConfigError naming the keys. Empty: every combination of
  /// the keys within their ranges runs.
  void (*check)(const AnyParams& params, const WindContext& context) = nullptr;
  /// True when the field made from `params` is the mean wind, exactly, at every point and always
  /// (a trace that did not record the true wind then knows it). Empty: never.
  bool (*steady)(const AnyParams& params) = nullptr;
  /// What the field depends on besides its keys and the mean wind, as text (`name=value`
  /// lines): the region for a field with a grid over it, a data file's contents. The
  /// plume-sharing key hashes it (plume_key). Empty: nothing, the field is the same over any
  /// region.
  std::string (*identity)(const AnyParams& params, const WindRegion& region) = nullptr;
};

/// A wind field: the air velocity at every point, now. The field carries its own state and time
/// and advances through step(), so every reader (the plume, each wind sensor) of one field sees
/// the same air.
class WindField {
 public:
  /// What a wind field's registration carries besides its factory.
  using Hooks = WindHooks;

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

/// The constant wind's params: none besides the mean wind (wind.vx, wind.vy, wind.vz), which
/// every wind field has.
struct ConstantWindParams {
  /// The config keys (core/config.hpp): none.
  template <class V>
  void fields(V&) {}
};

/// Laminar wind with the same velocity everywhere and always (paper eq. 1).
class ConstantWind final : public WindField {
 public:
  /// Builds the field from its velocity (m/s).
  explicit ConstantWind(const Vec3& velocity) : velocity_(velocity) {}
  /// Builds the field from a scenario's wind: the mean wind (m/s); a constant wind never draws
  /// from its stream.
  ConstantWind(const ConstantWindParams&, const WindContext& context, Rng)
      : velocity_(context.mean) {}
  /// Nothing changes.
  void step(double) override {}
  Vec3 velocity(const Vec3&) const override { return velocity_; }
  bool uniform_in_space() const override { return true; }

  /// Always the mean wind (WindHooks::steady).
  static bool steady(const ConstantWindParams&) { return true; }

 private:
  Vec3 velocity_;
};

/// The hooks of wind field Model with params struct Params: each from Model's static member of
/// the same name where it has one (`check(const Params&, const WindContext&)`,
/// `steady(const Params&)`, `identity(const Params&, const WindRegion&)`), else empty: the
/// model declares what it knows of itself next to its code, its registration line hands it over.
template <class Model, class Params>
WindHooks wind_hooks() {
  WindHooks hooks;
  if constexpr (requires(const Params& p, const WindContext& c) { Model::check(p, c); }) {
    hooks.check = [](const AnyParams& p, const WindContext& c) {
      Model::check(p.get<Params>(), c);
    };
  }
  if constexpr (requires(const Params& p) { Model::steady(p); }) {
    hooks.steady = [](const AnyParams& p) -> bool { return Model::steady(p.get<Params>()); };
  }
  if constexpr (requires(const Params& p, const WindRegion& r) { Model::identity(p, r); }) {
    hooks.identity = [](const AnyParams& p, const WindRegion& r) -> std::string {
      return Model::identity(p.get<Params>(), r);
    };
  }
  return hooks;
}

/// The wind fields, chosen by wind.model: each made from its own params, its context (the mean
/// wind, the region it covers, its time step and the robots' release) and its own random stream
/// (Stream::kWind).
using WindRegistry = Registry<WindField, const WindContext&, Rng>;

/// The registered wind fields (src/env/models.cpp: one line each).
WindRegistry& wind_field_registry();

/// Parameters of the wind field: which one, the mean wind, and the params of every registered
/// field, each in its own table (`wind.model = "meander"`, `[meander] gain = ...`).
struct WindParams {
  /// Which field.
  WindModel model = WindModel::kConstant;
  /// Constant wind velocity (m/s); paper eq. 1; the mean of every wind field. why: 1, the
  /// paper's "constant wind field of 1 m/s" (docs/fidelity.md, unknown 9 and "Which reading won").
  Vec3 velocity{1.0, 0.0, 0.0};
  /// The params of every registered wind field; each its defaults until written.
  FamilyParams<WindRegistry> params;

  /// The params struct P (MeanderParams, ...) of its wind field.
  template <class P>
  P& get() {
    return params.get<P>(wind_field_registry());
  }
  /// The params struct P (MeanderParams, ...) of its wind field.
  template <class P>
  const P& get() const {
    return params.get<P>(wind_field_registry());
  }

  /// The config keys: "model", "vx", "vy", "vz", then the table of every registered wind field
  /// with its keys.
  void fields(FieldVisitor& v);
  /// Reads the config keys without writing.
  void read_fields(FieldReader& v) const;
};

/// Builds the wind field a scenario asks for in `context` (whose mean is params.velocity; the
/// sim layer's wind_context makes both from one scenario); `rng` is its own random stream
/// (Stream::kWind), which a constant wind never draws from. Throws std::invalid_argument for a
/// model not registered.
std::unique_ptr<WindField> make_wind_field(const WindParams& params, const WindContext& context,
                                           Rng rng);

/// Refuses a wind that its field cannot run in `context` (whose mean is params.velocity): the
/// field's check hook, where it has one. Throws ConfigError naming the keys.
void check_wind_field(const WindParams& params, const WindContext& context);

/// True when the chosen field is the mean wind, exactly, at every point and always (its steady
/// hook).
bool wind_is_steady(const WindParams& params);

/// What the chosen field depends on besides its keys and the mean wind, over `region` (its
/// identity hook): text, empty for nothing.
std::string wind_identity(const WindParams& params, const WindRegion& region);

}  // namespace plumetrace
