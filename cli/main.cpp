// The plumetrace command: registers the subcommands (cli/commands/) and runs the one asked for.
#include <CLI/CLI.hpp>
#include <csignal>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "campaign_run.hpp"
#include "cli.hpp"
#include "commands/commands.hpp"
#include "errors.hpp"
#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/core/simd.hpp"
#include "plumetrace/distributed/distributed.hpp"

namespace plumetrace::cli {

namespace {

// the command line as summary.json records it, each word quoted for a POSIX shell (issue 22,
// G20), so that it can be pasted back
std::string command_line(int argc, char** argv) {
  std::string line = "plumetrace";
  for (int i = 1; i < argc; ++i) line += " " + shell_word(argv[i]);
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  // why: past a file size limit (ulimit -f) a write then fails with EFBIG, which is reported
  // naming the file (exit 3), where SIGXFSZ would kill the process mid-write
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"plumetrace: odor plume tracking simulator and benchmark"};
  app.set_version_flag("--version", std::string(version()));
  app.require_subcommand(1);

  RunCommand run;
  ViewCommand view;
  ProbeCommand probe;
  ConfigCommand config;
  SweepCommand sweep;
  ExportCommand export_store;
  ReportCommand report;
  MergeCommand merge;
  ReproduceCommand reproduce(command_line(argc, argv));
  SensitivityCommand sensitivity;
  StudyCommand study;
  BenchmarkCommand benchmark(argc, argv);
  std::vector<std::pair<CLI::App*, Command*>> commands;
  for (Command* c :
       std::initializer_list<Command*>{&run, &view, &probe, &config, &sweep, &export_store, &report,
                                       &merge, &reproduce, &sensitivity, &study, &benchmark}) {
    commands.emplace_back(c->add(app), c);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kBadInput;
  } catch (...) {
    return report_error(std::current_exception());
  }

  // why: a PLUMETRACE_SIMD naming no path this machine runs is bad input, found before any work
  try {
    simd::active();
  } catch (const std::invalid_argument& e) {
    return report_error(std::make_exception_ptr(ConfigError(e.what())));
  }

  const Command* chosen = nullptr;
  try {
    for (const auto& [sub, command] : commands) {
      if (!*sub) continue;
      chosen = command;
      if (!command->runs_on_ranks() && launched_ranks() > 1) {
        throw ConfigError(
            "only plumetrace sweep and benchmark run across the processes of an MPI job; run this "
            "command "
            "without mpirun");
      }
      return command->run();
    }
  } catch (...) {
    return report_error(std::current_exception(), "",
                        chosen ? chosen->memory_advice() : kMemoryAdvice);
  }
  return 0;
}

}  // namespace plumetrace::cli
