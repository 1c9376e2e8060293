#!/usr/bin/env python3
"""Effects decorate the scene, not the program's HUD (docs/effects.md, "Overlays"): ff_scene
--hud ends every frame with a game's HUD (the depth test off, an orthographic projection, an
opaque panel and glBitmap text). Replayed with every pass, the panel and the text are the same
pixels as without passes, while the scene around them changed. Before, shadows darkened the
panel, the cover whitened it and snow fell over it. And the other way round: a shader program
that draws its 3D scene with the depth test off (core_scene --painter) is decorated, not taken for
a HUD. And a scene drawn offscreen (core_scene --offscreen: into a framebuffer object of the
window's size, then copied to the window, then a HUD panel) is decorated as the same scene drawn
in the window is, its HUD untouched; before, the passes saw only the window's copy and the HUD.
And a first-person weapon drawn with glDepthRange(0, 0.3) among the scene's draws (ff_scene
--weapon) is left as the program drew it. And a scene dimmed whole before the HUD (ff_scene --hud --dim, a menu's way; `overlay_test.py
dimmed`) is decorated under the dimming. And a HUD drawn by the scene's own shader program
(pillars --shader --hud and its kin; `overlay_test.py shader_hud`) is untouched by the shadows'
redraw that ran before it, nor by the redraw's first draw when the HUD opens with glBegin. And an overlay engine's wire frames drawn over the scene's depth from
a target of their own (pillars --fbo --wire, as Blender's; `overlay_test.py overlay_engine`) are
not the scene's depth, and stay as drawn, also where one draw composites them with the scene. And
lines drawn with the scene's camera after its surfaces (pillars --bbox, as view3dscene draws its
bounding box; `overlay_test.py marks`) are no surfaces: kept as drawn, neither covered nor casting. And a scene another context draws into a texture only
every fourth frame, which the window's context shows in part of the window every frame (ff_scene
--widget, as Qt's QOpenGLWidget does), is decorated in every frame, where it is shown, and nothing
else is.

    overlay_test.py     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "overlay")
W, H, FRAMES = 320, 240, 4
PANEL = (8, 8, 136, 40)                  # window pixels, x0, y0, x1, y1 (GL: y up)
TEXT = (12, 52, 12 + 10 * 6 - 2, 60)     # the glyphs every frame has
TEXT_FRAME_1 = (12, 52, 12 + 10 * 7 - 2, 60)  # frame 1's (ff_scene draws 6 + frame % 3)


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def inside(rect, margin=1):
    x0, y0, x1, y1 = rect
    return [(x, H - 1 - y) for y in range(y0 + margin, y1 - margin) for x in range(x0 + margin, x1 - margin)]


def painter(headless):
    """core_scene --painter: a core-profile shader program draws its boxes after the ground with
    the depth test off, with the scene's camera. They are scene, not overlays: falling snow
    covers them. Before, the first such draw started the overlays and every box pixel was put
    back over the snow (0 of them changed)."""
    capture = os.path.join(OUT, "core_scene_painter.glcs")
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "core_scene"), "--painter",
                            "--size", f"{W}x{H}", "--frames", "2"], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"capture failed: {r.stderr[-2000:]}")
    for name, extra in (("painter-plain", []), ("painter-snow", ["--effects", "snow"])):
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", os.path.join(OUT, name)] + extra,
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {name} failed: {r.stderr[-2000:]}")
    frame = "frame-000001.png"
    _, _, plain = read_png(os.path.join(OUT, "painter-plain", frame))
    _, _, snowy = read_png(os.path.join(OUT, "painter-snow", frame))
    # The boxes' saturated colours, below the sky (the ground and the monitor's frame are grey).
    boxes = [(x, y) for y in range(H // 3, H) for x in range(W) if max(plain[y][x]) - min(plain[y][x]) > 90]
    check(len(boxes) > 500, f"the boxes are not where the test expects them ({len(boxes)} pixels)")
    snowed = sum(1 for x, y in boxes if plain[y][x] != snowy[y][x])
    print(f"painter: snow changed {snowed} of the boxes' {len(boxes)} pixels")
    check(snowed > len(boxes) // 3, f"snow changed only {snowed} of the boxes' {len(boxes)} pixels: they were "
                                    "taken for overlays")


def plain_and_decorated(app, variants, headless):
    """Captures `app` with each variant's extra arguments (2 frames) and replays each capture
    plain and with every pass: {(name, decorated): frame 1's pixels}."""
    captures = {}
    with Xvfb():
        for name, extra in variants:
            captures[name] = os.path.join(OUT, f"{app}_{name}.glcs")
            r = subprocess.run([GLCAST, "capture", "-o", captures[name], "--", os.path.join(APPS, app), *extra,
                                "--size", f"{W}x{H}", "--frames", "2"], capture_output=True, text=True, timeout=300)
            check(r.returncode == 0, f"capture {name} failed: {r.stderr[-2000:]}")
    images = {}
    for name, capture in captures.items():
        for effects in ("", "shadows,cover,icicles,snow"):
            out = os.path.join(OUT, f"{app}_{name}-{effects or 'plain'}")
            r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] +
                               (["--effects", effects] if effects else []),
                               capture_output=True, text=True, timeout=300, env=headless)
            check(r.returncode == 0, f"replay {out} failed: {r.stderr[-2000:]}")
            images[name, bool(effects)] = read_png(os.path.join(out, "frame-000001.png"))[2]
    return images


