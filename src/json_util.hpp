#pragma once
// JSON building blocks shared by io.cpp and report.cpp (private to the library).

#include <nlohmann/json.hpp>

#include "plumetrace/io.hpp"
#include "plumetrace/stats.hpp"

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

}  // namespace plumetrace::detail
