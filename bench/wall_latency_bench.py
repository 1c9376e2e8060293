#!/usr/bin/env python3
"""Time on the wall (docs/wall.md, "Time on the wall"): a 2x2 wall of local slaves (`glcast run`
with tests/configs/wall-2x2-barrier.json, 640x480 tiles) showing glxgears, with `--timing`, on the
null backend (receive, decode, map names: no rasterizing) and on EGL (llvmpipe), with and without
the swap barrier. The program is paced to --fps frames a second (bench/frame_counter.c), as a
display's refresh would hold it. For each: swap-to-present of every tile's frames (median, p95,
p99), the spread between the first and the last tile presenting each frame, the program's frame
rate, and where the time goes (medians): swap to arrival (the network, and a slave still busy
with an earlier frame), arrival to replayed (decode and replay), replayed to presented (the
barrier's wait and the present). The configurations run interleaved, --rounds times each, and
every sample of all rounds is pooled. Markdown to stdout.

--slow: the same wall with the barrier on the null backend, one tile's slave stopped (SIGSTOP) for
--stop-seconds from 3 s in and then continued: the other tiles' swap-to-present before, while
the barrier waits for the stopped tile (until it drops it: docs/wall.md), after the drop, and after
the tile is back.

    bench/wall_latency_bench.py BUILD_DIR [--frames N] [--fps N] [--rounds N] [--slow]
"""
import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
sys.path.insert(0, os.path.join(ROOT, "tests", "e2e"))
from xvfb import Xvfb, descendants  # noqa: E402

TILES = ("top-left", "top-right", "bottom-left", "bottom-right")


def config_file(tmp, barrier):
    with open(os.path.join(ROOT, "tests", "configs", "wall-2x2-barrier.json")) as f:
        config = json.load(f)
    config["swap_barrier"] = barrier
    path = os.path.join(tmp, f"wall-2x2-{'barrier' if barrier else 'free'}.json")
    with open(path, "w") as f:
        json.dump(config, f)
    return path


def run_wall(glcast, counter, tmp, backend, barrier, frames, fps, name, during=None):
    """One `glcast run --timing`; returns the timing file's lines. `during(run_pid)` runs beside it."""
    timing = os.path.join(tmp, f"{name}.jsonl")
    program = ["sh", "-c", f'LD_PRELOAD="{counter}:$LD_PRELOAD" exec glxgears']
    env = dict(os.environ, FRAME_COUNTER_FPS=str(fps))
    p = subprocess.Popen([glcast, "run", "--config", config_file(tmp, barrier), "--backend", backend, "--frames",
                          str(frames), "--timing", timing, "--"] + program, env=env,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    side = threading.Thread(target=during, args=(p.pid,)) if during else None
    if side:
        side.start()
    err = p.communicate()[1]
    if side:
        side.join()
    if p.returncode != 0:
        raise RuntimeError(f"glcast run failed ({p.returncode}): {err[-2000:]}")
    return [json.loads(line) for line in open(timing)], err


def pct(values, q):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, int(round(q * (len(v) - 1))))]


def figures(lines, skip=30):
    """Samples of frames every tile presented live, after the first `skip` (joining)."""
    full = [l for l in lines if l["swap"] is not None and len(l["tiles"]) == len(TILES)]
    full = full[skip:]
    lat, spread, net, work, wait, err = [], [], [], [], [], []
    for l in full:
        ts = l["tiles"].values()
        for t in ts:
            lat.append(t["presented"] - l["swap"])
            net.append(t["arrived"] - l["swap"])
            work.append(t["replayed"] - t["arrived"])
            wait.append(t["presented"] - t["replayed"])
            err.append(t["clock_error"])
        presents = [t["presented"] for t in ts]
        spread.append(max(presents) - min(presents))
    swaps = sorted(l["swap"] for l in lines if l["swap"] is not None)
    fps = (len(swaps) - 1) / (swaps[-1] - swaps[0]) if len(swaps) > 1 else float("nan")
    return dict(lat=lat, spread=spread, net=net, work=work, wait=wait, err=err, fps=fps, frames=len(full),
                timed=len(lines))


def merge(pooled, f):
    """Two rounds' figures as one: every sample of both, the frame rate their mean."""
    if pooled is None:
        return dict(f, rates=[f["fps"]])
    out = {k: pooled[k] + f[k] for k in ("lat", "spread", "net", "work", "wait", "err")}
    out.update(frames=pooled["frames"] + f["frames"], timed=pooled["timed"] + f["timed"], rates=pooled["rates"] + [f["fps"]])
    out["fps"] = statistics.mean(out["rates"])
    return out


def ms(x):
    return f"{x * 1000:.2f}"


def slave_pid(run_pid, tile):
    for pid in descendants(run_pid):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                argv = f.read().split(b"\0")
        except OSError:
            continue
        if b"slave" in argv and tile.encode() in argv:
            return pid
    return None