def offscreen(headless):
    """core_scene --offscreen against core_scene: the same scene, once drawn into a framebuffer
    object and copied to the window (then a HUD panel), once drawn in the window. With every
    pass, both come out alike (the main view, the redraw and the depth are the offscreen
    scene's), and the panel is untouched. Before, the passes found no main view in the window
    (the copy and the panel are flat draws): shadows and cover did nothing.
    With --hud-vao the panel is drawn from a vertex-array object of its own by glDrawElements, and
    each frame starts by binding the scene's element buffer into the vertex-array object 0: the same
    pictures. Before, the shadows' redraw started from the panel's object, bound when the passes
    ran, and bound the scene's element buffer into it: the panel was no longer drawn."""
    hud = [(x, H - 1 - y) for y in range(8, 8 + 24) for x in range(8, 8 + 96)]  # HUD_X, HUD_Y, HUD_W, HUD_H
    images = plain_and_decorated("core_scene", (("direct", []), ("offscreen", ["--offscreen"]),
                                                ("hud_vao", ["--offscreen", "--hud-vao"])), headless)
    outside = [(x, y) for y in range(H) for x in range(W) if (x, y) not in set(hud)]

    def off(a, b, points):
        return sum(1 for x, y in points if max(abs(p - q) for p, q in zip(a[y][x], b[y][x])) > 2)

    plain, decorated = images["offscreen", False], images["offscreen", True]
    check(all(plain[y][x] == (230, 51, 38) for x, y in hud), f"the HUD panel is not where the test expects it: "
                                                           f"{plain[H - 20][20]}")
    check(off(plain, images["direct", False], outside) == 0, "the offscreen scene does not look like the direct one")
    touched = sum(1 for x, y in hud if plain[y][x] != decorated[y][x])
    changed = sum(1 for x, y in outside if plain[y][x] != decorated[y][x])
    unlike = off(decorated, images["direct", True], outside)
    print(f"offscreen: the passes changed {changed} of {len(outside)} scene pixels and {touched} of the HUD's "
          f"{len(hud)}; {unlike} pixels more than 2 levels off the same scene drawn in the window with the passes")
    check(touched == 0, f"the passes changed {touched} of the HUD's pixels")
    check(changed > len(outside) // 2, f"the passes changed only {changed} pixels of the offscreen scene")
    check(unlike <= len(outside) // 100, f"decorated, the offscreen scene differs from the direct one in {unlike} pixels")
    same = sum(1 for y in range(H) for x in range(W) if images["hud_vao", True][y][x] == decorated[y][x])
    print(f"offscreen, the panel from a vertex-array object of its own: {same} of {W * H} pixels as the other's "
          f"decorated, plain {'the same' if images['hud_vao', False] == plain else 'not the same'}")
    check(images["hud_vao", False] == plain, "the panel from a vertex-array object of its own draws another picture")
    check(same == W * H, f"decorated, the panel from a vertex-array object of its own: {W * H - same} pixels differ")


def view_model(headless):
    """ff_scene --weapon: a first-person weapon drawn among the scene's draws with
    glDepthRange(0, 0.3) (Quake 3's depth hack). With every pass its pixels are the plain
    replay's, and every other pixel is what the passes make of the same scene without it. Before,
    the passes changed 5,045-5,137 of its 5,619 pixels (snow fell over it, cover on its top)."""
    images = plain_and_decorated("ff_scene", (("no-weapon", []), ("weapon", ["--weapon"]),
                                              ("weapon-hud", ["--hud", "--weapon"])), headless)
    plain = images["weapon", False]
    weapon = [(x, y) for y in range(H) for x in range(W) if plain[y][x] != images["no-weapon", False][y][x]]
    check(len(weapon) > 2000, f"the weapon is not where the test expects it ({len(weapon)} pixels)")
    touched = sum(1 for x, y in weapon if images["weapon", True][y][x] != plain[y][x])
    inside_weapon = set(weapon)
    unlike = sum(1 for y in range(H) for x in range(W) if (x, y) not in inside_weapon and
                 max(abs(p - q) for p, q in zip(images["weapon", True][y][x], images["no-weapon", True][y][x])) > 2)
    print(f"view model: the passes changed {touched} of the weapon's {len(weapon)} pixels; {unlike} other pixels "
          f"more than 2 levels off the scene without it")
    check(touched == 0, f"the passes changed {touched} of the weapon's {len(weapon)} pixels")
    # With a HUD too the frame is decorated under its overlays: the weapon's pixels are put back
    # from the window as the scene left it (before this was checked, from a copy never made).
    hud = set(inside(PANEL, margin=0)) | set(inside(TEXT, margin=0))
    under = [(x, y) for x, y in weapon if (x, y) not in hud]
    touched_hud = sum(1 for x, y in under if images["weapon-hud", True][y][x] != images["weapon-hud", False][y][x])
    print(f"view model under a HUD: the passes changed {touched_hud} of the weapon's {len(under)} pixels")
    check(touched_hud == 0, f"under a HUD the passes changed {touched_hud} of the weapon's {len(under)} pixels")
    check(unlike == 0, f"with the weapon, {unlike} scene pixels differ from the scene without it")


def shader_hud(headless):
    """pillars --hud with a shader program (--shader: its projection a uniform; --mvp: one
    premultiplied matrix; --builtins: GL_PROJECTION read through GLSL's built-ins; --fbo: the
    scene drawn offscreen and shown), whose HUD panel is drawn by the scene's own program under an
    orthographic matrix after the scene. With the shadows' redraw from the light (the shadow
    map, which re-renders the scene with the program's patched vertex shaders), every pass
    together, the panel is the plain replay's. Before, the panel's first draw came after the
    passes that ran under the overlays had left the light's clip transform in the program:
    drawn as the light sees it, 3,654 of its 6,000 pixels changed (--shader)."""
    variants = (("shader", ["--shader"]), ("mvp", ["--mvp"]), ("builtins", ["--builtins"]),
                ("fbo", ["--shader", "--fbo"]))
    for name, flags in variants:
        capture = os.path.join(OUT, f"pillars_hud_{name}.glcs")
        with Xvfb():
            r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "pillars"), *flags, "--hud",
                                "--size", "400x300", "--frames", "2"], capture_output=True, text=True, timeout=300)
        check(r.returncode == 0, f"capture {name} failed: {r.stderr[-2000:]}")
        images = {}
        for effects in ("", "shadows", "shadows,cover,icicles,snow"):
            out = os.path.join(OUT, f"pillars_hud_{name}-{effects or 'plain'}")
            r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] +
                               (["--effects", effects] if effects else []),
                               capture_output=True, text=True, timeout=300, env=headless)
            check(r.returncode == 0, f"replay {out} failed: {r.stderr[-2000:]}")
            w, h, images[effects] = read_png(os.path.join(out, "frame-000001.png"))
        plain = images[""]
        hud = [(x, y) for y in range(h) for x in range(w) if plain[y][x] == (230, 50, 40)]
        check(len(hud) >= 5000, f"{name}: the HUD panel is not where the test expects it ({len(hud)} pixels)")
        for effects, image in images.items():
            if not effects:
                continue
            touched = sum(1 for x, y in hud if image[y][x] != plain[y][x])
            scene = sum(1 for y in range(h) for x in range(w) if image[y][x] != plain[y][x])
            print(f"shader HUD ({name}, {effects}): the passes changed {touched} of the panel's {len(hud)} pixels, "
                  f"{scene} pixels in all")
            check(touched == 0, f"{name}, {effects}: the passes changed {touched} of the panel's {len(hud)} pixels")
            check(scene > 500, f"{name}, {effects}: the passes changed only {scene} pixels")


