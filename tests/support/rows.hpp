#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace::testing {

/// Expects two row lists to hold the same runs in the same order, every field bit for bit.
inline void expect_same_rows(const std::vector<RunRow>& a, const std::vector<RunRow>& b) {
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].sweep, b[i].sweep) << i;
    EXPECT_EQ(a[i].point, b[i].point) << i;
    EXPECT_EQ(a[i].trial, b[i].trial) << i;
    EXPECT_EQ(a[i].config_hash, b[i].config_hash) << i;
    const RunResult &x = a[i].result, &y = b[i].result;
    EXPECT_EQ(x.outcome, y.outcome) << i;
    EXPECT_EQ(bits(x.time), bits(y.time)) << i;
    EXPECT_EQ(bits(x.d_t), bits(y.d_t)) << i;
    EXPECT_EQ(bits(x.d_u), bits(y.d_u)) << i;
    EXPECT_EQ(bits(x.overhead), bits(y.overhead)) << i;
    EXPECT_EQ(x.losses, y.losses) << i;
    EXPECT_EQ(bits(x.odor_fraction), bits(y.odor_fraction)) << i;
    EXPECT_EQ(x.steps, y.steps) << i;
    EXPECT_EQ(x.wind_samples, y.wind_samples) << i;
    EXPECT_EQ(x.seed, y.seed) << i;
    EXPECT_EQ(x.trial, y.trial) << i;
  }
}

}  // namespace plumetrace::testing
