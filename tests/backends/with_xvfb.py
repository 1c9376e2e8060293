#!/usr/bin/env python3
"""Runs a command with DISPLAY set to a private Xvfb (tests/e2e/xvfb.py); its exit status."""
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "e2e"))
from xvfb import Xvfb  # noqa: E402

if __name__ == "__main__":
    with Xvfb():
        sys.exit(subprocess.call(sys.argv[1:]))
