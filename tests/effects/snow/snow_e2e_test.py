#!/usr/bin/env python3
"""Falling snow end to end, through the glcast command.

    snow_e2e_test.py CASE      with GLCAST, APPS_DIR, OUT_DIR in the environment

determinism: two `glcast replay --effects snow` runs of a committed capture write identical PNGs,
  and they differ from a replay without effects.
mosaic: `glcast run --effects snow --config wall-2x2.json` on ff_scene; the stitched tiles equal
  a replay of the same stream over the whole canvas with snow, within TOLERANCE: flakes are drawn
  in each tile with the tile's own transform, so llvmpipe rounds a few edge pixels of the quads
  differently at tile offsets, as it does for the program's own geometry (tests/e2e/wall_test.py).
  Tiles replayed with `glcast replay --config --tile` equal the slaves' tiles exactly.
bad_input: unknown effects and parameters, values that are not numbers or out of range are
  refused with the name, exit 2 (an odd texture size when the pass is built, exit 1).
foe: ff_scene with its camera moving straight forward (--camera dolly), replayed on the four
  tiles of wall-2x2.json with spectral snow only: in every tile the snow (each frame minus the
  same frame without snow) moves away from the focus of expansion, measured with
  `glcast image motion` between consecutive frames.
"""
import math
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "e2e"))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
DATA = os.path.join(ROOT, "tests", "data")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "snow")
TOLERANCE = 2e-3


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(cmd, env=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def compare(a, b):
    r = run([GLCAST, "image", "compare", a, b])
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    check(m, f"compare {a} {b}: {r.stdout} {r.stderr}")
    return int(m.group(1)), int(m.group(2))


def replay(capture, out, extra):
    shutil.rmtree(out, ignore_errors=True)
    r = run([GLCAST, "replay", capture, "--out", out] + extra)
    check(r.returncode == 0, f"replay failed: {r.stdout} {r.stderr}")
    return sorted(os.listdir(out))


def case_determinism():
    capture = os.path.join(DATA, "ff_scene.glcs")
    a = replay(capture, os.path.join(OUT, "a"), ["--effects", "snow"])
    b = replay(capture, os.path.join(OUT, "b"), ["--effects", "snow"])
    plain = replay(capture, os.path.join(OUT, "plain"), [])
    check(a and a == b == plain, f"frame lists differ: {a} {b} {plain}")
    for f in a:
        differing, _ = compare(os.path.join(OUT, "a", f), os.path.join(OUT, "b", f))
        check(differing == 0, f"{f}: two snow replays differ in {differing} pixels")
        with_snow, _ = compare(os.path.join(OUT, "a", f), os.path.join(OUT, "plain", f))
        print(f"{f}: identical reruns; snow changed {with_snow} pixels")
        check(with_snow > 1000, f"{f}: snow changed only {with_snow} pixels")


def case_mosaic():
    frames = 8
    out = os.path.join(OUT, "mosaic")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture = os.path.join(out, "capture.glcs")
    with Xvfb():
        env = dict(os.environ, GLCAST_CAPTURE=capture)
        r = run([GLCAST, "run", "--config", os.path.join(ROOT, "display_configs", "wall-2x2.json"), "--backend",
                 "egl", "--out", out, "--frames", str(frames), "--effects", "snow", "--",
                 os.path.join(APPS, "ff_scene"), "--frames", "100"], env=env)
    check(r.returncode == 0, f"glcast run failed ({r.returncode}): {r.stderr[-3000:]}")
    last = f"frame-{frames - 1:06d}.png"
    tiles = [os.path.join(out, t, last) for t in ("top-left", "top-right", "bottom-left", "bottom-right")]
    stitched = os.path.join(out, "mosaic.png")
    r = run([GLCAST, "image", "mosaic", "2x2", stitched] + tiles)
    check(r.returncode == 0, r.stderr)
    canvas = os.path.join(out, "canvas")
    r = run([GLCAST, "replay", capture, "--canvas", "1280x960", "--tile-rect", "0,0,1280,960", "--frames",
             f"0:{frames - 1}", "--out", canvas, "--effects", "snow"])
    check(r.returncode == 0, f"canvas replay failed: {r.stdout} {r.stderr}")
    plain = os.path.join(out, "plain")
    r = run([GLCAST, "replay", capture, "--canvas", "1280x960", "--tile-rect", "0,0,1280,960", "--frames",
             f"{frames - 1}:{frames - 1}", "--out", plain])
    check(r.returncode == 0, f"plain replay failed: {r.stdout} {r.stderr}")
    # A tile replayed from the capture (glcast replay --config --tile) is the slave's tile.
    for t in ("top-left", "bottom-right"):
        again = os.path.join(out, "again-" + t)
        r = run([GLCAST, "replay", capture, "--config", os.path.join(ROOT, "display_configs", "wall-2x2.json"),
                 "--tile", t, "--frames", f"{frames - 1}:{frames - 1}", "--out", again, "--effects", "snow"])
        check(r.returncode == 0, f"tile replay failed: {r.stdout} {r.stderr}")
        same, _ = compare(os.path.join(again, last), os.path.join(out, t, last))
        check(same == 0, f"{t}: glcast replay --tile differs from the slave's tile in {same} pixels")
    differing, max_diff = compare(stitched, os.path.join(canvas, last))
    with_snow, _ = compare(os.path.join(canvas, last), os.path.join(plain, last))
    total = 1280 * 960
    print(f"mosaic with snow vs canvas with snow: {differing} of {total} pixels differ "
          f"({100.0 * differing / total:.3f}%), max channel difference {max_diff}; snow changed {with_snow} pixels")
    check(with_snow > total // 4, "no snow on the canvas")
    check(differing <= TOLERANCE * total, f"mosaic differs from the canvas in {differing} pixels")


def case_bad_input():
    capture = os.path.join(DATA, "ff_scene.glcs")
    for args, message in ((["--effects", "snow,fog"], 'unknown effect "fog"'),
                          (["--effect-param", "snow.size=big"], 'snow.size: expected a number, got "big"'),
                          (["--effect-param", "snow.size=9"], None),
                          (["--effect-param", "snow.size=7"], "snow.size = 7 is out of range [8, 2048]"),
                          (["--effect-param", "snow.sise=8"], 'unknown effect parameter "snow.sise" (did you mean "snow.size"?'),
                          (["--effect-param", "snow.particles"], "--effect-param takes NAME=VALUE")):
        r = run([GLCAST, "replay", capture, "--effects", "snow"] + args)
        if message is None:  # valid syntax, refused when the pass is built: an odd texture size
            check(r.returncode == 1 and "snow.size must be even" in r.stderr, f"{args}: {r.returncode} {r.stderr}")
        else:
            check(r.returncode == 2 and message in r.stderr, f"{args}: exit {r.returncode}, {r.stderr}")
        print(f"{' '.join(args)}: exit {r.returncode}: {r.stderr.splitlines()[0]}")
    r = run([GLCAST, "run", "--effects", "hail", "--", "true"])
    check(r.returncode == 2 and 'unknown effect "hail"' in r.stderr, f"run: {r.returncode} {r.stderr}")


def case_foe():
    out = os.path.join(OUT, "foe")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture = os.path.join(out, "dolly.glcs")
    frames = 14
    with Xvfb():
        r = run([GLCAST, "capture", "-o", capture, "--frames", str(frames), "--",
                 os.path.join(APPS, "ff_scene"), "--size", "640x480", "--frames", str(frames), "--camera", "dolly"])
    check(r.returncode == 0, f"capture failed: {r.stdout} {r.stderr}")
    config = os.path.join(ROOT, "display_configs", "wall-2x2.json")
    tiles = {"top-left": (0, 0), "top-right": (640, 0), "bottom-left": (0, 480), "bottom-right": (640, 480)}
    # The camera moves 0.2 units a frame (12 units/s) towards -z; snow falls 1 near-plane distance
    # (0.5 units) a second: flakes approach with u = (0, -0.5, 12) in eye space. The FOE is the
    # projection of -u's direction: a = -u_xy / u_z, canvas y (down) = H/2 (1 - P11 a_y).
    p11 = 1 / math.tan(math.radians(22.5))
    foe = (640.0, 480.0 * (1 - p11 * (0.5 / 12)))
    print(f"focus of expansion at ({foe[0]:.0f}, {foe[1]:.0f}) on the 1280x960 canvas (y down)")
    for tile, (tx, ty) in tiles.items():
        snow, plain = os.path.join(out, tile, "snow"), os.path.join(out, tile, "plain")
        os.makedirs(os.path.join(out, tile))
        for d, extra in ((snow, ["--effects", "snow", "--effect-param", "snow.particles=0"]), (plain, [])):
            r = run([GLCAST, "replay", capture, "--config", config, "--tile", tile, "--out", d] + extra)
            check(r.returncode == 0, f"replay of {tile} failed: {r.stdout} {r.stderr}")
        total = [0, 0]
        for f in range(8, frames - 1):
            a, b = f"frame-{f:06d}.png", f"frame-{f + 1:06d}.png"
            r = run([GLCAST, "image", "motion", os.path.join(snow, a), os.path.join(snow, b), "--crop",
                     "40,40,560,400", "--radius", "24", "--without", os.path.join(plain, a), os.path.join(plain, b)])
            check(r.returncode == 0, r.stderr)
            dx, dy = map(int, r.stdout.split())
            total[0] += dx
            total[1] += dy
        centre = (tx + 320, ty + 240)
        away = (centre[0] - foe[0], centre[1] - foe[1])
        length = math.hypot(*total)
        check(length > 0, f"{tile}: the snow does not move")
        angle = math.degrees(math.acos((away[0] * total[0] + away[1] * total[1]) / (math.hypot(*away) * length)))
        print(f"{tile}: snow moved ({total[0]}, {total[1]}) px over {frames - 9} frames, "
              f"{angle:.1f} degrees from the direction away from the FOE")
        check(angle < 30, f"{tile}: the snow moves {angle:.0f} degrees off the direction away from the FOE")


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    globals()["case_" + sys.argv[1]]()
