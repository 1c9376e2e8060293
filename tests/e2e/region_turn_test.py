#!/usr/bin/env python3
"""A scene shown in part of the window, on the tiles of a 360-degree cylinder: pillars --fbo
--region --hud (tests/apps_extra/pillars.c) draws its ring of pillars into a framebuffer object
of its 3D viewport's size (320x260 of a 400x300 window, its own aspect) and shows it there
between a toolbar and a header, with a gizmo over it, as a content suite composites its
regions. On cylinder-360.json every tile must face its pillar with the seams' pillars on both
sides (as the program drawing directly into its window does), the interface must lie on the
program's screen (the toolbar, the header and the gizmo exactly where the viewport's frustum,
extended to the whole window, puts them; nowhere else), and the tiles that do not see that
screen must show what they show of the program drawing the same scene directly (within
rounding and the viewport target's resolution). Before, the viewport's target was not turned
and the toolbar was taken for the draw that shows the scene: every tile showed the window as
drawn, the toolbar down its left fifth.

    region_turn_test.py CASE     with GLCAST, APPS_DIR, OUT_DIR in the environment

fixed: the viewport drawn by fixed function and shown by a fixed-function textured quad.
builtins: drawn by a shader program on the built-ins, copied by a post-processing draw into a
  second target of its size, and shown by a GLSL texture blit (Blender's viewport's way).
winter: the fixed-function viewport under snow cover and shadows, then snow: the interface
  keeps every pixel where the screen puts it, and the floor of a tile away from the screen is
  covered and shadowed as the program drawing directly gets it (before: the passes decorated
  the viewport's rectangle of the window, mapped onto the tile, and snow fell on the toolbar).
"""
import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pillars_scene import floor_changes  # noqa: E402
from png import read_png  # noqa: E402
from wall_test import pillars_on_tiles  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
CONFIG = os.path.join(ROOT, "display_configs", "cylinder-360.json")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "region_turn")
TILES = [f"yaw{60 * i:03d}" for i in range(6)]
TOOLBAR, HEADER, GIZMO = (60, 62, 70), (45, 48, 55), (230, 50, 40)  # pillars.c --region --hud
# Window rectangles (GL: y up) of the interface, in drawing order: the gizmo lies over the viewport.
INTERFACE = [(TOOLBAR, 0, 0, 80, 300), (HEADER, 80, 260, 400, 300), (GIZMO, 330, 190, 380, 240)]
FRAME = 2  # the first frame finds the viewport's scene; from the second on it is turned
STEP = 3   # pixels of each tile looked at: every STEP-th of every STEP-th row


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def window_point(yaw, px, py):
    """The program's window point (x, y; GL y up) that its screen puts at pixel (px, py) of a
    1600x1200 tile of cylinder-360.json turned `yaw` degrees right (60 degrees across, 20 below
    the horizon to 30 above), or None where the tile does not face the screen. The viewport (x
    80..400, y 0..260) holds a 60-degree-wide frustum of its own aspect: the window is that
    frustum extended."""
    t30, t20 = math.tan(math.radians(30)), math.tan(math.radians(20))
    tx = -t30 + (px + 0.5) / 1600 * 2 * t30
    ty = t30 - (py + 0.5) / 1200 * (t30 + t20)
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    x, z = tx * c + s, tx * s - c  # the direction (tx, ty, -1), turned
    if z >= 0:
        return None
    top = t30 * 260 / 320
    return 80 + (x / -z / t30 + 1) / 2 * 320, (ty / -z / top + 1) / 2 * 260


def expected(point, margin=1.0):
    """The interface's colour at a window point, None for the scene (the viewport, or outside
    the window), "edge" within `margin` window pixels of a boundary."""
    if point is None:
        return None
    x, y = point
    for colour, x0, y0, x1, y1 in reversed(INTERFACE):
        if x0 - margin <= x < x1 + margin and y0 - margin <= y < y1 + margin:
            inside = x0 + margin <= x < x1 - margin and y0 + margin <= y < y1 - margin
            return colour if inside else "edge"
    if -margin <= x < 400 + margin and -margin <= y < 300 + margin and not (
            margin <= x < 400 - margin and margin <= y < 300 - margin):
        return "edge"
    return None


