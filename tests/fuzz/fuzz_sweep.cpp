// Fuzz target: a sweep file and --set overrides, read and expanded as `plumetrace sweep` and
// `export` do (read_sweep_file, expand_sweep, campaign_definition).
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_support.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"

namespace pf = plumetrace::fuzz;

namespace {

// why: the harness's own cap, so that an input cannot ask for a grid that takes minutes to
// expand; it is below any cap the library sets (F10), so it hides no finding of the parser
constexpr std::size_t kMaxPoints = 64;

// the folder the sweep file is written to: as deep below a copy of scenarios/ as the study's
// sets, so that their `scenario = "../../../scenarios/lochmatter2008.toml"` resolves as in the
// repository; the golden sweep's and radius.toml's "../../scenarios/..." find a second copy
std::filesystem::path sweep_folder() {
  static const std::filesystem::path folder = [] {
    const auto root = pf::scratch();
    const auto sets = root / "studies" / "lochmatter2008" / "sets";
    std::filesystem::create_directories(sets);
    for (const auto& scenarios : {root / "scenarios", root / "studies" / "scenarios"}) {
      std::filesystem::create_directories(scenarios);
      for (const char* name : {"lochmatter2008.toml", "paper-literal.toml"}) {
        std::filesystem::copy_file(
            std::filesystem::path(PLUMETRACE_SOURCE_DIR) / "scenarios" / name, scenarios / name,
            std::filesystem::copy_options::overwrite_existing);
      }
    }
    return sets;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const pf::TomlInput input = pf::split_toml_input(data, size);
  const auto path = sweep_folder() / "sweep.toml";
  pf::write_file(path, input.file);

  pf::guarded([&] {
    const plumetrace::SweepDef def = plumetrace::read_sweep_file(path.string());
    std::size_t points = 1;
    for (const auto& axis : def.axes) {
      if (axis.values.empty()) pf::finding("read_sweep_file accepted an empty axis " + axis.key);
      if (axis.values.size() > kMaxPoints / points) return;
      points *= axis.values.size();
    }
    const plumetrace::ExpandedSweep sweep =
        plumetrace::expand_sweep(def, pf::parse_sets(input.sets));
    if (sweep.points.size() != points) {
      pf::finding("expand_sweep made " + std::to_string(sweep.points.size()) + " points of a " +
                  std::to_string(points) + "-point grid");
    }
    (void)plumetrace::campaign_definition({sweep});
  });
  return 0;
}
