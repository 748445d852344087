#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer into a build of their own, and runs them (docs/reliability.md, "Fuzzing and sanitizers").
#
#   scripts/fuzz.sh build                  configure and build the targets (ccache when present)
#   scripts/fuzz.sh run TARGET [SECONDS]   fuzz one target from its seed corpus for SECONDS
#                                          (default 20); exits non-zero on any crash, sanitizer
#                                          report, uncaught exception, input slower than 5 s or
#                                          memory past 2 GB, and names the input that did it
#   scripts/fuzz.sh all [SECONDS]          build, then run every target
#   scripts/fuzz.sh repro TARGET FILE...   run a target once on each input (a finding's repro)
#   scripts/fuzz.sh check                  exits 0 when clang and libFuzzer are installed
#
# Targets: scenario, sweep, trace, store, study, calibration. Extra libFuzzer flags go in FUZZ_FLAGS (for a long
# campaign, say FUZZ_FLAGS="-fork=2 -ignore_crashes=1"). The build folder is build-fuzz/ unless
# PLUMETRACE_FUZZ_BUILD names another; the seeds in tests/fuzz/corpus/ are only read, what the
# fuzzer finds goes to BUILD/corpus/TARGET and failing inputs to BUILD/artifacts/TARGET/.
set -euo pipefail
cd "$(dirname "$0")/.."

build="${PLUMETRACE_FUZZ_BUILD:-build-fuzz}"
targets=(scenario sweep trace store study calibration)
clangxx="${FUZZ_CXX:-clang++}"
clangc="${FUZZ_CC:-clang}"

usage() {
  sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

have_libfuzzer() {
  command -v "$clangxx" >/dev/null || return 1
  local resource
  resource="$("$clangxx" -print-resource-dir 2>/dev/null)" || return 1
  compgen -G "$resource/lib/linux/libclang_rt.fuzzer-*.a" >/dev/null
}

known_target() {
  local t
  for t in "${targets[@]}"; do [[ "$1" == "$t" ]] && return 0; done
  echo "fuzz.sh: unknown target '$1' (targets: ${targets[*]})" >&2
  exit 2
}

do_build() {
  if ! have_libfuzzer; then
    echo "fuzz.sh: needs clang and libFuzzer (apt-get install clang libfuzzer-14-dev)" >&2
    exit 1
  fi
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # why: only the core library and the targets: no CLI, tests, Python module or benchmarks.
  # Each library is one compile unit (a unity build): most of this build is optimising and
  # instrumenting the inline code of toml++, nlohmann/json and the standard library, which
  # separate units each compile again (471 s of CPU before, 298 s after, docs/performance.md)
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_COMPILER="$clangc" -DCMAKE_CXX_COMPILER="$clangxx" "${launcher[@]}" \
    -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=0 \
    -DPLUMETRACE_FUZZ=ON -DPLUMETRACE_BUILD_TESTS=OFF -DPLUMETRACE_BUILD_BENCHMARKS=OFF \
    -DPLUMETRACE_BUILD_EXAMPLES=OFF -DPLUMETRACE_BUILD_PYTHON=OFF -DPLUMETRACE_MPI=OFF \
    -DPLUMETRACE_VECTOR_CLONES=OFF >/dev/null
  cmake --build "$build" --target fuzz -j "${FUZZ_BUILD_JOBS:-$(nproc)}"
}

# the environment a target runs in: a scratch folder of this invocation (removed on exit, so that
# two runs of one target never share one), sanitizers that stop at the first report
fuzz_env() {
  local target="$1"
  scratch="$build/tmp/$target.$$"
  rm -rf "$scratch"
  mkdir -p "$scratch"
  trap 'rm -rf "$scratch"' EXIT
  export TMPDIR="$PWD/$scratch"
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
}

fuzz_flags() {
  local target="$1"
  local flags=(-timeout=5 -rss_limit_mb=2048 -print_final_stats=1)
  local dict="$target"
  [[ "$target" == scenario || "$target" == sweep || "$target" == study ]] && dict=toml
  flags+=("-dict=tests/fuzz/dict/$dict.dict")
  echo "${flags[@]}"
}

do_run() {
  local target="$1" seconds="${2:-20}"
  known_target "$target"
  local exe="$build/tests/fuzz/fuzz_$target"
  [[ -x "$exe" ]] || { echo "fuzz.sh: $exe is not built (scripts/fuzz.sh build)" >&2; exit 1; }
  local work="$build/corpus/$target" artifacts="$build/artifacts/$target"
  mkdir -p "$work" "$artifacts"
  fuzz_env "$target"
  local rc=0
  # shellcheck disable=SC2046,SC2086
  "$exe" $(fuzz_flags "$target") ${FUZZ_FLAGS:-} -max_total_time="$seconds" \
    -artifact_prefix="$artifacts/" "$work" "tests/fuzz/corpus/$target" || rc=$?
  rm -rf "$scratch"
  if ((rc != 0)); then
    echo "fuzz.sh: fuzz_$target found a problem (exit $rc); the input is in $artifacts/" >&2
    echo "fuzz.sh: reproduce with: scripts/fuzz.sh repro $target $artifacts/<file>" >&2
  fi
  return "$rc"
}

do_repro() {
  local target="$1"
  shift
  known_target "$target"
  fuzz_env "$target"
  local rc=0
  # shellcheck disable=SC2046
  "$build/tests/fuzz/fuzz_$target" $(fuzz_flags "$target") "$@" || rc=$?
  return "$rc"
}

(($# >= 1)) || usage
command="$1"
shift
case "$command" in
  check) have_libfuzzer ;;
  build) do_build ;;
  run) (($# >= 1)) || usage; do_run "$@" ;;
  repro) (($# >= 2)) || usage; do_repro "$@" ;;
  all)
    do_build
    failed=()
    for t in "${targets[@]}"; do do_run "$t" "${1:-20}" || failed+=("$t"); done
    if ((${#failed[@]} > 0)); then
      echo "fuzz.sh: findings in: ${failed[*]}" >&2
      exit 1
    fi
    ;;
  *) usage ;;
esac