def pillars_pictures(prefix, variants, passes, headless, app="pillars", tail=("--size", "400x300", "--frames", "2"),
                     frame=1, verify=False):
    """Captures pillars (400x300, 2 frames; or `app` with `tail`) with each variant's arguments and
    replays each capture with each pass's: {(variant, pass): the pixels of `frame`}, and the
    pictures' width and height. With `verify` every replay also compares the slave's answers to
    the program's glGet* and glGetError calls with the master's (replay --verify)."""
    captures = {}
    with Xvfb():
        for name, extra in variants:
            captures[name] = os.path.join(OUT, f"{prefix}_{name}.glcs")
            r = subprocess.run([GLCAST, "capture", "-o", captures[name], "--", os.path.join(APPS, app), *extra, *tail],
                               capture_output=True, text=True, timeout=300)
            check(r.returncode == 0, f"capture {name} failed: {r.stderr[-2000:]}")
    pictures = {}
    for name, capture in captures.items():
        for label, extra in passes.items():
            out = os.path.join(OUT, f"{prefix}_{name}-{label}")
            r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] + extra +
                               (["--verify"] if verify else []), capture_output=True, text=True, timeout=300, env=headless)
            check(r.returncode == 0, f"replay {out} failed: {r.stdout[-500:]} {r.stderr[-2000:]}")
            w, h, pictures[name, label] = read_png(os.path.join(out, f"frame-{frame:06d}.png"))
    return pictures, w, h


