// plumetrace._core: thin pybind11 bindings of the C++ library. The model lives in the library;
// this file converts arguments and results and releases the GIL around long computations.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "lochmatter2008/calibration.hpp"
#include "lochmatter2008/calibration_study.hpp"
#include "lochmatter2008/claims.hpp"
#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/distributed/distributed.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/evidence.hpp"
#include "plumetrace/experiment/stats.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/benchmark.hpp"
#include "plumetrace/io/exports.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/probe.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/trace.hpp"
#include "plumetrace/sim/world.hpp"
#include "plumetrace/view/viewer.hpp"

namespace py = pybind11;
namespace pt = plumetrace;

namespace {

// dotted keys and values set from Python, in order
using Overrides = std::vector<std::pair<std::string, pt::ConfigValue>>;

// the name of an object's type, for messages ("NoneType", "MyController")
std::string type_name(const py::handle& value) {
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

// text of a Python str; ConfigError naming `what` where it cannot be UTF-8 (a lone surrogate)
std::string text_of(const py::handle& value, const std::string& what) {
  try {
    return value.cast<std::string>();
  } catch (const py::error_already_set&) {
    throw pt::ConfigError(what + ": " + py::repr(value).cast<std::string>() +
                          " is not valid Unicode text");
  }
}

// a config value from Python: bool, int, float or str, with the key in every refusal
// why: pybind's variant caster would take True as the int 1 (a bool is an int in Python), so
// that `sim.dt = True` passed as a number; bool goes first here, and no key takes a bool
pt::ConfigValue config_value(const std::string& key, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow != 0) {
      throw pt::ConfigError(key + ": " + py::repr(value).cast<std::string>() +
                            " is out of the range of a 64-bit integer");
    }
    return static_cast<std::int64_t>(v);
  }
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return text_of(value, key);
  throw pt::ConfigError(key + ": value " + py::repr(value).cast<std::string>() + " (" +
                        type_name(value) + ") is not a bool, int, float or str");
}

// the overrides of a Python list of (dotted key, value) pairs
Overrides overrides_of(const py::list& pairs) {
  Overrides out;
  for (const py::handle item : pairs) {
    const auto pair = py::reinterpret_borrow<py::tuple>(item);
    const std::string key = text_of(pair[0], "a config key");
    // why: the key goes into C strings (an exception's what()), which would end at the NUL
    if (key.find('\0') != std::string::npos) {
      throw pt::ConfigError("config key " + py::repr(pair[0]).cast<std::string>() +
                            " contains a NUL character");
    }
    out.emplace_back(key, config_value(key, pair[1]));
  }
  return out;
}

// settings of a scenario file (if any) then of the given overrides, in order
std::vector<pt::Setting> settings_of(const std::optional<std::string>& path,
                                     const py::list& overrides) {
  std::vector<pt::Setting> settings;
  if (path) settings = pt::read_scenario_file(*path);
  // why: no origin, so that an error reads "sim.warmup: ..." (the key is the caller's own)
  for (const auto& [key, value] : overrides_of(overrides)) {
    settings.push_back({key, value, false, "", pt::Layer::kCommandLine});
  }
  return settings;
}

pt::Scenario scenario_of(const std::optional<std::string>& path, const py::list& overrides) {
  return pt::build_scenario(settings_of(path, overrides));
}

template <class T>
py::array_t<T> to_array(const std::vector<T>& values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

// a trace as NumPy columns (and the controller states as a list of str)
py::dict trace_columns(const pt::Trace& trace) {
  std::vector<double> t, x, y, heading, odometer, concentration, wind_x, wind_y, true_x, true_y;
  std::vector<std::uint8_t> odor;
  std::vector<std::int32_t> wind_samples;
  py::list state;
  for (const pt::TraceStep& s : trace.agents.front().steps) {
    t.push_back(s.time);
    x.push_back(s.pose.x);
    y.push_back(s.pose.y);
    heading.push_back(s.pose.heading);
    odometer.push_back(s.odometer);
    concentration.push_back(s.concentration);
    odor.push_back(s.odor ? 1 : 0);
    wind_samples.push_back(s.wind_samples);
    wind_x.push_back(s.wind_samples > 0 ? s.wind_body.x : NAN);
    wind_y.push_back(s.wind_samples > 0 ? s.wind_body.y : NAN);
    true_x.push_back(s.true_wind.x);
    true_y.push_back(s.true_wind.y);
    state.append(s.state);
  }
  py::dict d;
  d["time"] = to_array(t);
  d["x"] = to_array(x);
  d["y"] = to_array(y);
  d["heading"] = to_array(heading);
  d["odometer"] = to_array(odometer);
  d["odor"] = to_array(odor).attr("astype")("bool");
  d["concentration"] = to_array(concentration);
  d["wind_samples"] = to_array(wind_samples);
  d["wind_x"] = to_array(wind_x);
  d["wind_y"] = to_array(wind_y);
  d["true_wind_x"] = to_array(true_x);
  d["true_wind_y"] = to_array(true_y);
  d["state"] = state;
  return d;
}

// the filament snapshots of a trace as a list of dicts of arrays
py::list snapshot_list(const pt::Trace& trace) {
  py::list out;
  for (const pt::FilamentSnapshot& s : trace.snapshots) {
    py::dict d;
    d["time"] = s.time;
    d["x"] = to_array(s.x);
    d["y"] = to_array(s.y);
    d["z"] = to_array(s.z);
    d["w"] = to_array(s.w);
    out.append(d);
  }
  return out;
}

// What a Python controller may read (its `reads`, plumetrace.controllers.READS): the names of
// the Reads flags of agent/measurement.hpp
constexpr std::array<std::pair<std::string_view, unsigned>, 3> kReadNames{{
    {"binary", pt::kReadsBinary},
    {"concentration", pt::kReadsConcentration},
    {"messages", pt::kReadsMessages},
}};

// the names of kReadNames, for messages: "binary, concentration, messages"
std::string read_names() {
  std::string names;
  for (const auto& [name, flag] : kReadNames) {
    names += (names.empty() ? "" : ", ") + std::string(name);
  }
  return names;
}

// The Reads flags of `value`, what a controller (`who`) says it reads: None, a name or an
// iterable of names. ValueError naming every unknown name, TypeError for anything else.
unsigned reads_of(const py::handle& value, const std::string& who) {
  if (value.is_none()) return pt::kReadsBinary;
  const std::string what = who + ".reads";
  std::vector<py::object> items;
  if (py::isinstance<py::str>(value)) {
    items.push_back(py::reinterpret_borrow<py::object>(value));
  } else if (py::isinstance<py::iterable>(value) && !py::isinstance<py::bytes>(value)) {
    for (const py::handle item : value) items.push_back(py::reinterpret_borrow<py::object>(item));
  } else {
    throw py::type_error(what + " must be a name or a tuple of names (" + read_names() + "), got " +
                         type_name(value));
  }
  unsigned flags = pt::kReadsBinary;
  std::string unknown;
  for (const py::object& item : items) {
    if (!py::isinstance<py::str>(item)) {
      throw py::type_error(what + ": " + py::repr(item).cast<std::string>() + " (" +
                           type_name(item) + ") is not a name (" + read_names() + ")");
    }
    const std::string name = text_of(item, what);
    const auto at = std::find_if(kReadNames.begin(), kReadNames.end(),
                                 [&](const auto& known) { return known.first == name; });
    if (at == kReadNames.end()) {
      unknown += (unknown.empty() ? "" : ", ") + py::repr(item).cast<std::string>();
    } else {
      flags |= at->second;
    }
  }
  if (!unknown.empty()) {
    throw py::value_error(what + ": unknown " + unknown + " (a controller reads " + read_names() +
                          ")");
  }
  return flags;
}

// a message's numbers as a tuple
py::tuple message_tuple(const std::array<double, pt::kMessageSize>& data) {
  py::tuple t(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) t[i] = data[i];
  return t;
}

// An observation as Python holds it: the C++ one with its messages copied out of the agent.
// why: Observation::messages views the agent's inbox, valid only during the step; a Python
// controller may keep the observation after it, or past the run
struct HeldObservation {
  explicit HeldObservation(const pt::Observation& seen)
      : obs(seen), messages(seen.messages.begin(), seen.messages.end()) {
    obs.messages = {};
  }
  pt::Observation obs;
  std::vector<pt::Message> messages;
};

// the finite numbers of a Python sequence (a list, tuple or array); `what` names it in the
// TypeError or ValueError of anything else
std::vector<double> finite_numbers(const py::handle& value, const std::string& what) {
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
      !py::isinstance<py::iterable>(value)) {
    throw py::type_error(what + " must be a sequence of numbers, got " + type_name(value));
  }
  std::vector<double> out;
  for (const py::handle item : value) {
    if (py::isinstance<py::bool_>(item) || py::isinstance<py::str>(item) ||
        !(PyFloat_Check(item.ptr()) || PyIndex_Check(item.ptr()) ||
          PyObject_HasAttrString(item.ptr(), "__float__"))) {
      throw py::type_error(what + ": " + py::repr(item).cast<std::string>() + " (" +
                           type_name(item) + ") is not a real number");
    }
    const double v = PyFloat_AsDouble(item.ptr());
    if (v == -1.0 && PyErr_Occurred()) {
      const bool overflow = PyErr_ExceptionMatches(PyExc_OverflowError) != 0;
      PyErr_Clear();
      if (!overflow) {
        throw py::type_error(what + ": " + py::repr(item).cast<std::string>() + " (" +
                             type_name(item) + ") is not a real number");
      }
      throw py::value_error(what + ": " + py::repr(item).cast<std::string>() +
                            " is out of a float's range");
    }
    if (!std::isfinite(v)) {
      throw py::value_error(what + ": " + py::repr(item).cast<std::string>() +
                            " is not a finite number");
    }
    out.push_back(v);
  }
  return out;
}

// `value` as a NumPy array of float64; ValueError naming `what` where NumPy cannot read it so
// (ragged lists, text)
py::object float_array(const py::handle& value, const std::string& what) {
  try {
    return py::module_::import("numpy").attr("asarray")(value, "float64");
  } catch (const py::error_already_set& e) {
    throw py::value_error(what + ": not an array of numbers (" + std::string(e.what()) + ")");
  }
}

// ValueError naming `what` and the first key of `d` that is not one of `keys`
void check_keys(const py::dict& d, std::initializer_list<const char*> keys,
                const std::string& what) {
  for (const auto& [key, item] : d) {
    const bool known =
        std::any_of(keys.begin(), keys.end(), [&](const char* k) { return key.equal(py::str(k)); });
    if (!known) {
      std::string names;
      for (const char* k : keys) names += (names.empty() ? "" : ", ") + std::string(k);
      throw py::value_error(what + ": unknown key " + py::repr(key).cast<std::string>() + " (" +
                            names + ")");
    }
  }
}

