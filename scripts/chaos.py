#!/usr/bin/python3
"""chaos.py: a wall on a bad day (docs/reliability.md). scripts/chaos.sh MINUTES runs it.

A wall of four machines made here as network namespaces on a bridge: the master (the program,
`glcast run`, its journal and keeper), two display machines with two tiles each (`glcast slave
--service`, started again a second after they end, as systemd's Restart=always does), and a
stranger; CURVE keys made by `glcast keygen`. A paced program (xscreensaver's gears, about 60
frames a second) runs for MINUTES, once calm and once under faults at random (seeded) times:

- a slave killed (SIGKILL) or frozen (SIGSTOP, SIGCONT 1-6 s later);
- the keeper killed (glcast run starts it again);
- a bad link to a display machine: packet loss (iptables' random drop) and a slow link (a token
  bucket: 2-20 Mbit/s, queueing delay up to 200 ms), 5-20 s;
- the stranger flooding every socket of the master (scripts/chaos_stranger.py, 5-15 s);
- the disk under a `glcast record` of the stream filling up (once).

Recorded: the program's frame rate and peak RSS, each tile's lag, recoveries and restarts.
Checked at the end (exit 1 when one breaks):
- the program keeps at least 90% of its calm frame rate and its peak RSS within 64 MiB of the
  calm run's;
- `glcast run` exits 0 and ends within 150 s of the program;
- each tile's last frames equal a replay of that tile from the program's capture, pixel for pixel;
- the recording on the full disk ends non-zero, saying so, and its file replays to its last whole
  message.

    scripts/chaos.sh MINUTES [--calm-minutes M] [--seed N] [--faults LIST] [--out DIR] [--build DIR]

Needs root (namespaces, tc, a tmpfs), Xvfb and /usr/libexec/xscreensaver/gears.
"""
import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "e2e"))
import netns  # noqa: E402
from xvfb import Xvfb  # noqa: E402

ADDRESS = {"master": "10.215.0.1", "dispa": "10.215.0.2", "dispb": "10.215.0.3", "stranger": "10.215.0.4"}
TILES = {"top-left": ("dispa", 0, 0), "top-right": ("dispa", 320, 0),
         "bottom-left": ("dispb", 0, 240), "bottom-right": ("dispb", 320, 240)}
PORT = 6400
# The machines share this one's cores: the master's processes (the program, glcast run, its
# keeper) get the first, the others (display machines, recorder, stranger) the rest, so that a
# display machine's work after a fault does not take the program's CPU as it could not on a wall.
CORES = os.cpu_count() or 1
MASTER_CPUS = ["taskset", "-c", "0"] if CORES > 1 else []
OTHER_CPUS = ["taskset", "-c", f"1-{CORES - 1}"] if CORES > 1 else []
PROGRAM = ["/usr/libexec/xscreensaver/gears", "-window", "-geometry", "640x480", "-delay", "12000"]
FPS_GUESS = 50  # to turn the calm run's minutes into frames; the chaos run takes the calm rate


def log_line(out, text):
    print(text, flush=True)
    with open(os.path.join(out, "events.log"), "a") as f:
        f.write(text + "\n")


def rss_kib(pid):
    try:
        for line in open(f"/proc/{pid}/status"):
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        pass
    return 0


