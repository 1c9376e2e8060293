#!/usr/bin/env python3
"""The wall, end to end on loopback: `glcast run` with a display config, real ZeroMQ sockets,
one slave process per tile, headless PNG output.

    wall_test.py CASE      with GLCAST, APPS_DIR, OUT_DIR in the environment

mosaic_*: the tiles of wall-2x2.json, stitched, equal one replay of the same stream at the
  canvas size, within the tolerance below.
  mosaic_fbo_ext: a viewport set while the program's own framebuffer object is bound with
  glBindFramebufferEXT (not an alias of glBindFramebuffer in gl.xml) is not a window viewport,
  and must stay as it is on every tile (tests/apps_extra/fbo_ext.c).
  mosaic_viewport_array: indexed viewports and scissor boxes (glViewportIndexedf[v],
  glViewportArrayv, glScissorIndexed[v], glScissorArrayv, a geometry shader writing
  gl_ViewportIndex) are window coordinates, mapped like glViewport's and glScissor's
  (tests/apps_extra/viewport_array.c).
  The canvas replay is a tile too (one as large as the canvas), so a mapping error can make
  it and the tiles wrong alike; for these two, pixels of the canvas are also checked against
  the program's picture scaled to the canvas.
bezel: every tile of wall-3x2-bezel.json equals its rectangle of the canvas (the bezel strips
  between them are not shown by any tile).
late_join: a slave started after the program has run 100 frames, and the same slave killed
  with SIGKILL and started again, show the frames of a slave that ran from the start.
loss: with every 29th message dropped on purpose, the slave notices, starts over from the
  journal, and its frames still equal the program's own (in lockstep, so that the journal is
  still there for a slave that fell behind).
sigstop: a slave stopped with SIGSTOP does not hold the program back.
timing: glcast run --timing: every frame's swap and each tile's arrival, replay and present,
  ordered, on one clock within the offsets' bounds.

Tolerance of the mosaic: llvmpipe evaluates interpolants relative to the framebuffer's
origin, so a tile (whose viewport is the canvas viewport moved by the tile's offset) rounds a
few interpolated colours one step differently, and an edge pixel can change coverage. Measured
on the test programs: at most 0.002% of the canvas pixels differ; the test allows 0.01%.
"""
import glob
import json
import contextlib
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png import read_png  # noqa: E402
from ports import free_port_run  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
CONFIGS = os.path.join(ROOT, "display_configs")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "wall")
TOLERANCE = 1e-4


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(cmd, env=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def compare(a, b, crop=None):
    r = run([GLCAST, "image", "compare", a, b] + (["--crop", crop] if crop else []))
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    check(m, f"compare {a} {b}: {r.stdout} {r.stderr}")
    return int(m.group(1)), int(m.group(2))


def wall_run(name, config, program, frames, extra_env=None):
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture = os.path.join(out, "capture.glcs")
    env = dict(os.environ, GLCAST_CAPTURE=capture, **(extra_env or {}))
    r = run([GLCAST, "run", "--config", os.path.join(CONFIGS, config), "--backend", "egl", "--out", out,
             "--frames", str(frames), "--"] + program, env=env)
    check(r.returncode == 0, f"glcast run failed ({r.returncode}): {r.stderr[-3000:]}")
    return out, capture


def canvas_replay(capture, out, canvas, frame):
    ref = os.path.join(out, "canvas")
    w, h = canvas
    r = run([GLCAST, "replay", capture, "--canvas", f"{w}x{h}", "--tile-rect", f"0,0,{w},{h}",
             "--frames", f"{frame}:{frame}", "--out", ref], env={k: v for k, v in os.environ.items() if k != "DISPLAY"})
    check(r.returncode == 0, f"canvas replay failed: {r.stdout} {r.stderr}")
    return os.path.join(ref, f"frame-{frame:06d}.png")


def mosaic(program, probes=None, name=None):
    """probes(frame): (x, y, rgb, tolerance, what) that the canvas replay of that frame must show
    at x, y (from the top left): the canvas itself is right, not only the tiles like it. `name`:
    the output's (each case's own: ctest runs them side by side)."""
    frames = 6
    out, capture = wall_run("mosaic_" + (name or os.path.basename(program[0])), "wall-2x2.json", program, frames)
    last = f"frame-{frames - 1:06d}.png"
    tiles = [os.path.join(out, t, last) for t in ("top-left", "top-right", "bottom-left", "bottom-right")]
    for t in tiles:
        check(os.path.exists(t), f"missing tile frame {t}")
    stitched = os.path.join(out, "mosaic.png")
    r = run([GLCAST, "image", "mosaic", "2x2", stitched] + tiles)
    check(r.returncode == 0, r.stderr)
    canvas = canvas_replay(capture, out, (1280, 960), frames - 1)
    differing, max_diff = compare(stitched, canvas)
    print(f"{program[0]}: mosaic vs canvas: {differing} of {1280 * 960} pixels differ, max channel difference {max_diff}")
    wrong = []
    for x, y, rgb, tolerance, what in (probes(frames - 1) if probes else []):
        seen = pixel(canvas, x, y)
        if max(abs(a - b) for a, b in zip(seen, rgb)) > tolerance:
            wrong.append(f"{what} at {x},{y}: {seen}, expected {rgb}")
    if probes:
        print(f"{program[0]}: canvas probes: " + ("; ".join(wrong) if wrong else "all as expected"))
    check(differing <= TOLERANCE * 1280 * 960, f"mosaic differs from the canvas in {differing} pixels")
    check(not wrong, f"the canvas does not show the program's picture: {'; '.join(wrong)}")


def case_mosaic_ff_scene():
    mosaic([os.path.join(APPS, "ff_scene"), "--frames", "100"])


def case_mosaic_core_scene():
    mosaic([os.path.join(APPS, "core_scene"), "--frames", "100"])


def case_mosaic_glfw_dynamic():
    mosaic([os.path.join(APPS, "glfw_dynamic"), "--frames", "100"])


def case_mosaic_glxgears():
    mosaic(["glxgears"])


def case_mosaic_grow():
    # A window grown after its viewport was set, never set again: the tiles map the viewport
    # by the window's new size. Before, they kept it mapped for 32x32 and every tile was black.
    def probes(frame):  # tests/apps_extra/pillars.c: pillar 0 straight ahead, above the horizon
        return [(*window_to_canvas(160, 150), (40, 200, 255), 3, "pillar 0")]
    mosaic([os.path.join(APPS, "pillars"), "--grow", "--size", "320x240", "--frames", "100"], probes, "grow")


def case_mosaic_fragcoord():
    # The scene in a framebuffer object shown by a fragment shader that reads it at gl_FragCoord
    # divided by the window's size (SuperTuxKart's last pass): each tile's fragments are the
    # master window's. Before, every tile (and the canvas) showed the whole scene in its part.
    def probes(frame):  # tests/apps_extra/pillars.c: pillar 0 straight ahead, above the horizon
        return [(*window_to_canvas(160, 150), (40, 200, 255), 3, "pillar 0"),
                (*window_to_canvas(80, 200), (0, 0, 0), 3, "the sky left of pillar 0")]
    mosaic([os.path.join(APPS, "pillars"), "--fbo", "--fragcoord", "--size", "320x240", "--frames", "100"], probes,
           "fragcoord")


def case_mosaic_msaa_blit():
    # A multisampled scene resolved into the window by glBlitFramebuffer at its own size: each
    # tile (and the canvas) scales it. GL resolves samples only at the same size: before, every
    # tile and the canvas were black where the scene is shown.
    def probes(frame):  # tests/apps_extra/pillars.c --region at 320x240: its viewport x 64..320, y 0..208
        return [(*window_to_canvas(192, 120), (40, 200, 255), 3, "pillar 0, straight ahead"),
                (*window_to_canvas(30, 120), (60, 62, 70), 3, "the toolbar")]
    mosaic([os.path.join(APPS, "pillars"), "--shader", "--fbo", "--region", "--blit", "--msaa", "--size", "320x240",
            "--frames", "100"], probes, "msaa_blit")


def window_to_canvas(x, y):
    """A point of the program's 320x240 window (GL: from the bottom left) on the 1280x960
    canvas image (from the top left), in the middle of the 4x4 pixels it becomes."""
    return round(4 * x + 2), round(959 - (4 * y + 2))


def rgb8(*c):
    return tuple(round(255 * v) for v in c)


def fbo_ext_probes(frame):
    # tests/apps_extra/fbo_ext.c: the texture (s, t) lies on the window quad x -0.9..0.35,
    # y -0.85..0.85 (NDC); the fan's white centre is at (0.2, 0.25) of the texture's scene.
    def texture_point(s, t):
        return window_to_canvas((0.1 + 1.25 * s) / 2 * 320, (0.15 + 1.7 * t) / 2 * 240)
    return [(*texture_point(0.6, 0.625), (255, 255, 255), 24, "the fan's white centre inside the texture"),
            (*texture_point(0.1, 0.9), rgb8(0.15 + 0.02 * (frame % 10), 0.1, 0.3), 3, "the texture's clear colour"),
            (*window_to_canvas(272, 100), rgb8(0.9, 0.6, 0.1), 3, "the window's orange triangle"),
            (*window_to_canvas(300, 230), rgb8(0.05, 0.05, 0.08), 3, "the window's clear colour")]


def case_mosaic_fbo_ext():
    mosaic([os.path.join(APPS, "fbo_ext"), "--frames", "100"], fbo_ext_probes)


def case_mosaic_line_width():
    # glLineWidth set while the window is bound, a line drawn into the framebuffer object: 3
    # texels wide there. Before, the width scaled for the window's draws (x4 on this canvas) was
    # kept for the texture's: 12 texels.
    def probes(frame):
        def texture_point(s, t):
            return window_to_canvas((0.1 + 1.25 * s) / 2 * 320, (0.15 + 1.7 * t) / 2 * 240)
        clear = rgb8(0.15 + 0.02 * (frame % 10), 0.1, 0.3)
        return [(*texture_point(0.1, 0.4), (255, 255, 255), 24, "the line's middle"),
                (*texture_point(0.1, 0.4 + 3 / 256), clear, 6, "3 texels above it (the line is 3 wide)"),
                (*texture_point(0.1, 0.4 - 3 / 256), clear, 6, "3 texels below it")]
    mosaic([os.path.join(APPS, "fbo_ext"), "--line", "--frames", "100"], probes, "line_width")


def viewport_array_probes(frame):
    # tests/apps_extra/viewport_array.c: in every viewport, corners inside its scissor box (on
    # either side of a seam it spans) show the viewport's colour; a point of the viewport
    # outside the box shows the clear colour.
    grey = rgb8(0.12, 0.12, 0.14)
    red, green, blue, yellow = rgb8(0.85, 0.2, 0.2), rgb8(0.2, 0.8, 0.3), rgb8(0.2, 0.35, 0.9), rgb8(0.95, 0.85, 0.2)
    return [(*window_to_canvas(15, 15), red, 3, "viewport 0 (red), left of the seam"),
            (*window_to_canvas(165, 95), red, 3, "viewport 0 (red), right of the seam"),
            (*window_to_canvas(183, 55), grey, 3, "viewport 0 beyond scissor box 0"),
            (*window_to_canvas(305, 25), green, 3, "viewport 1 (green), below the seam"),
            (*window_to_canvas(305, 165), green, 3, "viewport 1 (green), above the seam"),
            (*window_to_canvas(205, 90), grey, 3, "viewport 1 beyond scissor box 1"),
            (*window_to_canvas(45, 115), blue, 3, "viewport 2 (blue), below the seam"),
            (*window_to_canvas(165, 225), blue, 3, "viewport 2 (blue), right of the seam"),
            (*window_to_canvas(30, 170), grey, 3, "viewport 2 beyond scissor box 2"),
            (*window_to_canvas(185, 185), yellow, 3, "viewport 3 (yellow)"),
            (*window_to_canvas(245, 230), grey, 3, "viewport 3 beyond scissor box 3"),
            (*window_to_canvas(195, 120), grey, 3, "between the viewports")]


def case_mosaic_viewport_array():
    mosaic([os.path.join(APPS, "viewport_array"), "--frames", "100"], viewport_array_probes)


def case_bezel():
    frames = 4
    out, capture = wall_run("bezel", "wall-3x2-bezel.json", [os.path.join(APPS, "ff_scene"), "--frames", "100"], frames)
    canvas = canvas_replay(capture, out, (2000, 1000), frames - 1)
    worst = 0
    for name, x, y in (("top-left", 0, 0), ("top-middle", 680, 0), ("top-right", 1360, 0),
                       ("bottom-left", 0, 520), ("bottom-middle", 680, 520), ("bottom-right", 1360, 520)):
        tile = os.path.join(out, name, f"frame-{frames - 1:06d}.png")
        check(os.path.exists(tile), f"missing {tile} (tiles: {os.listdir(out)})")
        differing, _ = compare(canvas, tile, f"{x},{y},640,480")
        worst = max(worst, differing)
    print(f"bezel: worst tile differs from its canvas rectangle in {worst} of {640 * 480} pixels")
    check(worst <= TOLERANCE * 640 * 480 * 6, f"a tile differs from its canvas rectangle in {worst} pixels")


def pixel(image, x, y):
    r = run([GLCAST, "image", "pixel", image, f"{x},{y}"])
    check(r.returncode == 0, r.stderr)
    return tuple(int(v) for v in r.stdout.split())


def pillar_colour(k):  # tests/apps_extra/pillars.c
    return (40 + 16 * k, 200 - 12 * k, 255 - 20 * k)


def case_cylinder():
    cylinder("cylinder", os.path.join(CONFIGS, "cylinder-360.json"), [])


def case_cylinder_shader():
    # The same wall for a shader program: the projection comes from the config.
    cylinder("cylinder_shader", os.path.join(ROOT, "tests", "configs", "cylinder-360-shader.json"), ["--shader"])


def case_cylinder_shader_found():
    # The same shader program with the fixed-function config, which states no projection: the
    # slave finds it among the program's matrices (slave/program_camera.h).
    cylinder("cylinder_shader_found", os.path.join(CONFIGS, "cylinder-360.json"), ["--shader"])


def case_cylinder_shader_objects():
    # The projection in a uniform block after a block of 1,024 per-object matrices, all active
    # uniforms (Blender's draw manager's layout): before, the slave looked at the first 1,024
    # uniforms only and never reached the projection (no camera: every tile the same picture).
    cylinder("cylinder_shader_objects", os.path.join(CONFIGS, "cylinder-360.json"), ["--shader", "--objects"])


def case_cylinder_builtins():
    # A shader program that reads the fixed-function matrices through GLSL's built-ins
    # (gl_ModelViewProjectionMatrix) and has no matrix uniform: turned by its GL_PROJECTION.
    cylinder("cylinder_builtins", os.path.join(CONFIGS, "cylinder-360.json"), ["--builtins"])


def case_cylinder_left_handed():
    # A left-handed world and eye space (w = +z), as Irrlicht keeps them (minetest): before, every
    # turned tile lost all of it (turned into a right-handed frustum, the scene lay behind the eye).
    cylinder("cylinder_left_handed", os.path.join(CONFIGS, "cylinder-360.json"), ["--left-handed"])


def case_cylinder_left_handed_mixed():
    # ... with the floor by fixed function and the pillars by built-ins: GL_PROJECTION as the
    # fixed-function draw left it corrected must not be corrected again by glcast_clip.
    cylinder("cylinder_left_handed_mixed", os.path.join(CONFIGS, "cylinder-360.json"),
             ["--builtins", "--left-handed", "--mixed"])


def case_cylinder_builtins_mixed():
    # The floor by fixed function, the pillars by built-ins, right-handed.
    cylinder("cylinder_builtins_mixed", os.path.join(CONFIGS, "cylinder-360.json"), ["--builtins", "--mixed"])


def case_cylinder_mvp():
    # One premultiplied projection * view * model matrix per draw: each draw's camera split alone.
    cylinder("cylinder_mvp", os.path.join(CONFIGS, "cylinder-360.json"), ["--mvp"])


def case_cylinder_mvp_left_handed():
    # ... written in left-handed coordinates (w = +z, SuperTuxKart's u_projection_view_matrix):
    # before, the product did not split (its view came out mirrored) and no tile turned.
    cylinder("cylinder_mvp_left_handed", os.path.join(CONFIGS, "cylinder-360.json"), ["--mvp", "--left-handed"])


def case_cylinder_fbo():
    # The scene drawn into a framebuffer object and shown by a full-window quad (engines since
    # 2010): what is drawn into the scene's target is turned as what the window gets is.
    cylinder("cylinder_fbo", os.path.join(CONFIGS, "cylinder-360.json"), ["--fbo"])


def case_cylinder_fbo_post():
    # ... followed by a post-processing step into a second window-sized target with depth (VTK's
    # way, many engines'): before, that target was taken for the scene's from the second frame on
    # and the scene itself no longer turned.
    cylinder("cylinder_fbo_post", os.path.join(CONFIGS, "cylinder-360.json"), ["--builtins", "--fbo", "--post"], frames=3)


def case_cylinder_fbo_half():
    # ... at half the window's size (a render scale), shader program on the built-ins.
    cylinder("cylinder_fbo_half", os.path.join(CONFIGS, "cylinder-360.json"), ["--builtins", "--fbo", "--half"])


def case_cylinder_fbo_mvp():
    # ... with one premultiplied matrix per draw.
    cylinder("cylinder_fbo_mvp", os.path.join(CONFIGS, "cylinder-360.json"), ["--mvp", "--fbo"])


def case_cylinder_fbo_msaa():
    # ... drawn into a multisampled framebuffer object and resolved by a blit into the texture
    # the window's quad shows.
    cylinder("cylinder_fbo_msaa", os.path.join(CONFIGS, "cylinder-360.json"), ["--fbo", "--msaa"])


def case_cylinder_fbo_mrt():
    # ... into a framebuffer object with two colour attachments, both written.
    cylinder("cylinder_fbo_mrt", os.path.join(CONFIGS, "cylinder-360.json"), ["--fbo", "--mrt"])


def case_cylinder_fbo_fragcoord():
    # ... shown (and post-processed) by fragment shaders that read the scene at gl_FragCoord over
    # the window's size: before, the tiles (1600x1200) repeated the scene in a grid.
    cylinder("cylinder_fbo_fragcoord", os.path.join(CONFIGS, "cylinder-360.json"),
             ["--builtins", "--fbo", "--fragcoord", "--post"], frames=3)


def case_cylinder_fbo_fragcoord_objects():
    # ... with the camera in a uniform block that the window's program declares too and does not
    # read (std140 keeps it active): before, that program's draw was taken for a view into the
    # window, the window for the scene's target, and the scene no longer turned.
    cylinder("cylinder_fbo_fragcoord_objects", os.path.join(CONFIGS, "cylinder-360.json"),
             ["--shader", "--fbo", "--fragcoord", "--objects"], frames=3)


def case_cylinder_fbo_gbuffer():
    # ... drawn twice with one camera, as deferred renderers draw it (SuperTuxKart): into a target
    # of its own, then into the scene's by a program that reads the first at gl_FragCoord. Before,
    # only the last target drawn with the view was turned, and the second pass read the first
    # unturned.
    cylinder("cylinder_fbo_gbuffer", os.path.join(CONFIGS, "cylinder-360.json"),
             ["--mvp", "--fbo", "--gbuffer"], frames=3)


def case_cylinder_reversed():
    # Reversed depth (clip control GL_ZERO_TO_ONE, an infinite far plane mapped to 0, GL_GREATER):
    # the turned projection keeps the program's depth mapping.
    cylinder("cylinder_reversed", os.path.join(CONFIGS, "cylinder-360.json"), ["--reversed"])


def case_cylinder_reversed_builtins():
    cylinder("cylinder_reversed_builtins", os.path.join(CONFIGS, "cylinder-360.json"), ["--builtins", "--reversed"])


def case_cylinder_hud():
    # A HUD panel drawn over the scene in the program's window lies on the program's screen: the
    # front tile shows it where it sees that screen, the others not at all (before: on every tile).
    cylinder_hud("cylinder_hud", [])


def case_cylinder_hud_shader():
    # ... drawn by the shader program, its orthographic matrix in the projection uniform.
    cylinder_hud("cylinder_hud_shader", ["--shader"])


def case_cylinder_hud_builtins():
    # ... drawn by the shader program that reads GL_PROJECTION through gl_ModelViewProjectionMatrix.
    cylinder_hud("cylinder_hud_builtins", ["--builtins"])


def case_cylinder_hud_fbo():
    # ... over a scene drawn into a framebuffer object: the quad that shows the scene is left as
    # drawn, the HUD after it lies on the program's screen.
    cylinder_hud("cylinder_hud_fbo", ["--fbo"])


def case_cylinder_hud_fbo_shader():
    cylinder_hud("cylinder_hud_fbo_shader", ["--shader", "--fbo"])


def case_cylinder_hud_in_scene():
    # ... drawn into the scene's framebuffer object after the pillars, before it is shown (VTK's
    # text actors), over the floor.
    cylinder_hud("cylinder_hud_in_scene", ["--fbo"], after=["--in-scene"], panel=(20, 40, 120, 100))


def case_cylinder_hud_in_scene_shader():
    cylinder_hud("cylinder_hud_in_scene_shader", ["--shader", "--fbo"], after=["--in-scene"], panel=(20, 40, 120, 100))


HUD_COLOUR = (230, 50, 40)  # pillars --hud


def cylinder_hud(name, flags, after=(), panel=(20, 220, 120, 280)):
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    r = run([GLCAST, "run", "--config", os.path.join(CONFIGS, "cylinder-360.json"), "--backend", "egl", "--out", out,
             "--frames", "1", "--", os.path.join(APPS, "pillars")] + flags + ["--hud"] + list(after) +
            ["--size", "400x300", "--frames", "5"])
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    # Where the program's window pixels (`panel`: 20..120, 220..280 of 400x300, GL y up) lie on yaw000
    # (1600x1200, -30..30 across, -20..30 up and down): through their directions from the eye.
    half = math.tan(math.radians(30))
    top = half * 300 / 400

    def on_front_tile(x, y):
        dx, dy = (2 * x / 400 - 1) * half, (2 * y / 300 - 1) * top
        lo, hi = math.tan(math.radians(-20)), math.tan(math.radians(30))
        return (dx / half + 1) / 2 * 1600, 1200 - (dy - lo) / (hi - lo) * 1200  # from the top left

    x0, y1 = on_front_tile(panel[0], panel[1])
    x1, y0 = on_front_tile(panel[2], panel[3])
    seen = {}
    for i in range(6):
        tile = f"yaw{60 * i:03d}"
        w, h, rows = read_png(os.path.join(out, tile, "frame-000000.png"))
        seen[tile] = [(x, y) for y in range(h) for x in range(w) if tuple(rows[y][x][:3]) == HUD_COLOUR]
    inside = [(x, y) for x, y in seen["yaw000"] if x0 - 2 <= x <= x1 + 2 and y0 - 2 <= y <= y1 + 2]
    area = (x1 - x0) * (y1 - y0)
    print(f"{name}: HUD pixels per tile {[len(v) for v in seen.values()]}; on yaw000 {len(inside)} inside the "
          f"expected {x0:.0f}..{x1:.0f} x {y0:.0f}..{y1:.0f} ({area:.0f} px)")
    check(all(not seen[t] for t in seen if t != "yaw000"), "the HUD shows on tiles that do not see the program's screen")
    check(len(inside) >= 0.97 * area and len(inside) == len(seen["yaw000"]),
          f"yaw000 shows {len(seen['yaw000'])} HUD pixels, {len(inside)} where the program's screen puts them")
    pillars_on_tiles(name, out)  # and the scene under it turned as ever


def cylinder(name, config, flags, frames=1):
    # A ring of pillars every 30 degrees around the viewer; six tiles every 60 degrees, each
    # from -30 to +30: pillar 2i stands at the centre of tile i, pillar 2i+1 on the seam
    # between tile i and tile i+1, and must show on both sides of it.
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    r = run([GLCAST, "run", "--config", config, "--backend", "egl", "--out", out,
             "--frames", str(frames), "--", os.path.join(APPS, "pillars")] + flags + ["--size", "400x300", "--frames", "5"])
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    pillars_on_tiles(name, out, frames - 1)


def pillars_on_tiles(name, out, last=0, hidden_seams=()):
    """`hidden_seams`: tiles whose right edge's pillar something else covers."""
    tiles = [f"yaw{60 * i:03d}" for i in range(6)]
    frame = f"frame-{last:06d}.png"
    y = 1200 * 30 // 50 - 100  # a little above the horizon (top +30, bottom -20 degrees)
    for i, tile in enumerate(tiles):
        image = os.path.join(out, tile, frame)
        centre = pixel(image, 800, y)
        check(centre == pillar_colour(2 * i), f"{tile} centre shows {centre}, pillar {2 * i} is {pillar_colour(2 * i)}")
        # 10 degrees below the horizon the pillar stands in front of the floor: the depth test
        # (and the depth mapping of the turned projection) put it there.
        below = pixel(image, 800, 1200 * 40 // 50)
        check(below == pillar_colour(2 * i), f"{tile}: below the horizon the floor covers pillar {2 * i} ({below})")
        right = pixel(image, 1599, y)
        left_of_next = pixel(os.path.join(out, tiles[(i + 1) % 6], frame), 0, y)
        seam = pillar_colour((2 * i + 1) % 12)
        if tile in hidden_seams:
            right = seam
        check(right == seam and left_of_next == seam,
              f"seam {tile}|{tiles[(i + 1) % 6]} shows {right}|{left_of_next}, pillar {(2 * i + 1) % 12} is {seam}")
    print(f"{name}: every tile faces its pillar, every seam shows the pillar standing on it on both sides")


def case_swap_barrier():
    # With the barrier, no tile presents frame N+1 before every tile presented frame N.
    out = os.path.join(OUT, "swap_barrier")
    shutil.rmtree(out, ignore_errors=True)
    logs = os.path.join(out, "presents")
    os.makedirs(logs)
    config = os.path.join(ROOT, "tests", "configs", "wall-2x2-barrier.json")
    r = run([GLCAST, "run", "--config", config, "--backend", "egl", "--frames", "60", "--", "glxgears"],
            env=dict(os.environ, GLCAST_TEST_PRESENT_LOG_DIR=logs))
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    check("went alone" not in r.stderr, f"a barrier timed out: {r.stderr[-2000:]}")
    times = {}
    for tile in os.listdir(logs):
        for line in open(os.path.join(logs, tile)):
            frame, t, _ = line.split()
            times.setdefault(int(frame), []).append(float(t))
    frames = sorted(f for f, ts in times.items() if len(ts) == 4)
    check(len(frames) >= 50, f"only {len(frames)} frames presented by all four tiles")
    for a, b in zip(frames, frames[1:]):
        check(max(times[a]) < min(times[b]), f"a tile presented frame {b} before every tile had presented frame {a}")
    spread = max(max(times[f]) - min(times[f]) for f in frames)
    print(f"swap barrier: {len(frames)} frames, every tile presented frame N before any presented N+1; "
          f"widest spread within a frame {spread * 1000:.1f} ms")


def read_timing(path):
    """glcast run --timing's lines: {frame: line}, each frame once."""
    lines = {}
    for text in open(path):
        line = json.loads(text)
        check(line["frame"] not in lines, f"frame {line['frame']} written twice")
        lines[line["frame"]] = line
    return lines


def case_timing():
    # glcast run --timing on a 2x2 wall of null slaves with the barrier: every frame the tiles
    # drew live has the program's swap and each tile's arrival, replay and present, in that order
    # on one clock; the slaves' clock offsets (the same machine: truly 0) are within their bounds;
    # and no tile presented a frame before every tile had replayed it (the barrier, seen on the
    # clock).
    out = os.path.join(OUT, "timing")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    timing = os.path.join(out, "timing.jsonl")
    config = os.path.join(ROOT, "tests", "configs", "wall-2x2-barrier.json")
    r = run([GLCAST, "run", "--config", config, "--backend", "null", "--frames", "150", "--timing", timing, "--",
             "glxgears"])
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    lines = read_timing(timing)
    tiles = ("top-left", "top-right", "bottom-left", "bottom-right")
    full = sorted(f for f, line in lines.items() if line["swap"] is not None and len(line["tiles"]) == 4)
    check(full, f"no frame with the swap and all four tiles: {list(lines.values())[:3]}")
    # From the first frame all four drew live (before it they join through the journal, which
    # is not timed) to the program's last: every one, complete.
    last_swap = max(f for f, line in lines.items() if line["swap"] is not None)
    missing = [f for f in range(full[0], last_swap + 1) if f not in full]
    check(not missing, f"frames {missing[:10]} (of {full[0]}..{last_swap}) lack the swap or a tile: "
                       f"{[lines.get(f) for f in missing[:2]]}")
    check(last_swap - full[0] >= 100, f"only frames {full[0]}..{last_swap} timed")
    latencies, spreads, worst_error = [], [], 0
    for f in full:
        line = lines[f]
        for tile in tiles:
            t = line["tiles"][tile]
            err = t["clock_error"]
            worst_error = max(worst_error, err)
            check(0 <= err < 0.005, f"frame {f} {tile}: clock error {err} s (the same machine: a round trip)")
            check(abs(t["clock_offset"]) <= err + 1e-6,
                  f"frame {f} {tile}: clock offset {t['clock_offset']} s beyond its bound {err} s on one machine")
            check(line["swap"] <= t["arrived"] + err, f"frame {f} {tile}: arrived before the program swapped: {line}")
            check(t["arrived"] <= t["replayed"] <= t["presented"], f"frame {f} {tile}: times out of order: {t}")
            latencies.append(t["presented"] - line["swap"])
        replayed_all = max(line["tiles"][t]["replayed"] for t in tiles)
        first_present = min(line["tiles"][t]["presented"] for t in tiles)
        worst = max(line["tiles"][t]["clock_error"] for t in tiles)
        check(first_present >= replayed_all - 2 * worst,
              f"frame {f}: a tile presented before every tile had replayed it (the barrier): {line}")
        spreads.append(max(line["tiles"][t]["presented"] for t in tiles) - first_present)
    latencies.sort()
    spreads.sort()
    print(f"timing: frames {full[0]}..{last_swap}, swap to present median {latencies[len(latencies) // 2] * 1000:.2f} ms, "
          f"spread median {spreads[len(spreads) // 2] * 1000:.3f} ms, worst clock error {worst_error * 1e6:.0f} us")


@contextlib.contextmanager
def two_namespaces(name):
    """Two network namespaces joined by a veth pair, made here (10.213.0.1 for the program's,
    10.213.0.2 for a display machine's), with multicast routed; None where they cannot be made."""
    if os.geteuid() != 0 or not shutil.which("ip"):
        print(f"SKIP: {name} needs root and iproute2 to make two network namespaces")
        yield None
        return
    a, b = f"glcast-m{os.getpid()}", f"glcast-s{os.getpid()}"
    va, vb = f"gcm{os.getpid() % 100000}", f"gcs{os.getpid() % 100000}"
    setup = [["ip", "netns", "add", a], ["ip", "netns", "add", b],
             ["ip", "link", "add", va, "type", "veth", "peer", "name", vb],
             ["ip", "link", "set", va, "netns", a], ["ip", "link", "set", vb, "netns", b],
             ["ip", "netns", "exec", a, "ip", "addr", "add", "10.213.0.1/24", "dev", va],
             ["ip", "netns", "exec", b, "ip", "addr", "add", "10.213.0.2/24", "dev", vb]]
    for ns, dev in ((a, va), (b, vb)):
        setup += [["ip", "netns", "exec", ns, "ip", "link", "set", dev, "up"],
                  ["ip", "netns", "exec", ns, "ip", "link", "set", "lo", "up"],
                  ["ip", "netns", "exec", ns, "ip", "route", "add", "224.0.0.0/4", "dev", dev]]
    try:
        for cmd in setup:
            r = run(cmd)
            if r.returncode != 0:
                print(f"SKIP: cannot make network namespaces here ({' '.join(cmd)}: {r.stderr.strip()})")
                yield None
                return
        yield a, b
    finally:
        run(["ip", "netns", "del", a])
        run(["ip", "netns", "del", b])


def case_multicast():
    # epgm:// (PGM over UDP) from one network namespace to another over a veth pair.
    out = os.path.join(OUT, "multicast")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    with two_namespaces("multicast") as ns:
        if not ns:
            return
        a, b = ns
        group = "239.192.7.7:5555"
        # Multicast cannot carry CURVE: it is used only when asked for as insecure (docs/security.md).
        slave = subprocess.Popen(["ip", "netns", "exec", b, GLCAST, "slave", "--insecure", "--connect", f"epgm://10.213.0.2;{group}",
                                  "--journal", "tcp://10.213.0.1:5556", "--backend", "egl", "--out",
                                  os.path.join(out, "slave"), "--wait", "60", "--quiet"], stderr=subprocess.PIPE, text=True)
        time.sleep(1)
        env = dict(os.environ, GLCAST_PUBLISH=f"epgm://10.213.0.1;{group}", GLCAST_JOURNAL_ENDPOINT="tcp://10.213.0.1:5556",
                   GLCAST_SNAPSHOT_DIR=os.path.join(out, "program"), GLCAST_FRAMES="60", GLCAST_EXIT_AFTER_FRAMES="1",
                   GLCAST_INSECURE="1", LD_PRELOAD=os.environ["GLCAST_SHIM"])
        r = run(["ip", "netns", "exec", a, "glxgears"], env=env, timeout=120)
        check(r.returncode == 0, f"glxgears failed: {r.stderr[-2000:]}")
        check(slave.wait(timeout=120) == 0, f"slave failed: {slave.stderr.read()[-2000:]}")
        n = same_frames(os.path.join(out, "program"), os.path.join(out, "slave"))
        print(f"multicast: {n} frames over epgm:// between two network namespaces equal the program's")


def case_multicast_keeper():
    # glcast run publishing on epgm:// with a slave on another machine that joins late, after the
    # journal (1 MiB) lost the stream's start: the snapshot comes from the keeper glcast run starts
    # beside the program, over TCP; glcast run's own slave and the keeper take the stream over
    # ipc:// (multicast does not loop back).
    out = os.path.join(OUT, "multicast_keeper")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    with two_namespaces("multicast_keeper") as ns:
        if not ns:
            return
        a, b = ns
        endpoint, journal, keeper_at = "epgm://10.213.0.1;239.192.7.8:5565", "tcp://10.213.0.1:5566", "tcp://10.213.0.1:5567"
        env = dict(os.environ, GLCAST_JOURNAL_MB="1", GLCAST_SNAPSHOT_DIR=os.path.join(out, "program"))
        wall = subprocess.Popen(["ip", "netns", "exec", a, GLCAST, "run", "--insecure", "--endpoint", endpoint, "--backend", "egl",
                                 "--out", os.path.join(out, "local"), "--frames", "300", "--",
                                 "/usr/libexec/xscreensaver/gears", "-window", "-geometry", "320x240"],
                                env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wait_for(os.path.join(out, "program", "frame-000150.png"))
        slave = subprocess.Popen(["ip", "netns", "exec", b, GLCAST, "slave", "--insecure", "--connect", "epgm://10.213.0.2;239.192.7.8:5565",
                                  "--journal", journal, "--keeper", keeper_at, "--backend", "egl", "--out",
                                  os.path.join(out, "slave"), "--wait", "60"], stderr=subprocess.PIPE, text=True)
        rc = wall.wait(timeout=300)
        check(rc == 0, f"glcast run failed: {wall.stderr.read()[-2000:]}")
        rc = slave.wait(timeout=300)
        log = slave.stderr.read()
        check(rc == 0, f"slave failed: {log[-2000:]}")
        joined = [l for l in log.splitlines() if "joined at frame" in l]
        check(joined and "snapshot" in joined[0], f"the slave did not join from the keeper: {log[-2000:]}")
        first = min(int(f[6:12]) for f in os.listdir(os.path.join(out, "slave")) if f.endswith(".png"))
        check(first >= 100, f"the slave's first frame is {first}: it did not join late")
        n = same_frames(os.path.join(out, "program"), os.path.join(out, "slave"))
        n_local = same_frames(os.path.join(out, "program"), os.path.join(out, "local", "window"))
        print(f"multicast_keeper: {joined[0].split(': ', 1)[-1]}; {n} frames from frame {first} equal the program's; "
              f"the local slave's {n_local} frames too")


def case_lockstep():
    # Asked for, lockstep holds the program at each swap until every slave replayed the frame.
    out = os.path.join(OUT, "lockstep")
    shutil.rmtree(out, ignore_errors=True)
    logs = os.path.join(out, "presents")
    os.makedirs(logs)
    swaps = os.path.join(out, "swaps")
    r = run([GLCAST, "run", "--config", os.path.join(CONFIGS, "wall-2x2.json"), "--backend", "egl", "--lockstep",
             "--frames", "40", "--", "glxgears"], env=dict(os.environ, GLCAST_TEST_PRESENT_LOG_DIR=logs,
                                                          GLCAST_TEST_SWAP_LOG=swaps))
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    check("lockstep" not in r.stderr, f"lockstep timed out: {r.stderr[-2000:]}")
    swap = {int(f): float(t) for f, t in (line.split() for line in open(swaps))}
    replayed = {}
    for tile in os.listdir(logs):
        for line in open(os.path.join(logs, tile)):
            f, t, _ = line.split()
            replayed.setdefault(int(f), []).append(float(t))
    checked = 0
    for n in sorted(replayed):
        if n + 1 in swap and len(replayed[n]) == 4:
            check(swap[n + 1] >= max(replayed[n]), f"the program swapped frame {n + 1} before every slave replayed {n}")
            checked += 1
    check(checked >= 35, f"only {checked} frames checked")
    print(f"lockstep: for {checked} frames the program swapped frame N+1 only after all four slaves replayed N")


def start_program(out, frames, extra_env=None):
    """xscreensaver's gears (EGL, about 30 frames per second: slaves keep up while it runs)
    publishing on its own endpoints, with its own frames as the reference."""
    stream = f"ipc://{out}/stream"
    env = dict(os.environ, GLCAST_PUBLISH=stream, GLCAST_JOURNAL_ENDPOINT=stream + "-journal",
               GLCAST_SNAPSHOT_DIR=os.path.join(out, "program"), GLCAST_FRAMES=str(frames),
               GLCAST_EXIT_AFTER_FRAMES="1", LD_PRELOAD=os.environ["GLCAST_SHIM"], **(extra_env or {}))
    hack = ["/usr/libexec/xscreensaver/gears", "-window", "-geometry", "320x240"]
    return subprocess.Popen(hack, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True), stream


def start_slave(stream, out_dir, extra=()):
    return subprocess.Popen([GLCAST, "slave", "--connect", stream, "--journal", stream + "-journal", "--backend", "egl",
                             "--out", out_dir, "--wait", "120", "--quiet", *extra], stderr=subprocess.PIPE, text=True)


def wait_for(path, timeout=120):
    end = time.monotonic() + timeout
    while not os.path.exists(path):
        check(time.monotonic() < end, f"{path} did not appear")
        time.sleep(0.05)


def same_frames(a_dir, b_dir):
    frames = sorted(f for f in os.listdir(b_dir) if f.endswith(".png"))
    check(frames, f"{b_dir} is empty")
    for f in frames:
        differing, _ = compare(os.path.join(a_dir, f), os.path.join(b_dir, f))
        check(differing == 0, f"{b_dir}/{f} differs from {a_dir}/{f} in {differing} pixels")
    return len(frames)


def case_late_join():
    out = os.path.join(OUT, "late_join")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    program, stream = start_program(out, 300)
    first = start_slave(stream, os.path.join(out, "first"))
    wait_for(os.path.join(out, "program", "frame-000100.png"))
    late = start_slave(stream, os.path.join(out, "late"))
    wait_for(os.path.join(out, "late", "frame-000140.png"))
    late.send_signal(signal.SIGKILL)
    late.wait()
    again = start_slave(stream, os.path.join(out, "again"))
    program.wait(timeout=300)
    for p in (first, again):
        check(p.wait(timeout=300) == 0, f"slave failed: {p.stderr.read()[-2000:]}")
    n_first = same_frames(os.path.join(out, "program"), os.path.join(out, "first"))
    n_late = same_frames(os.path.join(out, "first"), os.path.join(out, "late"))
    n_again = same_frames(os.path.join(out, "first"), os.path.join(out, "again"))
    print(f"late join: {n_first} frames from the start, {n_late} from the late slave, {n_again} after SIGKILL and restart")


def case_loss():
    out = os.path.join(OUT, "loss")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    # In lockstep, so that the program (and the journal with it) is still there when a slave that
    # fell behind on a loaded machine asks for its last recovery.
    program, stream = start_program(out, 120, {"GLCAST_TEST_DROP_EVERY": "29", "GLCAST_WAIT_SUBSCRIBERS": "1",
                                               "GLCAST_LOCKSTEP": "1"})
    slave = start_slave(stream, os.path.join(out, "slave"), ["--lockstep"])
    program.wait(timeout=300)
    rc = slave.wait(timeout=300)
    log = slave.stderr.read()
    check(rc == 0, f"slave failed: {log[-2000:]}")
    check("messages lost" in log, f"the slave did not notice the loss: {log[-2000:]}")
    n = same_frames(os.path.join(out, "program"), os.path.join(out, "slave"))
    print(f"loss: {log.count('messages lost')} recoveries, {n} frames equal to the program's")


def case_sigstop():
    out = os.path.join(OUT, "sigstop")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    stream = f"ipc://{out}/stream"
    slave = start_slave(stream, os.path.join(out, "slave"))
    time.sleep(0.5)
    os.kill(slave.pid, signal.SIGSTOP)
    env = dict(os.environ, GLCAST_PUBLISH=stream, GLCAST_JOURNAL_ENDPOINT=stream + "-journal", GLCAST_FRAMES="3000",
               GLCAST_EXIT_AFTER_FRAMES="1", LD_PRELOAD=os.environ["GLCAST_SHIM"])
    t0 = time.monotonic()
    # Blocked by the stopped slave, the program would never finish its 3000 frames.
    r = subprocess.run(["glxgears"], env=env, capture_output=True, text=True, timeout=240)
    elapsed = time.monotonic() - t0
    os.kill(slave.pid, signal.SIGKILL)
    slave.wait()
    check(r.returncode == 0, f"glxgears failed: {r.stderr[-2000:]}")
    print(f"sigstop: the program ran 3000 frames in {elapsed:.1f} s with its only slave stopped")


def case_status_unwritten_frames():
    """A tile's slave that writes only later frames (glcast slave --frames A:) still reports each
    frame it replays to run's status: the status is the wall's, not the PNGs'."""
    out = os.path.join(OUT, "status_unwritten_frames")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    port = free_port_run(4)
    config = os.path.join(out, "wall.json")
    with open(config, "w") as f:
        f.write('{"name": "status", "canvas": {"width": 300, "height": 300}, '
                f'"master": {{"address": "127.0.0.1", "port": {port}}}, '
                '"tiles": [{"name": "here", "x": 0, "y": 0, "width": 150, "height": 300}, '
                '{"name": "there", "machine": "other", "x": 150, "y": 0, "width": 150, "height": 300}]}')
    status = os.path.join(out, "status.jsonl")

    def there_states():
        states = []
        for line in open(status) if os.path.exists(status) else []:
            with contextlib.suppress(ValueError):
                tile = [t for t in json.loads(line)["tiles"] if t["tile"] == "there"][0]
                states.append((tile["state"], tile["frame"]))
        return states

    # Until the status shows what the test is about, not a number of frames: on a loaded machine
    # a frame count is either too few to see a report or far too many to finish.
    with open(os.path.join(out, "there.log"), "w") as there_log, open(os.path.join(out, "run.log"), "w") as run_log:
        there = subprocess.Popen([GLCAST, "slave", "--service", "--config", config, "--tile", "there", "--machine", "other",
                                  "--insecure", "--backend", "egl", "--frames", "1000000:", "--out",
                                  os.path.join(out, "there"), "--wait", "60", "--quiet"], stderr=there_log,
                                 start_new_session=True)
        wall = subprocess.Popen([GLCAST, "run", "--config", config, "--machine", "here", "--insecure", "--backend", "egl",
                                 "--frames", "1000000", "--status-json", status, "--wait-tiles", "60", "--", "glxgears"],
                                stdout=subprocess.DEVNULL, stderr=run_log, start_new_session=True)
        try:
            deadline = time.monotonic() + 180
            while time.monotonic() < deadline and wall.poll() is None:
                if any(state == "live" and frame > 0 for state, frame in there_states()):
                    break
                time.sleep(0.5)
            wall.send_signal(signal.SIGTERM)  # the program ends; run stops its wall
            wall.wait(timeout=180)
        finally:
            for p in (wall, there):
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(p.pid, signal.SIGKILL)
                p.wait()
    states = there_states()
    live = [frame for state, frame in states if state == "live"]
    check(live and max(live) > 0, f"the tile that writes no frame never reported one: {states}; glcast run said: "
          f"{open(os.path.join(out, 'run.log')).read()[-2000:]}")
    print(f"status_unwritten_frames: the tile reported live up to frame {max(live)} ({len(live)} of {len(states)} "
          f"status lines)")


def case_ports_in_use():
    """Each of the wall's four ports (stream, journal, keeper, control) held by another process:
    glcast run refuses at once, naming the port, and starts nothing. Before, a taken stream port
    left the shim unable to publish: the program ran unseen and unbounded (GLCAST_FRAMES is the
    shim's) and run waited for it forever; a taken journal or keeper port failed only after the
    slaves' 10 s waits."""
    roles = ["stream", "journal", "keeper", "control"]
    for k, role in enumerate(roles):
        port = free_port_run(4)
        holder = socket.socket()
        holder.bind(("127.0.0.1", port + k))
        holder.listen(1)
        t0 = time.monotonic()
        wall = subprocess.Popen([GLCAST, "run", "--endpoint", f"tcp://127.0.0.1:{port}", "--insecure", "--backend", "egl",
                                 "--frames", "30", "--", "glxgears"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                text=True, start_new_session=True)
        try:
            _, stderr = wall.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            raise AssertionError(f"{role} port {port + k} taken: glcast run still ran after 60 s")
        finally:
            holder.close()
            with contextlib.suppress(ProcessLookupError):
                os.killpg(wall.pid, signal.SIGKILL)  # the program and slaves too, if it started them
            wall.wait()
        elapsed = time.monotonic() - t0
        check(wall.returncode != 0, f"{role} port {port + k} taken: glcast run exited 0: {stderr[-1500:]}")
        check(f"{port + k}" in stderr and "in use" in stderr and role in stderr,
              f"{role} port {port + k} taken: the error does not name the port, its role and why: {stderr[-1500:]}")
        check(elapsed < 5, f"{role} port {port + k} taken: refused only after {elapsed:.1f} s: {stderr[-1500:]}")
        print(f"ports_in_use: {role} port taken: refused in {elapsed:.2f} s: {stderr.strip().splitlines()[-1]}")


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
