#include "plumetrace/sim/world.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/math.hpp"
#include "plumetrace/env/filament_plume.hpp"

namespace plumetrace {

Outcome supervise(const Scenario& scenario, const RobotState& robot, double t) {
  const Pose& p = robot.pose;
  if (scenario.supervisor.success == SuccessRule::kReach) {
    const auto& src = scenario.source.center;
    const double dx = p.x - src.x, dy = p.y - src.y;
    const double rs = scenario.supervisor.success_radius;
    if (dx * dx + dy * dy <= rs * rs) return Outcome::kSuccess;
    // touching a solid source is finding it
    if (robot.touching) return Outcome::kSuccess;
  }
  if (scenario.supervisor.walls == WallRule::kEnd) {
    const auto& a = scenario.arena;
    const double r = scenario.robot.radius;
    if (p.x - a.x_min < r || a.x_max - p.x < r || p.y - a.y_min < r || a.y_max - p.y < r) {
      return Outcome::kWall;
    }
  }
  if (t >= scenario.supervisor.timeout) return Outcome::kTimeout;
  return Outcome::kRunning;
}

namespace {

// the robot's centre is clear of every wall by its radius
bool clear_of_walls(const ArenaParams& a, double r, double x, double y) {
  return x - a.x_min >= r && a.x_max - x >= r && y - a.y_min >= r && a.y_max - y >= r;
}

}  // namespace

Agent::Agent(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial, int index,
             std::unique_ptr<Controller> controller, const Environment& env)
    : scenario_(scenario),
      seed_(seed),
      trial_(trial),
      index_(index),
      env_(env),
      start_(scenario.robot.start),
      robot_{scenario.robot.start, 0.0},
      wind_rng_(derive_seed(seed, trial, Stream::kWindSensor, index)),
      wind_sensor_(scenario_.wind_sensor, *env.wind, robot_.pose, scenario_.odor.height, wind_rng_),
      sensor_model_(make_sensor_model(scenario_.odor,
                                      Rng(derive_seed(seed, trial, Stream::kOdorSensor, index)))),
      controller_(std::move(controller)),
      reads_(controller_->reads()) {}

void Agent::release(const Pose& start) {
  start_ = start;
  robot_ = {start, 0.0};
  proposed_ = robot_;
  // what the sensor reads at release (for traces; the controller first senses after one step)
  sensed_at_ = odor_sensor_point(scenario_.odor, robot_.pose);
  if (sensor_model_->ideal()) {
    odor_ = sense_odor(scenario_.odor, *env_.odor, robot_.pose);
  } else {
    // a sensor with a state starts settled in the concentration at release
    const double c = env_.odor->concentration(sensed_at_);
    sensor_model_->reset(c);
    reading_ = c;
    odor_ = perceives_odor(scenario_.odor, c);
  }
}

Command Agent::decide() {
  const Observation obs = sense(reads_);
  return controller_->step(obs, wind_sensor_);
}

void Agent::sense_odor_now(unsigned reads) {
  sensed_at_ = odor_sensor_point(scenario_.odor, robot_.pose);
  if (sensor_model_->ideal() && !(reads & kReadsConcentration)) {
    // why: the threshold test stops summing once it is reached; the paper's controllers pay no
    // more than before
    odor_ = sense_odor(scenario_.odor, *env_.odor, robot_.pose);
    reading_ = NAN;
    return;
  }
  const double c = env_.odor->concentration(sensed_at_);
  reading_ = sensor_model_->read(c, scenario_.sim.dt);
  odor_ = perceives_odor(scenario_.odor, reading_);
}

Observation Agent::sense(unsigned reads) {
  ++steps_;
  sense_odor_now(reads);
  if (odor_) {
    ++odor_steps_;
    if (std::isnan(t_first_odor_)) {
      t_first_odor_ = time();
      d_first_odor_ = robot_.odometer;
    }
  }
  wind_sensor_.clear();
  // why: odometry starts at the release pose, so a controller cannot read the arena's frame
  Observation obs;
  obs.time = time();
  obs.odor = odor_;
  obs.odometry = relative_pose(start_, robot_.pose);
  obs.odometer = robot_.odometer;
  if (reads & kReadsConcentration) obs.concentration = reading_;
  inbox_.clear();
  if (!pending_.empty()) {
    // messages due now, in the order (sent, from)
    auto due = std::stable_partition(pending_.begin(), pending_.end(),
                                     [&](const auto& m) { return m.first > steps_; });
    for (auto it = due; it != pending_.end(); ++it) inbox_.push_back(it->second);
    pending_.erase(due, pending_.end());
    std::sort(inbox_.begin(), inbox_.end(), [](const Message& a, const Message& b) {
      return a.sent != b.sent ? a.sent < b.sent : a.from < b.from;
    });
  }
  if (reads & kReadsMessages) obs.messages = inbox_;
  return obs;
}

void Agent::receive(std::int64_t step, const Message& message) {
  pending_.emplace_back(step, message);
}

void Agent::propose(Command command) {
  // why: a NaN heading or curvature would carry the robot to NaN, which no wall or timeout check
  // catches; it is the controller's error, so it stops the run rather than ending it as an outcome
  if (!std::isfinite(command.heading) || !std::isfinite(command.curvature) ||
      (command.declare && !(std::isfinite(command.source.x) && std::isfinite(command.source.y)))) {
    throw std::invalid_argument(
        "the controller returned a command with a non-finite value (heading " +
        format_number(command.heading) + ", curvature " + format_number(command.curvature) +
        (command.declare ? ", declared source (" + format_number(command.source.x) + ", " +
                               format_number(command.source.y) + ")"
                         : std::string()) +
        ") at t = " + format_number(time()) + " s of run seed " + std::to_string(seed_) +
        ", trial " + std::to_string(trial_) + (index_ ? ", robot " + std::to_string(index_) : ""));
  }
  proposed_ = robot_;
  moving_ = false;
  ended_ = false;
  if (command.give_up) {
    outcome_ = Outcome::kGaveUp;
    ended_ = true;
    return;
  }
  if (command.declare) {
    // the declaration, from the odometry frame into the arena's
    const Vec2 d = rotate(command.source, start_.heading);
    declared_ = {start_.x + d.x, start_.y + d.y};
    const auto& src = scenario_.source.center;
    declaration_error_ = math::hypot(declared_.x - src.x, declared_.y - src.y);
    outcome_ = declaration_error_ <= scenario_.supervisor.declaration_radius
                   ? Outcome::kSuccess
                   : Outcome::kWrongDeclaration;
    ended_ = true;
    return;
  }
  command.heading = wrap_angle(command.heading + start_.heading);
  const auto& src = scenario_.source;
  step_robot(scenario_.robot, command, scenario_.sim.dt, proposed_,
             {{src.center.x, src.center.y}, src.solid_radius});
  if (scenario_.supervisor.walls == WallRule::kBlock &&
      !clear_of_walls(scenario_.arena, scenario_.robot.radius, proposed_.pose.x,
                      proposed_.pose.y)) {
    block();
  }
  moving_ = proposed_.pose.x != robot_.pose.x || proposed_.pose.y != robot_.pose.y;
}

void Agent::block() {
  proposed_.pose.x = robot_.pose.x;
  proposed_.pose.y = robot_.pose.y;
  proposed_.odometer = robot_.odometer;
  proposed_.touching = robot_.touching;
  moving_ = false;
}

void Agent::slide(Vec2 to) {
  const auto& src = scenario_.source;
  const double r = scenario_.robot.radius;
  const double contact = src.solid_radius + r;
  if ((src.solid_radius > 0.0 && math::hypot(to.x - src.center.x, to.y - src.center.y) < contact) ||
      (scenario_.supervisor.walls == WallRule::kBlock &&
       !clear_of_walls(scenario_.arena, r, to.x, to.y))) {
    block();
    return;
  }
  proposed_.pose.x = to.x;
  proposed_.pose.y = to.y;
  proposed_.odometer = robot_.odometer + math::hypot(to.x - robot_.pose.x, to.y - robot_.pose.y);
  proposed_.touching = false;
  moving_ = to.x != robot_.pose.x || to.y != robot_.pose.y;
}

void Agent::commit() {
  if (ended_) return;
  robot_ = proposed_;
  outcome_ = supervise(scenario_, robot_, time());
}

RunResult Agent::result() const {
  RunResult r;
  r.outcome = outcome_;
  r.time = time();
  r.d_t = robot_.odometer;
  r.d_u = start_.x - robot_.pose.x;
  r.overhead = r.d_u > 0.0 ? r.d_t / r.d_u : NAN;
  r.losses = controller_->losses();
  r.odor_fraction =
      steps_ > 0 ? static_cast<double>(odor_steps_) / static_cast<double>(steps_) : 0.0;
  r.steps = steps_;
  r.wind_samples = wind_sensor_.total();
  r.t_first_odor = t_first_odor_;
  r.d_first_odor = d_first_odor_;
  r.declaration_error = declaration_error_;
  r.seed = seed_;
  r.trial = trial_;
  r.agent = index_;
  return r;
}

std::vector<Pose> team_starts(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                              const Environment& env) {
  const int n = scenario.team.count;
  const StartParams& st = scenario.start;
  const RobotParams& robot = scenario.robot;
  const double r = robot.radius;
  const bool contact = scenario.team.contact == TeamParams::Contact::kOn;
  std::vector<Pose> starts;
  starts.reserve(static_cast<std::size_t>(n));
  const auto heading = [&](Rng& rng) {
    return st.heading == StartHeading::kRandom ? kPi * (2.0 * rng.uniform() - 1.0)
                                               : robot.start.heading;
  };
  if (st.region == StartRegion::kPoint) {
    starts = point_starts(scenario);
    for (int k = 0; k < n; ++k) {
      Pose& p = starts[static_cast<std::size_t>(k)];
      if (st.heading == StartHeading::kRandom) {
        Rng rng(derive_seed(seed, trial, Stream::kStart, k));
        p.heading = heading(rng);
      }
    }
    return starts;
  }
  const bool source_frame = st.frame == StartFrame::kSource;
  const Vec2 origin =
      source_frame ? Vec2{scenario.source.center.x, scenario.source.center.y} : Vec2{0.0, 0.0};
  const auto& src = scenario.source;
  const double keep_off = std::max(src.solid_radius + r, scenario.supervisor.success_radius);
  for (int k = 0; k < n; ++k) {
    Rng rng(derive_seed(seed, trial, Stream::kStart, k));
    bool found = false;
    for (int draw = 0; draw < kMaxStartDraws && !found; ++draw) {
      Vec2 p;
      if (st.region == StartRegion::kRectangle) {
        p = {st.x_min + (st.x_max - st.x_min) * rng.uniform(),
             st.y_min + (st.y_max - st.y_min) * rng.uniform()};
      } else {
        // uniform in the disc: radius by the square root of a uniform
        const double rho = st.radius * std::sqrt(rng.uniform());
        const double phi = 2.0 * kPi * rng.uniform();
        p = {st.cx + rho * math::cos(phi), st.cy + rho * math::sin(phi)};
      }
      p = {origin.x + p.x, origin.y + p.y};
      const Pose pose{p.x, p.y, heading(rng)};
      if (!clear_of_walls(scenario.arena, r, p.x, p.y)) continue;
      if (math::hypot(p.x - src.center.x, p.y - src.center.y) <= keep_off) continue;
      bool overlaps = false;
      for (const Pose& q : starts) {
        if (contact && math::hypot(p.x - q.x, p.y - q.y) < 2.0 * r) overlaps = true;
      }
      if (overlaps) continue;
      if (st.condition == StartCondition::kInOdor && !sense_odor(scenario.odor, *env.odor, pose)) {
        continue;
      }
      starts.push_back(pose);
      found = true;
    }
    if (!found) {
      throw ConfigError(
          "start.region, start.condition: no start found for robot " + std::to_string(k) + " in " +
          std::to_string(kMaxStartDraws) + " draws of run seed " + std::to_string(seed) +
          ", trial " + std::to_string(trial) +
          " (the region is mostly outside the arena, blocked, crowded or outside odor)");
    }
  }
  return starts;
}

Environment make_environment(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial) {
  Environment env;
  env.wind = make_wind_field(scenario.wind, wind_context(scenario),
                             Rng(derive_seed(seed, trial, Stream::kWind)));
  const auto model = static_cast<std::size_t>(scenario.plume.model);  // plume.model
  env.odor = make_odor_field(odor_field_registry()[model].name, scenario.plume, scenario.source,
                             scenario.arena.x_max, derive_seed(seed, trial, Stream::kPlume));
  return env;
}

void warm_up(const Scenario& scenario, Environment& env) {
  const auto steps = static_cast<std::int64_t>(std::llround(scenario.sim.warmup / scenario.sim.dt));
  for (std::int64_t i = 0; i < steps; ++i) step(env, scenario.sim.dt);
}

std::unique_ptr<Controller> make_run_controller(const Scenario& scenario, std::uint64_t seed,
                                                std::uint64_t trial,
                                                const ControllerFactory& factory, int agent) {
  Rng rng(derive_seed(seed, trial, Stream::kController, agent));
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
  add_team(scenario, seed, trial, std::move(controller), {});
  start(scenario, seed, trial);
}

World::World(const std::vector<const Scenario*>& scenarios, std::uint64_t seed, std::uint64_t trial,
             const ControllerFactory& factory)
    : env_(make_environment(first_of(scenarios), seed, trial)), dt_(first_of(scenarios).sim.dt) {
  for (const Scenario* s : scenarios) {
    add_team(*s, seed, trial, make_run_controller(*s, seed, trial, factory), factory);
  }
  start(*scenarios.front(), seed, trial);
}

void World::add_team(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                     std::unique_ptr<Controller> first, const ControllerFactory& factory) {
  agents_.push_back(std::make_unique<Agent>(scenario, seed, trial, 0, std::move(first), env_));
  for (int k = 1; k < scenario.team.count; ++k) {
    // a robot of a mixed team runs with its own keys (Scenario::members)
    std::optional<Scenario> mine;
    if (std::any_of(scenario.members.begin(), scenario.members.end(),
                    [k](const MemberSetting& m) { return m.robot == k; })) {
      mine = member_scenario(scenario, k);
    }
    const Scenario& s = mine ? *mine : scenario;
    agents_.push_back(std::make_unique<Agent>(
        s, seed, trial, k, make_run_controller(s, seed, trial, factory, k), env_));
  }
  teams_.push_back(agents_.size());
}

void World::start(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial) {
  warm_up(scenario, env_);
  for (std::size_t t = 0; t + 1 < teams_.size(); ++t) {
    const Scenario& s = agents_[teams_[t]]->scenario();
    if (s.team.count == 1 && s.start.region == StartRegion::kPoint &&
        s.start.heading == StartHeading::kFixed) {
      agents_[teams_[t]]->release();  // a robot alone at the paper's start: no draw
      continue;
    }
    const std::vector<Pose> starts = team_starts(s, seed, trial, env_);
    for (std::size_t k = 0; k < starts.size(); ++k) agents_[teams_[t] + k]->release(starts[k]);
  }
  commands_.resize(agents_.size());
  sent_from_.resize(agents_.size());
  blocked_.resize(agents_.size());
  running_.resize(agents_.size());
  hit_.resize(agents_.size());
  slid_.resize(agents_.size());
  move_.resize(agents_.size());
  live_.reserve(agents_.size());
}

void World::step() {
  if (observed_) throw std::logic_error("step: observe_team() waits for act_team()");
  if (done()) return;
  // environment: the wind, then the filaments move in it and new ones are released
  plumetrace::step(env_, dt_);
  // every running robot senses and decides, then every one proposes its motion; contacts are
  // resolved within each team on the proposals; then every one commits and is checked. Teams
  // do not see each other, so each takes exactly the steps it would take alone
  const std::size_t n = agents_.size();
  std::vector<char>& running = running_;
  for (std::size_t i = 0; i < n; ++i) {
    running[i] = !agents_[i]->done();
    if (!running[i]) {
      commands_[i].send = false;  // a robot whose run has ended says nothing
      continue;
    }
    const RobotState& r = agents_[i]->robot();
    sent_from_[i] = {r.pose.x, r.pose.y};
    commands_[i] = agents_[i]->decide();
  }
  move_agents();
}

const std::vector<Observation>& World::observe_team() {
  if (observed_) throw std::logic_error("observe_team: call act_team() first");
  if (done()) throw std::logic_error("observe_team: every agent's run has ended");
  // the first half of step(): the environment, then every running robot senses
  plumetrace::step(env_, dt_);
  const std::size_t n = agents_.size();
  seen_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    running_[i] = !agents_[i]->done();
    if (!running_[i]) {
      seen_[i] = Observation{};
      continue;
    }
    const RobotState& r = agents_[i]->robot();
    sent_from_[i] = {r.pose.x, r.pose.y};
    seen_[i] = agents_[i]->sense();
  }
  observed_ = true;
  return seen_;
}

