#include "plumetrace/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
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

  // workers take the next task index; finished rows wait in `pending` for the calling thread
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
      const std::size_t i = next.fetch_add(1);
      if (i >= tasks.size()) break;
      const RunTask& t = tasks[i];
      const ExpandedSweep& sweep = sweeps[static_cast<std::size_t>(t.sweep)];
      const SweepPoint& point = sweep.points[static_cast<std::size_t>(t.point)];
      RunRow row{sweep.def.name, point.index, t.trial, point.config_hash,
                 run_once(point.scenario, sweep.def.seed, t.trial)};
      std::lock_guard lock(mutex);
      pending.push_back(std::move(row));
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
