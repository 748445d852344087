#include "plumetrace/experiment/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "plumetrace/core/errors.hpp"

namespace plumetrace {

std::string hash_text(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string campaign_definition(const std::vector<ExpandedSweep>& sweeps) {
  using nlohmann::json;
  const auto value_json = [](const ConfigValue& v) {
    return std::visit([](const auto& x) { return json(x); }, v);
  };
  json all = json::array();
  for (const auto& s : sweeps) {
    json axes = json::array();
    for (const auto& a : s.def.axes) {
      json values = json::array();
      for (const auto& v : a.values) values.push_back(value_json(v));
      axes.push_back({{"key", a.key}, {"values", values}});
    }
    json points = json::array();
    for (const auto& p : s.points) points.push_back(p.config_hash);
    all.push_back({{"name", s.def.name},
                   {"seed", std::to_string(s.def.seed)},
                   {"axes", axes},
                   {"point_configs", points}});
  }
  return json{{"sweeps", all}}.dump();
}

std::string axis_values_text(const SweepDef& def, const SweepPoint& point) {
  std::string text;
  for (std::size_t a = 0; a < point.values.size() && a < def.axes.size(); ++a) {
    text += (a ? ", " : "") + def.axes[a].key + " = " + format_value(point.values[a]);
  }
  return text;
}

namespace {

// the file a sweep came from, or its name, for messages
std::string sweep_where(const SweepDef& def) {
  return def.file.empty() ? "sweep " + def.name : def.file;
}

}  // namespace

std::int64_t grid_points(const SweepDef& def) {
  std::int64_t count = 1;
  double product = 1.0;  // for the message: may exceed any integer
  std::string sizes;
  for (const auto& axis : def.axes) {
    const auto size = static_cast<std::int64_t>(axis.values.size());
    product *= static_cast<double>(size);
    sizes += (sizes.empty() ? "" : " x ") + std::to_string(size);
    // why: checked before each multiplication, so the count never overflows
    count = size > 0 && count > kMaxGridPoints / size ? kMaxGridPoints + 1 : count * size;
  }
  if (count > kMaxGridPoints) {
    char total[40];
    std::snprintf(total, sizeof total, "%.3g", product);
    throw ConfigError(sweep_where(def) + ": the grid has " + sizes + " = " + total +
                      " points, more than the " + std::to_string(kMaxGridPoints) +
                      " a sweep may have (split it into several sweeps)");
  }
  return count;
}

ExpandedSweep expand_sweep(const SweepDef& def, const std::vector<Setting>& overrides) {
  const std::string where = sweep_where(def);
  const auto count = static_cast<std::size_t>(grid_points(def));
  for (const auto& o : overrides) {
    for (const auto& axis : def.axes) {
      if (current_key(o.key) == current_key(axis.key)) {
        // why: a preset file's setting names its file, a --set its option; one without an
        // origin (Python's keyword arguments) is named by its key alone
        const std::string from = o.origin.empty()      ? ""
                                 : o.origin == "--set" ? "--set "
                                                       : o.origin + ": ";
        throw ConfigError(where + ": " + from + o.key + " names an axis of the sweep");
      }
    }
  }
  std::vector<Setting> base = def.scenario_settings;
  base.insert(base.end(), def.settings.begin(), def.settings.end());
  base.insert(base.end(), overrides.begin(), overrides.end());

  ExpandedSweep out{def, {}, {}};
  for (const auto& o : overrides) {
    if (o.origin != "--set" && o.origin != "Python") continue;  // a preset file's: not a --set
    const auto* text = std::get_if<std::string>(&o.value);
    out.sets.push_back(o.key + "=" + (text ? *text : format_value(o.value)));
  }
  out.points.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    // the grid in row-major order: the first axis varies slowest
    SweepPoint point;
    point.index = static_cast<int>(i);
    std::vector<Setting> settings = base;
    std::size_t rest = i;
    std::vector<std::size_t> index(def.axes.size());
    for (std::size_t a = def.axes.size(); a-- > 0;) {
      index[a] = rest % def.axes[a].values.size();
      rest /= def.axes[a].values.size();
    }
    for (std::size_t a = 0; a < def.axes.size(); ++a) {
      const ConfigValue& v = def.axes[a].values[index[a]];
      point.values.push_back(v);
      settings.push_back(
          {def.axes[a].key, v, false, where + ": axis " + def.axes[a].key, Layer::kAxis});
    }
    point.scenario = build_scenario(settings);
    point.config_hash = scenario_hash(point.scenario);
    out.points.push_back(std::move(point));
  }
  return out;
}

std::string scenario_hash(const Scenario& scenario) {
  return hash_text(canonical_config(scenario, ConfigKeys::kOfTheRun));
}

std::string plume_key(const Scenario& scenario) {
  // everything the plume depends on, and nothing else
  Scenario p;
  p.sim = scenario.sim;
  p.source = scenario.source;
  p.source.solid_radius = 0.0;  // an obstacle for the robot only
  p.plume = scenario.plume;
  p.arena.x_max = scenario.arena.x_max;  // where odor leaves
  // the wind: its model, the mean wind and the params of that model alone (the others' stay
  // at their defaults), and what else it depends on (its identity hook: a grid over the arena)
  const WindRegistry& winds = wind_field_registry();
  const auto model = static_cast<std::size_t>(scenario.wind.model);
  p.wind.model = scenario.wind.model;
  p.wind.velocity = scenario.wind.velocity;
  p.wind.params.at(winds, model) = scenario.wind.params.at(winds, model);
  return hash_text(canonical_config(p, ConfigKeys::kOfTheRun) +
                   wind_identity(scenario.wind, wind_region(scenario.arena)));
}

namespace {

// why: teams that meet one World must meet one plume, or results would depend on the grouping
void check_one_plume(const std::vector<const Scenario*>& scenarios, const char* who) {
  if (scenarios.size() < 2) return;
  const std::string key = plume_key(*scenarios.front());
  for (const Scenario* s : scenarios) {
    if (plume_key(*s) != key) {
      throw std::invalid_argument(std::string(who) + ": the scenarios do not share one plume");
    }
  }
}

}  // namespace

std::vector<RunResult> run_shared(const std::vector<const Scenario*>& scenarios, std::uint64_t seed,
                                  std::uint64_t trial, const ControllerFactory& factory) {
  if (scenarios.empty()) return {};
  check_one_plume(scenarios, "run_shared");
  // one environment, every robot in it, in lockstep
  World world(scenarios, seed, trial, factory);
  while (!world.done()) world.step();
  return world.results();
}

std::vector<TaskGroup> plume_groups(const std::vector<ExpandedSweep>& sweeps,
                                    const std::vector<RunTask>& tasks, bool share) {
  std::vector<TaskGroup> groups;
  if (!share) {
    for (const RunTask& t : tasks) groups.push_back({t});
    return groups;
  }
  std::map<std::pair<int, int>, std::string> point_keys;
  std::map<std::string, std::size_t> group_of;
  for (const RunTask& t : tasks) {
    const ExpandedSweep& sweep = sweeps[static_cast<std::size_t>(t.sweep)];
    auto [it, fresh] = point_keys.try_emplace({t.sweep, t.point});
    if (fresh) {
      it->second = plume_key(sweep.points[static_cast<std::size_t>(t.point)].scenario);
    }
    const std::string key =
        it->second + "/" + std::to_string(sweep.def.seed) + "/" + std::to_string(t.trial);
    auto [g, added] = group_of.try_emplace(key, groups.size());
    if (added) groups.emplace_back();
    groups[g->second].push_back(t);
  }
  return groups;
}

std::vector<TaskGroup> split_groups(std::vector<TaskGroup> groups, std::size_t wanted) {
  if (groups.empty() || groups.size() >= wanted) return groups;
  const std::size_t parts = (wanted + groups.size() - 1) / groups.size();
  std::vector<TaskGroup> split;
  for (const auto& group : groups) {
    const std::size_t size = (group.size() + parts - 1) / parts;
    for (std::size_t at = 0; at < group.size(); at += size) {
      split.emplace_back(
          group.begin() + static_cast<std::ptrdiff_t>(at),
          group.begin() + static_cast<std::ptrdiff_t>(std::min(at + size, group.size())));
    }
  }
  return split;
}

std::vector<TaskGroup> work_groups(const std::vector<ExpandedSweep>& sweeps,
                                   const std::vector<RunTask>& tasks, bool share,
                                   std::size_t workers) {
  std::vector<TaskGroup> groups = plume_groups(sweeps, tasks, share);
  if (groups.size() >= workers) return groups;
  return split_groups(std::move(groups), 2 * workers);
}

std::vector<RunRow> run_group(const std::vector<ExpandedSweep>& sweeps, const TaskGroup& group,
                              const ControllerFactory& factory) {
  std::vector<const Scenario*> scenarios;
  for (const RunTask& t : group) {
    scenarios.push_back(&sweeps[static_cast<std::size_t>(t.sweep)]
                             .points[static_cast<std::size_t>(t.point)]
                             .scenario);
  }
  const RunTask& first = group.front();
  const std::uint64_t seed = sweeps[static_cast<std::size_t>(first.sweep)].def.seed;
  check_one_plume(scenarios, "run_group");
  // one environment, every task's team in it, in lockstep
  World world(scenarios, seed, first.trial, factory);
  while (!world.done()) world.step();
  const std::vector<RunResult> results = world.results();
  std::vector<RunRow> rows;
  rows.reserve(results.size());
  for (std::size_t k = 0; k < group.size(); ++k) {
    const ExpandedSweep& sweep = sweeps[static_cast<std::size_t>(group[k].sweep)];
    const SweepPoint& point = sweep.points[static_cast<std::size_t>(group[k].point)];
    for (std::size_t a = world.teams()[k]; a < world.teams()[k + 1]; ++a) {
      rows.push_back({sweep.def.name, point.index, group[k].trial, results[a].agent,
                      point.config_hash, results[a]});
    }
  }
  return rows;
}

std::int64_t runs_of(const std::vector<RunRow>& rows) {
  return std::count_if(rows.begin(), rows.end(), [](const RunRow& r) { return r.agent == 0; });
}

GroupPool::GroupPool(const std::vector<ExpandedSweep>& sweeps, int threads,
                     ControllerFactory factory, const std::atomic<bool>* stop)
    : sweeps_(sweeps), factory_(std::move(factory)), external_stop_(stop) {
  threads_.reserve(static_cast<std::size_t>(threads));
  try {
    for (int k = 0; k < threads; ++k) threads_.emplace_back([this] { work(); });
  } catch (const std::system_error& e) {
    // why: a joinable thread left behind would end the process in std::terminate
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    work_ready_.notify_all();
    for (auto& t : threads_) t.join();
    throw std::system_error(e.code(), "cannot start " + std::to_string(threads) +
                                          " worker threads (the system refused thread " +
                                          std::to_string(threads_.size() + 1) +
                                          "; ask for fewer threads)");
  }
}

GroupPool::~GroupPool() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  work_ready_.notify_all();
  for (auto& t : threads_) t.join();
}

