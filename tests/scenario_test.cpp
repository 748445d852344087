#include "plumetrace/sim/scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

const std::string kScenarios = std::string(PLUMETRACE_SOURCE_DIR) + "/scenarios/";

// the message of the ConfigError thrown by `f`, or "" when none is thrown
template <class F>
std::string config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string error_of_override(const std::string& text) {
  return config_error([&] { build_scenario({parse_override(text)}); });
}

TEST(Scenario, DefaultScenarioFileEqualsBuiltInDefaults) {
  const Scenario from_file = load_scenario(kScenarios + "lochmatter2008.toml", {});
  EXPECT_EQ(scenario_to_toml(from_file), scenario_to_toml(Scenario{}));
}

TEST(Scenario, MeanderFilesAreTheDefaultsInTheMeanderingWind) {
  for (const char* name : {"meander-weak.toml", "meander-strong.toml"}) {
    Scenario s = load_scenario(kScenarios + name, {});
    EXPECT_EQ(s.wind.model, WindModel::kMeander) << name;
    EXPECT_GT(s.wind.meander.gain, 0.0) << name;
    // the mean wind is the laminar default's, and nothing but the wind differs
    EXPECT_EQ(s.wind.velocity.x, Scenario{}.wind.velocity.x) << name;
    EXPECT_EQ(s.wind.velocity.y, 0.0) << name;
    s.wind = Scenario{}.wind;
    EXPECT_EQ(scenario_to_toml(s), scenario_to_toml(Scenario{})) << name;
  }
  // the strong meander is the keys' defaults
  Scenario strong = load_scenario(kScenarios + "meander-strong.toml", {});
  strong.wind.model = WindModel::kConstant;
  EXPECT_EQ(scenario_to_toml(strong), scenario_to_toml(Scenario{}));
  const Scenario weak = load_scenario(kScenarios + "meander-weak.toml", {});
  EXPECT_EQ(weak.wind.meander.damping, 0.071);
  EXPECT_EQ(weak.wind.meander.bandwidth, 0.71);
}

TEST(Scenario, PaperLiteralFileSetsEveryPresetRow) {
  const Scenario s = load_scenario(kScenarios + "paper-literal.toml", {});
  EXPECT_EQ(s.plume.preset, PlumePreset::kPaperLiteral);
  EXPECT_EQ(s.plume.release_shape, ReleaseShape::kDisc);
  EXPECT_EQ(s.plume.noise_mode, NoiseMode::kPerStep);
  EXPECT_EQ(s.plume.lifetime, Lifetime::kLeaveArena);
  EXPECT_EQ(s.plume.kernel, Kernel::kPrinted);
  EXPECT_TRUE(std::isinf(s.plume.cutoff));
  EXPECT_EQ(s.plume.amount, 8.3e9);
  EXPECT_EQ(s.plume.sigma_p, 0.1);
  // and the printed values outside the plume (the `printed` reading)
  EXPECT_EQ(s.wind.velocity.x, 1.0);
  EXPECT_EQ(s.odor.height, 0.0);
  EXPECT_EQ(s.source.solid_radius, 0.0);
  EXPECT_EQ(s.controller.get<SurgeSpiralParams>().start_radius, 0.0);
}

TEST(Scenario, PaperLiteralFileIsThePrintedReading) {
  // every key the `printed` preset sets has the same value in scenarios/paper-literal.toml
  const Scenario file = load_scenario(kScenarios + "paper-literal.toml", {});
  const Reading printed = read_reading(
      std::string(PLUMETRACE_SOURCE_DIR) + "/studies/lochmatter2008/presets", "printed");
  const Scenario preset = load_scenario(kScenarios + "lochmatter2008.toml", printed.settings);
  EXPECT_EQ(scenario_to_toml(file), scenario_to_toml(preset));
}

