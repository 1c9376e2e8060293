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
blit: drawn by a shader program into a multisampled target and shown by the glBlitFramebuffer
  that resolves it into the viewport's rectangle of the window (before: one frame turned shown
  squeezed into that rectangle, then the scene was left unturned).
widget: a scene another context draws, as a toolkit's GL widget (ff_scene --widget).
grade: a shader program's viewport with a colour grade in its target (a full-target pass with
  no matrix), which must grade every tile's scene.
overlay, overlay_builtins: the pillars drawn into a second target of the viewport's size that
  holds its colour and no depth (Blender's overlay engine's way), by fixed function or built-ins.
winter_shader: the same for a shader program's multisampled viewport shown by a blit.
winter: the fixed-function viewport under snow cover and shadows, then snow: the interface
  keeps every pixel where the screen puts it, and the floor of a tile away from the screen is
  covered and shadowed as the program drawing directly gets it (before: the passes decorated
  the viewport's rectangle of the window, mapped onto the tile, and snow fell on the toolbar).
"""
import json
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
# Its window's rectangles (GL: y up) in drawing order, None the viewport: the gizmo lies over it.
PILLARS_LAYOUT = [(TOOLBAR, 0, 0, 80, 300), (None, 80, 0, 400, 260), (HEADER, 80, 260, 400, 300),
                  (GIZMO, 330, 190, 380, 240)]
FRAME = 2  # the first frame finds the viewport's scene; from the second on it is turned
STEP = 3   # pixels of each tile looked at: every STEP-th of every STEP-th row


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


# pillars --fbo --region at 400x300: its viewport (x 80..400, y 0..260) holds a 60-degree-wide
# frustum of its own aspect, so the window is that frustum extended: its edges' tangents, left,
# right, bottom, top, and its size.
T30 = math.tan(math.radians(30))
TOP = T30 * 260 / 320
PILLARS_SCREEN = (-T30 - 80 * 2 * T30 / 320, T30, -TOP, TOP + 40 * 2 * TOP / 260, 400, 300)


def window_point(yaw, px, py, screen=PILLARS_SCREEN):
    """The program's window point (x, y; GL y up) that its screen puts at pixel (px, py) of a
    1600x1200 tile of cylinder-360.json turned `yaw` degrees right (60 degrees across, 20 below
    the horizon to 30 above), or None where the tile does not face the screen."""
    t20 = math.tan(math.radians(20))
    tx = -T30 + (px + 0.5) / 1600 * 2 * T30
    ty = T30 - (py + 0.5) / 1200 * (T30 + t20)
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    x, z = tx * c + s, tx * s - c  # the direction (tx, ty, -1), turned
    if z >= 0:
        return None
    left, right, bottom, top, w, h = screen
    return (x / -z - left) / (right - left) * w, (ty / -z - bottom) / (top - bottom) * h


def expected(point, layout, margin=1.0):
    """At a window point: the colour of the last of `layout`'s rectangles (colour, x0, y0, x1, y1 in
    drawing order) that holds it, None for the scene (a rectangle of colour None: the viewport; or
    outside the window), "edge" within `margin` window pixels of a boundary."""
    if point is None:
        return None
    x, y = point
    for colour, x0, y0, x1, y1 in reversed(layout):
        if x0 - margin <= x < x1 + margin and y0 - margin <= y < y1 + margin:
            inside = x0 + margin <= x < x1 - margin and y0 + margin <= y < y1 - margin
            return colour if inside else "edge"
    return None


def wall(name, flags, effects=()):
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([GLCAST, "run", "--config", CONFIG, "--backend", "egl", "--out", out, "--frames", str(FRAME + 1)] +
                       list(effects) + ["--", os.path.join(APPS, "pillars")] + flags + ["--size", "400x300", "--frames", "5"],
                       capture_output=True, text=True, timeout=600)
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    return out


def tile_image(out, tile, frame):
    return read_png(os.path.join(out, tile, f"frame-{frame:06d}.png"))


def interface_on_screen(name, out, layout=PILLARS_LAYOUT, screen=PILLARS_SCREEN, frame=FRAME):
    colours = {c for c, *_ in layout if c}
    for i, tile in enumerate(TILES):
        w, h, rows = tile_image(out, tile, frame)
        right = wrong = stray = shown = 0
        for py in range(0, h, STEP):
            for px in range(0, w, STEP):
                want = expected(window_point(60 * i, px, py, screen), layout)
                got = tuple(rows[py][px][:3])
                if want == "edge":
                    continue
                if want is None:
                    stray += got in colours
                    continue
                shown += 1
                right += got == want
                wrong += got != want
        print(f"{name} {tile}: {shown} interface pixels expected, {right} right; {stray} interface-coloured pixels "
              f"where the scene belongs")
        check(wrong <= shown // 100, f"{tile}: {wrong} of {shown} interface pixels are not where the screen puts them")
        check(stray <= w * h // STEP // STEP // 500, f"{tile}: {stray} interface pixels where the scene belongs")


def scene_like_direct(name, out, direct, layout=PILLARS_LAYOUT, screen=PILLARS_SCREEN, frame=FRAME, edges=1):
    """Where no interface lies, each tile shows what it shows of the program drawing the same scene
    directly into its window: within rounding and the scene target's resolution (at most 1 level
    on average, 1% of the pixels more than 8 levels off; `edges` times that where the scene's
    edges are smoothed and the direct program's are not). `direct` may hold tiles of another size
    (the scene target's): each of its pixels is compared with the tile's at its centre."""
    for i, tile in enumerate(TILES):
        w, h, a = tile_image(out, tile, frame)
        dw, dh, b = tile_image(direct, tile, frame)
        step = max(1, STEP * dw // w)
        total = off = n = 0
        for y in range(0, dh, step):
            for x in range(0, dw, step):
                px, py = int((x + 0.5) * w / dw), int((y + 0.5) * h / dh)
                if expected(window_point(60 * i, px, py, screen), layout, margin=2.0) is not None:
                    continue
                d = max(abs(a[py][px][k] - b[y][x][k]) for k in range(3))
                total, off, n = total + d, off + (d > 8), n + 1
        print(f"{name} {tile}: the scene ({n} pixels) differs from the program drawing directly by "
              f"{total / max(n, 1):.2f} levels on average, {100 * off / max(n, 1):.2f}% of pixels more than 8")
        check(total <= n * edges and off <= n * edges // 100, f"{tile}: the scene differs from the directly drawn one")


def config_of_size(path, width, height):
    """cylinder-360.json with tiles of width x height pixels: the same directions at another resolution."""
    with open(CONFIG) as f:
        config = json.load(f)
    for i, tile in enumerate(config["tiles"]):
        tile.update(x=i * width, y=0, width=width, height=height)
    config["canvas"] = {"width": 6 * width, "height": height}
    with open(path, "w") as f:
        json.dump(config, f)
    return path


def case(name, flags, viewport_flags=(), region_flags=(), edges=1, direct_flags=(), own_colours=None):
    out = wall(name, flags + ["--fbo", "--region"] + list(region_flags) + ["--hud"] + list(viewport_flags))
    # (the toolbar's right edge lies on the seam of yaw300 and yaw000: on yaw300's side the
    # toolbar hides that seam's pillar; a graded scene's pillars are not their own colours)
    if own_colours if own_colours is not None else not direct_flags:
        pillars_on_tiles(name, out, FRAME, hidden_seams=("yaw300",))
    interface_on_screen(name, out)
    direct = wall(name + "_direct", flags + list(direct_flags))
    scene_like_direct(name, out, direct, edges=edges)


def case_grade():
    # A colour grade in the viewport's target: a full-target triangle with no matrix (as
    # Blender's outline and background passes are). It works on the turned picture, so it covers
    # every tile's scene; before, it was taken for a HUD and turned onto the program's screen:
    # graded on the front tile's screen only. Compared with the program grading a scene of the
    # window's shape (pillars --shader --fbo --grade), which the cylinder turns as ever.
    case("grade", ["--shader"], ["--grade"], direct_flags=["--fbo", "--grade"])


def case_overlay(flags=()):
    # The pillars drawn into a second target that holds the viewport's colour and no depth, as
    # Blender's overlay engine draws its grid, outlines and object centres: before, that target
    # was not taken for the scene's and its draws were left unturned (every tile showed the
    # program's pillars over its own floor).
    case("overlay" + "".join(f.replace("--", "_") for f in flags), list(flags), ["--overlay"],
         direct_flags=["--overlay"], own_colours=True)


def case_overlay_builtins():
    case_overlay(["--builtins"])


def case_winter(flags=(), region=("--fbo", "--region", "--hud"), prefix="winter", edges=1):
    # (the toolbar's right edge lies on a seam: tiles are compared one by one)
    flags, region = list(flags), list(flags) + list(region)
    plain, plain_direct = wall(prefix + "_plain", region), wall(prefix + "_plain_direct", flags)
    for effects in (["--effects", "cover,shadows"], ["--effects", "snow", "--effect-param", "snow.spectral=0"]):
        name = prefix + "_" + effects[1].replace(",", "_")
        out = wall(name, region, effects)
        interface_on_screen(name, out)
        if effects[1] == "snow":
            continue
        direct = wall(name + "_direct", flags, effects)
        for tile in ("yaw060", "yaw120", "yaw180"):
            frame = f"frame-{FRAME:06d}.png"
            got = floor_changes(read_png(os.path.join(plain, tile, frame)), read_png(os.path.join(out, tile, frame)))
            want = floor_changes(read_png(os.path.join(plain_direct, tile, frame)),
                                 read_png(os.path.join(direct, tile, frame)))
            print(f"{name} {tile}: floor, whiter, darker {got}; the program drawing directly {want}")
            # (`edges`: a multisampled scene's floor has smoothed edges, stretched over the tile,
            # where the direct program's pixels are all the floor's colour)
            check(got[0] > 10000 and abs(got[0] - want[0]) <= edges * want[0] // 50,
                  f"{tile}: the floor differs: {got} {want}")
            # (the shadow map fits the program's frustum, whose aspect is the viewport's here)
            check(abs(got[1] / got[0] - want[1] / want[0]) <= 0.02,
                  f"{tile}: covered unlike the direct program's: {got} {want}")
            check(abs(got[2] / got[0] - want[2] / want[0]) <= 0.01,
                  f"{tile}: shadowed unlike the direct program's: {got} {want}")


def case_winter_shader():
    # A shader program's multisampled viewport resolved into the window by a blit. Before, its
    # depth was blitted into the whole window's rectangle, which GL refuses from samples at
    # another size: no cover, no shadows on any tile (and without samples, a nearest stretch of
    # the depth: the cover in stripes where the steps had no normal).
    # (408,365 floor pixels on yaw060 against the direct program's 417,303: edges)
    case_winter(["--shader"], ["--fbo", "--region", "--blit", "--msaa", "--hud"], "winter_shader", edges=2)


def case_widget():
    # ff_scene --widget (320x240): a second context, which never presents, draws the scene into a
    # framebuffer object of 200x180 in frames 0 and 4 only (as Qt's QOpenGLWidget draws when its
    # view changes); every frame the window's context draws a grey background, that texture at
    # (80, 30), a toolbar along the top and a label over the widget. From the widget's drawing
    # in frame 4 on, its scene is turned, the window's frame on the program's screen.
    top = math.tan(math.radians(22.5))
    tx, ty = top * 200 / 180, top  # the widget's frustum: tangents of its right and top edges
    screen = (-tx - 80 * 2 * tx / 200, tx + 40 * 2 * tx / 200, -ty - 30 * 2 * ty / 180, ty + 30 * 2 * ty / 180, 320, 240)
    grey, blue = (199, 199, 199), (40, 90, 200)
    layout = [(grey, 0, 0, 320, 240), (None, 80, 30, 280, 210), (blue, 0, 224, 320, 240), (blue, 84, 34, 144, 50)]
    out, direct = (os.path.join(OUT, n) for n in ("widget", "widget_direct"))
    os.makedirs(OUT, exist_ok=True)
    # (the widget's 200x180 picture is stretched over 1600x1200 tiles: it is compared with the
    # program drawing directly onto tiles of 200x180)
    small = config_of_size(os.path.join(OUT, "cylinder-200x180.json"), 200, 180)
    for d, args, config in ((out, ["--widget"], CONFIG), (direct, [], small)):
        shutil.rmtree(d, ignore_errors=True)
        r = subprocess.run([GLCAST, "run", "--config", config, "--backend", "egl", "--out", d, "--frames", "5", "--",
                            os.path.join(APPS, "ff_scene")] + args + ["--size", "320x240", "--frames", "6"],
                           capture_output=True, text=True, timeout=600)
        check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    interface_on_screen("widget", out, layout, screen, frame=4)
    scene_like_direct("widget", out, direct, layout, screen, frame=4)


def case_fixed():
    case("fixed", [])


def case_builtins():
    case("builtins", ["--builtins"], ["--post"])


def case_blit():
    # (multisampled, the scene's edges are smoothed, then stretched five times over the tile: bands
    # of a few pixels the direct program's aliased edges do not have; 1.05 levels and 2.06% of
    # pixels more than 8 off on yaw000, every such pixel on an edge)
    case("blit", ["--shader"], region_flags=["--blit", "--msaa"], edges=3)


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