// The snapshot of a controller's state from the dict its snapshot() returns (None: nothing to
// show); every key optional: points (N x 2), weights (N), path (M x 2), grid {x0, y0, dx, dy,
// values (ny x nx, rows by y; or flat, with nx and ny)}, estimate ((x, y) or None). Numbers
// finite, at most kMaxSnapshotValues of them; TypeError or ValueError naming the key.
pt::Snapshot snapshot_of(const py::handle& value, const std::string& who) {
  pt::Snapshot s;
  if (value.is_none()) return s;
  const std::string what = who + ".snapshot()";
  if (!py::isinstance<py::dict>(value)) {
    const std::string got = type_name(value);
    throw py::type_error(what + " must return a dict (points, weights, path, grid, estimate) " +
                         "or None, got " + got);
  }
  const auto d = py::reinterpret_borrow<py::dict>(value);
  check_keys(d, {"points", "weights", "path", "grid", "estimate"}, what);
  const auto has = [&](const char* key) { return d.contains(key) && !d[key].is_none(); };
  // a list of (x, y) points: any sequence of pairs, or an (N, 2) array
  const auto xy = [&](const char* key) {
    std::vector<pt::Vec2> points;
    if (!has(key)) return points;
    const std::string where = what + ": " + key;
    const py::object a = float_array(d[key], where);
    const auto shape = a.attr("shape").cast<std::vector<py::ssize_t>>();
    const bool empty = a.attr("size").cast<py::ssize_t>() == 0;
    if (!empty && (shape.size() != 2 || shape[1] != 2)) {
      throw py::value_error(where + " must be (x, y) pairs (an N x 2 array), got shape " +
                            py::repr(a.attr("shape")).cast<std::string>());
    }
    const std::vector<double> v = finite_numbers(a.attr("ravel")(), where);
    for (std::size_t i = 0; i + 1 < v.size(); i += 2) points.push_back({v[i], v[i + 1]});
    return points;
  };
  // numbers of any shape, in C order
  const auto flat = [&](const py::handle& item, const std::string& where) {
    return finite_numbers(float_array(item, where).attr("ravel")(), where);
  };
  s.points = xy("points");
  s.path = xy("path");
  if (has("weights")) s.weights = flat(d["weights"], what + ": weights");
  if (!s.weights.empty() && s.weights.size() != s.points.size()) {
    throw py::value_error(what + ": weights: " + std::to_string(s.weights.size()) +
                          " weights for " + std::to_string(s.points.size()) +
                          " points (one a point, or none)");
  }
  if (has("grid")) {
    const std::string where = what + ": grid";
    if (!py::isinstance<py::dict>(d["grid"])) {
      throw py::type_error(where + " must be a dict (x0, y0, dx, dy, values; nx, ny), got " +
                           type_name(d["grid"]));
    }
    const auto g = py::reinterpret_borrow<py::dict>(d["grid"]);
    check_keys(g, {"x0", "y0", "dx", "dy", "nx", "ny", "values"}, where);
    const auto number = [&](const char* key) {
      if (!g.contains(key)) throw py::value_error(where + ": no " + key);
      return finite_numbers(py::make_tuple(g[key]), where + "." + key).front();
    };
    s.x0 = number("x0");
    s.y0 = number("y0");
    s.dx = number("dx");
    s.dy = number("dy");
    if (!(s.dx > 0.0 && s.dy > 0.0)) throw py::value_error(where + ": dx and dy must be > 0");
    if (!g.contains("values")) throw py::value_error(where + ": no values");
    const py::object values = float_array(g["values"], where + ".values");
    const auto shape = values.attr("shape").cast<std::vector<py::ssize_t>>();
    // nx and ny: given, or the shape (ny, nx) of a 2-D values array
    const auto count = [&](const char* key, std::size_t axis) -> long long {
      if (g.contains(key)) {
        const py::object n = g[key];
        if (py::isinstance<py::bool_>(n) || !PyIndex_Check(n.ptr())) {
          throw py::type_error(where + "." + key + " must be an int, got " + type_name(n));
        }
        return n.cast<long long>();
      }
      if (shape.size() != 2) {
        throw py::value_error(where + ": no " + key + ", and values is not a 2-D (ny, nx) array");
      }
      return shape[axis];
    };
    const long long nx = count("nx", 1), ny = count("ny", 0);
    const auto max = static_cast<long long>(pt::kMaxSnapshotValues);
    if (nx < 1 || ny < 1 || nx > max || ny > max) {
      throw py::value_error(where + ": nx and ny must be from 1 to " + std::to_string(max));
    }
    if (shape.size() == 2 && (shape[0] != ny || shape[1] != nx)) {
      throw py::value_error(where + ": values of shape (" + std::to_string(shape[0]) + ", " +
                            std::to_string(shape[1]) + ") for ny = " + std::to_string(ny) +
                            ", nx = " + std::to_string(nx) + " (rows by y: (ny, nx))");
    }
    s.grid = flat(values, where + ".values");
    if (static_cast<long long>(s.grid.size()) != nx * ny) {
      throw py::value_error(where + ": " + std::to_string(s.grid.size()) +
                            " values for nx * ny = " + std::to_string(nx * ny));
    }
    s.nx = static_cast<int>(nx);
    s.ny = static_cast<int>(ny);
  }
  if (has("estimate")) {
    const std::vector<double> e = flat(d["estimate"], what + ": estimate");
    if (e.size() != 2) {
      throw py::value_error(what + ": estimate must be (x, y) or None, got " +
                            std::to_string(e.size()) + " numbers");
    }
    s.has_estimate = true;
    s.estimate = {e[0], e[1]};
  }
  const std::size_t values =
      2 * s.points.size() + s.weights.size() + 2 * s.path.size() + s.grid.size();
  if (values > pt::kMaxSnapshotValues) {
    throw py::value_error(what + ": " + std::to_string(values) + " numbers; a snapshot holds at " +
                          "most " + std::to_string(pt::kMaxSnapshotValues) +
                          " (points and path count 2 each)");
  }
  return s;
}

// a snapshot as the dict a controller's snapshot() returns, with NumPy arrays (every key: None
// or empty where there is nothing)
py::dict snapshot_dict(const pt::Snapshot& s) {
  const auto pairs = [](const std::vector<pt::Vec2>& points) {
    py::array_t<double> a({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
    auto m = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < points.size(); ++i) {
      m(static_cast<py::ssize_t>(i), 0) = points[i].x;
      m(static_cast<py::ssize_t>(i), 1) = points[i].y;
    }
    return a;
  };
  py::dict d;
  d["points"] = pairs(s.points);
  d["weights"] = to_array(s.weights);
  d["path"] = pairs(s.path);
  if (s.grid.empty()) {
    d["grid"] = py::none();
  } else {
    py::dict g;
    g["x0"] = s.x0;
    g["y0"] = s.y0;
    g["dx"] = s.dx;
    g["dy"] = s.dy;
    g["nx"] = s.nx;
    g["ny"] = s.ny;
    g["values"] = to_array(s.grid).attr("reshape")(s.ny, s.nx);
    d["grid"] = g;
  }
  d["estimate"] = s.has_estimate ? py::object(py::make_tuple(s.estimate.x, s.estimate.y))
                                 : py::object(py::none());
  return d;
}

// The wind probe a Python controller's step() receives: it measures only during that call.
// why: the C++ probe belongs to the run's World; a probe kept in Python and called after the run
// would read freed memory, and one called from another run's thread would race with its World
class StepWindProbe {
 public:
  explicit StepWindProbe(pt::WindProbe* probe) : probe_(probe) {}
  /// One noisy wind sample (m/s, robot frame); RuntimeError once its step() has returned.
  pt::Vec2 measure_wind_body() {
    if (probe_ == nullptr) {
      throw std::runtime_error(
          "the wind probe is valid only during the step() call that received it; measure the "
          "wind there and keep the value, not the probe");
    }
    return probe_->measure_wind_body();
  }
  /// Ends the probe's validity (its step() returned).
  void invalidate() { probe_ = nullptr; }

 private:
  pt::WindProbe* probe_;
};

// Gives a thread the interpreter has not seen (a worker thread of run_tasks) one thread state
// for the rest of its life, made here with the GIL released again. why: pybind's
// gil_scoped_acquire on such a thread makes a thread state and deletes it when it lets go, and a
// Python controller takes the GIL for every decision: that cost a sweep's thread about 60% more
// CPU than the same runs on the main thread (docs/performance.md, "Python controllers on every
// core"). The state goes when the thread ends (run_tasks joins its threads within the call).
void keep_thread_state() {
  struct Kept {
    PyGILState_STATE gil = PyGILState_Ensure();
    PyThreadState* state = PyEval_SaveThread();
    ~Kept() {
      // why: a thread ending while the interpreter finalises must not take the GIL
#if PY_VERSION_HEX >= 0x030D0000
      if (Py_IsFinalizing()) return;
#else
      if (_Py_IsFinalizing()) return;
#endif
      PyEval_RestoreThread(state);
      PyGILState_Release(gil);
    }
  };
  thread_local std::unique_ptr<Kept> kept;
  if (!kept && PyGILState_GetThisThreadState() == nullptr) kept = std::make_unique<Kept>();
}

// A controller written in Python: an object with step(observation, wind) -> Command and
// optional state() -> str, losses() -> int, reads (names, kReadNames) and snapshot() -> dict.
// Calls take the GIL; `stop` (may be null), set when the caller is interrupted, ends a run at
// its next step.
class PyController : public pt::Controller {
 public:
  // constructed with the GIL held
  PyController(py::object impl, const std::atomic<bool>* stop)
      : impl_(std::move(impl)), stop_(stop) {
    if (py::hasattr(impl_, "reads")) reads_ = reads_of(call_or_value("reads"), type_name(impl_));
    refresh();
  }
  ~PyController() override {
    py::gil_scoped_acquire gil;
    impl_ = py::object();
  }

  pt::Command step(const pt::Observation& obs, pt::WindProbe& wind) override {
    if (stop_ != nullptr && stop_->load()) throw Interrupted();
    keep_thread_state();
    py::gil_scoped_acquire gil;
    py::object probe = py::cast(StepWindProbe(&wind));
    py::object command;
    {
      // invalidates the probe however step() ends (the GIL is still held then)
      const ProbeLease lease{probe.cast<StepWindProbe*>()};
      command = impl_.attr("step")(HeldObservation(obs), probe);
    }
    // why: cast<Command>() of a wrong type throws pybind's reference_cast_error, which the
    // dispatcher of run()/sweep() reports as a mismatch of their own arguments
    if (!py::isinstance<pt::Command>(command)) {
      throw py::type_error("controller.step must return a Command, got " + type_name(command));
    }
    refresh();
    return command.cast<pt::Command>();
  }
  std::string_view state() const override { return state_; }
  int losses() const override { return losses_; }
  unsigned reads() const override { return reads_; }
  pt::Snapshot snapshot() const override {
    py::gil_scoped_acquire gil;
    if (!py::hasattr(impl_, "snapshot")) return {};
    return snapshot_of(impl_.attr("snapshot")(), type_name(impl_));
  }

  /// Thrown by step() once the caller is interrupted; the caller raises the signal's error.
  struct Interrupted : std::runtime_error {
    Interrupted() : std::runtime_error("interrupted") {}
  };

 private:
  struct ProbeLease {
    StepWindProbe* probe;
    ~ProbeLease() { probe->invalidate(); }
  };

  // the state name and loss count the Python object reports, if it has them
  void refresh() {
    if (py::hasattr(impl_, "state")) state_ = py::str(call_or_value("state")).cast<std::string>();
    if (py::hasattr(impl_, "losses")) {
      const py::object v = call_or_value("losses");
      if (py::isinstance<py::bool_>(v) || !PyIndex_Check(v.ptr())) {
        throw py::type_error("controller.losses must be an int, got " + type_name(v));
      }
      const auto n = py::reinterpret_steal<py::int_>(PyNumber_Index(v.ptr()));
      if (!n) throw py::error_already_set();
      int overflow = 0;
      const long long count = PyLong_AsLongLongAndOverflow(n.ptr(), &overflow);
      if (overflow != 0 || count < 0 || count > INT_MAX) {
        throw py::value_error("controller.losses must be an int from 0 to " +
                              std::to_string(INT_MAX) + ", got " + py::repr(v).cast<std::string>());
      }
      losses_ = static_cast<int>(count);
    }
  }
  py::object call_or_value(const char* name) {
    py::object v = impl_.attr(name);
    return PyCallable_Check(v.ptr()) ? v() : v;
  }

  py::object impl_;
  const std::atomic<bool>* stop_;
  std::string state_ = "python";
  int losses_ = 0;
  unsigned reads_ = pt::kReadsBinary;
};

// Runs in flight whose threads read the controller registry: a Python controller is registered
// only while there are none. why: registering grows the registry, which those threads read
// without a lock (agent/controllers.hpp: add to it only before runs start)
std::atomic<int> g_registry_readers{0};

// holds g_registry_readers up while it lives
struct RegistryReader {
  RegistryReader() { ++g_registry_readers; }
  ~RegistryReader() { --g_registry_readers; }
  RegistryReader(const RegistryReader&) = delete;
  RegistryReader& operator=(const RegistryReader&) = delete;
};

// the value of a choice key of a Python controller: the index of its name
enum class ScriptedChoice : int {};

// One config key a Python controller declares (plumetrace.Param).
struct ScriptedKey {
  enum class Kind { kNumber, kInteger, kChoice };
  std::string name;
  std::string help;
  Kind kind = Kind::kNumber;
  pt::NumberSpec number;
  pt::IntegerSpec integer{INT_MIN, INT_MAX};
  std::vector<std::string> names;  // a choice's values
  pt::Choices choices;             // views of `names`, made once they are final
};

// What a Python controller registered under a name is: its keys and its factory.
struct ScriptedSpec {
  std::vector<ScriptedKey> keys;
  // f(values: dict, rng) -> controller. why: a reference never given back; the registry keeps
  // it to the end of the process, after the interpreter is gone
  PyObject* factory = nullptr;
};

// The params of a Python controller: a value per declared key, visited as config keys of its
// table like a C++ params struct's.
struct ScriptedParams {
  std::shared_ptr<const ScriptedSpec> spec;
  std::vector<double> numbers;          // by key; used for number keys
  std::vector<int> integers;            // by key; used for integer keys
  std::vector<ScriptedChoice> choices;  // by key; used for choice keys

  template <class V>
  void fields(V& v) {
    for (std::size_t i = 0; i < spec->keys.size(); ++i) {
      const ScriptedKey& k = spec->keys[i];
      switch (k.kind) {
        case ScriptedKey::Kind::kNumber:
          v(k.name, numbers[i], k.help, k.number);
          break;
        case ScriptedKey::Kind::kInteger:
          v(k.name, integers[i], k.help, k.integer);
          break;
        case ScriptedKey::Kind::kChoice:
          v(k.name, choices[i], k.help, k.choices);
          break;
      }
    }
  }
};

// the registry's factory of every Python controller: its Python factory called with the run's
// values of its keys (a dict) and its controller stream
std::unique_ptr<pt::Controller> make_scripted(const pt::AnyParams& held, pt::Rng rng) {
  const ScriptedParams& params = held.get<ScriptedParams>();
  py::gil_scoped_acquire gil;
  py::dict values;
  for (std::size_t i = 0; i < params.spec->keys.size(); ++i) {
    const ScriptedKey& k = params.spec->keys[i];
    const py::str name(k.name);
    switch (k.kind) {
      case ScriptedKey::Kind::kNumber:
        values[name] = params.numbers[i];
        break;
      case ScriptedKey::Kind::kInteger:
        values[name] = params.integers[i];
        break;
      case ScriptedKey::Kind::kChoice:
        values[name] = k.names.at(static_cast<std::size_t>(params.choices[i]));
        break;
    }
  }
  py::object impl = py::reinterpret_borrow<py::object>(params.spec->factory)(values, rng);
  if (!py::hasattr(impl, "step")) {
    throw py::type_error(
        "the registered controller's factory must return an object with a "
        "step(observation, wind) method, got " +
        type_name(impl));
  }
  return std::make_unique<PyController>(std::move(impl), nullptr);
}

// a name of letters, digits and `extra`, not empty
bool plain_name(const std::string& name, std::string_view extra) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [&](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || extra.find(c) != std::string_view::npos;
  });
}

