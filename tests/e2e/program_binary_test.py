#!/usr/bin/env python3
"""Program binaries do not carry over between drivers (commands.yaml answered_by_shim): a
program with a warm shader cache (tests/apps_extra/program_binary.c) captured under the shim
compiles from source, whether it asks the driver for binary formats first (--ask, as Qt does)
or loads its cached binary regardless (--load: the load fails, as GL lets any load fail), and
both backends replay its frames pixel-identically. Before, the cached binary was loaded on
the master, EGL (the same llvmpipe) loaded it too, and OSMesa rejected it and drew white.

    program_binary_test.py     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "program_binary")
PROGRAM = os.path.join(APPS, "program_binary")


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    cache = os.path.join(OUT, "cache.bin")
    with Xvfb():
        r = subprocess.run([PROGRAM, "--cache", cache, "--ask", "--frames", "2"], capture_output=True, text=True,
                           timeout=120)
        check(r.returncode == 0, f"program_binary failed: {r.stderr}")
        if "formats 0" in r.stdout:
            print(f"SKIP: this driver reports no program binary format ({r.stdout.strip()})")
            return
        check(os.path.getsize(cache) > 0, "the native run wrote no binary")
        r = subprocess.run([PROGRAM, "--cache", cache, "--ask", "--frames", "2"], capture_output=True, text=True,
                           timeout=120)
        check("loaded" in r.stdout, f"natively, the cache is not used: {r.stdout}")
        for mode, said in (("ask", "formats 0, compiled"), ("load", "formats 0, load failed, compiled")):
            capture, frames = os.path.join(OUT, mode + ".glcs"), os.path.join(OUT, mode + "-program")
            env = dict(os.environ, GLCAST_SNAPSHOT_DIR=frames)
            r = subprocess.run([GLCAST, "capture", "-o", capture, "--", PROGRAM, "--cache", cache, f"--{mode}",
                                "--frames", "10"], capture_output=True, text=True, timeout=120, env=env)
            check(r.returncode == 0, f"capture --{mode} failed: {r.stderr[-2000:]}")
            check(said in r.stdout, f"--{mode} under the shim: {r.stdout.strip()!r}, expected {said!r}")
            headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
            for backend in ("egl", "osmesa"):
                r = subprocess.run([GLCAST, "replay", capture, "--backend", backend, "--compare", frames, "--verify"],
                                   capture_output=True, text=True, timeout=120, env=headless)
                check(r.returncode == 0 and "compared 10 frames: 0 differ" in r.stdout
                      and "replies: 0 differ" in r.stdout, f"--{mode} on {backend}: {r.stdout[-1500:]} {r.stderr[-1500:]}")
            print(f"--{mode}: the program said {said!r}; EGL and OSMesa replay its 10 frames pixel-identically")


if __name__ == "__main__":
    main()
    print("PASS")
