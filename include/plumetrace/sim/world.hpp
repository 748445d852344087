#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/robot.hpp"
#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace {

/// The supervisor's verdict on a robot state at run time t (s): success, wall, timeout or
/// running, under the scenario's supervisor.success and supervisor.walls rules (a declaration is
/// scored apart, by Agent).
Outcome supervise(const Scenario& scenario, const RobotState& robot, double t);

/// The robot side of one run: robot, sensors, controller and metrics, in an environment that
/// is stepped outside it. Its sensors read that environment's own wind and odor objects; robots
/// do not disturb the environment, so several Agents can share one. Agent `index` of a team has
/// its own random streams (derive_seed with the agent index: agent 0 draws what a robot alone
/// always drew).
class Agent {
 public:
  /// Agent `index` of the scenario's team with its random streams from (seed, trial, index), its
  /// sensors bound to `env` (which must outlive it).
  Agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial, int index,
        std::unique_ptr<Controller> controller, const Environment& env);
  /// Agent 0 (a robot alone).
  Agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
        std::unique_ptr<Controller> controller, const Environment& env)
      : Agent(scenario, seed, trial, 0, std::move(controller), env) {}
  Agent(const Agent&) = delete;
  Agent& operator=(const Agent&) = delete;

  /// Releases the robot at `start` (m, rad) into the environment as it is now (after the
  /// warm-up); its odometry frame is that pose.
  void release(const Pose& start);
  /// Releases the robot at the scenario's start (robot.start_x, _y, _heading_deg).
  void release() { release(scenario_.robot.start); }
  /// The first half of a step, after the environment has made its own: sense, then the
  /// controller's decision. Follow with act(), or propose() and commit().
  Command decide();
  /// Sensing alone, for callers that decide outside a Controller (learning agents): what a
  /// controller would see, the concentration included when `reads` asks for it. Follow with
  /// act().
  Observation sense(unsigned reads);
  /// Sensing with what the controller reads.
  Observation sense() { return sense(reads_); }
  /// The second half of a step: the decision (headings in the odometry frame), then move and
  /// check. propose() then commit().
  void act(const Command& command) {
    propose(command);
    commit();
  }
  /// The motion of a command, not yet made: a give-up or a declaration ends the run here; a
  /// move into a wall that blocks (supervisor.walls = "block") is not made.
  void propose(Command command);
  /// True when this step's proposal moves the robot's centre (a contact may block it).
  bool proposes_move() const { return moving_; }
  /// Where the proposal puts the robot's centre.
  Vec2 proposed_position() const { return {proposed_.pose.x, proposed_.pose.y}; }
  /// Blocks this step's move (a contact): the robot keeps its position, turns as proposed.
  void block();
  /// Replaces this step's move by a straight one to `to` (a contact it slides along); the
  /// odometer counts the new move. A slide into the source's solid body, or into a wall that
  /// blocks, is blocked instead.
  void slide(Vec2 to);
  /// Where the robot's centre is before this step's move.
  Vec2 position() const { return {robot_.pose.x, robot_.pose.y}; }
  /// Makes the proposed motion and checks the run (nothing after a give-up or declaration).
  void commit();
  /// Queues a teammate's message, delivered at the sense of step `step` (Agent::steps()).
  void receive(std::int64_t step, const Message& message);
  /// The wind sensor, for a decision made outside a Controller (one noisy sample per call).
  WindProbe& wind_probe() { return wind_sensor_; }

  /// True once the run has ended.
  bool done() const { return outcome_ != Outcome::kRunning; }
  /// The run's metrics so far.
  RunResult result() const;
  /// Time since release (s).
  double time() const { return static_cast<double>(steps_) * scenario_.sim.dt; }
  /// Steps since release.
  std::int64_t steps() const { return steps_; }
  /// Its index in its team.
  int index() const { return index_; }
  /// The scenario in use.
  const Scenario& scenario() const { return scenario_; }
  /// The robot's true state.
  const RobotState& robot() const { return robot_; }
  /// Where it was released (m, rad): the origin of its odometry.
  const Pose& start() const { return start_; }
  /// The controller.
  const Controller& controller() const { return *controller_; }
  /// What its controller reads (Reads flags).
  unsigned reads() const { return reads_; }
  /// The wind sensor (samples taken this step).
  const WindSensor& wind_sensor() const { return wind_sensor_; }
  /// Odor perceived at the last step.
  bool odor() const { return odor_; }
  /// The odor sensor's reading at the last step where it was computed (NaN where the binary
  /// test alone was needed).
  double reading() const { return reading_; }
  /// Where the odor sensor sampled the plume at the last step.
  const Vec3& sensed_at() const { return sensed_at_; }
  /// How the run ended (kRunning while it goes on).
  Outcome outcome() const { return outcome_; }
  /// Where it declared the source (m, world frame), NaN when it has not.
  Vec2 declared() const { return declared_; }

 private:
  void sense_odor_now(unsigned reads);

  Scenario scenario_;
  std::uint64_t seed_;
  std::uint64_t trial_;
  int index_;
  const Environment& env_;
  Pose start_;
  RobotState robot_;
  RobotState proposed_;
  bool moving_ = false;
  bool ended_ = false;  // a give-up or declaration this step
  Rng wind_rng_;
  WindSensor wind_sensor_;
  std::unique_ptr<OdorSensorModel> sensor_model_;
  std::unique_ptr<Controller> controller_;
  unsigned reads_;
  std::int64_t steps_ = 0;
  std::int64_t odor_steps_ = 0;
  Vec3 sensed_at_;
  bool odor_ = false;
  double reading_ = NAN;
  double t_first_odor_ = NAN;
  double d_first_odor_ = NAN;
  Vec2 declared_{NAN, NAN};
  double declaration_error_ = NAN;
  std::vector<std::pair<std::int64_t, Message>> pending_;  // (delivery step, message)
  std::vector<Message> inbox_;                             // delivered this step
  Outcome outcome_ = Outcome::kRunning;
};

