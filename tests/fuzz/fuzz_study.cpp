// Fuzz target: a study folder's study.toml, read and checked as `plumetrace study` does
// (read_study_file, its sweep files, check_campaign, the outputs' folder under out/); and the
// same bytes as a benchmark suite file, read and planned as `plumetrace benchmark` does
// (read_suite_file, plan_benchmark, check_campaign, the outputs' folder).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "fuzz_support.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/campaign.hpp"
#include "plumetrace/experiment/sweep.hpp"
#include "plumetrace/io/benchmark.hpp"
#include "plumetrace/io/study_file.hpp"
#include "plumetrace/io/suite_file.hpp"
#include "plumetrace/io/sweep_file.hpp"

namespace pf = plumetrace::fuzz;
namespace fs = std::filesystem;

namespace {

// the harness's own cap on the points expanded, as in fuzz_sweep.cpp
constexpr std::size_t kMaxPoints = 64;

// a study folder with two sweep files and a report script a study.toml may name, and a file
// beside it that it must not reach
fs::path study_folder() {
  static const fs::path folder = [] {
    const fs::path root = pf::scratch() / "studies" / "fuzzed";
    fs::create_directories(root / "sets");
    const fs::path support = fs::path(PLUMETRACE_SOURCE_DIR) / "tests" / "support";
    fs::copy_file(support / "two_plumes.toml", root / "two.toml",
                  fs::copy_options::overwrite_existing);
    pf::write_file(root / "sets" / "one.toml",
                   "name = \"one\"\nruns = 2\n[[axis]]\nkey = \"sim.dt\"\nvalues = [0.032]\n");
    pf::write_file(root / "report.py", "print('report')\n");
    pf::write_file(root.parent_path() / "outside.py", "print('outside')\n");
    return root;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path folder = study_folder();
  pf::write_file(folder / "study.toml",
                 std::string_view(reinterpret_cast<const char*>(data), size));

  pf::guarded([&] {
    const plumetrace::StudyFile study = plumetrace::read_study_file(folder.string());
    // what the reader promises of an accepted study
    if (plumetrace::control_character(study.name) != std::string::npos ||
        plumetrace::control_character(study.title) != std::string::npos) {
      pf::finding("read_study_file accepted a control character in name or title");
    }
    if (study.report_is_file) {
      const fs::path report = fs::canonical(study.report);
      const fs::path inside = report.lexically_relative(fs::canonical(folder));
      if (inside.empty() || *inside.begin() == ".." || !fs::is_regular_file(report)) {
        pf::finding("read_study_file accepted a report outside the study's folder: " +
                    study.report);
      }
    } else if (!study.report.empty() && study.report.rfind("plumetrace.", 0) != 0) {
      pf::finding("read_study_file accepted a report module outside plumetrace: " + study.report);
    }
    std::vector<plumetrace::ExpandedSweep> sweeps;
    std::size_t points = 0;
    for (const auto& file : study.sets) {
      const plumetrace::SweepDef def = plumetrace::read_sweep_file(file);
      const auto count = static_cast<std::size_t>(plumetrace::grid_points(def));
      if (count > kMaxPoints - points) return;
      points += count;
      sweeps.push_back(plumetrace::expand_sweep(def, {}));
    }
    plumetrace::check_campaign(sweeps, 0);
    // the outputs' folder: out/NAME, one plain folder below out/, or refused
    const std::string out = plumetrace::default_output_folder(study.name, study.file);
    const fs::path below = fs::path(out).lexically_normal();
    if (below.parent_path() != "out" || below.filename() == ".." || below.filename() == ".") {
      pf::finding("the study's outputs would leave out/: " + out);
    }
  });

  pf::write_file(folder / "suite.toml",
                 std::string_view(reinterpret_cast<const char*>(data), size));
  pf::guarded([&] {
    const plumetrace::SuiteFile suite =
        plumetrace::read_suite_file((folder / "suite.toml").string());
    // what the reader promises of an accepted suite
    for (std::size_t i = 0; i < suite.tasks.size(); ++i) {
      for (std::size_t j = 0; j < i; ++j) {
        if (suite.tasks[i].name == suite.tasks[j].name) {
          pf::finding("read_suite_file accepted two tasks named " + suite.tasks[i].name);
        }
      }
    }
    if (suite.name.empty() || suite.version.empty() || suite.tasks.empty() ||
        suite.controllers.empty()) {
      pf::finding("read_suite_file accepted a suite without name, version, tasks or controllers");
    }
    if (suite.tasks.size() * suite.controllers.size() > kMaxPoints) return;
    const plumetrace::BenchmarkPlan plan = plumetrace::plan_benchmark(suite, {});
    plumetrace::check_campaign(plan.sweeps, 0);
    const std::string out = plumetrace::default_output_folder(suite.name, suite.file);
    const fs::path below = fs::path(out).lexically_normal();
    if (below.parent_path() != "out" || below.filename() == ".." || below.filename() == ".") {
      pf::finding("the benchmark's outputs would leave out/: " + out);
    }
  });
  return 0;
}
