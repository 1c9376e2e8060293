#!/usr/bin/env python3
"""Late join from a keeper (docs/keeper.md): a program publishes with a journal of a few MiB,
a keeper replays its stream from the start, and a slave that starts long after the journal
stopped holding the stream's start joins from the keeper's snapshot plus the journal's last
messages. Its frames must equal the program's own from the first one it shows, and its join
must not depend on how long the program has run.

    keeper_test.py CASE      with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment

Cases: a program (or mode of tests/apps_extra/live_state.c) run for FRAMES frames, a slave
joining at JOIN. Long runs (20,000 frames) are for scripts/keeper_join_runs.sh; CI runs shorter ones.
"""
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png import read_png  # noqa: E402
from ports import free_port_run  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "keeper")


def check(cond, msg):
    """msg: a string, or a function that makes it (for messages that read a process's output)."""
    if not cond:
        raise AssertionError(msg() if callable(msg) else msg)


def rss_mib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return 0.0


def frame_of(out, n):
    return os.path.join(out, f"frame-{n:06d}.png")


def join(name, program, frames, join_at, journal_mb=2, size=None, fallback=None, restart_keeper_at=None):
    """fallback: what the keeper must name as missing; the slave then takes the journal.
    restart_keeper_at: the keeper is killed at this frame, once the journal no longer holds the
    stream's start and the keeper has kept its state on disk, and started again (from that state)."""
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    stream = f"ipc://{out}/stream"
    env = dict(os.environ, GLCAST_PUBLISH=stream, GLCAST_JOURNAL_ENDPOINT=stream + "-journal",
               GLCAST_JOURNAL_MB=str(journal_mb), GLCAST_SNAPSHOT_DIR=os.path.join(out, "program"),
               GLCAST_SNAPSHOT_FROM=str(join_at // 2), GLCAST_FRAMES=str(frames), GLCAST_EXIT_AFTER_FRAMES="1",
               GLCAST_WAIT_SUBSCRIBERS="1", GLCAST_TEST_SWAP_LOG=os.path.join(out, "swaps.log"),
               LD_PRELOAD=os.environ["GLCAST_SHIM"])
    if restart_keeper_at:
        env["GLCAST_VERBOSE"] = "1"  # (the program says when its journal lets go of the stream's start)
    swap_log = os.path.join(out, "swaps.log")
    keeper_log = os.path.join(out, "keeper.log")
    keeper_args = [GLCAST, "keeper", "--connect", stream, "--journal", stream + "-journal", "--bind", stream + "-keeper",
                   "--verbose", "--state", os.path.join(out, "keeper.state"), "--state-every", "1"]
    with open(keeper_log, "w") as log:
        keeper = subprocess.Popen(keeper_args, stderr=log, text=True)
    program_log = os.path.join(out, "program.log")
    with open(program_log, "w") as log:
        proc = subprocess.Popen(program, env=env, stdout=subprocess.DEVNULL, stderr=log, text=True)
    rss = {}
    # The program's memory while it publishes, at frame 1000 (or half the join), and at the join.
    for mark in sorted({min(1000, join_at // 2), join_at} | ({restart_keeper_at} if restart_keeper_at else set())):
        while program_frame(swap_log) < mark:
            check(proc.poll() is None, lambda: f"the program ended early: {open(program_log).read()[-2000:]}")
            check(keeper.poll() is None, lambda: f"the keeper ended: {open(keeper_log).read()[-2000:]}")
            time.sleep(0.01)
        rss[mark] = rss_mib(proc.pid)
        if mark == restart_keeper_at:
            # Killed once the journal no longer holds the stream's start (before, a keeper started
            # again could not be rebuilt at all) and once it has kept a state.
            t0 = time.monotonic()
            while not ("kept the state of frame" in open(keeper_log).read() and
                       "GLCAST_JOURNAL_MB" in open(program_log).read()):
                check(time.monotonic() - t0 < 120, lambda: f"no kept state and full journal within 120 s: "
                      f"{open(keeper_log).read()[-1500:]} {open(program_log).read()[-1500:]}")
                time.sleep(0.05)
            keeper.kill()
            keeper.wait()
            with open(keeper_log, "a") as log:
                log.write("(test: keeper killed)\n")
                log.flush()
                keeper = subprocess.Popen(keeper_args, stderr=log, text=True)
    # The program is stopped while the slave joins, so that the join happens at this frame
    # whatever the machine's speed; it goes on once the slave has the snapshot.
    os.kill(proc.pid, signal.SIGSTOP)
    rss[join_at] = rss_mib(proc.pid)
    slave_log = os.path.join(out, "slave.log")
    with open(slave_log, "w") as log:
        slave = subprocess.Popen([GLCAST, "slave", "--connect", stream, "--journal", stream + "-journal",
                                  "--keeper", stream + "-keeper", "--backend", "egl", "--out",
                                  os.path.join(out, "slave"), "--wait", "120", "--quiet"], stderr=log, text=True)
    t0 = time.monotonic()
    # The keeper answers at the frame the program stopped at; the journal (the program's own
    # thread) answers the rest once it runs again.
    def keeper_said(*what):
        text = open(keeper_log).read()
        return any(said in text[text.rfind("(test: keeper killed)") + 1:] for said in what)

    while not keeper_said("snapshot of frame", "not in the snapshot"):
        check(slave.poll() is None, lambda: f"the slave ended early: {open(slave_log).read()[-3000:]}")
        check(time.monotonic() - t0 < 120, lambda: f"the keeper gave no snapshot within 120 s: {open(keeper_log).read()[-3000:]}")
        time.sleep(0.01)
    os.kill(proc.pid, signal.SIGCONT)
    while "joined at frame" not in open(slave_log).read():
        check(slave.poll() is None, lambda: f"the slave ended early: {open(slave_log).read()[-3000:]}")
        check(time.monotonic() - t0 < 120, lambda: f"the slave did not join within 120 s: {open(slave_log).read()[-3000:]}")
        time.sleep(0.01)
    joined = [l for l in open(slave_log).read().splitlines() if "joined at frame" in l][0]
    join_seconds = float(joined.split(" in ", 1)[1].split()[0])
    proc.wait(timeout=900)
    check(slave.wait(timeout=300) == 0, lambda: f"slave failed: {open(slave_log).read()[-3000:]}")
    keeper.wait(timeout=300)
    keeper_log = open(keeper_log).read()
    if restart_keeper_at:
        check("starting from its kept state of frame" in keeper_log,
              f"the keeper started again did not start from its kept state: {keeper_log[-2000:]}")
    shown = sorted(f for f in os.listdir(os.path.join(out, "slave")) if f.endswith(".png"))
    check(shown, "the slave wrote no frame")
    first_frame = int(shown[0][6:12])
    if fallback:  # the keeper said its snapshot cannot hold the state: the slave took the journal
        check("catching up from the journal instead" in open(slave_log).read(),
              lambda: f"the slave did not fall back to the journal: {open(slave_log).read()[-2000:]}")
        check(fallback in keeper_log, f"the keeper did not name {fallback!r} as missing: {keeper_log[-2000:]}")
        check(first_frame == 0, f"the slave's first frame is {first_frame}, not 0: it did not replay the journal")
        compared = 0
        for f in shown:
            ref = os.path.join(out, "program", f)
            if os.path.exists(ref):
                check(read_png(ref) == read_png(os.path.join(out, "slave", f)), f"{name}: the slave's {f} differs")
                compared += 1
        check(compared > 0, "no frame to compare")
        print(f"{name}: the keeper refused ({[l for l in keeper_log.splitlines() if 'not in' in l][:1]}); "
              f"the slave replayed the journal from frame 0; {compared} frames equal to the program's")
        return 0, rss
    # The keeper may be behind the program (it renders too; on a loaded machine by hundreds of
    # frames): the slave joins where the keeper is and takes the rest from the journal.
    check(first_frame >= max(1, join_at // 2), f"the slave's first frame {first_frame} is far before the join at "
                                               f"{join_at}: it did not join from the keeper")
    compared = 0
    for f in shown:
        ref = os.path.join(out, "program", f)
        if not os.path.exists(ref):
            continue
        a, b = read_png(ref), read_png(os.path.join(out, "slave", f))
        check(a == b, f"{name}: the slave's {f} differs from the program's")
        compared += 1
    check(compared == len(shown), f"{len(shown) - compared} of the slave's frames have no frame of the program's")
    check("not in the snapshot" not in keeper_log, f"the keeper's snapshot misses state: {keeper_log[-2000:]}")
    snapshot_line = [l for l in keeper_log.splitlines() if "snapshot of frame" in l]
    print(f"{name}: {joined.split(': ', 1)[1]}; first frame shown {first_frame} of {frames}; {compared} frames equal to the "
          f"program's; program RSS {', '.join(f'{v:.1f} MiB at frame {k}' for k, v in rss.items())}; "
          f"{snapshot_line[-1] if snapshot_line else ''}")
    return join_seconds, rss


def program_frame(swap_log):
    """The program's last swapped frame, from its GLCAST_TEST_SWAP_LOG (a line per swap)."""
    try:
        with open(swap_log, "rb") as f:
            f.seek(0, 2)
            size = f.tell()
            f.seek(max(0, size - 64))
            lines = f.read().split(b"\n")
        complete = [l for l in lines[:-1] if l.strip()]
        return int(complete[-1].split()[0]) if complete else -1
    except (OSError, ValueError, IndexError):
        return -1


def app(name, *args):
    return [os.path.join(APPS, name), *args]


# CI: a few thousand frames each; scripts/keeper_join_runs.sh runs them for 20,000.
FRAMES = int(os.environ.get("KEEPER_TEST_FRAMES", "2000"))
JOIN = int(os.environ.get("KEEPER_TEST_JOIN", str(FRAMES * 5 // 6)))


def case_glxgears():  # display lists compiled once, lights, materials
    join("glxgears", ["glxgears", "-geometry", "128x128"], FRAMES, JOIN)


def case_ff_scene():  # fixed function: a texture, display lists, client arrays, matrices, lights
    join("ff_scene", app("ff_scene", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_core_scene():  # core profile: a texture rendered into every frame, VAOs, a uniform buffer, mapped writes
    join("core_scene", app("core_scene", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_glfw_dynamic():  # GL loaded with dlopen by GLFW, buffers
    join("glfw_dynamic", app("glfw_dynamic", "--size", "128x96", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_client_draws():  # client arrays, instancing, multi-draws, a program whose shaders are deleted
    join("client_draws", app("client_draws", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_threads_buffers():  # two threads, two contexts sharing objects, a persistent mapped buffer
    join("threads_buffers", app("threads_buffers", "--frames", str(FRAMES // 2)), FRAMES, JOIN)


def case_textures():  # a new texture every frame, the older ones deleted
    join("textures", app("live_state", "textures", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_render_once():  # a texture rendered into once, sampled forever; the window never cleared
    join("render_once", app("live_state", "render_once", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_renderbuffer():  # colour and depth renderbuffers drawn into, blitted to the window
    join("renderbuffer", app("live_state", "renderbuffer", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_fences():  # fences waited on two frames after they were made, an occlusion query read a frame later
    join("fences", app("live_state", "fences", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_multisample():  # a 4-sample window: the snapshot makes the slave's context multisampled too
    join("multisample", app("multisample", "--size", "160x120", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_fallback():  # an attribute stack left pushed: no snapshot can hold it, the journal can
    join("fallback", app("live_state", "pushed", "--size", "160x120", "--frames", "600"), 600, 400,
         journal_mb=64, fallback="attribute stack depth 1")


def case_fallback_feedback():  # a transform feedback object: no snapshot here recreates one
    join("fallback_feedback", app("live_state", "feedback", "--size", "160x120", "--frames", "600"), 600, 400,
         journal_mb=64, fallback="transform feedback object 1")


def case_fbo_ext():  # EXT framebuffer objects, a texture rendered into
    join("fbo_ext", app("fbo_ext", "--frames", str(FRAMES)), FRAMES, JOIN)


def case_capture_start_frame():
    """glcast capture --start-frame S --frames N: a capture of frames S..S+N-1 that replays on its own,
    equal to the program's own frames (a keeper and glcast record behind it)."""
    out = os.path.join(OUT, "capture_start_frame")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    start, n = FRAMES // 2, 20
    env = dict(os.environ, GLCAST_SNAPSHOT_DIR=os.path.join(out, "program"), GLCAST_SNAPSHOT_FROM=str(start))
    r = subprocess.run([GLCAST, "capture", "-o", os.path.join(out, "c.glcs"), "--start-frame", str(start), "--frames",
                        str(n), "--"] + app("ff_scene", "--size", "160x120", "--frames", str(FRAMES)),
                       env=env, capture_output=True, text=True, timeout=600)
    check(r.returncode == 0, lambda: f"capture failed: {r.stdout[-1000:]} {r.stderr[-2000:]}")
    reference = os.path.join(out, "reference")
    os.makedirs(reference)
    for k in range(n):
        shutil.copy(os.path.join(out, "program", f"frame-{start + k:06d}.png"), os.path.join(reference, f"frame-{k:06d}.png"))
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = subprocess.run([GLCAST, "replay", os.path.join(out, "c.glcs"), "--compare", reference], capture_output=True,
                       text=True, timeout=300, env=headless)
    check(r.returncode == 0 and f"compared {n} frames: 0 differ" in r.stdout, lambda: f"{r.stdout[-1500:]} {r.stderr[-1500:]}")
    print(f"capture --start-frame {start} --frames {n}: {r.stdout.strip().splitlines()[-1]}")


def case_keeper_restarted():
    """A keeper killed once the journal (1 MiB) no longer holds the stream's start comes back from
    the state it kept on disk and the journal's messages since; a slave then joins from it and
    shows the program's frames. Before, a keeper started again replayed the journal from the
    start: here it could not, and no slave could join from it for the rest of the program."""
    join("keeper_restarted", app("ff_scene", "--size", "160x120", "--frames", "4000"), 4000, 3300, journal_mb=1,
         restart_keeper_at=2400)


def case_run_keeper_killed():
    """glcast run --endpoint tcp://...: its keeper is killed while the program runs. run starts it
    again (as systemd would a slave), the new keeper rebuilds the state from the journal, and a
    slave that starts later joins from its snapshot, not from the journal's start."""
    out = os.path.join(OUT, "run_keeper_killed")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    port = free_port_run(4)
    swap_log = os.path.join(out, "swaps.log")
    env = dict(os.environ, GLCAST_TEST_SWAP_LOG=swap_log)
    run_log = os.path.join(out, "run.log")
    with open(run_log, "w") as log:
        run = subprocess.Popen([GLCAST, "run", "--endpoint", f"tcp://127.0.0.1:{port}", "--insecure", "--backend", "egl",
                                "--frames", "100000", "--", "glxgears"], env=env, stdout=subprocess.DEVNULL, stderr=log,
                               start_new_session=True)

    def keepers():
        r = subprocess.run(["pgrep", "-f", f"keeper --connect .* --bind tcp://127.0.0.1:{port + 2}"],
                           capture_output=True, text=True)
        return [int(p) for p in r.stdout.split()]

    def wait_until(cond, what, seconds=120):
        t0 = time.monotonic()
        while not cond():
            check(run.poll() is None, lambda: f"glcast run ended: {open(run_log).read()[-2000:]}")
            check(time.monotonic() - t0 < seconds, lambda: f"no {what} within {seconds} s: {open(run_log).read()[-2000:]}")
            time.sleep(0.05)

    try:
        wait_until(lambda: program_frame(swap_log) >= 300 and keepers(), "frame 300")
        first = keepers()[0]
        os.kill(first, signal.SIGKILL)
        wait_until(lambda: keepers() and keepers()[0] != first, "keeper started again")
        wait_until(lambda: program_frame(swap_log) >= 3000, "frame 3000")
        slave_log = os.path.join(out, "slave.log")
        with open(slave_log, "w") as log:
            slave = subprocess.Popen([GLCAST, "slave", "--connect", f"tcp://127.0.0.1:{port}", "--journal",
                                      f"tcp://127.0.0.1:{port + 1}", "--keeper", f"tcp://127.0.0.1:{port + 2}",
                                      "--insecure", "--backend", "egl", "--wait", "60", "--quiet"],
                                     stderr=log)
        t0 = time.monotonic()
        while "joined at frame" not in open(slave_log).read():
            check(slave.poll() is None, lambda: f"the slave ended: {open(slave_log).read()[-2000:]}")
            check(time.monotonic() - t0 < 60, lambda: f"the slave did not join in 60 s: {open(slave_log).read()[-2000:]}")
            time.sleep(0.05)
        joined = [l for l in open(slave_log).read().splitlines() if "joined at frame" in l][0]
        frame = int(joined.split("joined at frame ")[1].split(":")[0])
        # The new keeper may be far behind the program on a loaded machine (it replays the
        # journal from the start); a snapshot at all is the proof that a keeper answered.
        check(frame > 0 and ": 0 snapshot" not in joined, f"the slave did not join from the keeper: {joined}")
        said = [l for l in open(run_log).read().splitlines() if "keeper" in l and "again" in l]
        check(said, f"glcast run did not say it started the keeper again: {open(run_log).read()[-2000:]}")
        slave.kill()
        print(f"run_keeper_killed: {said[0]}; the late slave: {joined}")
    finally:
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGTERM)
            run.wait(timeout=60)


def case_run_keeper_killed_often():
    """The keeper killed again each time run has started it, four times in a row: run waits
    longer before each start (as systemd's restart backoff), and starts it again. Before, the
    third quick death made run give up on it for the rest of the program (the hour-long chaos run
    lost its keeper at minute 48 that way), and no slave could join from then on."""
    out = os.path.join(OUT, "run_keeper_killed_often")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    port = free_port_run(4)
    swap_log = os.path.join(out, "swaps.log")
    run_log = os.path.join(out, "run.log")
    with open(run_log, "w") as log:
        run = subprocess.Popen([GLCAST, "run", "--endpoint", f"tcp://127.0.0.1:{port}", "--insecure", "--backend", "egl",
                                "--frames", "1000000", "--", "glxgears"], env=dict(os.environ, GLCAST_TEST_SWAP_LOG=swap_log),
                               stdout=subprocess.DEVNULL, stderr=log, start_new_session=True)

    def keepers():
        r = subprocess.run(["pgrep", "-f", f"keeper --connect .* --bind tcp://127.0.0.1:{port + 2}"],
                           capture_output=True, text=True)
        return [int(p) for p in r.stdout.split()]

    def wait_for_keeper(other_than, seconds):
        t0 = time.monotonic()
        while time.monotonic() - t0 < seconds:
            check(run.poll() is None, lambda: f"glcast run ended: {open(run_log).read()[-2000:]}")
            now = [p for p in keepers() if p != other_than]
            if now:
                return now[0], time.monotonic() - t0
            time.sleep(0.05)
        return None, seconds

    try:
        keeper, _ = wait_for_keeper(None, 120)
        check(keeper, lambda: f"no keeper: {open(run_log).read()[-2000:]}")
        waits = []
        for kill in range(4):
            os.kill(keeper, signal.SIGKILL)
            keeper, waited = wait_for_keeper(keeper, 60)
            check(keeper, lambda: f"after kill {kill + 1}, no keeper within 60 s: {open(run_log).read()[-2000:]}")
            waits.append(waited)
        said = [l for l in open(run_log).read().splitlines() if "keeper" in l and "again" in l]
        check(not any("not starting it again" in l for l in said), f"run gave up on its keeper: {said}")
        check(waits[-1] > waits[0] + 2, f"run did not wait longer after quick deaths in a row: {waits}")
        print(f"run_keeper_killed_often: started again after {', '.join(f'{w:.1f} s' for w in waits)}; "
              f"run said: {said[-1]}")
    finally:
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGTERM)
            run.wait(timeout=60)


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
