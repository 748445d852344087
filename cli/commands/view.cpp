#include <filesystem>
#include <iostream>
#include <limits>

#include "commands.hpp"
#include "plumetrace/io/trace_io.hpp"
#include "validators.hpp"

namespace plumetrace::cli {

CLI::App* ViewCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand("view", "draw a run from its .json trace: viewer or figure");
  sub->add_option("trace", trace, "trace written by: plumetrace run --trace FILE.json")
      ->required()
      ->check(not_empty());
  sub->add_option("-o,--output", output,
                  "FILE.html (animated viewer) or FILE.svg (static figure); default: the "
                  "trace's name with .html")
      ->check(not_empty());
  sub->add_option("--max-frames", options.max_frames,
                  "most robot frames kept for the animation (default 12000)")
      ->check(whole_number(1, std::numeric_limits<int>::max()));
  sub->add_option("--max-snapshots", options.max_snapshots,
                  "most filament snapshots kept (default 600)")
      ->check(whole_number(1, std::numeric_limits<int>::max()));
  sub->add_option("--at", options.figure_time,
                  "time of the filaments drawn in an .svg figure (s; default: the end)")
      ->check(finite_number(0.0));
  return sub;
}

int ViewCommand::run() {
  std::string out = output;
  if (out.empty()) {
    const std::filesystem::path p(trace);
    out = (p.parent_path() / p.stem()).string() + ".html";
  }
  const RecordedRun recorded = read_trace(trace);
  check_view_path(out, "--output");
  write_view(out, recorded, options);
  std::cout << out << "\n";
  return 0;
}

}  // namespace plumetrace::cli
