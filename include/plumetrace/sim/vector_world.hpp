#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// What a learning agent observes at a decision, value by value (docs/vector.md, "Observations").
/// A frame holds, in this order, the values whose flag is set: odor (1: 0 or 1, or with
/// `concentration` the odor sensor's reading), odor fraction (1: the share of the decision's
/// sensings that perceived odor), wind (2: one noisy sample in the robot frame, m/s), odometry
/// (4: x, y, heading relative to the release pose, and the odometer; m, m, rad, m), time (1: s
/// since release). An observation is `stack` frames, the newest first.
struct ObservationSpec {
  bool odor = true;
  bool concentration = false;
  bool odor_fraction = false;
  bool wind = true;
  bool odometry = true;
  bool time = false;
  int stack = 1;

  /// Values per frame.
  int frame_width() const;
  /// Values per observation (frame_width() * stack).
  int width() const { return frame_width() * stack; }
};

/// Everything a frame is made of at the end of a decision.
struct FrameInputs {
  const Observation* seen = nullptr;  ///< the decision's last sensing
  double reading = 0.0;               ///< the odor value (0/1, or the sensor's reading)
  double odor_fraction = 0.0;         ///< share of the decision's sensings with odor
  Vec2 wind{0.0, 0.0};                ///< the wind sample (robot frame, m/s)
};

/// Writes one frame (spec.frame_width() floats) at `out`.
void write_frame(const ObservationSpec& spec, const FrameInputs& in, float* out);

/// Finite lower and upper bounds of each value of an observation (width() of each), from the
/// scenario (docs/vector.md): the odometry never exceeds the path a run can drive, the time the
/// timeout; a concentration has no upper bound and a wind sample none at all (infinities).
void observation_bounds(const ObservationSpec& spec, const Scenario& scenario,
                        std::vector<float>& low, std::vector<float>& high);

/// How an action becomes a command (docs/vector.md, "Actions").
enum class ActionMode {
  kHeading,   ///< a in [-1, 1]: go along heading pi a (rad, odometry frame; 0 is the start's)
  kTurn,      ///< a in [-1, 1]: go along the current odometry heading plus pi a
  kDiscrete,  ///< an index i of n: go along heading 2 pi i / n
};

/// The command of action `a` (docs/vector.md, "Actions"): kHeading, kTurn: a in [-1, 1],
/// clipped, kTurn turning from `odometry_heading` (rad, the robot's at its last sensing);
/// kDiscrete: an index of `headings`.
Command action_command(ActionMode mode, int headings, double a, double odometry_heading);

/// Checks the options a learning agent's decisions share (std::invalid_argument naming the
/// option): decision_interval >= 1, a stack of 1 to 1024 frames of at least one value, and
/// with kDiscrete at least one heading.
void check_agent_options(int decision_interval, const ObservationSpec& observe, ActionMode action,
                         int headings);

/// The reward of a decision (docs/vector.md, "Rewards").
enum class RewardMode {
  kSuccess,  ///< 1 at the step the run succeeds, else 0
  kShaped,   ///< kSuccess plus the decrease of the distance to the source over the distance at
             ///< release
};

/// A vector environment's options (docs/vector.md).
struct VectorSpec {
  int envs = 1;               ///< environments (agents), 1 to kMaxVectorEnvs
  int group = 1;              ///< environments per plume; divides envs
  bool renew_plumes = false;  ///< group = 1 only: a fresh plume for every episode
  int decision_interval = 1;  ///< simulation steps an action is held
  ObservationSpec observe;    ///< what is observed
  ActionMode action = ActionMode::kHeading;
  int headings = 0;  ///< kDiscrete: the number of headings n
  RewardMode reward = RewardMode::kSuccess;
  int threads = 1;  ///< worker threads (the agents, in chunks, and the plumes are split among them)
};

/// The most environments one VectorWorld holds (each takes a few kB, docs/vector.md).
inline constexpr int kMaxVectorEnvs = 1 << 16;

