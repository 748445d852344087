// Sweep files, grid expansion, the results store and the parallel resumable runner.
#include "plumetrace/experiment/sweep.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "lochmatter2008/axes.hpp"
#include "lochmatter2008/reproduce.hpp"
#include "lochmatter2008/study.hpp"
#include "lochmatter2008/summary.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/env/meander_wind.hpp"
#include "plumetrace/env/switching_wind.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "support/rows.hpp"
#include "support/temp_path.hpp"

namespace plumetrace {
namespace {

// a small, quick sweep: the robot starts 2 m from the source, so runs last seconds
const char* const kQuickSweep = R"(
name = "quick"
title = "a quick grid"
runs = 4
seed = 77

[set]
robot.start_x = 3.0
sim.warmup = 4.0
supervisor.timeout = 60.0

[[axis]]
key = "controller.algorithm"
values = ["casting", "surge-cast"]

[[axis]]
key = "wind_sensor.sigma_a"
values = [0.0, 0.3, 0.6]
fixed = 0.3
)";

std::string write_sweep(const std::string& text) {
  const std::string path = testing::temp_path("sweep", ".toml");
  std::ofstream(path) << text;
  return path;
}

std::string sweep_error(const std::string& text) {
  try {
    expand_sweep(read_sweep_file(write_sweep(text)), {});
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::vector<ExpandedSweep> quick() {
  return {expand_sweep(read_sweep_file(write_sweep(kQuickSweep)), {})};
}

using testing::expect_same_rows;

std::vector<RunRow> run_fresh(const std::vector<ExpandedSweep>& sweeps, int threads,
                              bool share = true) {
  Store store(testing::temp_path("store", ".sqlite"), sweeps, version(), false);
  CampaignOptions options;
  options.threads = threads;
  options.share_plumes = share;
  const CampaignResult r = run_campaign(sweeps, store, 0, options);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.computed, 24);
  return store.rows();
}

TEST(SweepFile, GridExpandsFirstAxisSlowest) {
  const auto sweeps = quick();
  const auto& points = sweeps[0].points;
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0].scenario.controller.algorithm, Algorithm::kCasting);
  EXPECT_EQ(points[2].scenario.wind_sensor.sigma_a, 0.6);
  EXPECT_EQ(points[3].scenario.controller.algorithm, Algorithm::kSurgeCast);
  EXPECT_EQ(points[3].scenario.wind_sensor.sigma_a, 0.0);
  EXPECT_EQ(points[5].scenario.robot.start.x, 3.0);  // the [set] table applies everywhere
  for (std::size_t i = 1; i < points.size(); ++i) {
    EXPECT_NE(points[i].config_hash, points[i - 1].config_hash);
  }
}

TEST(SweepFile, InvalidFilesAreRejectedNamingTheProblem) {
  const std::string base = "name = \"x\"\n";
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {base + "bogus = 1\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.01]\n",
       "unknown or mistyped key 'bogus'"},
      {base + "[[axis]]\nkey = \"sim.dt\"\nvalues = []\n", "axis sim.dt: values must not be empty"},
      {base + "[[axis]]\nkey = \"casting.beta_deg\"\nvalues = [10, \"wide\"]\n",
       "axis casting.beta_deg: casting.beta_deg: must be a number"},
      {base + "[[axis]]\nkey = \"casting.beta\"\nvalues = [10]\n",
       "unknown config key 'casting.beta'"},
      {base + "[[axis]]\nkey = \"sim.dt\"\nvalues = [0]\n", "sim.dt: must be a number > 0"},
      {base + "[[axis]]\nkey = \"sim.dt\"\nvalues = [0.1]\n[[axis]]\nkey = \"sim.dt\"\nvalues = "
              "[0.2]\n",
       "axis sim.dt is given twice"},
      {"[[axis]]\nkey = \"sim.dt\"\nvalues = [0.1]\n", "missing name"},
      {base, "no [[axis]]"},
      {base + "runs = 0\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.1]\n",
       "runs: must be an integer >= 1"},
      {base + "[set]\nplume.bogus = 2\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.1]\n",
       "unknown config key 'plume.bogus'"},
      {base + "[[axis]]\nkey = \"sim.dt\"\nvalues = [0.1\n", "invalid TOML"},
  };
  for (const auto& c : cases) {
    const std::string msg = sweep_error(c.text);
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.text << "\ngave: " << msg;
    EXPECT_NE(msg.find("sweep_"), std::string::npos) << "the file is named: " << msg;
  }
}

