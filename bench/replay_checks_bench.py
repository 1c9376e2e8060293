#!/usr/bin/env python3
"""What the slave's checks cost: process CPU time of `glcast replay FILE --backend egl` with two
glcast binaries (say, a build from before the checks and one with them) on the committed
captures made longer (glcast_stream_edit `stream:repeat=N`), interleaved in one run, medians of
R repeats. Writes a markdown table to stdout.

    bench/replay_checks_bench.py BEFORE_GLCAST AFTER_GLCAST STREAM_EDIT DATA_DIR [--repeat N] [--runs R]
"""
import argparse
import os
import resource
import statistics
import subprocess
import tempfile

CAPTURES = ["ff_scene", "core_scene", "glfw_dynamic", "glxgears"]


def cpu_seconds(cmd, env):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed: {r.stderr[-500:]}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), r.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("stream_edit")
    ap.add_argument("data")
    ap.add_argument("--repeat", type=int, default=100, help="times each message after the first is repeated")
    ap.add_argument("--runs", type=int, default=7)
    a = ap.parse_args()
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    tmp = tempfile.mkdtemp(prefix="glcast-checks-bench-")
    print(f"| capture (x{a.repeat}) | calls | before | after | after / before |")
    print("|---|---|---|---|---|")
    for name in CAPTURES:
        longer = os.path.join(tmp, name + ".glcs")
        subprocess.run([a.stream_edit, os.path.join(a.data, name + ".glcs"), longer, f"stream:repeat={a.repeat}"],
                       check=True)
        times = {"before": [], "after": []}
        calls = ""
        for _ in range(a.runs):
            for which in ("before", "after"):
                t, out = cpu_seconds([getattr(a, which), "replay", longer, "--backend", "egl"], env)
                times[which].append(t)
                calls = out.split(",")[1].strip() if "," in out else calls
        b, f = statistics.median(times["before"]), statistics.median(times["after"])
        print(f"| {name} | {calls} | {b:.3f} s | {f:.3f} s | {f / b:.3f} |", flush=True)


if __name__ == "__main__":
    main()