void World::act_team(std::span<const Command> commands) {
  if (!observed_) throw std::logic_error("act_team: call observe_team() first");
  const std::size_t n = agents_.size();
  if (commands.size() != n) {
    throw std::invalid_argument("act_team: " + std::to_string(commands.size()) + " commands for " +
                                std::to_string(n) + " agents");
  }
  // why: checked before anything moves, so a refused command leaves the world as it was
  for (std::size_t i = 0; i < n; ++i) {
    const Command& c = commands[i];
    if (!running_[i]) continue;
    bool finite = std::isfinite(c.heading) && std::isfinite(c.curvature);
    if (c.declare) finite = finite && std::isfinite(c.source.x) && std::isfinite(c.source.y);
    if (!finite) {
      throw std::invalid_argument("act_team: commands[" + std::to_string(i) + "] (agent " +
                                  std::to_string(i) + ") holds a value that is not finite");
    }
  }
  observed_ = false;
  for (std::size_t i = 0; i < n; ++i) commands_[i] = running_[i] ? commands[i] : Command{};
  move_agents();
}

void World::move_agents() {
  // the second half of step(): every running robot proposes its motion, contacts are resolved
  // within each team, every one commits and is checked, messages are queued
  const std::size_t n = agents_.size();
  const std::vector<char>& running = running_;
  for (std::size_t i = 0; i < n; ++i) {
    if (running[i]) agents_[i]->propose(commands_[i]);
  }
  for (std::size_t t = 0; t + 1 < teams_.size(); ++t) {
    const std::size_t b = teams_[t], e = teams_[t + 1];
    if (e - b < 2) continue;
    if (agents_[b]->scenario().team.contact == TeamParams::Contact::kOn) resolve_contacts(b, e);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (running[i]) agents_[i]->commit();
  }
  for (std::size_t t = 0; t + 1 < teams_.size(); ++t) {
    if (teams_[t + 1] - teams_[t] > 1) send_messages(teams_[t], teams_[t + 1]);
  }
}