def alive(pid):
    """Running, not a zombie waiting for its parent."""
    try:
        return open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def processes_of(executable):
    """The processes whose argv[0] is `executable` (not those that only name it among their
    arguments, as glcast run does)."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                if open(f"/proc/{entry}/cmdline", "rb").read().split(b"\0")[0] == executable.encode():
                    found.append(int(entry))
            except OSError:
                pass
    return found


def pids_matching(pattern):
    r = subprocess.run(["pgrep", "-f", pattern], capture_output=True, text=True)
    return [int(p) for p in r.stdout.split()]


ALL_SLAVES = []  # stopped on any way out of main(): none is left running behind the script


class Slave:
    """One tile's `glcast slave --service` in its display machine's namespace, started again a
    second after it ends, as systemd's Restart=always with RestartSec=1 does."""

    def __init__(self, glcast, ns, tile, machine, config, key_dir, out, first_written, epoch):
        self.args = ["ip", "netns", "exec", ns, *OTHER_CPUS, glcast, "slave", "--service", "--config", config, "--tile", tile,
                     "--keys", key_dir, "--machine", machine, "--backend", "egl", "--quiet",
                     "--frames", f"{first_written}:"]
        self.tile, self.out, self.lives, self.proc, self.epoch = tile, out, 0, None, epoch
        self.joins = []  # seconds from each life's start to its join
        self.ended_program = 0  # the life that saw the program end
        self.log = open(os.path.join(out, tile + ".log"), "a")
        self.running = True
        self.lock = threading.Lock()
        self.thread = threading.Thread(target=self.supervise, daemon=True)
        self.thread.start()
        ALL_SLAVES.append(self)

    def supervise(self):
        while self.running:
            with self.lock:
                if not self.running:
                    return
                self.lives += 1
                folder = os.path.join(self.out, self.tile, f"life-{self.lives}")
                self.proc = subprocess.Popen(self.args + ["--out", folder], stdout=subprocess.DEVNULL,
                                             stderr=subprocess.PIPE, text=True, errors="replace")
                started = time.monotonic()
                self.say(f"life {self.lives} starts")
            for line in self.proc.stderr:  # each line stamped with the run's clock
                line = line.strip("\r\n")
                if line.strip():
                    self.say(line)
                if "joined at frame" in line:
                    self.joins.append(time.monotonic() - started)
                if "the program ended" in line or "the program has ended" in line:
                    self.ended_program = self.lives
            self.proc.wait()
            self.say(f"life {self.lives} ends: exit {self.proc.returncode}")
            time.sleep(1)

    def say(self, text):
        self.log.write(f"{time.monotonic() - self.epoch:8.2f} {text}\n")
        self.log.flush()

    def finished(self):
        with self.lock:
            return self.ended_program == self.lives

    def pid(self):
        """The slave itself (ip netns exec execs it: the same process)."""
        with self.lock:
            return self.proc.pid if self.proc and self.proc.poll() is None else None

    def stop(self):
        with self.lock:
            self.running = False
            if self.proc and self.proc.poll() is None:
                self.proc.send_signal(signal.SIGCONT)
                self.proc.terminate()
        if self.proc is None:
            return
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.log.close()