TEST(Scenario, ExplicitRowsWinOverThePresetWhateverTheirOrder) {
  // the row is given before the preset, and still wins
  const Scenario s = build_scenario(
      {parse_override("plume.kernel=gaussian"), parse_override("plume.preset=paper-literal")});
  EXPECT_EQ(s.plume.kernel, Kernel::kGaussian);
  EXPECT_EQ(s.plume.noise_mode, NoiseMode::kPerStep);
}

TEST(Scenario, PresetInALaterLayerReplacesPlumeRowsOfEarlierLayers) {
  // the default file writes out every plume row; a preset on the command line still applies
  const Scenario s = load_scenario(kScenarios + "lochmatter2008.toml",
                                   {parse_override("plume.preset=paper-literal")});
  Scenario literal;
  literal.plume = plume_preset(PlumePreset::kPaperLiteral);
  EXPECT_EQ(scenario_to_toml(s), scenario_to_toml(literal));
  // a row in the same layer as the preset, or a later one, still wins
  const Scenario t = load_scenario(
      kScenarios + "lochmatter2008.toml",
      {parse_override("plume.sigma_p=0.05"), parse_override("plume.preset=paper-literal")});
  EXPECT_EQ(t.plume.sigma_p, 0.05);
  EXPECT_EQ(t.plume.kernel, Kernel::kPrinted);
  // non-plume keys of earlier layers are untouched
  const Scenario u = load_scenario(
      kScenarios + "lochmatter2008.toml",
      {parse_override("plume.preset=paper-literal"), parse_override("casting.beta_deg=30")});
  EXPECT_DOUBLE_EQ(u.controller.get<CastingParams>().beta, kPi / 6.0);
}

TEST(Scenario, ResolvedTomlReadsBackToTheSameScenario) {
  const Scenario s = build_scenario({parse_override("plume.preset=paper-literal"),
                                     parse_override("casting.beta_deg=33.3"),
                                     parse_override("wind_sensor.sigma_a=0.45")});
  const std::string toml = scenario_to_toml(s);
  const std::string path = testing::temp_path("resolved", ".toml");
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(toml.c_str(), f);
    std::fclose(f);
  }
  const Scenario back = load_scenario(path, {});
  EXPECT_EQ(scenario_to_toml(back), toml);
  EXPECT_EQ(back.controller.get<CastingParams>().beta, s.controller.get<CastingParams>().beta);
}

TEST(Scenario, DegreesAreStoredInRadiansAndPrintedInDegrees) {
  const Scenario s = build_scenario({parse_override("casting.beta_deg=30")});
  EXPECT_DOUBLE_EQ(s.controller.get<CastingParams>().beta, kPi / 6.0);
  EXPECT_EQ(format_value(get_field(s, "casting.beta_deg")), "30.0");
}

// a valid value for the field that differs from its default
ConfigValue other_value(const Field& f) {
  if (const auto* num = std::get_if<NumberField>(&f.kind)) {
    const double current = *num->value / num->scale;
    const double lo = std::isfinite(num->min) ? num->min / num->scale : current - 1.0;
    const double hi = std::isfinite(num->max) ? num->max / num->scale : current + 1.0;
    double v = std::isfinite(current) ? current : 2.0;
    v = v + 0.25 * (hi - v) < hi ? v + 0.25 * (hi - v) : lo + 0.25 * (v - lo);
    return v;
  }
  if (const auto* in = std::get_if<IntegerField>(&f.kind)) {
    return static_cast<std::int64_t>(*in->value + 1);
  }
  const auto& ch = std::get<ChoiceField>(f.kind);
  return ch.names[static_cast<std::size_t>(ch.get() + 1) % ch.names.size()];
}

