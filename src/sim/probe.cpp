#include "plumetrace/sim/probe.hpp"

#include <algorithm>
#include <cmath>

#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

namespace {

double warmup_of(const ProbeOptions& options, const Scenario& scenario) {
  return std::isnan(options.warmup) ? scenario.sim.warmup : options.warmup;
}

}  // namespace

void check_probe_options(const ProbeOptions& options, const Scenario& scenario) {
  const double dt = scenario.sim.dt;
  static_assert(kMaxSteps == 1e7, "the message below names the limit");
  if (!((warmup_of(options, scenario) + options.duration) / dt <= kMaxSteps)) {
    throw ConfigError("--warmup, --duration: must be at most 1e7 steps of sim.dt together");
  }
  // why: compared before rounding, so that a huge interval never reaches lround
  if (!(options.interval <= options.duration) ||
      std::lround(options.duration / dt) < std::max(1L, std::lround(options.interval / dt))) {
    throw ConfigError("--duration: must be at least --interval, or no sample is taken");
  }
}

std::vector<ProbeResult> probe_plume(const Scenario& scenario, const std::vector<Vec3>& points,
                                     const ProbeOptions& options) {
  const double dt = scenario.sim.dt;
  check_probe_options(options, scenario);
  Environment env = make_environment(scenario, options.seed, 0);
  const long warmup_steps = std::lround(warmup_of(options, scenario) / dt);
  const long steps = std::lround(options.duration / dt);
  const long every = std::max(1L, std::lround(options.interval / dt));

  std::vector<ProbeResult> results(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) results[i].point = points[i];
  for (long k = 0; k < warmup_steps + steps; ++k) {
    step(env, dt);
    const long since = k + 1 - warmup_steps;
    if (since <= 0 || since % every != 0) continue;
    for (auto& r : results) {
      const double c = env.odor->concentration(r.point);
      r.mean_concentration += c;
      if (perceives_odor(scenario.odor, c)) r.detect_fraction += 1.0;
      ++r.samples;
    }
  }
  for (auto& r : results) {
    if (r.samples == 0) continue;
    r.mean_concentration /= static_cast<double>(r.samples);
    r.detect_fraction /= static_cast<double>(r.samples);
  }
  return results;
}

}  // namespace plumetrace
