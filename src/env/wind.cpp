#include "plumetrace/env/wind.hpp"

namespace plumetrace {

std::unique_ptr<WindField> make_wind_field(const WindParams& params, Rng rng) {
  (void)rng;  // why: the constant wind has no randomness; a gusting field would keep it
  switch (params.model) {
    case WindModel::kConstant:
      return std::make_unique<ConstantWind>(params.velocity);
  }
  return nullptr;
}

}  // namespace plumetrace
