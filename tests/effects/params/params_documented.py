#!/usr/bin/env python3
"""Every parameter of the injected passes is documented: the table `glcast effects` prints is
the one at the end of docs/effects.md (after the marker line).

    params_documented.py GLCAST [--write]     --write updates docs/effects.md instead
"""
import os
import subprocess
import sys

DOC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "docs", "effects.md")
MARKER = "<!-- the output of `glcast effects`"


def main():
    table = subprocess.run([sys.argv[1], "effects"], check=True, capture_output=True, text=True).stdout
    with open(DOC) as f:
        text = f.read()
    at = text.find(MARKER)
    if at < 0:
        sys.exit(f"{DOC}: no marker line starting {MARKER!r}")
    head = text[:text.index("\n", at) + 1]
    if "--write" in sys.argv:
        with open(DOC, "w") as f:
            f.write(head + "\n" + table)
        return
    documented = text[len(head):].strip().splitlines()
    missing = [line for line in table.strip().splitlines() if line not in documented]
    stale = [line for line in documented if line.startswith("| `") and line not in table]
    for line in missing:
        print("not in docs/effects.md:", line)
    for line in stale:
        print("documented but gone:", line)
    if missing or stale:
        sys.exit(f"docs/effects.md is out of date: run {sys.argv[0]} {sys.argv[1]} --write")
    print(f"{len(table.strip().splitlines()) - 2} parameters documented")


if __name__ == "__main__":
    main()
