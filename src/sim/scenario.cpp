#include "plumetrace/sim/scenario.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

// the file value whose SI value is `si`: the shortest decimal that converts back exactly
double unscale(double si, double scale) {
  if (scale == 1.0 || !std::isfinite(si)) return si / scale;
  char buf[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, si / scale);
    const double d = std::strtod(buf, nullptr);
    if (d * scale == si) return d;
  }
  return si / scale;
}

std::string range_text(const NumberSpec& f) {
  std::string lo =
      f.min == -INFINITY ? "" : (f.min_open ? "> " : ">= ") + bound_text(unscale(f.min, f.scale));
  std::string hi =
      f.max == INFINITY ? "" : (f.max_open ? "< " : "<= ") + bound_text(unscale(f.max, f.scale));
  if (lo.empty() && hi.empty()) return "a number";
  if (lo.empty()) return "a number " + hi;
  if (hi.empty()) return "a number " + lo;
  return "a number " + lo + " and " + hi;
}

std::string choices_text(const Choices& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + ("'" + std::string(n) + "'");
  return "one of " + out;
}

std::string full_key(std::string_view table, std::string_view name) {
  return std::string(table) + "." + std::string(name);
}

// key is "table.name"
bool is_key(std::string_view key, std::string_view table, std::string_view name) {
  return key.size() == table.size() + 1 + name.size() && key.starts_with(table) &&
         key[table.size()] == '.' && key.ends_with(name);
}

// what a derived key takes besides its range
constexpr std::string_view kOrAuto = " or 'auto'";

void check_number(const std::string& key, const NumberSpec& f, double file_value,
                  std::string_view or_auto = "") {
  const double v = file_value * f.scale;
  if (std::isinf(v) && !f.allow_infinite) {
    throw ConfigError(key + ": must be a finite number" + std::string(or_auto) + " (got " +
                      format_number(file_value) + ")");
  }
  const bool ok = !std::isnan(v) && (f.min_open ? v > f.min : v >= f.min) &&
                  (f.max_open ? v < f.max : v <= f.max);
  if (!ok) {
    throw ConfigError(key + ": must be " + range_text(f) + std::string(or_auto) + " (got " +
                      format_number(file_value) + ")");
  }
}

std::optional<double> parse_double(std::string_view text) {
  std::string s(text);
  if (s == "inf" || s == "+inf") return INFINITY;
  if (s == "-inf") return -INFINITY;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || std::isnan(v)) return std::nullopt;
  return v;
}

std::string strip_quotes(std::string_view text) {
  if (text.size() >= 2 && (text.front() == '"' || text.front() == '\'') &&
      text.back() == text.front()) {
    return std::string(text.substr(1, text.size() - 2));
  }
  return std::string(text);
}

// the SI value of a number key from a typed value or text; throws naming the key and range
double number_value(const std::string& key, const NumberSpec& spec, const ConfigValue& value,
                    bool text, std::string_view or_auto = "") {
  std::optional<double> v;
  if (text) {
    v = parse_double(std::get<std::string>(value));
  } else if (const auto* d = std::get_if<double>(&value)) {
    v = *d;
  } else if (const auto* i = std::get_if<std::int64_t>(&value)) {
    v = static_cast<double>(*i);
  }
  if (!v) {
    throw ConfigError(key + ": must be " + range_text(spec) + std::string(or_auto) + " (got " +
                      format_value(value) + ")");
  }
  check_number(key, spec, *v, or_auto);
  return *v * spec.scale;
}

int integer_value(const std::string& key, const IntegerSpec& spec, const ConfigValue& value,
                  bool text, std::string_view or_auto = "") {
  std::optional<std::int64_t> v;
  if (text) {
    const std::string s = std::get<std::string>(value);
    std::int64_t parsed = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), parsed);
    if (ec == std::errc() && ptr == s.data() + s.size() && !s.empty()) v = parsed;
  } else if (const auto* i = std::get_if<std::int64_t>(&value)) {
    v = *i;
  }
  if (!v || *v < spec.min || *v > spec.max) {
    throw ConfigError(key + ": must be an integer >= " + std::to_string(spec.min) +
                      " and <= " + std::to_string(spec.max) + std::string(or_auto) + " (got " +
                      format_value(value) + ")");
  }
  return static_cast<int>(*v);
}

// the value selects derivation: "auto" (quoted or not on the command line)
bool is_auto(const ConfigValue& value, bool text) {
  const auto* s = std::get_if<std::string>(&value);
  return s && (text ? strip_quotes(*s) : *s) == "auto";
}

int choice_value(const std::string& key, const Choices& names, const ConfigValue& value,
                 bool text) {
  const auto* s = std::get_if<std::string>(&value);
  const std::string name = s ? (text ? strip_quotes(*s) : *s) : std::string();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (s && names[i] == name) return static_cast<int>(i);
  }
  throw ConfigError(key + ": must be " + choices_text(names) + " (got " + format_value(value) +
                    ")");
}

// every key bound to its place in the scenario visited
class Collector final : public FieldVisitor {
 public:
  std::vector<Field> fields;

 private:
  void number(std::string_view key, double& value, std::string_view help,
              const NumberSpec& spec) override {
    fields.push_back(
        {full_key(current_table(), key), std::string(help), NumberField{spec, &value}});
  }
  void integer(std::string_view key, int& value, std::string_view help,
               const IntegerSpec& spec) override {
    fields.push_back(
        {full_key(current_table(), key), std::string(help), IntegerField{spec, &value}});
  }
  void choice(std::string_view key, ChoiceRef value, std::string_view help,
              const Choices& names) override {
    fields.push_back({full_key(current_table(), key), std::string(help),
                      ChoiceField{{names.begin(), names.end()},
                                  [value] { return value.get(); },
                                  [value](int i) { value.set(i); }}});
  }
};

