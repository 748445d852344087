#include "plumetrace/sim/world.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "plumetrace/env/filament_plume.hpp"

namespace plumetrace {

Outcome supervise(const Scenario& scenario, const RobotState& robot, double t) {
  const Pose& p = robot.pose;
  const auto& src = scenario.source.center;
  const double dx = p.x - src.x, dy = p.y - src.y;
  const double rs = scenario.supervisor.success_radius;
  if (dx * dx + dy * dy <= rs * rs) return Outcome::kSuccess;
  // touching a solid source is finding it
  if (robot.touching) return Outcome::kSuccess;
  const auto& a = scenario.arena;
  const double r = scenario.robot.radius;
  if (p.x - a.x_min < r || a.x_max - p.x < r || p.y - a.y_min < r || a.y_max - p.y < r) {
    return Outcome::kWall;
  }
  if (t >= scenario.supervisor.timeout) return Outcome::kTimeout;
  return Outcome::kRunning;
}

Agent::Agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
             std::unique_ptr<Controller> controller, const Environment& env)
    : scenario_(scenario),
      seed_(seed),
      trial_(trial),
      env_(env),
      robot_{scenario.robot.start, 0.0},
      wind_rng_(derive_seed(seed, trial, Stream::kWindSensor)),
      wind_sensor_(scenario_.wind_sensor, *env.wind, robot_.pose, scenario_.odor.height, wind_rng_),
      controller_(std::move(controller)) {}

void Agent::release() {
  // what the sensor reads at release (for traces; the controller first senses after one step)
  sensed_at_ = odor_sensor_point(scenario_.odor, robot_.pose);
  odor_ = sense_odor(scenario_.odor, *env_.odor, robot_.pose);
}

Command Agent::decide() {
  const Observation obs = sense();
  return controller_->step(obs, wind_sensor_);
}

Observation Agent::sense() {
  ++steps_;
  sensed_at_ = odor_sensor_point(scenario_.odor, robot_.pose);
  odor_ = sense_odor(scenario_.odor, *env_.odor, robot_.pose);
  if (odor_) ++odor_steps_;
  wind_sensor_.clear();
  // why: odometry starts at the release pose, so a controller cannot read the arena's frame
  return {time(), odor_, relative_pose(scenario_.robot.start, robot_.pose), robot_.odometer};
}

void Agent::act(Command command) {
  // why: a NaN heading or curvature would carry the robot to NaN, which no wall or timeout check
  // catches; it is the controller's error, so it stops the run rather than ending it as an outcome
  if (!std::isfinite(command.heading) || !std::isfinite(command.curvature)) {
    throw std::invalid_argument(
        "the controller returned a command with a non-finite value (heading " +
        format_number(command.heading) + ", curvature " + format_number(command.curvature) +
        ") at t = " + format_number(time()) + " s of run seed " + std::to_string(seed_) +
        ", trial " + std::to_string(trial_));
  }
  command.heading = wrap_angle(command.heading + scenario_.robot.start.heading);
  if (command.give_up) {
    outcome_ = Outcome::kGaveUp;
    return;
  }
  // move
  const auto& src = scenario_.source;
  step_robot(scenario_.robot, command, scenario_.sim.dt, robot_,
             {{src.center.x, src.center.y}, src.solid_radius});
  // check
  outcome_ = supervise(scenario_, robot_, time());
}

RunResult Agent::result() const {
  RunResult r;
  r.outcome = outcome_;
  r.time = time();
  r.d_t = robot_.odometer;
  r.d_u = scenario_.robot.start.x - robot_.pose.x;
  r.overhead = r.d_u > 0.0 ? r.d_t / r.d_u : NAN;
  r.losses = controller_->losses();
  r.odor_fraction =
      steps_ > 0 ? static_cast<double>(odor_steps_) / static_cast<double>(steps_) : 0.0;
  r.steps = steps_;
  r.wind_samples = wind_sensor_.total();
  r.seed = seed_;
  r.trial = trial_;
  return r;
}

