#pragma once

namespace plumetrace::cli {

/// The plumetrace command: parses the arguments, runs the subcommand and returns the exit code
/// (docs/reliability.md, "Exit codes"). A program that registers controllers of its own calls
/// this from its main (examples/zigzag/).
int main(int argc, char** argv);

}  // namespace plumetrace::cli