// sets one key (the first of that name) from a typed value or text
class Setter final : public FieldVisitor {
 public:
  // `key` is matched, `shown` (the key as written: an old name of it) named in errors
  Setter(std::string_view key, std::string_view shown, const ConfigValue& value, bool text)
      : key_(key), shown_(shown), value_(value), text_(text) {}
  bool found = false;

 private:
  bool match(std::string_view key) {
    if (found || !is_key(key_, current_table(), key)) return false;
    found = true;
    return true;
  }
  void number(std::string_view key, double& value, std::string_view,
              const NumberSpec& spec) override {
    if (match(key)) value = number_value(shown_, spec, value_, text_);
  }
  void integer(std::string_view key, int& value, std::string_view,
               const IntegerSpec& spec) override {
    if (match(key)) value = integer_value(shown_, spec, value_, text_);
  }
  void choice(std::string_view key, ChoiceRef value, std::string_view,
              const Choices& names) override {
    if (match(key)) value.set(choice_value(shown_, names, value_, text_));
  }
  void derived_number(std::string_view key, double& value, std::string_view, const NumberSpec& spec,
                      bool& automatic) override {
    if (!match(key)) return;
    automatic = is_auto(value_, text_);
    if (!automatic) value = number_value(shown_, spec, value_, text_, kOrAuto);
  }
  void derived_integer(std::string_view key, int& value, std::string_view, const IntegerSpec& spec,
                       bool& automatic) override {
    if (!match(key)) return;
    automatic = is_auto(value_, text_);
    if (!automatic) value = integer_value(shown_, spec, value_, text_, kOrAuto);
  }
  void input_number(std::string_view key, double& value, std::string_view, const NumberSpec& spec,
                    bool& automatic) override {
    if (!match(key)) return;
    value = number_value(shown_, spec, value_, text_);
    automatic = true;
  }

  std::string_view key_;
  std::string shown_;
  const ConfigValue& value_;
  bool text_;
};

// calls f for every key with its value in file units
class ValueReader final : public FieldReader {
 public:
  explicit ValueReader(const std::function<void(const FieldValue&)>& f) : f_(f) {}

 private:
  void read_number(std::string_view key, double value, std::string_view help,
                   const NumberSpec& spec) override {
    f_({current_table(), key, help, unscale(value, spec.scale)});
  }
  void read_integer(std::string_view key, int value, std::string_view help,
                    const IntegerSpec&) override {
    f_({current_table(), key, help, static_cast<std::int64_t>(value)});
  }
  void read_choice(std::string_view key, int index, std::string_view help,
                   const Choices& names) override {
    f_({current_table(), key, help, std::string(names.at(static_cast<std::size_t>(index)))});
  }

  const std::function<void(const FieldValue&)>& f_;
};

// every key within its own range
class Validator final : public FieldReader {
  void read_number(std::string_view key, double value, std::string_view,
                   const NumberSpec& spec) override {
    check_number(full_key(current_table(), key), spec, unscale(value, spec.scale));
  }
  void read_integer(std::string_view key, int value, std::string_view,
                    const IntegerSpec& spec) override {
    integer_value(full_key(current_table(), key), spec, static_cast<std::int64_t>(value), false);
  }
  void read_choice(std::string_view key, int index, std::string_view,
                   const Choices& names) override {
    if (index < 0 || index >= static_cast<int>(names.size())) {
      throw ConfigError(full_key(current_table(), key) + ": must be " + choices_text(names));
    }
  }
  void input_number(std::string_view key, double& value, std::string_view, const NumberSpec& spec,
                    bool&) override {
    check_number(full_key(current_table(), key), spec, unscale(value, spec.scale));
  }
};

// every key that may be set, the input keys included, in file order
class KeyLister final : public FieldVisitor {
 public:
  std::vector<std::string> keys;

 private:
  void number(std::string_view key, double&, std::string_view, const NumberSpec&) override {
    keys.push_back(full_key(current_table(), key));
  }
  void integer(std::string_view key, int&, std::string_view, const IntegerSpec&) override {
    keys.push_back(full_key(current_table(), key));
  }
  void choice(std::string_view key, ChoiceRef, std::string_view, const Choices&) override {
    keys.push_back(full_key(current_table(), key));
  }
  void input_number(std::string_view key, double&, std::string_view, const NumberSpec&,
                    bool&) override {
    keys.push_back(full_key(current_table(), key));
  }
};

[[noreturn]] void unknown_key(const Scenario& scenario, std::string_view key) {
  // list the keys of the same table, to help with typos
  const auto dot = key.find('.');
  const std::string table(key.substr(0, dot == std::string_view::npos ? key.size() : dot + 1));
  std::string known;
  Scenario copy = scenario;
  KeyLister lister;
  copy.fields(lister);
  for (const std::string& k : lister.keys) {
    if (k.starts_with(table)) known += (known.empty() ? "" : ", ") + k;
  }
  std::string msg = "unknown config key '" + std::string(key) + "'";
  if (!known.empty()) msg += " (keys there: " + known + ")";
  throw ConfigError(msg);
}

