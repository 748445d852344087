// A program of one's own, built against an installed plumetrace (examples/out_of_tree/
// CMakeLists.txt): runs a scenario file (or the default scenario) with the seed and trial given,
// and prints the result as `plumetrace run --json` does.
//
// Usage: app [scenario.toml [seed [trial]]]
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/sim/world.hpp"

namespace pt = plumetrace;

int main(int argc, char** argv) {
  try {
    const pt::Scenario scenario = argc > 1 ? pt::load_scenario(argv[1], {}) : pt::Scenario{};
    const std::uint64_t seed = argc > 2 ? std::stoull(argv[2]) : 1;
    const std::uint64_t trial = argc > 3 ? std::stoull(argv[3]) : 0;
    const pt::RunResult result = pt::run_once(scenario, seed, trial);
    const pt::RunInfo info{std::string(pt::algorithm_name(scenario.controller.algorithm)), seed,
                           trial};
    std::printf("%s\n", pt::result_to_json(result, info).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "app: %s\n", e.what());
    return 2;
  }
  return 0;
}
