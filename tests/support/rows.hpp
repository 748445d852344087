#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace::testing {

/// Every result field of a run (RunResult::fields) as its name and its bits.
inline std::vector<std::pair<std::string, std::uint64_t>> field_bits(const RunResult& r) {
  std::vector<std::pair<std::string, std::uint64_t>> fields;
  RunResult::fields(r, [&](const ResultField& f, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (std::is_floating_point_v<T>) {
      fields.emplace_back(f.name, std::bit_cast<std::uint64_t>(static_cast<double>(value)));
    } else {
      fields.emplace_back(f.name, static_cast<std::uint64_t>(value));
    }
  });
  return fields;
}

/// Expects two row lists to hold the same runs in the same order, every field bit for bit.
inline void expect_same_rows(const std::vector<RunRow>& a, const std::vector<RunRow>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].sweep, b[i].sweep) << i;
    EXPECT_EQ(a[i].point, b[i].point) << i;
    EXPECT_EQ(a[i].trial, b[i].trial) << i;
    EXPECT_EQ(a[i].agent, b[i].agent) << i;
    EXPECT_EQ(a[i].config_hash, b[i].config_hash) << i;
    const RunResult &x = a[i].result, &y = b[i].result;
    EXPECT_EQ(field_bits(x), field_bits(y)) << i;
    EXPECT_EQ(x.seed, y.seed) << i;
    EXPECT_EQ(x.trial, y.trial) << i;
    EXPECT_EQ(x.agent, y.agent) << i;
  }
}

}  // namespace plumetrace::testing