// the keys renamed after version 0.4.0, still accepted under their old names until the next
// version: the meandering wind's keys moved to its own table (issue 24)
constexpr RenamedKey kRenamedKeys[] = {
    {"wind.meander_gain", "meander.gain", "0.4.0"},
    {"wind.meander_damping", "meander.damping", "0.4.0"},
    {"wind.meander_bandwidth", "meander.bandwidth", "0.4.0"},
    {"wind.meander_kx", "meander.kx", "0.4.0"},
    {"wind.meander_ky", "meander.ky", "0.4.0"},
    {"wind.meander_nx", "meander.nx", "0.4.0"},
    {"wind.meander_ny", "meander.ny", "0.4.0"},
};

// the current name of `key`; an old name is said on stderr, once per process and name, with
// `origin` (a file, "--set") where known
std::string_view current_key_warned(std::string_view key, const std::string& origin) {
  const std::string_view current = current_key(key);
  if (current == key) return key;
  static std::mutex mutex;
  static std::set<std::string, std::less<>> warned;
  const std::lock_guard<std::mutex> lock(mutex);
  if (warned.emplace(key).second) {
    const RenamedKey& r = *std::find_if(std::begin(kRenamedKeys), std::end(kRenamedKeys),
                                        [&](const RenamedKey& k) { return k.old_key == key; });
    std::fprintf(stderr, "plumetrace: warning: %s%s\n",
                 origin.empty() ? "" : (origin + ": ").c_str(), renamed_key_warning(r).c_str());
  }
  return current;
}

void set(Scenario& scenario, std::string_view key, const ConfigValue& value, bool text,
         const std::string& origin = "");

constexpr std::string_view kMemberPrefix = "member.";

// why: a robot's own keys are what is its own: its controller, its sensors, its body's motion
// and start; the world's and the team's keys (wind, plume, arena, start regions, team,
// supervisor) are one for all, and so is robot.radius, which contacts take as the team's
bool member_may_set(std::string_view key) {
  const std::string_view table = key.substr(0, key.find('.'));
  if (key == "robot.radius" || key == "robot.start_offset_x" || key == "robot.start_offset_y") {
    return false;
  }
  if (table == "controller" || table == "odor" || table == "wind_sensor" || table == "robot") {
    return true;
  }
  for (const auto& e : controller_registry().entries()) {
    if (e.table == table) return true;
  }
  for (const auto& e : sensor_model_registry().entries()) {
    if (e.table == table) return true;
  }
  return false;
}

// sets member.K.TABLE.KEY: checks the key and its value on a copy, keeps the value as written
void set_member(Scenario& scenario, std::string_view key, const ConfigValue& value, bool text,
                const std::string& origin) {
  const std::string_view rest = key.substr(kMemberPrefix.size());
  const std::size_t dot = rest.find('.');
  int robot = -1;
  const std::string_view digits = rest.substr(0, dot);
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), robot);
  if (dot == std::string_view::npos || digits.empty() || error != std::errc{} ||
      end != digits.data() + digits.size() || robot < 1 || robot >= kMaxTeam) {
    throw ConfigError("'" + std::string(key) +
                      "': a robot's own key is member.K.TABLE.KEY with K a robot of the team, 1 "
                      "to " +
                      std::to_string(kMaxTeam - 1) +
                      " (robot 0 takes the scenario's keys; docs/agents.md, \"Mixed teams\")");
  }
  const std::string prefix = std::string(kMemberPrefix) + std::to_string(robot) + ".";
  const std::string_view shown = rest.substr(dot + 1);
  const std::string own(current_key_warned(shown, origin));
  if (!member_may_set(own)) {
    throw ConfigError(prefix + own +
                      ": a robot's own keys are its controller's (controller, the algorithms' "
                      "tables), its sensors' (odor, its model's table, wind_sensor) and its "
                      "body's (robot, robot.radius and the start offsets aside); the others are "
                      "the team's or the world's");
  }
  Scenario probe = scenario;
  probe.members.clear();
  try {
    set(probe, own, value, text, origin);
  } catch (const ConfigError& e) {
    // the message names the key as the robot's: member.K.TABLE.KEY
    std::string message = e.what();
    const std::size_t at = message.find(own);
    if (at == std::string::npos) throw ConfigError(prefix + own + ": " + message);
    message.insert(at, prefix);
    throw ConfigError(message);
  }
  MemberSetting m;
  m.robot = robot;
  m.key = own;
  const std::size_t split = own.rfind('.');
  m.table = prefix + own.substr(0, split);
  m.name = own.substr(split + 1);
  for_each_value(probe, [&](const FieldValue& f) {
    if (is_key(own, f.table, f.name)) {
      m.help = f.help;
      m.value = f.value;
    }
  });
  auto& ms = scenario.members;
  const auto same = std::find_if(ms.begin(), ms.end(), [&](const MemberSetting& x) {
    return x.robot == robot && x.key == own;
  });
  if (same != ms.end()) {
    *same = std::move(m);
  } else {
    ms.push_back(std::move(m));
  }
  std::sort(ms.begin(), ms.end(), [](const MemberSetting& a, const MemberSetting& b) {
    return a.robot != b.robot ? a.robot < b.robot : a.key < b.key;
  });
}

void set(Scenario& scenario, std::string_view key, const ConfigValue& value, bool text,
         const std::string& origin) {
  if (key.starts_with(kMemberPrefix)) {
    set_member(scenario, key, value, text, origin);
    return;
  }
  Setter setter(current_key_warned(key, origin), key, value, text);
  scenario.fields(setter);
  if (!setter.found) unknown_key(scenario, key);
}

