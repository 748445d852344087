#include "plumetrace/env/wind.hpp"

namespace plumetrace {

std::unique_ptr<WindField> make_wind_field(const WindParams& params) {
  switch (params.model) {
    case WindModel::kConstant:
      return std::make_unique<ConstantWind>(params.velocity);
  }
  return nullptr;
}

}  // namespace plumetrace
