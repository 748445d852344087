#include "plumetrace/sim/vector_world.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "plumetrace/core/config.hpp"
#include "plumetrace/core/math.hpp"

namespace plumetrace {

int ObservationSpec::frame_width() const {
  return (odor ? 1 : 0) + (odor_fraction ? 1 : 0) + (wind ? 2 : 0) + (odometry ? 4 : 0) +
         (time ? 1 : 0);
}

void write_frame(const ObservationSpec& spec, const FrameInputs& in, float* out) {
  const Observation& seen = *in.seen;
  if (spec.odor) *out++ = static_cast<float>(in.reading);
  if (spec.odor_fraction) *out++ = static_cast<float>(in.odor_fraction);
  if (spec.wind) {
    *out++ = static_cast<float>(in.wind.x);
    *out++ = static_cast<float>(in.wind.y);
  }
  if (spec.odometry) {
    *out++ = static_cast<float>(seen.odometry.x);
    *out++ = static_cast<float>(seen.odometry.y);
    *out++ = static_cast<float>(seen.odometry.heading);
    *out++ = static_cast<float>(seen.odometer);
  }
  if (spec.time) *out++ = static_cast<float>(seen.time);
}

void observation_bounds(const ObservationSpec& spec, const Scenario& scenario,
                        std::vector<float>& low, std::vector<float>& high) {
  // why: the odometry is the true pose relative to the release pose, so |x|, |y| and the
  // odometer never exceed the path length, and the centre never drives faster than
  // robot.wheel_speed; a run lasts at most supervisor.timeout plus a step (2 steps and a relative
  // 1e-6 spare for rounding; an infinite timeout gives infinite bounds). The wind sample has
  // Gaussian noise: unbounded. A concentration is >= 0 with no upper bound.
  const double inf = std::numeric_limits<double>::infinity();
  const double dt = scenario.sim.dt;
  const double steps = std::ceil(scenario.supervisor.timeout / dt) + 2.0;
  const double duration = dt * steps * (1.0 + 1e-6);
  const double reach = scenario.robot.wheel_speed * duration;
  std::vector<double> lo, hi;
  const auto add = [&](double l, double h) {
    lo.push_back(l);
    hi.push_back(h);
  };
  if (spec.odor) add(0.0, spec.concentration ? inf : 1.0);
  if (spec.odor_fraction) add(0.0, 1.0);
  if (spec.wind) {
    add(-inf, inf);
    add(-inf, inf);
  }
  if (spec.odometry) {
    add(-reach, reach);
    add(-reach, reach);
    add(-kPi, kPi);
    add(0.0, reach);
  }
  if (spec.time) add(0.0, duration);
  low.clear();
  high.clear();
  for (int s = 0; s < spec.stack; ++s) {
    // why: float bounds rounded as the observations are (rounding keeps a value within them)
    for (const double v : lo) low.push_back(static_cast<float>(v));
    for (const double v : hi) high.push_back(static_cast<float>(v));
  }
}

Command action_command(ActionMode mode, int headings, double a, double odometry_heading) {
  switch (mode) {
    case ActionMode::kHeading:
      return Command::go(kPi * std::clamp(a, -1.0, 1.0));
    case ActionMode::kTurn:
      return Command::go(wrap_angle(odometry_heading + kPi * std::clamp(a, -1.0, 1.0)));
    case ActionMode::kDiscrete:
      break;
  }
  return Command::go(wrap_angle(2.0 * kPi * a / static_cast<double>(headings)));
}

void check_agent_options(int decision_interval, const ObservationSpec& observe, ActionMode action,
                         int headings) {
  const auto refuse = [](const std::string& why) { throw std::invalid_argument(why); };
  if (decision_interval < 1) {
    refuse("decision_interval = " + std::to_string(decision_interval) + ": must be >= 1");
  }
  if (observe.stack < 1 || observe.stack > 1024) {
    refuse("stack = " + std::to_string(observe.stack) + ": must be from 1 to 1024");
  }
  if (observe.frame_width() == 0) refuse("observations: at least one value is observed");
  if (action == ActionMode::kDiscrete && headings < 1) {
    refuse("discrete_headings = " + std::to_string(headings) + ": must be >= 1");
  }
}

namespace {

// The controller of an agent driven from outside: it is never asked to decide.
class HeldController : public Controller {
 public:
  Command step(const Observation&, WindProbe&) override {
    throw std::logic_error("a VectorWorld agent is driven by actions, not by a controller");
  }
  std::string_view state() const override { return "external"; }
  int losses() const override { return 0; }
};

double source_distance(const Scenario& scenario, const RobotState& robot) {
  return math::hypot(robot.pose.x - scenario.source.center.x,
                     robot.pose.y - scenario.source.center.y);
}

}  // namespace

struct VectorWorld::Group {
  Environment env;
};

struct VectorWorld::Slot {
  std::unique_ptr<Agent> agent;
  std::uint64_t seed = 0;
  std::uint64_t episode = 0;
  bool waiting = false;         // its episode has ended: the next step starts another
  double start_distance = 1.0;  // to the source at release (m)
  double distance = 0.0;        // to the source at the last decision (m)
  Observation seen;             // the last sensing
  Command command;              // the decision's command
  int sensed = 0;               // sensings in the decision so far
  int odor_count = 0;           // of which with odor
  Vec2 wind{0.0, 0.0};          // the last wind sample (robot frame, m/s)
};

// A processor's hint that the thread is spinning (lets the other hyperthread run).
inline void spin_pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// A pool of threads that wait between calls, so a step costs no thread start.
// why: a step is a few phases of a millisecond or less, and waking a sleeping thread costs tens
// of microseconds (more in a virtual machine): the threads and the caller spin for a while
// (kSpins pauses, some tens of microseconds) before they sleep, so the phases of one step follow
// each other without a wake-up, and a pool left idle sleeps
class VectorWorld::Pool {
 public:
  explicit Pool(int extra) {
    for (int t = 0; t < extra; ++t) {
      try {
        threads_.emplace_back([this] { serve(); });
      } catch (const std::system_error&) {
        break;  // why: the jobs share one counter, so fewer threads only take longer
      }
    }
  }
  ~Pool() {
    {
      const std::lock_guard lock(mutex_);
      stop_.store(true);
    }
    wake_.notify_all();
    for (auto& t : threads_) t.join();
  }