// the tables of a scenario in file order, each with its params struct
template <class S, class Visit>
void each_table(S& s, Visit visit) {
  visit("sim", s.sim);
  visit("arena", s.arena);
  visit("source", s.source);
  visit("wind", s.wind);
  visit("plume", s.plume);
  visit("odor", s.odor);
  visit("wind_sensor", s.wind_sensor);
  visit("robot", s.robot);
  visit("start", s.start);
  visit("team", s.team);
  visit("supervisor", s.supervisor);
  visit("controller", s.controller);
}

}  // namespace

void Scenario::fields(FieldVisitor& v) {
  each_table(*this, [&v](std::string_view table, auto& params) {
    v.table(table);
    params.fields(v);
  });
}

void Scenario::read_fields(FieldReader& v) const {
  each_table(*this, [&v](std::string_view table, const auto& params) {
    v.table(table);
    plumetrace::read_fields(params, v);
  });
}

std::vector<Field> scenario_fields(Scenario& scenario) {
  Collector collector;
  scenario.fields(collector);
  return std::move(collector.fields);
}

void set_field(Scenario& scenario, std::string_view key, const ConfigValue& value) {
  set(scenario, key, value, false);
}

void set_field(Scenario& scenario, std::string_view key, const ConfigValue& value,
               const std::string& origin) {
  set(scenario, key, value, false, origin);
}

void set_field_text(Scenario& scenario, std::string_view key, std::string_view text) {
  set(scenario, key, std::string(text), true);
}

std::span<const RenamedKey> renamed_keys() { return kRenamedKeys; }

std::string_view current_key(std::string_view key) {
  for (const RenamedKey& r : kRenamedKeys) {
    if (r.old_key == key) return r.new_key;
  }
  return key;
}

std::string renamed_key_warning(const RenamedKey& key) {
  return "config key " + std::string(key.old_key) + " is deprecated: write " +
         std::string(key.new_key) + " (renamed after version " + std::string(key.after) +
         "; the old name is accepted until the next version)";
}

ConfigValue get_field(const Scenario& scenario, std::string_view key) {
  std::optional<ConfigValue> value;
  const std::string_view current = current_key_warned(key, "");
  for_each_value(scenario, [&](const FieldValue& f) {
    if (!value && is_key(current, f.table, f.name)) value = f.value;
  });
  if (!value) unknown_key(scenario, key);
  return *value;
}

void for_each_value(const Scenario& scenario, const std::function<void(const FieldValue&)>& f) {
  ValueReader reader(f);
  read_fields(scenario, reader);
  for (const MemberSetting& m : scenario.members) f({m.table, m.name, m.help, m.value});
}

Scenario member_scenario(const Scenario& scenario, int robot) {
  Scenario s = scenario;
  s.members.clear();
  bool own = false;
  for (const MemberSetting& m : scenario.members) {
    if (m.robot != robot) continue;
    set(s, m.key, m.value, false);
    own = true;
  }
  if (own) derive_scenario(s);
  return s;
}

std::string own_algorithm(const Scenario& scenario, int robot) {
  for (const MemberSetting& m : scenario.members) {
    if (m.robot == robot && m.key == "controller.algorithm") {
      if (const auto* name = std::get_if<std::string>(&m.value)) return *name;
    }
  }
  return {};
}

bool has_own_start(const Scenario& scenario, int robot) {
  return std::any_of(scenario.members.begin(), scenario.members.end(), [&](const MemberSetting& m) {
    return m.robot == robot && m.key.starts_with("robot.start_");
  });
}

std::vector<Pose> point_starts(const Scenario& scenario) {
  const RobotParams& robot = scenario.robot;
  const int n = scenario.team.count;
  std::vector<Pose> starts;
  starts.reserve(static_cast<std::size_t>(n));
  // robot 0 at the start, the others beside it, alternately left and right of its heading
  const Vec2 left{-math::sin(robot.start.heading), math::cos(robot.start.heading)};
  for (int k = 0; k < n; ++k) {
    if (k > 0 && has_own_start(scenario, k)) {
      starts.push_back(member_scenario(scenario, k).robot.start);
      continue;
    }
    const double side = (k % 2 == 1 ? 1.0 : -1.0) * static_cast<double>((k + 1) / 2);
    const double off = side * scenario.team.spacing;
    starts.push_back(
        {robot.start.x + off * left.x, robot.start.y + off * left.y, robot.start.heading});
  }
  return starts;
}