def wall(name, flags, effects=()):
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([GLCAST, "run", "--config", CONFIG, "--backend", "egl", "--out", out, "--frames", str(FRAME + 1)] +
                       list(effects) + ["--", os.path.join(APPS, "pillars")] + flags + ["--size", "400x300", "--frames", "5"],
                       capture_output=True, text=True, timeout=600)
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    return out


def interface_on_screen(name, out):
    for i, tile in enumerate(TILES):
        w, h, rows = read_png(os.path.join(out, tile, f"frame-{FRAME:06d}.png"))
        right = wrong = stray = shown = 0
        for py in range(0, h, STEP):
            for px in range(0, w, STEP):
                want = expected(window_point(60 * i, px, py))
                got = tuple(rows[py][px][:3])
                if want == "edge":
                    continue
                if want is None:
                    stray += got in (TOOLBAR, HEADER, GIZMO)
                    continue
                shown += 1
                right += got == want
                wrong += got != want
        print(f"{name} {tile}: {shown} interface pixels expected, {right} right; {stray} interface-coloured pixels "
              f"where the scene belongs")
        check(wrong <= shown // 100, f"{tile}: {wrong} of {shown} interface pixels are not where the screen puts them")
        check(stray <= w * h // STEP // STEP // 500, f"{tile}: {stray} interface pixels where the scene belongs")
    # (the toolbar lies left of the front tile's frustum, the header and the gizmo on it)


def away_from_screen(name, out, direct):
    for tile in ("yaw120", "yaw180"):
        w, h, a = read_png(os.path.join(out, tile, f"frame-{FRAME:06d}.png"))
        _, _, b = read_png(os.path.join(direct, tile, f"frame-{FRAME:06d}.png"))
        total = off = 0
        for y in range(0, h, STEP):
            for x in range(0, w, STEP):
                d = max(abs(a[y][x][k] - b[y][x][k]) for k in range(3))
                total += d
                off += d > 8
        n = len(range(0, h, STEP)) * len(range(0, w, STEP))
        print(f"{name} {tile}: differs from the program drawing directly by {total / n:.2f} levels on average, "
              f"{100 * off / n:.2f}% of pixels more than 8")
        check(total / n <= 1 and off <= n // 100, f"{tile} differs from the directly drawn scene")


def case(name, flags, viewport_flags=()):
    out = wall(name, flags + ["--fbo", "--region", "--hud"] + list(viewport_flags))
    # (the toolbar's right edge lies on the seam of yaw300 and yaw000: on yaw300's side the
    # toolbar hides that seam's pillar)
    pillars_on_tiles(name, out, FRAME, hidden_seams=("yaw300",))
    interface_on_screen(name, out)
    direct = wall(name + "_direct", flags)
    away_from_screen(name, out, direct)


def case_winter():
    # (the toolbar's right edge lies on a seam: tiles are compared one by one)
    region = ["--fbo", "--region", "--hud"]
    plain, plain_direct = wall("winter_plain", region), wall("winter_plain_direct", [])
    for effects in (["--effects", "cover,shadows"], ["--effects", "snow", "--effect-param", "snow.spectral=0"]):
        name = "winter_" + effects[1].replace(",", "_")
        out = wall(name, region, effects)
        interface_on_screen(name, out)
        if effects[1] == "snow":
            continue
        direct = wall(name + "_direct", [], effects)
        for tile in ("yaw060", "yaw120", "yaw180"):
            frame = f"frame-{FRAME:06d}.png"
            got = floor_changes(read_png(os.path.join(plain, tile, frame)), read_png(os.path.join(out, tile, frame)))
            want = floor_changes(read_png(os.path.join(plain_direct, tile, frame)),
                                 read_png(os.path.join(direct, tile, frame)))
            print(f"{name} {tile}: floor, whiter, darker {got}; the program drawing directly {want}")
            check(got[0] > 10000 and abs(got[0] - want[0]) <= want[0] // 50, f"{tile}: the floor differs: {got} {want}")
            # (the shadow map fits the program's frustum, whose aspect is the viewport's here)
            check(abs(got[1] - want[1]) <= want[0] // 50, f"{tile}: covered unlike the direct program's: {got} {want}")
            check(abs(got[2] - want[2]) <= want[0] // 100, f"{tile}: shadowed unlike the direct program's: {got} {want}")


def case_fixed():
    case("fixed", [])


def case_builtins():
    case("builtins", ["--builtins"], ["--post"])


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
