#pragma once
// JSON and CSV building blocks of the io formats, shared with the studies' summaries.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "plumetrace/experiment/stats.hpp"
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

/// A text field of a CSV file, quoted as RFC 4180 says where it must be: a field holding a
/// comma, a double quote or a line break is enclosed in double quotes, each one doubled.
std::string csv_text(std::string_view text);

}  // namespace plumetrace::detail