def hud_after_glbegin(headless):
    """pillars --hud against pillars (fixed function): the HUD panel's first draw is a glBegin,
    and the passes that decorate the frame under its overlays run just before it. Outside the
    panel, the decorated picture is the one without the HUD (cover with its normals from the
    re-rendered triangles, and shadows). Before, the tile adapter still counted the program's
    glBegin as open during the passes' redraw, so the redraw's first draw (the floor) went
    uncorrected: the floor's row under each pillar's base stayed bare (146 pixels off)."""
    pictures, w, h = pillars_pictures("pillars_ff", (("no-hud", []), ("hud", ["--hud"])),
                                      {"plain": [], "cover": ["--effects", "cover"], "shadows": ["--effects", "shadows"]},
                                      headless)
    hud = {(x, y) for y in range(h) for x in range(w) if pictures["hud", "plain"][y][x] != pictures["no-hud", "plain"][y][x]}
    check(len(hud) >= 5000, f"the HUD panel is not where the test expects it ({len(hud)} pixels)")
    for label in ("cover", "shadows"):
        a, b = pictures["hud", label], pictures["no-hud", label]
        off = sum(1 for y in range(h) for x in range(w)
                  if (x, y) not in hud and max(abs(p - q) for p, q in zip(a[y][x], b[y][x])) > 2)
        print(f"HUD opened by glBegin ({label}): {off} pixels outside the panel off the scene without it")
        check(off == 0, f"{label}: {off} pixels outside the HUD differ from the scene without it")


def kept_as_drawn(what, images, variants, kept, w, h):
    """Under each pass (cover, shadows by both methods, snow) of pillars_pictures' `images`: none of
    the `kept` pixels changed from the plain picture of variants[0] (the program's with them), and
    every other pixel within 2 levels of what the pass makes of variants[1] (the scene without them)."""
    with_them, without = variants
    plain = images[with_them, "plain"]
    for label in ("cover", "shadows", "screen", "snow"):
        a, b = images[with_them, label], images[without, label]
        changed = sum(1 for y in range(h) for x in range(w) if a[y][x] != plain[y][x])
        touched = sum(1 for x, y in kept if a[y][x] != plain[y][x])
        off = sum(1 for y in range(h) for x in range(w)
                  if (x, y) not in kept and max(abs(p - q) for p, q in zip(a[y][x], b[y][x])) > 2)
        print(f"{what}, {label}: {touched} of the {len(kept)} pixels kept as drawn changed; {off} others more "
              f"than 2 levels off the scene without them; {changed} pixels decorated")
        check(changed > 500, f"{what}, {label}: the passes changed only {changed} pixels")
        check(touched == 0, f"{what}, {label}: {touched} of the pixels to keep as drawn changed")
        check(off == 0, f"{what}, {label}: {off} other pixels differ from the scene without them")


def overlay_engine(headless):
    """pillars --fbo --wire: after the scene, a wire-frame box with a filled lid drawn with the
    scene's camera into a second framebuffer object that holds a colour texture of its own and the
    scene's depth, writing depth, then composited over the scene in the window (Blender's overlay
    engine draws its cameras' and lights' wire frames so). The passes read the scene's depth from
    before the box: every pixel outside the box's is what they make of the scene without it
    (pillars --fbo --hud, the panel in both), within 2 levels. Before, the box's depth was the
    scene's: icicles hung from its lid over the floor (238 pixels off with cover and icicles).
    And the box is the program's overlay: every one of its pixels stays as drawn under every pass,
    also with --region, where one GLSL draw mixes the box's texture over the scene's as it shows
    the viewport (Blender's window composites its viewport's colour and overlay textures so):
    before, cover whitened all of the box's 1,774 pixels there and snow fell over 1,156 of them.
    And with --msaa: the box's target a multisampled colour texture over the multisampled scene's
    depth, resolved before it is blended (the slave reads a resolved copy). The program asks
    glGetError each frame and every replay verifies the answers: before, the slave bound the
    multisampled texture as a 2D one to read it, which failed and left GL_INVALID_OPERATION for the
    program's next glGetError (1282 where the master got 0, each frame, under every pass). And with
    --rect: the box's target a rectangle texture, blended by fixed function; the same failure
    before (the slave now copies the engine's colour by a blit whatever its target).
    And with ff_scene --widget-wire: the scene and the box drawn by a context that presents only to
    a pbuffer of a pixel (Blender's draw manager's), the box blended over the widget by the window's
    context. Before, the scene's depth was kept at a size bounded by that context's window (4x4
    texels), and the passes read garbage for the rest."""
    passes = {"plain": [], "cover": ["--effects", "cover,icicles"], "shadows": ["--effects", "shadows"],
              "screen": ["--effects", "shadows", "--effect-param", "shadows.method=screen-space"],
              "snow": ["--effects", "snow"]}
    # (both with the HUD panel: both frames are then decorated under their overlays, the same way)
    layouts = (("window", "pillars", ["--fbo", "--hud"], ["--wire"]),
               ("region", "pillars", ["--fbo", "--region", "--hud"], ["--wire"]),
               ("msaa", "pillars", ["--fbo", "--msaa", "--hud"], ["--wire"]),
               ("rect", "pillars", ["--fbo", "--hud"], ["--wire", "--rect"]),
               ("widget", "ff_scene", ["--widget"], ["--widget-wire"]))
    for layout, app, base, wire in layouts:
        tail = ("--frames", "5") if app == "ff_scene" else ("--size", "400x300", "--frames", "2")
        images, w, h = pillars_pictures(f"{app}_{layout}", (("no-wire", base), ("wire", base + wire)), passes, headless,
                                        app=app, tail=tail, frame=4 if app == "ff_scene" else 1, verify=True)
        plain = images["wire", "plain"]
        box = {(x, y) for y in range(h) for x in range(w) if plain[y][x] != images["no-wire", "plain"][y][x]}
        check(len(box) > 300, f"{layout}: the wire-frame box is not where the test expects it ({len(box)} pixels)")
        box |= {(x, y) for y in range(h) for x in range(w) if plain[y][x] == (230, 50, 40)}  # the panel or gizmo
        kept_as_drawn(f"overlay engine ({layout})", images, ("wire", "no-wire"), box, w, h)