  // calls job(i) for every i in [0, n) on the pool and the caller; rethrows the first exception
  void run(std::size_t n, const std::function<void(std::size_t)>& job) {
    if (threads_.empty() || n < 2) {
      for (std::size_t i = 0; i < n; ++i) job(i);
      return;
    }
    {
      const std::lock_guard lock(mutex_);
      job_ = &job;
      n_ = n;
      next_.store(0);
      busy_.store(threads_.size());
      failure_ = nullptr;
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    work();
    for (int spin = 0; spin < kSpins && busy_.load(std::memory_order_acquire) != 0; ++spin) {
      spin_pause();
    }
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return busy_.load() == 0; });
    job_ = nullptr;
    if (failure_) std::rethrow_exception(failure_);
  }

 private:
  static constexpr int kSpins = 1 << 11;

  void work() {
    try {
      for (std::size_t i = next_++; i < n_; i = next_++) (*job_)(i);
    } catch (...) {
      const std::lock_guard lock(mutex_);
      if (!failure_) failure_ = std::current_exception();
      next_ = n_;
    }
  }
  void serve() {
    std::uint64_t seen = 0;
    for (;;) {
      const auto called = [&] {
        return stop_.load(std::memory_order_acquire) ||
               generation_.load(std::memory_order_acquire) != seen;
      };
      for (int spin = 0; spin < kSpins && !called(); ++spin) spin_pause();
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, called);
        if (stop_.load()) return;
        seen = generation_.load();
      }
      work();
      {
        const std::lock_guard lock(mutex_);
        busy_.fetch_sub(1, std::memory_order_acq_rel);
      }
      done_.notify_one();
    }
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t n_ = 0;
  std::atomic<std::size_t> next_{0};
  std::atomic<std::size_t> busy_{0};
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<bool> stop_{false};
  std::exception_ptr failure_;
};

