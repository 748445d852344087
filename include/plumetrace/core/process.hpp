#pragma once

#include <string>
#include <vector>

namespace plumetrace {

/// The exit status run_program gives when the program could not be started (as a shell's).
inline constexpr int kProgramNotStarted = 127;

/// Runs the program `argv[0]` (a path, not looked up on PATH) with the arguments `argv[1..]` and
/// waits for it, without a shell: no argument is ever parsed or expanded. Its environment is this
/// process's with each "NAME=value" of `env` set (replacing NAME). While it runs, SIGINT and
/// SIGQUIT are ignored here and reach only the program, as with std::system. Returns its exit
/// status, 128 + the signal's number when a signal ended it, or kProgramNotStarted.
int run_program(const std::vector<std::string>& argv, const std::vector<std::string>& env = {});

}  // namespace plumetrace
