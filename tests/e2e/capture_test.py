#!/usr/bin/env python3
"""End-to-end capture tests: real GL programs run under Xvfb with the shim preloaded, and the
dump of what they sent is checked against what they did (names they printed, calls they made).

    capture_test.py CASE     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
"""
import os
import re
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.environ.get("OUT_DIR", "/tmp/glcast-e2e")
os.makedirs(OUT, exist_ok=True)


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def capture(name, program, frames, env=None):
    path = os.path.join(OUT, name + ".glcs")
    if os.path.exists(path):
        os.remove(path)
    limit = ["--frames", str(frames)] if frames else []
    r = subprocess.run([GLCAST, "capture", "-o", path] + limit + ["--"] + program,
                       capture_output=True, text=True, timeout=240, env=env)
    check(r.returncode == 0, f"{program[0]} under the shim exited {r.returncode}: {r.stderr[-2000:]}")
    check(os.path.exists(path), f"no capture written: {r.stderr[-2000:]}")
    return path, r.stdout


def dump(path, *extra):
    r = subprocess.run([GLCAST, "dump", path, *extra], capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, f"dump failed: {r.stderr}")
    return r.stdout


def printed_names(stdout, app, call):
    m = re.search(rf"{app}: {call} -> ([\d ]+)", stdout)
    check(m, f"{app} did not print its {call} names: {stdout!r}")
    return [int(x) for x in m.group(1).split()]


def reply_names(text, call):
    """Names in the replies of every `call` of the dump, in order."""
    names = []
    for m in re.finditer(rf"^\d+ {call}\(.*?= &\{{([^}}]*)\}}", text, re.M):
        names += [int(x) for x in m.group(1).split(", ") if x.isdigit()]
    return names


def summaries(text):
    return re.findall(r"^# frame (\d+): (\d+) calls.*?client arrays (\d+) sent \((\d+) bytes\) / (\d+) cache hits, "
                      r"(\d+) buffer writes, (\d+) unserialized", text, re.M)


def common(text, frames, swap="glXSwapBuffers"):
    s = summaries(text)
    check(len(s) == frames, f"{len(s)} frame summaries, expected {frames}")
    check(len(re.findall(rf"^\d+ {swap}\(", text, re.M)) == frames, f"{swap} count differs from {frames}")
    return s


