"""A private Xvfb server for a test: started with -displayfd so parallel tests never collide.

It also ends whatever the test started and left running, however the test ends: the test's
process becomes its descendants' subreaper (orphans come to it, not to init), and on leaving the
block every process below it is killed. A leftover slave or program holds the test's output pipe
open, and ctest then waits for it until the test's timeout: a failure of seconds took 900 s."""
import ctypes
import os
import signal
import subprocess
import time

PR_SET_CHILD_SUBREAPER = 36


def become_subreaper():
    try:
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    except (OSError, AttributeError):
        pass  # (then only the descendants whose parents are still alive are found)


def descendants(pid):
    """Every process below `pid`, from /proc's parent links."""
    children = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
            ppid = int(stat[stat.rfind(")") + 2:].split()[1])
        except (OSError, ValueError, IndexError):
            continue
        children.setdefault(ppid, []).append(int(entry))
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


def end_descendants():
    """Kills every process below this one and reaps those that are its children."""
    for _ in range(3):
        left = descendants(os.getpid())
        if not left:
            return
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            try:
                if os.waitpid(-1, os.WNOHANG) == (0, 0):
                    time.sleep(0.02)
            except ChildProcessError:
                break
            if not descendants(os.getpid()):
                break


class Xvfb:
    def __init__(self, size="1280x1024x24"):
        self.size = size
        self.proc = None

    def __enter__(self):
        become_subreaper()
        if os.environ.get("GLCAST_TEST_DISPLAY"):  # reuse a server the caller started
            os.environ["DISPLAY"] = os.environ["GLCAST_TEST_DISPLAY"]
            return self
        r, w = os.pipe()
        # -noreset: by default the server resets when its last client leaves, and a client that
        # connects during the reset is dropped before its setup is answered (XOpenDisplay fails:
        # Window.SameSceneAsHeadlessBackends once in CI, right after the previous test's window
        # closed).
        self.proc = subprocess.Popen(["Xvfb", "-displayfd", str(w), "-screen", "0", self.size, "-nolisten", "tcp",
                                      "-noreset"],
                                     pass_fds=(w,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(w)
        number = b""
        with os.fdopen(r, "rb") as f:
            while not number.endswith(b"\n"):
                c = f.read(1)
                if not c:
                    raise RuntimeError("Xvfb did not start")
                number += c
        os.environ["DISPLAY"] = ":" + number.decode().strip()
        os.environ.setdefault("LIBGL_ALWAYS_SOFTWARE", "1")
        return self

    def __exit__(self, *exc):
        if self.proc:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                pass
        end_descendants()
