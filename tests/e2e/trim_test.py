#!/usr/bin/env python3
"""`glcast trim` on the committed captures: a capture cut at frame A begins with a snapshot of
the live state there, and replays on EGL and OSMesa frame for frame equal to the program's own
frames A.. (the committed golden PNGs, renumbered from 0), and under --verify the slave's
answers to the snapshot's queries equal the keeper's. A cut of a cut too, so a snapshot
recreates what an earlier snapshot made. Nothing may be reported missing from a snapshot."""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

GLCAST = os.environ["GLCAST"]
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")
env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}


def run(args):
    return subprocess.run([GLCAST] + args, capture_output=True, text=True, timeout=300, env=env)


def renumbered(golden, first, last, into):
    os.makedirs(into, exist_ok=True)
    for k in range(first, last + 1):
        shutil.copy(os.path.join(golden, f"frame-{k:06d}.png"), os.path.join(into, f"frame-{k - first:06d}.png"))
    return into


failed = []
tmp = tempfile.mkdtemp(prefix="glcast-trim-")
for capture in sorted(glob.glob(os.path.join(DATA, "*.glcs"))):
    name = os.path.basename(capture)[: -len(".glcs")]
    golden = capture[: -len(".glcs")]
    last = len(glob.glob(os.path.join(golden, "frame-*.png"))) - 1
    for backend in ("egl", "osmesa"):
        for first in range(1, last + 1):
            cut = os.path.join(tmp, f"{name}-{backend}-{first}.glcs")
            cuts = [(cut, [capture], first)]
            if first < last:  # a cut of this cut, one frame further on
                cuts.append((cut + ".again.glcs", [cut], first + 1))
            for out, (source,), from_frame in cuts:
                at = 1 if source == cut else first
                r = run(["trim", source, "--frames", f"{at}:{last - (first if source == cut else 0)}", "-o", out,
                         "--backend", backend])
                label = f"{name} on {backend}, trimmed at {from_frame}" + (" (a cut of a cut)" if source == cut else "")
                if r.returncode != 0 or "not in the snapshot" in r.stdout:
                    failed.append(f"{label}: trim: {r.stdout[-800:]} {r.stderr[-800:]}")
                    continue
                reference = renumbered(golden, from_frame, last, os.path.join(tmp, os.path.basename(out) + ".ref"))
                # --verify: the snapshot carries the keeper's answers to the queries of its state,
                # which the replaying slave asks again and compares
                r = run(["replay", out, "--backend", backend, "--compare", reference, "--verify"])
                tail = r.stdout.strip().splitlines()[-1] if r.stdout.strip() else ""
                print(f"{label}: {tail}")
                if r.returncode != 0 or not re.search(r"verified [1-9]\d* replies: 0 differ", r.stdout):
                    failed.append(f"{label}: {r.stdout[-1500:]} {r.stderr[-1500:]}")
shutil.rmtree(tmp, ignore_errors=True)
if failed:
    sys.exit("\n".join(failed))
print("PASS")
