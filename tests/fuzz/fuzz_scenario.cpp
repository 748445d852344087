// Fuzz target: a scenario file and --set overrides, read as `plumetrace run/config` reads them
// (load_scenario), then the documented round trip: the resolved scenario written as TOML reads
// back to the same scenario.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace pf = plumetrace::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const pf::TomlInput input = pf::split_toml_input(data, size);
  const auto path = pf::scratch() / "scenario.toml";
  pf::write_file(path, input.file);

  plumetrace::Scenario scenario;
  bool loaded = false;
  pf::guarded([&] {
    scenario = plumetrace::load_scenario(path.string(), pf::parse_sets(input.sets));
    loaded = true;
  });
  if (!loaded) return 0;

  // what `config` prints must read back to the same scenario, and print the same again
  const std::string toml = plumetrace::scenario_to_toml(scenario);
  const auto again_path = pf::scratch() / "resolved.toml";
  pf::write_file(again_path, toml);
  try {
    const std::string again =
        plumetrace::scenario_to_toml(plumetrace::load_scenario(again_path.string(), {}));
    if (again != toml)
      pf::finding("the resolved scenario reads back differently:\n" + toml +
                  "\n--- read back as ---\n" + again);
  } catch (const std::exception& e) {
    pf::finding(std::string("the resolved scenario does not read back: ") + e.what() + "\n" + toml);
  }
  (void)plumetrace::scenario_to_json(scenario);
  return 0;
}
