#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "support/temp_path.hpp"

namespace plumetrace::testing {

/// The whole text of a file ("" when it cannot be read).
inline std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes `text` to a new temporary file and returns its path.
inline std::string write_temp(const std::string& stem, const std::string& suffix,
                              const std::string& text) {
  const std::string path = temp_path(stem, suffix);
  std::ofstream(path) << text;
  return path;
}

/// What a command did: its exit code (128 + signal when killed), stdout and stderr.
struct CommandOutput {
  int code = -1;
  std::string out;
  std::string err;
};

/// Runs a shell command line, capturing its output.
inline CommandOutput run_command(const std::string& command) {
  const std::string out = temp_path("stdout", ".txt");
  const std::string err = temp_path("stderr", ".txt");
  const int status = std::system((command + " >" + out + " 2>" + err).c_str());
  CommandOutput o;
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  o.out = read_file(out);
  o.err = read_file(err);
  return o;
}

}  // namespace plumetrace::testing
