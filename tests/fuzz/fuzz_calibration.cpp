// Fuzz target: a calibration study file, and optionally its unknowns file, read and checked as
// `python3 -m plumetrace.calibrate` reads them (read_calibration_study).
//
// Input: the study file's text; a line "#--unknowns" may follow, then the unknowns file's text
// (without it, the repository's studies/lochmatter2008/unknowns.toml). The study file is
// studies/lochmatter2008/calibration.toml in a copy of the repository's study folder, so that
// `unknowns = "unknowns.toml"` and `sets_dir = "sets"` find what they find there.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <variant>

#include "fuzz_support.hpp"
#include "lochmatter2008/calibration_study.hpp"
#include "plumetrace/experiment/sweep.hpp"

namespace fs = std::filesystem;
namespace pf = plumetrace::fuzz;

namespace {

// the separator line of the input (a TOML comment, so a study file alone is one TOML file)
constexpr std::string_view kUnknownsMarker = "\n#--unknowns\n";

// a copy of the study folder (its study.toml, unknowns file and sets) and of scenarios/, laid
// out as in the repository; returns the study folder
fs::path study_folder() {
  static const fs::path folder = [] {
    const fs::path source(PLUMETRACE_SOURCE_DIR);
    const fs::path root = pf::scratch();
    const fs::path study = root / "studies" / "lochmatter2008";
    fs::create_directories(root / "scenarios");
    for (const char* name : {"lochmatter2008.toml", "paper-literal.toml"}) {
      fs::copy_file(source / "scenarios" / name, root / "scenarios" / name);
    }
    fs::create_directories(study);
    fs::copy(source / "studies" / "lochmatter2008" / "sets", study / "sets");
    fs::copy_file(source / "studies" / "lochmatter2008" / "study.toml", study / "study.toml");
    return study;
  }();
  return folder;
}

const std::string& shipped_unknowns() {
  static const std::string text = pf::read_file(fs::path(PLUMETRACE_SOURCE_DIR) / "studies" /
                                                "lochmatter2008" / "unknowns.toml");
  return text;
}

// what a study the reader accepted must satisfy (docs/calibration.md)
void check(const plumetrace::CalibrationStudy& s) {
  using plumetrace::fuzz::finding;
  if (s.unknowns.empty()) finding("a study with no searched unknown");
  if (s.sets.empty()) finding("a study with no set");
  if (s.runs < 1 || s.runs > plumetrace::kMaxCampaignRuns) finding("runs out of range");
  if (s.validation.runs < 1 || s.validation.runs > plumetrace::kMaxCampaignRuns) {
    finding("validation.runs out of range");
  }
  if (s.threads < 0 || s.threads > plumetrace::kMaxThreads) finding("threads out of range");
  if (s.trials < 1 || s.trials > plumetrace::kMaxCalibrationTrials) finding("trials out of range");
  if (s.validation.seed == s.seed) finding("validation.seed equals seed");
  const auto number = [](const plumetrace::ConfigValue& v) -> double {
    if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
    if (const auto* d = std::get_if<double>(&v)) return *d;
    finding("a range bound that is not a number");
  };
  for (const auto& u : s.unknowns) {
    if (u.choices.empty() && !(number(u.low) < number(u.high))) {
      finding("unknown " + u.name + ": an empty range");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  const auto marker = all.find(kUnknownsMarker);
  const fs::path folder = study_folder();

  // the unknowns file: written only when it changes (most inputs keep the repository's)
  static std::string unknowns_now;
  static bool written = false;
  const std::string unknowns = marker == std::string_view::npos
                                   ? shipped_unknowns()
                                   : std::string(all.substr(marker + kUnknownsMarker.size()));
  if (!written || unknowns != unknowns_now) {
    pf::write_file(folder / "unknowns.toml", unknowns);
    unknowns_now = unknowns;
    written = true;
  }
  const fs::path study = folder / "calibration.toml";
  pf::write_file(study, all.substr(0, marker));

  pf::guarded([&] { check(plumetrace::read_calibration_study(study.string())); });
  return 0;
}
