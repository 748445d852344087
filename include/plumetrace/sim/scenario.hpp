#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/agent/robot.hpp"
#include "plumetrace/agent/sensors.hpp"
#include "plumetrace/core/config.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/env/filament_plume.hpp"
#include "plumetrace/env/wind.hpp"

namespace plumetrace {

/// Time stepping (docs/model.md section 2).
struct SimParams {
  /// Time step for plume, sensors, control and motion (s).
  double dt = 0.032;
  /// Plume-only time before the robot is released (s); derived unless set (derive_scenario).
  double warmup = 20.0;
  /// sim.warmup is "auto": derived from the arena's length and the wind.
  bool warmup_auto = true;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("dt", dt, "time step for everything (s)", kPositive);
    v("warmup", warmup, "plume-only time before the robot is released (s)", kNonNegative,
      warmup_auto);
  }
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

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("x_min", x_min, "upwind wall (m)", kAnyNumber);
    v("x_max", x_max, "downwind wall (m)", kAnyNumber);
    v("y_min", y_min, "right-hand wall (m)", kAnyNumber);
    v("y_max", y_max, "left-hand wall (m)", kAnyNumber);
  }
};

/// The region the wind field covers: the arena's walls.
inline WindRegion wind_region(const ArenaParams& arena) {
  return {arena.x_min, arena.x_max, arena.y_min, arena.y_max};
}

/// What ends a run in success (docs/agents.md, "Source declaration").
enum class SuccessRule {
  kReach,    ///< reaching the source (the paper's ideal supervisor); a declaration is scored too
  kDeclare,  ///< only a declaration within supervisor.declaration_radius of the source
};

/// What the arena's walls do (docs/agents.md, "Walls").
enum class WallRule {
  kEnd,    ///< touching a wall ends the run as a failure (the paper)
  kBlock,  ///< a wall only blocks the robot: a move into it is not made
};

/// When a run ends (docs/model.md section 8).
struct SupervisorParams {
  /// Success once the robot centre is this close to the source centre in (x, y) (m).
  double success_radius = 0.185;
  /// Simulated time after release at which the run fails (s).
  double timeout = 1200.0;
  /// What ends a run in success. why: "reach", the paper's ideal supervisor.
  SuccessRule success = SuccessRule::kReach;
  /// A declaration this close to the source centre (m) is a success, any other a
  /// "wrong_declaration". why: 0.5 m, a little over two body lengths of the Khepera III.
  double declaration_radius = 0.5;
  /// What the walls do. why: "end", the paper's ("we considered the experiment a failure if the
  /// robot hit a wall").
  WallRule walls = WallRule::kEnd;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("success_radius", success_radius,
      "success once this close to the source centre (m; 0 only with a solid source)", kNonNegative);
    v("timeout", timeout, "run time limit after release (s)", kPositive);
    v("success", success, "what ends a run in success: reach the source, or declare it",
      {"reach", "declare"});
    v("declaration_radius", declaration_radius,
      "a declared source this close to the true one is a success (m)",
      NumberSpec{.min = 0.0, .max = 1e3, .min_open = true});
    v("walls", walls, "what touching a wall does: end the run, or block the robot",
      {"end", "block"});
  }
};

/// The most robots one team may have. why: item 7's benchmark goes to 100; every robot of a team
/// is checked against every other for contacts each step (N^2 / 2 pairs).
inline constexpr int kMaxTeam = 1000;

/// Several robots on one plume (docs/agents.md, "Teams").
struct TeamParams {
  /// Robots released together, all running controller.algorithm with its params.
  int count = 1;
  /// Lateral spacing between the robots' starts when start.region is "point" (m): robot 0 at
  /// the start, robot k at k/2 spacings to its left (k odd) or right (k even), rounded up.
  /// why: 0.3 m, two body diameters and a little.
  double spacing = 0.3;
  /// Whether robot bodies collide.
  enum class Contact { kOff, kOn };
  /// Whether robot bodies collide. why: "on": robots are bodies.
  Contact contact = Contact::kOn;
  /// Range of a broadcast message (m): teammates farther than this when it is sent do not get
  /// it. why: inf, every teammate.
  double range = INFINITY;
  /// Delay of a message (s): it is delivered at the first step at least this long after it was
  /// sent, and never the step it was sent. why: 0, the next step.
  double delay = 0.0;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("count", count, "robots released together", IntegerSpec{1, kMaxTeam});
    v("spacing", spacing, "lateral spacing of the robots' starts at a point start (m)",
      kNonNegative);
    v("contact", contact, "whether robot bodies collide", {"off", "on"});
    v("range", range, "range of a broadcast message (m)",
      NumberSpec{.min = 0.0, .allow_infinite = true});
    v("delay", delay, "delay of a message (s)", NumberSpec{.min = 0.0, .max = 1e6});
  }
};

