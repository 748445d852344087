#include "cli.hpp"

int main(int argc, char** argv) { return plumetrace::cli::main(argc, argv); }