def marks(headless):
    """pillars --bbox: a bounding box's edges (GL_LINES, 2 pixels wide) drawn after the pillars with
    the main view's camera, the depth test and writes on, as view3dscene draws its scene's bounding
    box: by fixed function, with and without a HUD after it, by a shader program reading the
    built-in matrices, by one that keeps a projection and a model-view matrix (view3dscene's own
    way), and into the scene's framebuffer object. Lines are no surfaces: every one of their pixels
    stays as drawn under every pass, and every other pixel is what the pass makes of the scene
    without them, within 2 levels. Before, they were the scene's: the cover whitened them and hung
    icicles from them, and they cast thin shadows across the floor and the pillar behind them."""
    passes = {"plain": [], "cover": ["--effects", "cover,icicles"], "shadows": ["--effects", "shadows"],
              "screen": ["--effects", "shadows", "--effect-param", "shadows.method=screen-space"],
              "snow": ["--effects", "snow"]}
    sun = ["--sun", "0.3,1,0.2"]
    layouts = (("window", ["--hud"], ["--hud", "--bbox"]), ("window_alone", [], ["--bbox"]),
               ("builtins", ["--builtins", "--hud"], ["--builtins", "--hud", "--bbox"]),
               ("modelview", ["--mvp", "--modelview", "--hud"] + sun, ["--mvp", "--modelview", "--hud", "--bbox"] + sun),
               ("fbo", ["--fbo", "--hud"], ["--fbo", "--hud", "--bbox"]))
    for layout, base, boxed in layouts:
        images, w, h = pillars_pictures(f"marks_{layout}", (("no-box", base), ("box", boxed)), passes, headless)
        plain = images["box", "plain"]
        box = {(x, y) for y in range(h) for x in range(w) if plain[y][x] != images["no-box", "plain"][y][x]}
        check(len(box) > 1000, f"{layout}: the bounding box is not where the test expects it ({len(box)} pixels)")
        kept_as_drawn(f"marks ({layout})", images, ("box", "no-box"), box, w, h)