/// Many one-robot runs stepped together by an outside decision maker (a learning agent), groups
/// of `group` runs on one running plume each (docs/vector.md). Robots do not disturb the plume,
/// so a group's agents see exactly the plume one of them would see alone; an agent whose episode
/// ends starts a new one on its group's plume at the next step (Gymnasium's "next step"
/// autoreset). Environment i's episode e draws its robot's streams as run (seed_i, e) does, and
/// group g's plume is run (seed_{g K}, 0)'s; with renew_plumes, environment i's episode e is
/// exactly run (seed_i, e) driven by the same actions. Results do not depend on `threads`.
class VectorWorld {
 public:
  /// Checks the options against the scenario (std::invalid_argument naming the option).
  VectorWorld(const Scenario& scenario, const VectorSpec& spec);
  ~VectorWorld();
  VectorWorld(const VectorWorld&) = delete;
  VectorWorld& operator=(const VectorWorld&) = delete;

  /// Starts every environment afresh (new plumes, warmed up) with environment i's seed
  /// seeds[i] and its episode count at 0; or, with `mask` (one flag per environment), starts a
  /// new episode on the running plume for the flagged environments only, seeds unchanged.
  void reset(std::span<const std::uint64_t> seeds);
  void reset_some(std::span<const std::uint8_t> mask);
  /// Starts every environment's next episode on new plumes (group g's from the episode number
  /// of its first environment), seeds unchanged.
  void reset_next();
  /// One decision of every environment: actions[i] (kHeading, kTurn: in [-1, 1], clipped;
  /// kDiscrete: an index, checked before anything moves). An environment whose episode ended at
  /// the last step ignores its action and starts its next episode instead (reward 0, neither
  /// terminated nor truncated).
  void step(std::span<const double> actions);

  const VectorSpec& spec() const { return spec_; }
  const Scenario& scenario() const { return scenario_; }
  /// Observations, envs x width(), row-major.
  const std::vector<float>& observations() const { return obs_; }
  const std::vector<double>& rewards() const { return reward_; }
  const std::vector<std::uint8_t>& terminated() const { return terminated_; }
  const std::vector<std::uint8_t>& truncated() const { return truncated_; }

  /// Per environment, for infos: the outcome code (Outcome's value, named by kOutcomeNames), the
  /// time since release (s), the true pose (m, rad) and distance to the source (m), the odometer
  /// (m), the seed and episode number.
  struct Info {
    std::vector<std::int8_t> outcome;
    std::vector<double> time, x, y, heading, source_distance, odometer;
    std::vector<std::uint64_t> seed, episode;
  };
  const Info& info() const { return info_; }

  /// Environment i's run result so far (its current episode).
  RunResult result(std::size_t i) const;
  /// Plume g's environment (for drawing).
  const Environment& plume(std::size_t g) const;
  /// Environment i's agent (null before the first reset).
  const Agent* agent(std::size_t i) const;

 private:
  struct Slot;
  struct Group;
  void run_groups(void (VectorWorld::*job)(std::size_t));
  void reset_group(std::size_t g);
  void restart_group(std::size_t g);
  // one job per chunk of kChunk environments
  void run_agents(const std::function<void(std::size_t)>& job);
  void step_plume(std::size_t g);
  // environment i's part of a decision's step step_no (0 to decision_interval): its command
  // (step 0) or its sensing after the plume's step, then its move or, at the last, its
  // observation, reward and infos
  void agent_phase(std::size_t i, int step_no);
  void start_episode(std::size_t i, bool fresh_plume);
  void finish_decision(std::size_t i, const Observation* seen, int sensed, int odor_count);
  void write_info(std::size_t i);

  Scenario scenario_;
  VectorSpec spec_;
  std::vector<std::unique_ptr<Group>> groups_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::vector<float> obs_;
  std::vector<double> reward_;
  std::vector<std::uint8_t> terminated_, truncated_;
  std::vector<std::uint8_t> reset_mask_;
  std::span<const double> actions_;
  Info info_;

  // a pool of spec.threads - 1 workers that wait between calls
  class Pool;
  std::unique_ptr<Pool> pool_;
  static constexpr std::size_t kChunk = 16;
};

}  // namespace plumetrace