TEST(Scenario, EveryKeyChangesItsOwnValueAndNothingElse) {
  Scenario defaults;
  const auto fields = scenario_fields(defaults);
  for (const auto& f : fields) {
    const ConfigValue v = other_value(f);
    Scenario changed;
    set_field(changed, f.key, v);
    EXPECT_EQ(format_value(get_field(changed, f.key)), format_value(v)) << f.key;
    // every other key still has its default
    for (const auto& g : fields) {
      if (g.key == f.key) continue;
      EXPECT_EQ(format_value(get_field(changed, g.key)), format_value(get_field(defaults, g.key)))
          << "setting " << f.key << " changed " << g.key;
    }
  }
}

TEST(Scenario, ValidateChecksEveryKindOfField) {
  Scenario s;
  s.plume.capacity = 0;
  EXPECT_NE(config_error([&] { validate(s); }).find("plume.capacity"), std::string::npos);
  s = Scenario{};
  s.plume.noise_mode = static_cast<NoiseMode>(7);
  EXPECT_NE(config_error([&] { validate(s); }).find("plume.noise_mode"), std::string::npos);
  s = Scenario{};
  s.wind.velocity.x = INFINITY;
  EXPECT_NE(config_error([&] { validate(s); }).find("wind.vx"), std::string::npos);
  EXPECT_EQ(config_error([] { validate(Scenario{}); }), "");
}

