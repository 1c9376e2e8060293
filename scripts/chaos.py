#!/usr/bin/env python3
"""chaos.py: a wall on a bad day. `glcast run` puts a program on a local 2x2 wall (four slaves
and a keeper) and captures its stream, while its slaves and keeper are killed (SIGKILL) and
frozen (SIGSTOP, SIGCONT a few seconds later) at random. What must hold (docs/reliability.md):

- the program never dies for glcast and its memory does not grow with the chaos (its peak RSS,
  sampled every 0.2 s, against the same program run with no chaos);
- `glcast run` ends, in a bounded time, when the program ends (no hang on a frozen slave), says
  which of its slaves failed (those killed: a local wall does not restart them; systemd restarts
  a display machine's, docs/wall.md) and exits 1 then, else 0;
- the capture is whole: it ends with its end record and replays to as many frames as the
  program drew;
- the tiles that were never killed kept showing frames (the barrier-less wall does not wait for
  a frozen tile).

    scripts/chaos.py [--build build] [--frames 6000] [--seed 1] [--program glxgears] [--out DIR]

The program runs for --frames frames (`glcast run --frames`, which ends it normally); the chaos
lasts as long.

Needs Xvfb. Prints one line per event and a summary; exits 1 when an invariant breaks.
"""
import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402


def children(pid):
    """Every descendant of `pid`: {pid: command line}."""
    out, todo = {}, [pid]
    while todo:
        p = todo.pop()
        try:
            kids = open(f"/proc/{p}/task/{p}/children").read().split()
        except OSError:
            continue
        for k in map(int, kids):
            try:
                out[k] = open(f"/proc/{k}/cmdline").read().replace("\0", " ").strip()
            except OSError:
                continue
            todo.append(k)
    return out


def rss_kib(pid):
    try:
        for line in open(f"/proc/{pid}/status"):
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def run_wall(glcast, out, program, frames, chaos, seed):
    """One `glcast run` of `program` for `frames` frames; with `chaos`, slaves and keeper are
    killed and frozen at random meanwhile. Returns what was measured."""
    rng = random.Random(seed)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture = os.path.join(out, "capture.glcs")
    status = os.path.join(out, "status.jsonl")
    env = dict(os.environ, GLCAST_CAPTURE=capture)
    cmd = [glcast, "run", "--config", os.path.join(ROOT, "display_configs", "wall-2x2.json"), "--backend", "egl",
           "--status-json", status, "--frames", str(frames), "--"] + program
    run = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=open(os.path.join(out, "run.log"), "w"),
                           start_new_session=True)
    events, frozen, killed, peak = [], {}, set(), 0
    started = time.monotonic()
    next_event = started + rng.uniform(2, 4)
    program_pid = None
    program_seen_end = None
    while run.poll() is None and time.monotonic() - started < 3600:
        procs = children(run.pid)
        if program_pid is None:
            program_pid = next((p for p, c in procs.items() if os.path.basename(program[0]) in c.split()[0]), None)
        elif program_pid not in procs:  # the program ended: the chaos ends with it
            program_seen_end = time.monotonic()
            break
        if program_pid:
            peak = max(peak, rss_kib(program_pid))
        now = time.monotonic()
        for p, until in list(frozen.items()):
            if now >= until:
                os.kill(p, signal.SIGCONT) if p in procs else None
                events.append(f"{now - started:6.1f} s  SIGCONT {p}")
                del frozen[p]
        if chaos and now >= next_event:
            victims = [p for p, c in procs.items() if (" slave " in f" {c} " or " keeper " in f" {c} ")
                       and p not in frozen and p not in killed]
            if victims:
                v = rng.choice(victims)
                what = re.search(r"--tile (\S+)", procs[v])
                name = what.group(1) if what else "keeper"
                # Freezes mostly; at most two of the four tiles killed, so the wall goes on.
                if rng.random() < 0.3 and len(killed) < 2 and name != "keeper":
                    os.kill(v, signal.SIGKILL)
                    killed.add(v)
                    events.append(f"{now - started:6.1f} s  SIGKILL {name}")
                else:
                    frozen[v] = now + rng.uniform(1, 6)
                    os.kill(v, signal.SIGSTOP)
                    events.append(f"{now - started:6.1f} s  SIGSTOP {name} for {frozen[v] - now:.1f} s")
            next_event = now + rng.uniform(2, 5)
        time.sleep(0.2)
    for p in frozen:
        try:
            os.kill(p, signal.SIGCONT)
        except OSError:
            pass
    # The program ended (or an hour went by); run must end after it, in bounded time.
    ended_at = program_seen_end or time.monotonic()
    try:
        rc = run.wait(timeout=150)
    except subprocess.TimeoutExpired:
        os.killpg(run.pid, signal.SIGKILL)
        rc = None
    run_end = time.monotonic() - ended_at
    statuses = []
    if os.path.exists(status):
        for line in open(status):
            try:
                statuses.append(json.loads(line))
            except ValueError:
                pass
    return {"events": events, "peak_rss_kib": peak, "run_rc": rc, "run_end_s": run_end, "capture": capture,
            "statuses": statuses, "program_pid": program_pid, "seconds": ended_at - started}


