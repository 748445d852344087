#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/vector_world.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// A team environment's options (docs/vector.md, "Teams"): a vector environment's, for every
/// robot of the team.
struct TeamSpec {
  int decision_interval = 1;  ///< simulation steps an action is held
  ObservationSpec observe;    ///< what each robot observes
  ActionMode action = ActionMode::kHeading;
  int headings = 0;  ///< kDiscrete: the number of headings n
  RewardMode reward = RewardMode::kSuccess;
};

/// The scenario's team (team.count robots on one plume, with its contacts and messages),
/// every robot decided from outside by actions (docs/vector.md, "Teams"). A decision holds each
/// robot's action for decision_interval steps of World::observe_team and World::act_team; a
/// robot whose run ends stops there while the others go on, and the episode ends when every
/// run has. Episode (seed, trial) is run (seed, trial) of the scenario, each robot with the
/// random streams it has there, so actions that give the commands the robots' controllers would
/// give reproduce the built-in run bit for bit.
class TeamWorld {
 public:
  /// Checks the options (std::invalid_argument naming the option).
  TeamWorld(const Scenario& scenario, const TeamSpec& spec);
  ~TeamWorld();
  TeamWorld(const TeamWorld&) = delete;
  TeamWorld& operator=(const TeamWorld&) = delete;

  /// Starts episode (seed, trial): a fresh world, warmed up, every robot released and sensing
  /// once (every frame of a stack is that first one).
  void reset(std::uint64_t seed, std::uint64_t trial);
  /// One decision: actions[i] is robot i's (kHeading, kTurn: clipped to [-1, 1]; kDiscrete: an
  /// index), ignored for a robot whose run has ended. Checked before anything moves
  /// (std::invalid_argument naming the robot); std::logic_error before reset() and once every
  /// run has ended.
  void step(std::span<const double> actions);

  /// The robots.
  std::size_t size() const { return static_cast<std::size_t>(scenario_.team.count); }
  const TeamSpec& spec() const { return spec_; }
  const Scenario& scenario() const { return scenario_; }
  /// Robot i's scenario (its own keys in a mixed team).
  const Scenario& robot_scenario(std::size_t i) const { return robots_.at(i); }
  /// Observations, size() x observe.width(), row-major; a robot whose run has ended keeps its
  /// last.
  const std::vector<float>& observations() const { return obs_; }
  /// The last decision's rewards (0 for a robot whose run had ended before it).
  const std::vector<double>& rewards() const { return reward_; }
  /// The run ended in a state of the task (success, wall, gave up, wrong declaration).
  const std::vector<std::uint8_t>& terminated() const { return terminated_; }
  /// The run reached supervisor.timeout.
  const std::vector<std::uint8_t>& truncated() const { return truncated_; }
  /// True while every run has not ended.
  bool running() const { return world_ && !world_->done(); }
  /// The episode's world (std::logic_error before reset()).
  const World& world() const;
  /// Robot i's distance to the source now (m).
  double source_distance(std::size_t i) const;

 private:
  void finish_decision(std::size_t i, int sensed, int odor_count);

  Scenario scenario_;
  TeamSpec spec_;
  std::vector<Scenario> robots_;
  std::unique_ptr<World> world_;
  std::vector<float> obs_;
  std::vector<double> reward_;
  std::vector<std::uint8_t> terminated_, truncated_;
  std::vector<double> start_distance_, distance_;  // to the source at release, at the last decision
  std::vector<Command> commands_;                  // this decision's
  std::vector<char> decided_;                      // this decision: the robot's run had not ended
  std::vector<char> moving_;                       // this step: the robot's run had not ended
  std::vector<int> sensed_, odor_count_;           // this decision's sensings
  std::vector<Observation> last_;                  // each robot's last sensing
  std::vector<Vec2> wind_;  // each robot's last wind sample (robot frame, m/s)
};

}  // namespace plumetrace
