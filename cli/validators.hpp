#pragma once

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

// Checks for option values, with messages that say what is allowed. why: CLI11's own ranges
// accept "nan" and print their bound DBL_MAX with 300 digits (issue 13, F18 and F22).
namespace plumetrace::cli {

/// A finite number >= `lo` (> `lo` with `open`); "nan" and "inf" are refused.
inline CLI::Validator finite_number(double lo, bool open = false) {
  char lo_text[32];
  std::snprintf(lo_text, sizeof lo_text, "%g", lo);
  const std::string bound = (open ? "> " : ">= ") + std::string(lo_text);
  return CLI::Validator(
      [lo, open, bound](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool ok = !text.empty() && end == text.c_str() + text.size() && std::isfinite(v) &&
                        (open ? v > lo : v >= lo);
        return ok ? std::string() : "must be a finite number " + bound + " (got '" + text + "')";
      },
      "number " + bound);
}

/// A whole number from `lo` to `hi`.
inline CLI::Validator whole_number(std::int64_t lo, std::int64_t hi) {
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        std::int64_t v = 0;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        const bool ok = !text.empty() && ec == std::errc() && ptr == text.data() + text.size() &&
                        v >= lo && v <= hi;
        return ok ? std::string()
                  : "must be a whole number from " + range + " (got '" + text + "')";
      },
      "whole number " + range);
}

/// A text that is not empty (a file, a folder, a name): "" would otherwise mean "the default".
inline CLI::Validator not_empty() {
  return CLI::Validator(
      [](std::string& text) -> std::string { return text.empty() ? "must not be empty" : ""; }, "");
}

}  // namespace plumetrace::cli
