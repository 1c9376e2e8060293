#!/usr/bin/env python3
"""The e2e harness itself (tests/e2e/xvfb.py): a test that fails while processes it started
still run (one in a session of its own, one whose parent is gone) ends them as it ends, so that
ctest is not left waiting on its output pipe until the timeout.

    harness_test.py
"""
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))

FAILING_TEST = f"""
import subprocess, sys
sys.path.insert(0, {HERE!r})
from xvfb import Xvfb
with Xvfb():
    subprocess.Popen(["sleep", "300"], start_new_session=True)               # its own session
    subprocess.Popen(["sh", "-c", "sleep 300 & exit 0"])                      # an orphan
    raise AssertionError("the test fails with both still running")
"""


def main():
    t0 = time.monotonic()
    try:
        r = subprocess.run([sys.executable, "-c", FAILING_TEST], capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        raise AssertionError("a failed test's leftovers held its output for 60 s")
    elapsed = time.monotonic() - t0
    assert r.returncode != 0 and "the test fails" in r.stderr, r.stderr[-1000:]
    assert elapsed < 20, f"the failed test's output closed only after {elapsed:.1f} s"
    print(f"harness: a failed test and its two leftovers ended in {elapsed:.2f} s")


if __name__ == "__main__":
    main()
    print("PASS")
