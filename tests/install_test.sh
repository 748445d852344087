#!/usr/bin/env bash
# cmake --install gives a package that a project of its own finds and links: installs the build
# into a temporary prefix, builds examples/out_of_tree against it with nothing but
# CMAKE_PREFIX_PATH, and checks its run equals `plumetrace run --json` of the installed command
# (same scenario, seed and trial), and that the installed command finds its study files.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

cmake --install "$build" --prefix "$prefix" >/dev/null
test -f "$prefix/lib/cmake/plumetrace/plumetraceConfig.cmake"
test -f "$prefix/include/plumetrace/sim/world.hpp"
test -f "$prefix/share/plumetrace/studies/lochmatter2008/study.toml"
cmp "$prefix/share/doc/plumetrace/LICENSE" "$source/LICENSE"   # binaries carry the notice

cmake -S "$source/examples/out_of_tree" -B "$work/app" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/app" -j 2 >/dev/null

scenario="$source/scenarios/meander-weak.toml"
"$work/app/app" "$scenario" 7 3 >"$work/app.json"
"$prefix/bin/plumetrace" run "$scenario" --seed 7 --trial 3 --json >"$work/cli.json"
cmp "$work/app.json" "$work/cli.json"
grep -q '"outcome"' "$work/app.json"

# a bad scenario file is named, exit 2
if "$work/app/app" "$work/missing.toml" 2>"$work/err"; then exit 1; fi
grep -q "missing.toml" "$work/err"
# the installed command reads its study and draws its report from the installed data folder
# (PLUMETRACE_DATA_DIR stands in for a removed source folder), from any working folder
(cd "$work" && PLUMETRACE_DATA_DIR="$prefix/share/plumetrace" "$prefix/bin/plumetrace" reproduce \
  --runs 1 --presets none --out "$work/out" --quiet >/dev/null)
test -s "$work/out/report.html"
grep -q "set A" "$work/out/report.md"

echo "install_test: the out-of-tree app built against $prefix and equals plumetrace run --json"
