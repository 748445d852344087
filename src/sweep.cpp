#include "plumetrace/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "plumetrace/io.hpp"

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

ExpandedSweep expand_sweep(const SweepDef& def, const std::vector<Setting>& overrides) {
  const std::string where = def.file.empty() ? "sweep " + def.name : def.file;
  for (const auto& o : overrides) {
    for (const auto& axis : def.axes) {
      if (o.key == axis.key) {
        throw ConfigError(where + ": --set " + o.key + " names an axis of the sweep");
      }
    }
  }
  std::vector<Setting> base =
      def.scenario_path.empty() ? std::vector<Setting>{} : read_scenario_file(def.scenario_path);
  base.insert(base.end(), def.settings.begin(), def.settings.end());
  base.insert(base.end(), overrides.begin(), overrides.end());

  ExpandedSweep out{def, {}};
  std::size_t count = 1;
  for (const auto& axis : def.axes) count *= axis.values.size();
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
    point.config_hash = hash_text(scenario_to_toml(point.scenario));
    out.points.push_back(std::move(point));
  }
  return out;
}

std::string plume_key(const Scenario& scenario) {
  // everything the plume depends on, and nothing else
  Scenario p;
  p.sim = scenario.sim;
  p.source = scenario.source;
  p.wind = scenario.wind;
  p.plume = scenario.plume;
  p.arena.x_max = scenario.arena.x_max;
  return hash_text(scenario_to_toml(p));
}

std::vector<RunResult> run_shared(const std::vector<const Scenario*>& scenarios, std::uint64_t seed,
                                  std::uint64_t trial, const ControllerFactory& factory) {
  std::vector<RunResult> results;
  if (scenarios.empty()) return results;
  const Scenario& first = *scenarios.front();
  const std::string key = plume_key(first);
  std::vector<std::unique_ptr<Agent>> agents;
  for (const Scenario* s : scenarios) {
    if (plume_key(*s) != key) {
      throw std::invalid_argument("run_shared: the scenarios do not share one plume");
    }
    agents.push_back(
        std::make_unique<Agent>(*s, seed, trial, make_run_controller(*s, seed, trial, factory)));
  }
  const auto wind = make_wind_field(first.wind);
  Plume plume = make_plume(first, seed, trial);
  const double warmup_time = warm_up(first, *wind, plume);
  for (auto& a : agents) a->release(plume, warmup_time);

  // lockstep: one plume step, then every agent still running takes its step on it
  std::size_t running = agents.size();
  for (std::int64_t k = 0; running > 0; ++k) {
    running = 0;
    for (const auto& a : agents) running += !a->done();
    if (running == 0) break;
    plume.step(*wind, warmup_time + static_cast<double>(k) * first.sim.dt);
    for (auto& a : agents) a->step(plume);
  }
  for (const auto& a : agents) results.push_back(a->result());
  return results;
}

namespace {

// Work units: groups of tasks that meet the same plume (the same plume configuration, master
// seed and trial), or single tasks when sharing is off. Deterministic, in task order.
std::vector<std::vector<std::size_t>> work_units(const std::vector<ExpandedSweep>& sweeps,
                                                 const std::vector<RunTask>& tasks, bool share,
                                                 int threads) {
  std::vector<std::vector<std::size_t>> units;
  if (!share) {
    for (std::size_t i = 0; i < tasks.size(); ++i) units.push_back({i});
    return units;
  }
  std::map<std::pair<int, int>, std::string> point_keys;
  std::map<std::string, std::size_t> unit_of;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const RunTask& t = tasks[i];
    const ExpandedSweep& sweep = sweeps[static_cast<std::size_t>(t.sweep)];
    auto [it, fresh] = point_keys.try_emplace({t.sweep, t.point});
    if (fresh) {
      it->second = plume_key(sweep.points[static_cast<std::size_t>(t.point)].scenario);
    }
    const std::string key =
        it->second + "/" + std::to_string(sweep.def.seed) + "/" + std::to_string(t.trial);
    auto [u, added] = unit_of.try_emplace(key, units.size());
    if (added) units.emplace_back();
    units[u->second].push_back(i);
  }
  // why: too few plumes for the threads (a sweep of few trials) - split groups so every core
  // works; each part simulates the plume again, with the same result
  const std::size_t wanted = 2 * static_cast<std::size_t>(threads);
  if (units.empty() || units.size() >= wanted) return units;
  const std::size_t parts = (wanted + units.size() - 1) / units.size();
  std::vector<std::vector<std::size_t>> split;
  for (const auto& unit : units) {
    const std::size_t size = (unit.size() + parts - 1) / parts;
    for (std::size_t at = 0; at < unit.size(); at += size) {
      split.emplace_back(
          unit.begin() + static_cast<std::ptrdiff_t>(at),
          unit.begin() + static_cast<std::ptrdiff_t>(std::min(at + size, unit.size())));
    }
  }
  return split;
}

}  // namespace

