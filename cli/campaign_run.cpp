#include "campaign_run.hpp"

#include <cstdio>

#include "errors.hpp"
#include "plumetrace/core/process.hpp"
#include "plumetrace/paths.hpp"
#include "progress.hpp"

namespace plumetrace::cli {

namespace {

// `text` as one word of a POSIX shell, for messages a user may paste
std::string shell_word(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

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

int draw_report(const std::string& out, const std::string& module) {
  const std::string python_path = data_dir() + "/python";
  // what the report prints follows what was printed here
  std::fflush(nullptr);
  const int rc = run_program({kPython, "-m", module, out}, {"PYTHONPATH=" + python_path});
  if (rc != 0) {
    const std::string command = "PYTHONPATH=" + shell_word(python_path) + " " +
                                shell_word(kPython) + " -m " + module + " " + shell_word(out);
    std::fprintf(stderr,
                 "plumetrace: error: drawing the report failed (%s); the results are kept in "
                 "%s/\n",
                 command.c_str(), out.c_str());
    return kIoFailure;
  }
  return 0;
}

}  // namespace plumetrace::cli
