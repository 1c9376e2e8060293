#!/usr/bin/env python3
"""Distribution cost of the wall, on one 2-core machine: glxgears publishing to 1, 2,
4 and 8 local slaves on the null backend (they receive, decode and map, but rasterize nothing),
then to 1 and 2 slaves that render on EGL. For each: the program's frames per second (swap
counter, frames 10..N), its CPU time per frame, the message bytes per frame it sends (each
subscriber gets a copy), and the latency from the program's swap to each slave's replay of
that swap (median and 95th percentile; same machine, CLOCK_MONOTONIC). Markdown to stdout.

    bench/wall_bench.py BUILD_DIR [--frames N]
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


def measure(build, counter, tmp, slaves, backend, frames):
    glcast, shim = os.path.join(build, "glcast"), os.path.join(build, "libglcast.so")
    stream = f"ipc://{tmp}/s{slaves}{backend}"
    procs = []
    for i in range(slaves):
        env = dict(os.environ, GLCAST_TEST_PRESENT_LOG=f"{tmp}/present-{backend}-{slaves}-{i}")
        procs.append(subprocess.Popen([glcast, "slave", "--connect", stream, "--journal", stream + "-j", "--backend",
                                       backend, "--quiet", "--wait", "120"], env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    swap_log = f"{tmp}/swaps-{backend}-{slaves}"
    env = dict(os.environ, LD_PRELOAD=f"{counter}:{shim}", GLCAST_PUBLISH=stream, GLCAST_JOURNAL_ENDPOINT=stream + "-j",
               GLCAST_WAIT_SUBSCRIBERS=str(slaves), GLCAST_TEST_SWAP_LOG=swap_log, FRAME_COUNTER_EXIT=str(frames),
               FRAME_COUNTER_SKIP="10")
    p = subprocess.Popen(["glxgears"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(p.pid, 0)
    err = p.stderr.read()
    m = re.search(r"frame_counter: (\d+) frames in ([\d.]+) s", err)
    fps = int(m.group(1)) / float(m.group(2)) if m else float("nan")
    cpu_ms = (usage.ru_utime + usage.ru_stime) * 1000 / frames
    for s in procs:  # the counter ends the program with _exit: no end-of-stream message
        try:
            s.wait(timeout=10)
        except subprocess.TimeoutExpired:
            s.kill()
    swaps = {}
    for line in open(swap_log):
        f, t = line.split()
        swaps[int(f)] = float(t)
    latencies = []
    for i in range(slaves):
        path = f"{tmp}/present-{backend}-{slaves}-{i}"
        if not os.path.exists(path):
            continue
        for line in open(path):
            f, t = line.split()
            if int(f) in swaps and int(f) >= 10:
                latencies.append((float(t) - swaps[int(f)]) * 1000)
    latencies.sort()
    med = statistics.median(latencies) if latencies else float("nan")
    p95 = latencies[int(0.95 * (len(latencies) - 1))] if latencies else float("nan")
    return fps, cpu_ms, med, p95, len(latencies)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--frames", type=int, default=1000)
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    tmp = tempfile.mkdtemp(prefix="glcast-wall-bench-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    rows = []
    with Xvfb():
        capture = os.path.join(tmp, "size.glcs")
        subprocess.run([os.path.join(build, "glcast"), "capture", "-o", capture, "--frames", str(a.frames), "--",
                        "glxgears"], capture_output=True, check=True)
        bytes_per_frame = os.path.getsize(capture) / a.frames
        for backend, counts in (("null", (1, 2, 4, 8)), ("egl", (1, 2))):
            for n in counts:
                rows.append((backend, n) + measure(build, counter, tmp, n, backend, a.frames))
                print(rows[-1], file=sys.stderr)
    base = {r[0]: r[2] for r in rows if r[1] == 1}
    print(f"glxgears, {a.frames} frames, slaves on loopback (ipc), 2 cores shared by the program, its Mesa and every "
          f"slave. Message bytes per frame: {bytes_per_frame:.0f} (each subscriber receives a copy).\n")
    print("| slaves | backend | program fps | fps / 1 slave | program CPU ms/frame | latency median ms | latency p95 ms |")
    print("|---|---|---|---|---|---|---|")
    for backend, n, fps, cpu, med, p95, count in rows:
        print(f"| {n} | {backend} | {fps:.0f} | {fps / base[backend]:.2f} | {cpu:.3f} | {med:.2f} | {p95:.2f} |")


if __name__ == "__main__":
    main()
