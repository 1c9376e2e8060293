#!/usr/bin/env python3
"""A wall of three machines, made here as network namespaces joined by a bridge: the program's
(10.214.0.1) and two display machines (10.214.0.2, .3), each showing two tiles of a 2x2 wall.

    wall_machines_test.py CASE    with GLCAST, GLCAST_SHIM, OUT_DIR and SERVICE_UNIT set

tcp:        the display machines' slaves run as systemd services (packaging/systemd, one systemd
            per display machine, in a PID and mount namespace of its own) with CURVE keys made by
            glcast keygen. Two programs one after the other: the stitched tiles equal the canvas
            replay; the swap barrier holds across machines; run's status names every tile and
            machine; a slave killed during the second program is restarted by systemd and its
            frames are the program's again (the time it took is printed); a slave with an
            unknown key, a subscriber without keys and an endpoint without keys are refused.
epgm:       the same wall with the stream sent once by multicast (the TCP channels with CURVE).

Skipped where namespaces cannot be made (not root, no iproute2), or systemd is missing or does not
run in a namespace here.
"""
import contextlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import netns  # noqa: E402
from wall_test import TOLERANCE, check, compare, run  # noqa: E402  (the one-machine wall's helpers)
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
UNIT = os.environ.get("SERVICE_UNIT", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "wall_machines")
TILES = {"top-left": ("dispa", 0, 0), "top-right": ("dispa", 640, 0),
         "bottom-left": ("dispb", 0, 480), "bottom-right": ("dispb", 640, 480)}
ADDRESS = {"master": "10.214.0.1", "dispa": "10.214.0.2", "dispb": "10.214.0.3"}
HYBRID = os.path.isdir("/sys/fs/cgroup/systemd")  # cgroup v1's name=systemd beside v2, or v2 alone
HYBRID_BOOT = ("mount -t tmpfs tmpfs /sys/fs/cgroup; mkdir /sys/fs/cgroup/systemd /sys/fs/cgroup/unified\n"
               "mount -t cgroup -o none,name=systemd cgroup /sys/fs/cgroup/systemd\n"
               "mount -t cgroup2 cgroup2 /sys/fs/cgroup/unified\n"
               "for h in systemd unified; do\n"
               "  mkdir -p /sys/fs/cgroup/$h/{cgroup}; echo $$ > /sys/fs/cgroup/$h/{cgroup}/cgroup.procs\n"
               "  umount /sys/fs/cgroup/$h\n"
               "done\n"
               "exec unshare --cgroup sh -c 'set -e; "
               "mount -t cgroup -o none,name=systemd cgroup /sys/fs/cgroup/systemd; "
               "mount -t cgroup2 cgroup2 /sys/fs/cgroup/unified; ")
UNIFIED_BOOT = ("mount -t cgroup2 cgroup2 /sys/fs/cgroup\n"
                "mkdir -p /sys/fs/cgroup/{cgroup}; echo $$ > /sys/fs/cgroup/{cgroup}/cgroup.procs\n"
                "umount /sys/fs/cgroup\n"
                "exec unshare --cgroup sh -c 'set -e; mount -t cgroup2 cgroup2 /sys/fs/cgroup; ")


@contextlib.contextmanager
def machines(name, tag):
    """Three namespaces on a bridge (netns.py); yields their names by role, or None."""
    with netns.bridged(ADDRESS, tag, name) as made:
        yield {role: n for role, (n, _) in made.items()} if made else None


def keys(out):
    """master: master.key, authorized/dispa.pub, dispb.pub; each display machine: master.pub and
    its slave.key; stranger: a key the master does not know."""
    return netns.wall_keys(GLCAST, out, ("dispa", "dispb"))


