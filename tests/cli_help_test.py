#!/usr/bin/env python3
"""The glcast command line (cli/): help for every command, usage errors naming the option.

    cli_help_test.py GLCAST     with GLCAST_SHIM in the environment for the '--' check

For every command: `glcast CMD --help` exits 0 on stdout and names every option of the list
below (the options glcast has always had, so a lost or renamed one fails here); an unknown
option and bad values exit 2 with one line on stderr that names the command and the option.
A program's own options after '--' reach the program untouched, and runtime failures still
exit 1.
"""
import os
import re
import subprocess
import sys

GLCAST = sys.argv[1]

# command words -> its options (positionals are in the usage line)
OPTIONS = {
    ("capture",): ["-o", "--output", "--frames", "--start-frame"],
    ("dump",): ["--frames", "--summary"],
    ("replay",): ["--frames", "--backend", "--out", "--compare", "--size", "--offset-names", "--verify", "--config",
                  "--tile", "--canvas", "--tile-rect", "--effects", "--effect-param"],
    ("run",): ["--config", "--backend", "--out", "--frames", "--endpoint", "--lockstep", "--effects", "--effect-param"],
    ("slave",): ["--connect", "--journal", "--keeper", "--config", "--tile", "--backend", "--out", "--frames", "--wait", "--quiet",
                 "--swap-barrier", "--lockstep", "--effects", "--effect-param"],
    ("image",): ["mosaic", "compare", "pixel", "motion"],
    ("image", "mosaic"): ["COLSxROWS", "OUT", "TILES"],
    ("image", "compare"): ["--crop"],
    ("image", "pixel"): ["IMAGE", "POINT"],
    ("image", "motion"): ["--crop", "--radius", "--without"],
    ("effects",): [],
    ("trim",): ["IN", "--frames", "-o", "--output", "--backend"],
    ("keeper",): ["--connect", "--journal", "--bind", "--backend", "--wait", "--verbose", "--state", "--state-every",
                  "--keys", "--insecure"],
    ("record",): ["--connect", "--journal", "--keeper", "-o", "--output", "--start-frame", "--frames", "--wait", "--keys",
                  "--insecure"],
    # (its request's words come after WALL: the help names them)
    ("ctl",): ["WALL", "--keys", "--wait", "effects +NAME -NAME", "param NAME=VALUE"],
}
COMMANDS = ["capture", "dump", "replay", "run", "slave", "image", "effects", "trim", "keeper", "record", "doctor", "config", "ctl", "calibrate", "help"]

# (arguments, the option the one-line message must name); all exit 2
BAD_VALUES = [
    (["capture", "--frames", "0", "-o", "x.glcs", "--", "true"], "--frames"),
    (["capture", "--frames", "5x", "-o", "x.glcs", "--", "true"], "--frames"),
    (["capture", "--", "true"], "--output"),
    (["capture", "-o", "x.glcs"], "'--'"),
    (["dump", "x.glcs", "--frames", "x"], "--frames"),
    (["dump", "x.glcs", "--frames", "9:3"], "--frames"),
    (["dump", "x.glcs", "--frames"], "--frames"),
    (["replay", "x.glcs", "--frames", "x"], "--frames"),
    (["replay", "x.glcs", "--frames", "x", "--frames", "1:2"], "--frames"),  # every value is checked
    (["replay", "x.glcs", "--size", "0x5"], "--size"),
    (["replay", "x.glcs", "--offset-names", "10001"], "--offset-names"),
    (["replay", "x.glcs", "--canvas", "640"], "--canvas"),
    (["replay", "x.glcs", "--tile-rect", "1,2,3"], "--tile-rect"),
    (["replay", "x.glcs", "--tile-rect", "0,0,8,8"], "--tile-rect"),  # needs --canvas
    (["replay", "x.glcs", "--config", "c.json"], "--tile"),
    (["replay", "x.glcs", "--effects", "hail"], "--effects"),
    (["replay", "x.glcs", "--effect-param", "snow.size"], "--effect-param"),
    (["replay"], "FILE"),
    (["trim", "x.glcs", "-o", "y.glcs"], "--frames"),
    (["trim", "x.glcs", "--frames", "2:1", "-o", "y.glcs"], "--frames"),
    (["trim", "x.glcs", "--frames", "1:2"], "--output"),
    (["keeper", "--connect", "ipc:///tmp/x", "--journal", "ipc:///tmp/y"], "--bind"),
    (["record", "--connect", "ipc:///tmp/x", "--journal", "ipc:///tmp/y", "-o", "z.glcs"], "--keeper"),
    (["capture", "--start-frame", "x", "-o", "x.glcs", "--", "true"], "--start-frame"),
    (["run", "--frames", "x", "--", "true"], "--frames"),
    (["run", "--effects", "hail", "--", "true"], "--effects"),
    (["run", "--effect-param", "snow.nothing=1", "--", "true"], "snow.nothing"),
    (["slave", "--connect", "ipc:///tmp/x", "--wait", "0"], "--wait"),
    (["slave", "--connect", "ipc:///tmp/x", "--frames", "3:1"], "--frames"),
    (["slave", "--wait", "5"], "--connect"),
    (["image", "compare", "a.png", "b.png", "--crop", "1,2"], "--crop"),
    (["image", "motion", "a.png", "b.png", "--radius", "0"], "--radius"),
    (["image", "pixel", "a.png", "1"], "POINT"),
    (["image", "mosaic", "0x2", "o.png", "a.png"], "COLSxROWS"),
    (["effects", "extra"], "extra"),
    (["help", "nothing"], "nothing"),
]

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def glcast(args):
    try:
        return subprocess.run([GLCAST] + args, capture_output=True, text=True, timeout=20)
    except subprocess.TimeoutExpired:  # e.g. a bad value taken, and the command started
        check(False, f"glcast {' '.join(args)}: still running after 20 s")
        return subprocess.CompletedProcess(args, -1, "", "")