/// Where a robot starts (docs/agents.md, "Start distributions").
enum class StartRegion {
  kPoint,      ///< robot.start_x, robot.start_y (the paper)
  kRectangle,  ///< uniform in start.x_min..x_max by start.y_min..y_max
  kDisc,       ///< uniform in the disc of start.radius around (start.cx, start.cy)
};

/// The frame a start region is given in.
enum class StartFrame {
  kSource,  ///< relative to the source centre
  kArena,   ///< the arena's own coordinates
};

/// Whether a start must be in odor.
enum class StartCondition {
  kAny,     ///< anywhere in the region
  kInOdor,  ///< where the odor sensor perceives odor at release
};

/// Which way a robot faces at release.
enum class StartHeading {
  kFixed,   ///< robot.start_heading_deg
  kRandom,  ///< uniform in [-180, 180) degrees
};

/// The most draws a robot's start may take (a region mostly outside odor, crowded, or blocked).
inline constexpr int kMaxStartDraws = 100'000;

/// Start distributions: a region, its frame, a condition and the heading (docs/agents.md).
struct StartParams {
  /// The region. why: "point", the paper's single start.
  StartRegion region = StartRegion::kPoint;
  /// The frame of the region's keys. why: "source", so a region follows the source.
  StartFrame frame = StartFrame::kSource;
  /// Rectangle: upwind edge (m). why: the rectangle's defaults, in the source's frame, span
  /// 10-14.5 m downwind (the paper's start is at 14.5 m) across 3 m of the 4 m wide arena,
  /// 0.5 m clear of each wall: in the paper's arena the plume, about 1 m wide there, covers a
  /// third of it, so most starts are outside odor (plume finding).
  double x_min = 10.0;
  double x_max = 14.5;  ///< rectangle: downwind edge (m)
  double y_min = -1.5;  ///< rectangle: right edge (m)
  double y_max = 1.5;   ///< rectangle: left edge (m)
  /// Disc: centre x (m). why: the disc's defaults, 12 m downwind with a radius of 1.5 m, fit
  /// the paper's arena 0.5 m clear of its walls.
  double cx = 12.0;
  double cy = 0.0;      ///< disc: centre y (m)
  double radius = 1.5;  ///< disc: radius (m)
  /// Whether the start must be in odor. why: "any".
  StartCondition condition = StartCondition::kAny;
  /// The heading at release. why: "fixed", robot.start_heading_deg.
  StartHeading heading = StartHeading::kFixed;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    v("region", region, "where robots start: a point (robot.start_x, _y), a rectangle or a disc",
      {"point", "rectangle", "disc"});
    v("frame", frame, "frame of the region's keys: relative to the source, or the arena's",
      {"source", "arena"});
    v("x_min", x_min, "rectangle: smallest x (m)", kAnyNumber);
    v("x_max", x_max, "rectangle: largest x (m)", kAnyNumber);
    v("y_min", y_min, "rectangle: smallest y (m)", kAnyNumber);
    v("y_max", y_max, "rectangle: largest y (m)", kAnyNumber);
    v("cx", cx, "disc: centre x (m)", kAnyNumber);
    v("cy", cy, "disc: centre y (m)", kAnyNumber);
    v("radius", radius, "disc: radius (m)", kPositive);
    v("condition", condition, "a start must be anywhere in the region, or in odor at release",
      {"any", "in_odor"});
    v("heading", heading, "heading at release: robot.start_heading_deg, or uniform at random",
      {"fixed", "random"});
  }
};

/// One robot's own value of a key, in a mixed team (docs/agents.md, "Mixed teams").
struct MemberSetting {
  int robot = 0;      ///< the robot, 1 .. team.count - 1
  std::string key;    ///< the key it sets, "controller.algorithm"
  std::string table;  ///< its table as files write it, "member.2.controller"
  std::string name;   ///< its name in that table, "algorithm"
  std::string help;   ///< the key's help
  ConfigValue value;  ///< the value, in file units (as get_field gives it)
};

/// Everything one run depends on besides (seed, trial); defaults are the paper's setup.
struct Scenario {
  SimParams sim;                 ///< time stepping
  ArenaParams arena;             ///< walls
  SourceParams source;           ///< odor source
  WindParams wind;               ///< wind field
  PlumeParams plume;             ///< filament plume
  OdorSensorParams odor;         ///< odor sensor
  WindSensorParams wind_sensor;  ///< wind sensor
  RobotParams robot;             ///< the robot and its start
  StartParams start;             ///< start distributions
  TeamParams team;               ///< several robots on one plume
  SupervisorParams supervisor;   ///< when a run ends
  ControllerParams controller;   ///< algorithm and its parameters
  /// The robots' own keys (a mixed team): `member.K.TABLE.KEY` sets TABLE.KEY for robot K
  /// alone; robot 0 and every key a robot does not set take the scenario's value. Sorted by
  /// robot, then key (docs/agents.md, "Mixed teams").
  std::vector<MemberSetting> members;

