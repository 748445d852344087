#include "plumetrace/sim/team_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

// The controller of a robot decided from outside: it is never asked to decide, only what it
// reads.
class ActionController : public Controller {
 public:
  explicit ActionController(unsigned reads) : reads_(reads) {}
  Command step(const Observation&, WindProbe&) override {
    throw std::logic_error("a TeamWorld robot is driven by actions, not by a controller");
  }
  std::string_view state() const override { return "external"; }
  int losses() const override { return 0; }
  unsigned reads() const override { return reads_; }

 private:
  unsigned reads_;
};

double distance_to_source(const Scenario& scenario, const RobotState& robot) {
  return math::hypot(robot.pose.x - scenario.source.center.x,
                     robot.pose.y - scenario.source.center.y);
}

}  // namespace

TeamWorld::TeamWorld(const Scenario& scenario, const TeamSpec& spec)
    : scenario_(scenario), spec_(spec) {
  check_agent_options(spec.decision_interval, spec.observe, spec.action, spec.headings);
  const std::size_t n = size();
  for (std::size_t k = 0; k < n; ++k) {
    robots_.push_back(k == 0 ? scenario : member_scenario(scenario, static_cast<int>(k)));
  }
  obs_.assign(n * static_cast<std::size_t>(spec.observe.width()), 0.0f);
  reward_.assign(n, 0.0);
  terminated_.assign(n, 0);
  truncated_.assign(n, 0);
  start_distance_.assign(n, 1.0);
  distance_.assign(n, 0.0);
  commands_.assign(n, Command{});
  moving_.assign(n, 0);
  decided_.assign(n, 0);
  sensed_.assign(n, 0);
  odor_count_.assign(n, 0);
  last_.assign(n, Observation{});
  wind_.assign(n, Vec2{0.0, 0.0});
}

TeamWorld::~TeamWorld() = default;

const World& TeamWorld::world() const {
  if (!world_) throw std::logic_error("call reset() first");
  return *world_;
}

double TeamWorld::source_distance(std::size_t i) const {
  return distance_to_source(scenario_, world().agent(i).robot());
}

void TeamWorld::reset(std::uint64_t seed, std::uint64_t trial) {
  const unsigned reads = spec_.observe.concentration ? kReadsConcentration : kReadsBinary;
  const ControllerFactory held = [reads](const Scenario&, Rng) {
    return std::make_unique<ActionController>(reads);
  };
  // why: the team constructor builds each robot as run (seed, trial) does, members included
  world_.reset();
  world_ = std::make_unique<World>(std::vector<const Scenario*>{&scenario_}, seed, trial, held);
  const std::vector<Observation>& seen = world_->observe_team();
  const auto width = static_cast<std::size_t>(spec_.observe.frame_width());
  for (std::size_t i = 0; i < size(); ++i) {
    const double d = source_distance(i);
    start_distance_[i] = std::max(d, std::max(scenario_.supervisor.success_radius, 1e-9));
    distance_[i] = d;
    last_[i] = seen[i];
    finish_decision(i, 1, seen[i].odor ? 1 : 0);
    // a new episode: every frame of the stack is its first
    float* row = obs_.data() + i * static_cast<std::size_t>(spec_.observe.width());
    for (int f = 1; f < spec_.observe.stack; ++f) {
      std::memcpy(row + static_cast<std::size_t>(f) * width, row, width * sizeof(float));
    }
    reward_[i] = 0.0;
    terminated_[i] = truncated_[i] = 0;
  }
}

void TeamWorld::step(std::span<const double> actions) {
  if (!world_) throw std::logic_error("call reset() before step()");
  if (world_->done()) throw std::logic_error("every robot's run has ended: call reset()");
  const std::size_t n = size();
  if (actions.size() != n) {
    throw std::invalid_argument("actions: " + std::to_string(actions.size()) + " actions for " +
                                std::to_string(n) + " robots");
  }
  // every running robot's action, checked before anything changes
  for (std::size_t i = 0; i < n; ++i) {
    if (world_->agent(i).done()) continue;
    const double a = actions[i];
    const auto refuse = [&](const std::string& why) {
      throw std::invalid_argument("actions[" + std::to_string(i) + "] (robot " + std::to_string(i) +
                                  ") = " + format_number(a) + ": " + why);
    };
    if (!std::isfinite(a)) refuse("not a finite number");
    if (spec_.action == ActionMode::kDiscrete &&
        (a != std::floor(a) || a < 0.0 || a >= static_cast<double>(spec_.headings))) {
      refuse("not an index from 0 to " + std::to_string(spec_.headings - 1));
    }
  }
  // each running robot's command for the decision
  for (std::size_t i = 0; i < n; ++i) {
    reward_[i] = 0.0;
    sensed_[i] = odor_count_[i] = 0;
    decided_[i] = !world_->agent(i).done();
    commands_[i] = decided_[i] ? action_command(spec_.action, spec_.headings, actions[i],
                                                last_[i].odometry.heading)
                               : Command{};
  }
  for (int step_no = 0; step_no < spec_.decision_interval; ++step_no) {
    for (std::size_t i = 0; i < n; ++i) moving_[i] = !world_->agent(i).done();
    world_->act_team(commands_);
    for (std::size_t i = 0; i < n; ++i) {
      if (moving_[i] && world_->agent(i).outcome() == Outcome::kSuccess) reward_[i] += 1.0;
    }
    if (world_->done()) break;
    const std::vector<Observation>& seen = world_->observe_team();
    for (std::size_t i = 0; i < n; ++i) {
      if (world_->agent(i).done()) continue;
      last_[i] = seen[i];
      ++sensed_[i];
      if (seen[i].odor) ++odor_count_[i];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!decided_[i]) continue;
    finish_decision(i, sensed_[i], odor_count_[i]);
    if (spec_.reward == RewardMode::kShaped) {
      const double d = source_distance(i);
      reward_[i] += (distance_[i] - d) / start_distance_[i];
      distance_[i] = d;
    }
    const Outcome out = world_->agent(i).outcome();
    truncated_[i] = out == Outcome::kTimeout;
    terminated_[i] = out != Outcome::kRunning && out != Outcome::kTimeout;
  }
}

void TeamWorld::finish_decision(std::size_t i, int sensed, int odor_count) {
  // why: a run that ended at the decision's first step senses nothing: its frame stays
  if (sensed == 0) return;
  const ObservationSpec& o = spec_.observe;
  const Observation& seen = last_[i];
  FrameInputs in;
  in.seen = &seen;
  in.reading = o.concentration ? seen.concentration : (seen.odor ? 1.0 : 0.0);
  in.odor_fraction = static_cast<double>(odor_count) / static_cast<double>(sensed);
  // why: no sample once the run has ended (it would count in the run's wind_samples); the last
  // one stands
  if (o.wind && !world_->agent(i).done()) wind_[i] = world_->wind_probe(i).measure_wind_body();
  in.wind = wind_[i];
  float* row = obs_.data() + i * static_cast<std::size_t>(o.width());
  const auto width = static_cast<std::size_t>(o.frame_width());
  if (o.stack > 1) {
    std::memmove(row + width, row, width * static_cast<std::size_t>(o.stack - 1) * sizeof(float));
  }
  write_frame(o, in, row);
}

}  // namespace plumetrace