VectorWorld::VectorWorld(const Scenario& scenario, const VectorSpec& spec)
    : scenario_(scenario), spec_(spec) {
  const auto refuse = [](const std::string& why) { throw std::invalid_argument(why); };
  if (spec.envs < 1 || spec.envs > kMaxVectorEnvs) {
    refuse("num_envs = " + std::to_string(spec.envs) + ": must be from 1 to " +
           std::to_string(kMaxVectorEnvs));
  }
  if (spec.group < 1 || spec.envs % spec.group != 0) {
    refuse("group_size = " + std::to_string(spec.group) +
           ": must divide num_envs = " + std::to_string(spec.envs));
  }
  if (spec.renew_plumes && spec.group != 1) {
    refuse("renew_plumes: a fresh plume per episode needs group_size = 1, not " +
           std::to_string(spec.group));
  }
  check_agent_options(spec.decision_interval, spec.observe, spec.action, spec.headings);
  if (scenario.team.count != 1) {
    refuse("team.count = " + std::to_string(scenario.team.count) +
           ": a vector environment drives one robot per environment (a team: TeamPlumeEnv)");
  }
  const auto n = static_cast<std::size_t>(spec.envs);
  for (std::size_t g = 0; g < n / static_cast<std::size_t>(spec.group); ++g) {
    groups_.push_back(std::make_unique<Group>());
  }
  for (std::size_t i = 0; i < n; ++i) slots_.push_back(std::make_unique<Slot>());
  obs_.assign(n * static_cast<std::size_t>(spec.observe.width()), 0.0f);
  reward_.assign(n, 0.0);
  terminated_.assign(n, 0);
  truncated_.assign(n, 0);
  reset_mask_.assign(n, 0);
  for (auto* v :
       {&info_.time, &info_.x, &info_.y, &info_.heading, &info_.source_distance, &info_.odometer}) {
    v->assign(n, 0.0);
  }
  info_.outcome.assign(n, 0);
  info_.seed.assign(n, 0);
  info_.episode.assign(n, 0);
  const std::size_t jobs = std::max(groups_.size(), (n + kChunk - 1) / kChunk);
  const int threads = std::clamp(spec.threads, 1, static_cast<int>(jobs));
  pool_ = std::make_unique<Pool>(threads - 1);
}

VectorWorld::~VectorWorld() = default;

void VectorWorld::run_groups(void (VectorWorld::*job)(std::size_t)) {
  pool_->run(groups_.size(), [&](std::size_t g) { (this->*job)(g); });
}

void VectorWorld::reset(std::span<const std::uint64_t> seeds) {
  if (seeds.size() != slots_.size()) {
    throw std::invalid_argument("seed: " + std::to_string(seeds.size()) + " seeds for " +
                                std::to_string(slots_.size()) + " environments");
  }
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    slots_[i]->seed = seeds[i];
    slots_[i]->episode = 0;
  }
  run_groups(&VectorWorld::restart_group);
}

void VectorWorld::reset_some(std::span<const std::uint8_t> mask) {
  if (mask.size() != slots_.size()) {
    throw std::invalid_argument("reset_mask: " + std::to_string(mask.size()) + " flags for " +
                                std::to_string(slots_.size()) + " environments");
  }
  if (!slots_.front()->agent) throw std::logic_error("reset_mask: call reset() without it first");
  std::copy(mask.begin(), mask.end(), reset_mask_.begin());
  run_groups(&VectorWorld::reset_group);
}

void VectorWorld::reset_next() {
  if (!slots_.front()->agent) throw std::logic_error("call reset() with seeds first");
  for (auto& s : slots_) ++s->episode;
  run_groups(&VectorWorld::restart_group);
}

void VectorWorld::restart_group(std::size_t g) {
  // new plume (run (seed of the group's first environment, 0)'s), warmed up; every agent
  // released into it, then one step of the plume and each one's first sensing, as a run starts
  const auto k = static_cast<std::size_t>(spec_.group);
  Group& group = *groups_[g];
  const Slot& first = *slots_[g * k];
  group.env = make_environment(scenario_, first.seed, first.episode);
  warm_up(scenario_, group.env);
  for (std::size_t i = g * k; i < (g + 1) * k; ++i) start_episode(i, true);
}

void VectorWorld::reset_group(std::size_t g) {
  const auto k = static_cast<std::size_t>(spec_.group);
  for (std::size_t i = g * k; i < (g + 1) * k; ++i) {
    if (!reset_mask_[i]) continue;
    Slot& s = *slots_[i];
    if (s.agent) ++s.episode;
    if (spec_.renew_plumes) {
      restart_group(g);
    } else {
      start_episode(i, false);
    }
    reward_[i] = 0.0;
    terminated_[i] = truncated_[i] = 0;
  }
}

