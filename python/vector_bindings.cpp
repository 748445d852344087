// The vector environment's binding (plumetrace.vector): a VectorWorld stepped with the GIL
// released, its outputs handed to Python as NumPy copies.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "plumetrace/env/odor.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/vector_world.hpp"

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

py::array_t<float> observations_of(const pt::VectorWorld& w) {
  const auto n = static_cast<py::ssize_t>(w.spec().envs);
  const auto width = static_cast<py::ssize_t>(w.spec().observe.width());
  py::array_t<float> out({n, width});
  std::copy(w.observations().begin(), w.observations().end(), out.mutable_data());
  return out;
}

py::dict info_of(const pt::VectorWorld& w) {
  const pt::VectorWorld::Info& i = w.info();
  py::dict d;
  d["outcome"] = copy_of(i.outcome);
  d["time"] = copy_of(i.time);
  d["x"] = copy_of(i.x);
  d["y"] = copy_of(i.y);
  d["heading"] = copy_of(i.heading);
  d["source_distance"] = copy_of(i.source_distance);
  d["odometer"] = copy_of(i.odometer);
  d["seed"] = copy_of(i.seed);
  d["trial"] = copy_of(i.episode);
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

void bind_vector(py::module_& m, const ScenarioOf& scenario_of) {
  py::class_<pt::VectorWorld>(m, "VectorWorld")
      .def(py::init([scenario_of](const std::optional<std::string>& path, const py::list& overrides,
                                  int envs, int group, bool renew, int decision_interval,
                                  const py::dict& observe, const std::string& action, int headings,
                                  const std::string& reward, int threads) {
             pt::VectorSpec spec;
             spec.envs = envs;
             spec.group = group;
             spec.renew_plumes = renew;
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
             spec.threads = threads;
             const pt::Scenario scenario = scenario_of(path, overrides);
             return std::make_unique<pt::VectorWorld>(scenario, spec);
           }),
           py::arg("path"), py::arg("overrides"), py::arg("envs"), py::arg("group"),
           py::arg("renew"), py::arg("decision_interval"), py::arg("observe"), py::arg("action"),
           py::arg("headings"), py::arg("reward"), py::arg("threads"))
      .def(
          "reset",
          [](pt::VectorWorld& w, const py::array_t<std::uint64_t, py::array::c_style>& seeds) {
            const std::span<const std::uint64_t> s(seeds.data(),
                                                   static_cast<std::size_t>(seeds.size()));
            py::gil_scoped_release release;
            w.reset(s);
          },
          py::arg("seeds"), "every environment afresh, environment i with seeds[i]")
      .def(
          "reset_some",
          [](pt::VectorWorld& w, const py::array_t<std::uint8_t, py::array::c_style>& mask) {
            const std::span<const std::uint8_t> s(mask.data(),
                                                  static_cast<std::size_t>(mask.size()));
            py::gil_scoped_release release;
            w.reset_some(s);
          },
          py::arg("mask"), "a new episode on the running plume for the flagged environments")
      .def(
          "reset_next",
          [](pt::VectorWorld& w) {
            py::gil_scoped_release release;
            w.reset_next();
          },
          "every environment's next episode on new plumes")
      .def(
          "step",
          [](pt::VectorWorld& w, const py::array_t<double, py::array::c_style>& actions) {
            const std::span<const double> a(actions.data(),
                                            static_cast<std::size_t>(actions.size()));
            {
              py::gil_scoped_release release;
              w.step(a);
            }
            return py::make_tuple(observations_of(w), copy_of(w.rewards()),
                                  flags_of(w.terminated()), flags_of(w.truncated()), info_of(w));
          },
          py::arg("actions"),
          "one decision of every environment; (obs, reward, terminated, "
          "truncated, info) as NumPy copies")
      .def("observations", &observations_of)
      .def("info", &info_of)
      .def("bounds",
           [](const pt::VectorWorld& w) {
             std::vector<float> low, high;
             pt::observation_bounds(w.spec().observe, w.scenario(), low, high);
             return py::make_tuple(copy_of(low), copy_of(high));
           })
      .def_property_readonly("width",
                             [](const pt::VectorWorld& w) { return w.spec().observe.width(); })
      .def_property_readonly(
          "frame_width", [](const pt::VectorWorld& w) { return w.spec().observe.frame_width(); })
      .def("result_json",
           [](const pt::VectorWorld& w, std::size_t i) {
             const pt::RunResult r = w.result(i);
             return pt::result_to_json(r, {"external", r.seed, r.trial, r.agent});
           })
      .def(
          "filaments",
          [](const pt::VectorWorld& w, std::size_t g) {
            const pt::OdorSnapshot snap = w.plume(g).odor->snapshot();
            const bool puffs = snap.kind == pt::OdorSnapshotKind::kFilaments;
            const auto column = [&](std::span<const double> v) {
              return py::array_t<double>(static_cast<py::ssize_t>(puffs ? v.size() : 0), v.data());
            };
            const pt::FilamentSpans& f = snap.filaments;
            return py::make_tuple(column(f.x), column(f.y), column(f.w));
          },
          py::arg("group"), "plume `group`'s filaments (centres x, y and widths, m) as copies");
  m.attr("MAX_VECTOR_ENVS") = pt::kMaxVectorEnvs;
}
