#pragma once
// A controller that shows its state (Controller::snapshot), for the tests of traces and the
// viewer: it drives straight ahead and, after a while, declares the source where it believes it.

#include <cmath>
#include <memory>
#include <string_view>
#include <utility>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace::testing {

/// A snapshot of every layer, in the odometry frame, with numbers easy to move by hand: three
/// weighted points, a path of three vertices, a grid of 3 by 2 cells and an estimate.
inline Snapshot every_layer() {
  Snapshot s;
  s.points = {{1.0, 0.0}, {0.0, 2.0}, {3.0, -1.0}};
  s.weights = {1.0, 3.0, 2.0};
  s.path = {{0.0, 0.0}, {1.0, 1.0}, {2.0, 1.0}};
  s.x0 = 0.5, s.y0 = -1.0, s.dx = 0.5, s.dy = 1.0, s.nx = 3, s.ny = 2;
  s.grid = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0};
  s.has_estimate = true;
  s.estimate = {2.0, -1.0};
  return s;
}

/// A belief about the source `ahead` metres ahead of the release (odometry frame): a grid of 24
/// by 10 cells of 0.4 m with a bump there, 150 particles around it weighted by their distance,
/// the path from the robot to it, and the estimate; what a viewer draws.
inline Snapshot belief_ahead(const Pose& odometry, double ahead) {
  Snapshot s;
  const Vec2 at{ahead, 0.3};
  s.x0 = ahead - 6.0, s.y0 = -1.8, s.dx = 0.4, s.dy = 0.4, s.nx = 24, s.ny = 10;
  for (int j = 0; j < s.ny; ++j) {
    for (int i = 0; i < s.nx; ++i) {
      const double x = s.x0 + i * s.dx - at.x, y = s.y0 + j * s.dy - at.y;
      s.grid.push_back(std::exp(-(x * x / 8.0 + y * y / 0.8)));
    }
  }
  for (int k = 0; k < 150; ++k) {
    // a sunflower spiral: the particles fill a disc of 1.2 m evenly
    const double r = 1.2 * std::sqrt((k + 0.5) / 150.0), a = 2.39996 * k;
    s.points.push_back({at.x + r * std::cos(a), at.y + r * std::sin(a)});
    s.weights.push_back(std::exp(-r * r / 0.3));
  }
  s.path = {{odometry.x, odometry.y}, {0.5 * (odometry.x + at.x), odometry.y}, at};
  s.has_estimate = true;
  s.estimate = at;
  return s;
}

/// Drives straight ahead (its odometry's heading 0) for `steps` steps, then declares the source at
/// its estimate; its snapshot is `every_layer()` (fixed) or `belief_ahead` (following it).
class SnapshotController final : public Controller {
 public:
  SnapshotController(long steps, bool fixed, double ahead)
      : steps_(steps), fixed_(fixed), ahead_(ahead) {}
  Command step(const Observation& obs, WindProbe&) override {
    odometry_ = obs.odometry;
    if (++taken_ > steps_) return Command::declare_source(snapshot().estimate);
    return Command::go(0.0);
  }
  std::string_view state() const override { return "believing"; }
  int losses() const override { return 0; }
  Snapshot snapshot() const override {
    return fixed_ ? every_layer() : belief_ahead(odometry_, ahead_);
  }

 private:
  long steps_;
  bool fixed_;
  double ahead_;
  long taken_ = 0;
  Pose odometry_;
};

/// Every robot's controller a SnapshotController; robot k declares after `steps` + 40 k steps.
inline ControllerFactory snapshot_controllers(long steps, bool fixed, double ahead = 12.0) {
  auto made = std::make_shared<long>(0);
  return [=](const Scenario&, Rng) -> std::unique_ptr<Controller> {
    return std::make_unique<SnapshotController>(steps + 40 * (*made)++, fixed, ahead);
  };
}

}  // namespace plumetrace::testing
