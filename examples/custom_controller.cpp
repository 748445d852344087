// A controller of your own in C++: write a Controller, hand a ControllerFactory to a run or a
// sweep. This one surges upwind while it smells odor and zigzags crosswind, with legs growing
// by 50%, once it has lost the plume. It has no config keys of its own; examples/zigzag
// registers one that has, in one line, and makes it part of the plumetrace command.
//
// Build: part of the CMake project (build/example_custom_controller).
// Run:   build/example_custom_controller [sweep.toml]
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/world.hpp"

namespace pt = plumetrace;

// Sees only measurements (controller.hpp, measurement.hpp), like the built-in algorithms.
class Zigzag final : public pt::Controller {
 public:
  explicit Zigzag(double d_lost) : d_lost_(d_lost) {}

  pt::Command step(const pt::Observation& obs, pt::WindProbe& wind) override {
    tracker_.observe(obs);
    // measure the wind at the start and whenever odor is found again, then surge upwind
    if (!started_ || (obs.odor && !surging_)) {
      upwind_ = pt::upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
      started_ = surging_ = true;
    }
    if (surging_ && tracker_.lost(obs, d_lost_)) {
      surging_ = false;
      ++losses_;
      leg_ = 0.3;
      side_ = 1;
      leg_start_ = obs.odometer;
    }
    if (surging_) return pt::Command::go(upwind_);
    // zigzag: turn round at the end of each leg, each 50% longer
    if (obs.odometer - leg_start_ >= leg_) {
      side_ = -side_;
      leg_ *= 1.5;
      leg_start_ = obs.odometer;
    }
    return pt::Command::go(upwind_ + side_ * pt::kPi / 2.0);
  }
  std::string_view state() const override { return surging_ ? "surge" : "zigzag"; }
  int losses() const override { return losses_; }

 private:
  double d_lost_;
  pt::LossTracker tracker_;
  bool started_ = false, surging_ = false;
  double upwind_ = 0.0, leg_ = 0.3, leg_start_ = 0.0;
  int side_ = 1, losses_ = 0;
};

int main(int argc, char** argv) {
  // no registration: a factory, handed to each run and sweep
  const pt::ControllerFactory zigzag = [](const pt::Scenario& s, pt::Rng) {
    return std::make_unique<Zigzag>(s.controller.get<pt::SurgeCastParams>().d_lost);
  };

  // single runs of the default scenario
  const pt::Scenario scenario;
  int successes = 0;
  for (std::uint64_t trial = 0; trial < 10; ++trial) {
    const pt::RunResult r = pt::run_once(scenario, 1, trial, {}, zigzag);
    successes += r.outcome == pt::Outcome::kSuccess;
    std::printf("trial %llu: %-8s d_t %6.2f m, %d losses\n", static_cast<unsigned long long>(trial),
                std::string(pt::outcome_name(r.outcome)).c_str(), r.d_t, r.losses);
  }
  std::printf("zigzag: %d/10 successes\n", successes);

  // a sweep with the same runner as `plumetrace sweep` (threads, shared plumes)
  if (argc > 1) {
    const std::vector<pt::ExpandedSweep> sweeps = {
        pt::expand_sweep(pt::read_sweep_file(argv[1]), {})};
    pt::CampaignOptions options;
    options.make_controller = zigzag;
    std::vector<pt::RunRow> rows;
    pt::run_tasks(sweeps, pt::missing_runs(sweeps, {}, 0), options,
                  [&rows](const std::vector<pt::RunRow>& batch) {
                    rows.insert(rows.end(), batch.begin(), batch.end());
                  });
    int swept = 0;
    for (const pt::RunRow& r : rows) swept += r.result.outcome == pt::Outcome::kSuccess;
    std::printf("sweep %s: %d/%zu successes\n", sweeps[0].def.name.c_str(), swept, rows.size());
  }
  return 0;
}