void VectorWorld::start_episode(std::size_t i, bool fresh_plume) {
  const auto k = static_cast<std::size_t>(spec_.group);
  Group& group = *groups_[i / k];
  Slot& s = *slots_[i];
  s.agent = std::make_unique<Agent>(scenario_, s.seed, s.episode, 0,
                                    std::make_unique<HeldController>(), group.env);
  if (scenario_.start.region == StartRegion::kPoint &&
      scenario_.start.heading == StartHeading::kFixed) {
    s.agent->release();
  } else {
    s.agent->release(team_starts(scenario_, s.seed, s.episode, group.env).front());
  }
  // why: the plume's step before the first sensing, as World::observe makes it; once per group
  if (fresh_plume && i % k == k - 1) plumetrace::step(group.env, scenario_.sim.dt);
  s.waiting = false;
  s.start_distance = std::max(source_distance(scenario_, s.agent->robot()),
                              std::max(scenario_.supervisor.success_radius, 1e-9));
  s.distance = source_distance(scenario_, s.agent->robot());
  if (!fresh_plume || i % k == k - 1) {
    // sense once the plume has made its step (every agent of a fresh group senses after the last
    // is released)
    for (std::size_t j = fresh_plume ? i + 1 - k : i; j <= i; ++j) {
      Slot& t = *slots_[j];
      const unsigned reads = spec_.observe.concentration ? kReadsConcentration : kReadsBinary;
      t.seen = t.agent->sense(reads);
      finish_decision(j, &t.seen, 1, t.seen.odor ? 1 : 0);
      // a new episode: every frame of the stack is its first
      const auto width = static_cast<std::size_t>(spec_.observe.frame_width());
      float* row = obs_.data() + j * static_cast<std::size_t>(spec_.observe.width());
      for (int f = 1; f < spec_.observe.stack; ++f) {
        std::memcpy(row + static_cast<std::size_t>(f) * width, row, width * sizeof(float));
      }
      reward_[j] = 0.0;
      terminated_[j] = truncated_[j] = 0;
      write_info(j);
    }
  }
}

void VectorWorld::finish_decision(std::size_t i, const Observation* seen, int sensed,
                                  int odor_count) {
  Slot& s = *slots_[i];
  const ObservationSpec& o = spec_.observe;
  float* row = obs_.data() + i * static_cast<std::size_t>(o.width());
  if (sensed == 0) return;  // why: a run that ended at the decision's first step senses nothing
  FrameInputs in;
  in.seen = seen;
  in.reading = o.concentration ? s.agent->reading() : (seen->odor ? 1.0 : 0.0);
  in.odor_fraction = static_cast<double>(odor_count) / static_cast<double>(sensed);
  // why: once the run has ended its terminal frame repeats the last sample: a new one would count
  // in the run's wind_samples, which a controller never takes after the end
  if (o.wind && !s.agent->done()) s.wind = s.agent->wind_probe().measure_wind_body();
  in.wind = s.wind;
  const auto width = static_cast<std::size_t>(o.frame_width());
  if (o.stack > 1) {
    std::memmove(row + width, row, width * static_cast<std::size_t>(o.stack - 1) * sizeof(float));
  }
  write_frame(o, in, row);
}

void VectorWorld::step(std::span<const double> actions) {
  if (actions.size() != slots_.size()) {
    throw std::invalid_argument("actions: " + std::to_string(actions.size()) + " actions for " +
                                std::to_string(slots_.size()) + " environments");
  }
  if (!slots_.front()->agent) throw std::logic_error("call reset() before step()");
  for (std::size_t i = 0; i < actions.size(); ++i) {
    const double a = actions[i];
    if (!std::isfinite(a)) {
      throw std::invalid_argument("actions[" + std::to_string(i) + "] = " + format_number(a) +
                                  ": an action must be a finite number");
    }
    if (spec_.action == ActionMode::kDiscrete &&
        (a != std::floor(a) || a < 0.0 || a >= static_cast<double>(spec_.headings))) {
      throw std::invalid_argument("actions[" + std::to_string(i) + "] = " + format_number(a) +
                                  ": an index from 0 to " + std::to_string(spec_.headings - 1));
    }
  }
  actions_ = actions;
  // why: robots do not disturb the plume, so between two plume steps every agent's work (its
  // sensing, then its move) is its own, and the agents are split among the threads in chunks
  // whatever the groups: one plume of n agents keeps every core busy. Each plume steps alone,
  // in its own phase; the order of each agent's and each plume's operations is that of one run,
  // so the results do not depend on the threads
  const int d = spec_.decision_interval;
  for (int step_no = 0; step_no <= d; ++step_no) {
    run_agents([this, step_no](std::size_t i) { agent_phase(i, step_no); });
    if (step_no < d) run_groups(&VectorWorld::step_plume);
  }
}