namespace {

// why: the move nearest `d` that keeps a round body clear of teammates standing where they are
// now: for each teammate k in reach, the move's part toward it (unit normal n[k]) may not
// exceed the gap g[k] >= 0 between the bodies. The set of such moves is convex and holds 0, so
// the nearest one is unique; in the plane it is d itself, or d projected onto one constraint's
// line, or the corner of two, whichever is allowed and nearest
Vec2 nearest_clear_move(Vec2 d, const std::vector<Vec2>& n, const std::vector<double>& g) {
  constexpr double kSlack = 1e-12;
  const auto allowed = [&](Vec2 v) {
    for (std::size_t k = 0; k < n.size(); ++k) {
      if (v.x * n[k].x + v.y * n[k].y > g[k] + kSlack) return false;
    }
    return true;
  };
  if (allowed(d)) return d;
  Vec2 best{0.0, 0.0};
  double best_d2 = d.x * d.x + d.y * d.y;
  const auto consider = [&](Vec2 v) {
    const double e2 = (v.x - d.x) * (v.x - d.x) + (v.y - d.y) * (v.y - d.y);
    if (e2 < best_d2 && allowed(v)) {
      best = v;
      best_d2 = e2;
    }
  };
  for (std::size_t k = 0; k < n.size(); ++k) {
    const double over = d.x * n[k].x + d.y * n[k].y - g[k];
    consider({d.x - over * n[k].x, d.y - over * n[k].y});
    for (std::size_t l = k + 1; l < n.size(); ++l) {
      const double det = n[k].x * n[l].y - n[k].y * n[l].x;
      if (std::fabs(det) < 1e-12) continue;
      consider({(g[k] * n[l].y - g[l] * n[k].y) / det, (n[k].x * g[l] - n[l].x * g[k]) / det});
    }
  }
  return best;
}

}  // namespace

