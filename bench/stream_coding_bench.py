#!/usr/bin/env python3
"""Bytes per frame of the stream: each message compressed alone (GLCAST_INTER_FRAME=0,
the coding before format version 2), against the previous message (version 2's inter-frame
coding, the default), and apitrace's trace of the same frames (whole, and its steady bytes a
frame: a trace of FRAMES frames less one of 10, over FRAMES - 10); at zstd levels 1 and 3. Every
program draws FRAMES frames at 640x480 under Xvfb; the first 10 (start-up: textures, lists)
are counted apart, so the steady state shows. Writes a markdown table to stdout.

    bench/stream_coding_bench.py BUILD_DIR [--frames N]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
HACKS = "/usr/libexec/xscreensaver"


def programs(build):
    geometry = ["-window", "-geometry", "640x480"]
    out = {name: [os.path.join(HACKS, name)] + geometry
           for name in ("moebius", "atlantis", "sproingies", "gears", "pipes", "superquadrics", "engine", "glplanet",
                        "lament", "cage")}
    out["glxgears"] = ["glxgears", "-geometry", "640x480"]
    out["ff_scene"] = [os.path.join(build, "tests", "apps", "ff_scene"), "--frames", "100000"]
    out["core_scene"] = [os.path.join(build, "tests", "apps", "core_scene"), "--frames", "100000"]
    return out


def summary_bytes(glcast, capture, first, last):
    """Stored bytes of frames first..last from glcast dump --summary."""
    r = subprocess.run([glcast, "dump", capture, "--summary"], capture_output=True, text=True, timeout=600)
    total = 0
    for m in re.finditer(r"# frame (\d+): \d+ calls, \d+ bytes raw, (\d+) stored", r.stdout):
        if first <= int(m.group(1)) <= last:
            total += int(m.group(2))
    return total


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--frames", type=int, default=60)
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    shim, glcast = os.path.join(build, "libglcast.so"), os.path.join(build, "glcast")
    tmp = tempfile.mkdtemp(prefix="glcast-coding-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    rows = []
    steady = (10, a.frames - 2)  # the last frame may be cut short by the exit
    with Xvfb():
        for name, cmd in programs(build).items():
            if not os.path.exists(cmd[0]) and "/" in cmd[0]:
                print(f"{name}: not installed, skipped", file=sys.stderr)
                continue
            row = {"name": name}
            for label, env in (("alone1", {"GLCAST_INTER_FRAME": "0"}), ("inter1", {}),
                               ("alone3", {"GLCAST_INTER_FRAME": "0", "GLCAST_ZSTD_LEVEL": "3"}),
                               ("inter3", {"GLCAST_ZSTD_LEVEL": "3"}), ("raw", {"GLCAST_ZSTD_LEVEL": "0"})):
                capture = os.path.join(tmp, f"{name}-{label}.glcs")
                r = subprocess.run(cmd, env=dict(os.environ, LD_PRELOAD=shim, GLCAST_CAPTURE=capture,
                                                 GLCAST_FRAMES=str(a.frames), GLCAST_EXIT_AFTER_FRAMES="1",
                                                 GLCAST_VERBOSE="1", **env),
                                   capture_output=True, text=True, timeout=600)
                m = re.search(r"compression ([\d.]+) ms a frame", r.stderr)
                row[label + "_ms"] = float(m.group(1)) if m else float("nan")
                row[label] = summary_bytes(glcast, capture, *steady) / (steady[1] - steady[0] + 1)
                row[label + "_all"] = os.path.getsize(capture) / a.frames
            # apitrace's whole trace of the frames, and its steady bytes a frame: what a trace of
            # `frames` frames holds more than one of `steady[0]` frames (its start-up), per frame.
            sizes = {}
            for frames in (steady[0], a.frames):
                trace = os.path.join(tmp, f"{name}-{frames}.trace")
                subprocess.run(["apitrace", "trace", "-o", trace, "--"] + cmd,
                               env=dict(os.environ, LD_PRELOAD=counter, FRAME_COUNTER_EXIT=str(frames),
                                        FRAME_COUNTER_SKIP="1"), capture_output=True, timeout=600)
                sizes[frames] = os.path.getsize(trace) if os.path.exists(trace) else float("nan")
            row["apitrace_all"] = sizes[a.frames] / a.frames
            row["apitrace_steady"] = (sizes[a.frames] - sizes[steady[0]]) / (a.frames - steady[0])
            rows.append(row)
            print(f"{name}: {row}", file=sys.stderr)

    print(f"Bytes per frame: frames {steady[0]}-{steady[1]} of {a.frames} (steady state) and the whole file / "
          f"{a.frames} (all, with start-up), 640x480, llvmpipe under Xvfb. ms/frame: the writer thread's "
          f"compression time per frame (GLCAST_VERBOSE's summary). KB/s per tile: steady inter-1 bytes x 60 (a unicast "
          f"tile receives the whole stream).\n")
    print("| program | raw | zstd-1 alone | zstd-1 inter-frame | zstd-3 alone | zstd-3 inter-frame | inter-1 / alone-1 | "
          "all frames: inter-1 | all frames: apitrace | inter-1 / apitrace (all) | steady: apitrace | "
          "inter-1 / apitrace (steady) | ms/frame alone-1 | ms/frame inter-1 | KB/s per tile at 60 fps |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['name']} | {r['raw']:,.0f} | {r['alone1']:,.0f} | {r['inter1']:,.0f} | {r['alone3']:,.0f} | "
              f"{r['inter3']:,.0f} | {r['inter1'] / max(r['alone1'], 1):.3f} | {r['inter1_all']:,.0f} | "
              f"{r['apitrace_all']:,.0f} | {r['inter1_all'] / r['apitrace_all']:.3f} | {r['apitrace_steady']:,.0f} | "
              f"{r['inter1'] / r['apitrace_steady']:.3f} | {r['alone1_ms']:.3f} | "
              f"{r['inter1_ms']:.3f} | {r['inter1'] * 60 / 1000:,.1f} |")


if __name__ == "__main__":
    main()
