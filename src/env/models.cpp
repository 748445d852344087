// The environment's registries: every wind field and odor model, one line each.
#include <stdexcept>
#include <string>

#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/env/odor.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

WindRegistry& wind_field_registry() {
  // why: listed here rather than registered from their own sources, because a static library
  // leaves out the objects nothing refers to; in the order of WindModel
  static WindRegistry registry = [] {
    WindRegistry r;
    r.add<ConstantWind, WindParams>("constant");
    r.add<MeanderWind, WindParams>("meander");
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

std::unique_ptr<WindField> make_wind_field(const WindParams& params, const WindRegion& region,
                                           Rng rng) {
  const WindRegistry& registry = wind_field_registry();
  const auto i = static_cast<std::size_t>(params.model);
  return registry[i < registry.size() ? i : 0].make(AnyParams(params), region, rng);
}

std::unique_ptr<OdorField> make_odor_field(std::string_view name, const PlumeParams& params,
                                           const SourceParams& source, double removal_x,
                                           std::uint64_t seed) {
  const OdorRegistry& registry = odor_field_registry();
  const std::size_t i = registry.find(name);
  if (i == registry.size()) {
    throw std::invalid_argument("unknown odor model '" + std::string(name) + "'");
  }
  return registry[i].make(AnyParams(params), source, removal_x, seed);
}

}  // namespace plumetrace
