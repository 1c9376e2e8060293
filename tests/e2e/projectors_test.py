#!/usr/bin/env python3
"""Projector walls (docs/projectors.md): warp and blend from glcast calibrate, as the plain pair
and as MPCDI, replayed and thrown back onto the surface; and crafted map files refused.

    projectors_test.py CASE      with GLCAST in the environment

cylinder: three overlapping projectors on a 120-degree cylinder section; ff_scene (fixed
  function) and core_scene (GL 3.3 core) from the committed captures, each tile's warped and
  blended output unrolled by `glcast calibrate --simulate` against one replay of the canvas.
dome: four projectors on a dome, the canvas a dome master; ff_scene.
mpcdi: the cylinder written as one MPCDI file, loaded by the slave: the same reconstruction, and
  the same pictures as the plain pair (within a float's rounding). Then a file written by hand from the standard's description loads.
mpcdi3d: the 3D simulation profile: screen points through the region's frustum, on a view tile of
  that frustum; a tile of another view is refused.
cylinder3d: the cylinder written by glcast calibrate in the 3D profile (each projector a view from
  the eye), pillars by fixed function and GLSL: overlapping projectors show the same thing.
crafted: bad files are refused with a message naming the file, the entry and what is wrong.

Each unrolled pixel is the mean of 4x4 canvas points: the tiles render, and the projectors throw
light, at four times the resolution the picture is compared at (docs/projectors.md: a warp
resamples twice, the tile into the projector and the projector onto the surface, and each blurs
an edge by about a pixel). Mean difference at most 2 levels, at most 1% of pixels more than 8
levels off; the projectors' blend sums to 1 within 2% at all but 0.1% of the points.
"""
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import time
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DATA = os.path.join(ROOT, "tests", "data")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "projectors")
FRAME = 2  # the committed captures hold frames 0..2
SCALE = 4

PROJECTOR = {"position": [0, 0.3, 1], "left": -24, "right": 24, "down": -17, "up": 17}
CYLINDER = {"name": "cylinder-3", "canvas_width": 3840,
            "surface": {"kind": "cylinder", "radius": 5, "azimuth": [-60, 60], "height": [-1.4, 1.4]},
            "projectors": [dict(PROJECTOR, name=f"p{i + 1}", yaw=yaw) for i, yaw in enumerate([-40, 0, 40])]}
DOME = {"name": "dome-4", "canvas_width": 2048, "surface": {"kind": "dome", "radius": 5},
        "projectors": [{"name": f"d{i + 1}", "position": [0, 0, 0], "yaw": yaw, "pitch": 45,
                        "left": -47, "right": 47, "down": -33, "up": 33} for i, yaw in enumerate([0, 90, 180, 270])]}


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(cmd, timeout=600):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return r


def must(cmd):
    r = run(cmd)
    check(r.returncode == 0, f"{' '.join(cmd)}: exit {r.returncode}\n{r.stdout}\n{r.stderr[-3000:]}")
    return r.stdout + r.stderr


def installation(spec, folder, fmt="plain"):
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "spec.json")
    json.dump(spec, open(path, "w"))
    must([GLCAST, "calibrate", path, "--out", os.path.join(folder, "maps"), "--format", fmt])
    return path, os.path.join(folder, "maps", "wall.json")


