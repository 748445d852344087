// The environment's registries: every wind field and odor model, one line each.
#include <stdexcept>
#include <string>

#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/env/odor.hpp"
#include "plumetrace/env/switching_wind.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

namespace {

constexpr std::string_view kWindModelHelp = "wind field";
constexpr std::string_view kVxHelp = "constant (or mean) wind velocity, x component (m/s)";
constexpr std::string_view kVyHelp = "constant (or mean) wind velocity, y component (m/s)";
constexpr std::string_view kVzHelp = "constant (or mean) wind velocity, z component (m/s)";

// the chosen wind field's entry and its params; throws for a model no entry has
struct Chosen {
  const WindRegistry::Entry& entry;
  const AnyParams& params;
};
Chosen chosen(const WindParams& params) {
  const WindRegistry& registry = wind_field_registry();
  const auto i = static_cast<std::size_t>(params.model);
  return {registry.at(i, "wind model"), params.params.at(registry, i)};
}

}  // namespace

WindRegistry& wind_field_registry() {
  // why: listed here rather than registered from their own sources, because a static library
  // leaves out the objects nothing refers to; in the order of WindModel. Names, choices, tables,
  // factories and hooks all come from here
  static WindRegistry registry = [] {
    WindRegistry r;
    r.add<ConstantWind, ConstantWindParams>("constant",
                                            wind_hooks<ConstantWind, ConstantWindParams>());
    r.add<MeanderWind, MeanderParams>("meander", wind_hooks<MeanderWind, MeanderParams>());
    r.add<SwitchingWind, SwitchingParams>("switching",
                                          wind_hooks<SwitchingWind, SwitchingParams>());
    return r;
  }();
  return registry;
}

OdorRegistry& odor_field_registry() {
  static OdorRegistry registry = [] {
    OdorRegistry r;
    r.add<FilamentPlume, PlumeParams>("filament");
    return r;
  }();
  return registry;
}

Choices wind_model_names() { return wind_field_registry().names(); }

Choices odor_model_names() { return odor_field_registry().names(); }

void WindParams::fields(FieldVisitor& v) {
  const WindRegistry& registry = wind_field_registry();
  v("model", model, kWindModelHelp, registry.names());
  v("vx", velocity.x, kVxHelp, kAnyNumber);
  v("vy", velocity.y, kVyHelp, kAnyNumber);
  v("vz", velocity.z, kVzHelp, kAnyNumber);
  params.fields(registry, v);
}

void WindParams::read_fields(FieldReader& v) const {
  const WindRegistry& registry = wind_field_registry();
  // why: a FieldReader never writes through the references; the params are read without
  // writing (FamilyParams::fields would fill their slots)
  auto& visit = static_cast<FieldVisitor&>(v);
  auto& self = const_cast<WindParams&>(*this);
  visit("model", self.model, kWindModelHelp, registry.names());
  visit("vx", self.velocity.x, kVxHelp, kAnyNumber);
  visit("vy", self.velocity.y, kVyHelp, kAnyNumber);
  visit("vz", self.velocity.z, kVzHelp, kAnyNumber);
  params.read_fields(registry, v);
}

std::unique_ptr<WindField> make_wind_field(const WindParams& params, const WindContext& context,
                                           Rng rng) {
  const auto [entry, own] = chosen(params);
  return entry.make(own, context, rng);
}

void check_wind_field(const WindParams& params, const WindContext& context) {
  const auto [entry, own] = chosen(params);
  if (entry.hooks.check) entry.hooks.check(own, context);
}

bool wind_is_steady(const WindParams& params) {
  const auto [entry, own] = chosen(params);
  return entry.hooks.steady && entry.hooks.steady(own);
}

std::string wind_identity(const WindParams& params, const WindRegion& region) {
  const auto [entry, own] = chosen(params);
  return entry.hooks.identity ? entry.hooks.identity(own, region) : std::string();
}

std::unique_ptr<OdorField> make_odor_field(std::string_view name, const PlumeParams& params,
                                           const SourceParams& source, double removal_x,
                                           std::uint64_t seed) {
  return odor_field_registry()
      .at(name, "odor model")
      .make(AnyParams(params), source, removal_x, seed);
}

}  // namespace plumetrace