class Faults:
    """The faults of one run, each at a random time (seeded), one at a time."""

    KINDS = {"kill": 20, "freeze": 25, "keeper": 10, "link": 15, "stranger": 15, "disk": 5}

    def __init__(self, rng, out, ns, slaves, disk, kinds):
        self.rng, self.out, self.ns, self.slaves, self.disk, self.kinds = rng, out, ns, slaves, disk, kinds
        self.frozen = {}  # pid: when to SIGCONT
        self.undo = []  # (when, function, description)
        self.counts = {}
        self.disk_filled = False

    def count(self, what):
        self.counts[what] = self.counts.get(what, 0) + 1

    def tick(self, now, started, minutes):
        for pid, until in list(self.frozen.items()):
            if now >= until:
                try:
                    os.kill(pid, signal.SIGCONT)
                except OSError:
                    pass
                del self.frozen[pid]
        for item in list(self.undo):
            if now >= item[0]:
                item[1]()
                self.undo.remove(item)
                log_line(self.out, f"{now - started:7.1f} s  {item[2]}")

    def strike(self, now, started, minutes):
        t = f"{now - started:7.1f} s "
        kinds = [k for k in self.kinds if k != "disk" or not self.disk_filled]
        kind = self.rng.choices(kinds, weights=[self.KINDS[k] for k in kinds])[0]
        if kind in ("kill", "freeze"):
            slave = self.rng.choice(self.slaves)
            pid = slave.pid()
            if not pid or pid in self.frozen:
                return
            if kind == "kill":
                os.kill(pid, signal.SIGKILL)
                log_line(self.out, f"{t} SIGKILL slave {slave.tile}")
            else:
                seconds = self.rng.uniform(1, 6)
                os.kill(pid, signal.SIGSTOP)
                self.frozen[pid] = now + seconds
                log_line(self.out, f"{t} SIGSTOP slave {slave.tile} for {seconds:.1f} s")
        elif kind == "keeper":
            pids = pids_matching(f"glcast keeper --connect .* --bind tcp://\\*:{PORT + 2}")
            if not pids:
                pids = pids_matching(f" keeper --connect .*{PORT + 2}")
            if not pids:
                return
            os.kill(pids[0], signal.SIGKILL)
            log_line(self.out, f"{t} SIGKILL keeper")
        elif kind == "link":
            if any("link" in u[2] for u in self.undo):
                return
            # tc netem is not in every kernel (not in this one): loss is iptables' random drop
            # in the display machine, the slow link a token bucket on what the bridge sends it
            # (queueing delay up to 200 ms, then drops).
            machine = self.rng.choice(["dispa", "dispb"])
            n, link = self.ns[machine]
            loss, mbit = self.rng.uniform(1, 10), self.rng.choice([2, 5, 10, 20])
            seconds = self.rng.uniform(5, 20)
            drop = ["-m", "statistic", "--mode", "random", "--probability", f"{loss / 100:.3f}", "-j", "DROP"]
            subprocess.run(["ip", "netns", "exec", n, "iptables", "-A", "INPUT"] + drop, check=True)
            subprocess.run(["tc", "qdisc", "add", "dev", link, "root", "tbf", "rate", f"{mbit}mbit", "burst", "32kbit",
                            "latency", "200ms"], check=True)

            def heal():
                subprocess.run(["ip", "netns", "exec", n, "iptables", "-D", "INPUT"] + drop)
                subprocess.run(["tc", "qdisc", "del", "dev", link, "root"])
            log_line(self.out, f"{t} a bad link to {machine}: {loss:.1f}% loss, {mbit} Mbit/s for {seconds:.1f} s")
            self.undo.append((now + seconds, heal, f"the link to {machine} is good again"))
        elif kind == "stranger":
            if any("stranger" in u[2] for u in self.undo):
                return
            seconds = self.rng.uniform(5, 15)
            log = open(os.path.join(self.out, "stranger.log"), "a")
            proc = subprocess.Popen(["ip", "netns", "exec", self.ns["stranger"][0], *OTHER_CPUS, "/usr/bin/python3",
                                     os.path.join(HERE, "chaos_stranger.py"), ADDRESS["master"], str(PORT),
                                     f"{seconds:.1f}"], stdout=log, stderr=subprocess.STDOUT)
            log_line(self.out, f"{t} a stranger floods every socket of the master for {seconds:.1f} s")
            self.undo.append((now + seconds + 5, lambda: proc.wait(), "the stranger is gone"))
        elif kind == "disk":
            self.disk_filled = True
            filler = os.path.join(self.disk, "filler")
            subprocess.run(["dd", "if=/dev/zero", f"of={filler}", "bs=1M"], capture_output=True)
            log_line(self.out, f"{t} the recording's disk is full")
        else:
            return
        self.count(kind)

    def release(self):
        for pid in self.frozen:
            try:
                os.kill(pid, signal.SIGCONT)
            except OSError:
                pass
        for item in self.undo:
            item[1]()
        self.undo.clear()


def statuses(path):
    out = []
    if os.path.exists(path):
        for line in open(path):
            try:
                out.append(json.loads(line))
            except ValueError:
                pass
    return out