def reconstruct(spec_path, wall, capture, folder):
    """Each tile's frame through its warp and blend, thrown onto the surface and unrolled."""
    config = json.load(open(wall))
    outputs = os.path.join(folder, "outputs")
    os.makedirs(outputs, exist_ok=True)
    for tile in config["tiles"]:
        out = os.path.join(folder, "tiles", tile["name"])
        must([GLCAST, "replay", capture, "--backend", "egl", "--config", wall, "--tile", tile["name"],
              "--frames", str(FRAME), "--out", out])
        shutil.copy(os.path.join(out, "frame-%06d.png" % FRAME), os.path.join(outputs, tile["name"] + ".png"))
    w, h = config["canvas"]["width"], config["canvas"]["height"]
    canvas = os.path.join(folder, "canvas")
    must([GLCAST, "replay", capture, "--backend", "egl", "--canvas", f"{w}x{h}", "--tile-rect", f"0,0,{w},{h}",
          "--frames", str(FRAME), "--out", canvas])
    text = must([GLCAST, "calibrate", spec_path, "--simulate", wall, "--outputs", outputs, "--image",
                 os.path.join(folder, "unrolled.png"), "--reference", os.path.join(canvas, "frame-%06d.png" % FRAME),
                 "--scale", str(SCALE)])
    m = re.search(r"mean difference ([\d.]+) levels, ([\d.]+)% of pixels more than 8 levels off", text)
    b = re.search(r"(\d+) pixels lit whole; of (\d+) canvas points lit, (\d+) by more than one projector; "
                  r"blend sum: (\d+) points more than 2% off 1", text)
    check(m and b, f"simulate said: {text}")
    mean, far = float(m.group(1)), float(m.group(2))
    whole, points, overlap, off = (int(b.group(i)) for i in range(1, 5))
    print(f"{folder}: mean {mean}, {far}% > 8 levels, {overlap} of {points} points overlapped, {off} blend points off")
    check(whole > 0.5 * (w // SCALE) * (h // SCALE) * (0.7 if "dome" in folder else 1),
          f"only {whole} unrolled pixels lit whole")
    check(overlap > 0.05 * points, f"the projectors hardly overlap ({overlap} of {points} points)")
    check(mean <= 2.0, f"mean difference {mean} levels (at most 2)")
    check(far <= 1.0, f"{far}% of pixels more than 8 levels off (at most 1%)")
    check(off <= 0.001 * points, f"the blend sums more than 2% off 1 at {off} of {points} points")
    return os.path.join(folder, "unrolled.png")


def three_d_cylinder():
    """The 3D simulation profile written by glcast calibrate: each projector renders the view from
    the eye that holds what it lights (the program's camera turned), and its warp holds the
    points it lights. There is no canvas to compare with: where two projectors overlap they light
    one point of the surface, so both must show the same thing there. pillars (a ring of
    pillars around the eye) by fixed function and by a GLSL program whose camera the slave finds."""
    folder = os.path.join(OUT, "cylinder3d")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    path = os.path.join(folder, "spec.json")
    json.dump(CYLINDER, open(path, "w"))
    must([GLCAST, "calibrate", path, "--out", os.path.join(folder, "maps"), "--format", "mpcdi", "--profile", "3d"])
    wall = os.path.join(folder, "maps", "wall.json")
    config = json.load(open(wall))
    views = [t["view"] for t in config["tiles"]]
    # (projectors at yaw -40, 0 and 40, a metre behind the eye: the middle one's view straight
    # ahead, the others' symmetric about it)
    check(abs(views[1]["yaw"]) < 0.5 and abs(views[0]["yaw"] + views[2]["yaw"]) < 0.5 and views[2]["yaw"] > 20,
          f"the projectors' views: {views}")
    apps = os.environ["APPS_DIR"]
    for name, flags in (("fixed", []), ("shader", ["--shader"])):
        capture = os.path.join(folder, name + ".glcs")
        with Xvfb():
            must([GLCAST, "capture", "-o", capture, "--", os.path.join(apps, "pillars")] + flags +
                 ["--size", "400x300", "--frames", "3"])
        outputs = os.path.join(folder, name, "outputs")
        os.makedirs(outputs, exist_ok=True)
        for tile in config["tiles"]:
            out = os.path.join(folder, name, "tiles", tile["name"])
            said = must([GLCAST, "replay", capture, "--backend", "egl", "--config", wall, "--tile", tile["name"],
                         "--frames", str(FRAME), "--out", out])
            check("unturned" not in said, f"{name}: tile {tile['name']} left the program unturned: {said[-800:]}")
            shutil.copy(os.path.join(out, "frame-%06d.png" % FRAME), os.path.join(outputs, tile["name"] + ".png"))
        text = must([GLCAST, "calibrate", path, "--simulate", wall, "--outputs", outputs, "--image",
                     os.path.join(folder, name, "unrolled.png"), "--scale", str(SCALE)])
        a = re.search(r"where two projectors overlap: (\d+) pixels, mean difference ([\d.]+) levels between them, "
                      r"([\d.]+)% more than 8 levels off", text)
        b = re.search(r"(\d+) points more than 2% off 1", text)
        check(a and b, f"simulate said: {text}")
        points, mean, far, off = int(a.group(1)), float(a.group(2)), float(a.group(3)), int(b.group(1))
        print(f"cylinder3d {name}: {points} overlapping pixels, mean difference {mean} levels, {far}% > 8 levels; "
              f"{off} blend points more than 2% off 1; views {[(v['yaw'], v['left'], v['right']) for v in views]}")
        # Two projectors rasterize an edge each on their own pixel grid (a pillar's edge lands up to
        # a fifth of an unrolled pixel apart), so edges in the overlap differ; a projector turned
        # 0.1 degrees off its calibration gives 2.05 levels and 5.2% here, 0.3 degrees 5.5 and 9.3%.
        check(points > 2000, f"the projectors hardly overlap ({points} pixels)")
        check(mean <= 1.0, f"{name}: overlapping projectors show different things: mean difference {mean} levels")
        check(far <= 4.0, f"{name}: {far}% of overlapping pixels more than 8 levels apart (at most 4%)")
        check(off == 0, f"{name}: the blend sums more than 2% off 1 at {off} points")
        # And what they show is the view from the eye: the pillars (every 30 degrees around it,
        # tests/apps_extra/pillars.c) stand at their azimuths on the unrolled cylinder.
        w, h, rows = read_png(os.path.join(folder, name, "unrolled.png"))
        row = rows[h // 4]  # above the horizon: pillars on black
        runs, start = [], None
        for x in range(w + 1):
            lit = x < w and sum(row[x][:3]) > 60
            if lit and start is None:
                start = x
            elif not lit and start is not None:
                if start > 0 and x < w:  # (not cut by the section's edge)
                    runs.append((start + x - 1) / 2)
                start = None
        azimuths = [(c + 0.5) / w * 120 - 60 for c in runs]
        check(len(azimuths) == 3 and all(abs(a - 30 * round(a / 30)) < 0.3 for a in azimuths),
              f"{name}: pillars at azimuths {azimuths}, not at -30, 0 and 30 degrees")


def cylinder():
    spec, wall = installation(CYLINDER, os.path.join(OUT, "cylinder"))
    for program in ("ff_scene", "core_scene"):
        reconstruct(spec, wall, os.path.join(DATA, program + ".glcs"), os.path.join(OUT, "cylinder", program))


def dome():
    spec, wall = installation(DOME, os.path.join(OUT, "dome"))
    reconstruct(spec, wall, os.path.join(DATA, "ff_scene.glcs"), os.path.join(OUT, "dome", "ff_scene"))


def same_png_pixels(a, b):
    # MPCDI stores canvas positions, the plain pair tile positions: a float's rounding apart.
    r = run([GLCAST, "image", "compare", a, b])
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    return m and int(m.group(2)) <= 2


def pfm(width, height, values):
    return b"PF\n%d %d\n-1.0\n" % (width, height) + struct.pack("<%df" % len(values), *values)


def png_grey(width, height, level):
    import zlib
    raw = b"".join(b"\x00" + bytes([level]) * width for _ in range(height))
    chunk = lambda kind, body: struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


HAND_XML = """<?xml version="1.0" encoding="utf-8"?>
<MPCDI profile="2d" geometry="1" color="1" version="1.0">
  <display>
    <buffer id="main" Xresolution="64" Yresolution="32">
      <region id="left" Xresolution="32" Yresolution="32" x="0" y="0" xsize="0.5" ysize="1"/>
    </buffer>
  </display>
  <files>
    <fileset region="left">
      <geometryWarpFile>
        <path>left.pfm</path>
        <interpolation>linear</interpolation>
        <componentDepth>3</componentDepth>
        <bitDepth>32</bitDepth>
        <xres>2</xres>
        <yres>2</yres>
      </geometryWarpFile>
      <alphaMap>
        <path>left_alpha.png</path>
        <componentDepth>1</componentDepth>
        <bitDepth>8</bitDepth>
        <gammaEmbedded>2.2</gammaEmbedded>
      </alphaMap>
    </fileset>
  </files>
</MPCDI>
"""
# The identity over the left half of the buffer, rows bottom to top: (0,1) (0.5,1) then (0,0) (0.5,0).
HAND_WARP = [0, 1, 0, 0.5, 1, 0, 0, 0, 0, 0.5, 0, 0]
HAND_CONFIG = {"name": "hand", "canvas": {"width": 64, "height": 32},
               "tiles": [{"name": "left", "x": 0, "y": 0, "width": 32, "height": 32, "mpcdi": "hand.mpcdi",
                          "region": "left"}]}


def write_zip(path, entries, compression=zipfile.ZIP_DEFLATED):
    with zipfile.ZipFile(path, "w", compression) as z:
        for name, data in entries.items():
            z.writestr(name, data)


def mpcdi():
    folder = os.path.join(OUT, "mpcdi")
    spec, wall = installation(CYLINDER, folder, "mpcdi")
    check(json.load(open(wall))["tiles"][0]["mpcdi"] == "cylinder-3.mpcdi", "the config names the MPCDI file")
    names = zipfile.ZipFile(os.path.join(folder, "maps", "cylinder-3.mpcdi")).namelist()
    check("mpcdi.xml" in names and "p1_warp.pfm" in names and "p1_blend.png" in names, f"entries: {names}")
    reconstruct(spec, wall, os.path.join(DATA, "ff_scene.glcs"), os.path.join(folder, "ff_scene"))
    plain_spec, plain_wall = installation(CYLINDER, os.path.join(folder, "plain"))
    reconstruct(plain_spec, plain_wall, os.path.join(DATA, "ff_scene.glcs"), os.path.join(folder, "plain", "ff_scene"))
    plain = os.path.join(folder, "plain", "ff_scene", "outputs")
    for p in ("p1", "p2", "p3"):
        check(same_png_pixels(os.path.join(plain, p + ".png"), os.path.join(folder, "ff_scene", "outputs", p + ".png")),
              f"{p}: MPCDI and the plain pair give different pictures")
    # Written by hand from the standard's description (2D media profile, level 1).
    hand = os.path.join(folder, "hand")
    os.makedirs(hand, exist_ok=True)
    write_zip(os.path.join(hand, "hand.mpcdi"), {"mpcdi.xml": HAND_XML, "left.pfm": pfm(2, 2, HAND_WARP),
                                                 "left_alpha.png": png_grey(32, 32, 255)})
    json.dump(HAND_CONFIG, open(os.path.join(hand, "wall.json"), "w"))
    must([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
          os.path.join(hand, "wall.json"), "--tile", "left", "--frames", str(FRAME), "--out", os.path.join(hand, "out")])
    # An identity warp and a full alpha: the tile's own picture.
    plain_config = dict(HAND_CONFIG, tiles=[{k: v for k, v in HAND_CONFIG["tiles"][0].items() if k not in ("mpcdi", "region")}])
    json.dump(plain_config, open(os.path.join(hand, "plain.json"), "w"))
    must([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
          os.path.join(hand, "plain.json"), "--tile", "left", "--frames", str(FRAME), "--out", os.path.join(hand, "ref")])
    r = run([GLCAST, "image", "compare", os.path.join(hand, "out", "frame-%06d.png" % FRAME),
             os.path.join(hand, "ref", "frame-%06d.png" % FRAME)])
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    check(m and int(m.group(2)) <= 2, f"the hand-written identity warp changed the picture: {r.stdout}")


HAND_3D_XML = HAND_XML.replace('profile="2d"', 'profile="3d"').replace(
    '<region id="left" Xresolution="32" Yresolution="32" x="0" y="0" xsize="0.5" ysize="1"/>',
    '<region id="left" Xresolution="32" Yresolution="32" x="0" y="0" xsize="1" ysize="1">'
    '<frustum><yaw>0</yaw><pitch>0</pitch><roll>0</roll><leftAngle>-30</leftAngle><rightAngle>30</rightAngle>'
    '<downAngle>-20</downAngle><upAngle>20</upAngle></frustum></region>')
VIEW = {"yaw": 0, "pitch": 0, "roll": 0, "left": -30, "right": 30, "bottom": -20, "top": 20}


def three_d():
    """The 3D simulation profile: the warp's nodes are screen points; the region's frustum corners
    on a plane 2 m ahead are the identity on a view tile of that frustum."""
    folder = os.path.join(OUT, "mpcdi3d")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    tx, ty = 2 * math.tan(math.radians(30)), 2 * math.tan(math.radians(20))
    corners = [-tx, -ty, -2, tx, -ty, -2, -tx, ty, -2, tx, ty, -2]  # rows bottom to top, as PFM stores them
    write_zip(os.path.join(folder, "screen.mpcdi"), {"mpcdi.xml": HAND_3D_XML, "left.pfm": pfm(2, 2, corners),
                                                     "left_alpha.png": png_grey(32, 32, 255)})
    tile = {"name": "left", "width": 320, "height": 240, "view": VIEW}
    for name, extra in (("3d.json", {"mpcdi": "screen.mpcdi", "region": "left"}), ("view.json", {})):
        json.dump({"name": "three-d", "tiles": [dict(tile, **extra)]}, open(os.path.join(folder, name), "w"))
    for name in ("3d", "view"):
        must([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
              os.path.join(folder, name + ".json"), "--tile", "left", "--frames", str(FRAME), "--out",
              os.path.join(folder, name)])
    r = run([GLCAST, "image", "compare", os.path.join(folder, "3d", "frame-%06d.png" % FRAME),
             os.path.join(folder, "view", "frame-%06d.png" % FRAME)])
    m = re.search(r"(\d+) pixels differ, max channel difference (\d+)", r.stdout)
    check(m and int(m.group(2)) <= 2, f"the 3D profile's identity warp changed the view: {r.stdout}")
    # A tile whose view is not the region's frustum is refused, saying which angles it wants.
    json.dump({"name": "three-d", "tiles": [dict(tile, view=dict(VIEW, yaw=10), mpcdi="screen.mpcdi", region="left")]},
              open(os.path.join(folder, "other.json"), "w"))
    r = run([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
             os.path.join(folder, "other.json"), "--tile", "left", "--frames", "1"])
    check(r.returncode == 1 and "is rendered from its frustum (yaw 0, pitch 0, roll 0, leftAngle -30" in r.stderr,
          f"a view other than the frustum: {r.stderr[-800:]}")
    print("mpcdi 3d: the frustum's corners are the identity on its view tile")


def crafted():
    folder = os.path.join(OUT, "crafted")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    good = {"mpcdi.xml": HAND_XML, "left.pfm": pfm(2, 2, HAND_WARP), "left_alpha.png": png_grey(32, 32, 255)}
    nan = float("nan")
    cases = {
        "bad XML": (dict(good, **{"mpcdi.xml": HAND_XML.replace("</files>", "</filez>")}), r"mpcdi\.xml: .*line"),
        "no mpcdi.xml": ({k: v for k, v in good.items() if k != "mpcdi.xml"}, r"no mpcdi\.xml in the archive"),
        "missing warp": ({k: v for k, v in good.items() if k != "left.pfm"}, r"no entry \"left\.pfm\""),
        "missing alpha": ({k: v for k, v in good.items() if k != "left_alpha.png"}, r"no entry \"left_alpha\.png\""),
        "map of the wrong size": (dict(good, **{"left_alpha.png": png_grey(64, 32, 255)}),
                                  r"left_alpha\.png: a alphaMap of 64x32 for a region of 32x32"),
        "warp of the wrong size": (dict(good, **{"left.pfm": pfm(3, 2, HAND_WARP + [0] * 6)}),
                                   r"left\.pfm: the warp is 3x2 nodes, not the xres and yres"),
        "dot-dot path": (dict(good, **{"mpcdi.xml": HAND_XML.replace("<path>left.pfm", "<path>../left.pfm")}),
                         r"leaves the archive"),
        "dot-dot entry": (dict(good, **{"../../evil.pfm": b"x"}), r"entry \"\.\./\.\./evil\.pfm\": a name that leaves"),
        "NaN warp is allowed, 1e30 is not": (dict(good, **{"left.pfm": pfm(2, 2, [nan, nan, 0] + HAND_WARP[3:9] + [1e30, 0, 0])}),
                                             r"left\.pfm: warp node \(1, 0\) has u = 1e\+30"),
        "infinite warp": (dict(good, **{"left.pfm": pfm(2, 2, [float("inf")] + HAND_WARP[1:])}), r"warp node \(0, 1\) has u = inf"),
        "huge PFM header": (dict(good, **{"left.pfm": b"PF\n100000 100000\n-1.0\n" + b"\0" * 48}),
                            r"left\.pfm: a PFM of 100000x100000: each side must be 1 to 16384"),
        "PFM shorter than its header": (dict(good, **{"left.pfm": b"PF\n2 2\n-1.0\n" + b"\0" * 20}),
                                        r"the PFM header says 2x2x3 floats \(48 bytes\), the file holds 20"),
        "zip bomb": (dict(good, **{"bomb.png": b"\0" * (100 << 20)}), r"bomb\.png: compressed \d+ to 1"),
        "unknown region": (dict(good, **{"mpcdi.xml": HAND_XML.replace('region id="left"', 'region id="right"')}),
                           r"no region \"left\" \(regions: right\)"),
        "3D profile without a frustum": (dict(good, **{"mpcdi.xml": HAND_XML.replace('profile="2d"', 'profile="3d"')}),
                                         r"region left: a region of the 3D profile needs its <frustum>"),
        "advanced 3D profile": (dict(good, **{"mpcdi.xml": HAND_XML.replace('profile="2d"', 'profile="a3"')}),
                                r"profile \"a3\": .*advanced 3D \(\"a3\"\) and shader lamps \(\"sl\"\) are not supported"),
        "deep XML": (dict(good, **{"mpcdi.xml": HAND_XML.replace("<files>", "<x>" * 200 + "</x>" * 200 + "<files>")}),
                     r"mpcdi\.xml: .*nesting is too deep"),
    }
    for name, (entries, message) in cases.items():
        case = os.path.join(folder, re.sub(r"\W+", "_", name))
        os.makedirs(case)
        write_zip(os.path.join(case, "hand.mpcdi"), entries)
        json.dump(HAND_CONFIG, open(os.path.join(case, "wall.json"), "w"))
        r = run([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
                 os.path.join(case, "wall.json"), "--tile", "left", "--frames", "1", "--out", os.path.join(case, "out")])
        check(r.returncode != 0 and r.returncode < 128, f"{name}: exit {r.returncode} (want a refusal)\n{r.stderr[-1500:]}")
        check(re.search(message, r.stderr) and "hand.mpcdi" in r.stderr,
              f"{name}: the message does not say /{message}/ and name the file:\n{r.stderr[-1500:]}")
        print(f"crafted {name}: {r.stderr.strip().splitlines()[-1]}")
    # Not a zip at all, and a plain pair that is not what it says.
    case = os.path.join(folder, "not_a_zip")
    os.makedirs(case)
    open(os.path.join(case, "hand.mpcdi"), "w").write("<MPCDI/>")
    json.dump(HAND_CONFIG, open(os.path.join(case, "wall.json"), "w"))
    r = run([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
             os.path.join(case, "wall.json"), "--tile", "left", "--frames", "1"])
    check(r.returncode == 1 and "not a readable MPCDI archive" in r.stderr, f"not a zip: {r.stderr[-800:]}")
    open(os.path.join(case, "w.pfm"), "wb").write(pfm(2, 2, HAND_WARP)[:-4])
    json.dump({"name": "p", "canvas": {"width": 64, "height": 32},
               "tiles": [{"name": "left", "x": 0, "y": 0, "width": 32, "height": 32, "warp": "w.pfm"}]},
              open(os.path.join(case, "plain.json"), "w"))
    r = run([GLCAST, "replay", os.path.join(DATA, "ff_scene.glcs"), "--backend", "egl", "--config",
             os.path.join(case, "plain.json"), "--tile", "left", "--frames", "1"])
    check(r.returncode == 1 and "w.pfm: the PFM header says 2x2x3 floats" in r.stderr, f"short plain PFM: {r.stderr[-800:]}")
    # An installation with a misspelt key: refused, not calibrated with the default in its place.
    spec = dict(CYLINDER, surface={"kind": "cylinder", "radius": 5, "azimut": [-60, 60]})
    json.dump(spec, open(os.path.join(case, "spec.json"), "w"))
    r = run([GLCAST, "calibrate", os.path.join(case, "spec.json"), "--out", os.path.join(case, "maps")])
    check(r.returncode == 1 and 'surface.azimut: unknown key (did you mean "azimuth"?' in r.stderr,
          f"a misspelt key in the installation: {r.stderr[-800:]}")


def hostile():
    """What an installation file or a command line can make calibrate do: a name that is a path
    (it replaced a file outside --out, exit 0), a canvas whose height follows from a tall surface
    (8192 wide on a plane 12.5 times taller asked for 8192x102400), a FIFO among --simulate's
    outputs or as its --reference (read_png blocked forever on it)."""
    folder = os.path.join(OUT, "hostile")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(os.path.join(folder, "victim"))
    victim = os.path.join(folder, "victim", "escaped.mpcdi")
    open(victim, "w").write("precious\n")
    small = dict(CYLINDER, canvas_width=256)
    spec = os.path.join(folder, "escape.json")
    json.dump(dict(small, name="../victim/escaped"), open(spec, "w"))
    r = run([GLCAST, "calibrate", spec, "--out", os.path.join(folder, "out"), "--format", "mpcdi"], timeout=120)
    check(r.returncode == 1 and "name is not a plain name" in r.stderr, f"a name that is a path: exit {r.returncode} {r.stderr[-800:]}")
    check(open(victim).read() == "precious\n", "a file outside --out was replaced")
    tall = os.path.join(folder, "tall.json")
    json.dump({"name": "tall", "canvas_width": 8192, "surface": {"kind": "plane", "distance": 3, "x": [-0.5, 0.5], "y": [0, 12.5]},
               "projectors": [{"name": "p1", "position": [0, 6, 0], "left": -20, "right": 20, "down": -60, "up": 60}]},
              open(tall, "w"))
    start = time.time()
    r = run([GLCAST, "calibrate", tall, "--out", os.path.join(folder, "tall")], timeout=120)
    check(r.returncode == 1 and "over 8192" in r.stderr, f"a canvas of 8192x102400: exit {r.returncode} {r.stderr[-800:]}")
    check(time.time() - start < 30, f"refused only after {time.time() - start:.1f} s")
    spec_path, wall = installation(small, os.path.join(folder, "plain"))
    outputs = os.path.join(folder, "outputs")
    os.makedirs(outputs)
    for tile in json.load(open(wall))["tiles"]:
        os.mkfifo(os.path.join(outputs, tile["name"] + ".png"))
    try:
        r = run([GLCAST, "calibrate", spec_path, "--simulate", wall, "--outputs", outputs, "--image",
                 os.path.join(folder, "unrolled.png")], timeout=20)
    except subprocess.TimeoutExpired:
        raise AssertionError("calibrate --simulate blocked on a FIFO among its outputs")
    check(r.returncode == 1 and "not a regular file" in r.stderr, f"a FIFO as an output: exit {r.returncode} {r.stderr[-800:]}")


def trails():
    folder = os.path.join(OUT, "trails")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    capture = os.path.join(folder, "trails.glcs")
    with Xvfb():
        must([GLCAST, "capture", "-o", capture, "--", os.path.join(os.environ["APPS_DIR"], "trails"), "--frames", "30"])
    # u' = 1 - u: the tile's picture mirrored left to right, output pixel x showing pixel W-1-x.
    open(os.path.join(folder, "mirror.pfm"), "wb").write(pfm(2, 2, [1, 1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0]))
    json.dump({"name": "mirror", "canvas": {"width": 320, "height": 240},
               "tiles": [{"name": "m", "x": 0, "y": 0, "width": 320, "height": 240, "warp": "mirror.pfm"}]},
              open(os.path.join(folder, "wall.json"), "w"))
    must([GLCAST, "replay", capture, "--backend", "egl", "--config", os.path.join(folder, "wall.json"), "--tile", "m",
          "--out", os.path.join(folder, "mirrored")])
    must([GLCAST, "replay", capture, "--backend", "egl", "--out", os.path.join(folder, "plain")])
    for n in range(30):
        w1, h1, a = read_png(os.path.join(folder, "mirrored", "frame-%06d.png" % n))
        w2, h2, b = read_png(os.path.join(folder, "plain", "frame-%06d.png" % n))
        check((w1, h1) == (w2, h2) == (320, 240), f"frame {n}: sizes {w1}x{h1}, {w2}x{h2}")
        wrong = sum(1 for y in range(h1) for x in range(w1)
                    if any(abs(p - q) > 1 for p, q in zip(a[y][x], b[y][w1 - 1 - x])))
        check(wrong == 0, f"frame {n}: {wrong} pixels are not the mirror of the program's own frame")
    print("trails: 30 frames, each the mirror of the program's")


if __name__ == "__main__":
    {"cylinder": cylinder, "dome": dome, "mpcdi": mpcdi, "mpcdi3d": three_d, "cylinder3d": three_d_cylinder,
     "crafted": crafted, "trails": trails, "hostile": hostile}[sys.argv[1]]()
    print("projectors: ok")