  /// Every config key, in file order: each table, then the keys its params struct declares; the
  /// one list used by files, CLI and Python. The controllers' tables follow "controller", one
  /// per registered controller.
  void fields(FieldVisitor& v);
  /// Reads every config key in file order, without copying the scenario.
  void read_fields(FieldReader& v) const;
};

/// The wind field's context in a run of `scenario`: the mean wind (wind.vx, wind.vy, wind.vz),
/// the arena, sim.dt, and the robots' release after the warm-up's whole steps
/// (llround(sim.warmup / sim.dt) * sim.dt, as warm_up takes them).
WindContext wind_context(const Scenario& scenario);

/// The most steps of sim.dt a warm-up or a run may take: 1e7, 270 times the paper's run (37500
/// steps), about a minute of the default plume. why: a tiny sim.dt would otherwise run for hours
/// without a word (1.3e-6 s: two hours; issue 13, F23).
inline constexpr double kMaxSteps = 1e7;

/// The most filaments released in one step (plume.release_rate * sim.dt): 1e6. why: the count is
/// converted to an integer and released one by one; a large sim.dt must not make it huge (the
/// conversion is undefined from 2^64).
inline constexpr double kMaxReleasePerStep = 1e6;

/// The arena length (m) the paper's ring and warm-up were set for: the 16 m wind tunnel.
inline constexpr double kReferenceArenaLength = 16.0;
/// The wind (m/s) the paper's ring and warm-up were set for: the plugin's 0.9 m/s (the default
/// reading's until 0.4.0), with which a filament crosses the reference arena in 17.8 s.
inline constexpr double kReferenceWind = 0.9;
/// The time the paper's ring keeps at the reference (s): the plugin's 1600 filaments released at
/// 100 /s; the plume then ends 14.4 m downwind of the source (docs/scenarios.md).
inline constexpr double kReferenceRingSpan = 16.0;
/// The paper's warm-up at the reference (s).
inline constexpr double kReferenceWarmup = 20.0;

/// How many times longer a filament takes to cross the arena along x (arena.x_max -
/// arena.x_min at wind.vx) than at the reference (16 m at 0.9 m/s), and at least 1: 1 for the
/// paper's setups; 1 as well where wind.vx <= 0 (scenario_warnings says why).
double crossing_ratio(const Scenario& scenario);

/// The time the ring keeps when plume.capacity is "auto" (s): kReferenceRingSpan *
/// crossing_ratio, so that the plume reaches as far along the arena as the paper's.
double derived_ring_span(const Scenario& scenario);

/// plume.capacity when "auto": ceil(plume.release_rate * derived_ring_span), 1600 for the
/// paper's setups, and at most kMaxCapacity.
int derived_capacity(const Scenario& scenario);

/// sim.warmup when "auto" (s): kReferenceWarmup * crossing_ratio, 20 s for the paper's setups.
double derived_warmup(const Scenario& scenario);

/// Computes every key left "auto" from the others: sim.warmup, plume.capacity, and
/// robot.start_x, robot.start_y (source.x + robot.start_offset_x, source.y +
/// robot.start_offset_y). A key set to a value keeps it. build_scenario calls it; call it after
/// writing a Scenario's fields in code.
void derive_scenario(Scenario& scenario);

/// The most filament-steps one run may take: the filaments alive (the ring, or for
/// lifetime = "leave_arena" the release rate times the arena's crossing time) times the steps of
/// the warm-up and the timeout. The paper's setup: 1600 x 38125 = 6.1e7.
double run_work(const Scenario& scenario);

/// run_work above which a scenario is warned about (1e10 filament-steps, 160 times the paper's:
/// half a minute to a minute of one core). why: valid keys can ask for hours without a word
/// (plume.release_rate = 1e5 derives a ring of 1.6e6 filaments; issue 22, G18).
inline constexpr double kLargeRunWork = 1e10;

/// What makes a valid scenario an unlikely one to track, or a slow one: the robot starts outside
/// odor (upwind of the source, beside the plume, beyond its end, or with its sensor above or
/// below the plume), the plume cannot reach the start within the warm-up, or a run may take more
/// than kLargeRunWork filament-steps. One sentence each, naming the keys to change; empty for
/// the paper's setups. Geometric, at the mean wind (docs/scenarios.md).
std::vector<std::string> scenario_warnings(const Scenario& scenario);

/// Every config key of a scenario bound to its place, in file order (Scenario::fields).
std::vector<Field> scenario_fields(Scenario& scenario);

