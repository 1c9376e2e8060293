#!/usr/bin/env python3
"""Every pass together on every committed capture, with --verify: the replay runs without an
error, and every glGetError (and other reply) the program saw is what the slave sees too, so
no pass leaves a GL error or changed state behind for the program's later calls.

    all_effects_test.py GLCAST
"""
import os
import re
import subprocess
import sys

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data")
EFFECTS = ["shadows,cover,icicles,snow", "rain"]


def main():
    failures = []
    for capture in sorted(f for f in os.listdir(DATA) if f.endswith(".glcs")):
        for effects in EFFECTS:
            r = subprocess.run([sys.argv[1], "replay", os.path.join(DATA, capture), "--effects", effects, "--verify"],
                               capture_output=True, text=True, timeout=300)
            verified = re.search(r"verified (\d+) replies: (\d+) differ", r.stdout)
            print(f"{capture} --effects {effects}: exit {r.returncode}, {verified.group(0) if verified else r.stderr}")
            if r.returncode != 0 or not verified or verified.group(2) != "0":
                failures.append(f"{capture} {effects}: {r.stdout[-500:]} {r.stderr[-1500:]}")
    if failures:
        sys.exit("\n".join(failures))


if __name__ == "__main__":
    main()
