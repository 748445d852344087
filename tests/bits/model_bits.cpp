// The model's results as bits: a handful of runs (every registered algorithm in the default
// scenario, the meandering and the switching wind, the concentration sensor, a team), plumes
// stepped a while and the random generator, each printed as one line of exact hexadecimal
// doubles or of a hash of them. The suite builds it for this machine and for 64-bit ARM
// (cmake/aarch64-linux-gnu.cmake, run under qemu-user) and requires the same lines
// (tests/bits/compare.sh; docs/reliability.md, "Same bits on every machine"). It checks the
// vectorised loops against the scalar formulas too, and exits 1 when they differ.
#include <bit>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "plumetrace/agent/controllers.hpp"
#include "plumetrace/core/rng.hpp"
#include "plumetrace/env/environment.hpp"
#include "plumetrace/sim/result.hpp"
#include "plumetrace/sim/scenario.hpp"
#include "plumetrace/sim/world.hpp"
#include "support/loop_checks.hpp"

namespace plumetrace {
namespace {

constexpr std::uint64_t kSeed = 2008;

// FNV-1a over the bits of doubles and integers: a run's whole path in 16 hex digits
struct Hash {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void add(std::uint64_t v) {
    for (int b = 0; b < 8; ++b) {
      h ^= (v >> (8 * b)) & 0xff;
      h *= 0x100000001b3ull;
    }
  }
  void add(double v) { add(std::bit_cast<std::uint64_t>(v)); }
};

std::string hex(double v) {
  char text[24];
  std::snprintf(text, sizeof text, "%016" PRIx64, std::bit_cast<std::uint64_t>(v));
  return text;
}

std::string hex(const Hash& hash) {
  char text[24];
  std::snprintf(text, sizeof text, "%016" PRIx64, hash.h);
  return text;
}

// every field of a result: doubles as their bits, counts and outcomes as numbers
std::string result_bits(const RunResult& r) {
  std::string out;
  RunResult::fields(r, [&out](const ResultField& f, const auto& value) {
    using T = std::decay_t<decltype(value)>;
    out += ' ';
    out += f.name;
    out += '=';
    if constexpr (std::is_same_v<T, double>) {
      out += hex(value);
    } else if constexpr (std::is_same_v<T, Outcome>) {
      out += outcome_name(value);
    } else {
      out += std::to_string(value);
    }
  });
  return out;
}

Scenario scenario_of(const std::vector<std::string>& overrides) {
  std::vector<Setting> settings;
  for (const std::string& o : overrides) settings.push_back(parse_override(o));
  return build_scenario(settings);
}

// runs at (kSeed, trial) of scenarios that share one environment, stepped together in one World
// (each run is then the one it is alone: World's contract, tested by the world and team tests):
// every robot's result, and a hash of every robot's pose and odometer at every step
void print_runs(const std::vector<std::pair<std::string, std::vector<std::string>>>& runs,
                std::uint64_t trial = 0) {
  std::vector<Scenario> scenarios;
  for (const auto& run : runs) scenarios.push_back(scenario_of(run.second));
  std::vector<const Scenario*> group;
  for (const Scenario& s : scenarios) group.push_back(&s);
  World world(group, kSeed, trial);
  std::vector<Hash> paths(world.agent_count());
  while (!world.done()) {
    world.step();
    for (std::size_t i = 0; i < world.agent_count(); ++i) {
      const RobotState& r = world.agent(i).robot();
      paths[i].add(r.pose.x);
      paths[i].add(r.pose.y);
      paths[i].add(r.pose.heading);
      paths[i].add(r.odometer);
    }
  }
  const std::vector<RunResult> results = world.results();
  for (std::size_t t = 0; t < runs.size(); ++t) {
    for (std::size_t i = world.teams()[t]; i < world.teams()[t + 1]; ++i) {
      const std::size_t robot = i - world.teams()[t];
      std::printf("run %s robot %zu path=%s%s\n", runs[t].first.c_str(), robot,
                  hex(paths[i]).c_str(), result_bits(results[i]).c_str());
    }
  }
}

// a scenario's environment stepped `steps` times after its warm-up: the hash of every
// filament (centre and width), and the concentration and the wind at points downwind
void print_plume(const std::string& name, const std::vector<std::string>& overrides, int steps) {
  const Scenario s = scenario_of(overrides);
  Environment env = make_environment(s, kSeed, 1);
  warm_up(s, env);
  for (int k = 0; k < steps; ++k) step(env, s.sim.dt);
  Hash filaments;
  const OdorSnapshot snap = env.odor->snapshot();
  for (const auto& column :
       {snap.filaments.x, snap.filaments.y, snap.filaments.z, snap.filaments.w}) {
    for (const double v : column) filaments.add(v);
  }
  std::printf("plume %s filaments=%zu hash=%s\n", name.c_str(), snap.filaments.size(),
              hex(filaments).c_str());
  std::string c, w;
  for (const double x : {1.5, 4.0, 8.0, 14.5}) {
    for (const double y : {-0.3, 0.0, 0.2}) {
      const Vec3 p{x, y, s.odor.height};
      c += ' ' + hex(env.odor->concentration(p));
      const Vec3 v = env.wind->velocity(p);
      w += ' ' + hex(v.x) + ',' + hex(v.y);
    }
  }
  std::printf("plume %s concentration%s\n", name.c_str(), c.c_str());
  std::printf("plume %s wind%s\n", name.c_str(), w.c_str());
}

// the generator's draws: raw, uniform, normal (its tables come from exp and log)
void print_rng() {
  Rng rng(kSeed);
  Hash raw, uniform, normal;
  for (int k = 0; k < 100000; ++k) {
    raw.add(rng.next_u64());
    uniform.add(rng.uniform_open0());
    normal.add(rng.normal());
  }
  std::printf("rng raw=%s uniform=%s normal=%s\n", hex(raw).c_str(), hex(uniform).c_str(),
              hex(normal).c_str());
}

}  // namespace
}  // namespace plumetrace