// one field of a declared key's description as a C++ value; a field of another type is refused
// naming the key and the field (plumetrace.Param checks them first; this keeps pybind's "Unable
// to cast" from anyone who calls _core directly)
template <class T>
T spec_field(const py::dict& d, const char* field, const std::string& key) {
  try {
    return d[field].cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(key + ": " + field + " " + py::repr(d[field]).cast<std::string>() + " (" +
                         type_name(d[field]) + ") is not " +
                         (std::is_same_v<T, bool> ? "True or False" : "a number in range"));
  }
}

// one declared key from its Python description (plumetrace.Param._spec), checked
ScriptedKey scripted_key(const std::string& controller, const py::dict& d, double& number,
                         int& integer, ScriptedChoice& choice) {
  ScriptedKey k;
  k.name = text_of(d["name"], "a key name");
  const std::string key = controller + "." + k.name;
  if (!plain_name(k.name, "_")) {
    throw pt::ConfigError(key + ": a key's name is letters, digits and '_'");
  }
  k.help = text_of(d["help"], key + ": help");
  const std::string kind = text_of(d["kind"], key + ": kind");
  const bool no_min = d["min"].is_none(), no_max = d["max"].is_none();
  if (kind == "number") {
    k.kind = ScriptedKey::Kind::kNumber;
    k.number.min = no_min ? -INFINITY : spec_field<double>(d, "min", key);
    k.number.max = no_max ? INFINITY : spec_field<double>(d, "max", key);
    k.number.min_open = spec_field<bool>(d, "min_open", key);
    k.number.max_open = spec_field<bool>(d, "max_open", key);
    number = spec_field<double>(d, "default", key);
    const pt::NumberSpec& s = k.number;
    const bool ok = std::isfinite(number) && (s.min_open ? number > s.min : number >= s.min) &&
                    (s.max_open ? number < s.max : number <= s.max);
    if (!ok) {
      throw pt::ConfigError(key + ": the default " + pt::format_number(number) +
                            " is not a finite number within the declared range");
    }
  } else if (kind == "integer") {
    k.kind = ScriptedKey::Kind::kInteger;
    const auto bound = [&](const char* field, bool none, int otherwise) {
      if (none) return otherwise;
      const long long b = spec_field<long long>(d, field, key);
      if (b < INT_MIN || b > INT_MAX) {
        throw pt::ConfigError(key + ": " + field + ": an integer key's bounds are within +-2^31");
      }
      return static_cast<int>(b);
    };
    k.integer = {bound("min", no_min, INT_MIN), bound("max", no_max, INT_MAX)};
    const long long v = spec_field<long long>(d, "default", key);
    if (v < k.integer.min || v > k.integer.max) {
      throw pt::ConfigError(key + ": the default " + std::to_string(v) +
                            " is not within the declared range");
    }
    integer = static_cast<int>(v);
  } else {
    k.kind = ScriptedKey::Kind::kChoice;
    if (!py::isinstance<py::list>(d["choices"])) {
      throw py::type_error(key + ": choices must be a list of names, got " +
                           type_name(d["choices"]));
    }
    for (const py::handle n : py::reinterpret_borrow<py::list>(d["choices"])) {
      const std::string name = text_of(n, key + ": a choice");
      if (name.empty() || std::count(k.names.begin(), k.names.end(), name) > 0) {
        throw pt::ConfigError(key + ": choices are distinct, non-empty names");
      }
      k.names.push_back(name);
    }
    const std::string value = text_of(d["default"], key + ": default");
    const auto at = std::find(k.names.begin(), k.names.end(), value);
    if (at == k.names.end()) {
      throw pt::ConfigError(key + ": the default '" + value + "' is not one of the choices");
    }
    choice = static_cast<ScriptedChoice>(at - k.names.begin());
  }
  return k;
}

// Registers (or registers again) a controller written in Python under `name`, with the keys
// `keys` declare (plumetrace.register_controller).
void register_controller(const std::string& name, const py::list& keys, py::object factory) {
  if (!PyCallable_Check(factory.ptr())) {
    throw py::type_error("register_controller: the factory must be callable, got " +
                         type_name(factory));
  }
  if (!plain_name(name, "_-") || name.front() == '-') {
    throw pt::ConfigError("controller name '" + name +
                          "': letters, digits, '_' and '-' (not first), as in 'zigzag'");
  }
  pt::ControllerRegistry& registry = pt::controller_registry();
  // a table of the scenario's own ("robot", "controller"), not of a controller
  const std::string table = pt::ControllerRegistry::table_of(name);
  // why: "member" begins a robot's own keys (member.K.TABLE.KEY), so it is no table of a model
  bool scenario_table = table == "member";
  pt::for_each_value(pt::Scenario{}, [&](const pt::FieldValue& f) {
    scenario_table = scenario_table || f.table == table;
  });
  for (const auto& e : registry.entries()) scenario_table = scenario_table && e.table != table;
  if (scenario_table) {
    throw pt::ConfigError("controller name '" + name + "': '" + table +
                          "' is a table of the scenario already");
  }
  auto spec = std::make_shared<ScriptedSpec>();
  ScriptedParams defaults;
  for (const py::handle item : keys) {
    double number = 0.0;
    int integer = 0;
    ScriptedChoice choice{};
    spec->keys.push_back(
        scripted_key(name, py::reinterpret_borrow<py::dict>(item), number, integer, choice));
    defaults.numbers.push_back(number);
    defaults.integers.push_back(integer);
    defaults.choices.push_back(choice);
  }
  for (std::size_t i = 0; i < spec->keys.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (spec->keys[i].name == spec->keys[j].name) {
        throw pt::ConfigError(name + "." + spec->keys[i].name + ": declared twice");
      }
    }
    for (const std::string& n : spec->keys[i].names) spec->keys[i].choices.emplace_back(n);
  }
  const std::size_t existing = registry.find(name);
  if (existing < registry.size() && !registry[existing].defaults.holds<ScriptedParams>()) {
    throw pt::ConfigError("controller name '" + name +
                          "': taken by a controller of the library or of this program's C++");
  }
  if (g_registry_readers.load() > 0) {
    throw std::runtime_error("register_controller('" + name +
                             "'): runs are in progress; register controllers before running");
  }
  spec->factory = factory.release().ptr();
  defaults.spec = std::move(spec);
  try {
    if (existing < registry.size()) {
      registry.replace(existing, pt::AnyParams(std::move(defaults)), &make_scripted);
    } else {
      registry.add(name, pt::AnyParams(std::move(defaults)), &make_scripted);
    }
  } catch (const std::invalid_argument& e) {
    throw pt::ConfigError("controller name '" + name + "': " + e.what());
  }
}