class Supervisor:
    """systemd as PID 1 of a PID, mount and cgroup namespace inside a display machine's network
    namespace, running glcast-slave@TILE.service for its tiles from the shipped unit. /run, /tmp
    and /var/tmp are its own (tmpfs: systemd-tmpfiles would otherwise empty this machine's /tmp),
    so is its cgroup (otherwise it takes the host's root cgroup, and other tests' processes with
    it); only the tiles' units are started (no default target). Where systemd cannot run so, the
    test is skipped."""

    def __init__(self, out, machine, netns, tiles, config, key_dir):
        self.dir = os.path.join(out, "systemd-" + machine)
        self.config = config
        self.machine = machine
        units = os.path.join(self.dir, "units")
        os.makedirs(units)
        shutil.copy(UNIT, units)
        with open(os.path.join(units, "glcast-wall.target"), "w") as f:
            f.write("[Unit]\nDefaultDependencies=no\nWants=" +
                    " ".join(f"glcast-slave@{t}.service" for t in tiles) + "\n")
        for t in tiles:
            d = os.path.join(units, f"glcast-slave@{t}.service.d")
            os.makedirs(d)
            with open(os.path.join(d, "test.conf"), "w") as f:
                f.write("[Unit]\nDefaultDependencies=no\n[Service]\n"
                        f"Environment=GLCAST_CONFIG={config} GLCAST_BACKEND=egl GLCAST_KEYS={key_dir} "
                        f"GLCAST_MACHINE={machine} \"GLCAST_SLAVE_ARGS=--out {os.path.join(out, t)}\" "
                        f"GLCAST_TEST_PRESENT_LOG={os.path.join(out, 'presents', t)}\n"
                        f"StandardError=append:{os.path.join(out, t + '.log')}\n")
        # A cgroup of its own, seen as the root through a cgroup namespace: without it systemd
        # takes the host's root cgroup, where the other tests' processes live, for its own.
        self.cgroup = f"glcast-test-{machine}-{os.getpid()}"
        boot = os.path.join(self.dir, "boot.sh")
        with open(boot, "w") as f:
            f.write("#!/bin/sh\nset -e\n"
                    "for d in /run /tmp /var/tmp; do mount -t tmpfs tmpfs $d; done\n"
                    f"mount --bind {units} /etc/systemd/system\n"
                    # ip netns exec gave this namespace a /sys without the cgroup mounts: the
                    # hierarchies are mounted here, a cgroup made and entered, and mounted again
                    # inside a cgroup namespace whose root it is.
                    # (hybrid: name=systemd v1 and v2 at unified/, as this machine has; else v2 alone)
                    + (HYBRID_BOOT if HYBRID else UNIFIED_BOOT).format(cgroup=self.cgroup) +
                    "exec env container=glcast-test /lib/systemd/systemd --system --unit=glcast-wall.target "
                    "--log-target=console --log-level=warning'\n")
        os.chmod(boot, 0o755)
        self.log = open(os.path.join(self.dir, "systemd.log"), "w")
        self.proc = subprocess.Popen(["ip", "netns", "exec", netns, "unshare", "--pid", "--fork", "--mount",
                                      "--mount-proc", "--propagation", "private", boot],
                                     stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)

    def systemd_pid(self):
        r = run(["pgrep", "-P", str(self.proc.pid)])  # unshare's child: systemd itself
        return int(r.stdout.split()[0]) if r.returncode == 0 and r.stdout.split() else None

    def slave_pid(self, tile):
        r = run(["pgrep", "-f", f"slave --service --config {re.escape(self.config)} --tile {tile} "])
        pids = [int(p) for p in r.stdout.split()]
        return pids[0] if pids else None

    def stop(self):
        pid = self.systemd_pid()
        if pid:
            os.kill(pid, signal.SIGKILL)  # PID 1 of the namespace: every process in it goes too
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
        self.log.close()
        for top in (["/sys/fs/cgroup/systemd", "/sys/fs/cgroup/unified"] if HYBRID else ["/sys/fs/cgroup"]):
            # empty now: its processes are gone
            for d in sorted((os.path.join(r, x) for r, ds, _ in os.walk(f"{top}/{self.cgroup}")
                             for x in ds), key=len, reverse=True) + [f"{top}/{self.cgroup}"]:
                try:
                    os.rmdir(d)
                except OSError:
                    pass


def statuses(path):
    if not os.path.exists(path):
        return []
    out = []
    for line in open(path):
        try:
            out.append(json.loads(line))
        except ValueError:
            pass  # the line being written
    return out


def program_run(ns, config, key_dir, out, name, frames, program, extra=()):
    capture = os.path.join(out, name + ".glcs")
    env = dict(os.environ, GLCAST_CAPTURE=capture)
    return subprocess.Popen(["ip", "netns", "exec", ns["master"], GLCAST, "run", "--config", config, "--machine",
                             "master", "--keys", key_dir, "--backend", "egl", "--frames", str(frames),
                             "--status-json", os.path.join(out, name + "-status.jsonl"), "--wait-tiles", "120", *extra,
                             "--"] + program,
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True), capture


def tile_reference(capture, config, tile, frames, out):
    ref = os.path.join(out, "reference", os.path.basename(capture), tile)
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = run([GLCAST, "replay", capture, "--config", config, "--tile", tile, "--frames", f"{frames[0]}:{frames[1]}",
             "--out", ref], env=env)
    check(r.returncode == 0, f"tile replay failed: {r.stderr[-2000:]}")
    return ref


