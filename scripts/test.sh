#!/usr/bin/env bash
# The whole test suite: install, build, run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --test
ctest --test-dir build --output-on-failure -j "$(nproc)"