TEST(SweepFile, OverrideOfAnAxisKeyIsRejected) {
  const auto def = read_sweep_file(write_sweep(kQuickSweep));
  try {
    expand_sweep(def, {parse_override("wind_sensor.sigma_a=0.2")});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("names an axis"), std::string::npos) << e.what();
  }
  // other keys are fine and enter the config hash
  const auto changed = expand_sweep(def, {parse_override("casting.beta_deg=30")});
  EXPECT_NE(changed.points[0].config_hash, expand_sweep(def, {}).points[0].config_hash);
}

TEST(Experiments, TheNineSetsHold4050RunsWithTheirFixedValues) {
  const std::vector<SweepDef> sets = read_sets(read_study(default_study_file()));
  EXPECT_EQ(set_names(sets),
            (std::vector<std::string>{"A", "B", "C", "D", "E", "F", "G", "H", "I"}));
  int total = 0;
  for (const SweepDef& def : sets) {
    const std::string& name = def.name;
    const ExpandedSweep sweep = expand_sweep(def, {});
    ASSERT_EQ(sweep.def.axes.size(), 1u) << name;
    EXPECT_EQ(sweep.points.size(), 9u) << name;
    EXPECT_TRUE(sweep.def.axes[0].fixed.has_value()) << name;
    total += static_cast<int>(sweep.points.size()) * sweep.def.runs;
    // every point is the paper's default setup but for the algorithm and the varied key
    const Scenario& p = sweep.points[0].scenario;
    EXPECT_EQ(p.plume.preset, PlumePreset::kLochmatter2008) << name;
    EXPECT_EQ(p.robot.start.x, 15.5) << name;
  }
  EXPECT_EQ(total, 4050);
}

const std::string kStudy = std::string(PLUMETRACE_SOURCE_DIR) + "/studies/lochmatter2008";

std::vector<SweepDef> nine_sets() { return read_sets(read_study(default_study_file())); }

// a presets folder holding one file NAME.toml with `text`
std::string presets_folder(const std::string& name, const std::string& text) {
  const std::string folder = testing::temp_path("presets", "");
  std::filesystem::create_directories(folder);
  std::ofstream(folder + "/" + name + ".toml") << text;
  return folder;
}

TEST(Presets, TheFourReadingsSetTheSameKeysAndNoAxisOfTheNineSets) {
  const auto names = preset_names(kStudy + "/presets");
  EXPECT_EQ(names,
            (std::vector<std::string>{"calibrated", "plugin", "plugin-published", "printed"}));
  std::set<std::string> first;
  for (const auto& name : names) {
    const Reading r = read_reading(kStudy + "/presets", name);
    std::set<std::string> keys;
    for (const auto& s : r.settings) keys.insert(s.key);
    if (first.empty()) first = keys;
    EXPECT_EQ(keys, first) << name << " decides other unknowns than " << names.front();
    EXPECT_TRUE(keys.count("plume.preset") && keys.count("plume.amount")) << name;
    EXPECT_EQ(reading_sets(nine_sets(), r, false).size(), 9u) << name;
  }
}

TEST(Presets, APresetAppliesItsKeysToEverySetAndTheAxesStillVary) {
  const Reading printed = read_reading(kStudy + "/presets", "printed");
  const Reading published = read_reading(kStudy + "/presets", "plugin-published");
  for (const auto& sweep : reading_sets(nine_sets(), printed, false)) {
    for (const auto& p : sweep.points) {
      // the paper-literal plume, from a set whose scenario file writes out the plugin's rows
      EXPECT_EQ(p.scenario.plume.kernel, Kernel::kPrinted) << sweep.def.name;
      EXPECT_EQ(p.scenario.plume.noise_mode, NoiseMode::kPerStep) << sweep.def.name;
      EXPECT_EQ(p.scenario.plume.lifetime, Lifetime::kLeaveArena) << sweep.def.name;
      EXPECT_EQ(p.scenario.plume.release_shape, ReleaseShape::kDisc) << sweep.def.name;
      EXPECT_EQ(p.scenario.plume.amount, 8.3e9) << sweep.def.name;
    }
  }
  const auto sets = reading_sets(nine_sets(), published, false);
  std::set<std::string> configs;
  for (const auto& p : sets[0].points) {
    EXPECT_EQ(p.scenario.plume.amount, 1.0);
    EXPECT_EQ(p.scenario.controller.algorithm, Algorithm::kCasting);
    configs.insert(p.config_hash);
  }
  EXPECT_EQ(configs.size(), sets[0].points.size()) << "the axis of set A still varies";
  for (const auto& sweep : sets) {
    EXPECT_EQ(sweep.points[0].scenario.plume.amount, 1.0) << sweep.def.name;
  }
}