def slow_tile(glcast, counter, tmp, frames, fps, stop_seconds):
    marks = {}

    def stop_one(run_pid):
        time.sleep(3)
        pid = slave_pid(run_pid, "bottom-right")
        if not pid:
            print("descendants:", [open(f"/proc/{p}/cmdline").read()[:80] for p in descendants(run_pid)], file=sys.stderr)
        if not pid:
            return
        marks["stop"] = time.monotonic()
        os.kill(pid, signal.SIGSTOP)
        time.sleep(stop_seconds)
        marks["cont"] = time.monotonic()
        os.kill(pid, signal.SIGCONT)

    lines, err = run_wall(glcast, counter, tmp, "null", True, frames, fps, "slow", stop_one)
    if "stop" not in marks:
        raise RuntimeError("the slave of bottom-right was not found")
    stop, cont = marks["stop"], marks["cont"]
    others = [t for t in TILES if t != "bottom-right"]
    phases = {"before the stop": (stop - 2, stop), "stopped, before the drop (2 s)": (stop, stop + 2.5),
              "stopped, dropped": (stop + 2.5, cont), "continued": (cont, cont + 1),
              "back (from 1 s after)": (cont + 1, cont + 4)}
    rows = []
    for phase, (a, b) in phases.items():
        lat, spread, n = [], [], 0
        for l in lines:
            if l["swap"] is None or not (a <= l["swap"] < b):
                continue
            ts = [l["tiles"][t] for t in others if t in l["tiles"]]
            if len(ts) < len(others):
                continue
            n += 1
            lat += [t["presented"] - l["swap"] for t in ts]
            spread.append(max(t["presented"] for t in ts) - min(t["presented"] for t in ts))
        rows.append((phase, n, pct(lat, 0.5), pct(lat, 0.99), pct(spread, 0.99)))
    said = [line for line in err.splitlines() if "swap barrier" in line]
    return rows, said


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--fps", type=float, default=60)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--slow", action="store_true")
    ap.add_argument("--stop-seconds", type=float, default=5)
    a = ap.parse_args()
    glcast = os.path.join(os.path.abspath(a.build), "glcast")
    tmp = tempfile.mkdtemp(prefix="glcast-latency-bench-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    configs = [(b, barrier) for b in ("null", "egl") for barrier in (True, False)]
    pooled = {c: None for c in configs}
    with Xvfb():
        for r in range(a.rounds):
            for backend, barrier in configs:
                lines, _ = run_wall(glcast, counter, tmp, backend, barrier, a.frames, a.fps, f"{backend}-{barrier}-{r}")
                f = figures(lines)
                pooled[(backend, barrier)] = merge(pooled[(backend, barrier)], f)
                print(f"round {r} {backend} barrier={barrier}: {f['frames']} frames, median {ms(pct(f['lat'], .5))} ms, "
                      f"spread p99 {ms(pct(f['spread'], .99))} ms, {f['fps']:.1f} fps", file=sys.stderr)
        slow = slow_tile(glcast, counter, tmp, int(a.fps * (3 + a.stop_seconds + 5)), a.fps, a.stop_seconds) \
            if a.slow else None
    print(f"glxgears paced to {a.fps:g} fps, {a.frames} frames a run, {a.rounds} runs of each interleaved, the first 30 "
          f"frames of each left out; 2x2 wall of 640x480 tiles, four local slaves over ipc; 2 cores shared by the "
          f"program, its Mesa (Xvfb) and every slave. Milliseconds.\n")
    print("| backend | barrier | frames | swap-to-present median | p95 | p99 | spread median | p95 | p99 "
          "| program fps | to arrival | decode + replay | barrier + present | clock error max |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for backend, barrier in configs:
        f = pooled[(backend, barrier)]
        print(f"| {backend} | {'on' if barrier else 'off'} | {f['frames']} | {ms(pct(f['lat'], .5))} | "
              f"{ms(pct(f['lat'], .95))} | {ms(pct(f['lat'], .99))} | {ms(pct(f['spread'], .5))} | "
              f"{ms(pct(f['spread'], .95))} | {ms(pct(f['spread'], .99))} | {f['fps']:.1f} | {ms(pct(f['net'], .5))} | "
              f"{ms(pct(f['work'], .5))} | {ms(pct(f['wait'], .5))} | {ms(max(f['err']) if f['err'] else float('nan'))} |")
    if slow:
        rows, said = slow
        print(f"\nA slow tile: bottom-right's slave stopped (SIGSTOP) 3 s in for {a.stop_seconds:g} s, null backend, "
              f"barrier on; the other three tiles:\n")
        print("| phase | frames | swap-to-present median | p99 | spread p99 |")
        print("|---|---|---|---|---|")
        for phase, n, med, p99, sp in rows:
            print(f"| {phase} | {n} | {ms(med)} | {ms(p99)} | {ms(sp)} |")
        print("\nglcast run said: " + "; ".join(s.strip() for s in said))


if __name__ == "__main__":
    main()