// A controller factory calling the Python `factory(scenario_dict, rng)` for each run; empty
// for None (the scenario's built-in algorithm). `stop` as for PyController.
pt::ControllerFactory python_factory(py::object factory, const std::atomic<bool>* stop = nullptr) {
  if (factory.is_none()) return {};
  if (!PyCallable_Check(factory.ptr())) {
    throw py::type_error(
        "controller must be a factory f(scenario_dict, rng) (a class or a function), got " +
        type_name(factory));
  }
  auto shared = std::make_shared<py::object>(std::move(factory));
  return [shared, stop](const pt::Scenario& scenario,
                        pt::Rng rng) -> std::unique_ptr<pt::Controller> {
    py::gil_scoped_acquire gil;
    py::object impl =
        (*shared)(py::module_::import("json").attr("loads")(pt::scenario_to_json(scenario)), rng);
    if (!py::hasattr(impl, "step")) {
      throw py::type_error(
          "the controller factory must return an object with a step(observation, wind) method, "
          "got " +
          type_name(impl));
    }
    return std::make_unique<PyController>(std::move(impl), stop);
  };
}

// The controller of a run decided from outside (a learning agent drives it through
// World::observe and World::act); it is never asked to decide, only what it reads.
class ExternalController : public pt::Controller {
 public:
  explicit ExternalController(unsigned reads) : reads_(reads) {}
  pt::Command step(const pt::Observation&, pt::WindProbe&) override {
    throw std::logic_error("an externally driven run steps through observe() and act()");
  }
  std::string_view state() const override { return "external"; }
  int losses() const override { return 0; }
  unsigned reads() const override { return reads_; }

 private:
  unsigned reads_;
};

// one run, optionally traced, optionally with a Python controller
py::dict run(const std::optional<std::string>& path, const py::list& overrides, std::uint64_t seed,
             std::uint64_t trial, bool trace, double snapshot_interval,
             py::object controller_factory, const std::optional<std::string>& view) {
  const pt::Scenario scenario = scenario_of(path, overrides);
  const pt::ControllerFactory factory = python_factory(std::move(controller_factory));
  if (view) pt::check_view_path(*view, "view");
  pt::Trace recorded;
  pt::TraceRecorder recorder(recorded, snapshot_interval, scenario.sim.dt);
  pt::RunResult result;
  {
    const RegistryReader reading;
    py::gil_scoped_release release;
    result = pt::run_once(scenario, seed, trial,
                          trace || view ? pt::StepObserver(std::ref(recorder)) : nullptr, factory);
  }
  const std::string algorithm =
      factory ? "python" : std::string(pt::algorithm_name(scenario.controller.algorithm));
  const pt::RunInfo info{algorithm, seed, trial};
  py::dict out = py::module_::import("json").attr("loads")(pt::result_to_json(result, info));
  if (view) {
    // why: the page `plumetrace view` draws from a trace of the run; the trace returned is exact
    pt::Trace stored = recorded;
    pt::round_as_stored(stored);
    pt::write_view(*view, {scenario, result, info, std::string(pt::version()), std::move(stored)},
                   {});
  }
  if (trace) {
    out["trajectory"] = trace_columns(recorded);
    out["snapshots"] = snapshot_list(recorded);
  }
  return out;
}

// the plume alone, sampled at the rows (x, y, z) of `points` as `plumetrace probe` samples it:
// per point the detect fraction and mean concentration, and the centrelines at centreline_x
py::dict probe(const std::optional<std::string>& path, const py::list& overrides,
               const py::array_t<double, py::array::c_style | py::array::forcecast>& points,
               std::optional<double> warmup, double duration, double interval, std::uint64_t seed,
               const std::vector<double>& centreline_x, double slab) {
  if (points.ndim() != 2 || points.shape(1) != 3) {
    throw py::value_error("points: expected an array of shape (N, 3)");
  }
  const pt::Scenario scenario = scenario_of(path, overrides);
  pt::ProbeOptions options;
  if (warmup) options.warmup = *warmup;
  options.duration = duration;
  options.interval = interval;
  options.seed = seed;
  options.centreline_x = centreline_x;
  options.centreline_slab = slab;
  const auto xyz = points.unchecked<2>();
  std::vector<pt::Vec3> at;
  at.reserve(static_cast<std::size_t>(xyz.shape(0)));
  for (py::ssize_t i = 0; i < xyz.shape(0); ++i) at.push_back({xyz(i, 0), xyz(i, 1), xyz(i, 2)});
  pt::ProbeReport report;
  {
    py::gil_scoped_release release;
    report = pt::probe_report(scenario, at, options);
  }
  std::vector<double> detect, mean;
  for (const pt::ProbeResult& r : report.points) {
    detect.push_back(r.detect_fraction);
    mean.push_back(r.mean_concentration);
  }
  std::vector<double> cx, mean_y, std_y;
  std::vector<std::int64_t> samples, empty;
  for (const pt::CentrelineResult& c : report.centrelines) {
    cx.push_back(c.x);
    mean_y.push_back(c.mean_y);
    std_y.push_back(c.std_y);
    samples.push_back(c.samples);
    empty.push_back(c.empty);
  }
  py::dict centrelines;
  centrelines["x"] = to_array(cx);
  centrelines["mean_y"] = to_array(mean_y);
  centrelines["std_y"] = to_array(std_y);
  centrelines["samples"] = to_array(samples);
  centrelines["empty"] = to_array(empty);
  py::dict out;
  out["detect_fraction"] = to_array(detect);
  out["mean_concentration"] = to_array(mean);
  out["samples"] = report.points.empty() ? 0L : report.points.front().samples;
  out["centrelines"] = centrelines;
  return out;
}

// The most runs one Python sweep call may define. why: it lists every task up front and keeps
// every row in memory (about 0.5 kB with its Python columns), so 10^7 runs take some 5 GB; a
// larger campaign belongs in `plumetrace sweep --store`, which commits as it goes
constexpr std::int64_t kMaxPythonSweepRuns = 10'000'000;

// the rows of a sweep as columns: point, axis values, trial, seed and every metric
py::dict sweep_columns(const pt::ExpandedSweep& s, std::vector<pt::RunRow> rows);

// sets an attribute of an exception where it takes one (an exception type may refuse it)
void attach(const py::handle& error, const char* name, const py::object& value) {
  if (PyObject_SetAttrString(error.ptr(), name, value.ptr()) != 0) PyErr_Clear();
}

// Ctrl-C while C++ threads run without the GIL: Python sees a signal only when a thread that
// holds the GIL looks, so the caller's progress callback looks, and a raising handler stops the
// work; `signal` then holds the handler's error for the caller to raise. `report` (None for
// none) is called with (runs done, runs to do, seconds) at each progress call; its error stops
// the work as a signal's does.
struct SignalWatch {
  std::atomic<bool> stop{false};
  std::unique_ptr<py::error_already_set> signal;
  py::object report = py::none();

  std::function<void(const pt::Progress&)> on_progress() {
    return [this](const pt::Progress& p) {
      if (stop) return;
      py::gil_scoped_acquire gil;
      try {
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!report.is_none()) report(p.done, p.total, p.elapsed);
      } catch (py::error_already_set& e) {
        signal = std::make_unique<py::error_already_set>(std::move(e));
        stop = true;
      }
    };
  }
};

// a sweep as Python gives it: a sweep file's path, or a dict of its parts made by
// plumetrace.sweeps.sweep_spec (name, title, seed, runs, scenario, settings, axes), checked as a
// file is
pt::SweepDef sweep_def_of(const py::handle& spec) {
  if (py::isinstance<py::str>(spec)) return pt::read_sweep_file(text_of(spec, "sweep file"));
  const auto d = py::reinterpret_borrow<py::dict>(spec);
  pt::SweepDef def;
  def.name = text_of(d["name"], "name");
  def.title = text_of(d["title"], "title");
  def.seed = d["seed"].cast<std::uint64_t>();
  def.runs = d["runs"].cast<int>();
  if (!d["scenario"].is_none()) def.scenario_path = text_of(d["scenario"], "base");
  for (const auto& [key, value] : overrides_of(d["settings"].cast<py::list>())) {
    def.settings.push_back({key, value, false, "base", pt::Layer::kSweep});
  }
  for (const py::handle item : d["axes"].cast<py::list>()) {
    const auto a = py::reinterpret_borrow<py::dict>(item);
    pt::Axis axis;
    axis.key = text_of(a["key"], "an axis key");
    for (const py::handle v : a["values"].cast<py::list>()) {
      axis.values.push_back(config_value(axis.key, v));
    }
    axis.label = a["label"].is_none() ? axis.key : text_of(a["label"], axis.key + " label");
    if (!a["fixed"].is_none()) axis.fixed = config_value(axis.key, a["fixed"]);
    def.axes.push_back(std::move(axis));
  }
  pt::check_sweep_def(def, "sweep '" + def.name + "'");
  if (!def.scenario_path.empty()) def.scenario_settings = pt::read_scenario_file(def.scenario_path);
  return def;
}

// what a sweep says about itself besides its rows: title, file, seed, runs per point and axes
void describe_sweep(py::dict& out, const pt::ExpandedSweep& s, int runs) {
  out["name"] = s.def.name;
  out["title"] = s.def.title;
  out["file"] = s.def.file;
  out["seed"] = s.def.seed;
  out["runs_per_point"] = pt::runs_per_point(s, runs);
  py::list axes;
  for (const pt::Axis& a : s.def.axes) {
    py::dict axis;
    axis["key"] = a.key;
    axis["label"] = a.label;
    py::list values;
    for (const auto& v : a.values) std::visit([&](const auto& x) { values.append(x); }, v);
    axis["values"] = values;
    axis["fixed"] = py::none();
    if (a.fixed) std::visit([&](const auto& x) { axis["fixed"] = py::cast(x); }, *a.fixed);
    axes.append(axis);
  }
  out["axes"] = axes;
}

// the exports of the runs a results store holds of a sweep (path or dict), written into `out`
// as `plumetrace report` writes them; the points with runs missing, each a dict
py::list export_sweep_store(const py::object& spec, const py::list& overrides,
                            const std::string& store, const std::string& out, int runs) {
  if (runs < 0) {
    throw pt::ConfigError("runs: must be >= 0 (0: the sweep's; got " + std::to_string(runs) + ")");
  }
  const std::vector<pt::ExpandedSweep> sweeps = {
      pt::expand_sweep(sweep_def_of(spec), settings_of(std::nullopt, overrides))};
  pt::check_campaign(sweeps, runs);
  std::vector<pt::IncompletePoint> incomplete;
  {
    py::gil_scoped_release release;
    incomplete = pt::export_store(store, sweeps, out, runs);
  }
  py::list points;
  for (const auto& p : incomplete) {
    py::dict d;
    d["sweep"] = p.sweep;
    d["point"] = p.point;
    d["values"] = p.values;
    d["stored"] = p.stored;
    d["runs"] = p.runs;
    points.append(d);
  }
  return points;
}