TEST(Presets, OtherReadingsSetsArePrefixedAndTheMainOnesKeepTheirNames) {
  const Reading plugin = read_reading(kStudy + "/presets", "plugin");
  EXPECT_EQ(reading_sets(nine_sets(), plugin, false)[3].def.name, "plugin/D");
  EXPECT_EQ(reading_sets(nine_sets(), plugin, true)[3].def.name, "D");
  // the default reading adds nothing: the sets as their files define them
  const Reading none = read_reading(kStudy + "/presets", kDefaultReading);
  EXPECT_TRUE(none.settings.empty());
  const auto defaults = reading_sets(nine_sets(), none, true);
  EXPECT_EQ(defaults[0].points[0].config_hash,
            expand_sweep(nine_sets()[0], {}).points[0].config_hash);
}

// issue 23, item 3: the axes as readings
TEST(AxisReadings, AReadingReplacesOnlyTheAxesOfTheSetsItNames) {
  const auto sets = nine_sets();
  const AxisReading sigma = read_axis_reading(kStudy + "/axes", "sigma-a-0.4", sets);
  const auto moved = axis_reading_sets(sets, sigma);
  ASSERT_EQ(moved.size(), 3u);
  for (const auto& def : moved) {
    EXPECT_EQ(def.name.rfind("@sigma-a-0.4/", 0), 0u) << def.name;
    ASSERT_EQ(def.axes.size(), 1u);
    EXPECT_EQ(def.axes[0].key, "wind_sensor.sigma_a");
    EXPECT_EQ(def.axes[0].values.size(), 9u);
    EXPECT_EQ(std::get<double>(def.axes[0].values.back()), 0.4);
    EXPECT_EQ(std::get<double>(*def.axes[0].fixed), 0.1);
  }
  // the same set under its file's axis and under the reading share the fixed value's runs: the
  // same scenario, and so the same config hash
  const ExpandedSweep c = expand_sweep(sets[2], {});
  const ExpandedSweep c04 = expand_sweep(moved[0], {});
  EXPECT_EQ(c.points[1].config_hash, c04.points[2].config_hash);  // sigma_a = 0.1 in both
  // the set files' own axes are the reading "sets", which changes nothing
  EXPECT_TRUE(
      axis_reading_sets(sets, read_axis_reading(kStudy + "/axes", kSetsAxes, sets)).empty());
  EXPECT_EQ(axis_reading_names(kStudy + "/axes"), std::vector<std::string>{"sigma-a-0.4"});
}

TEST(AxisReadings, BadAxisReadingsAreRefusedNamingTheFileAndTheKey) {
  const auto sets = nine_sets();
  const auto refused = [&](const std::string& text, const std::string& names) {
    const std::string folder = presets_folder("bad", text);
    try {
      read_axis_reading(folder, "bad", sets);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
    }
  };
  refused("title = \"t\"\n[Z]\nvalues = [0.1, 0.2]\n", "unknown key 'Z'");
  refused("title = \"t\"\n[C]\nvalues = [0.2, 0.1]\n", "[C] values: must be increasing");
  refused("title = \"t\"\n[C]\nvalues = [0.1, 0.2]\nfixed = 0.3\n", "[C] fixed");
  refused("title = \"t\"\n[C]\nvalues = [\"a\", \"b\"]\n", "[C] values: must be numbers");
  refused("[C]\nvalues = [0.1, 0.2]\n", "title: missing");
  try {
    read_axis_reading(kStudy + "/axes", "nonesuch", sets);
    ADD_FAILURE() << "an unknown axis reading was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--axes: unknown axis reading 'nonesuch'"),
              std::string::npos);
  }
}

TEST(AxisReadings, AReproductionRunsTheChangedSetsUnderTheMainReading) {
  const Study study = read_study(default_study_file());
  const Reproduction plan = plan_reproduction(study, "plugin", std::vector<std::string>{});
  ASSERT_EQ(plan.axis_readings.size(), 2u);
  EXPECT_EQ(plan.axis_readings[0].name, kSetsAxes);
  std::vector<std::string> axis_sweeps;
  for (const auto& s : plan.sweeps) {
    if (s.def.name.rfind("@", 0) != 0) continue;
    axis_sweeps.push_back(s.def.name);
    // under the main reading, plugin: its amount
    EXPECT_EQ(s.points[0].scenario.plume.amount, 8.3e9) << s.def.name;
  }
  EXPECT_EQ(axis_sweeps,
            (std::vector<std::string>{"@sigma-a-0.4/C", "@sigma-a-0.4/F", "@sigma-a-0.4/I"}));
  const Reproduction none =
      plan_reproduction(study, "default", std::vector<std::string>{}, std::vector<std::string>{});
  EXPECT_EQ(none.axis_readings.size(), 1u);
  EXPECT_EQ(none.sweeps.size(), plan.sweeps.size() - 3);
}

