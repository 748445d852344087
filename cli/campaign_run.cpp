#include "campaign_run.hpp"

#include <cstdio>
#include <filesystem>
#include <string>

#include "errors.hpp"
#include "plumetrace/core/process.hpp"
#include "plumetrace/paths.hpp"
#include "progress.hpp"
#include "shell.hpp"

namespace plumetrace::cli {

bool run_with_progress(const std::string& label, const std::vector<ExpandedSweep>& sweeps,
                       Store& store, int runs, const CampaignFlags& flags, CampaignResult& result,
                       const Shard& shard, const TaskRunner& runner) {
  install_stop_handlers();
  ProgressBar bar(label, !flags.quiet && stderr_is_terminal());
  CampaignOptions options;
  options.threads = flags.threads;
  options.share_plumes = !flags.no_share;
  options.stop = &g_stop;
  options.on_progress = [&](const Progress& p) { bar.update(p); };
  result = run_campaign(sweeps, store, runs, options, shard, runner);
  bar.finish();
  if (!result.interrupted) return true;
  std::fprintf(stderr,
               "plumetrace: interrupted: %lld of %lld runs are in '%s'; run the same command "
               "again to compute the rest\n",
               static_cast<long long>(result.skipped + result.computed),
               static_cast<long long>(result.total), store.path().c_str());
  return false;
}

std::string extra_options(const std::vector<std::string>& sets, int runs) {
  std::string text;
  for (const auto& s : sets) text += " --set " + shell_word(s);
  if (runs > 0) text += " --runs " + std::to_string(runs);
  return text;
}

void warn_incomplete(const std::vector<ExpandedSweep>& sweeps,
                     const std::vector<IncompletePoint>& incomplete, const std::string& store,
                     const std::string& extra) {
  for (const auto& sweep : sweeps) {
    std::vector<const IncompletePoint*> mine;
    for (const auto& p : incomplete) {
      if (p.sweep == sweep.def.name) mine.push_back(&p);
    }
    if (mine.empty()) continue;
    std::fprintf(stderr,
                 "plumetrace: warning: %zu of %zu points of sweep %s have runs missing in '%s':\n",
                 mine.size(), sweep.points.size(), sweep.def.name.c_str(), store.c_str());
    for (std::size_t k = 0; k < mine.size() && k < 10; ++k) {
      std::fprintf(stderr, "  (%s): %lld of %d runs\n", mine[k]->values.c_str(),
                   static_cast<long long>(mine[k]->stored), mine[k]->runs);
    }
    if (mine.size() > 10) std::fprintf(stderr, "  and %zu more\n", mine.size() - 10);
    const std::string file = sweep.def.file.empty() ? "SWEEP.toml" : shell_word(sweep.def.file);
    std::fprintf(stderr, "  compute them with: plumetrace sweep %s --store %s%s\n", file.c_str(),
                 shell_word(store).c_str(), extra.c_str());
  }
}

std::string python_path() {
  // why: the reports' package is the source's; this build's copy after it lends the compiled
  // module, which the package's __init__ finds there (pkgutil.extend_path): the evidence rules'
  // Student's t quantile is the C++ library's
  std::string path = data_dir() + "/python";
  std::error_code error;
  if (std::filesystem::is_directory(std::string(kBuildPythonDir) + "/plumetrace", error)) {
    path += std::string(":") + kBuildPythonDir;
  }
  return path;
}

int run_python_module(const std::string& module, const std::vector<std::string>& args) {
  // what Python prints follows what was printed here
  std::fflush(nullptr);
  std::vector<std::string> argv{kPython, "-P", "-m", module};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_program(argv, {"PYTHONPATH=" + python_path()});
}

int draw_report(const std::string& out, const std::string& module,
                const std::vector<std::string>& args, bool is_file) {
  const std::string python_path = cli::python_path();
  // what the report prints follows what was printed here
  std::fflush(nullptr);
  std::vector<std::string> argv{kPython, "-P"};
  if (!is_file) argv.emplace_back("-m");
  argv.insert(argv.end(), {module, out});
  argv.insert(argv.end(), args.begin(), args.end());
  const int rc = run_program(argv, {"PYTHONPATH=" + python_path});
  if (rc != 0) {
    std::string command = "PYTHONPATH=" + shell_word(python_path) + " " + shell_word(kPython) +
                          (is_file ? " -P " : " -P -m ") + shell_word(module) + " " +
                          shell_word(out);
    for (const auto& a : args) command += " " + shell_word(a);
    std::fprintf(stderr,
                 "plumetrace: error: drawing the report failed (%s); the results are kept in "
                 "%s/\n",
                 command.c_str(), out.c_str());
    return kIoFailure;
  }
  return 0;
}

}  // namespace plumetrace::cli