def run_wall(glcast, out, ns, keys, frames, chaos, seed, minutes, kinds):
    """One program on the wall, with faults when `chaos`. Returns what was measured."""
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    rng = random.Random(seed)
    config = netns.wall_config(out, "chaos", ADDRESS["master"], PORT, TILES, (320, 240))
    first_written = max(0, frames - 30)
    epoch = time.monotonic()
    slaves = [Slave(glcast, ns[m][0], t, m, config, keys[m], out, first_written, epoch)
              for t, (m, _, _) in TILES.items()]
    # The recording's disk: a 48 MiB tmpfs of its own, filled up once under chaos.
    disk = os.path.join(out, "disk")
    os.makedirs(disk)
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=48m", "tmpfs", disk], check=True)
    capture = os.path.join(out, "capture.glcs")
    status = os.path.join(out, "status.jsonl")
    swaps = os.path.join(out, "swaps.log")  # the shim's line per swap: frame, time
    env = dict(os.environ, GLCAST_CAPTURE=capture, GLCAST_TEST_SWAP_LOG=swaps)
    run = subprocess.Popen(["ip", "netns", "exec", ns["master"][0], *MASTER_CPUS, glcast, "run", "--config", config, "--machine",
                            "master", "--keys", keys["master"], "--backend", "egl", "--frames", str(frames),
                            "--status-json", status, "--wait-tiles", "120", "--"] + PROGRAM,
                           env=env, stdout=subprocess.DEVNULL, stderr=open(os.path.join(out, "run.log"), "w"),
                           start_new_session=True)
    faults = Faults(rng, out, ns, slaves, disk, kinds)
    record = None
    program_pid, program_start, program_end, peak = None, None, None, 0
    rss_series = []
    started = epoch
    next_fault = None
    try:
        while run.poll() is None and time.monotonic() - started < minutes * 60 * 3 + 600:
            now = time.monotonic()
            if program_pid is None:
                found = processes_of(PROGRAM[0])
                if found:
                    program_pid, program_start = found[0], now
                    next_fault = now + rng.uniform(3, 8)
            elif not alive(program_pid):
                program_end = now
                break
            else:
                kib = rss_kib(program_pid)
                peak = max(peak, kib)
                if not rss_series or now - rss_series[-1][0] >= 10:
                    rss_series.append((now, kib))
                if record is None and now - program_start > 5:
                    record = subprocess.Popen(
                        ["ip", "netns", "exec", ns["recorder"][0], *OTHER_CPUS, glcast, "record",
                         "--connect", f"tcp://{ADDRESS['master']}:{PORT}", "--journal",
                         f"tcp://{ADDRESS['master']}:{PORT + 1}", "--keeper", f"tcp://{ADDRESS['master']}:{PORT + 2}",
                         "-o", os.path.join(disk, "recording.glcs"), "--wait", "60"],
                        env=dict(os.environ, GLCAST_KEYS=keys["recorder"]),
                        stdout=subprocess.DEVNULL, stderr=open(os.path.join(out, "record.log"), "w"))
                if chaos:
                    faults.tick(now, started, minutes)
                    # No new fault in the program's last 20 s: a tile killed then could not be
                    # back for the last frame, which is what the run compares.
                    closing = last_swap(swaps) >= frames - 20 * FPS_GUESS
                    if now >= next_fault and record is not None and not closing:
                        faults.strike(now, started, minutes)
                        next_fault = now + rng.uniform(3, 8)
            time.sleep(0.2)
    finally:
        faults.release()
    # The program's last swap (CLOCK_MONOTONIC, as time.monotonic()): run must end after it.
    last = swap_times(swaps)
    ended = last[-1] if last else (program_end or time.monotonic())
    try:
        rc = run.wait(timeout=150)
    except subprocess.TimeoutExpired:
        os.killpg(run.pid, signal.SIGKILL)
        rc = None
    run_end = time.monotonic() - ended
    record_rc = None
    if record:
        try:
            record_rc = record.wait(timeout=60)
        except subprocess.TimeoutExpired:
            record.kill()
            record_rc = "hung"
    # Each tile finishes the program (a frozen one was just let go): its slave says it ended.
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not all(s.finished() for s in slaves):
        time.sleep(0.2)
    for s in slaves:
        s.stop()
    seen = statuses(status)
    tiles = {}
    for line in seen:
        for t in line.get("tiles", []):
            k = tiles.setdefault(t["tile"], {"max_lag": 0, "recoveries": 0, "silent_s": 0})
            k["max_lag"] = max(k["max_lag"], t.get("lag", 0) or 0)
            k["recoveries"] = max(k["recoveries"], t.get("recoveries", 0) or 0)
            k["silent_s"] += t["state"] != "live"
    for s in slaves:
        tiles.setdefault(s.tile, {})["lives"] = s.lives
        tiles[s.tile]["join_s"] = [round(j, 1) for j in s.joins]
    seconds = (program_end or ended) - (program_start or started)
    fps, worst = swap_rates(swaps)
    return {"out": out, "config": config, "capture": capture, "run_rc": rc, "run_end_s": run_end,
            "program_seconds": seconds, "fps": fps, "worst_10s_fps": worst, "peak_rss_kib": peak,
            "rss_series": [(round(t - (program_start or started)), k) for t, k in rss_series],
            "tiles": tiles, "faults": faults.counts, "record_rc": record_rc, "disk": disk,
            "disk_filled": faults.disk_filled, "slaves": slaves}


def last_swap(path):
    try:
        with open(path, "rb") as f:
            f.seek(0, 2)
            f.seek(max(0, f.tell() - 80))
            lines = [l for l in f.read().split(b"\n")[:-1] if l.strip()]
        return int(lines[-1].split()[0]) if lines else -1
    except (OSError, ValueError, IndexError):
        return -1


def swap_times(path):
    times = []
    if os.path.exists(path):
        for line in open(path):
            parts = line.split()
            if len(parts) == 2:
                times.append(float(parts[1]))
    return times


