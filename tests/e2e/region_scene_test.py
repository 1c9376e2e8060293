#!/usr/bin/env python3
"""A scene shown in part of the window by its own context, as a content suite shows its 3D
viewport (tests/apps_extra/pillars.c --fbo --region): the program draws the ring of pillars into a
framebuffer object of the viewport's size (320x260 of a 400x300 window) and composites it with a
textured quad between a toolbar and a header, then a gizmo over it. Blender draws each region so.

With every pass the viewport is decorated as the same scene drawn directly into a 320x260 window
is (pillars --size 320x260): its floor covered and shadowed as much, within 2%; snow falls in the
viewport; and not one pixel of the toolbar, the header or the gizmo changes under any pass. So for a
fixed-function scene, one by GLSL built-ins (shown by a GLSL texture blit), one resolved from a
multisampled target, one resolved from it into the window by glBlitFramebuffer, and one whose
colour is copied by a post-processing draw into a second target that shares its depth (Blender's
viewport resolves its engines' colour so) before it is shown. On a 640x480 canvas as a 2x2 wall
the four tiles stitched equal the canvas within rounding. Before, the passes found no view in
any frame ("no draw with a perspective projection"): the viewport's target has neither the
window's size nor its shape.

    region_scene_test.py     with GLCAST, APPS_DIR, OUT_DIR in the environment
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pillars_scene import floor_changes  # noqa: E402
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "region_scene")
REGION = (80, 0, 400, 260)  # pillars.c --region at 400x300: x0, y0 (GL, from the bottom), x1, y1
PASSES = {"cover": ["--effects", "cover"], "shadows": ["--effects", "shadows"],
          "screen": ["--effects", "shadows", "--effect-param", "shadows.method=screen-space"],
          # (snow alone re-renders nothing: the slave then patches no shader, and the viewport's
          # place is found by drawing the program's own blit again unpatched)
          "snow": ["--effects", "snow", "--effect-param", "snow.spectral=0"]}


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(args, **kw):
    r = subprocess.run(args, capture_output=True, text=True, timeout=300, **kw)
    check(r.returncode == 0, f"{' '.join(args[:3])} failed: {r.stderr[-2000:]}")
    return r


def in_region(x, y, h):
    """Window pixel (x, y from the top) lies in the viewport."""
    return REGION[0] <= x < REGION[2] and REGION[1] <= h - 1 - y < REGION[3]


def replay(capture, out, extra, headless):
    run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] + extra, env=headless)
    return read_png(os.path.join(out, "frame-000001.png"))


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    pillars = os.path.join(APPS, "pillars")
    modes = {"direct": ["--size", "320x260"],
             "region": ["--fbo", "--region", "--hud"], "region_builtins": ["--builtins", "--fbo", "--region", "--hud"],
             "region_msaa": ["--fbo", "--region", "--msaa", "--hud"],
             "region_blit": ["--fbo", "--region", "--blit", "--msaa", "--hud"],
             "region_post": ["--builtins", "--fbo", "--region", "--hud", "--post"]}
    pictures = {}
    for mode, flags in modes.items():
        capture = os.path.join(OUT, f"{mode}.glcs")
        size = [] if mode == "direct" else ["--size", "400x300"]
        with Xvfb():
            run([GLCAST, "capture", "-o", capture, "--", pillars] + flags + size + ["--frames", "3"])
        pictures[mode] = {"plain": replay(capture, os.path.join(OUT, f"{mode}-plain"), [], headless)}
        for name, extra in PASSES.items():
            pictures[mode][name] = replay(capture, os.path.join(OUT, f"{mode}-{name}"), extra, headless)
    everywhere = lambda x, y, h: True  # noqa: E731
    direct = pictures["direct"]
    floor, covered, _ = floor_changes(direct["plain"], direct["cover"], everywhere)
    _, _, shadowed = floor_changes(direct["plain"], direct["shadows"], everywhere)
    print(f"direct 320x260: floor {floor} px, covered {covered}, shadowed {shadowed}")
    check(covered > floor // 2 and shadowed > 100, "the scene drawn directly is not decorated")
    for mode in modes:
        if mode == "direct":
            continue
        p = pictures[mode]
        w, h, plain = p["plain"]
        # The program's own picture: the viewport is the scene drawn directly, but for the gizmo's
        # 2,500 pixels (msaa: its edges blended).
        same = sum(1 for y in range(h) for x in range(w) if in_region(x, y, h) and
                   plain[y][x][:3] == direct["plain"][2][y - (h - REGION[3])][x - REGION[0]][:3])
        check(same >= 0.98 * (320 * 260 - 2500), f"{mode}: the program's viewport is not the scene drawn directly ({same} px)")
        f, c, _ = floor_changes(p["plain"], p["cover"], in_region)
        _, _, s = floor_changes(p["plain"], p["shadows"], in_region)
        snowed = sum(1 for y in range(h) for x in range(w)
                     if in_region(x, y, h) and p["snow"][2][y][x][:3] != plain[y][x][:3])
        print(f"{mode}: viewport floor {f} px, covered {c} ({100 * c / max(1, f):.1f}%), shadowed {s}; "
              f"snow changes {snowed} viewport pixels")
        check(abs(c - covered) <= floor // 50 + 10, f"{mode}: {c} floor pixels covered, the direct scene {covered}")
        check(abs(s - shadowed) <= max(10, shadowed // 50), f"{mode}: {s} floor pixels shadowed, the direct scene {shadowed}")
        check(snowed > 500, f"{mode}: snow changes {snowed} pixels of the viewport")
        # The toolbar, the header and the gizmo (everything outside the viewport's scene) stay.
        kept = [(x, y) for y in range(h) for x in range(w)
                if not in_region(x, y, h) or tuple(plain[y][x][:3]) == (230, 50, 40)]
        for name in PASSES:
            b = p[name][2]
            changed = sum(1 for x, y in kept if b[y][x][:3] != plain[y][x][:3])
            print(f"{mode} {name}: {changed} of the {len(kept)} interface pixels changed")
            check(changed == 0, f"{mode}: {name} changed {changed} of the {len(kept)} interface pixels")
    wall_mosaic(os.path.join(OUT, "region_builtins.glcs"), headless)
    print("a scene shown in part of the window: decorated there as drawn directly, the interface untouched")


def wall_mosaic(capture, headless):
    """On a 640x480 canvas as a 2x2 wall with shadows and cover, the four tiles stitched equal the
    canvas within rounding: the viewport's place, its depth and the interface are mapped to each tile."""
    def tile(name, rect):
        out = os.path.join(OUT, f"wall-{name}")
        run([GLCAST, "replay", capture, "--backend", "egl", "--canvas", "640x480", "--tile-rect", rect,
             "--out", out, "--effects", "shadows,cover", "--frames", "1:1"], env=headless)
        return read_png(os.path.join(out, "frame-000001.png"))[2]

    canvas = tile("canvas", "0,0,640,480")
    tiles = {(x, y): tile(f"{x}-{y}", f"{x},{y},320,240") for y in (0, 240) for x in (0, 320)}
    off = sum(1 for y in range(480) for x in range(640)
              if max(abs(p - q) for p, q in zip(tiles[x // 320 * 320, y // 240 * 240][y % 240][x % 320], canvas[y][x])) > 2)
    print(f"viewport on a 2x2 wall: {off} of 307,200 pixels more than 2 levels off the canvas")
    check(off <= 640 * 480 // 500, f"the 2x2 wall differs from the canvas in {off} pixels")


if __name__ == "__main__":
    main()