TEST(Presets, PlumePresetResetsTheScenarioFilesPlumeRowsAndExplicitRowsWin) {
  // the explicit row comes before the preset in the file and still wins over it
  const std::string folder = presets_folder("mixed", R"(
[plume]
kernel = "gaussian"
preset = "paper-literal"
)");
  const Reading r = read_reading(folder, "mixed");
  const auto sets = reading_sets(nine_sets(), r, false);
  const Scenario& s = sets[0].points[0].scenario;
  EXPECT_EQ(s.plume.preset, PlumePreset::kPaperLiteral);
  EXPECT_EQ(s.plume.kernel, Kernel::kGaussian);
  // the scenario file's own rows (noise "velocity", release "ball") gave way to the preset's
  EXPECT_EQ(s.plume.noise_mode, NoiseMode::kPerStep);
  EXPECT_EQ(s.plume.release_shape, ReleaseShape::kDisc);
}

TEST(Presets, AnUnknownNameIsAnErrorNamingItAndTheKnownOnes) {
  try {
    read_reading(kStudy + "/presets", "paper-literal");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown preset 'paper-literal'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("default, calibrated, plugin, plugin-published, printed"), std::string::npos)
        << msg;
  }
}

TEST(Presets, BadKeysAndAxisKeysAreRejectedNamingTheFile) {
  const std::string unknown = presets_folder("typo", "[plume]\namonut = 1.0\n");
  try {
    read_reading(unknown, "typo");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("typo.toml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("plume.amonut"), std::string::npos) << e.what();
  }
  const std::string axis = presets_folder("axis", "[casting]\nbeta_deg = 30.0\n");
  const Reading r = read_reading(axis, "axis");
  try {
    reading_sets(nine_sets(), r, false);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("axis.toml: casting.beta_deg names an axis"), std::string::npos) << msg;
  }
}

TEST(Campaign, OneAndTwoThreadsGiveIdenticalRows) {
  const auto sweeps = quick();
  expect_same_rows(run_fresh(sweeps, 1), run_fresh(sweeps, 2));
}

// the quick sweep with `settings` added to its [set] in wind `model`: 1 and 2 threads, and
// shared and separate plumes, give the same rows, and the wind changed the runs
void expect_identical_rows_in_the_wind(const std::string& settings, WindModel model) {
  std::string text = kQuickSweep;
  const std::string set = "[set]\n";
  text.insert(text.find(set) + set.size(), settings);
  const std::vector<ExpandedSweep> sweeps = {expand_sweep(read_sweep_file(write_sweep(text)), {})};
  ASSERT_EQ(sweeps[0].points[0].scenario.wind.model, model);
  const auto one = run_fresh(sweeps, 1);
  expect_same_rows(one, run_fresh(sweeps, 2));
  expect_same_rows(one, run_fresh(sweeps, 2, false));  // and shared plumes equal separate ones
  const auto laminar = run_fresh(quick(), 1);
  ASSERT_EQ(laminar.size(), one.size());
  bool differ = false;
  for (std::size_t i = 0; i < one.size(); ++i) {
    differ = differ || one[i].result.steps != laminar[i].result.steps;
  }
  EXPECT_TRUE(differ);
}

TEST(Campaign, OneAndTwoThreadsGiveIdenticalRowsInTheMeanderingWind) {
  expect_identical_rows_in_the_wind("wind.model = \"meander\"\nmeander.gain = 0.3\n",
                                    WindModel::kMeander);
}

TEST(Campaign, OneAndTwoThreadsGiveIdenticalRowsInTheSwitchingWind) {
  expect_identical_rows_in_the_wind(
      "wind.model = \"switching\"\nswitching.count = 100\nswitching.first = 2.0\n"
      "switching.draw = \"normal\"\nswitching.angle_deg = 60.0\n",
      WindModel::kSwitching);
}

