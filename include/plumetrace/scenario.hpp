#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "plumetrace/controllers.hpp"
#include "plumetrace/plume.hpp"
#include "plumetrace/robot.hpp"
#include "plumetrace/sensors.hpp"
#include "plumetrace/wind.hpp"

namespace plumetrace {

/// Time stepping (SPEC sections 1-2).
struct SimParams {
  /// Time step for plume, sensors, control and motion (s).
  double dt = 0.032;
  /// Plume-only time before the robot is released (s).
  double warmup = 20.0;
};

/// The rectangular arena with walls on all four sides (m).
struct ArenaParams {
  /// Upwind end (m).
  double x_min = 0.0;
  /// Downwind end (m).
  double x_max = 16.0;
  /// Right-hand wall (m).
  double y_min = -2.0;
  /// Left-hand wall (m).
  double y_max = 2.0;
};

/// When a run ends (SPEC section 6).
struct SupervisorParams {
  /// Success once the robot centre is this close to the source centre in (x, y) (m).
  double success_radius = 0.185;
  /// Simulated time after release at which the run fails (s).
  double timeout = 1200.0;
};

/// Everything one run depends on besides (seed, trial); defaults are the paper's setup.
struct Scenario {
  SimParams sim;
  ArenaParams arena;
  SourceParams source;
  WindParams wind;
  PlumeParams plume;
  OdorSensorParams odor;
  WindSensorParams wind_sensor;
  RobotParams robot;
  SupervisorParams supervisor;
  ControllerParams controller;
};

/// A bad configuration: names the dotted key (or file) and what is allowed.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A value as read from a file or the command line.
using ConfigValue = std::variant<double, std::int64_t, bool, std::string>;

/// A real-valued key: file value times `scale` gives the SI value.
struct NumberField {
  double* value;
  double min = -INFINITY;
  double max = INFINITY;
  bool min_open = false;  ///< the bound itself is excluded
  bool max_open = false;
  double scale = 1.0;
};

/// An integer key.
struct IntegerField {
  int* value;
  std::int64_t min;
  std::int64_t max;
};

/// A key with a fixed set of names.
struct ChoiceField {
  std::vector<std::string> names;
  std::function<int()> get;
  std::function<void(int)> set;
};

/// One config key bound to its place in a Scenario.
struct Field {
  /// Dotted key, e.g. "plume.sigma_p".
  std::string key;
  /// One line: meaning and unit.
  std::string help;
  std::variant<NumberField, IntegerField, ChoiceField> kind;
};

/// Every config key of a scenario, in file order; the one list used by files, CLI and Python.
std::vector<Field> scenario_fields(Scenario& scenario);

/// Sets one key from a typed value; throws ConfigError naming the key and the allowed range.
void set_field(Scenario& scenario, std::string_view key, const ConfigValue& value);

/// Sets one key from text as typed on the command line ("0.5", "casting", "inf").
void set_field_text(Scenario& scenario, std::string_view key, std::string_view text);

/// The current value of a key, as it would be written to a file.
ConfigValue get_field(const Scenario& scenario, std::string_view key);

/// Checks every key's range and the relations between keys; throws ConfigError.
void validate(const Scenario& scenario);

/// Formats a number so it reads back to the same double ("inf" for infinity).
std::string format_number(double value);

/// Formats a config value for display.
std::string format_value(const ConfigValue& value);

/// One key = value setting, from a file (typed) or the command line (text to parse).
struct Setting {
  /// Dotted key.
  std::string key;
  /// The value; with `text` set it is a string still to be parsed for the key's type.
  ConfigValue value;
  /// The value came from the command line as text.
  bool text = false;
  /// Where it came from, for error messages ("--set", a file name); may be empty.
  std::string origin;
};

/// Splits a command-line "key.path=value"; throws ConfigError when there is no '='.
Setting parse_override(std::string_view text);

/// Builds a scenario from defaults and settings applied in order. A `plume.preset` setting (the
/// last one wins) first resets every plume row to that preset; then every other setting is
/// applied; finally the whole scenario is validated. Throws ConfigError naming the key.
Scenario build_scenario(const std::vector<Setting>& settings);

}  // namespace plumetrace