int main(int argc, char** argv) {
  using namespace plumetrace;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // a line at a time, for a slow emulator's watcher
  if (argc > 1) {
    std::fprintf(stderr, "model_bits: unknown option '%s' (it takes none)\n", argv[1]);
    return 2;
  }
  // the vectorised loops of this build (SSE2 to AVX-512 on x86-64, NEON on ARM) against the
  // scalar formulas
  std::string paths;
  for (const std::string& mismatch :
       {testing::plume_loops_mismatch(&paths), testing::wind_advect_mismatch()}) {
    if (!mismatch.empty()) {
      std::fprintf(stderr, "model_bits: a vectorised loop differs from the scalar formulas: %s\n",
                   mismatch.c_str());
      return 1;
    }
  }
  std::printf("loops: the scalar formulas' bits\n");
  // why: on stderr, so that the lines compared are the same on every machine
  std::fprintf(stderr, "model_bits: plume loop paths compared:%s\n", paths.c_str());

  print_rng();
  print_plume("default", {}, 200);
  print_plume("meander", {"wind.model=meander"}, 200);
  print_plume("switching",
              {"wind.model=switching", "switching.first=-5", "switching.transition=2",
               "switching.draw=uniform"},
              200);
  print_plume("farrell", {"plume.dispersion=farrell", "plume.kernel=gaussian"}, 200);

  // every registered algorithm in the default scenario, nearer the source and briefly, the
  // first-order sensor and a team, on one plume
  const std::vector<std::string> near = {"robot.start_x=5.0", "supervisor.timeout=30.0"};
  std::vector<std::pair<std::string, std::vector<std::string>>> runs;
  for (const Algorithm a : all_algorithms()) {
    std::vector<std::string> o = near;
    o.push_back("controller.algorithm=" + std::string(algorithm_name(a)));
    runs.emplace_back(std::string(algorithm_name(a)), o);
  }
  runs.push_back({"first-order-chemotaxis",
                  {"odor.model=first-order", "first_order.noise=20", "robot.start_x=5.0",
                   "supervisor.timeout=30.0", "controller.algorithm=chemotaxis"}});
  runs.push_back({"team-hayes",
                  {"team.count=3", "robot.start_x=6.0", "supervisor.timeout=30.0",
                   "controller.algorithm=hayes", "hayes.declare_hits=3"}});
  print_runs(runs);
  print_runs({{"meander-surge-spiral",
               {"wind.model=meander", "robot.start_x=6.0", "supervisor.timeout=40.0",
                "controller.algorithm=surge-spiral"}},
              {"meander-casting",
               {"wind.model=meander", "robot.start_x=6.0", "supervisor.timeout=40.0",
                "controller.algorithm=casting"}}});
  print_runs({{"switching-casting",
               {"wind.model=switching", "switching.first=5", "switching.timing=random",
                "switching.count=3", "switching.draw=normal", "robot.start_x=6.0",
                "supervisor.timeout=40.0", "controller.algorithm=casting"}}},
             1);
  return 0;
}
