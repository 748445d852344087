#include "plumetrace/sim/world.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

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
             std::unique_ptr<Controller> controller)
    : scenario_(scenario),
      seed_(seed),
      trial_(trial),
      wind_(make_wind_field(scenario.wind)),
      robot_{scenario.robot.start, 0.0},
      wind_rng_(derive_seed(seed, trial, Stream::kWindSensor)),
      wind_sensor_(scenario_.wind_sensor, *wind_, robot_.pose, scenario_.odor.height, wind_rng_),
      controller_(std::move(controller)) {}

void Agent::release(const Plume& plume, double warmup_time) {
  warmup_time_ = warmup_time;
  // what the sensor reads at release (for traces; the controller first senses after one step)
  sensed_at_ = odor_sensor_point(scenario_.odor, robot_.pose);
  odor_ = sense_odor(scenario_.odor, plume, robot_.pose);
}

void Agent::step(const Plume& plume) {
  if (done()) return;
  const Observation obs = sense(plume);
  // decide
  act(controller_->step(obs, wind_sensor_));
}

Observation Agent::sense(const Plume& plume) {
  ++steps_;
  sensed_at_ = odor_sensor_point(scenario_.odor, robot_.pose);
  odor_ = sense_odor(scenario_.odor, plume, robot_.pose);
  if (odor_) ++odor_steps_;
  wind_sensor_.clear();
  wind_sensor_.set_time(plume_time());
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

Plume make_plume(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial) {
  return Plume(scenario.plume, scenario.source, scenario.sim.dt, scenario.arena.x_max,
               derive_seed(seed, trial, Stream::kPlume));
}

double warm_up(const Scenario& scenario, const WindField& wind, Plume& plume) {
  const auto steps = static_cast<std::int64_t>(std::llround(scenario.sim.warmup / scenario.sim.dt));
  for (std::int64_t i = 0; i < steps; ++i) {
    plume.step(wind, static_cast<double>(i) * scenario.sim.dt);
  }
  return static_cast<double>(steps) * scenario.sim.dt;
}

std::unique_ptr<Controller> make_run_controller(const Scenario& scenario, std::uint64_t seed,
                                                std::uint64_t trial,
                                                const ControllerFactory& factory) {
  Rng rng(derive_seed(seed, trial, Stream::kController));
  return factory ? factory(scenario, rng) : make_controller(scenario.controller, rng);
}

World::World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial)
    : World(scenario, seed, trial, make_run_controller(scenario, seed, trial)) {}

World::World(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
             std::unique_ptr<Controller> controller)
    : wind_(make_wind_field(scenario.wind)),
      plume_(make_plume(scenario, seed, trial)),
      agent_(scenario, seed, trial, std::move(controller)) {
  agent_.release(plume_, warm_up(scenario, *wind_, plume_));
}

void World::step() {
  if (done()) return;
  // environment: filaments move, then new ones are released
  plume_.step(*wind_, agent_.plume_time());
  // the robot: sense, decide, move, check
  agent_.step(plume_);
}

Observation World::observe() {
  plume_.step(*wind_, agent_.plume_time());
  return agent_.sense(plume_);
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
