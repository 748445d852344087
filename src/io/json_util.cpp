#include "plumetrace/io/json_util.hpp"

#include <cmath>
#include <type_traits>

#include "plumetrace/core/files.hpp"

namespace plumetrace::detail {

json value_to_json(const ConfigValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json result_json(const RunResult& r, const RunInfo& info) {
  json out{{"algorithm", info.algorithm}};
  RunResult::fields(r, [&](const ResultField& f, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    json& cell = out[std::string(f.name)];
    if constexpr (std::is_same_v<T, Outcome>) {
      cell = std::string(outcome_name(value));
    } else if constexpr (std::is_floating_point_v<T>) {
      cell = f.nullable ? number_or_null(value) : json(value);
    } else {
      cell = value;
    }
  });
  out["seed"] = info.seed;
  out["trial"] = info.trial;
  out["version"] = std::string(version());
  return out;
}

json stats_json(const PointStats& p) {
  return {{"runs", p.runs},
          {"successes", p.successes},
          {"walls", p.walls},
          {"timeouts", p.timeouts},
          {"gave_up", p.gave_up},
          {"success_rate", number_or_null(p.success_rate)},
          {"success_lo", number_or_null(p.success_ci.lo)},
          {"success_hi", number_or_null(p.success_ci.hi)},
          {"overhead",
           {{"n", p.overhead.n},
            {"mean", number_or_null(p.overhead.mean)},
            {"lo", number_or_null(p.overhead.lo)},
            {"hi", number_or_null(p.overhead.hi)},
            {"boot_lo", number_or_null(p.overhead_bootstrap.lo)},
            {"boot_hi", number_or_null(p.overhead_bootstrap.hi)},
            {"median", number_or_null(p.overhead_quartiles.median)},
            {"q1", number_or_null(p.overhead_quartiles.q1)},
            {"q3", number_or_null(p.overhead_quartiles.q3)}}},
          {"mean_time", number_or_null(p.mean_time)},
          {"mean_losses", number_or_null(p.mean_losses)}};
}

std::string csv_text(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (const char c : text) {
    quoted += c;
    if (c == '"') quoted += '"';
  }
  return quoted + '"';
}

}  // namespace plumetrace::detail