TEST(SharedPlume, AgentsOnOnePlumeEqualSeparateRunsBitForBit) {
  // robots as different as can be, on the paper's plume: algorithms, noise, radii, starts
  std::vector<Scenario> scenarios(6);
  scenarios[0].controller.algorithm = Algorithm::kCasting;
  scenarios[1].controller.algorithm = Algorithm::kSurgeSpiral;
  scenarios[2].controller.algorithm = Algorithm::kSurgeCast;
  scenarios[3].controller.algorithm = Algorithm::kSurgeSpiral;
  scenarios[3].wind_sensor.sigma_a = 0.5;
  scenarios[3].supervisor.success_radius = 0.6;
  scenarios[4].controller.algorithm = Algorithm::kSurgeCast;
  scenarios[4].robot.start.x = 6.0;
  scenarios[4].controller.get<SurgeCastParams>().d_cast = 0.1;
  scenarios[5].controller.algorithm = Algorithm::kCasting;
  scenarios[5].supervisor.timeout = 30.0;  // ends long before the others
  std::vector<const Scenario*> group;
  for (const auto& s : scenarios) group.push_back(&s);
  for (std::uint64_t trial = 0; trial < 3; ++trial) {
    const auto shared = run_shared(group, 9, trial);
    ASSERT_EQ(shared.size(), scenarios.size());
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
      const RunResult alone = run_once(scenarios[i], 9, trial);
      EXPECT_EQ(shared[i].outcome, alone.outcome) << i;
      EXPECT_EQ(shared[i].steps, alone.steps) << i;
      EXPECT_EQ(shared[i].d_t, alone.d_t) << i;
      EXPECT_EQ(shared[i].d_u, alone.d_u) << i;
      EXPECT_EQ(shared[i].losses, alone.losses) << i;
      EXPECT_EQ(shared[i].odor_fraction, alone.odor_fraction) << i;
      EXPECT_EQ(shared[i].wind_samples, alone.wind_samples) << i;
    }
  }
}

TEST(SharedPlume, ScenariosWithDifferentPlumesAreRefused) {
  Scenario a, b;
  b.plume.sigma_p = 0.2;
  EXPECT_NE(plume_key(a), plume_key(b));
  b = a;
  b.controller.algorithm = Algorithm::kSurgeCast;
  b.wind_sensor.sigma_a = 0.7;
  b.wind_sensor.sigma_a_scale = 2.0;
  b.wind_sensor.samples = 4;
  b.source.solid_radius = 0.05;  // an obstacle for the robot, not for the filaments
  b.controller.get<CastingParams>().reacquire_side = ReacquireSide::kSame;
  b.controller.get<SurgeSpiralParams>().start_radius = 0.1;
  EXPECT_EQ(plume_key(a), plume_key(b));  // robot-side keys do not change the plume
  b.plume.sigma_p = 0.2;
  EXPECT_THROW(run_shared({&a, &b}, 1, 0), std::invalid_argument);
}

// a key whose help text the test edits, in the slot of the constant wind's params (which have
// no keys of their own)
std::string g_help = "a help text";
struct HelpedParams {
  double value = 1.0;
  template <class V>
  void fields(V& v) {
    v("helped", value, g_help, kAnyNumber);
  }
};

// issue 24: a run's identity hashed the TOML with its help comments, so that editing one help
// text made every store refuse its own sweep; it hashes the values alone
TEST(ConfigHash, IsOfTheValuesNotOfTheHelpTexts) {
  Scenario s;
  const std::string text = canonical_config(s);
  EXPECT_EQ(text.find('#'), std::string::npos) << text;
  EXPECT_NE(text.find("\nwind.model='constant'\nwind.vx=1.0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nmeander.gain=0.14\n"), std::string::npos) << text;
  EXPECT_EQ(scenario_hash(s), hash_text(text));
  const SweepPoint point = expand_sweep(read_sweep_file(write_sweep(kQuickSweep)), {}).points[0];
  EXPECT_EQ(point.config_hash, scenario_hash(point.scenario));
  s.wind.params.at(wind_field_registry(), 0) = AnyParams(HelpedParams{});
  const std::string toml = scenario_to_toml(s), hash = scenario_hash(s), plume = plume_key(s);
  g_help = "another help text";
  EXPECT_NE(scenario_to_toml(s), toml);  // the help shows in the TOML
  EXPECT_EQ(scenario_hash(s), hash);
  EXPECT_EQ(plume_key(s), plume);
  // a value does change them
  s.wind.params.at(wind_field_registry(), 0).get<HelpedParams>().value = 2.0;
  EXPECT_NE(scenario_hash(s), hash);
  EXPECT_NE(plume_key(s), plume);
  Scenario other;
  other.wind.get<MeanderParams>().kx = 11.0;
  EXPECT_NE(scenario_hash(other), scenario_hash(Scenario{}));
}

