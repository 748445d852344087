#pragma once

#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>

namespace plumetrace {

/// How a run ended (docs/model.md section 8).
enum class Outcome { kRunning, kSuccess, kWall, kTimeout, kGaveUp, kWrongDeclaration };

/// The name of each outcome, indexed by its value: the one table outcome_name and parse_outcome
/// read.
inline constexpr std::array<std::string_view, 6> kOutcomeNames{
    "running", "success", "wall", "timeout", "gave_up", "wrong_declaration"};

/// Name of an outcome: "running", "success", "wall", "timeout", "gave_up", "wrong_declaration"
/// ("" for no outcome).
std::string_view outcome_name(Outcome outcome);

/// The outcome that outcome_name gives `name`; throws ConfigError naming it and the names
/// allowed when it is none.
Outcome parse_outcome(std::string_view name);

/// What the formats need to know of a result field besides its value's type.
struct ResultField {
  std::string_view name = {};  ///< column (CSV, SQLite, Python) and key (JSON) name
  std::string_view unit = {};  ///< SI unit, "" for a name, a count or a fraction
  bool nullable = false;       ///< may be NaN: written as null (JSON), NULL (SQLite), "" (CSV)
};

/// Whether a value given by RunResult::fields, as `decltype(value)` of an `auto&&` parameter, is
/// derived from the fields before it (given by value, as success) rather than a member: written
/// by every format, checked or skipped when read, never sent or hashed.
template <class T>
inline constexpr bool kDerivedField = !std::is_lvalue_reference_v<T>;

/// The metrics of one run (docs/model.md section 9).
struct RunResult {
  /// How the run ended.
  Outcome outcome = Outcome::kRunning;
  /// Simulated time from release to the end (s).
  double time = 0.0;
  /// Path length of the robot centre (m).
  double d_t = 0.0;
  /// Upwind displacement, start x minus end x (m).
  double d_u = 0.0;
  /// d_t / d_u; NaN when d_u <= 0.
  double overhead = 0.0;
  /// Times the plume was declared lost.
  int losses = 0;
  /// Fraction of steps with odor perceived.
  double odor_fraction = 0.0;
  /// Steps run after release.
  std::int64_t steps = 0;
  /// Wind samples the controller took.
  std::int64_t wind_samples = 0;
  /// Time from release to the first step with odor perceived (s); NaN when odor never was.
  /// Plume finding: 0 for a robot released in odor that perceives it at once.
  double t_first_odor = NAN;
  /// Path length from release to the first step with odor perceived (m); NaN when never.
  double d_first_odor = NAN;
  /// Distance from the declared source position to the true source centre (m); NaN when the
  /// robot declared nothing.
  double declaration_error = NAN;
  /// Master seed that, with the trial index, replays the run.
  std::uint64_t seed = 0;
  /// Trial index.
  std::uint64_t trial = 0;
  /// The robot's index in its team (0 for a robot alone); with seed and trial it identifies the
  /// row.
  int agent = 0;

  /// The one list of a run's result fields, in column order: calls `v(ResultField, value)` for
  /// each. runs.csv, the JSON result (run --json, results.json, traces), the store's runs table,
  /// the MPI row message and the Python sweep columns all follow it. A value is a member
  /// (Outcome, double, int or std::int64_t; integers are whole numbers from 0), or derived
  /// (kDerivedField). Seed and trial identify the run: each format writes them with its key.
  template <class Self, class Visitor>
  requires std::same_as<std::remove_const_t<Self>, RunResult>
  static constexpr void fields(Self& r, Visitor&& v) {
    v({.name = "outcome"}, r.outcome);
    v({.name = "success"}, r.outcome == Outcome::kSuccess);
    v({.name = "time_s", .unit = "s"}, r.time);
    v({.name = "d_t", .unit = "m"}, r.d_t);
    v({.name = "d_u", .unit = "m"}, r.d_u);
    v({.name = "overhead", .nullable = true}, r.overhead);
    v({.name = "losses"}, r.losses);
    v({.name = "odor_fraction"}, r.odor_fraction);
    v({.name = "steps"}, r.steps);
    v({.name = "wind_samples"}, r.wind_samples);
    v({.name = "t_first_odor", .unit = "s", .nullable = true}, r.t_first_odor);
    v({.name = "d_first_odor", .unit = "m", .nullable = true}, r.d_first_odor);
    v({.name = "declaration_error", .unit = "m", .nullable = true}, r.declaration_error);
  }
};

/// Every result field's description, in RunResult::fields order (for headers and schemas).
inline constexpr auto kResultFields = [] {
  constexpr std::size_t count = [] {
    std::size_t n = 0;
    const RunResult r{};
    RunResult::fields(r, [&](const ResultField&, const auto&) { ++n; });
    return n;
  }();
  std::array<ResultField, count> fields{};
  std::size_t k = 0;
  const RunResult r{};
  RunResult::fields(r, [&](const ResultField& f, const auto&) { fields[k++] = f; });
  return fields;
}();

/// Identifies a robot's run: what the trace and the JSON output carry besides the result.
struct RunInfo {
  std::string algorithm;    ///< algorithm name
  std::uint64_t seed = 0;   ///< master seed
  std::uint64_t trial = 0;  ///< trial index
  int agent = 0;            ///< the robot's index in its team (0 for a robot alone)
};

}  // namespace plumetrace
