#!/usr/bin/env bash
# The whole test suite under AddressSanitizer and UndefinedBehaviorSanitizer: builds every target
# with g++ -fsanitize=address,undefined (-fno-sanitize-recover: the first report fails the test)
# into build-asan/, then runs ctest there (docs/reliability.md, "Fuzzing and sanitizers"). Too slow for every CI run;
# run it before a release and after changes to memory handling.
#
#   scripts/test-sanitized.sh [CTEST ARGS...]     e.g. -R Store or -LE browser
#
# The Python test loads the instrumented module into Debian's python3, which is not
# instrumented: it runs with libasan preloaded and leak checks off (tests/CMakeLists.txt).
# Leaks that are not ours (Open MPI's) are listed in tests/sanitize/lsan.supp. The fuzz tests
# are not registered here: the fuzz build is sanitized already. Build folder: build-asan/ unless
# PLUMETRACE_ASAN_BUILD names another.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --test
build="${PLUMETRACE_ASAN_BUILD:-build-asan}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# why: -O1 keeps the instrumented build and its tests within reach of a small machine
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-O1 "${launcher[@]}" \
  -DPLUMETRACE_SANITIZE=address,undefined -DPLUMETRACE_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/tests/sanitize/lsan.supp:print_suppressions=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "$@"
