#!/usr/bin/env bash
# The model on 64-bit ARM (docs/reliability.md, "Same bits on every machine"): cross-builds the
# model library and tests/bits/model_bits for aarch64 with Debian's cross compiler, runs it under
# qemu-user and compares its output with this machine's model_bits, line for line.
#
#   scripts/aarch64.sh check         exits 0 when the cross compiler and qemu-user are installed
#   scripts/aarch64.sh build         configures and builds the model alone for aarch64 (ccache
#                                    when present)
#   scripts/aarch64.sh test NATIVE   build, then run NATIVE (this machine's model_bits, e.g.
#                                    build/tests/bits/model_bits), NATIVE again without glibc's
#                                    FMA variants of the maths functions (x86-64) and the ARM one
#                                    under qemu; exits 1 naming the first line that differs.
#                                    Exits 77 (a skip for ctest) when check fails
#
# The build folder is build-aarch64/ unless PLUMETRACE_AARCH64_BUILD names another (the test
# suite's is BUILD/aarch64). Packages: g++-aarch64-linux-gnu qemu-user-static (scripts/setup.sh
# --test installs them).
set -euo pipefail
cd "$(dirname "$0")/.."

build="${PLUMETRACE_AARCH64_BUILD:-build-aarch64}"
cxx=aarch64-linux-gnu-g++
qemu=qemu-aarch64-static
sysroot=/usr/aarch64-linux-gnu

usage() {
  sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

missing() {
  local m=()
  command -v "$cxx" >/dev/null || m+=(g++-aarch64-linux-gnu)
  command -v "$qemu" >/dev/null || m+=(qemu-user-static)
  echo "${m[@]}"
}

do_build() {
  local launcher=()
  if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    export CCACHE_BASEDIR="$PWD"
  fi
  # why: the model alone (no third-party package, no tests but model_bits), Release as the
  # suite's own build; its library is one compile unit (unity build): a third of the CPU time
  cmake -S . -B "$build" -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake \
    -DCMAKE_BUILD_TYPE=Release -DPLUMETRACE_MODEL_ONLY=ON "${launcher[@]}" \
    -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=0 >/dev/null
  cmake --build "$build" --target model_bits -j "${AARCH64_BUILD_JOBS:-$(nproc)}"
}

# runs a model_bits; its output goes to file $2
run_bits() {
  local out="$2"
  shift 2
  if ! "$@" >"$out"; then
    echo "aarch64.sh: $* failed" >&2
    exit 1
  fi
}

compare() {
  local a="$1" b="$2" what="$3"
  if ! cmp -s "$a" "$b"; then
    echo "aarch64.sh: $what differ; first differing lines:" >&2
    diff "$a" "$b" | head -6 >&2
    exit 1
  fi
}

do_test() {
  local native="$1"
  [[ -x "$native" ]] || { echo "aarch64.sh: $native is not built" >&2; exit 1; }
  local m
  m="$(missing)"
  if [[ -n "$m" ]]; then
    echo "aarch64.sh: skipped: needs $m (apt-get install $m, or bash scripts/setup.sh --test)"
    exit 77
  fi
  do_build
  local out="$build/bits"
  mkdir -p "$out"
  run_bits x86 "$out/native.txt" "$native"
  # why: glibc picks FMA versions of sin, cos, exp, log, pow, atan... when it is loaded on an
  # x86-64 processor that has FMA; without them are the versions every other x86-64 runs
  run_bits x86 "$out/native-no-fma.txt" env \
    GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-FMA4 "$native"
  run_bits arm "$out/aarch64.txt" "$qemu" -L "$sysroot" "$build/tests/bits/model_bits"
  compare "$out/native.txt" "$out/native-no-fma.txt" \
    "this machine's results with and without glibc's FMA maths functions"
  compare "$out/native.txt" "$out/aarch64.txt" "the results on x86-64 and on aarch64 (qemu)"
  echo "aarch64.sh: the same $(wc -l <"$out/native.txt") lines of bits on x86-64 (with and" \
    "without FMA maths functions) and on aarch64 under qemu-user"
}

(($# >= 1)) || usage
command="$1"
shift
case "$command" in
  check) [[ -z "$(missing)" ]] ;;
  build) do_build ;;
  test) (($# == 1)) || usage; do_test "$1" ;;
  *) usage ;;
esac
