#!/usr/bin/env python3
"""`glcast run` leaves nothing behind however it ends: its temporary folder is removed and every
slave and keeper it started is stopped and reaped, on an error after the slaves started too.

    run_cleanup_test.py GLCAST
"""
import json
import os
import subprocess
import sys
import tempfile
import time


def processes_naming(text):
    """Processes whose command line contains `text` (the slaves name the run's folder)."""
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                if text.encode() in f.read():
                    found.append(int(pid))
        except OSError:
            pass
    return found


def case(glcast, name, args, expect_in_log, max_seconds, succeeds=False):
    with tempfile.TemporaryDirectory(prefix="glcast-cleanup-") as tmp:
        env = dict(os.environ, TMPDIR=tmp)
        env.pop("DISPLAY", None)
        t0 = time.monotonic()
        r = subprocess.run([glcast, "run", "--backend", "egl"] + args, env=env, capture_output=True, text=True,
                           timeout=180)
        took = time.monotonic() - t0
        left = os.listdir(tmp)
        alive = processes_naming(tmp)
        problems = []
        if (r.returncode == 0) != succeeds:
            problems.append(f"exited {r.returncode}")
        if expect_in_log not in r.stderr:
            problems.append(f"no '{expect_in_log}' in its messages")
        if left:
            problems.append(f"left {left} in TMPDIR")
        if alive:
            problems.append(f"left processes {alive} running")
        if took > max_seconds:
            problems.append(f"took {took:.1f} s (at most {max_seconds})")
        print(f"{name}: exit {r.returncode} in {took:.1f} s; " + ("; ".join(problems) if problems else "nothing left"))
        if problems:
            print(r.stderr[-3000:])
        return not problems


def main():
    glcast = sys.argv[1]
    ok = True
    # The status file cannot be written: found after the slaves have started.
    ok &= case(glcast, "status file in a missing folder",
               ["--status-json", "/nonexistent-glcast-dir/status.json", "--", "true"], "--status-json", 30)
    # The program cannot be started: the slaves, waiting for its stream, are stopped at once.
    ok &= case(glcast, "a program that does not exist",
               ["--", "/nonexistent-glcast-program"], "the program did not run", 30)
    # A program that runs but never calls GL: its slaves would wait 120 s for a stream that never
    # comes (they did); they are stopped at once, and run exits with the program's status.
    ok &= case(glcast, "a program that makes no GL calls", ["--", "true"], "the program made no GL calls", 20,
               succeeds=True)
    # A bad endpoint: refused before anything starts; the folder made for it goes.
    ok &= case(glcast, "an endpoint it cannot serve", ["--endpoint", "bogus://x", "--", "true"], "glcast run:", 30)
    ok &= case(glcast, "an endpoint without a port", ["--endpoint", "tcp://*", "--", "true"], "needs a port", 30)
    # A valid config of 40 tiles on this machine: 40 slaves of about 90 MB each, refused at once.
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        tiles = [{"name": f"t{i}", "x": 64 * (i % 8), "y": 64 * (i // 8), "width": 64, "height": 64} for i in range(40)]
        json.dump({"name": "forty", "canvas": {"width": 512, "height": 320}, "tiles": tiles}, f)
    try:
        ok &= case(glcast, "forty local tiles", ["--config", f.name, "--", "true"], "more than --max-local-slaves 16", 10)
    finally:
        os.unlink(f.name)
    print(f"{'1 passed, 0 failed' if ok else '0 passed, 1 failed'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
