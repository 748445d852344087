#include "plumetrace/env/environment.hpp"

namespace plumetrace {

void step(Environment& env, double dt) {
  env.wind->step(dt);
  env.odor->step(*env.wind, dt);
  env.time += dt;
}

}  // namespace plumetrace
