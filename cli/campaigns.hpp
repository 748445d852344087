#pragma once

#include <CLI/CLI.hpp>
#include <exception>
#include <string>
#include <vector>

#include "plumetrace/distributed/distributed.hpp"

namespace plumetrace::cli {

/// `plumetrace sweep SWEEP.toml ...`
struct SweepCommand {
  std::string file;
  int runs = 0;
  int threads = 0;
  std::string store;
  std::string out;
  std::vector<std::string> sets;
  bool quiet = false;
  bool fresh = false;
  bool no_share = false;
  std::string shard;
};

/// Registers `sweep` on the app.
CLI::App* add_sweep_command(CLI::App& app, SweepCommand& cmd);
/// Runs it on every rank of `ranks` (one process: as always); returns the exit code.
int run_sweep_command(const SweepCommand& cmd, Ranks& ranks);

/// `plumetrace export STORE ...`
struct ExportCommand {
  std::vector<std::string> sweep_files;
  std::string store;
  std::string out;
  int runs = 0;
  std::vector<std::string> sets;
};

/// Registers `export` on the app.
CLI::App* add_export_command(CLI::App& app, ExportCommand& cmd);
/// Runs it; returns the exit code.
int run_export_command(const ExportCommand& cmd);

/// `plumetrace merge PART... --store OUT`
struct MergeCommand {
  std::vector<std::string> parts;
  std::string store;
};

/// Registers `merge` on the app.
CLI::App* add_merge_command(CLI::App& app, MergeCommand& cmd);
/// Runs it; returns the exit code.
int run_merge_command(const MergeCommand& cmd);

/// Flags shared by `reproduce` and `sensitivity`.
struct CampaignFlags {
  int threads = 0;
  std::string out = "out";
  std::string experiments;
  bool quiet = false;
  bool fresh = false;
  bool no_share = false;

  /// Registers the flags on a subcommand.
  void add_to(CLI::App& sub);
};

/// `plumetrace reproduce ...`
struct ReproduceCommand {
  std::string preset = "default";
  std::string presets;
  int runs = 0;
  CampaignFlags flags;
  std::string command_line;
};

/// Registers `reproduce` on the app.
CLI::App* add_reproduce_command(CLI::App& app, ReproduceCommand& cmd);
/// Runs it; returns the exit code.
int run_reproduce_command(const ReproduceCommand& cmd);

/// `plumetrace sensitivity ...`
struct SensitivityCommand {
  int runs = 10;
  CampaignFlags flags;
};

/// Registers `sensitivity` on the app.
CLI::App* add_sensitivity_command(CLI::App& app, SensitivityCommand& cmd);
/// Runs it; returns the exit code.
int run_sensitivity_command(const SensitivityCommand& cmd);

/// Exit codes shared by every command.
inline constexpr int kBadInput = 2;
inline constexpr int kIoFailure = 3;
inline constexpr int kInterrupted = 130;
/// Out of memory: a failure of the machine, not of the input (input that asks for more memory
/// than any machine has is refused before anything is allocated, with kBadInput).
inline constexpr int kOutOfMemory = kIoFailure;
/// An exception nothing expected: a bug (never kBadInput or kIoFailure, never an abort).
inline constexpr int kInternalError = 1;

/// The exit code for an error: kBadInput for bad input (ConfigError, StoreError), kIoFailure
/// for I/O (IoError, StoreIoError, filesystem errors), kOutOfMemory for std::bad_alloc,
/// kInternalError for anything else.
int exit_code(const std::exception_ptr& error);

/// Prints "plumetrace: error: " + `prefix` + the error's message on stderr; returns exit_code.
int report_error(const std::exception_ptr& error, const std::string& prefix = "");

}  // namespace plumetrace::cli
