#pragma once
// JSON and CSV building blocks of the io formats, shared with the studies' summaries.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/experiment/teams.hpp"
#include "plumetrace/sim/plume_stats.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace::detail {

using nlohmann::json;

/// A config value as JSON.
json value_to_json(const ConfigValue& v);

/// A finite number, or null.
json number_or_null(double v);

/// One run's result with the keys of `plumetrace run --json`.
json result_json(const RunResult& r, const RunInfo& info);

/// The statistics of one point (keys documented in docs/report.md).
json stats_json(const PointStats& p);

/// The statistics of one point's teams (results.json's `team`; keys documented in
/// docs/experiments.md, "Teams").
json team_stats_json(const TeamStats& t);

/// A plume's statistics (keys documented in docs/plume-statistics.md).
json plume_stats_json(const PlumeStats& st);

/// A text field of a CSV file, quoted as RFC 4180 says where it must be: a field holding a
/// comma, a double quote or a line break is enclosed in double quotes, each one doubled.
std::string csv_text(std::string_view text);

/// Standard base64 (RFC 4648, with padding) of bytes.
std::string base64(const std::vector<std::uint8_t>& bytes);

/// The bytes of standard base64 text (RFC 4648, padded); false when the text is not that.
bool unbase64(std::string_view text, std::vector<std::uint8_t>& bytes);

/// Numbers in 16 bits over their range: v = origin + unit * q, q a whole number in 0..65535.
struct Quantizer {
  double origin = 0.0;  ///< the value of q = 0
  double unit = 1.0;    ///< the value of one step of q, > 0
  /// The quantizer of values in [lo, hi] with steps of at least `finest` (and 1 when lo = hi
  /// and finest is 0); an empty range (lo > hi) gives origin 0.
  static Quantizer over(double lo, double hi, double finest);
  /// The nearest q to v (clamped to 0..65535).
  std::uint16_t operator()(double v) const;
  /// The value of q.
  double value(std::uint16_t q) const { return origin + unit * q; }
};

/// The quantized values as little-endian 16-bit words in base64.
std::string quantized_base64(const Quantizer& q, const std::vector<double>& values);

}  // namespace plumetrace::detail
