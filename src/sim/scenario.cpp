#include "plumetrace/sim/scenario.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>

namespace plumetrace {

namespace {

NumberField positive(double& v) { return {&v, 0.0, INFINITY, true, false}; }
NumberField non_negative(double& v) { return {&v, 0.0, INFINITY, false, false}; }
NumberField any(double& v) { return {&v}; }

template <class E>
ChoiceField choice(E& value, std::vector<std::string> names) {
  return {std::move(names), [&value] { return static_cast<int>(value); },
          [&value](int i) { value = static_cast<E>(i); }};
}

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

// a bound or count as people write it: 0.5, 1200, 1e7, 1.3e-6
std::string bound_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", v);
  std::string s(buf);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  // 1e+07 -> 1e7, 1.3e-06 -> 1.3e-6
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  exponent.erase(0, exponent.find_first_not_of("+-0"));
  return s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

// why: the names and their order come from the controller registry, so they are written once
ChoiceField algorithm_choice(Algorithm& value) {
  const auto& all = all_algorithms();
  std::vector<std::string> names;
  for (const Algorithm a : all) names.emplace_back(algorithm_name(a));
  return {std::move(names),
          [&value, &all] {
            return static_cast<int>(std::find(all.begin(), all.end(), value) - all.begin());
          },
          [&value, &all](int i) { value = all[static_cast<std::size_t>(i)]; }};
}

std::string range_text(const NumberField& f) {
  std::string lo =
      f.min == -INFINITY ? "" : (f.min_open ? "> " : ">= ") + bound_text(unscale(f.min, f.scale));
  std::string hi =
      f.max == INFINITY ? "" : (f.max_open ? "< " : "<= ") + bound_text(unscale(f.max, f.scale));
  if (lo.empty() && hi.empty()) return "a number";
  if (lo.empty()) return "a number " + hi;
  if (hi.empty()) return "a number " + lo;
  return "a number " + lo + " and " + hi;
}

std::string choices_text(const ChoiceField& f) {
  std::string out;
  for (const auto& n : f.names) out += (out.empty() ? "" : ", ") + ("'" + n + "'");
  return "one of " + out;
}

const Field* find(const std::vector<Field>& fields, std::string_view key) {
  for (const auto& f : fields) {
    if (f.key == key) return &f;
  }
  return nullptr;
}

[[noreturn]] void unknown_key(const std::vector<Field>& fields, std::string_view key) {
  // list the keys of the same table, to help with typos
  const auto dot = key.find('.');
  const std::string table(key.substr(0, dot == std::string_view::npos ? key.size() : dot + 1));
  std::string known;
  for (const auto& f : fields) {
    if (f.key.rfind(table, 0) == 0) known += (known.empty() ? "" : ", ") + f.key;
  }
  std::string msg = "unknown config key '" + std::string(key) + "'";
  if (!known.empty()) msg += " (keys there: " + known + ")";
  throw ConfigError(msg);
}

void check_number(const std::string& key, const NumberField& f, double file_value) {
  const double v = file_value * f.scale;
  if (std::isinf(v) && !f.allow_infinite) {
    throw ConfigError(key + ": must be a finite number (got " + format_number(file_value) + ")");
  }
  const bool ok = !std::isnan(v) && (f.min_open ? v > f.min : v >= f.min) &&
                  (f.max_open ? v < f.max : v <= f.max);
  if (!ok) {
    throw ConfigError(key + ": must be " + range_text(f) + " (got " + format_number(file_value) +
                      ")");
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

void assign(const Field& field, const ConfigValue& value, bool text) {
  const std::string& key = field.key;
  if (const auto* num = std::get_if<NumberField>(&field.kind)) {
    std::optional<double> v;
    if (text) {
      v = parse_double(std::get<std::string>(value));
    } else if (const auto* d = std::get_if<double>(&value)) {
      v = *d;
    } else if (const auto* i = std::get_if<std::int64_t>(&value)) {
      v = static_cast<double>(*i);
    }
    if (!v) {
      throw ConfigError(key + ": must be " + range_text(*num) + " (got " + format_value(value) +
                        ")");
    }
    check_number(key, *num, *v);
    *num->value = *v * num->scale;
  } else if (const auto* in = std::get_if<IntegerField>(&field.kind)) {
    std::optional<std::int64_t> v;
    if (text) {
      const std::string s = std::get<std::string>(value);
      std::int64_t parsed = 0;
      const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), parsed);
      if (ec == std::errc() && ptr == s.data() + s.size() && !s.empty()) v = parsed;
    } else if (const auto* i = std::get_if<std::int64_t>(&value)) {
      v = *i;
    }
    if (!v || *v < in->min || *v > in->max) {
      throw ConfigError(key + ": must be an integer >= " + std::to_string(in->min) + " and <= " +
                        std::to_string(in->max) + " (got " + format_value(value) + ")");
    }
    *in->value = static_cast<int>(*v);
  } else {
    const auto& ch = std::get<ChoiceField>(field.kind);
    const auto* s = std::get_if<std::string>(&value);
    const std::string name = s ? (text ? strip_quotes(*s) : *s) : std::string();
    for (std::size_t i = 0; i < ch.names.size(); ++i) {
      if (s && ch.names[i] == name) {
        ch.set(static_cast<int>(i));
        return;
      }
    }
    throw ConfigError(key + ": must be " + choices_text(ch) + " (got " + format_value(value) + ")");
  }
}

}  // namespace

std::vector<Field> scenario_fields(Scenario& s) {
  const double deg = kPi / 180.0;
  auto& c = s.controller;
  return {
      {"sim.dt", "time step for everything (s)", positive(s.sim.dt)},
      {"sim.warmup", "plume-only time before the robot is released (s)",
       non_negative(s.sim.warmup)},
      {"arena.x_min", "upwind wall (m)", any(s.arena.x_min)},
      {"arena.x_max", "downwind wall (m)", any(s.arena.x_max)},
      {"arena.y_min", "right-hand wall (m)", any(s.arena.y_min)},
      {"arena.y_max", "left-hand wall (m)", any(s.arena.y_max)},
      {"source.x", "source centre x (m)", any(s.source.center.x)},
      {"source.y", "source centre y (m)", any(s.source.center.y)},
      {"source.z", "source centre z (m)", any(s.source.center.z)},
      {"source.radius", "source radius, filaments are released within it (m)",
       positive(s.source.radius)},
      {"source.solid_radius", "radius of a solid source cylinder the robot stops at (m, 0: none)",
       NumberField{&s.source.solid_radius, 0.0, 1.0}},
      {"wind.model", "wind field", choice(s.wind.model, {"constant"})},
      {"wind.vx", "constant wind velocity, x component (m/s)", any(s.wind.velocity.x)},
      {"wind.vy", "constant wind velocity, y component (m/s)", any(s.wind.velocity.y)},
      {"wind.vz", "constant wind velocity, z component (m/s)", any(s.wind.velocity.z)},
      {"plume.preset", "preset the plume rows start from",
       choice(s.plume.preset, {"lochmatter2008", "paper-literal"})},
      {"plume.release_rate", "filaments released per second (1/s)",
       NumberField{&s.plume.release_rate, 0.0, kMaxReleaseRate, true, false}},
      {"plume.release_shape", "release region around the source centre",
       choice(s.plume.release_shape, {"ball", "disc"})},
      {"plume.initial_width", "width of a new filament (m)", positive(s.plume.initial_width)},
      {"plume.amount", "odor amount per filament (molecules)", positive(s.plume.amount)},
      {"plume.noise_mode", "random-walk scaling with dt",
       choice(s.plume.noise_mode, {"velocity", "per_step", "wiener"})},
      {"plume.sigma_p", "random-walk intensity (m/s, m or m/sqrt(s) by noise_mode)",
       non_negative(s.plume.sigma_p)},
      {"plume.gamma", "width growth per step: w += gamma / (2 w) (m^2)",
       non_negative(s.plume.gamma)},
      {"plume.lifetime", "how filaments leave", choice(s.plume.lifetime, {"ring", "leave_arena"})},
      {"plume.capacity", "ring-buffer size (filaments), lifetime = ring",
       IntegerField{&s.plume.capacity, 1, kMaxCapacity}},
      {"plume.kernel", "concentration kernel", choice(s.plume.kernel, {"gaussian", "printed"})},
      {"plume.cutoff", "filaments farther than this contribute nothing (m, may be inf)",
       NumberField{&s.plume.cutoff, 0.0, INFINITY, true, false, 1.0, true}},
      {"odor.threshold", "concentration at which odor is perceived", positive(s.odor.threshold)},
      {"odor.height", "odor and wind sensor height (m)", any(s.odor.height)},
      {"wind_sensor.sigma_a", "noise std on each wind component (m/s)",
       non_negative(s.wind_sensor.sigma_a)},
      {"wind_sensor.sigma_a_scale", "factor on sigma_a: the noise std is sigma_a * sigma_a_scale",
       NumberField{&s.wind_sensor.sigma_a_scale, 0.0, 100.0}},
      {"wind_sensor.samples", "noisy samples averaged into one wind measurement",
       IntegerField{&s.wind_sensor.samples, 1, 1000}},
      {"robot.radius", "body radius (m)", positive(s.robot.radius)},
      {"robot.axle", "distance between the wheels (m)", positive(s.robot.axle)},
      {"robot.wheel_speed", "wheel-speed limit = straight-line speed (m/s)",
       positive(s.robot.wheel_speed)},
      {"robot.start_x", "start position x (m)", any(s.robot.start.x)},
      {"robot.start_y", "start position y (m)", any(s.robot.start.y)},
      {"robot.start_heading_deg", "start heading (deg, counter-clockwise from +x)",
       NumberField{&s.robot.start.heading, -kPi - 1e-12, kPi + 1e-12, false, false, deg}},
      {"supervisor.success_radius",
       "success once this close to the source centre (m; 0 only with a solid source)",
       non_negative(s.supervisor.success_radius)},
      {"supervisor.timeout", "run time limit after release (s)", positive(s.supervisor.timeout)},
      {"controller.algorithm", "algorithm driving the robot", algorithm_choice(c.algorithm)},
      {"casting.beta_deg", "upwind leg angle to the measured upwind direction (deg)",
       NumberField{&c.casting.beta, 0.0, 90.0 * deg, false, true, deg}},
      {"casting.d_lost", "path length without odor before the plume is lost (m)",
       positive(c.casting.d_lost)},
      {"casting.reacquire_side", "upwind side after a crosswind leg finds odor",
       choice(c.casting.reacquire_side, {"alternate", "same"})},
      {"surge_spiral.d_gap", "gap between spiral turns (m)", positive(c.surge_spiral.d_gap)},
      {"surge_spiral.d_lost", "path length without odor before the plume is lost (m)",
       positive(c.surge_spiral.d_lost)},
      {"surge_spiral.start_radius", "radius on the spiral r = b theta where spiralling starts (m)",
       NumberField{&c.surge_spiral.start_radius, 0.0, 5.0}},
      {"surge_cast.d_cast", "length of the first cast (m)", positive(c.surge_cast.d_cast)},
      {"surge_cast.d_lost", "path length without odor before the plume is lost (m)",
       positive(c.surge_cast.d_lost)},
  };
}

void set_field(Scenario& scenario, std::string_view key, const ConfigValue& value) {
  const auto fields = scenario_fields(scenario);
  const Field* f = find(fields, key);
  if (!f) unknown_key(fields, key);
  assign(*f, value, false);
}

void set_field_text(Scenario& scenario, std::string_view key, std::string_view text) {
  const auto fields = scenario_fields(scenario);
  const Field* f = find(fields, key);
  if (!f) unknown_key(fields, key);
  assign(*f, std::string(text), true);
}

ConfigValue get_field(const Scenario& scenario, std::string_view key) {
  Scenario copy = scenario;
  const auto fields = scenario_fields(copy);
  const Field* f = find(fields, key);
  if (!f) unknown_key(fields, key);
  if (const auto* num = std::get_if<NumberField>(&f->kind)) return unscale(*num->value, num->scale);
  if (const auto* in = std::get_if<IntegerField>(&f->kind)) {
    return static_cast<std::int64_t>(*in->value);
  }
  const auto& ch = std::get<ChoiceField>(f->kind);
  return ch.names.at(static_cast<std::size_t>(ch.get()));
}

void validate(const Scenario& scenario) {
  // every key within its own range
  Scenario copy = scenario;
  for (const auto& f : scenario_fields(copy)) {
    if (const auto* num = std::get_if<NumberField>(&f.kind)) {
      check_number(f.key, *num, unscale(*num->value, num->scale));
    } else if (const auto* in = std::get_if<IntegerField>(&f.kind)) {
      assign(f, static_cast<std::int64_t>(*in->value), false);
    } else {
      const auto& ch = std::get<ChoiceField>(f.kind);
      const int i = ch.get();
      if (i < 0 || i >= static_cast<int>(ch.names.size())) {
        throw ConfigError(f.key + ": must be " + choices_text(ch));
      }
    }
  }
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
  const auto& start = scenario.robot.start;
  const double r = scenario.robot.radius;
  if (solid > 0.0 && std::hypot(start.x - src.x, start.y - src.y) <= solid + r) {
    throw ConfigError(
        "robot.start_x, robot.start_y: the robot must start clear of the solid source "
        "(source.solid_radius)");
  }
  if (start.x - r < a.x_min || start.x + r > a.x_max) {
    throw ConfigError("robot.start_x: the robot must start inside the arena, clear of the walls");
  }
  if (start.y - r < a.y_min || start.y + r > a.y_max) {
    throw ConfigError("robot.start_y: the robot must start inside the arena, clear of the walls");
  }
  if (scenario.sim.dt > scenario.supervisor.timeout) {
    throw ConfigError("sim.dt: must not exceed supervisor.timeout");
  }
  const double dt = scenario.sim.dt;
  const auto steps = [&](const char* key, double time) {
    if (time / dt > kMaxSteps) {
      throw ConfigError(std::string(key) + ": must be at most " + bound_text(kMaxSteps) +
                        " steps of sim.dt (got " + bound_text(time) + " s / " + bound_text(dt) +
                        " s = " + bound_text(time / dt) + " steps)");
    }
  };
  steps("sim.warmup", scenario.sim.warmup);
  steps("supervisor.timeout", scenario.supervisor.timeout);
  const double per_step = scenario.plume.release_rate * dt;
  if (per_step > kMaxReleasePerStep) {
    throw ConfigError("plume.release_rate: must release at most " + bound_text(kMaxReleasePerStep) +
                      " filaments per step of sim.dt (got " +
                      bound_text(scenario.plume.release_rate) + " /s * " + bound_text(dt) +
                      " s = " + bound_text(per_step) + ")");
  }
}

std::string format_number(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0.0) return "0.0";
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  std::string s(buf);
  // keep it a float in TOML: 25 -> 25.0
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string format_value(const ConfigValue& value) {
  if (const auto* d = std::get_if<double>(&value)) return format_number(*d);
  if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  return "'" + std::get<std::string>(value) + "'";
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
    if (s.text) {
      set_field_text(scenario, s.key, std::get<std::string>(s.value));
    } else {
      set_field(scenario, s.key, s.value);
    }
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
  validate(scenario);
  return scenario;
}

std::string scenario_to_toml(const Scenario& scenario) {
  Scenario copy = scenario;
  std::ostringstream out;
  std::string table;
  for (const auto& f : scenario_fields(copy)) {
    const auto dot = f.key.find('.');
    const std::string t = f.key.substr(0, dot);
    if (t != table) {
      out << (table.empty() ? "" : "\n") << "[" << t << "]\n";
      table = t;
    }
    const ConfigValue v = get_field(scenario, f.key);
    std::string text = std::holds_alternative<std::string>(v)
                           ? "\"" + std::get<std::string>(v) + "\""
                           : format_value(v);
    out << f.key.substr(dot + 1) << " = " << text << "  # " << f.help << "\n";
  }
  return out.str();
}

}  // namespace plumetrace
