#!/usr/bin/env bash
# The main job (scripts/run.sh) needs only what `scripts/setup.sh` without --test installs: the
# project configures for it with the test-only packages hidden from CMake (GoogleTest, Google
# Benchmark, pybind11, MPI), and its build target is the command alone.
# Usage: main_job_test.sh SOURCE_DIR
set -euo pipefail
source=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# the options scripts/build.sh gives the main job's build, read from the script itself
options=$(sed -n '/^  "")/,/;;/p' "$source/scripts/build.sh" | grep -o -- '-DPLUMETRACE_[A-Z_]*=[A-Z]*' | tr '\n' ' ')
[[ $options == *"PLUMETRACE_BUILD_TESTS=OFF"* && $options == *"PLUMETRACE_BUILD_PYTHON=OFF"* ]]
# shellcheck disable=SC2086
cmake -S "$source" -B "$work/build" -DCMAKE_BUILD_TYPE=Release $options \
  -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON >"$work/log" 2>&1
grep -q "MPI: not found or off" "$work/log"
# the command is a target of that build; no test target is
make -C "$work/build" help >"$work/targets"
grep -q '\.\.\. plumetrace$' "$work/targets"
if grep -q -e '_test$' -e 'plumetrace_bench' -e 'plumetrace_python' "$work/targets"; then
  echo "main_job_test: the main job's build has test targets" >&2
  exit 1
fi

# the package lists: every test-only package is under --test
main_list=$(sed -n '/^packages=(/,/^)/p' "$source/scripts/setup.sh")
for p in libgtest-dev libbenchmark-dev pybind11-dev libopenmpi-dev chromium python3-pytest; do
  if grep -qw -- "$p" <<<"$main_list"; then
    echo "main_job_test: $p is installed for the main job" >&2
    exit 1
  fi
done
# a wrong option is refused, exit 2
if bash "$source/scripts/setup.sh" --bogus 2>"$work/err"; then exit 1; fi
grep -q "unknown option '--bogus'" "$work/err"
echo "main_job_test: the main job configures without the test-only packages"