def swap_rates(path):
    """The program's frame rate from its first swap to its last (not counting its wait for the
    wall at its first GL call), and its slowest 10 s."""
    times = swap_times(path)
    if len(times) < 2 or times[-1] <= times[0]:
        return 0.0, 0.0
    worst, j = float("inf"), 0
    for i, t in enumerate(times):
        while j < len(times) and times[j] < t + 10:
            j += 1
        if j == len(times):
            break
        worst = min(worst, (j - i) / 10)
    return (len(times) - 1) / (times[-1] - times[0]), (0.0 if worst == float("inf") else worst)


def replay_tile(glcast, capture, config, tile, frame, out):
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = subprocess.run([glcast, "replay", capture, "--config", config, "--tile", tile, "--frames", f"{frame}:{frame}",
                        "--out", out, "--backend", "egl"], capture_output=True, text=True, env=env, timeout=1800)
    return r.returncode == 0, os.path.join(out, f"frame-{frame:06d}.png"), r.stderr[-800:]


def compare(glcast, a, b):
    r = subprocess.run([glcast, "image", "compare", a, b], capture_output=True, text=True)
    m = re.search(r"(\d+) pixels differ", r.stdout)
    return int(m.group(1)) if m else None


def check_tiles(glcast, result, frames):
    """Each tile's last frame against a replay of that tile from the capture: from a trim of its
    last frames (a snapshot, then those frames; docs/keeper.md), which equals the whole capture's
    replay pixel for pixel and does not replay an hour of frames once per tile."""
    failures, shown = [], {}
    last = frames - 1
    first = max(0, last - 5)
    trimmed = os.path.join(result["out"], "last-frames.glcs")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = subprocess.run([glcast, "trim", result["capture"], "--frames", f"{first}:{last}", "-o", trimmed],
                       capture_output=True, text=True, env=env, timeout=3600)
    if r.returncode != 0:
        return [f"the capture cannot be trimmed to its last frames: {r.stderr[-800:]}"], shown
    for s in result["slaves"]:
        lives = sorted((os.path.join(result["out"], s.tile, d) for d in os.listdir(os.path.join(result["out"], s.tile))),
                       key=lambda d: int(d.rsplit("-", 1)[1]))
        pngs = [os.path.join(root, f) for d in lives for root, _, fs in os.walk(d) for f in fs
                if f == f"frame-{last:06d}.png"]
        if not pngs:
            failures.append(f"tile {s.tile} never showed the program's last frame {last}")
            continue
        ok, reference, why = replay_tile(glcast, trimmed, result["config"], s.tile, last - first,
                                         os.path.join(result["out"], "reference", s.tile))
        if not ok:
            failures.append(f"the capture does not replay tile {s.tile}: {why}")
            continue
        differing = compare(glcast, pngs[-1], reference)
        shown[s.tile] = differing
        if differing != 0:
            failures.append(f"tile {s.tile}'s last frame differs from the capture's in {differing} pixels")
    return failures, shown


