#!/usr/bin/env python3
"""Soft shadows end to end (docs/shadows.md): real captures replayed by `glcast replay` and
shown by `glcast run`, with `--effects shadows`.

    shadows_e2e_test.py CASE     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment

occluder: tests/effects/shadows/shadow_occluder.c (a slab floating above a ground plane, a cube
  standing on it, a positional light; no shadows of its own) is captured under Xvfb with its
  own frames. Replayed without effects it is pixel-exact; with shadows the ground under the
  slab, where ray casting from the light puts the umbra, is darkened by the strength, a corner
  of the ground far from both objects and the sky keep their bytes, no pixel brightens, and
  the penumbra at the slab's shadow is wider than at the cube's base (contact hardening).
  `glcast run --effects shadows` on the live program shows the same frame as the replay.
ff_scene, core_scene: the committed captures (fixed function; a core-profile shader program)
  replay pixel-exact without effects; with shadows, pixels darken, none brighten, the sky keeps
  its bytes.
mosaic: the tiles of wall-2x2.json, each replayed with shadows (`--config --tile`), stitched
  with `glcast image mosaic`, equal the canvas replayed with shadows within the tolerance below.

Tolerance of the mosaic: each tile re-renders the camera depth of its own rectangle plus a
guard band through another clip-space correction, and llvmpipe rounds a few silhouette pixels
differently there (the same happens to the program's own image, see tests/e2e/wall_test.py);
a hard-shadow test that flips on such a pixel moves an edge by a pixel. Measured: 11 pixels of
1280x960 differ on the occluder (0.0009%), 47 on ff_scene (0.0038%; 20 differ without
shadows). The test allows 0.02%.
"""
import math
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tests", "e2e"))
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "shadows")
DATA = os.path.join(ROOT, "tests", "data")
CONFIGS = os.path.join(ROOT, "display_configs")
MOSAIC_TOLERANCE = 2e-4
STRENGTH = 0.6  # shadows.strength's default


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(cmd, env=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def headless():
    return {k: v for k, v in os.environ.items() if k != "DISPLAY"}


def compare(a, b):
    r = run([GLCAST, "image", "compare", a, b])
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    check(m, f"compare {a} {b}: {r.stdout} {r.stderr}")
    return int(m.group(1)), int(m.group(2))


def replay(capture, out, *extra):
    os.makedirs(os.path.dirname(out), exist_ok=True)
    r = run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] + list(extra), env=headless())
    check(r.returncode == 0, f"replay {' '.join(extra)} failed: {r.stdout[-2000:]} {r.stderr[-2000:]}")
    return r


def capture_occluder(out, frames=3):
    capture, program = os.path.join(out, "capture.glcs"), os.path.join(out, "program")
    with Xvfb():
        r = run([GLCAST, "capture", "-o", capture, "--frames", str(frames), "--",
                 os.path.join(APPS, "shadow_occluder"), "--size", "640x480", "--frames", str(frames)],
                env=dict(os.environ, GLCAST_SNAPSHOT_DIR=program))
    check(r.returncode == 0, f"capture failed: {r.stderr[-2000:]}")
    return capture, program


# The occluder's camera (shadow_occluder.c): eye (0, 5, 8) looking at (0, 0.5, 0), 45 degrees.
def project(point, width=640, height=480):
    eye, target = (0.0, 5.0, 8.0), (0.0, 0.5, 0.0)
    f = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in f))
    f = [c / n for c in f]
    s = [-f[2], 0.0, f[0]]  # f x (0, 1, 0), normalized (f has no x component here)
    n = math.sqrt(sum(c * c for c in s))
    s = [c / n for c in s]
    u = [s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]]
    d = [p - e for p, e in zip(point, eye)]
    x, y, z = sum(a * b for a, b in zip(s, d)), sum(a * b for a, b in zip(u, d)), sum(a * b for a, b in zip(f, d))
    focal = 1 / math.tan(math.radians(22.5))
    ndc_x, ndc_y = focal * height / width * x / z, focal * y / z
    return int((ndc_x + 1) / 2 * width), int((1 - ndc_y) / 2 * height)  # from the top left


def on_ground_from_light(point, light=(0.5, 6.0, 1.0)):
    t = light[1] / (light[1] - point[1])
    return (light[0] + (point[0] - light[0]) * t, 0.0, light[2] + (point[2] - light[2]) * t)


def luminance(p):
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]


def darkening_width(before, after, start, step, limit=60):
    """Pixels along `step` from `start` over which the after/before ratio goes from its first
    value (inside the shadow) to within 2% of 1 (lit), i.e. the penumbra's visible width."""
    x, y = start
    first = None
    for i in range(limit):
        px, py = x + i * step[0], y + i * step[1]
        ratio = luminance(after[py][px]) / max(luminance(before[py][px]), 1)
        if first is None:
            first = ratio
            inner = None
        if inner is None and ratio > first + 0.05:
            inner = i
        if ratio > 0.98:
            return i - (inner or i)
    return limit