namespace {

// why: a team or a start region that cannot be placed is bad input, found before any run (issue
// 24, item 8); what only a run can tell (a region mostly outside odor) is said by the run
void check_team_start(const Scenario& scenario) {
  const auto& a = scenario.arena;
  const RobotParams& robot = scenario.robot;
  const double r = robot.radius;
  const StartParams& st = scenario.start;
  const TeamParams& team = scenario.team;
  const bool contact = team.contact == TeamParams::Contact::kOn;
  const std::string n = std::to_string(team.count);
  if (st.region == StartRegion::kPoint) {
    if (st.condition == StartCondition::kInOdor) {
      throw ConfigError(
          "start.condition: 'in_odor' needs a start region to draw from (start.region = "
          "'rectangle' or 'disc'); a point start is where it is");
    }
    if (team.count < 2) return;
    const std::vector<Pose> starts = point_starts(scenario);
    const auto own_keys = [](int k) {
      const std::string m = "member." + std::to_string(k) + ".robot.";
      return m + "start_x, " + m + "start_y";
    };
    bool formation = false;  // two robots or more stand in the line beside robot 0
    for (int k = 1; k < team.count; ++k) formation = formation || !has_own_start(scenario, k);
    if (contact && formation && team.spacing < 2.0 * r) {
      throw ConfigError("team.spacing: the " + n + " robots would start inside each other (" +
                        bound_text(team.spacing) + " m apart, less than two radii, " +
                        bound_text(2.0 * r) + " m); set team.spacing >= " + bound_text(2.0 * r) +
                        " or team.contact = 'off'");
    }
    const double keep_off = scenario.source.solid_radius + r;
    // why: from the last robot down, so the first formation robot found outside is an outermost
    for (int k = team.count - 1; k >= 1; --k) {
      const Pose& p = starts[static_cast<std::size_t>(k)];
      const bool own = has_own_start(scenario, k);
      if (p.x - r < a.x_min || p.x + r > a.x_max || p.y - r < a.y_min || p.y + r > a.y_max) {
        if (own) {
          throw ConfigError(own_keys(k) + ": robot " + std::to_string(k) +
                            " would start outside the arena, at (" + bound_text(p.x) + ", " +
                            bound_text(p.y) + ") m");
        }
        // the outermost robots: on the left k = 1, 3, ... at (k + 1) / 2 spacings, on the
        // right k = 2, 4, ... at k / 2
        throw ConfigError("team.count, team.spacing: the outermost of the " + n +
                          " robots would start outside the arena, at (" + bound_text(p.x) + ", " +
                          bound_text(p.y) +
                          ") m; fewer robots, a smaller spacing or a "
                          "start region (start.region)");
      }
      if (scenario.source.solid_radius > 0.0 &&
          math::hypot(p.x - scenario.source.center.x, p.y - scenario.source.center.y) <= keep_off) {
        throw ConfigError((own ? own_keys(k) : std::string("team.count, team.spacing")) +
                          ": robot " + std::to_string(k) +
                          " would start inside the source's solid body");
      }
      if (!own || !contact) continue;
      for (int j = 0; j < team.count; ++j) {
        const Pose& q = starts[static_cast<std::size_t>(j)];
        if (j == k || (j > k && has_own_start(scenario, j))) continue;
        if (math::hypot(p.x - q.x, p.y - q.y) < 2.0 * r) {
          throw ConfigError(own_keys(k) + ": robot " + std::to_string(k) +
                            " would start inside robot " + std::to_string(j) + " (" +
                            bound_text(math::hypot(p.x - q.x, p.y - q.y)) +
                            " m apart, less than two radii, " + bound_text(2.0 * r) +
                            " m); move it, or set team.contact = 'off'");
        }
      }
    }
    return;
  }
  const double ox = st.frame == StartFrame::kSource ? scenario.source.center.x : 0.0;
  const double oy = st.frame == StartFrame::kSource ? scenario.source.center.y : 0.0;
  // the region in the arena's frame, as a box; where a robot's centre may be
  double x0, x1, y0, y1;
  std::string keys;
  if (st.region == StartRegion::kRectangle) {
    if (!(st.x_max > st.x_min)) throw ConfigError("start.x_max: must be > start.x_min");
    if (!(st.y_max > st.y_min)) throw ConfigError("start.y_max: must be > start.y_min");
    x0 = ox + st.x_min, x1 = ox + st.x_max, y0 = oy + st.y_min, y1 = oy + st.y_max;
    keys = "start.x_min, start.x_max, start.y_min, start.y_max";
  } else {
    x0 = ox + st.cx - st.radius, x1 = ox + st.cx + st.radius;
    y0 = oy + st.cy - st.radius, y1 = oy + st.cy + st.radius;
    keys = "start.cx, start.cy, start.radius";
  }
  const double fx0 = std::max(x0, a.x_min + r), fx1 = std::min(x1, a.x_max - r);
  const double fy0 = std::max(y0, a.y_min + r), fy1 = std::min(y1, a.y_max - r);
  bool fits = fx1 > fx0 && fy1 > fy0;
  if (fits && st.region == StartRegion::kDisc) {
    // the point of the free box nearest the disc's centre lies inside the disc
    const double cx = ox + st.cx, cy = oy + st.cy;
    const double nx = std::clamp(cx, fx0, fx1), ny = std::clamp(cy, fy0, fy1);
    fits = math::hypot(nx - cx, ny - cy) < st.radius;
  }
  if (!fits) {
    throw ConfigError(keys + ": no robot fits in the start region (" +
                      (st.frame == StartFrame::kSource ? "relative to the source; " : "") +
                      "a robot's centre must be robot.radius = " + bound_text(r) +
                      " m clear of the walls)");
  }
  if (contact && team.count > 1) {
    double area = (fx1 - fx0) * (fy1 - fy0);
    if (st.region == StartRegion::kDisc) area = std::min(area, kPi * st.radius * st.radius);
    // why: random placement of discs fills at most about half the plane (random sequential
    // adsorption jams at 0.547); a robot's exclusion square is (2 r)^2
    if (static_cast<double>(team.count) * 4.0 * r * r > 0.5 * area) {
      throw ConfigError("team.count: " + n + " robots of radius " + bound_text(r) +
                        " m do not fit apart in the start region (" + keys + "; about " +
                        bound_text(area) + " m^2 inside the walls)");
    }
  }
}

// every robot's own keys name a robot of the team and make, with the rest, a scenario that
// holds for that robot alone
void check_members(const Scenario& scenario) {
  const int n = scenario.team.count;
  int checked = 0;
  for (const MemberSetting& m : scenario.members) {
    const std::string key = m.table + "." + m.name;
    if (m.robot >= n) {
      throw ConfigError(key + ": the team has " + std::to_string(n) +
                        (n == 1 ? " robot" : " robots") + " (team.count), so there is no robot " +
                        std::to_string(m.robot));
    }
    if (m.key.starts_with("robot.start_") && scenario.start.region != StartRegion::kPoint) {
      throw ConfigError(key +
                        ": a robot's own start needs start.region = 'point'; in a start "
                        "region every robot draws its start");
    }
    if (m.robot == checked) continue;
    checked = m.robot;
    Scenario alone = member_scenario(scenario, m.robot);
    alone.team.count = 1;
    try {
      validate(alone);
    } catch (const ConfigError& e) {
      throw ConfigError("member." + std::to_string(m.robot) + ": " + e.what());
    }
  }
}

}  // namespace