void GroupPool::add(std::vector<TaskGroup> groups) {
  {
    std::lock_guard lock(mutex_);
    for (auto& g : groups) queue_.push_back(std::move(g));
  }
  work_ready_.notify_all();
}

std::size_t GroupPool::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

GroupPool::Batch GroupPool::take(double timeout) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, std::chrono::duration<double>(timeout), [&] { return idle(); });
  Batch batch;
  batch.rows.swap(rows_);
  batch.idle = idle();
  batch.error = error_;
  return batch;
}

void GroupPool::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  changed_.notify_all();
}

bool GroupPool::stopped() const { return stop_ || (external_stop_ && external_stop_->load()); }

bool GroupPool::idle() const { return running_ == 0 && (queue_.empty() || stopped()); }

void GroupPool::work() {
  for (;;) {
    TaskGroup group;
    {
      std::unique_lock lock(mutex_);
      // why: the external stop flag is set from a signal handler, which cannot notify: look again
      // every few milliseconds
      while (!closed_ && !stopped() && queue_.empty()) {
        work_ready_.wait_for(lock, std::chrono::milliseconds(20));
      }
      if (closed_ || stopped()) {
        changed_.notify_all();
        return;
      }
      group = std::move(queue_.front());
      queue_.pop_front();
      ++running_;
    }
    std::vector<RunRow> rows;
    std::exception_ptr error;
    try {
      rows = run_group(sweeps_, group, factory_);
    } catch (...) {
      // why: an exception leaving a thread ends the process; the caller rethrows it instead
      error = std::current_exception();
    }
    {
      std::lock_guard lock(mutex_);
      for (auto& row : rows) rows_.push_back(std::move(row));
      --running_;
      if (error && !error_) {
        error_ = error;
        stop_ = true;
      }
    }
    if (error) work_ready_.notify_all();
    changed_.notify_all();
  }
}