// Whether a run of the campaign decides in Python: a controller factory is given from Python, or
// a robot of some point runs a controller registered from Python.
bool decides_in_python(const std::vector<pt::ExpandedSweep>& sweeps, bool factory) {
  if (factory) return true;
  const pt::ControllerRegistry& registry = pt::controller_registry();
  const auto scripted = [&](std::size_t index) {
    return index < registry.size() && registry[index].defaults.holds<ScriptedParams>();
  };
  for (const pt::ExpandedSweep& s : sweeps) {
    for (const pt::SweepPoint& p : s.points) {
      if (scripted(static_cast<std::size_t>(p.scenario.controller.algorithm))) return true;
      for (int robot = 0; robot < p.scenario.team.count; ++robot) {
        const std::string own = pt::own_algorithm(p.scenario, robot);
        if (!own.empty() && scripted(registry.find(own))) return true;
      }
    }
  }
  return false;
}

// The worker processes of process_runner: a plumetrace._workers.ProcessPool forked from this
// process, each worker computing the plume groups handed to it (encode_groups) on one thread
// and sending back their rows (encode_rows, doubles as their bits). Ended, every worker stopped
// and reaped, when this goes, however the campaign ends. Made and used without the GIL.
class WorkerProcesses {
 public:
  WorkerProcesses(const std::vector<pt::ExpandedSweep>& sweeps, pt::ControllerFactory factory,
                  const std::vector<pt::TaskGroup>& groups, std::size_t processes) {
    // why: a worker is a fork of this process, so it holds the campaign and the registered
    // Python controllers already; its own copy of the campaign outlives this call in any case
    auto campaign = std::make_shared<const std::vector<pt::ExpandedSweep>>(sweeps);
    py::gil_scoped_acquire gil;
    py::cpp_function work([campaign, factory](const py::bytes& job) {
      const std::vector<pt::TaskGroup> jobs = pt::decode_groups(bytes_of(job));
      std::vector<pt::RunRow> rows;
      {
        py::gil_scoped_release release;
        for (const pt::TaskGroup& group : jobs) {
          std::vector<pt::RunRow> done = pt::run_group(*campaign, group, factory);
          rows.insert(rows.end(), done.begin(), done.end());
        }
      }
      const std::vector<char> out = pt::encode_rows(rows);
      return py::bytes(out.data(), out.size());
    });
    py::list jobs;
    for (const pt::TaskGroup& group : groups) {
      const std::vector<char> job = pt::encode_groups({group});
      jobs.append(py::bytes(job.data(), job.size()));
    }
    pool_ = py::module_::import("plumetrace._workers").attr("ProcessPool")(work, jobs, processes);
  }
  ~WorkerProcesses() {
    py::gil_scoped_acquire gil;
    try {
      pool_.attr("close")();
    } catch (py::error_already_set& e) {
      e.discard_as_unraisable("closing the worker processes");
    }
    pool_ = py::object();
  }
  WorkerProcesses(const WorkerProcesses&) = delete;
  WorkerProcesses& operator=(const WorkerProcesses&) = delete;

  /// The rows finished within `timeout` (s), and whether every worker is idle (nothing left, or
  /// stopped); `stop` hands out no further group.
  std::pair<std::vector<pt::RunRow>, bool> take(double timeout, bool stop) {
    std::vector<std::vector<char>> parts;
    bool idle = false;
    {
      py::gil_scoped_acquire gil;
      const py::tuple got = pool_.attr("take")(timeout, stop);
      for (const py::handle part : got[0].cast<py::list>()) {
        parts.push_back(bytes_of(py::reinterpret_borrow<py::bytes>(part)));
      }
      idle = got[1].cast<bool>();
    }
    std::vector<pt::RunRow> rows;
    for (const auto& part : parts) {
      std::vector<pt::RunRow> decoded = pt::decode_rows(part);
      rows.insert(rows.end(), decoded.begin(), decoded.end());
    }
    return {std::move(rows), idle};
  }

  /// Raises the first error of a worker (a controller's exception, with its traceback) or of
  /// this process (Ctrl-C while waiting), once the pool is idle.
  void finish() {
    py::gil_scoped_acquire gil;
    pool_.attr("finish")();
  }

 private:
  static std::vector<char> bytes_of(const py::bytes& b) {
    char* data = nullptr;
    Py_ssize_t size = 0;
    if (PyBytes_AsStringAndSize(b.ptr(), &data, &size) != 0) throw py::error_already_set();
    return {data, data + size};
  }

  py::object pool_;
};

// A TaskRunner for a campaign that decides in Python: its plume groups (split as run_tasks
// splits them) computed in `processes` worker processes, so that each decides in its own
// interpreter instead of every run waiting for this one's GIL. The rows are run_tasks' rows,
// bit for bit (each run is a pure function of its point and trial; docs/python.md). With one
// process, or one group, it is run_tasks on one thread, here.
pt::TaskRunner process_runner(int processes) {
  return [processes](const std::vector<pt::ExpandedSweep>& sweeps,
                     const std::vector<pt::RunTask>& tasks, const pt::CampaignOptions& options,
                     const pt::RowSink& sink) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto seconds = [&] {
      return std::chrono::duration<double>(Clock::now() - start).count();
    };
    const std::vector<pt::TaskGroup> groups =
        pt::work_groups(sweeps, tasks, options.share_plumes, static_cast<std::size_t>(processes));
    const std::size_t workers = std::min(static_cast<std::size_t>(processes), groups.size());
    if (workers <= 1) {
      pt::CampaignOptions one = options;
      one.threads = 1;
      return pt::run_tasks(sweeps, tasks, one, sink);
    }
    WorkerProcesses pool(sweeps, options.make_controller, groups, workers);
    pt::CampaignResult result;
    result.total = static_cast<std::int64_t>(tasks.size());
    for (;;) {
      const bool stop = options.stop != nullptr && options.stop->load();
      auto [rows, idle] = pool.take(options.progress_interval, stop);
      if (!rows.empty()) {
        sink(rows);
        result.computed += std::count_if(rows.begin(), rows.end(),
                                         [](const pt::RunRow& r) { return r.agent == 0; });
      }
      if (options.on_progress) options.on_progress({result.computed, result.total, seconds()});
      if (idle) break;
    }
    pool.finish();
    result.interrupted = result.computed < result.total;
    result.elapsed = seconds();
    return result;
  };
}

// The runner of a campaign from Python: worker processes when `processes` is allowed, more
// than one is asked for (`threads`, 0 for every core) and a run decides in Python; else none
// (run_tasks: the threads of this process).
pt::TaskRunner python_runner(const std::vector<pt::ExpandedSweep>& sweeps, bool factory,
                             int threads, bool processes) {
  const int count =
      threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (!processes || count <= 1 || !decides_in_python(sweeps, factory)) return {};
  return process_runner(count);
}

// every run of a sweep file, in C++ threads without the GIL, or with a controller written in
// Python and `processes`, in worker processes (python_runner); rows sorted by (point, trial,
// agent). Ctrl-C (any Python signal handler that raises) or an error of a run (a Python
// controller's exception) stops it: runs not started are dropped, the error is raised here, and the
// rows finished before it ride on the exception as `partial_rows` (name, columns)
py::dict sweep(const py::object& spec, const py::list& overrides, int runs, int threads,
               bool share_plumes, py::object controller_factory, bool processes) {
  if (runs < 0) {
    throw pt::ConfigError("runs: must be >= 0 (0: the sweep file's; got " + std::to_string(runs) +
                          ")");
  }
  if (threads < 0 || threads > pt::kMaxThreads) {
    throw pt::ConfigError("threads: must be 0 (all cores) to " + std::to_string(pt::kMaxThreads) +
                          " (got " + std::to_string(threads) + ")");
  }
  std::vector<pt::Setting> settings = settings_of(std::nullopt, overrides);
  const std::vector<pt::ExpandedSweep> sweeps = {pt::expand_sweep(sweep_def_of(spec), settings)};
  const pt::ExpandedSweep& s = sweeps.front();
  const std::int64_t defined = static_cast<std::int64_t>(s.points.size()) *
                               static_cast<std::int64_t>(pt::runs_per_point(s, runs));
  if (defined > kMaxPythonSweepRuns) {
    throw pt::ConfigError(
        "runs: " + std::to_string(s.points.size()) + " points x " +
        std::to_string(pt::runs_per_point(s, runs)) + " runs = " + std::to_string(defined) +
        " runs, more than the " + std::to_string(kMaxPythonSweepRuns) +
        " a Python sweep holds in memory; use plumetrace sweep --store for a larger campaign");
  }
  const std::vector<pt::RunTask> tasks = pt::missing_runs(sweeps, {}, runs);
  const pt::TaskRunner runner =
      python_runner(sweeps, !controller_factory.is_none(), threads, processes);
  SignalWatch watch;
  std::atomic<bool>& stop = watch.stop;
  std::unique_ptr<py::error_already_set>& signal = watch.signal;
  pt::CampaignOptions options;
  options.threads = threads;
  options.share_plumes = share_plumes;
  options.make_controller = python_factory(std::move(controller_factory), &stop);
  options.stop = &stop;
  options.on_progress = watch.on_progress();
  std::vector<pt::RunRow> rows;
  std::exception_ptr failure;
  {
    const RegistryReader reading;
    py::gil_scoped_release release;
    try {
      const pt::RowSink sink = [&rows](const std::vector<pt::RunRow>& batch) {
        rows.insert(rows.end(), batch.begin(), batch.end());
      };
      runner ? runner(sweeps, tasks, options, sink) : pt::run_tasks(sweeps, tasks, options, sink);
    } catch (...) {
      failure = std::current_exception();
    }
  }
  if (signal || failure) {
    // the signal's error first: a run cut short by it (PyController::Interrupted) is no failure
    py::dict partial;
    describe_sweep(partial, s, runs);
    partial["columns"] = sweep_columns(s, std::move(rows));
    if (signal) {
      attach(signal->value(), "partial_rows", partial);
      throw std::move(*signal);
    }
    try {
      std::rethrow_exception(failure);
    } catch (py::error_already_set& e) {
      attach(e.value(), "partial_rows", partial);
      throw;
    }
  }
  py::dict out;
  describe_sweep(out, s, runs);
  out["columns"] = sweep_columns(s, std::move(rows));
  return out;
}