/// Where the robots of a scenario's team are released (m, rad), robot 0 first: at a point start
/// robot 0 at robot.start and the others beside it (team.spacing), else drawn from start.region
/// with each robot's own start stream, under start.condition, clear of the walls, the solid
/// source, the success radius and (with team.contact on) the robots drawn before it. Throws
/// ConfigError naming the start keys when no start is found in kMaxStartDraws draws.
std::vector<Pose> team_starts(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                              const Environment& env);

/// Builds a run's controller from its scenario and its controller stream; the extension point
/// for controllers of your own (C++ or Python), used by runs and sweeps alike.
using ControllerFactory = std::function<std::unique_ptr<Controller>(const Scenario&, Rng)>;

/// The controller of run (seed, trial): `factory`'s when given, else the scenario's built-in
/// algorithm; either gets the run's controller stream.
std::unique_ptr<Controller> make_run_controller(const Scenario& scenario, std::uint64_t seed,
                                                std::uint64_t trial,
                                                const ControllerFactory& factory = {},
                                                int agent = 0);

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
  /// One team per scenario (team.count agents each) in one environment, the first scenario's,
  /// warmed up; the scenarios must agree on everything the environment depends on (`plume_key`,
  /// sweep.hpp). Teams do not see each other: each takes exactly the steps it would take alone.
  World(const std::vector<const Scenario*>& scenarios, std::uint64_t seed, std::uint64_t trial,
        const ControllerFactory& factory = {});
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// One step (docs/model.md section 2; docs/agents.md, "One step of a team"): the
  /// environment; every running agent senses and decides; every one proposes its motion;
  /// contacts within each team are resolved; every one commits and is checked; messages sent
  /// this step are queued for delivery. Results do not depend on the order of the agents. Does
  /// nothing once every agent is done.
  void step();
  /// A step of a one-agent world split for a decision made outside the controller: the
  /// environment and sensing ...
  Observation observe();
  /// ... then the decision, move and check (see Agent::sense, Agent::act).
  void act(const Command& command) { agents_.front()->act(command); }
  /// The wind sensor of agent 0, for a decision made outside the controller.
  WindProbe& wind_probe() { return agents_.front()->wind_probe(); }
  /// A step of every agent split for decisions made outside the controllers (a learning team,
  /// docs/vector.md, "Teams"): the environment, then every running agent senses what its
  /// controller reads; observations()[i] is agent i's (a default one for an agent whose run has
  /// ended), valid until the next call. std::logic_error once every run has ended, or before
  /// act_team() has followed the last call ...
  const std::vector<Observation>& observe_team();
  /// ... then every running agent proposes commands[i] (the command of an agent whose run had
  /// ended is ignored), contacts are resolved, every one commits and is checked, messages are
  /// queued: observe_team() and act_team() with the commands the controllers would return make
  /// exactly step(). std::invalid_argument naming the agent, before anything moves, for a
  /// command with a value that is not finite or a count other than agent_count().
  void act_team(std::span<const Command> commands);
  /// Agent i's wind sensor, for a decision made outside its controller (between observe_team
  /// and act_team).
  WindProbe& wind_probe(std::size_t i) { return agents_.at(i)->wind_probe(); }
  /// The observations of the last observe_team().
  const std::vector<Observation>& observations() const { return seen_; }
  /// True once every agent's run has ended.
  bool done() const;
  /// Agent 0's metrics so far.
  RunResult result() const { return agents_.front()->result(); }
  /// Every agent's metrics so far: the scenarios' teams in order, each robot 0 first.
  std::vector<RunResult> results() const;
  /// The first agent of each team, and one past the last: team t is agents [teams()[t],
  /// teams()[t + 1]).
  const std::vector<std::size_t>& teams() const { return teams_; }

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
  void add_team(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                std::unique_ptr<Controller> first, const ControllerFactory& factory);
  void start(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial);
  void move_agents();
  void resolve_contacts(std::size_t begin, std::size_t end);
  void send_messages(std::size_t begin, std::size_t end);

  Environment env_;
  double dt_;
  std::vector<std::size_t> teams_{0};
  std::vector<std::unique_ptr<Agent>> agents_;
  std::vector<Command> commands_;  // this step's decisions, one per agent
  std::vector<Vec2> sent_from_;    // where each agent was when it decided
  std::vector<char> blocked_;      // contact resolution: the agent's move is blocked
  std::vector<char> running_;      // this step: the agent's run had not ended
  std::vector<char> hit_;          // contact resolution: the agent's body would overlap
  std::vector<std::size_t> live_;  // contact resolution: the team's running agents
  std::vector<Vec2> slid_;         // contact resolution: the agent's move after sliding
  std::vector<double> move_;       // contact resolution: the length of the agent's move
  std::vector<Vec2> normals_;      // contact resolution: toward the teammates a move meets
  std::vector<double> gaps_;       // contact resolution: the gaps to them
  std::vector<Observation> seen_;  // observe_team: each agent's sensing
  bool observed_ = false;          // observe_team has been called, act_team not yet
};

/// Called after the warm-up and after every step of a run.
using StepObserver = std::function<void(const World&)>;

/// Runs one whole run: a pure function of (scenario, seed, trial) and the controller factory
/// (empty: the scenario's built-in algorithm). Robot 0's result (the run's, for a robot alone).
RunResult run_once(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                   const StepObserver& observer = {}, const ControllerFactory& factory = {});

/// Runs one whole run of the scenario's team: every robot's result, robot 0 first.
std::vector<RunResult> run_team(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                                const StepObserver& observer = {},
                                const ControllerFactory& factory = {});

}  // namespace plumetrace
