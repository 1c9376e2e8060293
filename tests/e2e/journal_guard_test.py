#!/usr/bin/env python3
"""The journal channel cannot hurt the program (docs/security.md): a real program runs with the
shim publishing on loopback, and tests/tools/journal_peer.cpp attacks its journal channel.

    journal_guard_test.py CASE     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR, JOURNAL_PEER set

snapshot_noread: 100 journal requests from a client that never reads (10 connections, held
  6 s). The program (ff_scene, its journal about 9 MiB when they come) keeps its memory: its
  VmRSS at the end is within RSS_SLACK of the same program's at the same frame without them.
garbage: random frames, near misses of the request forms, oversized frames, messages of 1,001
  parts, a SNAPSHOT flood from one identity and from 200, raw bytes on the TCP port. The
  program runs on, its memory stays bounded, and a slave that joins late afterwards shows the
  program's own frames.
done_flood: a million "DONE n" reports without lockstep change nothing: the program's memory
  stays within RSS_SLACK of a run without them, as above.
"""
import os
import shutil
import signal
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402
import wall_test  # noqa: E402  (same_frames, wait_for: the wall tests' helpers)
from ports import free_port_run  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
PEER = os.environ["JOURNAL_PEER"]
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "journal_guard")
MIB = 1 << 20
RSS_SLACK = 16 * MIB
KILL_ABOVE = 1536 * MIB  # a program past this much growth is stopped: the old code grows by GiBs


def check(cond, msg):
    """msg: a string, or a function giving it (for messages that read a process's stderr)."""
    if not cond:
        raise AssertionError(msg() if callable(msg) else msg)