void validate(const Scenario& scenario) {
  // every key within its own range
  Validator validator;
  read_fields(scenario, validator);
  // relations between keys
  const auto& a = scenario.arena;
  if (!(a.x_max > a.x_min)) throw ConfigError("arena.x_max: must be > arena.x_min");
  if (!(a.y_max > a.y_min)) throw ConfigError("arena.y_max: must be > arena.y_min");
  const auto& src = scenario.source.center;
  if (src.x < a.x_min || src.x > a.x_max || src.y < a.y_min || src.y > a.y_max) {
    throw ConfigError("source.x, source.y: the source must lie inside the arena");
  }
  const double solid = scenario.source.solid_radius;
  if (!(scenario.supervisor.success_radius > 0.0) && !(solid > 0.0)) {
    throw ConfigError(
        "supervisor.success_radius: must be a number > 0 (0 only with source.solid_radius > 0)");
  }
  const RobotParams& robot = scenario.robot;
  const auto& start = robot.start;
  const double r = robot.radius;
  // where the start follows the source, the keys that put it there
  const auto follows = [&](bool automatic, const char* axis, double source, double offset) {
    if (!automatic) return std::string();
    const std::string a(axis);
    return " (robot.start_" + a + " follows the source: source." + a + " + robot.start_offset_" +
           a + " = " + bound_text(source) + " + " + bound_text(offset) + " = " +
           bound_text(source + offset) + " m; set robot.start_offset_" + a + " or robot.start_" +
           a + ")";
  };
  if (solid > 0.0 && math::hypot(start.x - src.x, start.y - src.y) <= solid + r) {
    throw ConfigError(
        "robot.start_x, robot.start_y: the robot must start clear of the solid source "
        "(source.solid_radius)");
  }
  if (start.x - r < a.x_min || start.x + r > a.x_max) {
    throw ConfigError("robot.start_x: the robot must start inside the arena, clear of the walls" +
                      follows(robot.start_x_auto, "x", src.x, robot.start_offset.x));
  }
  if (start.y - r < a.y_min || start.y + r > a.y_max) {
    throw ConfigError("robot.start_y: the robot must start inside the arena, clear of the walls" +
                      follows(robot.start_y_auto, "y", src.y, robot.start_offset.y));
  }
  check_team_start(scenario);
  check_members(scenario);
  if (scenario.sim.dt > scenario.supervisor.timeout) {
    throw ConfigError("sim.dt: must not exceed supervisor.timeout");
  }
  const double dt = scenario.sim.dt;
  const auto steps = [&](const char* key, double time, const std::string& why) {
    if (time / dt > kMaxSteps) {
      throw ConfigError(std::string(key) + ": must be at most " + bound_text(kMaxSteps) +
                        " steps of sim.dt (got " + bound_text(time) + " s / " + bound_text(dt) +
                        " s = " + bound_text(time / dt) + " steps)" + why);
    }
  };
  steps("sim.warmup", scenario.sim.warmup,
        scenario.sim.warmup_auto
            ? " (derived from wind.vx = " + bound_text(scenario.wind.velocity.x) +
                  " m/s and the arena's length: raise wind.vx or set sim.warmup)"
            : "");
  steps("supervisor.timeout", scenario.supervisor.timeout, "");
  check_wind_field(scenario.wind, wind_context(scenario));
  check_controller(scenario.controller);
  const double per_step = scenario.plume.release_rate * dt;
  if (per_step > kMaxReleasePerStep) {
    throw ConfigError("plume.release_rate: must release at most " + bound_text(kMaxReleasePerStep) +
                      " filaments per step of sim.dt (got " +
                      bound_text(scenario.plume.release_rate) + " /s * " + bound_text(dt) +
                      " s = " + bound_text(per_step) + ")");
  }
}

Setting parse_override(std::string_view text) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    throw ConfigError("--set '" + std::string(text) + "': expected key.path=value");
  }
  return {std::string(text.substr(0, eq)), std::string(text.substr(eq + 1)), true, "--set",
          Layer::kCommandLine};
}

namespace {

void apply(Scenario& scenario, const Setting& s) {
  try {
    set(scenario, s.key, s.value, s.text, s.origin);
  } catch (const ConfigError& e) {
    if (s.origin.empty()) throw;
    throw ConfigError(s.origin + ": " + e.what());
  }
}

}  // namespace

Scenario build_scenario(const std::vector<Setting>& settings) {
  Scenario scenario;
  // the preset first: it resets every plume row, explicit rows then win whatever their order
  const Setting* preset = nullptr;
  for (const auto& s : settings) {
    if (s.key == "plume.preset") preset = &s;
  }
  if (preset) {
    Scenario probe;
    apply(probe, *preset);
    scenario.plume = plume_preset(probe.plume.preset);
  }
  for (const auto& s : settings) {
    // why: a preset chosen in a later layer (say a sweep's [set] on a full scenario file)
    // replaces the plume rows that earlier layers wrote out
    const bool overridden_row = preset && s.key != "plume.preset" &&
                                s.key.rfind("plume.", 0) == 0 && s.layer < preset->layer;
    if (overridden_row) continue;
    apply(scenario, s);
  }
  derive_scenario(scenario);
  validate(scenario);
  return scenario;
}