def dimmed(headless, app="ff_scene"):
    """ff_scene --hud --dim: a menu dims the whole scene with a black quad of alpha 0.27 before its
    HUD panel, as neverball's title screen does. With every pass the scene is decorated under it and
    dimmed with the rest: each pixel outside the HUD is the undimmed scene's decorated pixel
    (ff_scene --hud) times 0.73, within 2 levels, and the opaque panel is untouched. Before, the
    dimming quad was the first overlay and changed every pixel, so every pixel was put back as the
    program drew it: the passes changed none. The same for a scene drawn offscreen and shown over
    the whole window by a draw, the window's colour never cleared (core_scene --offscreen --dim,
    against core_scene --offscreen)."""
    if app == "ff_scene":
        images = plain_and_decorated(app, (("hud", ["--hud"]), ("dim", ["--hud", "--dim"])), headless)
        panel = inside(PANEL)
        hud = set(inside(PANEL, margin=0)) | set(inside(TEXT_FRAME_1, margin=0))
    else:
        images = plain_and_decorated(app, (("hud", ["--offscreen"]), ("dim", ["--offscreen", "--dim"])), headless)
        panel = [(x, H - 1 - y) for y in range(8, 8 + 24) for x in range(8, 8 + 96)]  # HUD_X, HUD_Y, HUD_W, HUD_H
        hud = set(panel)
    scene = [(x, y) for y in range(H) for x in range(W) if (x, y) not in hud]

    def off_dimmed(a, b):  # a, b: pictures; pixels of `a` not `b` dimmed
        return sum(1 for x, y in scene if max(abs(p - round(0.73 * q)) for p, q in zip(a[y][x][:3], b[y][x][:3])) > 2)

    plain, decorated = images["dim", False], images["dim", True]
    check(off_dimmed(plain, images["hud", False]) <= len(scene) // 100, "the dimmed picture is not what the test expects")
    changed = sum(1 for x, y in scene if decorated[y][x] != plain[y][x])
    unlike = off_dimmed(decorated, images["hud", True])
    touched = sum(1 for x, y in panel if decorated[y][x] != plain[y][x])
    print(f"dimmed {app}: the passes changed {changed} of the scene's {len(scene)} pixels under the dimming, {unlike} more "
          f"than 2 levels off the undimmed decorated scene dimmed; {touched} of the panel's pixels changed")
    check(touched == 0, f"the passes changed {touched} of the panel's pixels")
    check(changed > len(scene) // 2, f"under the dimming the passes changed only {changed} of {len(scene)} pixels")
    check(unlike == 0, f"{unlike} pixels are not the decorated scene dimmed")


def widget_that_swapped_once(headless):
    """ff_scene --widget-swaps: the widget's context swaps its pbuffer once when it is made (the
    slave's frame 0), as Blender's draw manager's hidden window does, and never presents again. It
    lends its scene from two frames after that swap on: from frame 3 on, more than half of the
    widget's pixels change under cover and snow, and none outside it. Before, a context that had
    presented once never lent: no frame was decorated (Blender's viewport, docs/compatibility.md)."""
    x0, y0, x1, y1 = 80, 30, 280, 210
    label = {(x, H - 1 - y) for y in range(y0 + 4, y0 + 20) for x in range(x0 + 4, x0 + 64)}
    widget_px = [(x, H - 1 - y) for y in range(y0, y1) for x in range(x0, x1) if (x, H - 1 - y) not in label]
    rect = set(widget_px) | label
    outside = [(x, y) for y in range(H) for x in range(W) if (x, y) not in rect] + sorted(label)
    capture = os.path.join(OUT, "ff_scene_widget_swaps.glcs")
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "ff_scene"), "--widget-swaps",
                            "--size", f"{W}x{H}", "--frames", "6"], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"capture --widget-swaps failed: {r.stderr[-2000:]}")
    outs = {}
    for effects in ("", "cover,snow"):
        outs[effects] = os.path.join(OUT, f"widget_swaps-{effects.replace(',', '-') or 'plain'}")
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", outs[effects]] +
                           (["--effects", effects] if effects else []),
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay --widget-swaps failed: {r.stderr[-2000:]}")
    for k in range(3, 7):
        plain = read_png(os.path.join(outs[""], f"frame-{k:06d}.png"))[2]
        decorated = read_png(os.path.join(outs["cover,snow"], f"frame-{k:06d}.png"))[2]
        changed = sum(1 for x, y in widget_px if plain[y][x] != decorated[y][x])
        touched = sum(1 for x, y in outside if plain[y][x] != decorated[y][x])
        print(f"widget that swapped once, frame {k}: {changed} of the widget's {len(widget_px)} pixels changed, "
              f"{touched} outside it")
        check(touched == 0 and changed > len(widget_px) // 2,
              f"frame {k}: the widget that swapped once is not decorated as a widget ({changed} in, {touched} out)")


