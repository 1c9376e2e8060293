#!/usr/bin/env python3
"""Bash completion (packaging/glcast.bash-completion) in a real bash: the commands, a command's
options, a display config's tile names after --tile, effect names after --effects (also the last
of a list), effect parameters after --effect-param, commands after "--"; and glcast config, which
it asks for the tile names.

    completion_test.py GLCAST
"""
import os
import subprocess
import sys

GLCAST = sys.argv[1]
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SCRIPT = os.path.join(ROOT, "packaging", "glcast.bash-completion")


def complete(words):
    """COMPREPLY for the command line `words`, the last being the word under the cursor."""
    quoted = " ".join("'" + w.replace("'", "'\\''") + "'" for w in [GLCAST] + words)
    script = f'source "{SCRIPT}"; COMP_WORDS=({quoted}); COMP_CWORD={len(words)}; _glcast; printf "%s\\n" "${{COMPREPLY[@]}}"'
    r = subprocess.run(["bash", "-c", script], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return [w for w in r.stdout.splitlines() if w]


def check(got, want, what):
    print(f"{what}: {got}")
    if got != want:
        raise AssertionError(f"{what}: {got}, expected {want}")


def main():
    cave = os.path.join(ROOT, "display_configs", "cave-4-metres.json")
    check(complete(["re"]), ["replay", "record"], "commands")
    check(complete(["run", "--tr"]), ["--tracker"], "run's options")
    check(complete(["replay", "x.glcs", "--config", cave, "--tile", ""]), ["front", "left", "right", "floor"], "tiles")
    check(complete(["slave", "--config", cave, "--tile", "f"]), ["front", "floor"], "tiles starting with f")
    check(complete(["run", "--effects", "s"]), ["snow", "shadows"], "effects")
    check(complete(["run", "--effects", "snow,co"]), ["snow,cover"], "the last of a list of effects")
    check(complete(["replay", "x.glcs", "--effect-param", "cover.dens"]), ["cover.density="], "effect parameters")
    check(complete(["ctl", "ipc:///run/wall", ""]), ["effects", "param"], "ctl's requests")
    check(complete(["ctl", "ipc:///run/wall", "effects", "+snow", "-s"]), ["-snow", "-shadows"], "ctl's effects")
    check(complete(["ctl", "--keys", "k", "ipc:///run/wall", "param", "snow.fall"]), ["snow.fall_speed="], "ctl's parameters")
    program = complete(["run", "--", "glxgear"])  # after "--": commands (mesa-utils is installed by the setup)
    print(f"the program: {program}")
    if "glxgears" not in program:
        raise AssertionError(f"the program: {program}, no glxgears")
    # What --tile's completion asks: glcast config --names, and a bad file refused with its place.
    r = subprocess.run([GLCAST, "config", "--names", cave], capture_output=True, text=True)
    check(r.stdout.split(), ["front", "left", "right", "floor"], "glcast config --names")
    r = subprocess.run([GLCAST, "config", SCRIPT], capture_output=True, text=True)
    if r.returncode != 1 or "line 1, column" not in r.stderr:
        raise AssertionError(f"glcast config of a non-config: exit {r.returncode}, {r.stderr}")
    print("PASS")


if __name__ == "__main__":
    main()
