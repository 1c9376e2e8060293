#!/usr/bin/env python3
"""Imports go one way between the source folders (README.md, "Layout"):

    cli -> anything
    interceptor -> master -> protocol -> common
    display_configs -> slave -> protocol -> common
    master, slave, keeper -> net (CURVE keys and endpoint checks; nothing of glcast's own) -> common
    keeper -> master, slave (snapshots: the slave's replay read back, written with the encoders)

Every .h/.cpp/.c under the layer folders is read for #include "folder/..." lines; an include of
a folder its layer may not use fails the test, named as file:line. A folder may always include
itself; the generated headers (glcast_*.h, no folder, in the build tree) are allowed everywhere.
A quoted include that names no layer folder (a bare "shim.h", a "tests/..." file) fails too, so
nothing slips past the check by leaving the folder out.

Usage: layers_test.py [SOURCE_DIR]   (default: the folder above tests/)
Before the real tree, the checker runs on a small made-up tree with one wrong include and must
find exactly that one, so a checker that cannot fail does not pass.
"""
import os
import re
import sys
import tempfile

# What each layer may include besides itself.
ALLOWED = {
    "common": set(),
    "net": {"common"},
    "protocol": {"common"},
    "master": {"protocol", "net", "common"},
    "interceptor": {"master", "protocol", "net", "common"},
    "slave": {"protocol", "net", "common"},
    "display_configs": {"slave", "protocol", "common"},
    "keeper": {"master", "slave", "protocol", "net", "common"},
    "cli": None,  # the command line sits on top: anything
}
LAYERS = list(ALLOWED)

SOURCE_SUFFIXES = (".h", ".cpp", ".c")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]')
GENERATED = re.compile(r"^glcast_[A-Za-z0-9_]+\.h$")


def layer_of(path):
    """The layer of a source path relative to the root ("slave/effects/pipeline.h" -> "slave")."""
    return path.split("/", 1)[0]


def allowed(layer, target):
    return target == layer or ALLOWED[layer] is None or target in ALLOWED[layer]


def rule(layer):
    if ALLOWED[layer] is None:
        return f"{layer} may include anything"
    others = sorted(ALLOWED[layer])
    return f"{layer} may include " + (", ".join(others) + " and itself" if others else "only itself")


def sources(root):
    for layer in LAYERS:
        top = os.path.join(root, layer)
        if not os.path.isdir(top):  # the self-check's made-up tree has only some layers
            continue
        for dirpath, dirnames, filenames in os.walk(top):
            dirnames.sort()
            for name in sorted(filenames):
                if name.endswith(SOURCE_SUFFIXES):
                    yield os.path.relpath(os.path.join(dirpath, name), root).replace(os.sep, "/")


def check(root):
    """Returns (number of files read, list of "file:line: message")."""
    problems = []
    count = 0
    for rel in sources(root):
        count += 1
        layer = layer_of(rel)
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                quote, name = m.groups()
                where = f"{rel}:{number}"
                first = name.split("/", 1)[0] if "/" in name else None
                if first in ALLOWED:
                    target = layer_of(name)
                    if not allowed(layer, target):
                        what = f"{target} (command line)" if target == "cli" and first != "cli" else target
                        problems.append(f'{where}: #include "{name}": {layer} may not include {what} ({rule(layer)})')
                elif quote == '"' and not GENERATED.match(name):
                    problems.append(f'{where}: #include "{name}": not a layer folder; name the header '
                                    f"by its path from the source root ({', '.join(LAYERS)}) "
                                    "or include a generated glcast_*.h")
    return count, problems


def self_check():
    """The checker must catch a wrong include and let the right ones through."""
    files = {
        "common/a.h": '#include "common/b.h"\n',
        "common/b.h": "#include <vector>\n",
        "protocol/p.h": '#include "common/a.h"\n#include "glcast_commands.h"\n',
        "master/m.cpp": '#include "protocol/p.h"\n#include "master/m.h"\n',
        "master/m.h": "",
        "cli/run.cpp": '#include "slave/s.h"\n#include "interceptor/i.h"\n',  # command line: anything
        "interceptor/i.cpp": '#include "master/m.h"\n',
        "slave/s.h": '#include "protocol/p.h"\n',
        "slave/s.cpp": '#include "slave/s.h"\n\n  #  include "master/m.h"\n',  # the wrong one
        "display_configs/d.cpp": '#include "slave/s.h"\n',
    }
    with tempfile.TemporaryDirectory() as root:
        for rel, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w") as f:
                f.write(text)
        count, problems = check(root)
    expected = ['slave/s.cpp:3: #include "master/m.h": slave may not include master '
                "(slave may include common, net, protocol and itself)"]
    if count != len(files) or problems != expected:
        print(f"layers_test: the checker itself is wrong: read {count} of {len(files)} files, found:")
        for p in problems:
            print("  " + p)
        sys.exit(2)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    self_check()
    count, problems = check(root)
    if count == 0:
        print(f"layers_test: no sources under {root} ({', '.join(LAYERS)}): wrong folder?")
        return 1
    for p in problems:
        print(p)
    if problems:
        print(f"layers_test: {len(problems)} include(s) against the layer order in {count} files")
        return 1
    print(f"layers_test: {count} files, every include follows the layer order")
    return 0


if __name__ == "__main__":
    sys.exit(main())