def case_occluder():
    out = os.path.join(OUT, "occluder")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture, program = capture_occluder(out)
    r = replay(capture, os.path.join(out, "off"), "--compare", program)
    print("without effects:", r.stdout.strip())
    shadowed_dir = os.path.join(out, "shadows")
    replay(capture, shadowed_dir, "--effects", "shadows")
    last = "frame-000002.png"
    _, _, before = read_png(os.path.join(program, last))
    _, _, after = read_png(os.path.join(shadowed_dir, last))
    darker = brighter = 0
    for y in range(480):
        for x in range(640):
            a, b = before[y][x], after[y][x]
            darker += b != a
            brighter += any(bc > ac for ac, bc in zip(a, b))
    print(f"with shadows: {darker} of {640 * 480} pixels darkened, {brighter} brightened")
    check(brighter == 0, f"{brighter} pixels brightened")
    check(5000 < darker < 60000, f"{darker} pixels changed")
    # The umbra: the ground below the slab's centre, seen along the light, darkened by the strength.
    ux, uy = project(on_ground_from_light((0.0, 1.5, 0.0)))
    for dx, dy in ((0, 0), (-10, 0), (10, 0), (0, -5), (0, 5)):
        a, b = before[uy + dy][ux + dx], after[uy + dy][ux + dx]
        ratio = luminance(b) / luminance(a)
        check(abs(ratio - (1 - STRENGTH)) < 0.03, f"umbra pixel {ux + dx},{uy + dy}: {a} -> {b} (ratio {ratio:.3f})")
    # Far from both objects: untouched bytes (ground near the bottom left, and the sky).
    for x, y in ((20, 470), (60, 440), (320, 10), (600, 20)):
        check(before[y][x] == after[y][x], f"pixel {x},{y} changed: {before[y][x]} -> {after[y][x]}")
    # Contact hardening: across the slab's shadow edge (blocker 1.5 above the ground) the
    # penumbra is wider than across the shadow at the base of the cube (blocker at 0).
    slab_edge = project(on_ground_from_light((1.0, 1.6, 0.0)))
    cube_edge = project((2.8, 0.0, 0.3))
    slab = darkening_width(before, after, (slab_edge[0] - 15, slab_edge[1]), (1, 0))
    cube = darkening_width(before, after, (cube_edge[0] + 1, cube_edge[1]), (1, 0))
    print(f"penumbra: {slab} px at the slab's shadow edge, {cube} px beside the cube's base")
    check(slab >= cube + 4, "no contact hardening")
    # The live program through `glcast run` shows the same frame.
    live = os.path.join(out, "run")
    with Xvfb():
        r = run([GLCAST, "run", "--backend", "egl", "--out", live, "--frames", "3", "--effects", "shadows", "--",
                 os.path.join(APPS, "shadow_occluder"), "--size", "640x480", "--frames", "3"])
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-2000:]}")
    frames = sorted(os.path.join(dp, f) for dp, _, fs in os.walk(live) for f in fs if f == last)
    check(frames, f"glcast run wrote no {last} under {live}")
    differing, _ = compare(frames[0], os.path.join(shadowed_dir, last))
    print(f"glcast run --effects shadows against the replay: {differing} pixels differ")
    check(differing == 0, "the live wall differs from the replay")


def committed_scene(scene):
    out = os.path.join(OUT, scene)
    shutil.rmtree(out, ignore_errors=True)
    capture = os.path.join(DATA, scene + ".glcs")
    r = replay(capture, os.path.join(out, "off"), "--compare", os.path.join(DATA, scene))
    print("without effects:", r.stdout.strip())
    replay(capture, os.path.join(out, "shadows"), "--effects", "shadows")
    darker = brighter = 0
    for name in sorted(os.listdir(os.path.join(DATA, scene))):
        w, h, before = read_png(os.path.join(DATA, scene, name))
        _, _, after = read_png(os.path.join(out, "shadows", name))
        for y in range(h):
            for x in range(w):
                a, b = before[y][x], after[y][x]
                darker += a != b
                brighter += any(bc > ac for ac, bc in zip(a, b))
        check(before[2][w // 2] == after[2][w // 2], f"{name}: the sky changed")
    print(f"with shadows: {darker} pixels darkened, {brighter} brightened")
    check(brighter == 0 and darker > 300, "shadows missing or brightening")


def case_ff_scene():
    committed_scene("ff_scene")


def case_core_scene():
    """A core-profile shader program (camera in a uniform block, per-object model matrices as
    uniforms): the shadow map is the program's own draws re-rendered through its patched vertex
    shaders. Before that redraw existed, no pixel changed."""
    committed_scene("core_scene")


def case_mosaic():
    out = os.path.join(OUT, "mosaic")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture, _ = capture_occluder(out, frames=2)
    config = os.path.join(CONFIGS, "wall-2x2.json")
    last = "frame-000001.png"
    results = {}
    for name, cap in (("occluder", capture), ("ff_scene", os.path.join(DATA, "ff_scene.glcs")),
                      ("core_scene", os.path.join(DATA, "core_scene.glcs"))):
        frame = last if name == "occluder" else "frame-000002.png"
        tiles = []
        for tile in ("top-left", "top-right", "bottom-left", "bottom-right"):
            replay(cap, os.path.join(out, name, tile), "--config", config, "--tile", tile, "--effects", "shadows")
            tiles.append(os.path.join(out, name, tile, frame))
        stitched = os.path.join(out, name, "mosaic.png")
        r = run([GLCAST, "image", "mosaic", "2x2", stitched] + tiles)
        check(r.returncode == 0, r.stderr)
        canvas = os.path.join(out, name, "canvas")
        replay(cap, canvas, "--canvas", "1280x960", "--tile-rect", "0,0,1280,960", "--effects", "shadows")
        differing, max_diff = compare(stitched, os.path.join(canvas, frame))
        print(f"{name}: 2x2 mosaic with shadows vs the canvas with shadows: {differing} of {1280 * 960} pixels "
              f"differ ({100.0 * differing / (1280 * 960):.4f}%), max channel difference {max_diff}")
        results[name] = differing
    for name, differing in results.items():
        check(differing <= MOSAIC_TOLERANCE * 1280 * 960, f"{name}: mosaic differs in {differing} pixels")


if __name__ == "__main__":
    globals()["case_" + sys.argv[1]]()
