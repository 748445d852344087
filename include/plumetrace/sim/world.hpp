#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/robot.hpp"
#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/wind.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// The supervisor's verdict on a robot state at run time t (s): success, wall, timeout or running.
Outcome supervise(const Scenario& scenario, const RobotState& robot, double t);

/// The robot side of one run: robot, sensors, controller and metrics, driven by a plume that
/// is stepped outside it. Robots do not disturb the plume, so several Agents can share one.
class Agent {
 public:
  /// An agent of the scenario with its random streams from (seed, trial), at its start pose.
  Agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
        std::unique_ptr<Controller> controller);
  Agent(const Agent&) = delete;
  Agent& operator=(const Agent&) = delete;

  /// Releases the robot into a plume warmed up for `warmup_time` seconds.
  void release(const Plume& plume, double warmup_time);
  /// One step after the plume has made its own: sense, decide, move, check (docs/model.md
  /// section 2).
  void step(const Plume& plume);
  /// The first half of a step, for callers that decide outside a Controller (learning agents):
  /// sense and return what a controller would see. Follow with act().
  Observation sense(const Plume& plume);
  /// The second half of a step: the decision (headings in the odometry frame), then move and
  /// check.
  void act(Command command);
  /// The wind sensor, for a decision made outside a Controller (one noisy sample per call).
  WindProbe& wind_probe() { return wind_sensor_; }
  /// Plume time (s) at which the plume's next step starts.
  double plume_time() const { return warmup_time_ + time(); }

  /// True once the run has ended.
  bool done() const { return outcome_ != Outcome::kRunning; }
  /// The run's metrics so far.
  RunResult result() const;
  /// Time since release (s).
  double time() const { return static_cast<double>(steps_) * scenario_.sim.dt; }
  /// The scenario in use.
  const Scenario& scenario() const { return scenario_; }
  /// The robot's true state.
  const RobotState& robot() const { return robot_; }
  /// The controller.
  const Controller& controller() const { return *controller_; }
  /// The wind sensor (samples taken this step).
  const WindSensor& wind_sensor() const { return wind_sensor_; }
  /// Odor perceived at the last step.
  bool odor() const { return odor_; }
  /// Where the odor sensor sampled the plume at the last step.
  const Vec3& sensed_at() const { return sensed_at_; }
  /// How the run ended (kRunning while it goes on).
  Outcome outcome() const { return outcome_; }

 private:
  Scenario scenario_;
  std::uint64_t seed_;
  std::uint64_t trial_;
  std::unique_ptr<WindField> wind_;
  RobotState robot_;
  Rng wind_rng_;
  WindSensor wind_sensor_;
  std::unique_ptr<Controller> controller_;
  double warmup_time_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t odor_steps_ = 0;
  Vec3 sensed_at_;
  bool odor_ = false;
  Outcome outcome_ = Outcome::kRunning;
};

/// Builds a run's controller from its scenario and its controller stream; the extension point
/// for controllers of your own (C++ or Python), used by runs and sweeps alike.
using ControllerFactory = std::function<std::unique_ptr<Controller>(const Scenario&, Rng)>;

/// The controller of run (seed, trial): `factory`'s when given, else the scenario's built-in
/// algorithm; either gets the run's controller stream.
std::unique_ptr<Controller> make_run_controller(const Scenario& scenario, std::uint64_t seed,
                                                std::uint64_t trial,
                                                const ControllerFactory& factory = {});

/// The plume of a scenario and trial, before its warm-up.
Plume make_plume(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial);

/// Runs a plume alone for the scenario's warm-up; returns the warm-up time (s).
double warm_up(const Scenario& scenario, const WindField& wind, Plume& plume);

/// One run's whole state: a plume and one agent. A fresh World per run; it is neither copied
/// nor moved.
class World {
 public:
  /// A run of the scenario's algorithm, warmed up and ready for its first step; random streams
  /// from (seed, trial).
  World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial);
  /// A run driven by a given controller (the extension point for custom algorithms), warmed up.
  World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
        std::unique_ptr<Controller> controller);
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// One step: environment, sense, decide, move, check (docs/model.md section 2).
  void step();
  /// A step split for a decision made outside the controller: environment and sense ...
  Observation observe();
  /// ... then the decision, move and check (see Agent::sense, Agent::act).
  void act(const Command& command) { agent_.act(command); }
  /// The wind sensor, for a decision made outside the controller.
  WindProbe& wind_probe() { return agent_.wind_probe(); }
  /// True once the run has ended.
  bool done() const { return agent_.done(); }
  /// The run's metrics so far.
  RunResult result() const { return agent_.result(); }

  /// Time since release (s).
  double time() const { return agent_.time(); }
  /// The scenario in use.
  const Scenario& scenario() const { return agent_.scenario(); }
  /// The plume.
  const Plume& plume() const { return plume_; }
  /// The wind field.
  const WindField& wind() const { return *wind_; }
  /// The robot's true state.
  const RobotState& robot() const { return agent_.robot(); }
  /// The controller.
  const Controller& controller() const { return agent_.controller(); }
  /// The wind sensor (samples taken this step).
  const WindSensor& wind_sensor() const { return agent_.wind_sensor(); }
  /// Odor perceived at the last step.
  bool odor() const { return agent_.odor(); }
  /// Concentration at the odor sensor at the last step (computed on demand, for traces).
  double concentration() const { return plume_.concentration(agent_.sensed_at()); }
  /// How the run ended (kRunning while it goes on).
  Outcome outcome() const { return agent_.outcome(); }

 private:
  std::unique_ptr<WindField> wind_;
  Plume plume_;
  Agent agent_;
};

/// Called after the warm-up and after every step of a run.
using StepObserver = std::function<void(const World&)>;

/// Runs one whole run: a pure function of (scenario, seed, trial) and the controller factory
/// (empty: the scenario's built-in algorithm).
RunResult run_once(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                   const StepObserver& observer = {}, const ControllerFactory& factory = {});

}  // namespace plumetrace
