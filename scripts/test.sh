#!/usr/bin/env bash
# README command 2: set up, build, run every test. CI runs exactly this (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
cd "${GLCAST_BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc)" --timeout 600
