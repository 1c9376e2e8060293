#!/usr/bin/env bash
# keeper_join_runs.sh [BUILD_DIR] [CASES...]: the long late-join runs of docs/keeper.md. Each
# program runs twice with a journal of 2 MiB: 2,000 frames with a slave joining from the keeper at
# frame 1,000, and 20,000 frames joining at 19,000. Prints the join (snapshot and journal
# messages, bytes, seconds), the frames compared with the program's own, and the program's RSS.
# About 15 minutes on 2 cores.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$here/build}" && pwd)
shift $(( $# > 0 ? 1 : 0 ))
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(glxgears ff_scene core_scene glfw_dynamic client_draws fbo_ext threads_buffers textures render_once renderbuffer fences)
export GLCAST=$build/glcast GLCAST_SHIM=$build/libglcast.so APPS_DIR=$build/tests/apps OUT_DIR=${OUT_DIR:-/tmp/glcast-keeper-runs}
for c in "${cases[@]}"; do
    for run in "2000 1000" "20000 19000"; do
        set -- $run
        KEEPER_TEST_FRAMES=$1 KEEPER_TEST_JOIN=$2 python3 "$here/tests/e2e/keeper_test.py" "$c" | grep -v '^PASS$'
    done
done
