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
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// The supervisor's verdict on a robot state at run time t (s): success, wall, timeout or running.
Outcome supervise(const Scenario& scenario, const RobotState& robot, double t);

/// The robot side of one run: robot, sensors, controller and metrics, in an environment that
/// is stepped outside it. Its sensors read that environment's own wind and odor objects; robots
/// do not disturb the environment, so several Agents can share one.
class Agent {
 public:
  /// An agent of the scenario with its random streams from (seed, trial), at its start pose, its
  /// sensors bound to `env` (which must outlive it).
  Agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
        std::unique_ptr<Controller> controller, const Environment& env);
  Agent(const Agent&) = delete;
  Agent& operator=(const Agent&) = delete;

  /// Releases the robot into the environment as it is now (after the warm-up).
  void release();
  /// The first half of a step, after the environment has made its own: sense, then the
  /// controller's decision. Follow with act().
  Command decide();
  /// Sensing alone, for callers that decide outside a Controller (learning agents): what a
  /// controller would see. Follow with act().
  Observation sense();
  /// The second half of a step: the decision (headings in the odometry frame), then move and
  /// check.
  void act(Command command);
  /// The wind sensor, for a decision made outside a Controller (one noisy sample per call).
  WindProbe& wind_probe() { return wind_sensor_; }

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
  const Environment& env_;
  RobotState robot_;
  Rng wind_rng_;
  WindSensor wind_sensor_;
  std::unique_ptr<Controller> controller_;
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

/// The environment of a scenario and trial (its wind and its filament plume, each with its own
/// random stream), before its warm-up.
Environment make_environment(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial);

/// Runs an environment alone for the scenario's warm-up (sim.warmup, in steps of sim.dt).
void warm_up(const Scenario& scenario, Environment& env);

/// One run's whole state: one environment and the agents in it (one for a run, several for
/// robots that share a plume). A fresh World per run; it is neither copied nor moved, because
/// its agents' sensors hold references into it.
class World {
 public:
  /// A run of the scenario's algorithm, warmed up and ready for its first step; random streams
  /// from (seed, trial).
  World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial);
  /// A run driven by a given controller (the extension point for custom algorithms), warmed up.
  World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
        std::unique_ptr<Controller> controller);
  /// A run in a given environment (the extension point for other wind or odor models), warmed
  /// up for the scenario's sim.warmup.
  World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
        std::unique_ptr<Controller> controller, Environment env);
  /// One agent per scenario in one environment, the first scenario's, warmed up; the scenarios
  /// must agree on everything the environment depends on (`plume_key`, sweep.hpp). Each agent
  /// takes exactly the steps it would take alone.
  World(const std::vector<const Scenario*>& scenarios, std::uint64_t seed, std::uint64_t trial,
        const ControllerFactory& factory = {});
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// One step (docs/model.md section 2): the environment, then every running agent senses and
  /// decides, then every one moves and is checked. Does nothing once every agent is done.
  void step();
  /// A step of a one-agent world split for a decision made outside the controller: the
  /// environment and sensing ...
  Observation observe();
  /// ... then the decision, move and check (see Agent::sense, Agent::act).
  void act(const Command& command) { agents_.front()->act(command); }
  /// The wind sensor of agent 0, for a decision made outside the controller.
  WindProbe& wind_probe() { return agents_.front()->wind_probe(); }
  /// True once every agent's run has ended.
  bool done() const;
  /// Agent 0's metrics so far.
  RunResult result() const { return agents_.front()->result(); }
  /// Every agent's metrics so far, in the order of the scenarios.
  std::vector<RunResult> results() const;

  /// The number of agents.
  std::size_t agent_count() const { return agents_.size(); }
  /// Agent i.
  const Agent& agent(std::size_t i) const { return *agents_.at(i); }
  /// The environment.
  const Environment& environment() const { return env_; }

  /// Agent 0's time since release (s).
  double time() const { return agents_.front()->time(); }
  /// Agent 0's scenario.
  const Scenario& scenario() const { return agents_.front()->scenario(); }
  /// Agent 0's robot's true state.
  const RobotState& robot() const { return agents_.front()->robot(); }
  /// Agent 0's controller.
  const Controller& controller() const { return agents_.front()->controller(); }
  /// Agent 0's wind sensor (samples taken this step).
  const WindSensor& wind_sensor() const { return agents_.front()->wind_sensor(); }
  /// Odor perceived by agent 0 at the last step.
  bool odor() const { return agents_.front()->odor(); }
  /// Concentration at agent 0's odor sensor at the last step (computed on demand, for traces).
  double concentration() const { return env_.odor->concentration(agents_.front()->sensed_at()); }
  /// How agent 0's run ended (kRunning while it goes on).
  Outcome outcome() const { return agents_.front()->outcome(); }

 private:
  void add_agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                 std::unique_ptr<Controller> controller);
  void start(const Scenario& scenario);

  Environment env_;
  double dt_;
  std::vector<std::unique_ptr<Agent>> agents_;
  std::vector<Command> commands_;  // this step's decisions, one per agent
};

/// Called after the warm-up and after every step of a run.
using StepObserver = std::function<void(const World&)>;

/// Runs one whole run: a pure function of (scenario, seed, trial) and the controller factory
/// (empty: the scenario's built-in algorithm).
RunResult run_once(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                   const StepObserver& observer = {}, const ControllerFactory& factory = {});

}  // namespace plumetrace
