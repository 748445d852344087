#pragma once

// What the fuzz targets share: a scratch folder per process, the input format of the TOML
// targets, and the rule that the library's documented errors are valid outcomes while anything
// else (another exception, a sanitizer report, a crash, a hang) is a finding.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <typeinfo>
#include <vector>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/experiment/store.hpp"
#include "plumetrace/io/results_io.hpp"
#include "plumetrace/io/scenario_io.hpp"
#include "plumetrace/io/sweep_file.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "plumetrace/sim/scenario.hpp"

namespace plumetrace::fuzz {

/// A folder of this process's own under $TMPDIR (scripts/fuzz.sh points TMPDIR into the fuzz
/// build, so what a crashed process leaves is cleared with it); removed at a normal exit.
class ScratchDir {
 public:
  ScratchDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/plumetrace-fuzz-XXXXXX";
    if (!mkdtemp(pattern.data())) {
      std::perror("plumetrace fuzz: cannot make a scratch folder");
      std::abort();
    }
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The scratch folder of this process, made on first use.
inline const std::filesystem::path& scratch() {
  static const ScratchDir dir;
  return dir.path();
}

/// Writes `text` to `path`, replacing it; aborts when it cannot (the harness's own failure).
inline void write_file(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "plumetrace fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

/// The whole text of a file.
inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The separator line of the TOML targets' inputs (a TOML comment, so a file without it is
/// still one TOML file).
inline constexpr std::string_view kSetMarker = "\n#--set\n";

/// An input of the TOML targets: a file's text, then, after a line "#--set", one --set
/// override (key.path=value) per line.
struct TomlInput {
  std::string file;               ///< the file's text
  std::vector<std::string> sets;  ///< --set arguments, as typed
};

/// Splits a fuzz input into the file and its --set lines.
inline TomlInput split_toml_input(const std::uint8_t* data, std::size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  const auto marker = all.find(kSetMarker);
  TomlInput input{std::string(all.substr(0, marker)), {}};
  if (marker == std::string_view::npos) return input;
  std::string_view rest = all.substr(marker + kSetMarker.size());
  while (!rest.empty()) {
    const auto eol = rest.find('\n');
    input.sets.emplace_back(rest.substr(0, eol));
    rest = eol == std::string_view::npos ? std::string_view{} : rest.substr(eol + 1);
  }
  return input;
}

/// --set arguments parsed as the command line does.
inline std::vector<Setting> parse_sets(const std::vector<std::string>& sets) {
  std::vector<Setting> out;
  for (const auto& s : sets) out.push_back(parse_override(s));
  return out;
}

/// Stops the process as a finding, with a message libFuzzer prints beside the input.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "plumetrace fuzz: FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// Whether a standard exception is a known finding to look past: its what() is one of the
/// comma-separated texts in $PLUMETRACE_FUZZ_TOLERATE (e.g. "stoull,stoi"). For long campaigns
/// only, so that a known finding does not stop every run; never set in CI.
inline bool tolerated(const std::exception& e) {
  static const std::vector<std::string> texts = [] {
    std::vector<std::string> out;
    const char* env = std::getenv("PLUMETRACE_FUZZ_TOLERATE");
    std::string_view rest = env ? env : "";
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      if (comma != 0) out.emplace_back(rest.substr(0, comma));
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
    return out;
  }();
  for (const auto& t : texts) {
    if (t == e.what()) return true;
  }
  return false;
}

/// Runs `body`: a ConfigError, StoreError or IoError (bad input, named) is a valid outcome;
/// any other exception is a finding.
template <class Body>
void guarded(Body&& body) {
  try {
    body();
  } catch (const ConfigError&) {
  } catch (const StoreError&) {
  } catch (const IoError&) {
  } catch (const std::exception& e) {
    if (tolerated(e)) return;
    finding(std::string("uncaught ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("uncaught exception of a type not derived from std::exception");
  }
}

}  // namespace plumetrace::fuzz
