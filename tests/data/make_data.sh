#!/usr/bin/env bash
# Regenerates the committed captures and their golden frames (the programs' own frames, read
# before each swap). Run after a change to the stream format, the registry or the annotations
# (a capture's header carries the opcode-table hash, so old captures are then refused).
#
#   tests/data/make_data.sh BUILD_DIR
set -euo pipefail
build=$(cd "${1:?usage: make_data.sh BUILD_DIR}" && pwd)
data=$(cd "$(dirname "$0")" && pwd)
apps=$build/tests/apps

exec 3< <(exec Xvfb -displayfd 1 -screen 0 1024x768x24 -nolisten tcp -noreset 2>/dev/null)
xvfb=$!  # (the server itself: the process substitution execs it; pkill by pattern ended others' too)
read -r display <&3
export DISPLAY=:$display
trap 'kill "$xvfb" 2>/dev/null || true' EXIT

capture() {  # name frames program args...
    local name=$1 frames=$2
    shift 2
    rm -rf "${data:?}/$name" "$data/$name.glcs"
    GLCAST_SNAPSHOT_DIR="$data/$name" "$build/glcast" capture -o "$data/$name.glcs" --frames "$frames" -- "$@" > /dev/null
    echo "$name: $(stat -c %s "$data/$name.glcs") bytes, $(ls "$data/$name" | wc -l) frames"
}
capture ff_scene 3 "$apps/ff_scene" --size 160x120 --frames 3
capture ff_scene_backdrop 3 "$apps/ff_scene" --backdrop --size 160x120 --frames 3
capture ff_scene_reflection 3 "$apps/ff_scene" --reflection --size 160x120 --frames 3
capture ff_scene_widget 4 "$apps/ff_scene" --widget --size 160x120 --frames 4
capture core_scene 3 "$apps/core_scene" --size 160x120 --frames 3
capture glfw_dynamic 3 "$apps/glfw_dynamic" --size 128x96 --frames 3
capture glxgears 3 glxgears -geometry 128x128
capture client_draws 3 "$apps/client_draws" --size 160x120 --frames 3
du -sh "$data"
