#!/usr/bin/env python3
"""`glcast replay --verify` compares answers that name objects through the slave's name map
(semantics.yaml name_pnames): tests/apps_extra/bindings.c makes one object of each kind every
frame, binds it and asks glGetIntegerv which is bound (the program itself checks that each answer
names its object). With a pass on, the slave's passes make objects of their own in the program's
context after its first frame, so the program's later objects have other names on the slave
than on the master. Every replay, without and with each pass, must verify all 64 answers (with the six glIs* answers a frame about names never made or
deleted: before, the slave stopped on them, "texture 900 was never generated"; and two a
frame about two textures under names the program chose, copied with glCopyImageSubData, whose
names' kind another parameter says (commands.yaml name_classes_by): before, the slave passed
those names unmapped, and the copy failed there with GL_INVALID_VALUE); before,
15 of them differed under the cover and shadows (12 under snow), which `--verify` reported as a
replay that had gone wrong.

    verify_names_test.py     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "verify_names")


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    capture = os.path.join(OUT, "bindings.glcs")
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "bindings"), "--frames", "4",
                            "--size", "320x240"], capture_output=True, text=True, timeout=120)
        check(r.returncode == 0, f"capture failed: {r.stderr[-2000:]}")
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    for passes in ([], ["--effects", "cover,icicles"], ["--effects", "shadows"], ["--effects", "snow"]):
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--verify", "--out",
                            os.path.join(OUT, "frames")] + passes, capture_output=True, text=True, timeout=120,
                           env=headless)
        m = re.search(r"verified (\d+) replies: (\d+) differ", r.stdout + r.stderr)
        check(r.returncode == 0 and m, f"replay {passes}: {r.stdout[-1500:]} {r.stderr[-1500:]}")
        check(int(m.group(1)) == 4 * (8 + 6 + 2) and m.group(2) == "0",
              f"replay {passes}: {m.group(0)}\n" + "\n".join(r.stderr.splitlines()[:10]))
        print(f"replay {' '.join(passes) or '(no pass)'}: {m.group(0)}")


if __name__ == "__main__":
    main()
    print("1 passed, 0 failed")
