#include "plumetrace/controllers.hpp"

namespace plumetrace {

std::string_view algorithm_name(Algorithm algorithm) {
  switch (algorithm) {
    case Algorithm::kCasting:
      return "casting";
    case Algorithm::kSurgeSpiral:
      return "surge-spiral";
    case Algorithm::kSurgeCast:
      return "surge-cast";
  }
  return "";
}

const std::vector<Algorithm>& all_algorithms() {
  static const std::vector<Algorithm> all{Algorithm::kCasting, Algorithm::kSurgeSpiral,
                                          Algorithm::kSurgeCast};
  return all;
}

std::unique_ptr<Controller> make_controller(const ControllerParams& params, Rng rng) {
  switch (params.algorithm) {
    case Algorithm::kCasting:
      return std::make_unique<Casting>(params.casting, rng);
    case Algorithm::kSurgeSpiral:
      return std::make_unique<SurgeSpiral>(params.surge_spiral, rng);
    case Algorithm::kSurgeCast:
      return std::make_unique<SurgeCast>(params.surge_cast, rng);
  }
  return nullptr;
}

}  // namespace plumetrace