// as for the baselines, adding the switching wind changed no stored config or hash of a run in
// another wind: its table is in a run's config only when it blows there
TEST(ConfigHash, HoldsTheSwitchingWindsKeysOnlyWhereItBlows) {
  Scenario laminar, meander, switching;
  meander.wind.model = WindModel::kMeander;
  switching.wind.model = WindModel::kSwitching;
  for (const Scenario* s : {&laminar, &meander}) {
    EXPECT_EQ(canonical_config(*s).find("\nswitching."), std::string::npos);
    EXPECT_EQ(scenario_to_toml(*s, ConfigKeys::kOfTheRun).find("[switching]"), std::string::npos);
    EXPECT_NE(scenario_to_toml(*s, ConfigKeys::kAll).find("[switching]"), std::string::npos);
  }
  EXPECT_NE(canonical_config(switching).find("\nswitching.angle_deg=45.0\n"), std::string::npos);
  // a change of its keys leaves the other winds' runs alone
  Scenario other = laminar;
  other.wind.get<SwitchingParams>().angle_deg = 10.0;
  EXPECT_EQ(scenario_hash(other), scenario_hash(laminar));
  Scenario turned = switching;
  turned.wind.get<SwitchingParams>().angle_deg = 10.0;
  EXPECT_NE(scenario_hash(turned), scenario_hash(switching));
}

TEST(SharedPlume, AMeanderingWindsPlumeDependsOnTheWholeArena) {
  Scenario a, b;
  b.arena.y_max = 3.0;  // the robot's wall; the constant wind's plume does not see it
  EXPECT_EQ(plume_key(a), plume_key(b));
  a.wind.model = b.wind.model = WindModel::kMeander;
  EXPECT_NE(plume_key(a), plume_key(b));  // the wind's grid covers the arena
  b = a;
  b.wind.get<MeanderParams>().gain = 0.2;
  EXPECT_NE(plume_key(a), plume_key(b));
  // the constant wind's plume does not see the meander's keys
  a.wind.model = b.wind.model = WindModel::kConstant;
  EXPECT_EQ(plume_key(a), plume_key(b));
}

// robots share a plume only where it is the same plume: every key of the switching wind, and the
// release its switches are timed from, enter the plume's key
TEST(SharedPlume, ASwitchingWindsPlumeDependsOnEveryKeyOfItAndTheRelease) {
  Scenario a;
  a.wind.model = WindModel::kSwitching;
  const std::string key = plume_key(a);
  const std::pair<const char*, const char*> changes[] = {
      {"switching.count", "2"},      {"switching.first", "44"},
      {"switching.interval", "2.9"}, {"switching.timing", "random"},
      {"switching.jitter", "0.2"},   {"switching.angle_deg", "40"},
      {"switching.draw", "uniform"}, {"switching.transition", "1"},
      {"sim.warmup", "21"},          {"wind.vy", "0.1"}};
  for (const auto& [name, value] : changes) {
    Scenario b = a;
    set_field_text(b, name, value);
    EXPECT_NE(plume_key(b), key) << name;
    // the constant wind's plume does not see the switching wind's keys
    if (std::string(name).rfind("switching.", 0) == 0) {
      Scenario c, d;
      set_field_text(d, name, value);
      EXPECT_EQ(plume_key(c), plume_key(d)) << name;
    }
  }
  // nor the arena's side walls: the switching wind is the same over any region
  Scenario wide = a;
  wide.arena.y_max = 16.0;
  EXPECT_EQ(plume_key(wide), key);
}

TEST(Campaign, SharedAndSeparatePlumesGiveIdenticalRows) {
  const auto sweeps = quick();
  expect_same_rows(run_fresh(sweeps, 2, true), run_fresh(sweeps, 2, false));
  expect_same_rows(run_fresh(sweeps, 1, true), run_fresh(sweeps, 1, false));
}

TEST(Campaign, RowsEqualSingleRunsOfTheSameSeedAndTrial) {
  const auto sweeps = quick();
  const auto rows = run_fresh(sweeps, 2);
  for (const auto& r : rows) {
    const auto& point = sweeps[0].points[static_cast<std::size_t>(r.point)];
    const RunResult single = run_once(point.scenario, 77, r.trial);
    EXPECT_EQ(single.d_t, r.result.d_t);
    EXPECT_EQ(single.steps, r.result.steps);
    EXPECT_EQ(single.outcome, r.result.outcome);
  }
}

TEST(Campaign, StoppedCampaignResumesToTheRowsOfACleanOne) {
  const auto sweeps = quick();
  const auto clean = run_fresh(sweeps, 2);

  const std::string path = testing::temp_path("resume", ".sqlite");
  std::atomic<bool> stop{false};
  {
    Store store(path, sweeps, version(), false);
    CampaignOptions options;
    options.threads = 2;
    options.stop = &stop;
    options.progress_interval = 0.001;
    options.share_plumes = false;  // one run per unit, so the stop lands mid-way
    options.on_progress = [&](const Progress& p) {
      if (p.done >= 5) stop = true;
    };
    const CampaignResult first = run_campaign(sweeps, store, 0, options);
    EXPECT_TRUE(first.interrupted);
    EXPECT_GE(first.computed, 5);
    EXPECT_LT(first.computed, 24);
  }
  Store store(path, sweeps, version(), false);
  const auto before = store.keys().size();
  CampaignOptions options;
  options.threads = 2;
  const CampaignResult second = run_campaign(sweeps, store, 0, options);
  EXPECT_FALSE(second.interrupted);
  EXPECT_EQ(second.skipped, static_cast<std::int64_t>(before));
  EXPECT_EQ(second.skipped + second.computed, 24);
  expect_same_rows(store.rows(), clean);
}

