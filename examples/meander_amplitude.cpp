// The plume's centreline meander at a distance downwind of the source: the lateral (y) position
// of the centroid of the filaments within a thin slab across the wind, sampled over time and
// trials, and its standard deviation (the meander amplitude of docs/model.md section 3.1).
// Runs the scenario's environment alone (plume and wind, no robot), as `plumetrace probe` does.
//
// Build: part of the CMake project (build/example_meander_amplitude).
// Run:   build/example_meander_amplitude scenarios/meander-strong.toml [key=value]...
//          [--trials N] [--duration S] [--distance M] [--half-width M]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/sim/world.hpp"

namespace pt = plumetrace;

namespace {

struct Options {
  std::string scenario;
  std::vector<pt::Setting> overrides;
  int trials = 20;           // independent trials (seed 1, trials 0..N-1)
  double duration = 600.0;   // s sampled per trial, after the scenario's warm-up
  double interval = 0.32;    // s between samples
  double distance = 14.5;    // m downwind of the source centre: the robot's start
  double half_width = 0.25;  // m, half the slab's extent along x
};

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / static_cast<double>(v.size());
}

double sd_of(const std::vector<double>& v, double mean) {
  double s = 0.0;
  for (double x : v) s += (x - mean) * (x - mean);
  return v.size() < 2 ? NAN : std::sqrt(s / static_cast<double>(v.size() - 1));
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&] { return i + 1 < argc ? std::atof(argv[++i]) : NAN; };
    if (a == "--trials") {
      o.trials = static_cast<int>(value());
    } else if (a == "--duration") {
      o.duration = value();
    } else if (a == "--distance") {
      o.distance = value();
    } else if (a == "--half-width") {
      o.half_width = value();
    } else if (a.find('=') != std::string::npos) {
      o.overrides.push_back(pt::parse_override(a));
    } else {
      o.scenario = a;
    }
  }
  if (o.scenario.empty() || !(o.trials >= 1) || !(o.duration > 0.0)) {
    std::fprintf(stderr,
                 "usage: %s SCENARIO.toml [key=value]... [--trials N] [--duration S] "
                 "[--distance M] [--half-width M]\n",
                 argv[0]);
    return 2;
  }
  try {
    const pt::Scenario s = pt::load_scenario(o.scenario, o.overrides);
    const double dt = s.sim.dt;
    const double x0 = s.source.center.x + o.distance;
    const auto every = std::max<long>(1, std::lround(o.interval / dt));
    const auto steps = std::lround(o.duration / dt);
    std::vector<double> centroids, trial_sd, counts;
    long instants = 0;
    for (int t = 0; t < o.trials; ++t) {
      pt::Environment env = pt::make_environment(s, 1, static_cast<std::uint64_t>(t));
      pt::warm_up(s, env);
      std::vector<double> mine;
      for (long k = 1; k <= steps; ++k) {
        pt::step(env, dt);
        if (k % every != 0) continue;
        ++instants;
        const pt::FilamentSpans f = env.odor->snapshot().filaments;
        double sum = 0.0;
        long n = 0;
        for (std::size_t i = 0; i < f.size(); ++i) {
          if (std::abs(f.x[i] - x0) <= o.half_width) {
            sum += f.y[i];
            ++n;
          }
        }
        if (n == 0) continue;
        mine.push_back(sum / static_cast<double>(n));
        counts.push_back(static_cast<double>(n));
      }
      trial_sd.push_back(sd_of(mine, mean_of(mine)));
      centroids.insert(centroids.end(), mine.begin(), mine.end());
    }
    const double mean = mean_of(centroids), sd = sd_of(centroids, mean);
    const double spread = sd_of(trial_sd, mean_of(trial_sd));
    std::sort(counts.begin(), counts.end());
    if (s.wind.model == pt::WindModel::kMeander) {
      const auto& m = s.wind.get<pt::MeanderParams>();
      std::printf("scenario %s: meandering wind, gain %g, damping %g, bandwidth %g\n",
                  o.scenario.c_str(), m.gain, m.damping, m.bandwidth);
    } else {
      std::printf("scenario %s: constant wind\n", o.scenario.c_str());
    }
    std::printf("slab x = %.3f +- %.3f m (source + %.2f m), %d trials x %.0f s, every %.3f s\n", x0,
                o.half_width, o.distance, o.trials, o.duration, static_cast<double>(every) * dt);
    std::printf("instants with filaments in the slab: %zu of %ld (%.1f%%), median %g filaments\n",
                centroids.size(), instants,
                100.0 * static_cast<double>(centroids.size()) / static_cast<double>(instants),
                counts.empty() ? 0.0 : counts[counts.size() / 2]);
    std::printf("centroid y: mean %.4f m, std %.4f m (meander amplitude)\n", mean, sd);
    std::printf("per-trial std: mean %.4f m, sd %.4f m, standard error of the mean %.4f m\n",
                mean_of(trial_sd), spread, spread / std::sqrt(static_cast<double>(o.trials)));
  } catch (const pt::ConfigError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
