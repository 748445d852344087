// The team environment's binding (plumetrace.team_env): a TeamWorld stepped with the GIL
// released, its outputs handed to Python as NumPy copies.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "plumetrace/env/odor.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/team_world.hpp"

namespace py = pybind11;
namespace pt = plumetrace;

using ScenarioOf = std::function<pt::Scenario(const std::optional<std::string>&, const py::list&)>;

namespace {

template <class T>
py::array_t<T> copy_of(const std::vector<T>& values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

py::array_t<bool> flags_of(const std::vector<std::uint8_t>& values) {
  py::array_t<bool> out(static_cast<py::ssize_t>(values.size()));
  bool* p = out.mutable_data();
  for (std::size_t i = 0; i < values.size(); ++i) p[i] = values[i] != 0;
  return out;
}

py::array_t<float> observations_of(const pt::TeamWorld& w) {
  const auto n = static_cast<py::ssize_t>(w.size());
  const auto width = static_cast<py::ssize_t>(w.spec().observe.width());
  py::array_t<float> out({n, width});
  std::copy(w.observations().begin(), w.observations().end(), out.mutable_data());
  return out;
}

// per robot: whether its run goes on, its outcome's name, time since release (s), true pose
// (m, rad), distance to the source (m), odometer (m)
py::dict info_of(const pt::TeamWorld& w) {
  const std::size_t n = w.size();
  py::list outcome;
  std::vector<double> time(n), x(n), y(n), heading(n), distance(n), odometer(n);
  py::array_t<bool> running(static_cast<py::ssize_t>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const pt::Agent& a = w.world().agent(i);
    const pt::RobotState& r = a.robot();
    running.mutable_data()[i] = !a.done();
    outcome.append(std::string(pt::outcome_name(a.outcome())));
    time[i] = a.time();
    x[i] = r.pose.x;
    y[i] = r.pose.y;
    heading[i] = r.pose.heading;
    distance[i] = w.source_distance(i);
    odometer[i] = r.odometer;
  }
  py::dict d;
  d["running"] = running;
  d["outcome"] = outcome;
  d["time"] = copy_of(time);
  d["x"] = copy_of(x);
  d["y"] = copy_of(y);
  d["heading"] = copy_of(heading);
  d["source_distance"] = copy_of(distance);
  d["odometer"] = copy_of(odometer);
  return d;
}

pt::ActionMode action_of(const std::string& name) {
  if (name == "heading") return pt::ActionMode::kHeading;
  if (name == "turn") return pt::ActionMode::kTurn;
  if (name == "discrete") return pt::ActionMode::kDiscrete;
  throw py::value_error("action must be 'heading', 'turn' or 'discrete', got '" + name + "'");
}

pt::RewardMode reward_of(const std::string& name) {
  if (name == "success") return pt::RewardMode::kSuccess;
  if (name == "shaped") return pt::RewardMode::kShaped;
  throw py::value_error("reward must be 'success' or 'shaped', got '" + name + "'");
}

}  // namespace

void bind_team(py::module_& m, const ScenarioOf& scenario_of) {
  py::class_<pt::TeamWorld>(m, "TeamWorld")
      .def(py::init([scenario_of](const std::optional<std::string>& path, const py::list& overrides,
                                  int decision_interval, const py::dict& observe,
                                  const std::string& action, int headings,
                                  const std::string& reward) {
             pt::TeamSpec spec;
             spec.decision_interval = decision_interval;
             pt::ObservationSpec& o = spec.observe;
             o.odor = observe["odor"].cast<bool>();
             o.concentration = observe["concentration"].cast<bool>();
             o.odor_fraction = observe["odor_fraction"].cast<bool>();
             o.wind = observe["wind"].cast<bool>();
             o.odometry = observe["odometry"].cast<bool>();
             o.time = observe["time"].cast<bool>();
             o.stack = observe["stack"].cast<int>();
             spec.action = action_of(action);
             spec.headings = headings;
             spec.reward = reward_of(reward);
             return std::make_unique<pt::TeamWorld>(scenario_of(path, overrides), spec);
           }),
           py::arg("path"), py::arg("overrides"), py::arg("decision_interval"), py::arg("observe"),
           py::arg("action"), py::arg("headings"), py::arg("reward"))
      .def(
          "reset",
          [](pt::TeamWorld& w, std::uint64_t seed, std::uint64_t trial) {
            py::gil_scoped_release release;
            w.reset(seed, trial);
          },
          py::arg("seed"), py::arg("trial"), "episode (seed, trial): run (seed, trial)'s team")
      .def(
          "step",
          [](pt::TeamWorld& w, const py::array_t<double, py::array::c_style>& actions) {
            const std::span<const double> a(actions.data(),
                                            static_cast<std::size_t>(actions.size()));
            {
              py::gil_scoped_release release;
              w.step(a);
            }
            return py::make_tuple(observations_of(w), copy_of(w.rewards()),
                                  flags_of(w.terminated()), flags_of(w.truncated()));
          },
          py::arg("actions"),
          "one decision of every robot; (obs, reward, terminated, truncated) as NumPy copies")
      .def("observations", &observations_of)
      .def("info", &info_of)
      .def(
          "bounds",
          [](const pt::TeamWorld& w, std::size_t i) {
            std::vector<float> low, high;
            pt::observation_bounds(w.spec().observe, w.robot_scenario(i), low, high);
            return py::make_tuple(copy_of(low), copy_of(high));
          },
          py::arg("robot"), "robot i's observation bounds (low, high)")
      .def_property_readonly("size", &pt::TeamWorld::size)
      .def_property_readonly("width",
                             [](const pt::TeamWorld& w) { return w.spec().observe.width(); })
      .def("result_json",
           [](const pt::TeamWorld& w, std::size_t i) {
             const pt::RunResult r = w.world().agent(i).result();
             return pt::result_to_json(r, {"external", r.seed, r.trial, r.agent});
           })
      .def(
          "filaments",
          [](const pt::TeamWorld& w) {
            const pt::OdorSnapshot snap = w.world().environment().odor->snapshot();
            const bool puffs = snap.kind == pt::OdorSnapshotKind::kFilaments;
            const auto column = [&](std::span<const double> v) {
              return py::array_t<double>(static_cast<py::ssize_t>(puffs ? v.size() : 0), v.data());
            };
            const pt::FilamentSpans& f = snap.filaments;
            return py::make_tuple(column(f.x), column(f.y), column(f.w));
          },
          "the filaments' centres x, y and widths (m) now, as NumPy copies");
}
