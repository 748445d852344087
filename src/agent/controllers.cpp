#include "plumetrace/agent/controllers.hpp"

#include <array>

namespace plumetrace {

namespace {

struct Registration {
  Algorithm algorithm;
  std::string_view name;
  std::unique_ptr<Controller> (*make)(const ControllerParams&, Rng);
};

// why: the one registration line per algorithm; names, order and factories all come from here
constexpr std::array kRegistry{
    Registration{Algorithm::kCasting, "casting",
                 [](const ControllerParams& p, Rng rng) -> std::unique_ptr<Controller> {
                   return std::make_unique<Casting>(p.casting, rng);
                 }},
    Registration{Algorithm::kSurgeSpiral, "surge-spiral",
                 [](const ControllerParams& p, Rng rng) -> std::unique_ptr<Controller> {
                   return std::make_unique<SurgeSpiral>(p.surge_spiral, rng);
                 }},
    Registration{Algorithm::kSurgeCast, "surge-cast",
                 [](const ControllerParams& p, Rng rng) -> std::unique_ptr<Controller> {
                   return std::make_unique<SurgeCast>(p.surge_cast, rng);
                 }},
};

const Registration& registration(Algorithm algorithm) {
  for (const auto& r : kRegistry) {
    if (r.algorithm == algorithm) return r;
  }
  return kRegistry.front();
}

}  // namespace

std::string_view algorithm_name(Algorithm algorithm) { return registration(algorithm).name; }

const std::vector<Algorithm>& all_algorithms() {
  static const std::vector<Algorithm> all = [] {
    std::vector<Algorithm> v;
    for (const auto& r : kRegistry) v.push_back(r.algorithm);
    return v;
  }();
  return all;
}

std::unique_ptr<Controller> make_controller(const ControllerParams& params, Rng rng) {
  return registration(params.algorithm).make(params, rng);
}

}  // namespace plumetrace
