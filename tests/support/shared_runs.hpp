#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include "plumetrace/sim/world.hpp"

namespace plumetrace::testing {

/// Runs `scenarios` together in one World (one plume, one team each) at (seed, trial) and
/// expects every one's result to equal its run alone (run_once), bit for bit: a wind model's
/// shared plume must not depend on who meets it.
inline void expect_shared_plume_equals_runs_alone(const std::vector<Scenario>& scenarios,
                                                  std::uint64_t seed, std::uint64_t trial) {
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  std::vector<const Scenario*> group;
  for (const auto& s : scenarios) group.push_back(&s);
  World world(group, seed, trial);
  while (!world.done()) world.step();
  const std::vector<RunResult> together = world.results();
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const RunResult alone = run_once(scenarios[i], seed, trial);
    EXPECT_EQ(together[i].steps, alone.steps) << i;
    EXPECT_EQ(bits(together[i].d_t), bits(alone.d_t)) << i;
    EXPECT_EQ(bits(together[i].time), bits(alone.time)) << i;
    EXPECT_EQ(together[i].outcome, alone.outcome) << i;
  }
}

}  // namespace plumetrace::testing
