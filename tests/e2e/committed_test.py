#!/usr/bin/env python3
"""The committed captures (tests/data/*.glcs) replay headless, without X, on EGL and OSMesa,
frame for frame equal to the committed golden PNGs: a change in the decoder, the generator or
the replay that breaks replay fails here first. Regenerate with tests/data/make_data.sh."""
import glob
import os
import subprocess
import sys

GLCAST = os.environ["GLCAST"]
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")
env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
captures = sorted(glob.glob(os.path.join(DATA, "*.glcs")))
if not captures:
    sys.exit("no committed captures in tests/data")
failed = []
for capture in captures:
    golden = capture[: -len(".glcs")]
    for backend in ("egl", "osmesa"):
        r = subprocess.run([GLCAST, "replay", capture, "--backend", backend, "--compare", golden],
                           capture_output=True, text=True, timeout=300, env=env)
        print(f"{os.path.basename(capture)} on {backend}: {r.stdout.strip().splitlines()[-1] if r.stdout.strip() else ''}")
        if r.returncode != 0:
            hint = " (run tests/data/make_data.sh if the opcode table changed)" if "opcode table" in r.stderr else ""
            failed.append(f"{capture} on {backend}{hint}: {r.stdout[-1500:]} {r.stderr[-1500:]}")
if failed:
    sys.exit("\n".join(failed))
print("PASS")
