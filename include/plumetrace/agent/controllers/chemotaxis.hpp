#pragma once

#include <array>

#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

/// What chemotaxis reads.
enum class ChemotaxisSignal {
  kConcentration,  ///< the odor sensor's reading
  kBinary,         ///< the binary odor, 1 or 0
};

/// Parameters of chemotaxis, the bacterial biased random walk (docs/algorithms.md,
/// "chemotaxis").
struct ChemotaxisParams {
  /// What a run's mean reading averages.
  ChemotaxisSignal signal = ChemotaxisSignal::kConcentration;
  /// Length of a run after a tumble (m). why: 0.5 m, chosen: about 5 s at the Khepera III's
  /// speed, a few body lengths, long enough to cross the laminar plume's metre of width in two.
  double run_length = 0.5;
  /// A run after a rise is (1 + bias) run_length long. why: 2, chosen: a run up the gradient is
  /// three times a base run (E. coli extends runs up a gradient; Berg & Brown 1972).
  double bias = 2.0;

  /// The config keys (core/config.hpp), in the table "chemotaxis".
  template <class V>
  void fields(V& v) {
    v("signal", signal,
      "what a run's mean reading averages: the odor sensor's reading or the binary odor",
      {"concentration", "binary"});
    v("run_length", run_length, "length of a run after a tumble (m)",
      NumberSpec{.min = 0.0, .max = 100.0, .min_open = true});
    v("bias", bias, "a run after a rise of the mean reading is (1 + bias) run_length long",
      NumberSpec{.min = 0.0, .max = 100.0});
  }
};

/// The most recent runs chemotaxis's snapshot shows.
inline constexpr int kChemotaxisHistory = 64;

/// Chemotaxis: straight runs; at the end of each, the mean reading over it is compared with the
/// previous run's: after a rise the robot runs on in the same direction for a lengthened run,
/// otherwise it tumbles to a uniformly random heading for a base run (the E. coli biased random
/// walk of Dhariwal, Sukhatme & Requicha 2004). A blocked run ends in a tumble. Uses no wind;
/// never gives up.
class Chemotaxis final : public Controller {
 public:
  /// States: a base run after a tumble, or a lengthened run after a rise.
  enum class State { kRun, kExtended };

  /// Creates the walk; `rng` draws its tumbles.
  Chemotaxis(const ChemotaxisParams& params, Rng rng) : params_(params), rng_(rng) {}
  Command step(const Observation& obs, WindProbe& wind) override;
  std::string_view state() const override;
  int losses() const override { return 0; }
  /// The concentration when signal is "concentration", else nothing more than the binary odor.
  unsigned reads() const override;
  /// The current run as a path (its start, its planned end) and the starts of recent runs as
  /// points weighted by their runs' mean readings.
  Snapshot snapshot() const override;
  /// The current run.
  const Leg& run() const { return run_; }
  /// Number of runs begun so far.
  int runs() const { return runs_; }
  /// Mean reading over the last finished run (NaN before the first ends).
  double last_mean() const { return last_mean_; }

 private:
  ChemotaxisParams params_;
  Rng rng_;
  State state_ = State::kRun;
  Leg run_;
  int runs_ = 0;
  double sum_ = 0.0;  // readings summed over the current run
  int count_ = 0;     // readings in the sum
  double last_mean_ = NAN;
  std::array<Vec2, kChemotaxisHistory> starts_{};
  std::array<double, kChemotaxisHistory> means_{};
  int recorded_ = 0;
};

}  // namespace plumetrace