def check_recording(glcast, result):
    """Under chaos the recording's disk filled: it must end non-zero, saying so, and its file
    must replay to its last whole message."""
    if not result["disk_filled"]:
        if result["record_rc"] != 0:
            return [f"glcast record ended with {result['record_rc']} on a good disk"], ""
        return [], "the recording on a good disk ended 0"
    log = open(os.path.join(result["out"], "record.log")).read()
    failures = []
    if result["record_rc"] in (0, None, "hung"):
        failures.append(f"glcast record on a full disk ended with {result['record_rc']}: {log[-500:]}")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = subprocess.run([glcast, "replay", os.path.join(result["disk"], "recording.glcs"), "--backend", "egl"],
                       capture_output=True, text=True, env=env, timeout=1800)
    said = (r.stdout + r.stderr).strip().splitlines()
    if r.returncode == 0 or not re.search(r"the capture was cut after message \d+, frame \d+", r.stderr):
        failures.append(f"the recording on the full disk does not replay to its cut, saying so: {' | '.join(said[-3:])}")
    cut = re.search(r"cut after message \d+, frame \d+", r.stderr)
    return failures, (f"record exit {result['record_rc']}; its file replays to the {cut.group(0) if cut else '?'}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("minutes", type=float)
    ap.add_argument("--calm-minutes", type=float, default=None,
                    help="each of the runs without faults, before and after (default: MINUTES)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default="/tmp/glcast-chaos")
    ap.add_argument("--faults", default=",".join(Faults.KINDS), help="the kinds of fault (default: all)")
    a = ap.parse_args()
    kinds = a.faults.split(",")
    if not kinds or any(k not in Faults.KINDS for k in kinds):
        ap.error(f"--faults: a comma-separated list of {', '.join(Faults.KINDS)}")
    glcast = os.path.join(a.build, "glcast")
    calm_minutes = a.minutes if a.calm_minutes is None else a.calm_minutes
    if not os.path.exists(PROGRAM[0]):
        print(f"chaos: {PROGRAM[0]} is missing (apt-get install xscreensaver-gl)")
        return 2
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    failures, results = [], {}
    with netns.bridged(ADDRESS | {"recorder": "10.215.0.5"}, "x", "the chaos run") as ns:
        if not ns:
            return 2
        keys = netns.wall_keys(glcast, a.out, ("dispa", "dispb", "recorder"))
        with Xvfb() as x:
            # The program's X server belongs to the master machine: each of the program's swaps
            # waits on it, and left to any core it competed with the display machines' slaves.
            if MASTER_CPUS and x.proc:
                subprocess.run(["taskset", "-a", "-p", "-c", MASTER_CPUS[-1], str(x.proc.pid)], capture_output=True)
            fps = FPS_GUESS
            # Calm before and after: the first run of a session has been the slower one here
            # (the wall's first start), and the chaos run is compared with both.
            for name, minutes, chaos in (("calm", calm_minutes, False), ("chaos", a.minutes, True),
                                         ("calm-after", calm_minutes, False)):
                # MINUTES of the program at the calm run's frame rate
                frames = int(minutes * 60 * fps)
                log_line(a.out, f"{name}: {frames} frames of gears (about {minutes:g} minutes)")
                try:
                    r = run_wall(glcast, os.path.join(a.out, name), ns, keys, frames, chaos, a.seed, minutes, kinds)
                    rec_failures, rec = check_recording(glcast, r)
                finally:
                    subprocess.run(["umount", os.path.join(a.out, name, "disk")], capture_output=True)
                results[name] = r
                fps = r["fps"] or fps
                if r["run_rc"] != 0:
                    failures.append(f"{name}: glcast run ended with {r['run_rc']}: "
                                    f"{open(os.path.join(r['out'], 'run.log')).read()[-1500:]}")
                if r["run_end_s"] > 150:
                    failures.append(f"{name}: glcast run ended {r['run_end_s']:.0f} s after the program")
                tile_failures, shown = check_tiles(glcast, r, frames)
                failures += [f"{name}: {f}" for f in tile_failures]
                failures += [f"{name}: {f}" for f in rec_failures]
                r["last_frame_differs"], r["recording"] = shown, rec
                log_line(a.out, f"{name}: {r['program_seconds']:.1f} s, {r['fps']:.2f} frames/s (slowest 10 s: "
                                f"{r['worst_10s_fps']:.1f}), program peak RSS "
                                f"{r['peak_rss_kib'] / 1024:.1f} MiB; run exit {r['run_rc']}, "
                                f"{r['run_end_s']:.1f} s after the program; faults {r['faults']}; tiles "
                                f"{json.dumps(r['tiles'])}; last frame differs {shown}; {rec}")
    wild = results["chaos"]
    calm = {"fps": max(results["calm"]["fps"], results["calm-after"]["fps"]),
            "peak_rss_kib": min(results["calm"]["peak_rss_kib"], results["calm-after"]["peak_rss_kib"])}
    # against the better calm run on each count
    ratio = wild["fps"] / calm["fps"] if calm["fps"] else 0
    growth = (wild["peak_rss_kib"] - calm["peak_rss_kib"]) / 1024
    if ratio < 0.9:
        failures.append(f"the program's frame rate under chaos is {ratio:.1%} of the calm run's")
    if growth > 64:
        failures.append(f"the program's peak RSS under chaos is {growth:.1f} MiB above the calm run's")
    log_line(a.out, f"chaos/calm: frame rate {ratio:.3f}, peak RSS {growth:+.1f} MiB")
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump({k: {x: y for x, y in v.items() if x != "slaves"} for k, v in results.items()}, f, indent=1)
    for f in failures:
        log_line(a.out, "FAIL: " + f)
    log_line(a.out, "chaos: " + ("every invariant held" if not failures else f"{len(failures)} invariants broken"))
    return 1 if failures else 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    finally:
        for slave in ALL_SLAVES:
            slave.stop()
