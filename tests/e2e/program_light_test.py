#!/usr/bin/env python3
"""The light of shader programs: the shadows fall where the program's own sun puts them.

The ring of pillars (tests/apps_extra/pillars.c), its camera turned 40 degrees so that the
world's space and the eye's differ, lit by its shader program from a sun given in the world's
space: a `sun_direction` uniform (towards the sun), the same uniform with its sign flipped (the
way the light travels, as minetest's v_LightDirection goes), and fixed-function light 0 read
through gl_LightSource[0] with GL_LIGHTING off, and a program that keeps a projection and a
model-view matrix (no world space in its shaders) with its light in the eye's space under a name
that does not say so (`u_lightDirection`, as Castle Game Engine's view3dscene keeps its
`castle_LightSource0Position`): before, that light was taken for the world's and turned through
the view. The ground truth is the unlit fixed-function
program with the passes' light set by parameters to that sun in the eye's space (the turn applied
by the test): the floor pixels it shadows are the pixels the sun's shadows cover. Every sun
program must shadow at least 90% of them and few others, with both shadow methods; the passes'
default light shadows other pixels (checked too, so that the comparison can fail). Before the
program's light was read, every shader program got the default light.

    program_light_test.py     with GLCAST, APPS_DIR, OUT_DIR in the environment
"""
import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pillars_scene import FLOOR  # noqa: E402
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "program_light")
TURN = 40.0
EYE_LIGHT = (-0.6, 1.0, 0.3)  # towards the sun in the turned camera's eye space


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def world_from_eye(v):
    """The inverse of glRotated(TURN, 0, 1, 0) on a direction."""
    c, s = math.cos(math.radians(TURN)), math.sin(math.radians(TURN))
    x, y, z = v
    return (c * x - s * z, y, s * x + c * z)


def vector(v):
    return ",".join(f"{c:.6f}" for c in v)


def darkened(floor, plain, decorated):
    """The floor pixels that `decorated` made darker than `plain`."""
    w, h, a = read_png(plain)
    _, _, b = read_png(decorated)
    return {(x, y) for (x, y) in floor if sum(b[y][x][:3]) - sum(a[y][x][:3]) < -30}


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    sun = world_from_eye(EYE_LIGHT)
    against = tuple(-c for c in sun)
    programs = {"fixed": [], "sun_builtins": ["--builtins", "--turn", str(TURN), "--sun", vector(sun)],
                "sun_travel_mvp": ["--mvp", "--turn", str(TURN), "--sun", vector(against)],
                "gl_light_builtins": ["--builtins", "--turn", str(TURN), "--gl-light", vector(sun)],
                "eye_light_modelview": ["--mvp", "--modelview", "--turn", str(TURN), "--sun", vector(EYE_LIGHT)]}
    programs["fixed"] = ["--turn", str(TURN)]
    frame = "frame-000001.png"

    def replay(mode, name, extra):
        out = os.path.join(OUT, f"{mode}-{name}")
        r = subprocess.run([GLCAST, "replay", os.path.join(OUT, f"{mode}.glcs"), "--backend", "egl", "--frames", "1:1",
                            "--out", out] + extra, capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {mode} {name} failed: {r.stderr[-2000:]}")
        return os.path.join(out, frame)

    for mode, flags in programs.items():
        with Xvfb():
            r = subprocess.run([GLCAST, "capture", "-o", os.path.join(OUT, f"{mode}.glcs"), "--",
                                os.path.join(APPS, "pillars")] + flags + ["--size", "400x300", "--frames", "2"],
                               capture_output=True, text=True, timeout=300)
        check(r.returncode == 0, f"capture {mode} failed: {r.stderr[-2000:]}")

    light = ["--effect-param", f"shadows.light_x={EYE_LIGHT[0]}", "--effect-param", f"shadows.light_y={EYE_LIGHT[1]}",
             "--effect-param", f"shadows.light_z={EYE_LIGHT[2]}"]
    screen = ["--effect-param", "shadows.method=screen-space"]
    plain = replay("fixed", "plain", [])
    w, h, p = read_png(plain)
    floor = {(x, y) for y in range(h) for x in range(w) if tuple(p[y][x][:3]) == FLOOR}
    check(len(floor) > w * h // 10, f"the floor shows in {len(floor)} pixels only")
    truth = {"map": darkened(floor, plain, replay("fixed", "sun", ["--effects", "shadows"] + light)),
             "screen": darkened(floor, plain, replay("fixed", "sun-screen", ["--effects", "shadows"] + light + screen))}
    default = darkened(floor, plain, replay("fixed", "default", ["--effects", "shadows"]))
    print(f"the sun shadows {len(truth['map'])} of the floor's {len(floor)} pixels (screen-space {len(truth['screen'])}); "
          f"the default light {len(default)}, {len(default & truth['map'])} of them the sun's")
    check(len(truth["map"]) > 1000, "the sun's shadows on the floor are too small to compare")
    check(len(default & truth["map"]) < 0.5 * len(truth["map"]), "the default light shadows the sun's pixels too")
    for mode in programs:
        if mode == "fixed":
            continue
        own_plain = replay(mode, "plain", [])
        for method, extra in (("map", []), ("screen", screen)):
            found = darkened(floor, own_plain, replay(mode, f"shadows-{method}", ["--effects", "shadows"] + extra))
            ref = truth[method]
            hit, more = len(found & ref), len(found - ref)
            print(f"{mode} ({method}): {hit} of the sun's {len(ref)} shadowed floor pixels "
                  f"({100 * hit / len(ref):.1f}%), {more} others")
            check(hit >= 0.9 * len(ref), f"{mode} ({method}): its shadows cover {hit} of the {len(ref)} floor pixels "
                                         f"the program's sun shadows")
            check(more <= 0.1 * len(ref), f"{mode} ({method}): {more} floor pixels shadowed that the sun leaves lit")
    print("shader programs' suns: the shadows fall where the program's light puts them")


if __name__ == "__main__":
    main()