TEST(Campaign, MoreRunsExtendTheStoreAndFewerReuseIt) {
  const auto sweeps = quick();
  const std::string path = testing::temp_path("extend", ".sqlite");
  Store store(path, sweeps, version(), false);
  CampaignOptions options;
  EXPECT_EQ(run_campaign(sweeps, store, 2, options).computed, 12);
  const CampaignResult more = run_campaign(sweeps, store, 4, options);
  EXPECT_EQ(more.skipped, 12);
  EXPECT_EQ(more.computed, 12);
  EXPECT_EQ(run_campaign(sweeps, store, 3, options).computed, 0);
  expect_same_rows(store.rows(), run_fresh(sweeps, 1));
}

// the quick sweep with its sigma_a axis given `values` (a TOML array)
std::vector<ExpandedSweep> quick_with(const std::string& values) {
  std::string text = kQuickSweep;
  const std::string axis = "[0.0, 0.3, 0.6]";
  text.replace(text.find(axis), axis.size(), values);
  return {expand_sweep(read_sweep_file(write_sweep(text)), {})};
}

// the exports of a campaign's rows (runs.csv, summary.csv, results.json) as one text
std::string exports_of(const std::vector<ExpandedSweep>& sweeps, const std::vector<RunRow>& rows) {
  const std::string out = testing::temp_path("exports", "");
  std::filesystem::create_directories(out);
  write_exports(out, sweeps, rows, 0);
  std::string text;
  for (const char* name : {"/runs.csv", "/summary.csv", "/results.json"}) {
    std::ifstream in(out + name);
    text += std::string(std::istreambuf_iterator<char>(in), {});
  }
  return text;
}

// the rows of `all` whose key is among `some`'s
std::vector<RunRow> same_keys(const std::vector<RunRow>& all, const std::vector<RunRow>& some) {
  std::set<RunKey> keys;
  for (const auto& r : some) keys.insert(run_key(r));
  std::vector<RunRow> out;
  for (const auto& r : all) {
    if (keys.count(run_key(r))) out.push_back(r);
  }
  return out;
}

TEST(Campaign, AValueAddedToAnAxisComputesOnlyItsRunsAndKeepsEveryStoredRow) {
  const auto first = quick_with("[0.0, 0.6]");          // 2 x 2 points, 16 runs
  const auto extended = quick_with("[0.0, 0.3, 0.6]");  // 0.3 added between: 2 x 3 points
  const std::string path = testing::temp_path("added", ".sqlite");
  CampaignOptions options;
  options.threads = 2;
  {
    Store store(path, first, version(), false);
    EXPECT_EQ(run_campaign(first, store, 0, options).computed, 16);
  }
  const std::vector<RunRow> before = read_store_rows(path, nullptr);
  Store store(path, extended, version(), false);
  const CampaignResult more = run_campaign(extended, store, 0, options);
  EXPECT_EQ(more.skipped, 16);
  EXPECT_EQ(more.computed, 8);  // the two new points' runs only
  EXPECT_FALSE(more.interrupted);

  // the stored rows are as they were, bit for bit, under the numbers the store gave them
  const std::vector<RunRow> after = read_store_rows(path, nullptr);
  EXPECT_EQ(after.size(), 24u);
  expect_same_rows(same_keys(after, before), before);
  // and the store now holds what a fresh run of the extended sweep computes, point by point
  const std::vector<RunRow> fresh = run_fresh(extended, 1);
  expect_same_rows(store.rows(), fresh);
  EXPECT_EQ(exports_of(extended, store.rows()), exports_of(extended, fresh));
  // the point 0.6 moved from index 1 to index 2 of each algorithm: found by its values
  EXPECT_EQ(fresh[8].point, 2);
  EXPECT_EQ(extended[0].points[2].config_hash, first[0].points[1].config_hash);
}

