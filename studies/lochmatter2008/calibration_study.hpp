#pragma once
// The calibration study file and the unknowns file it names (docs/calibration.md), read and
// checked before anything runs: `python3 -m plumetrace.calibrate` builds its study from these.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "plumetrace/core/config.hpp"

namespace plumetrace {

/// The most completed trials a calibration study may ask for (`trials`, `startup_trials`,
/// `validation.top`, `--trials`): 1e5. why: Optuna's sampler reads every earlier trial from the
/// study's database before it proposes the next, so a study's time grows with the square of its
/// trials; at the limit it is months of evaluations (a candidate takes about a minute).
inline constexpr std::int64_t kMaxCalibrationTrials = 100'000;

/// One evidenced value of an unknown.
struct UnknownEvidence {
  /// The value.
  ConfigValue value;
  /// Where it comes from.
  std::string source;
  /// What the source shows.
  std::string says;
};

/// A quantity the paper leaves open: a config key and its candidate values or range.
struct CalibrationUnknown {
  /// Short id, the Optuna parameter's name.
  std::string name;
  /// The dotted config key it sets.
  std::string key;
  /// A title for the report.
  std::string title;
  /// The value as the paper prints it (none: not printed).
  std::optional<ConfigValue> printed;
  /// The candidate values (empty: a range, low to high).
  std::vector<ConfigValue> choices;
  /// A range's lower bound, as written (an integer or a real).
  ConfigValue low = 0.0;
  /// A range's upper bound, as written.
  ConfigValue high = 0.0;
  /// The range is searched on a log scale.
  bool log = false;
  /// The range holds integers.
  bool integer = false;
  /// What the unknown changes, in words.
  std::string changes;
  /// The evidenced values, in the file's order.
  std::vector<UnknownEvidence> evidence;
};

/// How the best candidates are checked: the top ones rerun at more runs with a fresh seed.
struct CalibrationValidation {
  /// Candidates to validate.
  std::int64_t top = 3;
  /// Runs per value.
  int runs = 50;
  /// The fresh master seed (never the search's).
  std::uint64_t seed = 0;
  /// Runs per value of a second validation with the same seed, more than `runs` (0: none); its
  /// verdicts are shown beside, and docs/fidelity.md's rule reads them.
  int confirm_runs = 0;
};

/// A calibration study as its file says, checked, with every path resolved.
struct CalibrationStudy {
  /// The study file, as given.
  std::string file;
  /// The Optuna study's name.
  std::string name = "calibration";
  /// The unknowns file, absolute.
  std::string unknowns_file;
  /// Every unknown the unknowns file declares, in its order.
  std::vector<CalibrationUnknown> all_unknowns;
  /// The searched unknowns, in the unknowns file's order; with `evidenced_only` each offers its
  /// evidenced values alone (as choices).
  std::vector<CalibrationUnknown> unknowns;
  /// The folder of the sweep files NAME.toml, absolute.
  std::string sets_dir;
  /// The sets to run, by name.
  std::vector<std::string> sets;
  /// Runs per value during the search.
  int runs = 10;
  /// The search's master seed.
  std::uint64_t seed = 1;
  /// Completed trials to reach.
  std::int64_t trials = 500;
  /// Worker threads (0: all cores).
  int threads = 0;
  /// The sampler's random start-up trials.
  std::int64_t startup_trials = 10;
  /// "paper" or "synthetic".
  std::string target = "paper";
  /// The synthetic target's values: unknown name and value, by name.
  std::vector<std::pair<std::string, ConfigValue>> truth;
  /// Settings applied to every candidate: dotted key and value, by key.
  std::vector<std::pair<std::string, ConfigValue>> fixed;
  /// How the best candidates are validated.
  CalibrationValidation validation;
};

/// The [[unknown]] entries of an unknowns file. Fields beyond the documented ones are ignored
/// (the file is shared with the fidelity documents); missing or malformed ones throw ConfigError
/// naming the file and the entry.
std::vector<CalibrationUnknown> read_calibration_unknowns(const std::string& path);

/// Reads and checks a calibration study file, the unknowns file it names and the size of the
/// evaluations it asks for (runs times the sets' points, against kMaxCampaignRuns), reading files
/// only as every input is read (detail::parse_toml_file: a regular file, without blocking, keys
/// bounded in depth). Throws ConfigError naming the file and the key. The simulator's own check
/// of the keys and values is the caller's (a candidate's settings resolve as --set would).
CalibrationStudy read_calibration_study(const std::string& path);

}  // namespace plumetrace