void World::resolve_contacts(std::size_t begin, std::size_t end) {
  // why: set rules, so the result does not depend on the agents' order. First, a robot whose
  // move could bring it within reach of teammates (closer than two radii plus both moves)
  // slides: its move becomes the nearest one that closes at most half the gap to each of them
  // where they stand now (a round body pushed against another slides along it; pressed into a
  // corner of two, it stops; half each, so two closing on each other never overlap). Without
  // the slide two robots pressing into each other stand still for ever with their odometers
  // frozen, so no controller's loss rule ever turns them. All slides are computed from
  // positions before the step, then made together. Second, every robot of a pair whose proposals
  // would still overlap keeps its position (it turns as proposed); repeat until no two overlap.
  // Positions before the step never overlap, so each round blocks at least one robot more or ends.
  // Robots whose runs have ended are out of the arena
  const double r = agents_[begin]->scenario().robot.radius;
  std::fill(blocked_.begin() + static_cast<std::ptrdiff_t>(begin),
            blocked_.begin() + static_cast<std::ptrdiff_t>(end), 0);
  // why: members, so that a step allocates nothing once the first has sized them
  std::vector<std::size_t>& live = live_;
  live.clear();
  for (std::size_t i = begin; i < end; ++i) {
    if (!agents_[i]->done()) live.push_back(i);
  }
  // the slides; why the pass over pairs first: most robots are far from every other, and a
  // squared distance is all it takes to know (a team of 100 is 4950 pairs a step)
  std::vector<double>& move = move_;
  std::vector<char>& near = hit_;
  for (const std::size_t i : live) {
    const Vec2 p = agents_[i]->position(), q = agents_[i]->proposed_position();
    move[i] = agents_[i]->proposes_move() ? math::hypot(q.x - p.x, q.y - p.y) : 0.0;
    near[i] = 0;
  }
  bool any_near = false;
  for (std::size_t a = 0; a < live.size(); ++a) {
    const std::size_t i = live[a];
    const Vec2 pi = agents_[i]->position();
    for (std::size_t b = a + 1; b < live.size(); ++b) {
      const std::size_t j = live[b];
      if (move[i] == 0.0 && move[j] == 0.0) continue;
      const Vec2 pj = agents_[j]->position();
      const double reach = 2.0 * r + move[i] + move[j];
      const double dx = pi.x - pj.x, dy = pi.y - pj.y;
      if (dx * dx + dy * dy < reach * reach) near[i] = near[j] = any_near = true;
    }
  }
  bool slid = false;
  for (const std::size_t i : live) {
    slid_[i] = agents_[i]->proposed_position();
    if (!any_near || !near[i] || move[i] == 0.0) continue;
    const Vec2 p = agents_[i]->position(), q = slid_[i];
    normals_.clear();
    gaps_.clear();
    for (const std::size_t j : live) {
      if (j == i) continue;
      const Vec2 pj = agents_[j]->position();
      const double reach = 2.0 * r + move[i] + move[j];
      const double dx = pj.x - p.x, dy = pj.y - p.y;
      // why: a squared distance beyond reach^2 by more than its rounding (a few ulps) already
      // says dist >= reach, without the hypot (same bits: the same robots go on)
      if (dx * dx + dy * dy > reach * reach * (1.0 + 1e-12)) continue;
      const double dist = math::hypot(dx, dy);
      if (dist >= reach) continue;
      normals_.push_back({(pj.x - p.x) / dist, (pj.y - p.y) / dist});
      // each of the two may close half the gap, so together they never overlap
      gaps_.push_back(std::max(0.0, 0.5 * (dist - 2.0 * r)));
    }
    if (normals_.empty()) continue;
    const Vec2 v = nearest_clear_move({q.x - p.x, q.y - p.y}, normals_, gaps_);
    slid_[i] = {p.x + v.x, p.y + v.y};
    slid = true;
  }
  if (slid) {
    for (const std::size_t i : live) {
      const Vec2 q = agents_[i]->proposed_position();
      if (slid_[i].x != q.x || slid_[i].y != q.y) agents_[i]->slide(slid_[i]);
    }
  }
  // the blocks; why the nanometre: two slides that keep exactly in touch may round to an
  // overlap of a few ulps, which is no overlap of bodies
  const double d2_block = (2.0 * r - 1e-9) * (2.0 * r - 1e-9);
  std::vector<char>& hit = hit_;
  for (;;) {
    std::fill(hit.begin() + static_cast<std::ptrdiff_t>(begin),
              hit.begin() + static_cast<std::ptrdiff_t>(end), 0);
    for (std::size_t a = 0; a < live.size(); ++a) {
      const Vec2 pa = agents_[live[a]]->proposed_position();
      for (std::size_t b = a + 1; b < live.size(); ++b) {
        const Vec2 pb = agents_[live[b]]->proposed_position();
        const double dx = pa.x - pb.x, dy = pa.y - pb.y;
        if (dx * dx + dy * dy < d2_block) hit[live[a]] = hit[live[b]] = 1;
      }
    }
    bool more = false;
    for (const std::size_t i : live) {
      if (hit[i] && !blocked_[i] && agents_[i]->proposes_move()) {
        blocked_[i] = 1;
        more = true;
      }
    }
    if (!more) break;
    for (const std::size_t i : live) {
      if (blocked_[i]) agents_[i]->block();
    }
  }
}

