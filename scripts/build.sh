#!/usr/bin/env bash
# Installs the dependencies and builds plumetrace (Release) into build/.
#   bash scripts/build.sh          the main job's build: the plumetrace command only
#   bash scripts/build.sh --test   everything: the command, the Python module, the tests, the
#                                  benchmarks and the examples
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  "")
    bash scripts/setup.sh
    # why: the main job needs neither GoogleTest, nor pybind11, nor MPI; without them installed
    # the parts that use them must be off, and only the command is built
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPLUMETRACE_BUILD_TESTS=OFF \
      -DPLUMETRACE_BUILD_BENCHMARKS=OFF -DPLUMETRACE_BUILD_EXAMPLES=OFF \
      -DPLUMETRACE_BUILD_PYTHON=OFF >/dev/null
    cmake --build build -j "$(nproc)" --target plumetrace
    ;;
  --test)
    bash scripts/setup.sh --test
    # why: ccache with paths relative to the checkout, so that the test of `pip install .`
    # (tests/python_install_test.sh), which builds the same sources in a copy, reuses these
    # objects instead of compiling the library a second time on the suite's clock
    launcher=()
    if command -v ccache >/dev/null; then
      launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
      export CCACHE_BASEDIR="$PWD"
    fi
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPLUMETRACE_BUILD_TESTS=ON \
      -DPLUMETRACE_BUILD_BENCHMARKS=ON -DPLUMETRACE_BUILD_EXAMPLES=ON \
      -DPLUMETRACE_BUILD_PYTHON=ON "${launcher[@]}" >/dev/null
    cmake --build build -j "$(nproc)"
    ;;
  *) echo "build: unknown option '$1' (use --test or nothing)" >&2; exit 2 ;;
esac
