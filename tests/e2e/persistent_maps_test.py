#!/usr/bin/env python3
"""Streaming through persistent mapped buffers (tests/apps_extra/persistent_maps.c): what the
program writes into a persistent, coherent mapping outside any GL call reaches the stream before
the first command that may read it (interceptor/special/buffer_map.cpp, the pages found written
by interceptor/write_tracking.cpp). For each shape the program checks its own picture, and the
capture replays equal to the program's own frames on EGL and OSMesa, and as a 2x2 wall (four tile
replays of a canvas the size of the window, stitched) within the wall's tolerance
(tests/e2e/wall_test.py). The stream carries at most twice the bytes the program wrote.

    persistent_maps_test.py SHAPE     ring uniform unpack thread rewrite sigsegv several contexts, or:
      untracked   the ring with GLCAST_MAP_TRACKING=0: said once, compared whole, the same frames
      crash       a fault of the program's own with no handler of its own (after the ring is
                  tracked) kills it with SIGSEGV, as without glcast, and the capture is still read
      with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
"""
import os
import re
import shutil
import signal
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
FRAMES, W, H = 6, 320, 240
TOLERANCE = 1e-4  # of the wall's pixels, as tests/e2e/wall_test.py allows
# The unpack shape's texture is a gradient of 4 a texel, sampled nearest: a tile's interpolation
# (tests/e2e/wall_test.py) picks the neighbouring texel along texel edges, while last frame's
# image (what a stale pixel-unpack ring shows) differs by 16 in blue everywhere.
NEIGHBOUR_TEXEL = 4


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(cmd, env=None, timeout=300):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def crash(out):
    program = [os.path.join(APPS, "persistent_maps"), "--shape", "crash", "--size", f"{W}x{H}"]
    with Xvfb():
        alone = run(program)
        r = run(program, env=dict(os.environ, LD_PRELOAD=os.environ["GLCAST_SHIM"],
                                  GLCAST_CAPTURE=os.path.join(out, "capture.glcs")), timeout=60)
    check(alone.returncode == -signal.SIGSEGV, f"alone the program ended {alone.returncode}: {alone.stderr[-500:]}")
    check(r.returncode == -signal.SIGSEGV and "writing into a read-only page" in r.stdout,
          f"under the shim the program ended {r.returncode}, not by SIGSEGV: {r.stdout} {r.stderr[-1500:]}")
    print("crash: the program's own fault kills it with SIGSEGV under the shim as alone")


def main(case):
    out = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "persistent_maps", case)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    if case == "crash":
        return crash(out)
    shape = "ring" if case == "untracked" else case
    capture, own = os.path.join(out, "capture.glcs"), os.path.join(out, "program")
    with Xvfb():  # (it sets DISPLAY)
        env = dict(os.environ, GLCAST_SNAPSHOT_DIR=own)
        if case == "untracked":
            env["GLCAST_MAP_TRACKING"] = "0"
        r = run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "persistent_maps"), "--shape", shape,
                 "--ring-mb", "4", "--draws", "100", "--frames", str(FRAMES), "--size", f"{W}x{H}"], env=env)
    check(r.returncode == 0, f"capture failed ({r.returncode}): {r.stdout} {r.stderr[-2000:]}")
    m = re.search(r"persistent_maps: \w+ ok, (\d+) bytes written a frame", r.stdout)
    check(m, f"the program did not check its picture: {r.stdout} {r.stderr[-2000:]}")
    written = int(m.group(1))
    total = FRAMES * (2 if case == "contexts" else 1)  # frames of every window, in the order of their swaps
    said = r.stderr.count("GLCAST_MAP_TRACKING=0")
    if case == "untracked":
        check(said == 1, f"tracking off is said {said} times, not once: {r.stderr[-2000:]}")
    else:
        check("compared whole" not in r.stderr, f"tracking was refused: {r.stderr[-2000:]}")

    # Bytes on the stream for the mapping against the bytes written (frames after the first: the
    # first also carries the mapping's creation).
    dump = run([GLCAST, "dump", capture]).stdout
    frames = re.split(r"\n\d+ (?:glXSwapBuffers)\(", dump)
    check(len(frames) >= total, f"the dump shows {len(frames)} frames")
    shipped = [sum(int(b) for b in re.findall(r"glcast\.buffer_write\(.*data = (\d+) bytes\)", f))
               for f in frames[2:total]]
    if case == "contexts":  # two threads' tuples interleave between swaps: their sum
        check(0 < sum(shipped) <= 2 * written * len(shipped),
              f"buffer writes of {len(shipped)} frames {sum(shipped)} bytes, the program wrote {written} a frame")
    else:
        check(max(shipped) <= 2 * written and min(shipped) > 0,
              f"buffer writes per frame {shipped} bytes, the program wrote {written}")

    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    for backend in ("egl", "osmesa"):
        r = run([GLCAST, "replay", capture, "--backend", backend, "--compare", own, "--verify"], env=headless)
        check(r.returncode == 0 and f"compared {total} frames: 0 differ" in r.stdout and "replies: 0 differ" in r.stdout,
              f"{backend}: {r.stdout[-1500:]} {r.stderr[-1500:]}")

    # The 2x2 wall: each tile replays the whole stream and shows its quarter of the window.
    last = f"frame-{total - 1:06d}.png"
    tiles = []
    for name, x, y in (("top-left", 0, 0), ("top-right", W // 2, 0), ("bottom-left", 0, H // 2),
                       ("bottom-right", W // 2, H // 2)):
        tile = os.path.join(out, name)
        r = run([GLCAST, "replay", capture, "--backend", "egl", "--canvas", f"{W}x{H}", "--tile-rect",
                 f"{x},{y},{W // 2},{H // 2}", "--frames", f"{total - 1}:{total - 1}", "--out", tile], env=headless)
        check(r.returncode == 0, f"tile {name}: {r.stdout[-1500:]} {r.stderr[-1500:]}")
        tiles.append(os.path.join(tile, last))
    stitched = os.path.join(out, "wall.png")
    r = run([GLCAST, "image", "mosaic", "2x2", stitched] + tiles)
    check(r.returncode == 0, r.stderr)
    r = run([GLCAST, "image", "compare", stitched, os.path.join(own, last)])
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    check(m, f"compare: {r.stdout} {r.stderr}")
    if case == "unpack":
        check(int(m.group(2)) <= NEIGHBOUR_TEXEL, f"the 2x2 wall shows another texture: {r.stdout}")
    else:
        check(int(m.group(1)) <= TOLERANCE * W * H, f"the 2x2 wall differs from the program's frame: {r.stdout}")
    print(f"{case}: the program wrote {written} bytes a frame, the stream carried {min(shipped)}..{max(shipped)}; "
          f"EGL and OSMesa replay its {total} frames pixel-identically; the 2x2 wall differs in {m.group(1)} pixels "
          f"(at most {m.group(2)} a channel)")


if __name__ == "__main__":
    main(sys.argv[1])
    print("PASS")
