#!/usr/bin/env bash
# README command 1: set up, build, and run the main job on the built-in default: the bundled
# fixed-function scene on a 2x2 wall (four headless slaves, their tiles stitched into
# demo/wall.png), a capture of it and the first lines of its dump, and the same stream replayed
# on the wall's tiles with the injected passes (snow, snow cover, icicles, shadows) into
# demo/wall-effects.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build=${GLCAST_BUILD_DIR:-build}
out=${1:-demo}
rm -rf "$out" && mkdir -p "$out"
xvfb-run -a -s "-screen 0 1280x1024x24" env GLCAST_CAPTURE="$out/capture.glcs" \
    "$build/glcast" run --config display_configs/wall-2x2.json --backend egl --out "$out/tiles" --frames 60 \
    -- "$build/tests/apps/ff_scene" --frames 1000
last=frame-000059.png
"$build/glcast" image mosaic 2x2 "$out/wall.png" "$out"/tiles/{top-left,top-right,bottom-left,bottom-right}/$last
"$build/glcast" dump "$out/capture.glcs" --frames 0:0 > "$out/dump.txt"
head -25 "$out/dump.txt"
echo "..."
"$build/glcast" dump "$out/capture.glcs" --summary | tail -2
mkdir -p "$out/effects"
for tile in top-left top-right bottom-left bottom-right; do
    "$build/glcast" replay "$out/capture.glcs" --config display_configs/wall-2x2.json --tile $tile \
        --effects shadows,cover,icicles,snow --frames 59:59 --out "$out/effects/$tile" > /dev/null
done
"$build/glcast" image mosaic 2x2 "$out/wall-effects.png" "$out"/effects/{top-left,top-right,bottom-left,bottom-right}/$last
echo "demo: $out/wall.png is frame 59 of the four tiles, $out/tiles/ has every frame of each,"
echo "      $out/capture.glcs the stream ($(stat -c %s "$out/capture.glcs") bytes; glcast dump shows every call),"
echo "      $out/wall-effects.png the same frame with soft shadows, snow cover, icicles and falling snow"