def rss(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise AssertionError(f"no VmRSS for {pid}")


class Watch:
    """Samples a process's VmRSS every 50 ms; stops the process if it grows past KILL_ABOVE."""

    def __init__(self, proc):
        self.proc, self.base, self.peak, self.killed = proc, rss(proc.pid), 0, False
        self.done = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while not self.done.is_set() and self.proc.poll() is None:
            try:
                value = rss(self.proc.pid)
            except (OSError, AssertionError):
                return
            self.peak = max(self.peak, value)
            if value - self.base > KILL_ABOVE:
                self.killed = True
                self.proc.kill()
                return
            time.sleep(0.05)

    def stop(self):
        self.done.set()
        self.thread.join()
        return self.peak - self.base


def frames_done(swaps):
    try:
        with open(swaps) as f:
            return sum(1 for _ in f)
    except FileNotFoundError:
        return 0


def start_ff_scene(out, journal):
    """ff_scene publishing uncompressed (its journal grows by about 60 KiB a frame)."""
    swaps = os.path.join(out, "swaps")
    env = dict(os.environ, GLCAST_PUBLISH=f"ipc://{out}/stream", GLCAST_JOURNAL_ENDPOINT=journal,
               GLCAST_ZSTD_LEVEL="0", GLCAST_VERBOSE="1", GLCAST_TEST_SWAP_LOG=swaps)
    env["LD_PRELOAD"] = os.environ["GLCAST_SHIM"]
    # stderr into a file: a pipe nobody reads while the program runs could fill and hold it.
    p = subprocess.Popen([os.path.join(APPS, "ff_scene"), "--frames", "100000000"], env=env,
                         stdout=subprocess.DEVNULL, stderr=open(os.path.join(out, "stderr"), "w"))
    p.log, p.swaps = os.path.join(out, "stderr"), swaps
    return p


def wait_frames(p, n, timeout=180):
    end = time.monotonic() + timeout
    while frames_done(p.swaps) < n:
        check(p.poll() is None, lambda: f"ff_scene ended: {open(p.log).read()[-2000:]}")
        check(time.monotonic() < end, f"ff_scene did not reach frame {n}")
        time.sleep(0.01)


def stop(p):
    p.send_signal(signal.SIGKILL)
    p.wait()
    return open(p.log).read()


def fresh(name):
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    return out


def compare_runs(name, attack, start_frame=150):
    """ff_scene attacked at start_frame, then the same program without the attack: VmRSS of
    both at the frame the attacked one had reached when the attack ended (the journal, the only
    thing that grows, is then the same)."""
    out = fresh(name + "-attacked")
    journal = f"ipc://{out}/journal"
    p = start_ff_scene(out, journal)
    wait_frames(p, start_frame)
    watch = Watch(p)
    peer = attack(journal)
    time.sleep(1.5)  # what the peer sent is read and acted on
    attacked = rss(p.pid) if p.poll() is None else 0
    frame = frames_done(p.swaps)
    growth = watch.stop()
    alive = p.poll() is None
    log = stop(p)
    check(not watch.killed, f"the program grew past {KILL_ABOVE // MIB} MiB and was stopped")
    check(alive, f"the program died under the attack: {log[-2000:]}")
    check(peer.returncode == 0, f"journal_peer failed: {peer.stderr}")
    out = fresh(name + "-quiet")
    q = start_ff_scene(out, f"ipc://{out}/journal")
    wait_frames(q, frame)
    quiet = rss(q.pid)
    stop(q)
    print(f"{name}: {peer.stdout.strip()}; at frame {frame} VmRSS {attacked / MIB:.1f} MiB attacked, "
          f"{quiet / MIB:.1f} MiB without the attack (journal about {frame * 60 / 1024:.0f} MiB)")
    return attacked, quiet


def case_snapshot_noread():
    attacked, quiet = compare_runs("snapshot_noread", lambda journal: subprocess.run(
        [PEER, "snapshot", journal, "100", "10", "6"], capture_output=True, text=True, timeout=60))
    check(attacked - quiet <= RSS_SLACK, f"100 unread journal requests grew the program by "
          f"{(attacked - quiet) / MIB:.1f} MiB, more than {RSS_SLACK // MIB} MiB")


def case_done_flood():
    attacked, quiet = compare_runs("done_flood", lambda journal: subprocess.run(
        [PEER, "done", journal, "1000000"], capture_output=True, text=True, timeout=120))
    check(attacked - quiet <= RSS_SLACK, f"a DONE flood without lockstep grew the program by "
          f"{(attacked - quiet) / MIB:.1f} MiB, more than {RSS_SLACK // MIB} MiB")


def case_garbage():
    out = fresh("garbage")
    stream = f"ipc://{out}/stream"
    journal = f"tcp://127.0.0.1:{free_port_run()}"
    env = dict(os.environ, GLCAST_PUBLISH=stream, GLCAST_JOURNAL_ENDPOINT=journal, GLCAST_VERBOSE="1",
               GLCAST_SNAPSHOT_DIR=os.path.join(out, "program"), GLCAST_FRAMES="360", GLCAST_EXIT_AFTER_FRAMES="1",
               LD_PRELOAD=os.environ["GLCAST_SHIM"])
    program = subprocess.Popen(["/usr/libexec/xscreensaver/gears", "-window", "-geometry", "320x240"], env=env,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall_test.wait_for(os.path.join(out, "program", "frame-000040.png"))
    watch = Watch(program)
    peer = subprocess.run([PEER, "garbage", journal], capture_output=True, text=True, timeout=120)
    check(peer.returncode == 0, f"journal_peer failed: {peer.stderr}")
    check(program.poll() is None,
          lambda: f"the program ended under garbage ({program.returncode}): {program.stderr.read()[-2000:]}")
    late = subprocess.Popen([GLCAST, "slave", "--connect", stream, "--journal", journal, "--backend", "egl", "--out",
                             os.path.join(out, "late"), "--wait", "60", "--quiet"], stderr=subprocess.PIPE, text=True)
    rc = program.wait(timeout=300)
    growth = watch.stop()
    log = program.stderr.read()
    check(not watch.killed, f"the program grew past {KILL_ABOVE // MIB} MiB and was stopped")
    check(rc == 0, f"the program failed ({rc}): {log[-2000:]}")
    check(late.wait(timeout=120) == 0, lambda: f"the late slave failed: {late.stderr.read()[-2000:]}")
    n = wall_test.same_frames(os.path.join(out, "program"), os.path.join(out, "late"))
    summary = [line for line in log.splitlines() if "glcast: journal:" in line]
    print(f"garbage: {peer.stdout.strip()}; peak VmRSS growth {growth / MIB:.1f} MiB; "
          f"a slave joined late afterwards and showed {n} frames equal to the program's")
    print("\n".join(summary))
    check(growth <= 4 * RSS_SLACK, f"the program grew by {growth / MIB:.1f} MiB under garbage")
    check(summary and "rate=" in summary[-1] and "parts=" in summary[-1] and "unknown=" in summary[-1],
          f"the program did not count the dropped requests: {log[-2000:]}")


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
