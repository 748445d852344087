#include "plumetrace/agent/controllers/chemotaxis.hpp"

#include <algorithm>
#include <cmath>

namespace plumetrace {

Command Chemotaxis::step(const Observation& obs, WindProbe& /*wind*/) {
  const double reading =
      params_.signal == ChemotaxisSignal::kConcentration ? obs.concentration : (obs.odor ? 1 : 0);
  if (runs_ > 0 && run_.over(obs)) {
    // end of a run: compare its mean reading with the last run's
    const double mean = sum_ / count_;
    const bool rose = mean > last_mean_;  // false while last_mean_ is NaN
    starts_[recorded_ % kChemotaxisHistory] = run_.start_point();
    means_[recorded_ % kChemotaxisHistory] = mean;
    ++recorded_;
    last_mean_ = mean;
    if (rose && !run_.blocked()) {
      state_ = State::kExtended;
      run_.start(obs, run_.heading(), (1.0 + params_.bias) * params_.run_length);
    } else {
      // tumble: a new heading, uniform
      state_ = State::kRun;
      run_.start(obs, wrap_angle(2.0 * kPi * rng_.uniform()), params_.run_length);
    }
    ++runs_;
    sum_ = 0.0;
    count_ = 0;
  } else if (runs_ == 0) {
    run_.start(obs, wrap_angle(2.0 * kPi * rng_.uniform()), params_.run_length);
    ++runs_;
  }
  // why: the reading of the step a run starts on belongs to it, so every step counts once
  sum_ += reading;
  ++count_;
  return run_.command();
}

std::string_view Chemotaxis::state() const { return state_ == State::kRun ? "run" : "extended"; }

unsigned Chemotaxis::reads() const {
  return params_.signal == ChemotaxisSignal::kConcentration ? kReadsConcentration : kReadsBinary;
}

Snapshot Chemotaxis::snapshot() const {
  Snapshot s;
  if (runs_ == 0) return s;
  s.path = {run_.start_point(), run_.end_point()};
  const int n = std::min(recorded_, kChemotaxisHistory);
  for (int k = recorded_ - n; k < recorded_; ++k) {
    s.points.push_back(starts_[k % kChemotaxisHistory]);
    s.weights.push_back(means_[k % kChemotaxisHistory]);
  }
  return s;
}

}  // namespace plumetrace