// A benchmark (docs/benchmark.md) into a results store, as `plumetrace benchmark` plans it: in
// C++ threads without the GIL (a Python controller takes it for each of its steps), or with a
// controller written in Python and `processes`, in worker processes (python_runner); then, for a
// whole campaign, the manifest and the exports. Ctrl-C (a raising signal handler) stops it
// between runs and is raised here; every run finished is in the store, and calling again
// computes only what is missing. `python_files` maps a controller written in Python to its file;
// `progress` (None for none) is called with (runs done, runs to do, seconds) every 0.25 s.
py::dict benchmark(const std::string& suite_path, const std::vector<std::string>& controllers,
                   bool only, const std::vector<std::string>& tasks, int runs,
                   const py::list& overrides, int threads, bool share_plumes,
                   const std::string& out_option, const std::string& store_option, bool fresh,
                   const std::string& shard_option,
                   const std::map<std::string, std::string>& python_files, bool processes,
                   py::object progress) {
  if (runs < 0) throw pt::ConfigError("runs: must be >= 0 (0: the suite's)");
  if (threads < 0 || threads > pt::kMaxThreads) {
    throw pt::ConfigError("threads: must be 0 (all cores) to " + std::to_string(pt::kMaxThreads));
  }
  pt::BenchmarkChoice choice;
  choice.controllers = controllers;
  choice.only = only;
  choice.tasks = tasks;
  choice.runs = runs;
  choice.overrides = settings_of(std::nullopt, overrides);
  const pt::BenchmarkPlan plan = pt::plan_benchmark(pt::read_suite_file(suite_path), choice);
  const pt::Shard shard = shard_option.empty() ? pt::Shard{} : pt::parse_shard(shard_option);
  pt::check_campaign(plan.sweeps, 0);
  const std::string out =
      out_option.empty() ? pt::default_output_folder(plan.suite.name, suite_path) : out_option;
  const std::string store_path =
      store_option.empty() ? pt::default_store_path(out, shard) : store_option;
  if (shard.count <= 1) pt::make_output_folder(out, out_option.empty() ? "out/NAME" : "out");
  const auto folder = std::filesystem::path(store_path).parent_path();
  if (!folder.empty()) pt::make_output_folder(folder.string(), "the folder of store", false);
  pt::Store store(store_path, plan.sweeps, pt::version(), fresh);
  SignalWatch watch;
  watch.report = std::move(progress);
  pt::CampaignOptions options;
  options.threads = threads;
  options.share_plumes = share_plumes;
  options.stop = &watch.stop;
  options.on_progress = watch.on_progress();
  pt::CampaignResult result;
  std::exception_ptr failure;
  {
    const RegistryReader reading;
    py::gil_scoped_release release;
    try {
      result = pt::run_campaign(plan.sweeps, store, 0, options, shard,
                                python_runner(plan.sweeps, false, threads, processes));
    } catch (...) {
      failure = std::current_exception();
    }
  }
  if (watch.signal) throw std::move(*watch.signal);
  if (failure) std::rethrow_exception(failure);
  py::dict d;
  d["out"] = out;
  d["store"] = store_path;
  d["suite"] = plan.suite.name;
  d["version"] = plan.suite.version;
  d["digest"] = plan.digest;
  d["total"] = result.total;
  d["computed"] = result.computed;
  d["skipped"] = result.skipped;
  d["elapsed"] = result.elapsed;
  d["shard"] = pt::shard_text(shard);
  if (shard.count <= 1) {
    pt::write_text_file(out + "/benchmark.json", pt::benchmark_manifest(plan, python_files));
    pt::write_exports(out, plan.sweeps, store.rows(), 0);
  }
  return d;
}

// the values of a result field over a sweep's rows, by the field's type: outcome names, flags
// (as bytes, made bool at the end), reals, whole numbers
template <class T>
using ColumnOf = std::conditional_t<
    std::is_same_v<T, pt::Outcome>, py::list,
    std::conditional_t<std::is_same_v<T, bool>, std::vector<std::uint8_t>,
                       std::conditional_t<std::is_floating_point_v<T>, std::vector<double>,
                                          std::vector<std::int64_t>>>>;
using FieldColumn = std::variant<py::list, std::vector<std::uint8_t>, std::vector<double>,
                                 std::vector<std::int64_t>>;

py::dict sweep_columns(const pt::ExpandedSweep& s, std::vector<pt::RunRow> rows) {
  std::sort(rows.begin(), rows.end(), [](const pt::RunRow& a, const pt::RunRow& b) {
    return pt::RunRow::key_of(a) < pt::RunRow::key_of(b);
  });
  // the run key's numbers (point, trial, agent; one sweep, so not its name), in key order
  std::vector<std::vector<std::int64_t>> key(pt::kRunKeyFields.size());
  std::vector<std::uint64_t> seed;
  std::vector<py::list> axis_values(s.def.axes.size());
  std::vector<FieldColumn> fields;
  const pt::RunResult none{};
  pt::RunResult::fields(none, [&](const pt::ResultField&, const auto& value) {
    fields.emplace_back(std::in_place_type<ColumnOf<std::remove_cvref_t<decltype(value)>>>);
  });
  for (const pt::RunRow& r : rows) {
    std::size_t member = 0;
    pt::RunRow::key_fields(r, [&](std::string_view, const auto& value) {
      if constexpr (!std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
        key[member].push_back(static_cast<std::int64_t>(value));
      }
      ++member;
    });
    seed.push_back(r.result.seed);
    std::size_t k = 0;
    pt::RunResult::fields(r.result, [&](const pt::ResultField&, const auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      auto& column = std::get<ColumnOf<T>>(fields[k++]);
      if constexpr (std::is_same_v<T, pt::Outcome>) {
        column.append(std::string(pt::outcome_name(value)));
      } else {
        column.push_back(value);
      }
    });
    const pt::SweepPoint& p = s.points[static_cast<std::size_t>(r.point)];
    for (std::size_t a = 0; a < axis_values.size(); ++a) {
      std::visit([&](const auto& v) { axis_values[a].append(v); }, p.values[a]);
    }
  }
  // the key's columns, the axis values after the point's
  py::dict columns;
  std::size_t member = 0;
  pt::RunRow::key_fields(pt::RunRow{}, [&](std::string_view name, const auto& value) {
    const std::size_t k = member++;
    if constexpr (!std::is_same_v<std::remove_cvref_t<decltype(value)>, std::string>) {
      columns[py::str(std::string(name))] = to_array(key[k]);
      if (name != "point") return;
      for (std::size_t a = 0; a < axis_values.size(); ++a) {
        columns[py::str(s.def.axes[a].key)] = axis_values[a];
      }
    }
  });
  columns["seed"] = to_array(seed);
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const py::str name(std::string(pt::kResultFields[k].name));
    columns[name] = std::visit(
        [](auto& values) -> py::object {
          using C = std::remove_cvref_t<decltype(values)>;
          if constexpr (std::is_same_v<C, py::list>) {
            return values;
          } else if constexpr (std::is_same_v<C, std::vector<std::uint8_t>>) {
            return to_array(values).attr("astype")("bool");
          } else {
            return to_array(values);
          }
        },
        fields[k]);
  }
  return columns;
}

// one point's statistics as a dict
py::dict point_dict(const pt::PointStats& p) {
  py::dict d;
  d["runs"] = p.runs;
  d["successes"] = p.successes;
  d["walls"] = p.walls;
  d["timeouts"] = p.timeouts;
  d["gave_up"] = p.gave_up;
  d["success_rate"] = p.success_rate;
  d["success_ci"] = py::make_tuple(p.success_ci.lo, p.success_ci.hi);
  d["overhead_mean"] = p.overhead.mean;
  d["overhead_ci"] = py::make_tuple(p.overhead.lo, p.overhead.hi);
  d["overhead_sd"] = p.overhead.stddev;
  d["overhead_n"] = p.overhead.n;
  d["mean_time"] = p.mean_time;
  d["mean_losses"] = p.mean_losses;
  return d;
}

// a calibration unknown as plumetrace.calibrate.study builds its Unknown from it
py::dict unknown_dict(const pt::CalibrationUnknown& u) {
  py::dict d;
  d["name"] = u.name;
  d["key"] = u.key;
  d["title"] = u.title;
  d["printed"] = u.printed ? py::cast(*u.printed) : py::none();
  d["choices"] = u.choices.empty() ? py::none() : py::cast(u.choices);
  d["low"] = u.choices.empty() ? py::cast(u.low) : py::none();
  d["high"] = u.choices.empty() ? py::cast(u.high) : py::none();
  d["log"] = u.log;
  d["integer"] = u.integer;
  d["changes"] = u.changes;
  py::list evidence;
  for (const pt::UnknownEvidence& e : u.evidence) {
    evidence.append(py::make_tuple(e.value, e.source, e.says));
  }
  d["evidence"] = evidence;
  return d;
}

// a calibration study file read and checked in C++ (lochmatter2008/calibration_study.hpp), as
// the dict plumetrace.calibrate.study.load_study builds its Study from
py::dict read_calibration_study(const py::handle& path) {
  const pt::CalibrationStudy s = pt::read_calibration_study(text_of(path, "study file"));
  const auto unknowns = [](const std::vector<pt::CalibrationUnknown>& list) {
    py::list out;
    for (const pt::CalibrationUnknown& u : list) out.append(unknown_dict(u));
    return out;
  };
  const auto table = [](const std::vector<std::pair<std::string, pt::ConfigValue>>& pairs) {
    py::dict out;
    for (const auto& [key, value] : pairs) out[py::str(key)] = value;
    return out;
  };
  py::dict d;
  d["name"] = s.name;
  d["unknowns_path"] = s.unknowns_file;
  d["all_unknowns"] = unknowns(s.all_unknowns);
  d["unknowns"] = unknowns(s.unknowns);
  d["sets_dir"] = s.sets_dir;
  d["sets"] = s.sets;
  d["runs"] = s.runs;
  d["seed"] = s.seed;
  d["trials"] = s.trials;
  d["threads"] = s.threads;
  d["startup_trials"] = s.startup_trials;
  d["target"] = s.target;
  d["truth"] = table(s.truth);
  d["fixed"] = table(s.fixed);
  d["validation"] = py::dict(py::arg("top") = s.validation.top, py::arg("runs") = s.validation.runs,
                             py::arg("seed") = s.validation.seed,
                             py::arg("confirm_runs") = s.validation.confirm_runs);
  return d;
}

