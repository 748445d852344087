#!/usr/bin/env bash
# Installs the dependencies from Debian 12 packages (and npm, for the browser test); does nothing
# when all are present. Safe to run again.
#   bash scripts/setup.sh          what the main job needs: build the command, draw the report
#   bash scripts/setup.sh --test   that, plus what the tests need (GoogleTest, Google Benchmark,
#                                  the Python module and its tests, MPI, chromium and node, clang's
#                                  libFuzzer, the aarch64 cross compiler and qemu-user)
set -euo pipefail

mode=main
case "${1:-}" in
  "") ;;
  --test) mode=test ;;
  *) echo "setup: unknown option '$1' (use --test or nothing)" >&2; exit 2 ;;
esac

# the command and its report (matplotlib and numpy draw it)
packages=(
  g++ cmake make pkg-config
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libsqlite3-dev
  python3 python3-matplotlib python3-numpy
)
if [[ $mode == test ]]; then
  packages+=(
    libgtest-dev libbenchmark-dev
    python3-dev pybind11-dev python3-pytest python3-optuna python3-sklearn python3-hypothesis
    python3-pandas
    # CITATION.cff read and checked against the CFF schema (tests/citation)
    python3-yaml python3-jsonschema
    # `pip install .` offline (pyproject.toml, setup.py) and its test in a fresh venv
    python3-pip python3-venv python3-setuptools python3-wheel
    # the test build and that wheel's build share compiled objects (scripts/build.sh --test)
    ccache
    clang libfuzzer-14-dev
    # the model built for 64-bit ARM and run under qemu-user (scripts/aarch64.sh)
    g++-aarch64-linux-gnu qemu-user-static
    libopenmpi-dev openmpi-bin
    chromium
  )
  # node and npm run the viewer's browser test; a Node.js from elsewhere (which bundles npm) will do
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    packages+=(nodejs npm)
  fi
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install packages" >&2; exit 1; }
    sudo="sudo"
  fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [[ $mode == test ]]; then
  # playwright-core (npm, pinned by tests/browser/package-lock.json) drives chromium in the
  # viewer's test; installed again only when the lock file changed
  browser_tests="$(dirname "$0")/../tests/browser"
  if [[ ! -f "$browser_tests/node_modules/.package-lock.json" ||
        "$browser_tests/package-lock.json" -nt "$browser_tests/node_modules/.package-lock.json" ]]; then
    echo "setup: npm ci in tests/browser"
    npm ci --prefix "$browser_tests" --no-audit --no-fund --loglevel=error
  fi
fi