def replayed_frames(glcast, capture):
    r = subprocess.run([glcast, "replay", capture, "--backend", "egl"], capture_output=True, text=True,
                       env={k: v for k, v in os.environ.items() if k != "DISPLAY"}, timeout=900)
    m = re.search(r"replayed (\d+) frames", r.stdout + r.stderr)
    return r.returncode, int(m.group(1)) if m else -1, (r.stdout + r.stderr)[-600:]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--frames", type=int, default=6000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--program", default="glxgears")
    ap.add_argument("--out", default="/tmp/glcast-chaos")
    a = ap.parse_args()
    glcast = os.path.join(a.build, "glcast")
    program = a.program.split()
    failures = []
    with Xvfb():
        calm = run_wall(glcast, os.path.join(a.out, "calm"), program, a.frames, False, a.seed)
        wild = run_wall(glcast, os.path.join(a.out, "chaos"), program, a.frames, True, a.seed)
    for line in wild["events"]:
        print(line)
    for name, r in (("calm", calm), ("chaos", wild)):
        rc, frames, tail = replayed_frames(glcast, r["capture"])
        r["replay_rc"], r["frames"] = rc, frames
        print(f"{name}: {r['seconds']:.1f} s, {len(r['events'])} events; run exit {r['run_rc']}, "
              f"{r['run_end_s']:.1f} s after the program ended; program "
              f"peak RSS {r['peak_rss_kib'] / 1024:.1f} MiB; capture replays {frames} frames (exit {rc})")
        # run says which of its slaves failed (a killed one) and exits 1 then, else 0.
        killed = sorted({e.split()[-1] for e in r["events"] if "SIGKILL" in e and not e.endswith("keeper")})
        log = open(os.path.join(os.path.dirname(r["capture"]), "run.log")).read()
        if r["run_rc"] is None:
            failures.append(f"{name}: glcast run did not end within 150 s of the program")
        elif r["run_rc"] != (1 if killed else 0):
            failures.append(f"{name}: glcast run exited {r['run_rc']} with {len(killed)} slaves killed")
        for tile in killed:
            if f"slave {tile} failed" not in log:
                failures.append(f"{name}: run did not say that slave {tile} failed")
        if rc != 0 or frames < a.frames:
            failures.append(f"{name}: the capture does not replay whole: {tail}")
        if r["program_pid"] is None:
            failures.append(f"{name}: the program was never seen")
    last = wild["statuses"][-1]["tiles"] if wild["statuses"] else []
    print("chaos: last status: " + ", ".join(f"{t['tile']} {t['state']} frame {t.get('frame', 0)}" for t in last))
    if calm["peak_rss_kib"] and wild["peak_rss_kib"] > 1.25 * calm["peak_rss_kib"] + 32 * 1024:
        failures.append(f"the program grew under chaos: peak {wild['peak_rss_kib']} KiB against {calm['peak_rss_kib']}")
    for f in failures:
        print("FAIL: " + f)
    print("chaos: " + ("every invariant held" if not failures else f"{len(failures)} invariants broken"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