void World::send_messages(std::size_t begin, std::size_t end) {
  // a message sent at step k reaches teammates in range at the first step at least team.delay
  // later, and never before step k + 1
  for (std::size_t i = begin; i < end; ++i) {
    if (!commands_[i].send) continue;
    const Agent& from = *agents_[i];
    const TeamParams& team = from.scenario().team;
    const auto lag =
        std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(team.delay / dt_ - 1e-9)));
    const Message m{from.index(), from.time(), commands_[i].message};
    for (std::size_t j = begin; j < end; ++j) {
      if (j == i || agents_[j]->done() || !(agents_[j]->reads() & kReadsMessages)) continue;
      const Vec2 p = sent_from_[j];
      const double d = math::hypot(p.x - sent_from_[i].x, p.y - sent_from_[i].y);
      if (d <= team.range) agents_[j]->receive(agents_[j]->steps() + lag, m);
    }
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
  return run_team(scenario, seed, trial, observer, factory).front();
}

std::vector<RunResult> run_team(const Scenario& scenario, std::uint64_t seed, std::uint64_t trial,
                                const StepObserver& observer, const ControllerFactory& factory) {
  World world({&scenario}, seed, trial, factory);
  if (observer) observer(world);
  while (!world.done()) {
    world.step();
    if (observer) observer(world);
  }
  return world.results();
}

}  // namespace plumetrace