CampaignResult run_tasks(const std::vector<ExpandedSweep>& sweeps,
                         const std::vector<RunTask>& tasks, const CampaignOptions& options,
                         const RowSink& sink) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  CampaignResult result;
  if (options.threads < 0 || options.threads > kMaxThreads) {
    throw ConfigError("threads: must be 0 (all cores) to " + std::to_string(kMaxThreads) +
                      " (got " + std::to_string(options.threads) + ")");
  }
  const int threads = options.threads > 0
                          ? options.threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));

  // why: too few plumes for the threads (a sweep of few trials): split groups so every core works
  std::vector<TaskGroup> groups =
      work_groups(sweeps, tasks, options.share_plumes, static_cast<std::size_t>(threads));
  // why: a thread with no group to run would only cost its stack
  const int workers = static_cast<int>(std::min(static_cast<std::size_t>(threads), groups.size()));
  GroupPool pool(sweeps, workers, options.make_controller, options.stop);
  pool.add(std::move(groups));

  // the calling thread hands batches to the sink and reports progress; a failing sink (say, a
  // full disk) throws, and the pool's destructor stops the workers before the error goes up;
  // a failing run stops the pool, and its error goes up once the finished rows are in the sink
  for (;;) {
    GroupPool::Batch batch = pool.take(options.progress_interval);
    if (!batch.rows.empty()) {
      sink(batch.rows);
      result.computed += runs_of(batch.rows);
    }
    if (options.on_progress) {
      options.on_progress({result.computed, static_cast<std::int64_t>(tasks.size()), seconds()});
    }
    if (batch.idle && batch.error) std::rethrow_exception(batch.error);
    if (batch.idle) break;
  }
  result.total = static_cast<std::int64_t>(tasks.size());
  result.interrupted = result.computed < result.total;
  result.elapsed = seconds();
  return result;
}

}  // namespace plumetrace
