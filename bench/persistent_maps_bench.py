#!/usr/bin/env python3
"""Streaming through one persistent coherent mapping (tests/apps_extra/persistent_maps.c --shape ring:
each draw writes its triangle, 96 bytes, at the next 4 KiB-aligned offset of the ring) at several
ring sizes and draws a frame: the program alone, capturing to a file, publishing to one slave
(glcast slave, EGL, its own process on the same cores), and the floor: the same stream with the
writes made by glBufferSubData (no mapping, nothing to find), captured. The configurations run
interleaved, REPEATS times each; medians. Frames per second and the program's CPU per frame (user +
system of every thread of the process, from frame 10 on), peak RSS (the process's ru_maxrss),
and bytes a frame on the stream before compression (GLCAST_ZSTD_LEVEL=0, the difference of two
captures of different lengths) against the bytes the program wrote. Markdown on stdout.

    bench/persistent_maps_bench.py BUILD_DIR [--rings 4,64,256] [--draws 100,1000] [--repeats R]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def run(cmd, env, frames):
    """fps, CPU ms a frame, peak RSS MiB of one run of `frames` frames (10 more before)."""
    p = subprocess.Popen(cmd, env=dict(os.environ, FRAME_COUNTER_EXIT=str(frames + 10), FRAME_COUNTER_SKIP="10", **env),
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = status
    m = re.search(r"frame_counter: (\d+) frames in ([\d.]+) s = [\d.]+ fps, cpu ([\d.]+) s", err)
    if not m:
        raise RuntimeError(f"{cmd}: no frame count: {err[-1500:]}")
    n, seconds, cpu = int(m.group(1)), float(m.group(2)), float(m.group(3))
    return n / seconds, cpu / n * 1000, usage.ru_maxrss / 1024


def stream_bytes(cmd, shim, tmp, frames):
    """Uncompressed stream bytes a frame, from two captures `frames` frames apart."""
    sizes = []
    for n in (10, 10 + frames):
        path = os.path.join(tmp, f"size-{n}.glcs")
        subprocess.run(cmd, env=dict(os.environ, LD_PRELOAD=shim, GLCAST_CAPTURE=path, GLCAST_ZSTD_LEVEL="0",
                                     GLCAST_FRAMES=str(n), GLCAST_EXIT_AFTER_FRAMES="1"),
                       capture_output=True, timeout=600, check=True)
        sizes.append(os.path.getsize(path))
    return (sizes[1] - sizes[0]) / frames


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--rings", default="4,64,256", help="ring sizes in MiB")
    ap.add_argument("--draws", default="100,1000", help="draws a frame")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--draws-measured", type=int, default=20000, help="draws timed in each run (frames = this / draws)")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    shim, glcast = os.path.join(build, "libglcast.so"), os.path.join(build, "glcast")
    program = os.path.join(build, "tests", "apps", "persistent_maps")
    tmp = tempfile.mkdtemp(prefix="glcast-persistent-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    stream = f"ipc://{tmp}/stream"
    rows = []
    with Xvfb():
        for mb in (int(x) for x in a.rings.split(",")):
            for draws in (int(x) for x in a.draws.split(",")):
                frames = max(20, a.draws_measured // draws)
                ring = [program, "--shape", "ring", "--ring-mb", str(mb), "--draws", str(draws), "--frames", "1000000",
                        "--size", "640x480"]
                floor = [program, "--shape", "subdata"] + ring[3:]
                configs = {
                    "alone": (ring, {"LD_PRELOAD": counter}),
                    "capture": (ring, {"LD_PRELOAD": f"{counter}:{shim}", "GLCAST_CAPTURE": os.path.join(tmp, "c.glcs")}),
                    "slave": (ring, {"LD_PRELOAD": f"{counter}:{shim}", "GLCAST_PUBLISH": stream,
                                     "GLCAST_JOURNAL_ENDPOINT": stream + "-journal", "GLCAST_WAIT_SUBSCRIBERS": "1"}),
                    "floor": (floor, {"LD_PRELOAD": f"{counter}:{shim}", "GLCAST_CAPTURE": os.path.join(tmp, "f.glcs")}),
                }
                results = {k: [] for k in configs}
                for _ in range(a.repeats):
                    for k, (cmd, env) in configs.items():
                        slave = None
                        if k == "slave":
                            slave = subprocess.Popen([glcast, "slave", "--connect", stream, "--journal",
                                                      stream + "-journal", "--backend", "egl", "--quiet", "--wait", "60"],
                                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                            time.sleep(0.3)
                        results[k].append(run(cmd, env, frames))
                        if slave:  # the program has its figures; the slave's replay is not measured
                            slave.kill()
                            slave.wait()
                med = {k: tuple(statistics.median(r[i] for r in v) for i in range(3)) for k, v in results.items()}
                written = draws * 96
                on_stream = stream_bytes(ring, shim, tmp, max(10, frames // 4))
                rows.append((mb, draws, frames, med, written, on_stream))
                print(f"{mb} MiB, {draws} draws: {med} written {written} stream {on_stream:.0f}", file=sys.stderr)

    print(f"Median of {a.repeats} interleaved runs; each run times {a.draws_measured} draws (frames = that / draws a "
          "frame) after 10 frames; 640x480, Mesa llvmpipe under Xvfb. fps ratios are against the program alone; the "
          "floor is the same stream through glBufferSubData, captured. Stream bytes are uncompressed, a frame.\n")
    print("| ring | draws/frame | alone fps | capturing fps | publishing, one slave, fps | floor fps | capture / alone "
          "| slave / alone | CPU ms/frame alone / capturing / slave | written B/frame | stream B/frame "
          "| RSS MiB alone / capturing / slave |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for mb, draws, frames, m, written, on_stream in rows:
        print(f"| {mb} MiB | {draws} | {m['alone'][0]:.0f} | {m['capture'][0]:.0f} | {m['slave'][0]:.0f} | "
              f"{m['floor'][0]:.0f} | {m['capture'][0] / m['alone'][0]:.2f} | {m['slave'][0] / m['alone'][0]:.2f} | "
              f"{m['alone'][1]:.2f} / {m['capture'][1]:.2f} / {m['slave'][1]:.2f} | {written:,} | {on_stream:,.0f} | "
              f"{m['alone'][2]:.0f} / {m['capture'][2]:.0f} / {m['slave'][2]:.0f} |")


if __name__ == "__main__":
    main()
