// A controller of your own in C++, used from your own program: it surges upwind while it smells
// odor and zigzags crosswind, with legs growing by a factor, once it has lost the plume. Its
// params struct declares its own config keys (surge_zigzag.d_lost, .first_leg, .growth), one
// line registers it, and then it is chosen, set and swept by its keys like a built-in
// controller. examples/zigzag does the same for the plumetrace command itself.
//
// Build: part of the CMake project (build/example_custom_controller).
// Run:   build/example_custom_controller [sweep.toml]
//        (default: a sweep over surge_zigzag.first_leg written below)
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "plumetrace/agent/controllers.hpp"
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

/// Parameters of the surge-zigzag: config keys in the table "surge_zigzag".
struct SurgeZigzagParams {
  /// Path length without odor after which the plume is lost (m).
  double d_lost = 0.614;
  /// Length of the first crosswind leg after a loss (m).
  double first_leg = 0.3;
  /// Factor on the leg length at each turn.
  double growth = 1.5;

  /// The config keys (plumetrace/core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("d_lost", d_lost, "path length without odor before the plume is lost (m)", pt::kPositive);
    v("first_leg", first_leg, "first crosswind leg after a loss (m)", pt::kPositive);
    v("growth", growth, "factor on the leg length at each turn",
      pt::NumberSpec{.min = 1.0, .max = 10.0});
  }
};

/// Sees only measurements (controller.hpp, measurement.hpp), like the built-in algorithms.
class SurgeZigzag final : public pt::Controller {
 public:
  /// Made by the registry from the run's params and its controller stream.
  SurgeZigzag(const SurgeZigzagParams& params, pt::Rng) : params_(params) {}

  pt::Command step(const pt::Observation& obs, pt::WindProbe& wind) override {
    tracker_.observe(obs);
    // measure the wind at the start and whenever odor is found again, then surge upwind
    if (!started_ || (obs.odor && !surging_)) {
      upwind_ = pt::upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
      started_ = surging_ = true;
    }
    if (surging_ && tracker_.lost(obs, params_.d_lost)) {
      surging_ = false;
      ++losses_;
      leg_ = params_.first_leg;
      side_ = 1;
      leg_start_ = obs.odometer;
    }
    if (surging_) return pt::Command::go(upwind_);
    // zigzag: turn round at the end of each leg, each `growth` times longer
    if (obs.odometer - leg_start_ >= leg_) {
      side_ = -side_;
      leg_ *= params_.growth;
      leg_start_ = obs.odometer;
    }
    return pt::Command::go(upwind_ + side_ * pt::kPi / 2.0);
  }
  std::string_view state() const override { return surging_ ? "surge" : "zigzag"; }
  int losses() const override { return losses_; }

 private:
  SurgeZigzagParams params_;
  pt::LossTracker tracker_;
  bool started_ = false, surging_ = false;
  double upwind_ = 0.0, leg_ = 0.0, leg_start_ = 0.0;
  int side_ = 1, losses_ = 0;
};

// the one registration line: "surge-zigzag" becomes a value of controller.algorithm, and the
// keys of SurgeZigzagParams config keys of every scenario of this program
const pt::RegisterController<SurgeZigzag, SurgeZigzagParams> kRegistered("surge-zigzag");

int main(int argc, char** argv) {
  // single runs of the default scenario, with this controller and one of its keys set
  const pt::Scenario scenario =
      pt::build_scenario({pt::parse_override("controller.algorithm=surge-zigzag"),
                          pt::parse_override("surge_zigzag.growth=1.4")});
  int successes = 0;
  for (std::uint64_t trial = 0; trial < 10; ++trial) {
    const pt::RunResult r = pt::run_once(scenario, 1, trial);
    successes += r.outcome == pt::Outcome::kSuccess;
    std::printf("trial %llu: %-8s d_t %6.2f m, %d losses\n", static_cast<unsigned long long>(trial),
                std::string(pt::outcome_name(r.outcome)).c_str(), r.d_t, r.losses);
  }
  std::printf("surge-zigzag: %d/10 successes\n", successes);

  // a sweep with the same runner as `plumetrace sweep` (threads, shared plumes): a sweep file,
  // or one over the controller's own key, each value its own point with its own config hash
  pt::SweepDef def;
  if (argc > 1) {
    def = pt::read_sweep_file(argv[1]);
  } else {
    def.name = "surge_zigzag_legs";
    def.settings = {pt::parse_override("controller.algorithm=surge-zigzag"),
                    pt::parse_override("robot.start_x=6.0"),
                    pt::parse_override("supervisor.timeout=150")};
    def.axes = {{"surge_zigzag.first_leg", {0.15, 0.3, 0.6}}};
    def.runs = 4;
    def.seed = 7;
  }
  const std::vector<pt::ExpandedSweep> sweeps = {pt::expand_sweep(def, {})};
  std::set<std::string> hashes;
  for (const pt::SweepPoint& p : sweeps[0].points) hashes.insert(p.config_hash);
  pt::CampaignOptions options;
  std::vector<pt::RunRow> rows;
  pt::run_tasks(sweeps, pt::missing_runs(sweeps, {}, 0), options,
                [&rows](const std::vector<pt::RunRow>& batch) {
                  rows.insert(rows.end(), batch.begin(), batch.end());
                });
  int swept = 0;
  for (const pt::RunRow& r : rows) swept += r.result.outcome == pt::Outcome::kSuccess;
  std::printf("sweep %s: %zu points, %zu config hashes, %d/%zu successes\n",
              sweeps[0].def.name.c_str(), sweeps[0].points.size(), hashes.size(), swept,
              rows.size());
  return 0;
}
