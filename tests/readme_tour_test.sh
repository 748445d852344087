#!/usr/bin/env bash
# The README's "A one-minute tour", run as written: its shell block, line by line, in an empty
# folder (with the repository's scenarios/ beside it), P set to the command under test. Every
# line must succeed, so a file one line reads (trace.json) must be one an earlier line wrote.
# Usage: readme_tour_test.sh SOURCE_DIR PLUMETRACE_CLI
set -euo pipefail
src=$(cd "$1" && pwd)
cli=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
work=$(mktemp -d "${TMPDIR:-/tmp}/plumetrace-tour.XXXXXX")
trap 'rm -rf "$work"' EXIT

# the first ```sh block after the heading
awk '/^## A one-minute tour/ { tour = 1 }
     tour && /^```sh$/ { block = 1; next }
     block && /^```$/ { exit }
     block { print }' "$src/README.md" > "$work/tour.sh"
grep -q '^P=build/plumetrace$' "$work/tour.sh" || { echo "FAIL: no 'P=build/plumetrace' in the tour"; exit 1; }
[[ $(grep -c '^\$P ' "$work/tour.sh") -ge 5 ]] || { echo "FAIL: the tour has fewer than 5 commands"; exit 1; }
sed -i "s|^P=build/plumetrace\$|P='$cli'|" "$work/tour.sh"

ln -s "$src/scenarios" "$work/scenarios"
cd "$work"
bash -euo pipefail -x tour.sh > tour.out
for f in trace.json run.html run.svg meander.html; do
  [[ -s $f ]] || { echo "FAIL: the tour wrote no $f"; exit 1; }
done
echo "readme_tour: $(grep -c '^\$P ' tour.sh) commands OK"
