#!/usr/bin/env python3
"""The Debian package (packaging/install.cmake): built by CPack from the build tree, its
dependencies resolvable by apt on this machine, and once unpacked into a scratch root its glcast
runs: --version, a replay of a committed capture equal to the build tree's, and a capture whose
shim the installed glcast finds by itself (no GLCAST_SHIM), under Xvfb.

    package_test.py BUILD_DIR SOURCE_DIR     with GLCAST (the build tree's) and OUT_DIR set
"""
import glob
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

BUILD, SOURCE = sys.argv[1], sys.argv[2]
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "package")


def check(cond, msg):
    if not cond:
        print("FAIL: " + msg)
        sys.exit(1)


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600, **kw)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    r = run(["cpack", "-G", "DEB", "-B", OUT], cwd=BUILD)
    check(r.returncode == 0, f"cpack failed: {r.stdout[-2000:]}{r.stderr[-2000:]}")
    version = run([os.environ["GLCAST"], "--version"]).stdout.splitlines()[0].split()[-1]
    deb = os.path.join(OUT, f"glcast_{version}_amd64.deb")
    check(os.path.exists(deb), f"no {deb}: {os.listdir(OUT)}")
    fields = run(["dpkg-deb", "-f", deb, "Package", "Version", "Depends"]).stdout
    for needed in ("libzmq5", "libzstd1", "libglfw3", "libegl1", "libosmesa6", "libpng16-16"):
        check(needed in fields, f"the package does not depend on {needed}: {fields}")
    # apt resolves every dependency from what this machine has (a simulation installs nothing).
    if os.geteuid() == 0:
        r = run(["apt-get", "install", "-s", "-q", deb])
        check(r.returncode == 0 and "Inst glcast" in r.stdout, f"apt cannot install it: {r.stdout[-1500:]}{r.stderr[-1500:]}")
    root = os.path.join(OUT, "root")
    check(run(["dpkg-deb", "-x", deb, root]).returncode == 0, "dpkg-deb -x failed")
    files = run(["dpkg-deb", "-c", deb]).stdout
    for path in ("./usr/bin/glcast", "/glcast/libglcast.so", "./usr/lib/systemd/system/glcast-slave@.service",
                 "./usr/share/glcast/display_configs/wall-2x2.json", "./usr/share/doc/glcast/wall.md",
                 "./usr/share/bash-completion/completions/glcast"):
        check(path in files, f"the package lacks {path}")
    copyright = open(os.path.join(root, "usr/share/doc/glcast/copyright")).read()
    check(copyright.startswith("Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/") and
          "License: Expat" in copyright and "Permission is hereby granted" in copyright,
          "the package's copyright file does not give the licence (MIT, Debian's Expat)")
    # A manual page per command of glcast --help, found by man as an installed one is.
    listed = run([os.environ["GLCAST"], "--help"]).stdout.split("Commands:", 1)[1]
    commands = [line.split()[0] for line in listed.splitlines() if line.startswith("  ") and line.split()[0] != "help"]
    check(len(commands) >= 10, f"glcast --help lists {commands}")
    for page in ["glcast"] + [f"glcast-{c}" for c in commands]:
        check(f"./usr/share/man/man1/{page}.1.gz" in files, f"the package lacks the manual page {page}(1)")
    r = run(["man", "-P", "cat", "glcast-run"], env=dict(os.environ, MANPATH=os.path.join(root, "usr/share/man"),
                                                         MANWIDTH="100"))
    check(r.returncode == 0 and "glcast-run - run a program on a wall" in r.stdout and "--config FILE" in r.stdout,
          f"man glcast-run: {r.returncode} {r.stdout[:500]} {r.stderr[-500:]}")
    # Debian's checks of a package: no error.
    lintian = "lintian: not installed"
    if shutil.which("lintian"):
        r = run(["lintian", "--tag-display-limit", "0", deb])
        errors = [line for line in r.stdout.splitlines() if line.startswith("E:")]
        check(not errors, "lintian finds errors:\n" + "\n".join(errors))
        lintian = f"lintian: no error, {sum(l.startswith('W:') for l in r.stdout.splitlines())} warnings"
    unit = open(os.path.join(root, "usr/lib/systemd/system/glcast-slave@.service")).read()
    check("ExecStart=/usr/bin/glcast slave --service" in unit, "the unit does not start the installed glcast")

    glcast = os.path.join(root, "usr/bin/glcast")
    env = {k: v for k, v in os.environ.items() if k not in ("GLCAST_SHIM", "GLCAST")}
    r = run([glcast, "--version"], env=env)
    check(r.returncode == 0 and r.stdout.splitlines()[0] == f"glcast {version}" and
          re.fullmatch(r"stream format \d+ \(reads \d+ to \d+\)", r.stdout.splitlines()[1]),
          f"--version: {r.stdout}{r.stderr}")
    capture = os.path.join(SOURCE, "tests/data/ff_scene.glcs")
    for name, exe in (("installed", glcast), ("build", os.environ["GLCAST"])):
        r = run([exe, "replay", capture, "--backend", "egl", "--out", os.path.join(OUT, name)], env=env)
        check(r.returncode == 0, f"{name} replay failed: {r.stderr[-1500:]}")
    frames = sorted(os.path.basename(p) for p in glob.glob(os.path.join(OUT, "build", "*.png")))
    check(frames, "the build tree's replay wrote no frames")
    for f in frames:
        a = open(os.path.join(OUT, "build", f), "rb").read()
        b = open(os.path.join(OUT, "installed", f), "rb").read()
        check(a == b, f"{f} differs between the installed and the build tree's glcast")
    # The installed glcast preloads the installed shim (found beside it, not the build tree's).
    r = run([glcast, "capture", "-o", os.path.join(OUT, "maps.glcs"), "--", "cat", "/proc/self/maps"], env=env)
    shims = {line.split()[-1] for line in r.stdout.splitlines() if line.endswith("libglcast.so")}
    check(shims == {os.path.realpath(os.path.join(root, "usr/lib", os.path.relpath(p, "./usr/lib")))
                    for p in files.split() if p.endswith("libglcast.so")},
          f"the installed glcast preloaded {shims}, not its own shim")
    with Xvfb():
        env["DISPLAY"] = os.environ["DISPLAY"]
        cap = os.path.join(OUT, "gears.glcs")
        r = run([glcast, "capture", "--frames", "5", "-o", cap, "--", "glxgears"], env=env)
        check(r.returncode == 0 and os.path.getsize(cap) > 0, f"installed capture failed: {r.stderr[-1500:]}")
    print(f"package: {os.path.basename(deb)} ({os.path.getsize(deb) // 1024} KiB), installed into a scratch root: "
          f"--version, a replay of {len(frames)} frames equal to the build tree's, and a capture with its own shim; "
          f"{len(commands) + 1} manual pages; {lintian}")


main()