void VectorWorld::run_agents(const std::function<void(std::size_t)>& job) {
  const std::size_t n = slots_.size();
  pool_->run((n + kChunk - 1) / kChunk, [&](std::size_t c) {
    for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) job(i);
  });
}

void VectorWorld::step_plume(std::size_t g) {
  const auto k = static_cast<std::size_t>(spec_.group);
  // why: with a fresh plume per episode, a plume whose only agent waits is replaced, not stepped;
  // a shared plume keeps the group's clock whoever runs on it
  bool anyone = !spec_.renew_plumes;
  for (std::size_t i = g * k; i < (g + 1) * k && !anyone; ++i) anyone = !slots_[i]->waiting;
  if (anyone) plumetrace::step(groups_[g]->env, scenario_.sim.dt);
}

void VectorWorld::agent_phase(std::size_t i, int step_no) {
  Slot& s = *slots_[i];
  if (step_no == 0) {
    // the command for the decision, from the action
    reward_[i] = 0.0;
    terminated_[i] = truncated_[i] = 0;
    s.sensed = s.odor_count = 0;
    if (!s.waiting) {
      s.command =
          action_command(spec_.action, spec_.headings, actions_[i], s.seen.odometry.heading);
    }
  } else if (!s.waiting && !s.agent->done()) {
    // the sensing after the plume's step
    s.seen = s.agent->sense(spec_.observe.concentration ? kReadsConcentration : kReadsBinary);
    ++s.sensed;
    if (s.seen.odor) ++s.odor_count;
  }
  if (step_no < spec_.decision_interval) {
    if (s.waiting || s.agent->done()) return;
    s.agent->act(s.command);
    if (s.agent->outcome() == Outcome::kSuccess) reward_[i] += 1.0;
    return;
  }
  if (s.waiting) {
    // the episode ended at the last step: the next one starts on the plume as it is now
    ++s.episode;
    if (spec_.renew_plumes) {
      restart_group(i);  // why: group_size = 1, so group i is environment i's alone
    } else {
      start_episode(i, false);
    }
    return;
  }
  finish_decision(i, &s.seen, s.sensed, s.odor_count);
  if (spec_.reward == RewardMode::kShaped) {
    const double dist = source_distance(scenario_, s.agent->robot());
    reward_[i] += (s.distance - dist) / s.start_distance;
    s.distance = dist;
  }
  const Outcome out = s.agent->outcome();
  truncated_[i] = out == Outcome::kTimeout;
  terminated_[i] = out != Outcome::kRunning && out != Outcome::kTimeout;
  s.waiting = out != Outcome::kRunning;
  write_info(i);
}

void VectorWorld::write_info(std::size_t i) {
  const Slot& s = *slots_[i];
  const RobotState& r = s.agent->robot();
  info_.outcome[i] = static_cast<std::int8_t>(s.agent->outcome());
  info_.time[i] = s.agent->time();
  info_.x[i] = r.pose.x;
  info_.y[i] = r.pose.y;
  info_.heading[i] = r.pose.heading;
  info_.source_distance[i] = source_distance(scenario_, r);
  info_.odometer[i] = r.odometer;
  info_.seed[i] = s.seed;
  info_.episode[i] = s.episode;
}

RunResult VectorWorld::result(std::size_t i) const {
  const Agent* a = agent(i);
  if (a == nullptr) throw std::logic_error("call reset() before result()");
  return a->result();
}

const Environment& VectorWorld::plume(std::size_t g) const { return groups_.at(g)->env; }

const Agent* VectorWorld::agent(std::size_t i) const { return slots_.at(i)->agent.get(); }

}  // namespace plumetrace