def case_ff_scene():
    path, out = capture("ff_scene", [os.path.join(APPS, "ff_scene"), "--frames", "8"], 8)
    text = dump(path)
    s = common(text, 8)
    check(reply_names(text, "glGenTextures")[:2] == printed_names(out, "ff_scene", "glGenTextures"),
          "glGenTextures replies differ from the names the program saw")
    lists = printed_names(out, "ff_scene", "glGenLists")
    check(re.search(rf"glGenLists\(range = \d+\) = {lists[0]}$", text, re.M), "glGenLists reply differs")
    check(re.search(rf"glNewList\(list = {lists[0]}, mode = GL_COMPILE\)", text), "display list not streamed")
    check(re.search(r"glTexImage2D\(.*pixels = blob\(\d+\)\)", text), "texture pixels missing")
    check(re.search(r"glLightfv\(light = GL_LIGHT0, pname = GL_POSITION, params = \{[^}]*\}\)", text),
          "glLightfv position missing")
    # client arrays: sent in the first frame, cache hits for unchanged ones later, and the
    # array that changes every frame sent again
    check(int(s[0][2]) > 0, "no client arrays shipped in frame 0")
    check(all(int(f[4]) > 0 for f in s[1:]), "unchanged client arrays were not cache hits")
    check(all(int(f[2]) > 0 for f in s[1:]), "the array the program changes every frame was not resent")
    # the indexed draw ships the range up to the max index, not the index count
    m = re.search(r"glcast.client_arrays\(arrays = \[\{slot = vertex, index = 0, size = 3, type = GL_FLOAT, stride = 12, "
                  r"[^}]*first_byte = (\d+), cached = 0, data = (\d+) bytes\}.*\n\d+ "
                  r"glDraw(?:Range)?Elements\(mode = \w+, (?:start = \d+, end = \d+, )?count = (\d+), "
                  r"type = GL_UNSIGNED_SHORT, indices = (?:blob|\{)", text)
    check(m, "no client-array draw with client indices")
    vertices = (int(m.group(1)) + int(m.group(2))) // 12
    check(vertices > int(m.group(3)) // 2, f"range {vertices} vertices looks like the index count")
    print(f"ff_scene: {len(s)} frames, frame 0 {s[0][1]} calls, later {s[-1][1]} calls, "
          f"{s[-1][4]} cache hits/frame")


def case_core_scene():
    path, out = capture("core_scene", [os.path.join(APPS, "core_scene"), "--frames", "6"], 6)
    text = dump(path)
    common(text, 6)
    check(reply_names(text, "glGenBuffers")[:3] == printed_names(out, "core_scene", "glGenBuffers")[:3],
          "glGenBuffers replies differ from the program's names")
    check(re.search(r"glXCreateContextAttribsARB\(.*attrib_list = \{[^}]*\b3, [^}]*\}", text), "no 3.x context")
    check(re.search(r'glShaderSource\(shader = \d+, count = 2, string = \{"#version 330', text),
          "shader source strings missing")
    check(re.search(r"glCheckFramebufferStatus\(target = GL_FRAMEBUFFER\) = GL_FRAMEBUFFER_COMPLETE", text),
          "FBO status reply missing")
    check(re.search(r"glcast.buffer_write\(buffer = \d+, offset = \d+, data = \d+ bytes\)\n\d+ glUnmapBuffer", text),
          "mapped range not shipped before glUnmapBuffer")
    check(re.search(r"glDrawElements\(.*indices = buffer\+0x", text), "element-buffer draw missing")
    print("core_scene: ok")


def case_glfw_dynamic():
    path, out = capture("glfw_dynamic", [os.path.join(APPS, "glfw_dynamic"), "--frames", "5"], 5)
    text = dump(path)
    s = common(text, 5)
    check(all(int(f[1]) >= 5 for f in s), "GLFW-loaded GL calls were not captured")
    check(re.search(r"^\d+ glClear\(", text, re.M) and re.search(r"^\d+ glDraw", text, re.M),
          "glClear/glDraw* missing: dlopen/glfwGetProcAddress path not intercepted")
    print(f"glfw_dynamic: {s[-1][1]} calls per frame")


def case_glxgears():
    path, _ = capture("glxgears", ["glxgears"], 30)
    text = dump(path)
    s = common(text, 30)
    check(reply_names(text, "glGenLists") == [] and re.search(r"glGenLists\(range = 1\) = 1$", text, re.M),
          "glGenLists reply")
    for n in (1, 2, 3):
        check(re.search(rf"glCallList\(list = {n}\)", text), f"glCallList({n}) missing")
    check(all(f[6] == "0" for f in s), "glxgears calls were left unserialized")
    check(re.search(r"glcast.drawable_size\(drawable = 0x[0-9a-f]+, width = 300, height = 300\)", text),
          "drawable size missing")
    print(f"glxgears: 30 frames, {s[1][1]} calls per frame after the first")


def case_xscreensaver_gears():
    # xscreensaver 6's GL hacks render through EGL on X11: frames end at eglSwapBuffers
    hack = "/usr/libexec/xscreensaver/gears"
    path, _ = capture("xscreensaver_gears", [hack, "-window"], 10)
    text = dump(path)
    s = common(text, 10, swap="eglSwapBuffers")
    m = re.search(r"eglCreateContext\(.*attrib_list = \{([^}]*)\}\) = 0x", text)
    check(m and m.group(1).split(", ")[-1] == "12344", "EGL attribute list not cut at EGL_NONE")
    check(re.search(r"glcast.context\(id = 1, .*api = EGL\)", text), "EGL context not announced")
    check(all(f[6] == "0" for f in s), "calls left unserialized")
    print(f"xscreensaver gears: {s[-1][1]} calls per frame")


def case_threads_buffers():
    # two threads, two contexts (the second sharing the first's objects), buffers written
    # through a persistent map (detected before each draw) and through explicit flushes
    path, out = capture("threads_buffers", [os.path.join(APPS, "threads_buffers"), "--frames", "6"], None)
    text = dump(path)
    check(re.search(r"glcast.context\(id = 1, .*share = 0", text) and re.search(r"glcast.context\(id = 2, .*share = 1", text),
          "two contexts with sharing not announced")
    contexts = set(re.findall(r"^# context (\d+)$", text, re.M))
    check({"1", "2"} <= contexts, f"tuples did not carry both contexts: {contexts}")
    m = re.search(r"persistent buffer (\d+), explicit-flush buffer (\d+)", out)
    persistent, explicit = m.group(1), m.group(2)
    writes = re.findall(rf"glcast.buffer_write\(buffer = {persistent}, .*\)\n\d+ glDrawArrays", text)
    check(len(writes) >= 5, f"persistent-map writes before draws: {len(writes)}")
    flushes = re.findall(rf"glcast.buffer_write\(buffer = {explicit}, offset = 0, data = 24 bytes\)\n\d+ glFlushMappedBufferRange", text)
    check(len(flushes) == 6, f"explicit flushes shipped: {len(flushes)}")
    print(f"threads_buffers: {len(writes)} persistent writes, {len(flushes)} flushes")


def case_bad_files():
    # (a capture of its own: glxgears.glcs is case_glxgears', which ctest may be rewriting
    # beside this case; reading it half-written failed this case once)
    good, _ = capture("bad_files_source", ["glxgears"], 30)
    data = open(good, "rb").read()
    cases = {
        "truncated": data[: len(data) // 2],
        "foreign": b"\x89PNG\r\n\x1a\n" + bytes(200),
        "empty": b"",
        "corrupted": data[:100] + bytes([data[100] ^ 0xFF]) + data[101:],
        "absurd_length": data[:64 + 20] + b"\xf0\xff\xff\xff" + data[64 + 24:],
    }
    for name, content in cases.items():
        p = os.path.join(OUT, f"bad_{name}.glcs")
        open(p, "wb").write(content)
        r = subprocess.run([GLCAST, "dump", p], capture_output=True, text=True, timeout=60)
        check(r.returncode == 1, f"{name}: exit {r.returncode}, stderr {r.stderr!r}")
        check(re.search(r"at byte \d+", r.stderr), f"{name}: no byte offset in {r.stderr!r}")
        print(f"{name}: {r.stderr.strip()}")
    r = subprocess.run([GLCAST, "dump", "/nonexistent.glcs"], capture_output=True, text=True)
    check(r.returncode == 1 and "nonexistent" in r.stderr, "missing file")
    r = subprocess.run([GLCAST, "dump", good, "--frames", "9:3"], capture_output=True, text=True)
    check(r.returncode == 2 and "--frames" in r.stderr, "bad --frames accepted")


def case_children():
    # a shell that is not a GL program passes through and writes nothing; its GL child is captured
    p = os.path.join(OUT, "children.glcs")
    if os.path.exists(p):
        os.remove(p)
    r = subprocess.run([GLCAST, "capture", "-o", p, "--", "sh", "-c", "ls / > /dev/null; echo hi"],
                       capture_output=True, text=True, timeout=60)
    check(r.returncode == 0 and r.stdout.strip() == "hi", f"non-GL program disturbed: {r}")
    check(not os.path.exists(p), "a capture file was written for a program without GL calls")
    r = subprocess.run([GLCAST, "capture", "-o", p, "--frames", "3", "--", "sh", "-c", "true; glxgears"],
                       capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, f"glxgears under sh: {r.stderr}")
    common(dump(p), 3)


def case_terminated():
    # glcast capture stopped by SIGTERM (timeout(1), a service manager) stops its program too;
    # before, the program ran on without it (found when a timed-out capture of a game kept
    # running for half an hour)
    p = os.path.join(OUT, "terminated.glcs")
    proc = subprocess.Popen([GLCAST, "capture", "-o", p, "--", "glxgears"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    time.sleep(3)
    with open(f"/proc/{proc.pid}/task/{proc.pid}/children") as f:
        children = [int(c) for c in f.read().split()]
    program = [c for c in children if b"glxgears" in open(f"/proc/{c}/cmdline", "rb").read()]
    check(len(program) == 1, f"glxgears is not among glcast's children {children}")
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise AssertionError("glcast capture did not end within 60 s of SIGTERM")
    try:
        os.kill(program[0], 0)
        alive = True
    except ProcessLookupError:
        alive = False
    if alive:
        os.kill(program[0], signal.SIGKILL)
    check(not alive, "the program runs on after glcast capture was stopped")


def case_relative_paths():
    # `-o rel.glcs` means rel.glcs where glcast was started, even when the program changes
    # directory first; `replay --out a/b` makes a/ too
    work = os.path.join(OUT, "relative")
    sub = os.path.join(work, "sub")
    subprocess.run(["rm", "-rf", work], check=True)
    os.makedirs(sub)
    r = subprocess.run([GLCAST, "capture", "-o", "rel.glcs", "--frames", "2", "--", "sh", "-c", "cd sub && glxgears"],
                       cwd=work, capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, f"capture: {r.stderr}")
    check(os.path.exists(os.path.join(work, "rel.glcs")), "rel.glcs not written where glcast was started")
    check(not os.path.exists(os.path.join(sub, "rel.glcs")), "rel.glcs written where the program went")
    out = os.path.join(work, "a", "b")
    r = subprocess.run([GLCAST, "replay", os.path.join(work, "rel.glcs"), "--backend", "egl", "--out", out],
                       capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, f"replay --out a/b: {r.stderr}")
    check(os.path.exists(os.path.join(out, "frame-000001.png")), "replay --out a/b wrote no frames")
    r = subprocess.run([GLCAST, "replay", os.path.join(work, "rel.glcs"), "--backend", "egl", "--out",
                        os.path.join(work, "rel.glcs", "x")], capture_output=True, text=True, timeout=120)
    check(r.returncode == 1 and "--out" in r.stderr, f"replay --out under a file: {r.returncode} {r.stderr}")


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