def stitched_against_canvas(out, capture, program_dir, frame):
    """Frame `frame` of the four tiles stitched, against the canvas replay; when a tile joined
    after it (a slave that took long to start under load), the last frame all four showed."""
    shown = []
    for t in TILES:
        d = os.path.join(out, t, program_dir)
        check(os.path.isdir(d), f"missing {d}")
        shown.append({int(f[6:12]) for f in os.listdir(d) if f.startswith("frame-") and f.endswith(".png")})
    common = set.intersection(*shown)
    check(common, f"the four tiles of {program_dir} showed no frame in common")
    if frame not in common:
        late = max(common)
        print(f"frame {frame} is not on every tile (first frames shown: {[min(s) for s in shown]}): frame {late}")
        frame = late
    tiles = [os.path.join(out, t, program_dir, f"frame-{frame:06d}.png") for t in TILES]
    stitched = os.path.join(out, f"mosaic-{os.path.basename(capture)}.png")
    check(run([GLCAST, "image", "mosaic", "2x2", stitched] + tiles).returncode == 0, "mosaic failed")
    ref = os.path.join(out, "canvas-" + os.path.basename(capture))
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = run([GLCAST, "replay", capture, "--canvas", "1280x960", "--tile-rect", "0,0,1280,960", "--frames",
             f"{frame}:{frame}", "--out", ref], env=env)
    check(r.returncode == 0, f"canvas replay failed: {r.stderr[-2000:]}")
    differing, worst = compare(stitched, os.path.join(ref, f"frame-{frame:06d}.png"))
    check(differing <= TOLERANCE * 1280 * 960, f"the stitched tiles differ from the canvas in {differing} pixels")
    return differing, worst


def barrier_held(logs, out, run_log):
    """Frames replayed while a tile catches up (it joined late) are not held; every frame each of
    the four tiles presented through the barrier is. On failure, what each tile presented and
    said, and what run said."""
    times, seen = {}, {}
    for tile in sorted(os.listdir(logs)):
        presents = [line.split() for line in open(os.path.join(logs, tile))]
        held = [int(f) for f, _, h in presents if h == "1"]
        seen[tile] = (f"{len(presents)} presents, {len(held)} held"
                      + (f" (frames {held[0]}..{held[-1]})" if held else "")
                      + (f", first present frame {presents[0][0]}" if presents else ""))
        for frame, t, h in presents:
            if h == "1":
                times.setdefault(int(frame), []).append(float(t))
    frames = sorted(f for f, ts in times.items() if len(ts) == 4)
    if len(frames) < 30:
        tails = "".join(f"\n--- {t}.log:\n" + open(os.path.join(out, t + ".log"), errors="replace").read()[-1500:]
                        for t in TILES if os.path.exists(os.path.join(out, t + ".log")))
        check(False, f"only {len(frames)} frames presented by all four tiles; per tile: {seen}\n--- run:\n"
                     f"{run_log[-2500:]}{tails}")
    for a, b in zip(frames, frames[1:]):
        check(max(times[a]) < min(times[b]), f"a tile presented frame {b} before every tile had presented frame {a}")
    return len(frames)


def wait_until(what, predicate, timeout):
    end = time.monotonic() + timeout
    while not predicate():
        check(time.monotonic() < end, f"{what} within {timeout} s")
        time.sleep(0.1)


def case_tcp():
    out = os.path.join(OUT, "tcp")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "presents"))
    if not UNIT or not os.path.exists("/lib/systemd/systemd"):
        print("SKIP: tcp needs systemd (/lib/systemd/systemd) and the test unit")
        return
    with machines("tcp", "t") as ns:
        if not ns:
            return
        port = 6200
        k = keys(out)
        config = netns.wall_config(out, "wall-machines", ADDRESS["master"], port, TILES, (640, 480))
        supervisors = [Supervisor(out, m, ns[m], [t for t, (tm, _, _) in TILES.items() if tm == m], config, k[m])
                       for m in ("dispa", "dispb")]
        try:
            end = time.monotonic() + 30
            while not all(s.slave_pid(t) for s in supervisors for t in TILES if TILES[t][0] == s.machine):
                if any(s.proc.poll() is not None for s in supervisors) or time.monotonic() > end:
                    log = open(os.path.join(supervisors[0].dir, "systemd.log")).read()[-1500:]
                    print(f"SKIP: systemd does not run in a namespace here: {log}")
                    return
                time.sleep(0.2)
            with Xvfb():
                tcp_wall(out, ns, config, k, port, supervisors)
        finally:
            for s in supervisors:
                s.stop()


