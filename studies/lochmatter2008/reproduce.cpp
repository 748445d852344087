#include "lochmatter2008/reproduce.hpp"

#include <algorithm>

#include "plumetrace/core/files.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/sweep_file.hpp"

namespace plumetrace {

namespace {

// the reading without the keys that are axes of `def` (the radius sweep varies the radius that
// a reading may set)
Reading without_axes(Reading reading, const SweepDef& def) {
  std::erase_if(reading.settings, [&](const Setting& s) {
    return std::any_of(def.axes.begin(), def.axes.end(),
                       [&](const Axis& a) { return a.key == s.key; });
  });
  return reading;
}

}  // namespace

Reproduction plan_reproduction(const Study& study, const std::string& main,
                               const std::optional<std::vector<std::string>>& others,
                               const std::optional<std::vector<std::string>>& axes) {
  Reproduction plan;
  plan.readings.push_back(read_reading(study.presets_dir, main));
  for (const auto& name : others ? *others : preset_names(study.presets_dir)) {
    const bool seen = std::any_of(plan.readings.begin(), plan.readings.end(),
                                  [&](const Reading& r) { return r.name == name; });
    if (!seen) plan.readings.push_back(read_reading(study.presets_dir, name));
  }
  plan.sets = read_sets(study);
  plan.sweeps = reading_sets(plan.sets, plan.readings.front(), true);
  const SweepDef radius = read_sweep_file(study.radius_file);
  plan.radius = radius.name;
  plan.sweeps.push_back(expand_sweep(radius, without_axes(plan.readings.front(), radius).settings));
  for (std::size_t i = 1; i < plan.readings.size(); ++i) {
    for (auto& s : reading_sets(plan.sets, plan.readings[i], false)) {
      plan.sweeps.push_back(std::move(s));
    }
  }
  // the axis readings: the sets on the set files' axes are the main sets; the others run the
  // sets they change, under the main reading
  plan.axis_readings.push_back(read_axis_reading(study.axes_dir, kSetsAxes, plan.sets));
  for (const auto& name : axes ? *axes : axis_reading_names(study.axes_dir)) {
    const bool seen = std::any_of(plan.axis_readings.begin(), plan.axis_readings.end(),
                                  [&](const AxisReading& r) { return r.name == name; });
    if (seen) continue;
    plan.axis_readings.push_back(read_axis_reading(study.axes_dir, name, plan.sets));
    for (const SweepDef& def : axis_reading_sets(plan.sets, plan.axis_readings.back())) {
      plan.sweeps.push_back(expand_sweep(def, plan.readings.front().settings));
    }
  }
  return plan;
}

void write_reproduction(const std::string& out, const Study& study, const Reproduction& plan,
                        const std::vector<RunRow>& rows, ReproduceInfo info) {
  info.sets = set_names(plan.sets);
  info.trajectory_sets = study.trajectory_sets;
  info.radius = plan.radius;
  info.preset = plan.readings.front().name;
  info.readings = plan.readings;
  info.axis_readings = plan.axis_readings;
  info.base_config = scenario_to_toml(
      load_scenario(plan.sweeps.front().def.scenario_path, plan.readings.front().settings));
  write_exports(out, plan.sweeps, rows, info.runs_override);
  write_text_file(out + "/summary.json", build_summary(plan.sweeps, rows, info));
}

std::vector<ExpandedSweep> sensitivity_campaign(const Study& study, int runs) {
  std::vector<ExpandedSweep> sweeps;
  for (const auto& def : sensitivity_sweeps(read_sets(study), study.sensitivity_axes, runs)) {
    sweeps.push_back(expand_sweep(def, {}));
  }
  return sweeps;
}

std::string write_sensitivity(const std::string& out, const Study& study,
                              const std::vector<ExpandedSweep>& sweeps,
                              const std::vector<RunRow>& rows, int runs, double elapsed) {
  const SensitivityMatrix matrix =
      sensitivity_matrix(sweeps, rows, runs, study.sensitivity_axes.size());
  write_text_file(out + "/sensitivity.json", sensitivity_json(matrix, runs, elapsed));
  std::string md = sensitivity_markdown(matrix, runs, elapsed);
  write_text_file(out + "/sensitivity.md", md);
  return md;
}

}  // namespace plumetrace