def mentions(text, word):
    return re.search(r"(?<![\w-])" + re.escape(word) + r"(?![\w-])", text) is not None


def one_line_error(r, args, word, prefix):
    cmd = " ".join(args)
    lines = r.stderr.splitlines()
    check(r.returncode == 2, f"glcast {cmd}: exit {r.returncode}, not 2 ({r.stderr.strip()!r})")
    check(len(lines) == 1, f"glcast {cmd}: {len(lines)} lines on stderr, not 1: {r.stderr!r}")
    check(bool(lines) and lines[0].startswith(prefix + ":"), f"glcast {cmd}: message not from {prefix}: {r.stderr!r}")
    check(word in r.stderr, f"glcast {cmd}: message does not name {word}: {r.stderr!r}")
    check(r.stdout == "", f"glcast {cmd}: wrote to stdout: {r.stdout!r}")


def main():
    # Top level: the commands listed, usage errors.
    for args in (["--help"], ["-h"], ["help"]):
        r = glcast(args)
        check(r.returncode == 0, f"glcast {' '.join(args)}: exit {r.returncode}")
        for c in COMMANDS:
            check(mentions(r.stdout, c), f"glcast {' '.join(args)} does not list {c}")
    r = glcast([])
    check(r.returncode == 2 and len(r.stderr.splitlines()) == 1, f"glcast alone: exit {r.returncode}, {r.stderr!r}")
    one_line_error(glcast(["frobnicate"]), ["frobnicate"], "frobnicate", "glcast")
    one_line_error(glcast(["--frobnicate"]), ["--frobnicate"], "--frobnicate", "glcast")

    # Every command: its help names all its options; an unknown option is refused by name.
    for words, options in OPTIONS.items():
        for how in (list(words) + ["--help"], list(words) + ["-h"], ["help"] + list(words[:1])):
            if how[0] == "help" and len(words) > 1:
                continue
            r = glcast(how)
            name = " ".join(how)
            check(r.returncode == 0, f"glcast {name}: exit {r.returncode}, stderr {r.stderr!r}")
            check(mentions(r.stdout, "glcast " + " ".join(words)), f"glcast {name}: no usage line: {r.stdout!r}")
            for o in options:
                check(mentions(r.stdout, o), f"glcast {name} does not mention {o}")
        for bad in ("--no-such-option", "-Z"):
            args = list(words) + [bad]
            one_line_error(glcast(args), args, bad, "glcast " + words[0])
    print(f"help and unknown options: {len(OPTIONS)} commands")

    # Bad values: exit 2, one line naming the option.
    for args, word in BAD_VALUES:
        one_line_error(glcast(args), args, word, "glcast " + args[0])
    print(f"bad values: {len(BAD_VALUES)} cases")

    # After '--' everything is the program's, even what looks like glcast's own options.
    shim = os.environ.get("GLCAST_SHIM")
    if shim and os.path.exists(shim):
        program = ["sh", "-c", 'echo "$@"; exit 7', "sh", "--help", "--frames", "x", "-o", "y", "--", "z"]
        r = glcast(["capture", "-o", os.path.join(os.environ.get("OUT_DIR", "/tmp"), "cli_help_none.glcs"), "--"]
                   + program)
        check(r.returncode == 7, f"capture -- sh ...: exit {r.returncode}, not the program's 7: {r.stderr!r}")
        check(r.stdout.strip() == "--help --frames x -o y -- z", f"the program's arguments changed: {r.stdout!r}")
    else:
        print("no GLCAST_SHIM: the capture of a program's own options is not checked")
    r = glcast(["run", "--config", "/nonexistent/wall.json", "--", "true", "--config", "--frames", "x", "--bogus"])
    check(r.returncode == 1 and "/nonexistent/wall.json" in r.stderr,
          f"run with the program's options after '--': exit {r.returncode}, {r.stderr!r}")

    # Runtime failures stay exit 1.
    for args in (["dump", "/nonexistent.glcs"], ["replay", "/nonexistent.glcs", "--backend", "egl"],
                 # keys given on the command line are read before anything starts, as run's and slave's
                 ["keeper", "--connect", "tcp://127.0.0.1:1", "--journal", "tcp://127.0.0.1:2", "--bind", "tcp://*:3",
                  "--keys", "/nonexistent-keys"],
                 ["record", "--connect", "tcp://127.0.0.1:1", "--journal", "tcp://127.0.0.1:2", "--keeper",
                  "tcp://127.0.0.1:3", "-o", "/tmp/x.glcs", "--keys", "/nonexistent-keys"]):
        r = glcast(args)
        check(r.returncode == 1 and "nonexistent" in r.stderr, f"glcast {' '.join(args)}: exit {r.returncode}: {r.stderr!r}")

    if failures:
        print(f"{len(failures)} failures")
        return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