def tcp_wall(out, ns, config, k, port, supervisors):
    # Refused before anything starts: an endpoint on the network without keys.
    r = run(["ip", "netns", "exec", ns["master"], GLCAST, "run", "--config", config, "--machine", "master", "--",
             "true"], env={k_: v for k_, v in os.environ.items() if k_ != "GLCAST_KEYS"})
    check(r.returncode == 1 and "without keys" in r.stderr, f"an endpoint without keys was not refused: {r.stderr}")

    # Program 1: the wall, the barrier across machines, the status view.
    # 1,200 frames: the stream's socket lives in the program, so slaves subscribe only once it
    # runs; a program of 300 frames (5 s) once ended here before any slave's subscription was in,
    # and a slave that never saw a live message never joins (docs/wall.md).
    wall, capture1 = program_run(ns, config, k["master"], out, "program1", 1200, ["glxgears"])
    rc = wall.wait(timeout=300)
    log1 = wall.stderr.read()
    check(rc == 0, f"glcast run failed: {log1[-3000:]}")
    check("4 of 4 tiles on other machines are there" in log1, f"run did not count the remote tiles: {log1[-2000:]}")
    frames_held = barrier_held(os.path.join(out, "presents"), out, log1)
    differing, worst = stitched_against_canvas(out, capture1, "program-0001", 280)
    seen = statuses(os.path.join(out, "program1-status.jsonl"))
    live = [s for s in seen if all(t["state"] == "live" for t in s["tiles"])]
    check(live, f"the status never showed all four tiles live: {seen[-3:]}")
    machines_seen = {t["tile"]: t["machine"] for t in live[-1]["tiles"]}
    check(machines_seen == {t: m for t, (m, _, _) in TILES.items()}, f"status machines: {machines_seen}")
    print(f"tcp: program 1 on four tiles of two display machines (CURVE): frame 280 stitched differs from the canvas "
          f"in {differing} pixels (max {worst}); the barrier held over {frames_held} frames; status: "
          f"{json.dumps(live[-1]['tiles'][0])}")

    # Program 2 on the same slaves: they stayed up. Kill one meanwhile: systemd restarts it.
    wall, capture2 = program_run(ns, config, k["master"], out, "program2", 1500,
                                 ["/usr/libexec/xscreensaver/gears", "-window", "-geometry", "320x240"])
    status2 = os.path.join(out, "program2-status.jsonl")

    def tile_state(tile):
        s = statuses(status2)
        return next((t for t in s[-1]["tiles"] if t["tile"] == tile), {}) if s else {}

    def joins():
        path = os.path.join(out, "top-left.log")
        return open(path).read().count("joined at frame") if os.path.exists(path) else 0

    # The first reports program 2's run gets can be program 1's last frames (the slaves replay
    # what they hold after its run ended): top-left is in program 2 once its log says it joined.
    wait_until("top-left live in program 2", lambda: joins() >= 2 and tile_state("top-left").get("state") == "live" and
               tile_state("top-left").get("frame", 0) > 100, 120)
    victim = supervisors[0].slave_pid("top-left")
    check(victim, "no slave process for top-left")
    # The restarted slave counts programs from 1 again: its frames go to top-left/program-0001,
    # emptied here so that they are the restarted slave's alone.
    shutil.rmtree(os.path.join(out, "top-left"), ignore_errors=True)
    killed_at = time.monotonic()
    os.kill(victim, signal.SIGKILL)
    wait_until("top-left restarted by systemd", lambda: supervisors[0].slave_pid("top-left") not in (None, victim), 30)
    restarted = time.monotonic() - killed_at
    frame_at_kill = tile_state("top-left").get("frame", 0)
    # Back once it joined again; given as long as program 2 runs (a loaded machine starts slowly).
    def back_or_ended():
        check(joins() >= 3 or wall.poll() is None, "program 2 ended before top-left was back")
        return joins() >= 3

    wait_until("top-left back", back_or_ended, 300)
    back = time.monotonic() - killed_at
    joined = re.findall(r"joined at frame (\d+)", open(os.path.join(out, "top-left.log")).read())[-1]

    # Refusals while program 2 runs: a key the master does not know, a subscriber without keys.
    stranger = run(["ip", "netns", "exec", ns["dispb"], GLCAST, "slave", "--config", config, "--tile", "bottom-left",
                    "--keys", k["stranger"], "--wait", "10", "--quiet"], timeout=60)
    check(stranger.returncode == 1 and "refused this machine's key" in stranger.stderr,
          f"a slave with an unknown key was not refused: {stranger.stderr[-1500:]}")
    plain = run(["ip", "netns", "exec", ns["dispb"], GLCAST, "slave", "--insecure", "--connect",
                 f"tcp://{ADDRESS['master']}:{port}", "--wait", "5", "--quiet"], timeout=60,
                env={k_: v for k_, v in os.environ.items() if k_ != "GLCAST_KEYS"})
    check(plain.returncode == 1 and "no message" in plain.stderr,
          f"a subscriber without keys got the stream: {plain.stderr[-1500:]}")

    rc = wall.wait(timeout=600)
    log2 = wall.stderr.read()
    check(rc == 0, f"glcast run (program 2) failed: {log2[-3000:]}")
    check("refused" in log2, f"the master did not say it refused the stranger: {log2[-2000:]}")
    frames = sorted(int(f[6:12]) for f in os.listdir(os.path.join(out, "top-left", "program-0001"))
                    if f.endswith(".png") and int(f[6:12]) > int(joined))
    check(len(frames) > 50, f"the restarted top-left showed only {len(frames)} frames")
    ref = tile_reference(capture2, config, "top-left", (frames[0], frames[-1]), out)
    worst_diff = 0
    for f in frames[:: max(1, len(frames) // 20)]:
        name = f"frame-{f:06d}.png"
        differing, _ = compare(os.path.join(out, "top-left", "program-0001", name), os.path.join(ref, name))
        worst_diff = max(worst_diff, differing)
    check(worst_diff <= TOLERANCE * 640 * 480, f"the restarted tile differs from the program's in {worst_diff} pixels")
    for t in ("top-right", "bottom-left", "bottom-right"):
        check(os.path.isdir(os.path.join(out, t, "program-0002")), f"{t} did not show program 2 (it did not stay up)")
    print(f"tcp: program 2 on the same slaves; top-left killed at its frame {frame_at_kill}: restarted by systemd in "
          f"{restarted:.2f} s, back (joined at frame {joined} from the keeper) {back:.2f} s after the kill; its "
          f"{len(frames)} frames since equal the program's (worst {worst_diff} pixels); a stranger's key and a "
          f"subscriber without keys refused")


def case_epgm():
    out = os.path.join(OUT, "epgm")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.join(out, "presents"))
    with machines("epgm", "e") as ns:
        if not ns:
            return
        port = 6300
        k = keys(out)
        config = netns.wall_config(out, "wall-machines", ADDRESS["master"], port, TILES, (640, 480))
        group = f"239.192.9.9:{port}"
        slaves = []
        for tile, (machine, _, _) in TILES.items():
            env = dict(os.environ, GLCAST_TEST_PRESENT_LOG=os.path.join(out, "presents", tile))
            slaves.append(subprocess.Popen(
                ["ip", "netns", "exec", ns[machine], GLCAST, "slave", "--service", "--insecure", "--keys", k[machine],
                 "--connect", f"epgm://{ADDRESS[machine]};{group}", "--config", config, "--tile", tile,
                 "--machine", machine, "--backend", "egl", "--out", os.path.join(out, tile), "--quiet"],
                env=env, stdout=subprocess.DEVNULL, stderr=open(os.path.join(out, tile + ".log"), "w")))
        try:
            with Xvfb():
                capture = os.path.join(out, "program.glcs")
                env = dict(os.environ, GLCAST_CAPTURE=capture)
                r = run(["ip", "netns", "exec", ns["master"], GLCAST, "run", "--config", config, "--machine", "master",
                         "--keys", k["master"], "--insecure", "--endpoint", f"epgm://{ADDRESS['master']};{group}",
                         "--backend", "egl", "--frames", "1200", "--wait-tiles", "120", "--", "glxgears"], env=env,
                        timeout=400)
                check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
                check("4 of 4 tiles on other machines are there" in r.stderr,
                      f"run started the program without every tile: {r.stderr[-2000:]}")
                frames_held = barrier_held(os.path.join(out, "presents"), out, r.stderr)
                differing, worst = stitched_against_canvas(out, capture, "program-0001", 280)
        finally:
            for s in slaves:
                s.kill()
                s.wait()
        print(f"epgm: four tiles on two display machines by multicast (journal, keeper, barrier with CURVE): frame 280 "
              f"stitched differs from the canvas in {differing} pixels (max {worst}); the barrier held over "
              f"{frames_held} frames")


if __name__ == "__main__":
    globals()["case_" + sys.argv[1]]()