def widget(headless, samples=0, post=False):
    """ff_scene --widget (320x240): a second context draws the scene into a framebuffer object of
    200x180 in frames 0 and 4 only; every frame the window's context draws a grey background,
    that texture at (80, 30), a toolbar and a label over the widget. With every pass, frames 0-5
    are decorated inside the widget and not one pixel outside it or of the label changes; with
    shadows and cover, the widget's frames 0-3 are within 2% of ff_scene drawn directly at 200x180
    with the same passes (screen-space filters shift some shadow-edge pixels). Before, the passes
    found no scene in any frame (cover and shadows did nothing) and snow fell over the whole
    window, toolbar and label included. With `samples` (--widget-samples: the scene drawn into
    multisampled renderbuffers, its colour resolved into the texture), the same but for the
    comparison with the direct scene (whose edges are not antialiased); before, 31,564 pixels
    outside the widget changed. With `post` (--widget-post: the widget's context copies its picture
    into a second texture by a full-target quad and the window shows that one, as Blender's draw
    manager's viewport is copied through post-processing targets), the same; before, the window's
    draw sampled a texture the lent scene did not name, and once the scene's first draw had a
    camera no pass found a view in any frame."""
    x0, y0, x1, y1 = 80, 30, 280, 210  # the widget, GL window pixels
    label = {(x, H - 1 - y) for y in range(y0 + 4, y0 + 20) for x in range(x0 + 4, x0 + 64)}
    widget_px = [(x, H - 1 - y) for y in range(y0, y1) for x in range(x0, x1) if (x, H - 1 - y) not in label]
    rect = set(widget_px) | label
    outside = [(x, y) for y in range(H) for x in range(W) if (x, y) not in rect] + sorted(label)
    frames = 6
    variant = f"widget{samples or ''}" + ("_post" if post else "")
    captures = {"widget": os.path.join(OUT, f"ff_scene_{variant}.glcs"),
                "direct": os.path.join(OUT, "ff_scene_direct.glcs")}
    mode = ["--widget-samples", str(samples)] if samples else ["--widget"] + (["--widget-post"] if post else [])
    with Xvfb():
        for name, args in (("widget", mode + ["--size", f"{W}x{H}", "--frames", str(frames)]),
                           ("direct", ["--size", f"{x1 - x0}x{y1 - y0}", "--frames", "1"])):
            r = subprocess.run([GLCAST, "capture", "-o", captures[name], "--", os.path.join(APPS, "ff_scene"), *args],
                               capture_output=True, text=True, timeout=300)
            check(r.returncode == 0, f"capture {name} failed: {r.stderr[-2000:]}")
    runs = {}
    for name, effects in (("widget", ""), ("widget", "shadows,cover,icicles,snow"), ("widget", "shadows,cover"),
                          ("direct", ""), ("direct", "shadows,cover")):
        out = os.path.join(OUT, f"{name}-{effects or 'plain'}")
        r = subprocess.run([GLCAST, "replay", captures[name], "--backend", "egl", "--out", out] +
                           (["--effects", effects] if effects else []),
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {out} failed: {r.stderr[-2000:]}")
        runs[name, effects] = out

    def frame(name, effects, k):
        return read_png(os.path.join(runs[name, effects], f"frame-{k:06d}.png"))[2]

    def off(a, b, dx=0, dy=0):  # widget pixels more than 2 levels off the direct scene's
        return sum(1 for x, y in widget_px if max(abs(p - q) for p, q in zip(a[y][x], b[y - dy][x - dx])) > 2)

    direct_plain, direct_decorated = frame("direct", "", 0), frame("direct", "shadows,cover", 0)
    dx, dy = x0, H - y1  # the widget's top left corner in image rows
    check(off(frame("widget", "", 1), direct_plain, dx, dy) <= len(widget_px) // (20 if samples else 1000),
          "the widget's picture is not the direct scene where the test expects it")
    for k in range(frames):
        plain, decorated = frame("widget", "", k), frame("widget", "shadows,cover,icicles,snow", k)
        touched = sum(1 for x, y in outside if plain[y][x] != decorated[y][x])
        changed = sum(1 for x, y in widget_px if plain[y][x] != decorated[y][x])
        unlike = off(frame("widget", "shadows,cover", k), direct_decorated, dx, dy) if k < 4 and not samples else -1
        print(f"{variant} frame {k}{' (scene drawn)' if k % 4 == 0 else ' (scene kept)'}: the passes changed {changed} "
              f"of the widget's {len(widget_px)} pixels and {touched} of the {len(outside)} outside it and of the "
              f"label" + (f"; shadows and cover: {unlike} pixels more than 2 levels off the direct scene's"
                          if unlike >= 0 else ""))
        check(touched == 0, f"frame {k}: the passes changed {touched} pixels outside the widget or of its label")
        check(changed > len(widget_px) // 2, f"frame {k}: the passes changed only {changed} of the widget's pixels")
        check(unlike <= len(widget_px) // 50, f"frame {k}: decorated, the widget differs from the direct scene in "
                                              f"{unlike} pixels")
    if not samples:
        widget_mosaic(captures["widget"], headless)


def preview(headless):
    """ff_scene --preview: the second context's picture drawn small in the window's sky first,
    then the window's own scene over it (the colour not cleared). The window's scene is the main
    view: with every pass it comes out as ff_scene's does, pixel for pixel outside the preview.
    Before, the preview's draw lent the other context's view and the window's own scene was taken
    for overlays: the passes changed 1,568 pixels (the preview) instead of 59,661."""
    images = plain_and_decorated("ff_scene", (("direct", []), ("preview", ["--preview"])), headless)
    plain, direct = images["preview", False], images["direct", False]
    scene = [(x, y) for y in range(H) for x in range(W) if plain[y][x] == direct[y][x]]
    check(len(scene) > W * H * 9 // 10, f"the preview covers {W * H - len(scene)} pixels")
    decorated, direct_decorated = images["preview", True], images["direct", True]
    changed = sum(1 for x, y in scene if plain[y][x] != decorated[y][x])
    unlike = sum(1 for x, y in scene if max(abs(p - q) for p, q in zip(decorated[y][x], direct_decorated[y][x])) > 2)
    print(f"preview: the passes changed {changed} of the window scene's {len(scene)} pixels; {unlike} more than 2 "
          f"levels off ff_scene's")
    check(changed > len(scene) // 2, f"the passes changed only {changed} pixels of the window's own scene")
    check(unlike <= len(scene) // 100, f"decorated, the window's scene differs from ff_scene's in {unlike} pixels")


def widget_mosaic(capture, headless):
    """The widget's capture on a 640x480 canvas as a 2x2 wall, with shadows and cover: the four
    tiles' frame 1 (a kept scene) stitched equal the canvas's within rounding: the scene's place,
    its depth and the pixels put back outside it are mapped to each tile."""
    def replay(name, rect):
        out = os.path.join(OUT, f"widget-tile-{name}")
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--canvas", "640x480", "--tile-rect", rect,
                            "--out", out, "--effects", "shadows,cover", "--frames", "1:1"],
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {out} failed: {r.stderr[-2000:]}")
        return read_png(os.path.join(out, "frame-000001.png"))[2]

    canvas = replay("canvas", "0,0,640,480")
    tiles = {(x, y): replay(f"{x}-{y}", f"{x},{y},320,240") for y in (0, 240) for x in (0, 320)}
    off = sum(1 for y in range(480) for x in range(640)
              if max(abs(p - q) for p, q in zip(tiles[x // 320 * 320, y // 240 * 240][y % 240][x % 320], canvas[y][x])) > 2)
    print(f"widget on a 2x2 wall: {off} of 307,200 pixels more than 2 levels off the canvas")
    check(off <= 640 * 480 // 500, f"the 2x2 wall of the widget differs from the canvas in {off} pixels")


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    capture = os.path.join(OUT, "ff_scene_hud.glcs")
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "ff_scene"), "--hud", "--size",
                            f"{W}x{H}", "--frames", str(FRAMES)], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"capture failed: {r.stderr[-2000:]}")
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    for name, extra in (("plain", []), ("effects", ["--effects", "shadows,cover,icicles,snow"])):
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", os.path.join(OUT, name)] + extra,
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {name} failed: {r.stderr[-2000:]}")
    for k in range(FRAMES):
        frame = f"frame-{k:06d}.png"
        _, _, plain = read_png(os.path.join(OUT, "plain", frame))
        _, _, decorated = read_png(os.path.join(OUT, "effects", frame))
        x, y = inside(PANEL)[0]
        check(plain[y][x] == (230, 50, 40), f"{frame}: the HUD panel is not where the test expects it: {plain[y][x]}")
        glyphs = [(x, y) for x, y in inside(TEXT, margin=0) if plain[y][x] == (255, 255, 255)]  # bits set
        check(len(glyphs) > 100, f"{frame}: the HUD's text is not where the test expects it ({len(glyphs)} pixels)")
        hud = inside(PANEL) + glyphs
        touched = [(x, y) for x, y in hud if plain[y][x] != decorated[y][x]]
        check(not touched, f"{frame}: the passes changed {len(touched)} of the HUD's {len(hud)} pixels, e.g. "
                           f"{touched[:3]}: {[(plain[y][x], decorated[y][x]) for x, y in touched[:3]]}")
        scene = sum(1 for y in range(H) for x in range(W) if plain[y][x] != decorated[y][x])
        check(scene > W * H // 20, f"{frame}: the passes changed only {scene} pixels of the scene")
        print(f"{frame}: the HUD's {len(hud)} pixels untouched; {scene} of the scene's pixels decorated")
    painter(headless)
    offscreen(headless)
    view_model(headless)
    widget(headless)
    widget(headless, samples=4)
    widget_that_swapped_once(headless)
    preview(headless)


if __name__ == "__main__":
    if sys.argv[1:] in (["widget_post"], ["dimmed"], ["shader_hud"], ["overlay_engine"], ["marks"]):  # (tests of their own, beside main's in ctest: own folders)
        OUT += "_" + sys.argv[1]
        shutil.rmtree(OUT, ignore_errors=True)
        os.makedirs(OUT)
        headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
        if sys.argv[1] == "widget_post":
            widget(headless, post=True)
        elif sys.argv[1] == "shader_hud":
            shader_hud(headless)
            hud_after_glbegin(headless)
        elif sys.argv[1] == "overlay_engine":
            overlay_engine(headless)
        elif sys.argv[1] == "marks":
            marks(headless)
        else:
            dimmed(headless)
            dimmed(headless, "core_scene")
    else:
        main()
    print("PASS")