CampaignResult run_tasks(const std::vector<ExpandedSweep>& sweeps,
                         const std::vector<RunTask>& tasks, const CampaignOptions& options,
                         const RowSink& sink) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  CampaignResult result;
  const int threads = options.threads > 0
                          ? options.threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));

  const auto units = work_units(sweeps, tasks, options.share_plumes, threads);

  // workers take the next unit; finished rows wait in `pending` for the calling thread
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::condition_variable wake;
  std::vector<RunRow> pending;
  int running = threads;
  std::atomic<bool> abort{false};
  const auto stopped = [&] { return abort.load() || (options.stop && options.stop->load()); };

  auto work = [&] {
    for (;;) {
      if (stopped()) break;
      const std::size_t u = next.fetch_add(1);
      if (u >= units.size()) break;
      std::vector<const Scenario*> scenarios;
      for (const std::size_t i : units[u]) {
        const RunTask& t = tasks[i];
        scenarios.push_back(&sweeps[static_cast<std::size_t>(t.sweep)]
                                 .points[static_cast<std::size_t>(t.point)]
                                 .scenario);
      }
      const RunTask& first = tasks[units[u].front()];
      const std::uint64_t seed = sweeps[static_cast<std::size_t>(first.sweep)].def.seed;
      const std::vector<RunResult> results =
          scenarios.size() == 1 ? std::vector<RunResult>{run_once(*scenarios[0], seed, first.trial,
                                                                  {}, options.make_controller)}
                                : run_shared(scenarios, seed, first.trial, options.make_controller);
      std::vector<RunRow> rows;
      for (std::size_t k = 0; k < results.size(); ++k) {
        const RunTask& t = tasks[units[u][k]];
        const ExpandedSweep& sweep = sweeps[static_cast<std::size_t>(t.sweep)];
        const SweepPoint& point = sweep.points[static_cast<std::size_t>(t.point)];
        rows.push_back({sweep.def.name, point.index, t.trial, point.config_hash, results[k]});
      }
      std::lock_guard lock(mutex);
      for (auto& row : rows) pending.push_back(std::move(row));
    }
    std::lock_guard lock(mutex);
    --running;
    wake.notify_all();
  };
  std::vector<std::thread> workers;
  workers.reserve(static_cast<std::size_t>(threads));
  for (int k = 0; k < threads; ++k) workers.emplace_back(work);

  // the calling thread hands batches to the sink and reports progress
  const auto interval = std::chrono::duration<double>(options.progress_interval);
  auto collect = [&] {
    for (;;) {
      std::vector<RunRow> batch;
      bool finished;
      {
        std::unique_lock lock(mutex);
        wake.wait_for(lock, interval, [&] { return running == 0; });
        batch.swap(pending);
        finished = running == 0;
      }
      if (!batch.empty()) {
        sink(batch);
        result.computed += static_cast<std::int64_t>(batch.size());
      }
      if (options.on_progress) {
        options.on_progress({result.computed, static_cast<std::int64_t>(tasks.size()), seconds()});
      }
      if (finished) return;
    }
  };
  try {
    collect();
  } catch (...) {
    // a failing sink (say, a full disk) stops the workers before the error goes up
    abort = true;
    for (auto& w : workers) w.join();
    throw;
  }
  for (auto& w : workers) w.join();
  result.total = static_cast<std::int64_t>(tasks.size());
  result.interrupted = result.computed < result.total;
  result.elapsed = seconds();
  return result;
}

}  // namespace plumetrace
