#include "plumetrace/agent/controllers.hpp"

namespace plumetrace {

namespace {

constexpr std::string_view kAlgorithmHelp = "algorithm driving the robot";

// why: an algorithm no entry has is an error, never another algorithm's name
const ControllerRegistry::Entry& entry(Algorithm algorithm) {
  return controller_registry().at(static_cast<std::size_t>(algorithm), "algorithm");
}

// adds Model with its hooks: one line per built-in
template <class Model, class Params>
void add(ControllerRegistry& r, std::string name) {
  r.add<Model, Params>(std::move(name), controller_hooks<Model, Params>());
}

// the controllers, and how many of them the library itself registers
struct Controllers {
  ControllerRegistry registry;
  std::size_t built_in = 0;
};

Controllers& controllers() {
  // why: the built-ins are listed here, not registered from their own sources: a static library
  // leaves out the objects nothing refers to, registrars and all. One line each, in the order
  // of Algorithm; names, choices, tables and factories all come from here.
  static Controllers all = [] {
    Controllers c;
    ControllerRegistry& r = c.registry;
    add<Casting, CastingParams>(r, "casting");
    add<SurgeSpiral, SurgeSpiralParams>(r, "surge-spiral");
    add<SurgeCast, SurgeCastParams>(r, "surge-cast");
    add<Infotaxis, InfotaxisParams>(r, "infotaxis");
    add<ParticleFilter, ParticleFilterParams>(r, "particle-filter");
    add<Chemotaxis, ChemotaxisParams>(r, "chemotaxis");
    add<Crw, CrwParams>(r, "crw");
    add<Levy, LevyParams>(r, "levy");
    add<Hayes, HayesParams>(r, "hayes");
    c.built_in = r.size();
    return c;
  }();
  return all;
}

}  // namespace

ControllerRegistry& controller_registry() { return controllers().registry; }

void ControllerParams::fields(FieldVisitor& v) {
  const ControllerRegistry& registry = controller_registry();
  v("algorithm", algorithm, kAlgorithmHelp, registry.names());
  params.fields(registry, v);
}

void ControllerParams::read_fields(FieldReader& v) const {
  const ControllerRegistry& registry = controller_registry();
  // why: a FieldReader never writes through the reference
  static_cast<FieldVisitor&>(v)("algorithm", const_cast<Algorithm&>(algorithm), kAlgorithmHelp,
                                registry.names());
  params.read_fields(registry, v);
}

std::string_view algorithm_name(Algorithm algorithm) { return entry(algorithm).name; }

std::vector<Algorithm> all_algorithms() {
  std::vector<Algorithm> all;
  for (std::size_t i = 0; i < controller_registry().size(); ++i) {
    all.push_back(static_cast<Algorithm>(i));
  }
  return all;
}

std::vector<Algorithm> builtin_algorithms() {
  return {Algorithm::kCasting, Algorithm::kSurgeSpiral, Algorithm::kSurgeCast};
}

std::vector<Algorithm> baseline_algorithms() {
  // every entry the library registers after the paper's three: a new baseline needs no line here
  std::vector<Algorithm> out;
  for (std::size_t i = builtin_algorithms().size(); i < controllers().built_in; ++i) {
    out.push_back(static_cast<Algorithm>(i));
  }
  return out;
}

std::vector<Algorithm> library_algorithms() {
  std::vector<Algorithm> all = builtin_algorithms();
  const std::vector<Algorithm> baselines = baseline_algorithms();
  all.insert(all.end(), baselines.begin(), baselines.end());
  return all;
}

void check_controller(const ControllerParams& params) {
  const ControllerRegistry& registry = controller_registry();
  const ControllerRegistry::Entry& e = entry(params.algorithm);
  if (e.hooks.check != nullptr) {
    e.hooks.check(params.params.at(registry, static_cast<std::size_t>(params.algorithm)));
  }
}

std::unique_ptr<Controller> make_controller(const ControllerParams& params, Rng rng) {
  const ControllerRegistry& registry = controller_registry();
  const auto i = static_cast<std::size_t>(params.algorithm);
  return entry(params.algorithm).make(params.params.at(registry, i), rng);
}

}  // namespace plumetrace
