#pragma once

#include <memory>

#include "plumetrace/env/odor.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// Everything in a run that the robots do not change: the wind, the odor it carries, and their
/// common clock. Every reader (the odor model, each robot's sensors) holds the same objects.
struct Environment {
  std::unique_ptr<WindField> wind;  ///< the air
  std::unique_ptr<OdorField> odor;  ///< the odor, moved by `wind`
  double time = 0.0;                ///< time since the environment was built (s), warm-up included
};

/// Advances the environment by dt (s): the wind, then the odor in the new wind, then the clock.
/// The one place an environment advances.
void step(Environment& env, double dt);

}  // namespace plumetrace