// the experiment sets of a folder under overrides, in memory, and their claims; Ctrl-C (any
// Python signal handler that raises) stops it between runs and raises here
py::dict evaluate_sets(const std::string& sets_dir, const py::dict& overrides, int runs,
                       std::uint64_t seed, int threads, const std::vector<std::string>& sets,
                       const std::vector<int>& claim_ids) {
  pt::CalibrationOptions options;
  options.sets_dir = sets_dir;
  options.sets = sets;
  options.runs = runs;
  options.seed = seed;
  options.threads = threads;
  for (const auto& [key, value] : overrides) {
    const std::string name = text_of(py::str(key), "a config key");
    options.overrides.push_back(
        {name, config_value(name, value), false, "", pt::Layer::kCommandLine});
  }
  SignalWatch watch;
  std::unique_ptr<py::error_already_set>& signal = watch.signal;
  options.stop = &watch.stop;
  options.on_progress = watch.on_progress();
  pt::CalibrationResult result;
  {
    const RegistryReader reading;
    py::gil_scoped_release release;
    result = pt::evaluate_sets(options);
  }
  if (signal) throw std::move(*signal);
  if (result.interrupted) throw std::runtime_error("evaluate_sets: stopped before all runs");

  py::list claims;
  for (const pt::ClaimResult& c : result.claims) {
    // why: a calibration search must not see its held-out claims, so they never leave C++
    if (!claim_ids.empty() &&
        std::find(claim_ids.begin(), claim_ids.end(), c.id) == claim_ids.end()) {
      continue;
    }
    py::list parts;
    for (const pt::ClaimPart& part : c.parts) {
      py::dict pd;
      pd["text"] = part.text;
      pd["support"] = std::string(pt::verdict_name(part.support));
      pd["margin"] = part.margin;
      pd["estimate"] = part.estimate;
      pd["lo"] = part.lo;
      pd["hi"] = part.hi;
      pd["threshold"] = part.threshold;
      parts.append(pd);
    }
    py::dict cd;
    cd["id"] = c.id;
    cd["text"] = c.text;
    cd["verdict"] = std::string(pt::verdict_name(c.verdict));
    cd["margin"] = c.margin;
    cd["evidence"] = c.evidence;
    cd["parts"] = parts;
    claims.append(cd);
  }
  py::dict set_dicts;
  for (const auto& [name, st] : result.sets) {
    py::list points;
    for (const pt::PointStats& p : st.points) points.append(point_dict(p));
    py::dict sd;
    sd["algorithm"] = st.algorithm;
    sd["key"] = st.key;
    sd["values"] = st.values;
    sd["fixed_index"] = st.fixed_index;
    sd["points"] = points;
    set_dicts[py::str(name)] = sd;
  }
  py::dict out;
  out["claims"] = claims;
  out["sets"] = set_dicts;
  out["runs"] = result.runs;
  out["elapsed"] = result.elapsed;
  return out;
}

// the evidence library's values as plumetrace.evidence writes them: intervals as (lo, hi),
// tests as (verdict, margin) with verdicts "yes", "no", "unclear"

using PyInterval = std::pair<double, double>;
using PyTest = std::pair<std::string, double>;

pt::Interval interval_of(const PyInterval& i) { return {i.first, i.second}; }

PyInterval py_interval(const pt::Interval& i) { return {i.lo, i.hi}; }

PyTest py_test(const pt::evidence::Test& t) {
  return {std::string(pt::evidence::support_name(t.support)), t.margin};
}

pt::evidence::Test test_of(const PyTest& t) {
  for (const auto s :
       {pt::evidence::Support::kYes, pt::evidence::Support::kNo, pt::evidence::Support::kUnclear}) {
    if (pt::evidence::support_name(s) == t.first) return {s, t.second};
  }
  throw py::value_error("verdict '" + t.first + "': use yes, no or unclear");
}

pt::evidence::DirectionalRule rule_of(const std::string& name) {
  for (const auto r : {pt::evidence::DirectionalRule::kSingleThreshold,
                       pt::evidence::DirectionalRule::kLegacy030}) {
    if (pt::evidence::directional_rule_name(r) == name) return r;
  }
  throw py::value_error("rule '" + name + "': use single-threshold or legacy-0.3.0");
}

// a mean as (n, mean, stddev), what Welch's interval reads of it
pt::MeanCi mean_of(const std::tuple<std::int64_t, double, double>& m) {
  pt::MeanCi out;
  out.n = std::get<0>(m);
  out.mean = std::get<1>(m);
  out.stddev = std::get<2>(m);
  return out;
}

void bind_evidence(py::module_& m) {
  py::module_ ev = m.def_submodule(
      "evidence", "the evidence library (experiment/evidence.hpp); use plumetrace.evidence");
  ev.def(
      "directional",
      [](const PyInterval& effect, double m, const std::string& rule) {
        return py_test(pt::evidence::directional(interval_of(effect), m, rule_of(rule)));
      },
      py::arg("effect"), py::arg("m"), py::arg("rule"),
      "(verdict, margin): the effect above m (single-threshold) or 0 (legacy-0.3.0), or below m");
  // the tests of an interval against one number
  const auto def_test = [&ev](const char* name,
                              pt::evidence::Test (*test)(const pt::Interval&, double),
                              const char* interval, const char* number, const char* doc) {
    ev.def(
        name, [test](const PyInterval& i, double x) { return py_test(test(interval_of(i), x)); },
        py::arg(interval), py::arg(number), doc);
  };
  def_test("within", &pt::evidence::within, "effect", "margin",
           "(verdict, margin): the effect inside +-margin");
  def_test("below", &pt::evidence::below, "value", "limit",
           "(verdict, margin): the quantity below the limit");
  def_test("at_least", &pt::evidence::at_least, "value", "limit",
           "(verdict, margin): the quantity at least the limit");
  ev.def(
      "all_of",
      [](const std::vector<PyTest>& tests) {
        std::vector<pt::evidence::Test> ts;
        for (const PyTest& t : tests) ts.push_back(test_of(t));
        return py_test(pt::evidence::all_of(ts));
      },
      py::arg("tests"), "(verdict, margin) of a conjunction of (verdict, margin) tests");
  ev.def("weakest", &pt::evidence::weakest, py::arg("margins"),
         "the smallest margin; NaN when any is NaN or there is none");
  ev.def(
      "newcombe_difference",
      [](std::int64_t k1, std::int64_t n1, std::int64_t k2, std::int64_t n2) {
        return py_interval(pt::newcombe_difference(k1, n1, k2, n2));
      },
      py::arg("successes1"), py::arg("n1"), py::arg("successes2"), py::arg("n2"),
      "(lo, hi): Newcombe's 95% interval of p1 - p2");
  ev.def(
      "relative_difference",
      [](const std::tuple<std::int64_t, double, double>& a,
         const std::tuple<std::int64_t, double, double>& b,
         const std::tuple<std::int64_t, double, double>& ref) {
        return py_interval(pt::evidence::relative_difference(mean_of(a), mean_of(b), mean_of(ref)));
      },
      py::arg("a"), py::arg("b"), py::arg("ref"),
      "(lo, hi): Welch's 95% interval of (mean_a - mean_b) / mean_ref, means as (n, mean, sd)");
}

}  // namespace

// python/vector_bindings.cpp
void bind_vector(py::module_& m,
                 const std::function<pt::Scenario(const std::optional<std::string>&,
                                                  const py::list&)>& scenario_of);
// python/team_bindings.cpp
void bind_team(py::module_& m,
               const std::function<pt::Scenario(const std::optional<std::string>&,
                                                const py::list&)>& scenario_of);

