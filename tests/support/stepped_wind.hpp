#pragma once

#include "plumetrace/env/wind.hpp"

namespace plumetrace::testing {

/// A uniform wind that blows 0.1 m/s harder after every step (0.5 m/s before the first), so that
/// a reading tells which step the field is at; counts its steps.
class SteppedWind final : public WindField {
 public:
  void step(double) override { ++steps; }
  Vec3 velocity(const Vec3&) const override { return {0.5 + 0.1 * steps, 0.0, 0.0}; }
  bool uniform_in_space() const override { return true; }
  int steps = 0;
};

}  // namespace plumetrace::testing