WindContext wind_context(const Scenario& scenario) {
  const double dt = scenario.sim.dt;
  const auto warmup_steps = static_cast<double>(std::llround(scenario.sim.warmup / dt));
  return {scenario.wind.velocity, wind_region(scenario.arena), dt, warmup_steps * dt};
}

double crossing_ratio(const Scenario& scenario) {
  const double vx = scenario.wind.velocity.x;
  if (!(vx > 0.0)) return 1.0;
  const double length = scenario.arena.x_max - scenario.arena.x_min;
  // why: written so that the reference itself gives exactly 1 (both products are 14.4 rounded
  // the same way), so that the paper's setups keep their 1600 filaments and 20 s to the bit
  const double ratio = (length * kReferenceWind) / (kReferenceArenaLength * vx);
  return std::isfinite(ratio) ? std::max(1.0, ratio) : INFINITY;
}

double derived_ring_span(const Scenario& scenario) {
  return kReferenceRingSpan * crossing_ratio(scenario);
}

int derived_capacity(const Scenario& scenario) {
  const double count = std::ceil(scenario.plume.release_rate * derived_ring_span(scenario));
  // why: at most the ring's limit; a plume that then ends before the robot is warned about
  // (scenario_warnings) rather than refused, since every release rate up to its limit is valid
  return count < kMaxCapacity ? std::max(1, static_cast<int>(count)) : kMaxCapacity;
}

double derived_warmup(const Scenario& scenario) {
  return kReferenceWarmup * crossing_ratio(scenario);
}

void derive_scenario(Scenario& scenario) {
  if (scenario.sim.warmup_auto) scenario.sim.warmup = derived_warmup(scenario);
  if (scenario.plume.capacity_auto) scenario.plume.capacity = derived_capacity(scenario);
  RobotParams& robot = scenario.robot;
  const Vec3& source = scenario.source.center;
  if (robot.start_x_auto) robot.start.x = source.x + robot.start_offset.x;
  if (robot.start_y_auto) robot.start.y = source.y + robot.start_offset.y;
}

double run_work(const Scenario& scenario) {
  const PlumeParams& plume = scenario.plume;
  const double vx = scenario.wind.velocity.x;
  const double crossing =
      vx > 0.0 ? (scenario.arena.x_max - scenario.arena.x_min) / vx : scenario.supervisor.timeout;
  const double alive = plume.lifetime == Lifetime::kRing ? static_cast<double>(plume.capacity)
                                                         : plume.release_rate * crossing;
  return alive * (scenario.sim.warmup + scenario.supervisor.timeout) / scenario.sim.dt;
}

std::vector<std::string> scenario_warnings(const Scenario& scenario) {
  // a length or time in a sentence: to the centimetre (or hundredth of a second)
  const auto cm = [](double v) { return bound_text(std::round(v * 100.0) / 100.0); };
  std::vector<std::string> out;
  if (const double work = run_work(scenario); work > kLargeRunWork) {
    const auto sig = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.2g", v);
      return std::string(text);
    };
    out.push_back(
        "a run may take up to " + sig(work) + " filament-steps (" +
        (scenario.plume.lifetime == Lifetime::kRing
             ? "plume.capacity = " + std::to_string(scenario.plume.capacity) + " filaments"
             : "the filaments plume.release_rate = " + bound_text(scenario.plume.release_rate) +
                   " /s keeps in the arena") +
        " over (sim.warmup + supervisor.timeout) / sim.dt = " +
        sig((scenario.sim.warmup + scenario.supervisor.timeout) / scenario.sim.dt) + " steps), " +
        sig(work / 6.1e7) +
        " times the paper's setup: minutes to hours per run at 3 to 10 ns per filament-step "
        "(docs/performance.md); lower plume.release_rate or plume.capacity, or "
        "supervisor.timeout");
  }
  const Vec3& source = scenario.source.center;
  const Pose& start = scenario.robot.start;
  const double vx = scenario.wind.velocity.x;
  if (!(vx > 0.0)) {
    out.push_back("wind.vx = " + bound_text(vx) +
                  " m/s does not carry odor downwind (+x) from the source: the robot starts "
                  "outside odor; set wind.vx > 0");
    return out;
  }
  const double downwind = start.x - source.x;
  if (!(downwind > 0.0)) {
    out.push_back("the robot starts upwind of the source (robot.start_x = " + cm(start.x) +
                  " m, source.x = " + cm(source.x) +
                  " m), outside odor: set robot.start_offset_x > 0 (or robot.start_x)");
    return out;
  }
  // how far the odor spreads to each side of the centreline where the robot starts: the release
  // radius, a filament's width and 3 standard deviations of the random walk on the way there
  const PlumeParams& plume = scenario.plume;
  const double dt = scenario.sim.dt;
  const double steps = downwind / vx / dt;
  const double spread = scenario.source.radius + plume.initial_width +
                        3.0 * walk_stddev(plume, dt) * std::sqrt(steps);
  const std::string move = "or move the robot's start (robot.start_offset_x or robot.start_x)";
  const double front = vx * scenario.sim.warmup;
  const bool ring = plume.lifetime == Lifetime::kRing;
  const double span = static_cast<double>(plume.capacity) / plume.release_rate;
  if (downwind > front + spread) {
    out.push_back("the plume cannot reach the robot's start within the warm-up: its front is " +
                  cm(front) + " m downwind of the source at release (wind.vx * sim.warmup = " +
                  bound_text(vx) + " m/s * " + cm(scenario.sim.warmup) + " s), the robot " +
                  cm(downwind) + " m: raise sim.warmup (or set it to \"auto\"), " + move);
  } else if (ring && downwind > vx * span + spread) {
    out.push_back(
        "the robot starts outside odor, beyond the plume's end: the ring of plume.capacity = " +
        std::to_string(plume.capacity) +
        " filaments at plume.release_rate = " + bound_text(plume.release_rate) + " /s keeps " +
        cm(span) + " s of plume, which ends " + cm(vx * span) +
        " m downwind of the source at wind.vx = " + bound_text(vx) + " m/s, and the robot starts " +
        cm(downwind) + " m downwind: raise plume.capacity (or set it to \"auto\"), " + move);
  }
  // the centreline of the mean wind where the robot starts
  const double centre = source.y + scenario.wind.velocity.y / vx * downwind;
  const double aside = std::abs(start.y - centre);
  if (aside > spread) {
    out.push_back("the robot starts outside odor, " + cm(aside) +
                  " m to the side of the plume's centreline (y = " + cm(centre) +
                  " m where it starts: source.y + wind.vy / wind.vx * (robot.start_x - "
                  "source.x)), while the odor spreads about " +
                  cm(spread) +
                  " m to each side: set robot.start_y to \"auto\" (it follows source.y + "
                  "robot.start_offset_y), or robot.start_offset_y or robot.start_y nearer the "
                  "centreline");
  }
  // the sensor's height: the walk spreads odor up and down as it does sideways (issue 22)
  const double above = scenario.odor.height - source.z;
  if (std::abs(above) > spread) {
    out.push_back("the robot's odor sensor is " + cm(std::abs(above)) + " m " +
                  (above > 0.0 ? "above" : "below") + " the source's centre (odor.height = " +
                  cm(scenario.odor.height) + " m, source.z = " + cm(source.z) +
                  " m), while the odor spreads about " + cm(spread) +
                  " m up and down where the robot starts: it may never perceive odor; set "
                  "odor.height nearer source.z");
  }
  return out;
}

