// Fuzz target: a run's trace, read and drawn as `plumetrace view` does (read_trace, then the
// viewer page and the figure). The same bytes named .csv must be refused: a CSV trace carries no
// configuration, and the library has no CSV trace reader.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/view/viewer.hpp"

namespace pf = plumetrace::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto json_path = pf::scratch() / "trace.json";
  pf::write_file(json_path, text);
  pf::guarded([&] {
    const plumetrace::RecordedRun run = plumetrace::read_trace(json_path.string());
    const plumetrace::ViewerOptions options;
    (void)plumetrace::viewer_html(run, options);
    (void)plumetrace::figure_svg(run, options);
  });

  const auto csv_path = pf::scratch() / "trace.csv";
  pf::write_file(csv_path, text);
  try {
    (void)plumetrace::read_trace(csv_path.string());
    pf::finding("a .csv trace was read");
  } catch (const plumetrace::ConfigError&) {
  }
  return 0;
}
