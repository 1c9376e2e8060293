#!/usr/bin/env python3
"""The program's memory while it publishes: RSS of an xscreensaver hack every STEP seconds for
SECONDS, run twice side by side on one Xvfb: natively, and with the shim publishing on ipc with
its journal (GLCAST_JOURNAL_MB, default 64) and no slave. Writes a markdown table to stdout.

    bench/publish_rss.py SHIM [--hack moebius] [--seconds 600] [--step 60] [--journal-mb N]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402


def rss_mib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return float("nan")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("shim")
    ap.add_argument("--hack", default="moebius")
    ap.add_argument("--seconds", type=int, default=600)
    ap.add_argument("--step", type=int, default=60)
    ap.add_argument("--journal-mb", type=int, default=None)
    a = ap.parse_args()
    hack = [f"/usr/libexec/xscreensaver/{a.hack}", "-window", "-geometry", "640x480"]
    tmp = tempfile.mkdtemp(prefix="glcast-rss-")
    with Xvfb():
        native = subprocess.Popen(hack, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        env = dict(os.environ, LD_PRELOAD=a.shim, GLCAST_PUBLISH=f"ipc://{tmp}/stream",
                   GLCAST_JOURNAL_ENDPOINT=f"ipc://{tmp}/journal")
        if a.journal_mb is not None:
            env["GLCAST_JOURNAL_MB"] = str(a.journal_mb)
        published = subprocess.Popen(hack, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        print(f"| {a.hack}, seconds | native RSS | publishing RSS (journal {a.journal_mb or 64} MiB) |")
        print("|---|---|---|")
        start = time.monotonic()
        for t in range(a.step, a.seconds + 1, a.step):
            time.sleep(max(0.0, start + t - time.monotonic()))
            print(f"| {t} | {rss_mib(native.pid):.1f} MiB | {rss_mib(published.pid):.1f} MiB |", flush=True)
        for p in (native, published):
            p.kill()
            p.wait()


if __name__ == "__main__":
    main()