Environment make_environment(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial) {
  Environment env;
  env.wind = make_wind_field(scenario.wind, wind_region(scenario.arena),
                             Rng(derive_seed(seed, trial, Stream::kWind)));
  env.odor = make_odor_field("filament", scenario.plume, scenario.source, scenario.arena.x_max,
                             derive_seed(seed, trial, Stream::kPlume));
  return env;
}

void warm_up(const Scenario& scenario, Environment& env) {
  const auto steps = static_cast<std::int64_t>(std::llround(scenario.sim.warmup / scenario.sim.dt));
  for (std::int64_t i = 0; i < steps; ++i) step(env, scenario.sim.dt);
}

std::unique_ptr<Controller> make_run_controller(const Scenario& scenario, std::uint64_t seed,
                                                std::uint64_t trial,
                                                const ControllerFactory& factory) {
  Rng rng(derive_seed(seed, trial, Stream::kController));
  return factory ? factory(scenario, rng) : make_controller(scenario.controller, rng);
}

namespace {

const Scenario& first_of(const std::vector<const Scenario*>& scenarios) {
  if (scenarios.empty()) throw std::invalid_argument("World: no scenario, so no agent");
  return *scenarios.front();
}

// why: the agents' sensors bind to the environment's fields as they are built
Environment complete(Environment env) {
  if (!env.wind || !env.odor) {
    throw std::invalid_argument("World: the environment needs a wind field and an odor field");
  }
  return env;
}

}  // namespace

World::World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial)
    : World(scenario, seed, trial, make_run_controller(scenario, seed, trial)) {}

World::World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
             std::unique_ptr<Controller> controller)
    : World(scenario, seed, trial, std::move(controller), make_environment(scenario, seed, trial)) {
}

World::World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
             std::unique_ptr<Controller> controller, Environment env)
    : env_(complete(std::move(env))), dt_(scenario.sim.dt) {
  add_agent(scenario, seed, trial, std::move(controller));
  start(scenario);
}

World::World(const std::vector<const Scenario*>& scenarios, std::uint64_t seed, std::uint64_t trial,
             const ControllerFactory& factory)
    : env_(make_environment(first_of(scenarios), seed, trial)), dt_(first_of(scenarios).sim.dt) {
  for (const Scenario* s : scenarios) {
    add_agent(*s, seed, trial, make_run_controller(*s, seed, trial, factory));
  }
  start(*scenarios.front());
}

void World::add_agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                      std::unique_ptr<Controller> controller) {
  agents_.push_back(std::make_unique<Agent>(scenario, seed, trial, std::move(controller), env_));
}

void World::start(const Scenario& scenario) {
  warm_up(scenario, env_);
  for (const auto& a : agents_) a->release();
  commands_.resize(agents_.size());
}

void World::step() {
  if (done()) return;
  // environment: the wind, then the filaments move in it and new ones are released
  plumetrace::step(env_, dt_);
  // every running robot senses and decides, then every one moves and is checked; robots do not
  // see each other, so each takes exactly the step it would take alone
  const std::size_t n = agents_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!agents_[i]->done()) commands_[i] = agents_[i]->decide();
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!agents_[i]->done()) agents_[i]->act(commands_[i]);
  }
}

Observation World::observe() {
  plumetrace::step(env_, dt_);
  return agents_.front()->sense();
}

bool World::done() const {
  for (const auto& a : agents_) {
    if (!a->done()) return false;
  }
  return true;
}

std::vector<RunResult> World::results() const {
  std::vector<RunResult> out;
  out.reserve(agents_.size());
  for (const auto& a : agents_) out.push_back(a->result());
  return out;
}

RunResult run_once(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                   const StepObserver& observer, const ControllerFactory& factory) {
  World world(scenario, seed, trial, make_run_controller(scenario, seed, trial, factory));
  if (observer) observer(world);
  while (!world.done()) {
    world.step();
    if (observer) observer(world);
  }
  return world.result();
}

}  // namespace plumetrace
