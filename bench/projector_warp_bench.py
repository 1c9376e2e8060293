#!/usr/bin/env python3
"""What a projector's warp and blend cost: `glcast replay CAPTURE --config WALL --tile p` of one
1920x1080 tile with a warp (a barrel distortion, 241x136 nodes) and a blend (an edge ramp),
against the same tile without them, interleaved A B A B, whole-process CPU (user + system).
Prints the medians and the ratio A/B; and, in the same interleaved rounds, the least any
full-screen pass can add to the plain replay on this driver (bench/fullscreen_pass.c: one
textured quad per frame, the simplest shader, nearest texels) as the same ratio.

    bench/projector_warp_bench.py BUILD_DIR CAPTURE [--repeats R]

CAPTURE: a capture of several hundred frames, so that start-up (the driver, the shaders) does
not hide the per-frame cost; docs/performance.md names the one measured.
"""
import argparse
import json
import math
import os
import resource
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import zlib

W, H = 1920, 1080


def write_maps(folder):
    nx, ny = 121, 68
    rows = []
    for j in range(ny):  # node rows top to bottom; PFM stores them bottom to top
        row = []
        for i in range(nx):
            x, y = i / (nx - 1) * 2 - 1, j / (ny - 1) * 2 - 1
            k = 1 + 0.08 * (x * x + y * y)  # a projector lens's barrel, undone
            row += [(x / k + 1) / 2, (y / k + 1) / 2, 0.0]
        rows.append(row)
    with open(os.path.join(folder, "warp.pfm"), "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (nx, ny))
        for row in reversed(rows):
            f.write(struct.pack("<%df" % len(row), *row))
    ramp = bytes(min(255, int(255 * min(1.0, x / 300, (W - 1 - x) / 300))) for x in range(W))
    raw = b"".join(b"\x00" + ramp for _ in range(H))
    chunk = lambda kind, body: struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(os.path.join(folder, "blend.png"), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 0, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    tile = {"name": "p", "x": 0, "y": 0, "width": W, "height": H}
    for name, extra in (("warped.json", {"warp": "warp.pfm", "blend": "blend.png"}), ("plain.json", {})):
        json.dump({"name": "bench", "canvas": {"width": W, "height": H}, "tiles": [dict(tile, **extra)]},
                  open(os.path.join(folder, name), "w"))


def cpu_of(cmd, out=None):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {r.stderr[-2000:]}")
    if out is not None:
        out.append(r.stdout + r.stderr)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("capture")
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    glcast = os.path.join(os.path.abspath(a.build), "glcast")
    with tempfile.TemporaryDirectory() as folder:
        write_maps(folder)
        runs = {"warped": [], "plain": [], "pass": []}
        said = []
        for _ in range(a.repeats):
            for name in ("warped", "plain"):
                runs[name].append(cpu_of([glcast, "replay", a.capture, "--backend", "egl", "--config",
                                          os.path.join(folder, name + ".json"), "--tile", "p"], said))
            frames = int(said[-1].split("replayed ", 1)[1].split()[0])
            per_pass = subprocess.run([os.path.join(os.path.abspath(a.build), "tests", "fullscreen_pass"), str(frames),
                                       f"{W}x{H}"], capture_output=True, text=True, timeout=1800, check=True)
            runs["pass"].append(float(per_pass.stdout) * frames)
        ratios = [w / p for w, p in zip(runs["warped"], runs["plain"])]
        floor = [(p + f) / p for p, f in zip(runs["plain"], runs["pass"])]
        print(f"| tile | warped CPU s (median) | plain CPU s (median) | A/B min | A/B median | A/B max |")
        print(f"|---|---|---|---|---|---|")
        print(f"| {W}x{H}, {os.path.basename(a.capture)} | {statistics.median(runs['warped']):.2f} | "
              f"{statistics.median(runs['plain']):.2f} | {min(ratios):.3f} | {statistics.median(ratios):.3f} | "
              f"{max(ratios):.3f} |")
        print(f"| the plain replay and one full-screen pass a frame (fullscreen_pass) | - | "
              f"{statistics.median(runs['plain']):.2f} + {statistics.median(runs['pass']):.2f} | {min(floor):.3f} | "
              f"{statistics.median(floor):.3f} | {max(floor):.3f} |")


if __name__ == "__main__":
    main()
