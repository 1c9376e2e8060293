#!/usr/bin/env python3
"""`glcast doctor` on a display machine (cli/doctor.cpp): it finds what would stop a tile.

    doctor_test.py CASE      with GLCAST in the environment

drivers: under Xvfb, the EGL and GLX lines are ok, llvmpipe is named a software rasterizer (a
  warning: exit 0).
missing_key: a keys folder with the wall's master.pub but no slave.key: FAIL on the keys line, exit 1.
unreachable_master: a master whose ports nobody serves: FAIL naming each port; the same master
  once something listens on its control port: ok, exit 0.
clock: a running glcast run answers the clock on its control channel: ok, the offset in ms.
multicast: a group that is not one: FAIL.
"""
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ports import free_port_run  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def doctor(*args, env=None):
    r = subprocess.run([GLCAST, "doctor"] + list(args), capture_output=True, text=True, timeout=120, env=env)
    print(r.stdout, end="")
    return r.returncode, r.stdout.splitlines()


def line(lines, start):
    found = [l for l in lines if l.split(" ", 1)[-1].lstrip().startswith(start)]
    check(found, f"no line about {start!r} in {lines}")
    return found[0]


def case_drivers():
    with Xvfb():
        status, lines = doctor()
    check(status == 0, f"exit {status}")
    check(line(lines, "gl (egl").startswith("ok"), "the EGL line")
    check(line(lines, "glx").startswith("ok"), "the GLX line under Xvfb")
    check(line(lines, "gl: llvmpipe").startswith("WARN"), "llvmpipe not named a software rasterizer")


def case_missing_key():
    keys = tempfile.mkdtemp(prefix="glcast-doctor-keys-")
    try:
        subprocess.run([GLCAST, "keygen", os.path.join(keys, "master")], check=True, capture_output=True)
        os.remove(os.path.join(keys, "master.key"))  # as on a display machine, which lacks its own pair
        env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "GLCAST_KEYS")}
        status, lines = doctor("--keys", keys, env=env)
        check(status == 1, f"exit {status}: a missing slave.key passed")
        keys_line = line(lines, "keys")
        check(keys_line.startswith("FAIL") and "slave.key" in keys_line, keys_line)
    finally:
        shutil.rmtree(keys, ignore_errors=True)


def case_unreachable_master():
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "GLCAST_KEYS")}
    port = free_port_run(4)
    status, lines = doctor("--master", f"127.0.0.1:{port}", "--timeout", "500", env=env)
    master = line(lines, "master")
    check(status == 1 and master.startswith("FAIL") and f"control {port + 3}" in master, master)
    control = socket.socket()
    control.bind(("127.0.0.1", port + 3))
    control.listen(4)
    try:
        status, lines = doctor("--master", f"127.0.0.1:{port}", "--timeout", "500", env=env)
    finally:
        control.close()
    master = line(lines, "master")
    check(status == 0 and master.startswith("ok") and f"not now: stream {port}" in master, master)


def case_clock():
    # A real glcast run's control channel answers the clock: same machine, so the offset is small.
    port = free_port_run(4)
    with Xvfb():
        env = {k: v for k, v in os.environ.items() if k != "GLCAST_KEYS"}
        run = subprocess.Popen([GLCAST, "run", "--backend", "egl", "--endpoint", f"tcp://127.0.0.1:{port}", "--frames",
                                "400", "--", os.path.join(os.environ["APPS_DIR"], "pillars"), "--frames", "500"],
                               env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        for _ in range(100):  # until its control channel is up
            probe = socket.socket()
            up = probe.connect_ex(("127.0.0.1", port + 3)) == 0
            probe.close()
            if up:
                break
            time.sleep(0.1)
        status, lines = doctor("--master", f"127.0.0.1:{port}", env=env)
        _, errors = run.communicate(timeout=240)
        check(run.returncode == 0, f"glcast run failed: {errors[-1000:]}")
    clock = line(lines, "clock")
    check(status == 0 and clock.startswith("ok") and "ms from the master's" in clock, clock)


def case_multicast():
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "GLCAST_KEYS")}
    status, lines = doctor("--multicast", "10.1.2.3", env=env)
    bad = line(lines, "multicast")
    check(status == 1 and bad.startswith("FAIL") and "not an IPv4 multicast group" in bad, bad)


if __name__ == "__main__":
    globals()["case_" + sys.argv[1]]()
    print("PASS")
