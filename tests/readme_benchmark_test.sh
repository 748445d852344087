#!/usr/bin/env bash
# The README's benchmark commands ("## The benchmark"), run as written in an empty folder, each
# benchmark on one task at 2 runs per cell (a stand-in for build/plumetrace and
# build/example_zigzag adds --task laminar --runs 2; --compare is run as it is). Every command
# must succeed and write what the README says.
# Usage: readme_benchmark_test.sh SOURCE_DIR PLUMETRACE_CLI EXAMPLE_ZIGZAG
set -euo pipefail
src=$(cd "$1" && pwd)
cli=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
zigzag=$(cd "$(dirname "$3")" && pwd)/$(basename "$3")
work=$(mktemp -d "${TMPDIR:-/tmp}/plumetrace-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT

awk '/^## The benchmark/ { on = 1 }
     on && /^```sh$/ { block = 1; next }
     block && /^```$/ { exit }
     block { print }' "$src/README.md" > "$work/commands.sh"
[[ $(grep -c benchmark "$work/commands.sh") -ge 4 ]] || { echo "FAIL: no benchmark block"; exit 1; }
grep -q -- '--controller examples/python_surge_cast.py' "$work/commands.sh" \
  || { echo "FAIL: the README runs no example Python controller"; exit 1; }
grep -q -- 'example_zigzag benchmark --controller zigzag' "$work/commands.sh" \
  || { echo "FAIL: the README runs no example C++ controller"; exit 1; }

mkdir -p "$work/build" "$work/examples"
for pair in "plumetrace:$cli" "example_zigzag:$zigzag"; do
  name=${pair%%:*} real=${pair#*:}
  cat > "$work/build/$name" <<WRAP
#!/usr/bin/env bash
if [[ "\$1" == benchmark && " \$* " != *" --compare "* ]]; then
  exec "$real" "\$@" --task laminar --runs 2 --quiet
fi
exec "$real" "\$@"
WRAP
  chmod +x "$work/build/$name"
done
cp "$src/examples/python_surge_cast.py" "$work/examples/"
cd "$work"
bash -euo pipefail -x commands.sh > commands.out
for f in out/plumetrace-core/leaderboard.html out/core-check/leaderboard.json; do
  [[ -s $f ]] || { echo "FAIL: the commands wrote no $f"; exit 1; }
done
grep -q py-surge-cast out/plumetrace-core/runs.csv || { echo "FAIL: no py-surge-cast runs"; exit 1; }
grep -q zigzag out/zigzag/runs.csv || { echo "FAIL: no zigzag runs"; exit 1; }
echo "readme_benchmark: $(grep -c benchmark commands.sh) commands OK"
