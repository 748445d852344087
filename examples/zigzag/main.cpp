// The plumetrace command with one more controller, "zigzag" (registered in zigzag.cpp): run,
// config, sweep and every other subcommand know it and its keys.
//
// Build: part of the CMake project (build/example_zigzag).
// Run:   build/example_zigzag config
//        build/example_zigzag run --algorithm zigzag --set zigzag.leg=0.8
#include "cli.hpp"

int main(int argc, char** argv) { return plumetrace::cli::main(argc, argv); }
