#!/usr/bin/env python3
"""gl_paths.py: the other ways programs reach GL, under glcast's shim, measured as
scripts/piglit.py measures piglit: OpenGL ES 2 on X11 (glmark2-es2), Wayland-native programs under
weston's headless backend (glmark2-wayland, glmark2-es2-wayland), and a program of our own that
draws from three threads with three contexts and exits from one of them (exit_paths threads-exit).

Each program runs alone and then under `glcast capture` with its own frames kept
(GLCAST_SNAPSHOT_DIR, read back in a format OpenGL ES allows); the capture is replayed on EGL and
on OSMesa with --compare (the program's frames) and --verify (every reply). Prints a Markdown
table; with --doc FILE writes it between FILE's `<!-- gl paths table -->` markers.

    scripts/gl_paths.py [--build build] [--frames 30] [--out DIR] [--doc docs/compatibility.md]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402

BEGIN, END = "<!-- gl paths table: scripts/gl_paths.py writes from here -->", "<!-- gl paths table: to here -->"


def programs(build, frames):
    glmark = ["--size", "320x240", "-b", f"shading:duration={frames}"]
    return [
        ("glmark2-es2 (OpenGL ES 2, X11)", "x11", ["glmark2-es2"] + glmark),
        ("glmark2-es2-wayland (OpenGL ES 2, Wayland)", "wayland", ["glmark2-es2-wayland"] + glmark),
        ("glmark2-wayland (OpenGL, Wayland)", "wayland", ["glmark2-wayland"] + glmark),
        ("exit_paths threads-exit (3 threads, 3 contexts, exit from a thread)", "x11",
         [os.path.join(build, "tests", "apps", "exit_paths"), "threads-exit", "--frames", "6"]),
    ]


def run(cmd, env, timeout=300):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def replay(glcast, capture, backend, reference, env):
    r = run([glcast, "replay", capture, "--backend", backend, "--compare", reference, "--verify"], env)
    said = r.stdout + r.stderr
    frames = re.search(r"compared (\d+) frames: (\d+) differ", said)
    replies = re.search(r"verified (\d+) replies: (\d+) differ", said)
    cell = f"exit {r.returncode}"
    if frames:
        cell += f"; frames {int(frames.group(1)) - int(frames.group(2))}/{frames.group(1)} equal"
    if replies:
        cell += f"; replies {int(replies.group(1)) - int(replies.group(2))}/{replies.group(1)} equal"
    return cell


def measure(name, where, cmd, glcast, frames, out, env):
    alone = run(cmd, env)
    capture, reference = os.path.join(out, "capture.glcs"), os.path.join(out, "program")
    limit = ["--frames", str(frames)] if cmd[0].startswith("glmark2") else []
    shimmed = run([glcast, "capture", "-o", capture] + limit + ["--"] + cmd, dict(env, GLCAST_SNAPSHOT_DIR=reference))
    kept = len(os.listdir(reference)) if os.path.isdir(reference) else 0
    dumped = run([glcast, "dump", capture, "--summary"], env)
    headless = {k: v for k, v in env.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    return [name, where, f"{alone.returncode} / {shimmed.returncode}",
            "complete" if dumped.returncode == 0 and "cut" not in dumped.stderr else "CUT", str(kept),
            replay(glcast, capture, "egl", reference, headless), replay(glcast, capture, "osmesa", reference, headless)]


def weston(env):
    """weston's headless backend on a socket of its own; (process, environment for its clients)."""
    runtime = tempfile.mkdtemp(prefix="glcast-weston-")
    os.chmod(runtime, 0o700)
    wenv = dict(env, XDG_RUNTIME_DIR=runtime)
    wenv.pop("DISPLAY", None)
    proc = subprocess.Popen(["weston", "--backend=headless-backend.so", "--socket=glcast-paths", "--idle-time=0"],
                            env=wenv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(100):
        if os.path.exists(os.path.join(runtime, "glcast-paths")):
            break
        time.sleep(0.1)
    return proc, dict(wenv, WAYLAND_DISPLAY="glcast-paths"), runtime


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--out", default="/tmp/glcast-gl-paths")
    ap.add_argument("--doc", default="")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    glcast = os.path.join(build, "glcast")
    shutil.rmtree(args.out, ignore_errors=True)
    rows = []
    with Xvfb():
        proc, wenv, runtime = weston(dict(os.environ))
        try:
            for i, (name, where, cmd) in enumerate(programs(build, args.frames)):
                out = os.path.join(args.out, str(i))
                os.makedirs(out)
                env = wenv if where == "wayland" else dict(os.environ)
                if shutil.which(cmd[0]) is None and not os.path.exists(cmd[0]):
                    rows.append([name, where, "not installed", "", "", "", ""])
                    continue
                rows.append(measure(name, where, cmd, glcast, args.frames, out, env))
                print(" | ".join(rows[-1]), flush=True)
        finally:
            proc.terminate()
            proc.wait()
            shutil.rmtree(runtime, ignore_errors=True)
    table = ["| program | window system | exit alone / captured | capture | program frames kept | "
             "EGL replay | OSMesa replay |", "|---|---|---|---|---|---|---|"]
    table += ["| " + " | ".join(r) + " |" for r in rows]
    text = "\n".join(table)
    print(text)
    if args.doc:
        doc = open(args.doc).read()
        a, b = doc.index(BEGIN) + len(BEGIN), doc.index(END)
        open(args.doc, "w").write(doc[:a] + "\n\n" + f"`scripts/gl_paths.py --frames {args.frames}`, "
                                  f"{time.strftime('%Y-%m-%d')}, llvmpipe; Wayland: weston's headless backend.\n\n"
                                  + text + "\n\n" + doc[b:])


if __name__ == "__main__":
    main()
