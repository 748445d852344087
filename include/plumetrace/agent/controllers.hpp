#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/controllers/casting.hpp"
#include "plumetrace/agent/controllers/surge_cast.hpp"
#include "plumetrace/agent/controllers/surge_spiral.hpp"

namespace plumetrace {

/// The built-in algorithms.
enum class Algorithm { kCasting, kSurgeSpiral, kSurgeCast };

/// Which algorithm runs, and the parameters of each.
struct ControllerParams {
  /// Algorithm driving the robot.
  Algorithm algorithm = Algorithm::kCasting;
  /// Casting parameters.
  CastingParams casting;
  /// Surge-spiral parameters.
  SurgeSpiralParams surge_spiral;
  /// Surge-cast parameters.
  SurgeCastParams surge_cast;
};

/// Name of an algorithm as written in configs and on the command line.
std::string_view algorithm_name(Algorithm algorithm);

/// Every algorithm, in declaration order.
const std::vector<Algorithm>& all_algorithms();

/// Builds the controller of the selected algorithm with its random stream.
std::unique_ptr<Controller> make_controller(const ControllerParams& params, Rng rng);

}  // namespace plumetrace
