#!/usr/bin/env bash
# README command 1: set up, build, and run the main job on the built-in default: capture the
# bundled fixed-function demo scene under a private Xvfb and dump what glcast recorded.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build=${GLCAST_BUILD_DIR:-build}
out=${1:-demo.glcs}
xvfb-run -a -s "-screen 0 1280x1024x24" \
    "$build/glcast" capture -o "$out" --frames 60 -- "$build/tests/apps/ff_scene" --frames 60
"$build/glcast" dump "$out" --frames 0:1 | head -40
echo "..."
"$build/glcast" dump "$out" --summary | tail -3
echo "demo: $(stat -c %s "$out") bytes in $out; 'glcast dump $out' shows every call"
