#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "plumetrace/agent/controller.hpp"
#include "plumetrace/agent/controllers/casting.hpp"
#include "plumetrace/agent/controllers/chemotaxis.hpp"
#include "plumetrace/agent/controllers/hayes.hpp"
#include "plumetrace/agent/controllers/infotaxis.hpp"
#include "plumetrace/agent/controllers/particle_filter.hpp"
#include "plumetrace/agent/controllers/random_walks.hpp"
#include "plumetrace/agent/controllers/surge_cast.hpp"
#include "plumetrace/agent/controllers/surge_spiral.hpp"
#include "plumetrace/core/registry.hpp"

namespace plumetrace {

/// What a controller's registration carries besides its factory (Registry::Entry::hooks); each
/// may be empty. controller_hooks<Model, Params>() fills them from the model's static members.
struct ControllerHooks {
  /// Refuses params (an AnyParams holding the model's params struct) with which the controller
  /// cannot run, throwing ConfigError naming the keys: relations between its keys that their
  /// own ranges cannot say. Empty: every combination of the keys within their ranges runs.
  void (*check)(const AnyParams& params) = nullptr;
};

/// The controllers' hooks (core/registry.hpp).
template <>
struct RegistryHooks<Controller> {
  using type = ControllerHooks;  ///< the controllers'
};

/// The hooks of controller Model with params struct Params: `check` from Model's static
/// `check(const Params&)` where it has one, else empty.
template <class Model, class Params>
ControllerHooks controller_hooks() {
  ControllerHooks hooks;
  if constexpr (requires(const Params& p) { Model::check(p); }) {
    hooks.check = [](const AnyParams& p) { Model::check(p.get<Params>()); };
  }
  return hooks;
}

/// Every controller a config can choose: a model type and its params struct, made with the run's
/// controller stream (core/registry.hpp).
using ControllerRegistry = Registry<Controller, Rng>;

/// The controllers: the built-in algorithms, then those registered from outside the library.
/// Add to it only before the first run starts, as static registrars do (runs read it from many
/// threads); a name must not be that of a scenario table ("robot", "controller", ...).
ControllerRegistry& controller_registry();

/// Registers a controller from outside the library: one line at namespace scope in a source of
/// the program (examples/zigzag/zigzag.cpp),
///   const plumetrace::RegisterController<Zigzag, ZigzagParams> kZigzag("zigzag");
/// `Model` is made as Model(const Params&, Rng). The name becomes a value of
/// controller.algorithm, and the keys of Params::fields config keys in the table of that name
/// ("zigzag.leg"): in files, --set, sweeps, `plumetrace config` and every resolved scenario of
/// that program. Throws std::invalid_argument when the name is taken.
template <class Model, class Params>
struct RegisterController {
  /// Adds Model to controller_registry() under `name`.
  explicit RegisterController(std::string name)
      : index(controller_registry().add<Model, Params>(std::move(name),
                                                       controller_hooks<Model, Params>())) {}
  /// Its place in controller_registry().
  std::size_t index;
};

/// An algorithm: its place in controller_registry(). The built-ins are named here, in the order
/// they are registered; a controller registered from outside the library comes after them.
enum class Algorithm : int {
  kCasting,
  kSurgeSpiral,
  kSurgeCast,
  kInfotaxis,
  kParticleFilter,
  kChemotaxis,
  kCrw,
  kLevy,
  kHayes,
};

/// Which algorithm runs, and the parameters of each.
struct ControllerParams {
  /// Algorithm driving the robot.
  Algorithm algorithm = Algorithm::kCasting;
  /// The params of every registered controller; each its defaults until written.
  FamilyParams<ControllerRegistry> params;

  /// The params struct P (CastingParams, ...) of its controller.
  template <class P>
  P& get() {
    return params.get<P>(controller_registry());
  }
  /// The params struct P (CastingParams, ...) of its controller.
  template <class P>
  const P& get() const {
    return params.get<P>(controller_registry());
  }

  /// The config keys: "algorithm", then the table of every registered controller with its keys.
  void fields(FieldVisitor& v);
  /// Reads the config keys without writing.
  void read_fields(FieldReader& v) const;
};

/// Name of an algorithm as written in configs and on the command line.
std::string_view algorithm_name(Algorithm algorithm);

/// Every registered algorithm, in registry order.
std::vector<Algorithm> all_algorithms();

/// The paper's three algorithms, built into the library: casting, surge-spiral, surge-cast.
/// What holds for them alone (their loss rule, their wind sampling) is checked on these, not on
/// every registered controller.
std::vector<Algorithm> builtin_algorithms();

/// The baselines of the field built into the library after the paper's three (infotaxis, the
/// particle filter, chemotaxis, the random walks, Hayes' team spiral: docs/algorithms.md), in
/// registry order. Their tables are in a run's stored config only when a robot runs them, as
/// for a controller registered outside the library.
std::vector<Algorithm> baseline_algorithms();

/// Every algorithm built into the library: builtin_algorithms(), then baseline_algorithms().
std::vector<Algorithm> library_algorithms();

/// Refuses the selected algorithm's params when its check (ControllerHooks::check) does;
/// throws ConfigError naming the keys.
void check_controller(const ControllerParams& params);

/// Builds the controller of the selected algorithm with its random stream.
std::unique_ptr<Controller> make_controller(const ControllerParams& params, Rng rng);

}  // namespace plumetrace
