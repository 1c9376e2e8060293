#!/usr/bin/env python3
"""A capture never lies about being whole. Written onto a disk that fills (here: a file size limit,
RLIMIT_FSIZE, with SIGXFSZ ignored, so that writes fail as on a full disk), the capture stops at
its last whole message with one message, `glcast capture` exits non-zero, and the file replays
to that message, `glcast replay` and `glcast dump` saying where it was cut. A complete capture
ends with its end record and replays with exit 0. A program killed while capturing leaves a file
its readers call cut. (Before: the same error a thousand times, writes going on after a half-written
message, exit 0, and a file readable only in part; a killed program's capture replayed with no word.)

    capture_cut_test.py     with GLCAST, GLCAST_SHIM, OUT_DIR in the environment
"""
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "capture_cut")


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(args, **kw):
    return subprocess.run(args, capture_output=True, text=True, timeout=300, **kw)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    whole, cut, killed, recorded = (os.path.join(OUT, n) for n in ("whole.glcs", "cut.glcs", "killed.glcs",
                                                                    "recorded.glcs"))
    with Xvfb():
        r = run([GLCAST, "capture", "-o", whole, "--frames", "30", "--", "glxgears"])
        check(r.returncode == 0, f"a whole capture failed: {r.stderr[-2000:]}")
        # 12 KiB of file at most: glxgears' first 600 frames need about 20.
        r = run(["bash", "-c", f"trap '' XFSZ; ulimit -f 12; exec {GLCAST} capture -o {cut} --frames 600 -- glxgears"])
        said = [line for line in r.stderr.splitlines() if line.startswith("glcast: writing")]
        print(f"full disk: glcast capture exit {r.returncode}, {len(said)} write error message(s), "
              f"{os.path.getsize(cut)} bytes kept")
        check(r.returncode != 0, "glcast capture exited 0 on a capture the disk cut short")
        check(len(said) == 1, f"{len(said)} write error messages, not one: {said[:3]}")
        check("whole messages" in said[0] and "the program goes on" in said[0], said[0])
        check(os.path.getsize(cut) <= 12 * 1024, "the capture went on past the limit")
        # The same disk under a recording from a frame on (glcast record behind a keeper).
        r = run(["bash", "-c", f"trap '' XFSZ; ulimit -f 72; exec {GLCAST} capture -o {recorded} --start-frame 20 "
                               f"--frames 3000 -- glxgears"])  # the snapshot alone is about 58 KiB
        said = [line for line in r.stderr.splitlines() if line.startswith("glcast: writing")]
        print(f"full disk under a recording: glcast capture --start-frame exit {r.returncode}, {len(said)} write error "
              f"message(s), {os.path.getsize(recorded)} bytes kept")
        check(r.returncode != 0, f"glcast capture --start-frame exited 0 on a recording the disk cut short: {r.stderr[-1500:]}")
        check(len(said) == 1 and "whole messages" in said[0], f"write error messages: {said[:3]}")
        # A program killed while it captures: its stream never closed.
        program = subprocess.Popen([GLCAST, "capture", "-o", killed, "--", "glxgears"], stdout=subprocess.DEVNULL,
                                   stderr=subprocess.PIPE, text=True)
        time.sleep(1.5)
        # Only this capture's program (glcast capture's child): other tests may run glxgears too.
        subprocess.run(["pkill", "-KILL", "-P", str(program.pid)], check=False)
        program.wait(timeout=60)
    r = run([GLCAST, "replay", whole, "--backend", "egl"], env=headless)
    check(r.returncode == 0 and "cut" not in r.stderr, f"a whole capture replays with: {r.returncode} {r.stderr[-1000:]}")
    for name, path in (("full disk", cut), ("full disk under a recording", recorded), ("killed program", killed)):
        r = run([GLCAST, "replay", path, "--backend", "egl", "--out", path + ".frames"], env=headless)
        frames = len(os.listdir(path + ".frames")) if os.path.isdir(path + ".frames") else 0
        print(f"{name}: replay exit {r.returncode}, {frames} frames written; {r.stderr.strip().splitlines()[-1]}")
        check(r.returncode != 0, f"{name}: the replay of a cut capture exited 0")
        check("the capture was cut after message" in r.stderr, f"{name}: the replay did not say where: {r.stderr[-800:]}")
        check(frames > 10, f"{name}: only {frames} frames replayed before the cut")
        r = run([GLCAST, "dump", path, "--summary"])
        check(r.returncode != 0 and "the capture was cut after message" in r.stderr,
              f"{name}: glcast dump did not say it was cut: {r.returncode} {r.stderr[-500:]}")
    print("1 passed, 0 failed")


if __name__ == "__main__":
    main()