TEST(Campaign, AValueTakenOffAnAxisKeepsItsRunsAndTheSmallerSweepComputesNothing) {
  const auto first = quick_with("[0.0, 0.6]");
  const auto extended = quick_with("[0.0, 0.3, 0.6]");
  const std::string path = testing::temp_path("removed", ".sqlite");
  Store big(path, extended, version(), false);
  EXPECT_EQ(run_campaign(extended, big, 0, {}).computed, 24);
  {
    Store small(path, first, version(), false);
    const CampaignResult again = run_campaign(first, small, 0, {});
    EXPECT_EQ(again.computed, 0);
    EXPECT_EQ(again.skipped, 16);
    Store clean(testing::temp_path("clean", ".sqlite"), first, version(), false);
    run_campaign(first, clean, 0, {});
    expect_same_rows(small.rows(), clean.rows());
  }
  EXPECT_EQ(read_store_rows(path, nullptr).size(), 24u);  // 0.3's runs are still there
  EXPECT_EQ(run_campaign(extended, big, 0, {}).computed, 0);
}

TEST(Campaign, AStoreExtendedByAnotherProcessMeanwhileServesTheFirstOneStill) {
  const auto first = quick_with("[0.0, 0.6]");
  const auto extended = quick_with("[0.0, 0.3, 0.6]");
  const std::string path = testing::temp_path("meanwhile", ".sqlite");
  Store a(path, first, version(), false);
  EXPECT_EQ(run_campaign(first, a, 2, {}).computed, 8);
  Store b(path, extended, version(), false);  // another process adds 0.3 and runs everything
  EXPECT_EQ(run_campaign(extended, b, 0, {}).computed, 16);
  // a finds its points among b's by their values: all 16 runs of its sweep are stored
  const CampaignResult rest = run_campaign(first, a, 0, {});
  EXPECT_EQ(rest.computed, 0);
  EXPECT_EQ(rest.skipped, 16);
  Store clean(testing::temp_path("clean", ".sqlite"), first, version(), false);
  run_campaign(first, clean, 0, {});
  expect_same_rows(a.rows(), clean.rows());
}

TEST(Store, RefusesAnotherDefinitionUnlessFresh) {
  const auto sweeps = quick();
  const std::string path = testing::temp_path("refuse", ".sqlite");
  {
    Store store(path, sweeps, version(), false);
    run_campaign(sweeps, store, 1, {});
  }
  const auto other = std::vector<ExpandedSweep>{
      expand_sweep(read_sweep_file(write_sweep(kQuickSweep)), {parse_override("sim.dt=0.05")})};
  try {
    Store store(path, other, version(), false);
    FAIL() << "a different definition was accepted";
  } catch (const StoreError& e) {
    // the same values under another base scenario: the message names the point
    for (const std::string& part : {std::string("--fresh"), path,
                                    std::string("controller.algorithm = 'casting', "
                                                "wind_sensor.sigma_a = 0")}) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << part << ": " << e.what();
    }
  }
  try {
    Store store(path, sweeps, "0.0.0-other", false);
    FAIL() << "another version was accepted";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("0.0.0-other"), std::string::npos) << e.what();
  }
  // the same name and values under another master seed: the runs would all differ
  auto reseeded = read_sweep_file(write_sweep(kQuickSweep));
  reseeded.seed = 78;
  try {
    Store store(path, std::vector<ExpandedSweep>{expand_sweep(reseeded, {})}, version(), false);
    FAIL() << "another seed was accepted";
  } catch (const StoreError& e) {
    for (const char* part : {"seed 77", "seed 78", "quick", "--fresh"}) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << part << ": " << e.what();
    }
  }
  Store fresh(path, other, version(), true);
  EXPECT_TRUE(fresh.keys().empty());
}

TEST(Store, StoredRowsHaveNoDuplicatesAndKeepFullSeeds) {
  auto def = read_sweep_file(write_sweep(kQuickSweep));
  def.seed = 18446744073709551615ULL;  // the largest seed survives the round trip
  const std::vector<ExpandedSweep> sweeps{expand_sweep(def, {})};
  Store store(testing::temp_path("seed", ".sqlite"), sweeps, version(), false);
  run_campaign(sweeps, store, 2, {});
  const auto rows = store.rows();
  EXPECT_EQ(rows.size(), 12u);
  EXPECT_EQ(store.keys().size(), rows.size());
  for (const auto& r : rows) EXPECT_EQ(r.result.seed, 18446744073709551615ULL);
  // a second insert of a stored run adds no row when identical and is refused otherwise
  store.insert({rows.front()});
  EXPECT_EQ(store.rows().size(), 12u);
  RunRow other = rows.front();
  other.result.losses += 1;
  EXPECT_THROW(store.insert({other}), StoreError);
  EXPECT_EQ(store.rows().size(), 12u);
}

}  // namespace
}  // namespace plumetrace
