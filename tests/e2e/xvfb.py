"""A private Xvfb server for a test: started with -displayfd so parallel tests never collide."""
import os
import subprocess


class Xvfb:
    def __init__(self, size="1280x1024x24"):
        self.size = size
        self.proc = None

    def __enter__(self):
        if os.environ.get("GLCAST_TEST_DISPLAY"):  # reuse a server the caller started
            os.environ["DISPLAY"] = os.environ["GLCAST_TEST_DISPLAY"]
            return self
        r, w = os.pipe()
        self.proc = subprocess.Popen(["Xvfb", "-displayfd", str(w), "-screen", "0", self.size, "-nolisten", "tcp"],
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
            self.proc.wait(timeout=10)
