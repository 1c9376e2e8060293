#!/usr/bin/env python3
"""What glcast costs the program: frames per second and CPU time per frame (user +
system of the whole process, every thread, from rusage; both over frames 10 on) of each program natively, capturing to a file, publishing with no slave
(ipc://, with the journal, as glcast run does) and publishing to one slave (glcast slave, EGL,
its own process, not counted). The configurations run interleaved, REPEATS times each; medians.
Writes a markdown table to stdout.

    bench/program_cost_bench.py BUILD_DIR [--frames N] [--repeats R] [--only a,b] [--default-delays]
                                [--baseline OTHER_SHIM.so]
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
HACKS = "/usr/libexec/xscreensaver"


def programs(build, default_delays=False):
    # Flat out by default: on 2 cores whatever glcast takes is then taken from the program's frames.
    geometry = ["-window", "-geometry", "640x480"] + ([] if default_delays else ["-delay", "0"])
    out = {"glxgears": ["glxgears", "-geometry", "640x480"]}
    # the committed test programs (tests/apps), flat out until the frame counter stops them
    for name in ("ff_scene", "core_scene"):
        out[name] = [os.path.join(build, "tests", "apps", name), "--size", "640x480", "--frames", "100000"]
    for name in ("moebius", "atlantis", "sproingies", "gears", "pipes", "superquadrics", "engine"):
        if os.path.exists(os.path.join(HACKS, name)):
            out[name] = [os.path.join(HACKS, name)] + geometry
    return out


def run(cmd, env, frames):
    r = subprocess.run(cmd, env=dict(os.environ, FRAME_COUNTER_EXIT=str(frames), FRAME_COUNTER_SKIP="10", **env),
                       capture_output=True, text=True, timeout=600)
    m = re.search(r"frame_counter: (\d+) frames in ([\d.]+) s = [\d.]+ fps, cpu ([\d.]+) s", r.stderr)
    if not m:
        raise RuntimeError(f"{cmd}: no frame count: {r.stderr[-1500:]}")
    n, seconds, cpu = int(m.group(1)), float(m.group(2)), float(m.group(3))
    return n / seconds, cpu / n * 1000  # fps, CPU ms per frame (both over frames 10 on)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--frames", type=int, default=400)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--only", help="comma-separated program names")
    ap.add_argument("--default-delays", action="store_true",
                    help="the hacks at their own frame delays (as a screen saver runs them), not flat out")
    ap.add_argument("--baseline", help="another libglcast.so: adds publishing with it (an A/B of a change)")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    shim, glcast = os.path.join(build, "libglcast.so"), os.path.join(build, "glcast")
    tmp = tempfile.mkdtemp(prefix="glcast-cost-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    stream = f"ipc://{tmp}/stream"
    publish = {"LD_PRELOAD": f"{counter}:{shim}", "GLCAST_PUBLISH": stream, "GLCAST_JOURNAL_ENDPOINT": stream + "-journal"}
    rows = []
    with Xvfb():
        for name, cmd in programs(build, a.default_delays).items():
            if a.only and name not in a.only.split(","):
                continue
            configs = {
                "native": {"LD_PRELOAD": counter},
                "capture": {"LD_PRELOAD": f"{counter}:{shim}", "GLCAST_CAPTURE": os.path.join(tmp, "c.glcs")},
                "publish": publish,
                "slave": dict(publish, GLCAST_WAIT_SUBSCRIBERS="1"),
                "publish_nice0": dict(publish, GLCAST_WRITER_NICE="0"),  # the writer at the program's priority
            }
            if a.baseline:
                configs["baseline"] = dict(publish, LD_PRELOAD=f"{counter}:{os.path.abspath(a.baseline)}")
            results = {k: [] for k in configs}
            for _ in range(a.repeats):
                for k, env in configs.items():
                    slave = None
                    if k == "slave":
                        slave = subprocess.Popen([glcast, "slave", "--connect", stream, "--journal", stream + "-journal",
                                                  "--backend", "egl", "--quiet", "--wait", "60"],
                                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                        time.sleep(0.3)
                    results[k].append(run(cmd, env, a.frames))
                    if slave:  # the program has its figures; the slave's replay is not measured
                        slave.kill()
                        slave.wait()
            med = {k: (statistics.median(f for f, _ in v), statistics.median(c for _, c in v)) for k, v in results.items()}
            rows.append((name, med))
            print(f"{name}: {med}", file=sys.stderr)

    pace = "the hacks at their default delays" if a.default_delays else "the hacks flat out (-delay 0)"
    print(f"Median of {a.repeats} interleaved runs of {a.frames} frames (fps and CPU: the program's user + system "
          f"time, every thread, over frames 10 on), 640x480, llvmpipe under Xvfb, 2 cores, {pace}.\n")
    columns = [("capture", "capture"), ("publish", "publish, no slave"), ("slave", "publish, one slave"),
               ("publish_nice0", "publish, writer not niced")] + ([("baseline", "publish, baseline shim")]
                                                                   if a.baseline else [])
    heads = " | ".join(h for _, h in columns)
    print(f"| program | native fps | {heads} | native CPU ms/frame | {heads} |")
    print("|---" * (3 + 2 * len(columns)) + "|")
    for name, m in rows:
        nf, nc = m["native"]
        fps = " | ".join(f"{m[k][0] / nf:.2f}" for k, _ in columns)
        cpu = " | ".join(f"{m[k][1] / nc:.2f}" for k, _ in columns)
        print(f"| {name} | {nf:.0f} | {fps} | {nc:.2f} | {cpu} |")


if __name__ == "__main__":
    main()
