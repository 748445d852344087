#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>

namespace plumetrace::testing {

/// A temporary file path unique to this process and call, so tests may run in parallel.
/// `suffix` keeps the extension the code under test looks at (".csv", ".toml").
inline std::string temp_path(const std::string& stem, const std::string& suffix) {
  static int counter = 0;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "";
  return ::testing::TempDir() + "plumetrace_" + test + "_" + stem + "_" +
         std::to_string(::getpid()) + "_" + std::to_string(counter++) + suffix;
}

}  // namespace plumetrace::testing