/// A config key renamed in a later version than `after`: its old name is still accepted, with a
/// warning on stderr, until the next version.
struct RenamedKey {
  std::string_view old_key;  ///< the name it had, "wind.meander_gain"
  std::string_view new_key;  ///< the name it has, "meander.gain"
  std::string_view after;    ///< the last version that had the old name, "0.4.0"
};

/// The keys renamed since the last version, accepted under their old names wherever a key is
/// (files, --set, sweep axes, Python's keyword settings): set_field, set_field_text and
/// get_field map an old name to its new one, saying so on stderr once per process and name
/// (renamed_key_warning). A resolved scenario has the new names only.
std::span<const RenamedKey> renamed_keys();

/// The current name of a key: the new name of a renamed key, else `key` itself.
std::string_view current_key(std::string_view key);

/// What is said on stderr when a renamed key is used under its old name; it names the new one.
std::string renamed_key_warning(const RenamedKey& key);

/// Sets one key from a typed value; throws ConfigError naming the key and the allowed range.
void set_field(Scenario& scenario, std::string_view key, const ConfigValue& value);

/// As above; a renamed key's warning names `origin` (a file and what in it).
void set_field(Scenario& scenario, std::string_view key, const ConfigValue& value,
               const std::string& origin);

/// Sets one key from text as typed on the command line ("0.5", "casting", "inf").
void set_field_text(Scenario& scenario, std::string_view key, std::string_view text);

/// The current value of a key, as it would be written to a file.
ConfigValue get_field(const Scenario& scenario, std::string_view key);

/// Checks every key's range and the relations between keys; throws ConfigError.
void validate(const Scenario& scenario);

/// The scenario robot `robot` of its team runs: the scenario with that robot's own keys
/// (Scenario::members) set, and no members; the scenario itself for a robot with none.
Scenario member_scenario(const Scenario& scenario, int robot);

/// The algorithm robot `robot` sets as its own (member.K.controller.algorithm); empty when it
/// runs the team's.
std::string own_algorithm(const Scenario& scenario, int robot);

/// True when robot `robot` sets its own start (member.K.robot.start_x, _y or _heading_deg).
bool has_own_start(const Scenario& scenario, int robot);

/// Where the robots of a team start when start.region = "point": robot 0 at robot.start, the
/// others beside it (team.spacing), alternately left and right of its heading, or at their own
/// start where they set one. Headings are robot.start's (a random heading is drawn later).
std::vector<Pose> point_starts(const Scenario& scenario);

/// One key's value as it would be written to a file, with its table, name and help.
struct FieldValue {
  std::string_view table;  ///< "plume" of "plume.sigma_p"
  std::string_view name;   ///< "sigma_p" of "plume.sigma_p"
  std::string_view help;   ///< one line: meaning and unit
  ConfigValue value;       ///< file units (degrees for a _deg key)
};

/// Calls `f` for every key of the scenario, in file order, without copying it.
void for_each_value(const Scenario& scenario, const std::function<void(const FieldValue&)>& f);

/// Which keys scenario_to_toml writes.
enum class ConfigKeys {
  kAll,       ///< every key, the tables of every registered controller included
  kOfTheRun,  ///< a controller after the paper's three, or a wind field after the meander, only
              ///< when it is the one that runs
};

/// The fully resolved scenario as TOML that reads back to the same scenario: its keys, in the
/// order of the field list, with its help as a comment. With ConfigKeys::kOfTheRun (what a sweep
/// point stores) registering a controller changes no other controller's config.
std::string scenario_to_toml(const Scenario& scenario, ConfigKeys keys = ConfigKeys::kAll);

/// The scenario's values as canonical text, one `table.key=value` line per key in the order of
/// the field list: numbers as format_number writes them (they read back to the same double),
/// choices by name in quotes, no help and no comments. What a run's identity hashes
/// (scenario_hash, sweep.hpp), so that editing a key's help changes no hash; `keys` as for
/// scenario_to_toml.
std::string canonical_config(const Scenario& scenario, ConfigKeys keys = ConfigKeys::kOfTheRun);

/// Where a setting comes from; later layers override earlier ones.
enum class Layer {
  kFile,         ///< a scenario file
  kSweep,        ///< a sweep file's [set] table
  kCommandLine,  ///< --set, --algorithm, --preset
  kAxis,         ///< a sweep axis value
};

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
  /// Which layer it belongs to.
  Layer layer = Layer::kCommandLine;
};

/// Splits a command-line "key.path=value"; throws ConfigError when there is no '='.
Setting parse_override(std::string_view text);

/// Builds a scenario from defaults and settings applied in order. A `plume.preset` setting (the
/// last one wins) resets every plume row to that preset: plume rows of earlier layers are
/// dropped, rows of its own layer or later ones still win whatever their order. Every other
/// setting is applied in order; finally the whole scenario is validated. Throws ConfigError
/// naming the key.
Scenario build_scenario(const std::vector<Setting>& settings);

}  // namespace plumetrace