PYBIND11_MODULE(_core, m) {
  m.doc() = "plumetrace C++ core (use the plumetrace package, not this module)";
  m.attr("__version__") = std::string(pt::version());
  // why: PLUMETRACE_SIMD is read at import, so that a name this machine does not run fails
  // here (ValueError, naming the variable) before any work
  pt::simd::active();

  py::register_exception<pt::ConfigError>(m, "ConfigError", PyExc_ValueError);
  py::register_exception<pt::IoError>(m, "IoError", PyExc_OSError);
  // why: registered base first, as pybind11 tries the latest registration first
  const auto store_error =
      py::register_exception<pt::StoreError>(m, "StoreError", PyExc_ValueError);
  py::register_exception<pt::StoreIoError>(m, "StoreIoError", store_error.ptr());
  m.attr("MAX_THREADS") = pt::kMaxThreads;
  // the size bound of every input file (core/files.hpp), which plumetrace._files shares
  m.attr("MAX_INPUT_BYTES") = pt::kMaxInputBytes;

  m.def(
      "resolve_json",
      [](const std::optional<std::string>& path, const py::list& overrides) {
        return pt::scenario_to_json(scenario_of(path, overrides));
      },
      "the resolved scenario as JSON");
  m.def(
      "resolve_toml",
      [](const std::optional<std::string>& path, const py::list& overrides) {
        return pt::scenario_to_toml(scenario_of(path, overrides));
      },
      "the resolved scenario as TOML");
  m.def(
      "result_fields",
      [] {
        py::list fields;
        for (const pt::ResultField& f : pt::kResultFields) {
          py::dict d;
          d["name"] = std::string(f.name);
          d["unit"] = std::string(f.unit);
          d["nullable"] = f.nullable;
          fields.append(d);
        }
        return fields;
      },
      "the per-run result fields in column order: name, SI unit (\"\" for none), nullable");
  m.def("register_controller", &register_controller, py::arg("name"), py::arg("keys"),
        py::arg("factory"),
        "registers a Python controller: its keys (dicts of plumetrace.Param._spec) and its "
        "factory f(values: dict, rng)");
  m.def(
      "renamed_key",
      [](const std::string& key) -> std::optional<std::pair<std::string, std::string>> {
        for (const pt::RenamedKey& r : pt::renamed_keys()) {
          if (r.old_key == key) {
            return std::make_pair(std::string(r.new_key), pt::renamed_key_warning(r));
          }
        }
        return std::nullopt;
      },
      "for a key renamed since the last version: (its new name, the deprecation warning); else "
      "None");
  m.def(
      "scenario_warnings",
      [](const std::optional<std::string>& path, const py::list& overrides) {
        return pt::scenario_warnings(scenario_of(path, overrides));
      },
      "why the resolved scenario is unlikely to be tracked (sim/scenario.hpp)");
  m.def("algorithms", [] {
    std::vector<std::string> names;
    for (const pt::Algorithm a : pt::all_algorithms()) names.emplace_back(pt::algorithm_name(a));
    return names;
  });
  m.def("run", &run, py::arg("path"), py::arg("overrides"), py::arg("seed"), py::arg("trial"),
        py::arg("trace"), py::arg("snapshot_interval"), py::arg("controller_factory"),
        py::arg("view") = std::nullopt);
  m.def("sweep", &sweep, py::arg("sweep"), py::arg("overrides"), py::arg("runs"),
        py::arg("threads"), py::arg("share_plumes"), py::arg("controller_factory"),
        py::arg("processes") = false);
  m.def("benchmark", &benchmark, py::arg("suite"), py::arg("controllers"), py::arg("only"),
        py::arg("tasks"), py::arg("runs"), py::arg("overrides"), py::arg("threads"),
        py::arg("share_plumes"), py::arg("out"), py::arg("store"), py::arg("fresh"),
        py::arg("shard"), py::arg("python_files"), py::arg("processes") = false,
        py::arg("progress") = py::none(),
        "a benchmark suite's runs into a results store, its manifest and exports "
        "(plumetrace.benchmark)");
  m.def("export_store", &export_sweep_store, py::arg("sweep"), py::arg("overrides"),
        py::arg("store"), py::arg("out"), py::arg("runs"),
        "the exports of a sweep's runs in a results store (as plumetrace report writes them); "
        "the points with runs missing");
  m.def("probe", &probe, py::arg("path"), py::arg("overrides"), py::arg("points"),
        py::arg("warmup"), py::arg("duration"), py::arg("interval"), py::arg("seed"),
        py::arg("centreline_x"), py::arg("slab"),
        "the plume alone sampled at points (plumetrace probe): detect fraction, mean "
        "concentration, samples, centrelines");
  m.def(
      "arena_grid",
      [](const std::optional<std::string>& path, const py::list& overrides) {
        const pt::MapGrid grid = pt::arena_grid(scenario_of(path, overrides));
        return py::make_tuple(to_array(grid.x), to_array(grid.y), grid.z);
      },
      py::arg("path"), py::arg("overrides"),
      "the detection map's cell centres x, y and height z (plumetrace probe --map)");
  m.def("read_calibration_study", &read_calibration_study, py::arg("path"),
        "a calibration study file and its unknowns file, read and checked (docs/calibration.md): "
        "a dict of the study's keys, its unknowns (dicts) and resolved paths; ConfigError naming "
        "the file and the key");
  m.attr("MAX_CALIBRATION_TRIALS") = pt::kMaxCalibrationTrials;
  m.def("evaluate_sets", &evaluate_sets, py::arg("sets_dir"), py::arg("overrides"), py::arg("runs"),
        py::arg("seed"), py::arg("threads"), py::arg("sets") = std::vector<std::string>{},
        py::arg("claims") = std::vector<int>{},
        "the experiment sets of a folder (`sets`; empty: A..I) under overrides (dict of dotted "
        "keys), in memory: "
        "runs per value (0: the files'), master seed (0: the files'); per-set statistics and "
        "the claims (ids in `claims`; empty: 1-11) with their verdicts, margins and parts");

  // the statistics of the report (docs/experiments.md)
  m.def(
      "wilson_interval",
      [](std::int64_t k, std::int64_t n) {
        const pt::Interval i = pt::wilson_interval(k, n);
        return py::make_tuple(i.lo, i.hi);
      },
      py::arg("successes"), py::arg("n"), "Wilson 95% interval of a success rate");
  m.def(
      "mean_ci",
      [](const std::vector<double>& values) {
        const pt::MeanCi c = pt::mean_ci(values);
        return py::make_tuple(c.mean, c.lo, c.hi);
      },
      py::arg("values"), "mean and its t-based 95% interval");
  m.def(
      "bootstrap_mean_interval",
      [](const std::vector<double>& values) {
        const pt::Interval i = pt::bootstrap_mean_interval(values);
        return py::make_tuple(i.lo, i.hi);
      },
      py::arg("values"),
      "percentile bootstrap 95% interval of the mean (2000 resamples, fixed seed; NaN skipped; "
      "NaN ends below two values), as plumetrace sweep's summary");
  m.def(
      "quartiles",
      [](const std::vector<double>& values) {
        const pt::Quartiles q = pt::quartiles(values);
        return py::make_tuple(q.q1, q.median, q.q3);
      },
      py::arg("values"), "lower quartile, median, upper quartile (NaN skipped; type 7)");
  bind_evidence(m);

  bind_vector(m, scenario_of);
  bind_team(m, scenario_of);

  // a run driven step by step from Python (plumetrace.env)
  py::class_<pt::World>(m, "World")
      .def(py::init([](const std::optional<std::string>& path, const py::list& overrides,
                       std::uint64_t seed, std::uint64_t trial, const py::object& reads) {
             const pt::Scenario scenario = scenario_of(path, overrides);
             const unsigned flags = reads_of(reads, "World");
             py::gil_scoped_release release;
             return std::make_unique<pt::World>(scenario, seed, trial,
                                                std::make_unique<ExternalController>(flags));
           }),
           py::arg("path"), py::arg("overrides"), py::arg("seed"), py::arg("trial"),
           py::arg("reads") = py::none(),
           "a run of agent 0 decided from outside, sensing what `reads` names (as a controller's)")
      .def(
          "observe", [](pt::World& w) { return HeldObservation(w.observe()); },
          "environment step and sensing")
      .def("act", &pt::World::act, "decision, move and check")
      .def("measure_wind_body",
           [](pt::World& w) {
             const pt::Vec2 v = w.wind_probe().measure_wind_body();
             return py::make_tuple(v.x, v.y);
           })
      .def("done", &pt::World::done)
      .def("time", &pt::World::time)
      .def("outcome", [](const pt::World& w) { return std::string(pt::outcome_name(w.outcome())); })
      .def("pose",
           [](const pt::World& w) {
             const pt::Pose& p = w.robot().pose;
             return py::make_tuple(p.x, p.y, p.heading);
           })
      .def("odometer", [](const pt::World& w) { return w.robot().odometer; })
      .def(
          "filaments",
          [](const pt::World& w) {
            // why: only puffs are drawn, as in traces; another odor model gives no filaments
            const pt::OdorSnapshot snap = w.environment().odor->snapshot();
            const bool puffs = snap.kind == pt::OdorSnapshotKind::kFilaments;
            const auto column = [&](std::span<const double> v) {
              return py::array_t<double>(static_cast<py::ssize_t>(puffs ? v.size() : 0), v.data());
            };
            const pt::FilamentSpans& f = snap.filaments;
            return py::make_tuple(column(f.x), column(f.y), column(f.w));
          },
          "the filaments' centres x, y and widths (m) now, as NumPy copies (for rendering)")
      .def("result_json", [](const pt::World& w) {
        const pt::RunResult r = w.result();
        return pt::result_to_json(r, {"external", r.seed, r.trial, r.agent});
      });

  // the controller interface (measurement.hpp): what a Python controller sees and returns
  py::class_<pt::Pose>(m, "Pose")
      .def_readonly("x", &pt::Pose::x)
      .def_readonly("y", &pt::Pose::y)
      .def_readonly("heading", &pt::Pose::heading);
  py::class_<pt::Message>(m, "Message")
      .def_readonly("from_", &pt::Message::from, "the sender's index in its team")
      .def_readonly("sent", &pt::Message::sent, "the sender's time since release when sent (s)")
      .def_property_readonly(
          "data", [](const pt::Message& msg) { return message_tuple(msg.data); },
          "the four numbers sent")
      .def("__iter__",
           [](const pt::Message& msg) {
             return py::iter(py::make_tuple(msg.from, msg.sent, message_tuple(msg.data)));
           })
      .def("__repr__", [](const pt::Message& msg) {
        return "Message(from_=" + std::to_string(msg.from) +
               ", sent=" + py::repr(py::float_(msg.sent)).cast<std::string>() +
               ", data=" + py::repr(message_tuple(msg.data)).cast<std::string>() + ")";
      });
  m.attr("READS") = [] {
    py::list names;
    for (const auto& [name, flag] : kReadNames) names.append(std::string(name));
    return py::tuple(names);
  }();
  m.def(
      "reads_flags",
      [](const py::object& reads, const std::string& who) { return reads_of(reads, who); },
      py::arg("reads"), py::arg("who"),
      "the Reads flags of a controller's `reads`; ValueError naming unknown names");
  py::class_<HeldObservation>(m, "Observation")
      .def_property_readonly("time", [](const HeldObservation& o) { return o.obs.time; })
      .def_property_readonly("odor", [](const HeldObservation& o) { return o.obs.odor; })
      .def_property_readonly("odometry", [](const HeldObservation& o) { return o.obs.odometry; })
      .def_property_readonly("odometer", [](const HeldObservation& o) { return o.obs.odometer; })
      .def_property_readonly(
          "concentration", [](const HeldObservation& o) { return o.obs.concentration; },
          "the odor sensor's reading (NaN unless the controller reads 'concentration')")
      .def_property_readonly(
          "messages",
          [](const HeldObservation& o) {
            py::tuple out(o.messages.size());
            for (std::size_t i = 0; i < o.messages.size(); ++i) out[i] = py::cast(o.messages[i]);
            return out;
          },
          "teammates' messages delivered this step, by (sent, from_) (empty unless the "
          "controller reads 'messages')");
  m.def(
      "controller_snapshot",
      [](py::object controller) {
        return snapshot_dict(PyController(std::move(controller), nullptr).snapshot());
      },
      py::arg("controller"),
      "a Python controller's snapshot() as a run takes it (checked and converted), as a dict");
  py::class_<StepWindProbe>(m, "WindProbe").def("measure_wind_body", [](StepWindProbe& w) {
    const pt::Vec2 v = w.measure_wind_body();
    return py::make_tuple(v.x, v.y);
  });
  // why: a non-finite heading or curvature is refused where the controller makes it, so that
  // the traceback points at the controller's line
  const auto finite = [](const char* what, double value) {
    if (!std::isfinite(value)) {
      throw py::value_error(std::string(what) + " must be a finite number, got " +
                            py::repr(py::float_(value)).cast<std::string>());
    }
    return value;
  };
  py::class_<pt::Command>(m, "Command")
      .def_static("stop", &pt::Command::stop)
      .def_static(
          "turn_to",
          [finite](double heading) {
            return pt::Command::turn_to(finite("Command.turn_to: heading", heading));
          },
          py::arg("heading"))
      .def_static(
          "go",
          [finite](double heading) {
            return pt::Command::go(finite("Command.go: heading", heading));
          },
          py::arg("heading"))
      .def_static(
          "curve",
          [finite](double curvature) {
            return pt::Command::curve(finite("Command.curve: curvature", curvature));
          },
          py::arg("curvature"))
      .def_static("abandon", &pt::Command::abandon)
      .def_static(
          "declare_source",
          [finite](double x, double y) {
            return pt::Command::declare_source(
                {finite("Command.declare_source: x", x), finite("Command.declare_source: y", y)});
          },
          py::arg("x"), py::arg("y"))
      .def(
          "with_message",
          [](const pt::Command& c, const py::handle& data) {
            const std::vector<double> v = finite_numbers(data, "Command.with_message: data");
            if (v.size() != pt::kMessageSize) {
              throw py::value_error("Command.with_message: data holds " + std::to_string(v.size()) +
                                    " numbers, not " + std::to_string(pt::kMessageSize));
            }
            std::array<double, pt::kMessageSize> message{};
            std::copy(v.begin(), v.end(), message.begin());
            return c.with_message(message);
          },
          py::arg("data"))
      .def_readonly("heading", &pt::Command::heading)
      .def_readonly("curvature", &pt::Command::curvature)
      .def_readonly("give_up", &pt::Command::give_up)
      .def_readonly("declare", &pt::Command::declare)
      .def_property_readonly("source",
                             [](const pt::Command& c) {
                               return c.declare ? py::object(py::make_tuple(c.source.x, c.source.y))
                                                : py::object(py::none());
                             })
      .def_readonly("send", &pt::Command::send)
      .def_property_readonly("message", [](const pt::Command& c) {
        return c.send ? py::object(message_tuple(c.message)) : py::object(py::none());
      });
  py::class_<pt::Rng>(m, "Rng")
      .def("uniform", &pt::Rng::uniform)
      .def("normal", py::overload_cast<>(&pt::Rng::normal))
      .def("sign", &pt::Rng::sign);
  m.def(
      "controller_rng",
      [](std::uint64_t seed, std::uint64_t trial) {
        return pt::Rng(pt::derive_seed(seed, trial, pt::Stream::kController));
      },
      py::arg("seed"), py::arg("trial"), "the controller random stream of run (seed, trial)");
  m.def(
      "upwind_heading",
      [](std::pair<double, double> wind_body, double robot_heading) {
        return pt::upwind_heading({wind_body.first, wind_body.second}, robot_heading);
      },
      py::arg("wind_body"), py::arg("robot_heading"));
  m.def("guess_plume_side", &pt::guess_plume_side, py::arg("surge_heading"), py::arg("upwind_now"),
        py::arg("rng"));
  m.def("wrap_angle", &pt::wrap_angle);
}