TEST(Scenario, UnknownKeyIsNamed) {
  const std::string msg = error_of_override("plume.sigma=0.2");
  EXPECT_NE(msg.find("unknown config key 'plume.sigma'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("plume.sigma_p"), std::string::npos) << msg;  // suggests the real keys
}

TEST(Scenario, InvalidValuesNameTheKeyAndTheAllowedRange) {
  struct Case {
    std::string set, expect;
  };
  const Case cases[] = {
      {"sim.dt=0", "sim.dt: must be a number > 0"},
      {"sim.dt=-0.1", "sim.dt: must be a number > 0"},
      {"robot.wheel_speed=-1", "robot.wheel_speed: must be a number > 0"},
      {"robot.radius=0", "robot.radius: must be a number > 0"},
      {"source.radius=0", "source.radius: must be a number > 0"},
      {"supervisor.success_radius=-0.1", "supervisor.success_radius: must be a number >= 0"},
      {"odor.threshold=0", "odor.threshold: must be a number > 0"},
      {"plume.capacity=0", "plume.capacity: must be an integer >= 1"},
      {"plume.capacity=1.5", "plume.capacity: must be an integer >= 1"},
      {"wind_sensor.sigma_a=-0.1", "wind_sensor.sigma_a: must be a number >= 0"},
      {"casting.beta_deg=90", "casting.beta_deg: must be a number >= 0 and < 90"},
      {"sim.dt=abc", "sim.dt: must be a number > 0 (got 'abc')"},
      {"controller.algorithm=zigzag",
       "controller.algorithm: must be one of 'casting', 'surge-spiral', 'surge-cast'"},
      {"plume.preset=foo", "plume.preset: must be one of 'lochmatter2008', 'paper-literal'"},
      {"plume.noise_mode=brownian", "plume.noise_mode: must be one of 'velocity'"},
      {"source.solid_radius=-0.1", "source.solid_radius: must be a number >= 0 and <= 1"},
      {"wind_sensor.samples=0", "wind_sensor.samples: must be an integer >= 1 and <= 1000"},
      {"wind_sensor.sigma_a_scale=101", "wind_sensor.sigma_a_scale: must be a number >= 0"},
      {"surge_spiral.start_radius=6", "surge_spiral.start_radius: must be a number >= 0 and <= 5"},
      {"casting.reacquire_side=left", "casting.reacquire_side: must be one of 'alternate', 'same'"},
  };
  for (const auto& c : cases) {
    const std::string msg = error_of_override(c.set);
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.set << " gave: " << msg;
  }
}

TEST(Scenario, RelationsBetweenKeysAreChecked) {
  EXPECT_NE(error_of_override("arena.x_max=-1").find("arena.x_max"), std::string::npos);
  EXPECT_NE(error_of_override("robot.start_y=1.99").find("robot.start_y"), std::string::npos);
  EXPECT_NE(error_of_override("source.x=20").find("source.x"), std::string::npos);
}

TEST(Scenario, ZeroSuccessRadiusNeedsASolidSource) {
  const std::string msg = config_error([] {
    build_scenario(
        {parse_override("source.solid_radius=0"), parse_override("supervisor.success_radius=0")});
  });
  EXPECT_NE(msg.find("source.solid_radius"), std::string::npos) << msg;
  const Scenario s = build_scenario(
      {parse_override("source.solid_radius=0.05"), parse_override("supervisor.success_radius=0")});
  EXPECT_EQ(s.supervisor.success_radius, 0.0);
  EXPECT_EQ(s.source.solid_radius, 0.05);
  // the robot must start clear of the solid source
  const std::string inside = config_error([] {
    build_scenario(
        {parse_override("source.solid_radius=0.05"), parse_override("robot.start_x=1.1")});
  });
  EXPECT_NE(inside.find("source.solid_radius"), std::string::npos) << inside;
}

TEST(Scenario, DefaultsAreTheEvidencedReading) {
  // docs/fidelity.md, "Which reading won": each value below has a source there
  const Scenario s;
  EXPECT_EQ(s.plume.amount, 1.0);
  EXPECT_EQ(s.plume.sigma_p, 0.02);
  EXPECT_EQ(s.plume.kernel, Kernel::kPrinted);
  EXPECT_EQ(s.plume.noise_mode, NoiseMode::kVelocity);
  EXPECT_EQ(s.plume.release_shape, ReleaseShape::kBall);
  EXPECT_EQ(s.wind.velocity.x, 0.9);
  EXPECT_EQ(s.odor.height, 0.02);
  EXPECT_EQ(s.supervisor.success_radius, 0.185);
  EXPECT_EQ(s.source.solid_radius, 0.05);
  EXPECT_EQ(s.wind_sensor.samples, 1);
  EXPECT_EQ(s.wind_sensor.sigma_a_scale, 1.0);
  EXPECT_EQ(s.controller.get<SurgeSpiralParams>().start_radius, 0.049);
  EXPECT_EQ(s.controller.get<CastingParams>().reacquire_side, ReacquireSide::kAlternate);
  EXPECT_EQ(format_value(get_field(s, "casting.reacquire_side")), "'alternate'");
}

TEST(Scenario, OverrideWithoutEqualsSignIsRejected) {
  const std::string msg = config_error([] { parse_override("sim.dt"); });
  EXPECT_NE(msg.find("key.path=value"), std::string::npos) << msg;
}

TEST(Scenario, FileErrorsNameTheFile) {
  const std::string missing = config_error([] { load_scenario("no/such/file.toml", {}); });
  EXPECT_NE(missing.find("no/such/file.toml"), std::string::npos) << missing;

  const std::string path = testing::temp_path("bad", ".toml");
  std::FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("[plume]\nsigma_p = 0.1\nbogus = 3\n", f);
  std::fclose(f);
  const std::string unknown = config_error([&] { load_scenario(path, {}); });
  EXPECT_NE(unknown.find(path), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("plume.bogus"), std::string::npos) << unknown;

  f = std::fopen(path.c_str(), "w");
  std::fputs("[plume\nsigma_p = \n", f);
  std::fclose(f);
  const std::string syntax = config_error([&] { load_scenario(path, {}); });
  EXPECT_NE(syntax.find(path + ":1:"), std::string::npos) << syntax;
}

TEST(Scenario, FormatNumberRoundTrips) {
  for (double v : {0.1, 0.032, 8.3e9, 4e-7, 1.0 / 3.0, 0.614, 15.5, -2.0}) {
    EXPECT_EQ(std::strtod(format_number(v).c_str(), nullptr), v);
  }
  EXPECT_EQ(format_number(INFINITY), "inf");
}

}  // namespace
}  // namespace plumetrace
