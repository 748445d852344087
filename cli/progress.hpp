#pragma once

#include <atomic>
#include <string>

#include "plumetrace/experiment/sweep.hpp"

namespace plumetrace::cli {

/// Set by SIGINT/SIGTERM: stop dispatching runs, store what is finished, exit.
extern std::atomic<bool> g_stop;

/// Installs the SIGINT/SIGTERM handlers that set g_stop (a second signal kills at once).
void install_stop_handlers();

/// A one-line progress bar on stderr: runs done, rate and ETA. Prints nothing when `enabled`
/// is false (off a terminal, or --quiet).
class ProgressBar {
 public:
  /// `label` prefixes the line (e.g. the campaign name).
  ProgressBar(std::string label, bool enabled) : label_(std::move(label)), enabled_(enabled) {}
  /// Redraws the line.
  void update(const Progress& p);
  /// Ends the line.
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
};

/// True when stderr is a terminal.
bool stderr_is_terminal();

}  // namespace plumetrace::cli
