#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

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

/// Starts `program` with `args` without a shell, its stdout and stderr sent to the files `out`
/// and `err`, after `in_child` has run in the child (a resource limit, say); returns its pid.
inline pid_t spawn_program(const std::string& program, const std::vector<std::string>& args,
                           const std::string& out = "/dev/null",
                           const std::string& err = "/dev/null",
                           const std::function<void()>& in_child = {}) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (in_child) in_child();
    std::vector<char*> argv{const_cast<char*>(program.c_str())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (!std::freopen(out.c_str(), "w", stdout) || !std::freopen(err.c_str(), "w", stderr)) {
      _exit(126);
    }
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

/// Waits for a child to end: its exit code, or 128 + the signal that killed it.
inline int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Runs `program` with `args` to its end without a shell, capturing stdout and stderr.
inline CommandOutput run_program(const std::string& program, const std::vector<std::string>& args) {
  const std::string out = temp_path("stdout", ".txt");
  const std::string err = temp_path("stderr", ".txt");
  CommandOutput o;
  o.code = wait_for(spawn_program(program, args, out, err));
  o.out = read_file(out);
  o.err = read_file(err);
  return o;
}

}  // namespace plumetrace::testing
