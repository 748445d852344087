#include <iostream>

#include "commands.hpp"
#include "plumetrace/io/scenario_io.hpp"

namespace plumetrace::cli {

CLI::App* ConfigCommand::add(CLI::App& app) {
  auto* sub = app.add_subcommand("config", "print the fully resolved configuration");
  scenario.add_to(*sub, true);
  sub->add_flag("--json", json, "print JSON instead of TOML");
  return sub;
}

int ConfigCommand::run() {
  const Scenario s = scenario.load();
  std::cout << (json ? scenario_to_json(s) + "\n" : scenario_to_toml(s));
  return 0;
}

}  // namespace plumetrace::cli
