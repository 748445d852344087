// Fuzz target: a results store (the input is the SQLite file), read as `plumetrace export` reads
// it (read_campaign_rows: the store checked and its runs found by the sweep's points, then
// runs.csv, summary.csv and results.json written), and described as `merge` and `sweep --store`
// describe it (read_store_info). The sweep is tests/fuzz/store_sweep.toml, of which the seed stores
// are made.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"

namespace pf = plumetrace::fuzz;

namespace {

struct Campaign {
  std::vector<plumetrace::ExpandedSweep> sweeps;
};

const Campaign& campaign() {
  static const Campaign c = [] {
    Campaign out;
    const auto file = std::filesystem::path(PLUMETRACE_SOURCE_DIR) / "tests/fuzz/store_sweep.toml";
    out.sweeps.push_back(plumetrace::expand_sweep(plumetrace::read_sweep_file(file.string()), {}));
    return out;
  }();
  return c;
}

// the store and every file SQLite may have made beside it (a mutated header can ask for WAL)
void remove_store(const std::filesystem::path& store) {
  std::error_code ec;
  for (const char* suffix : {"", "-journal", "-wal", "-shm"}) {
    std::filesystem::remove(store.string() + suffix, ec);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Campaign& c = campaign();
  const auto store = pf::scratch() / "results.sqlite";
  const auto out = pf::scratch() / "export";
  remove_store(store);
  pf::write_file(store, std::string_view(reinterpret_cast<const char*>(data), size));

  pf::guarded([&] {
    // export refuses a store of another campaign (StoreError) before it writes anything
    const auto rows = plumetrace::read_campaign_rows(store.string(), c.sweeps);
    std::filesystem::create_directories(out);
    plumetrace::write_runs_csv((out / "runs.csv").string(), c.sweeps, rows);
    plumetrace::write_summary_csv((out / "summary.csv").string(), c.sweeps, rows, 0);
    plumetrace::write_results_json((out / "results.json").string(), c.sweeps, rows, 0);
  });
  pf::guarded([&] { (void)plumetrace::read_store_info(store.string()); });
  remove_store(store);
  return 0;
}