namespace {

// calls f for every key of `keys` (ConfigKeys) in file order
void for_each_value_of(const Scenario& scenario, ConfigKeys keys,
                       const std::function<void(const FieldValue&)>& f) {
  // why: the keys of a controller registered outside the library (examples/zigzag, a Python
  // one) are in a run's config only when it is the one that runs, so that registering it
  // changes neither the stored config nor the hash of a run of any other controller (a store
  // made by the plain command stays the same store in a program with more controllers)
  // The same holds for the baselines built in after the paper's three (infotaxis, ...): adding
  // one changed no stored config of a run that does not use it. The paper's three are always
  // written, as every store before 0.6.0 wrote them. A table is kept when robot 0 or any
  // member of a mixed team runs its controller.
  const ControllerRegistry& registry = controller_registry();
  const std::size_t always = builtin_algorithms().size();
  std::vector<std::string> running{
      registry[static_cast<std::size_t>(scenario.controller.algorithm)].name};
  for (int k = 1; k < scenario.team.count; ++k) {
    if (std::string own = own_algorithm(scenario, k); !own.empty())
      running.push_back(std::move(own));
  }
  std::vector<std::string> unused_tables;
  for (std::size_t i = always; keys == ConfigKeys::kOfTheRun && i < registry.size(); ++i) {
    if (std::find(running.begin(), running.end(), registry[i].name) == running.end()) {
      unused_tables.push_back(registry[i].table);
    }
  }
  // why: likewise for the wind fields after those of 0.6.0 (constant, meander; the switching
  // wind and later ones): a field's table is in a run's config only when it blows there, so
  // that adding a field changes no stored config of a run in another wind
  const WindRegistry& winds = wind_field_registry();
  const std::size_t always_winds = static_cast<std::size_t>(WindModel::kMeander) + 1;
  for (std::size_t i = always_winds; keys == ConfigKeys::kOfTheRun && i < winds.size(); ++i) {
    if (i != static_cast<std::size_t>(scenario.wind.model)) unused_tables.push_back(winds[i].table);
  }
  for_each_value(scenario, [&](const FieldValue& v) {
    if (std::find(unused_tables.begin(), unused_tables.end(), v.table) == unused_tables.end()) {
      f(v);
    }
  });
}

}  // namespace

std::string scenario_to_toml(const Scenario& scenario, ConfigKeys keys) {
  std::ostringstream out;
  std::string table;
  for_each_value_of(scenario, keys, [&](const FieldValue& f) {
    if (f.table != table) {
      out << (table.empty() ? "" : "\n") << "[" << f.table << "]\n";
      table = f.table;
    }
    const std::string text = std::holds_alternative<std::string>(f.value)
                                 ? "\"" + std::get<std::string>(f.value) + "\""
                                 : format_value(f.value);
    out << f.name << " = " << text << "  # " << f.help << "\n";
  });
  return out.str();
}

std::string canonical_config(const Scenario& scenario, ConfigKeys keys) {
  std::string out;
  for_each_value_of(scenario, keys, [&](const FieldValue& f) {
    out.append(f.table).append(".").append(f.name).append("=").append(format_value(f.value));
    out += '\n';
  });
  return out;
}

}  // namespace plumetrace
