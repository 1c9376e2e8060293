#!/usr/bin/env python3
"""The program never notices glcast, however it ends: tests/apps_extra/exit_paths.c ends in one way
(return, exit with a GL teardown in an atexit handler, a library's destructor, a thread's exit,
the last thread's exit, exit from one of three threads with contexts of their own, fork, dlclose,
_exit, a fatal signal), alone and then under
`glcast capture`. Its exit status and output are the same both times, nothing on stderr speaks of a
corrupted heap or a crash, and the capture is complete: its end record is there, the calls the
program made on the way out are in it, and it replays on EGL with exit 0 and 0 replies differing
under --verify. A program that ends by _exit or a fatal signal leaves a capture readable to its last
whole message, which dump and replay call cut.

    exit_paths_test.py MODE     with GLCAST, APPS_DIR, OUT_DIR in the environment
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
PROGRAM = os.path.join(os.environ["APPS_DIR"], "exit_paths")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "exit_paths")
FRAMES = 6

# Per mode: calls that must be in the capture after its last swap, as the dump prints them (a
# prefix of the line after the call number), in this order.
AFTER_LAST_SWAP = {
    "return": ["glClearColor(red = 0.25, green = 0.5, blue = 0.75, alpha = 1)", "glClear(", "glFinish("],
    "atexit": ["glClearColor(red = 0.25, green = 0.5, blue = 0.75, alpha = 1)", "glFinish(", "glXMakeCurrent(", "glClearColor(red = 0.125, green = 0.25, blue = 0.375, alpha = 1)",
               "glClear(", "glXMakeCurrent(", "glXDestroyContext("],
    "destructor": ["glClearColor(red = 0.25, green = 0.5, blue = 0.75, alpha = 1)", "glFinish(", "glXMakeCurrent(",
                   "glClearColor(red = 0.0625, green = 0.125, blue = 0.1875, alpha = 1)", "glXMakeCurrent(", "glXDestroyContext("],
    "thread": ["glClearColor(red = 0.25, green = 0.5, blue = 0.75, alpha = 1)", "glFinish(", "glClearColor(red = 0.125, green = 0.25, blue = 0.375, alpha = 1)",
               "glXMakeCurrent(", "glXMakeCurrent(", "glClearColor(red = 0.0625, green = 0.125, blue = 0.1875, alpha = 1)", "glFinish(",
               "glXMakeCurrent(", "glXDestroyContext("],
    "last-thread": ["glClearColor(red = 0.25, green = 0.5, blue = 0.75, alpha = 1)", "glFinish(", "glClearColor(red = 0.125, green = 0.25, blue = 0.375, alpha = 1)",
                    "glXMakeCurrent("],
    "threads-exit": ["glClearColor(red = 0.25, green = 0.5, blue = 0.75, alpha = 1)", "glFinish("],
    "fork": [],
    "dlclose": ["glXMakeCurrent(", "glXDestroyContext("],
}
CUT = ("_exit", "signal")
BAD_WORDS = ("corrupted", "double free", "free():", "malloc", "Segmentation", "Aborted", "core dumped",
             "AddressSanitizer", "glcast: symbol lookup")


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(args, **kw):
    return subprocess.run(args, capture_output=True, text=True, timeout=120, **kw)


def main():
    mode = sys.argv[1]
    os.makedirs(OUT, exist_ok=True)
    if mode.startswith("gles"):
        return gles(mode)
    path = os.path.join(OUT, mode + ".glcs")
    if os.path.exists(path):
        os.remove(path)
    program = [PROGRAM, mode, "--frames", str(FRAMES)]
    # Mesa's threads (llvmpipe's rasterizers, the shader cache's) would outlive the program's last one:
    # it would never end, alone too.
    with Xvfb():  # sets DISPLAY
        env = dict(os.environ, LP_NUM_THREADS="0", MESA_SHADER_CACHE_DISABLE="true") if mode == "last-thread" else None
        alone = run(program, env=env)
        shimmed = run([GLCAST, "capture", "-o", path, "--"] + program, env=env)
    print(f"{mode}: alone exit {alone.returncode}, under the shim exit {shimmed.returncode}")
    expected = -11 if mode == "signal" else 0
    check(alone.returncode == expected, f"alone, exit_paths {mode} exited {alone.returncode}: {alone.stderr[-1500:]}")
    # glcast capture reports a program killed by a signal as 128 + the signal, as a shell does.
    check(shimmed.returncode == (128 + 11 if mode == "signal" else 0) or (mode in CUT and shimmed.returncode == 1),
          f"under the shim, exit_paths {mode} exited {shimmed.returncode} (alone {alone.returncode}): "
          f"{shimmed.stderr[-2500:]}")
    check(alone.stdout == shimmed.stdout, f"output differs: alone {alone.stdout!r}, under the shim {shimmed.stdout!r}")
    for word in BAD_WORDS:
        check(word not in shimmed.stderr, f"under the shim, stderr says {word!r}: {shimmed.stderr[-2500:]}")
    check(f"exit_paths: {mode} done" in shimmed.stdout, f"the program did not finish: {shimmed.stdout!r}")

    dumped = run([GLCAST, "dump", path])
    replayed = run([GLCAST, "replay", path, "--backend", "egl", "--verify"],
                   env={k: v for k, v in os.environ.items() if k != "DISPLAY"})
    print(f"{mode}: dump exit {dumped.returncode}; replay exit {replayed.returncode}: "
          f"{' / '.join(replayed.stdout.strip().splitlines()[-2:])}")
    if mode in CUT:
        for name, r in (("dump", dumped), ("replay", replayed)):
            check(r.returncode != 0 and "the capture was cut after message" in r.stderr,
                  f"{name} of the capture a {mode} cut did not say where it was cut: {r.returncode} {r.stderr[-800:]}")
        # How far the writer got before the end is the machine's: on a loaded one, no whole frame.
        print(f"{mode}: the cut capture holds {dumped.stdout.count('glXSwapBuffers(')} whole frames")
        print("1 passed, 0 failed")
        return
    check(dumped.returncode == 0 and "cut" not in dumped.stderr, f"dump: {dumped.returncode} {dumped.stderr[-1000:]}")
    check(replayed.returncode == 0 and "cut" not in replayed.stderr,
          f"replay: {replayed.returncode} {replayed.stdout[-800:]} {replayed.stderr[-1500:]}")
    check(re.search(r"verified \d+ replies: 0 differ", replayed.stdout), f"replies differ: {replayed.stdout[-800:]}")
    calls = [re.sub(r"^\d+\s+(\[ctx \d+\]\s+)?", "", line) for line in dumped.stdout.splitlines() if re.match(r"^\d+ ", line)]
    swaps = [i for i, c in enumerate(calls) if c.startswith("glXSwapBuffers(")]
    drawn = FRAMES * (3 if mode == "threads-exit" else 1)  # three threads draw in threads-exit
    check(len(swaps) == drawn, f"{len(swaps)} swaps in the capture, the program drew {drawn} frames")
    tail = calls[swaps[-1] + 1:]
    at = 0
    for want in AFTER_LAST_SWAP[mode]:
        found = next((i for i in range(at, len(tail)) if tail[i].startswith(want)), None)
        check(found is not None, f"{want!r} is not in the capture after the last swap (in order); after it: {tail[:40]}")
        at = found + 1
    if mode == "fork":  # the child's own frame (a magenta clear) is its own, not in its parent's stream
        check(not any(c.startswith("glClearColor(red = 1, green = 0, blue = 1, alpha = 1)") for c in calls), "the forked child's calls are in the parent's capture")
    print(f"{mode}: {len(calls)} calls, {len(swaps)} frames, the {len(AFTER_LAST_SWAP[mode])} calls after the last swap there")
    print("1 passed, 0 failed")


def gles(mode):
    """An OpenGL ES program that checks glGetError after each call the shim sizes
    (tests/apps_extra/gles_errors.c): the shim's own queries must leave no error behind. Replayed
    on EGL in an ES context, every reply is the master's (its version strings, extensions, the
    slave's own size queries leaving no error); OSMesa, which has no ES, says so and replays."""
    path = os.path.join(OUT, mode + ".glcs")
    program = [os.path.join(os.environ["APPS_DIR"], "gles_errors"), mode[4:], "--frames", str(FRAMES)]
    with Xvfb():
        alone = run(program)
        shimmed = run([GLCAST, "capture", "-o", path, "--"] + program)
    print(f"{mode}: alone exit {alone.returncode}, under the shim exit {shimmed.returncode}: {shimmed.stderr.strip()[-300:]}")
    check(alone.returncode == 0, f"alone: {alone.stderr[-800:]}")
    check(shimmed.returncode == 0 and shimmed.stdout == alone.stdout, f"under the shim: {shimmed.stderr[-1500:]}")
    dumped = run([GLCAST, "dump", path, "--summary"])
    check(dumped.returncode == 0 and "cut" not in dumped.stderr, f"dump: {dumped.stderr[-800:]}")
    verified = run([GLCAST, "replay", path, "--backend", "egl", "--verify"])
    said = verified.stdout + verified.stderr
    print(said.strip()[-300:])
    check(verified.returncode == 0 and "replies: 0 differ" in said, f"replay --verify: {said[-1500:]}")
    osmesa = run([GLCAST, "replay", path, "--backend", "osmesa"])
    check(osmesa.returncode == 0 and "osmesa has no OpenGL ES" in osmesa.stderr, f"replay on osmesa: {osmesa.stderr[-1500:]}")
    print("1 passed, 0 failed")


if __name__ == "__main__":
    main()
