#!/usr/bin/env python3
"""piglit.py: Mesa's conformance suite (Debian's `piglit` package) under glcast's shim.

Each test of a piglit profile, or of a seeded sample spread over its groups, is run alone and
then with the shim capturing to a file (LD_PRELOAD, as `glcast capture` runs a program, with the
program's own frames kept before each swap, GLCAST_SNAPSHOT_DIR). Compared: the verdict (every
`PIGLIT:` line the test prints: its result and its subtests') and the exit status. Then the
capture must be complete (its end record: `glcast dump --summary` exits 0 and says nothing of a
cut), replay on EGL with exit 0 under `--verify` with 0 replies differing, and, where the test
swapped, replay frames equal to the test's own (`--compare`).

A test whose verdict or exit status differs is run alone twice more: if the driver gives two
answers to the same test without glcast, the test is listed with that evidence instead of as a
divergence. The same for frames: a test whose replay frames differ is captured a second time, and
if its own frames differ between the two runs the driver drew it two ways.

    scripts/piglit.py [--build build] [--profile quick] [--sample N] [--seed S] [--jobs J]
                      [--out DIR] [--doc docs/compatibility.md] [--timeout SECONDS] [--only NAME,...]

Exit status 0 when every test that ran matched (divergences proven to be the driver's own do
not count), 1 otherwise; the last line says `N passed, N failed`. Install piglit with
`apt-get install piglit` (scripts/setup.sh does). docs/compatibility.md ("Mesa's conformance
suite") holds the figures of the last long run.
"""
import argparse
import collections
import concurrent.futures
import json
import os
import random
import re
import shutil
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402

PIGLIT_DIR = "/usr/lib/x86_64-linux-gnu/piglit"
# The groups a sample is spread over (a test's name up to its first '@'); the rest form "other".
GROUPS = ["spec", "glslparsertest", "asmparsertest", "shaders", "glx", "hiz", "fast_color_clear", "security"]
VERDICT = re.compile(r"^PIGLIT: (\{.*\})\s*$", re.M)
DOC_BEGIN = "<!-- piglit table: scripts/piglit.py writes from here -->"
DOC_END = "<!-- piglit table: to here -->"


def load_tests(profile_name):
    """[(name, command)] of a piglit profile, in the profile's order."""
    sys.path.insert(0, PIGLIT_DIR)
    try:
        from framework import profile  # piglit's own: the commands exactly as `piglit run` makes them
    except ImportError:
        sys.exit(f"piglit.py: piglit is not installed ({PIGLIT_DIR} is missing): apt-get install piglit")
    return [(name, list(test.command)) for name, test in profile.load_test_profile(profile_name).itertests()]


def group_of(name):
    g = name.split("@", 1)[0]
    return g if g in GROUPS else "other"


def sample(tests, count, seed):
    """About `count` tests, spread over the groups in proportion, each group given at least a few."""
    by_group = collections.defaultdict(list)
    for t in tests:
        by_group[group_of(t[0])].append(t)
    rng = random.Random(seed)
    total = len(tests)
    chosen = []
    for g in sorted(by_group):
        members = by_group[g]
        want = min(len(members), max(3, round(count * len(members) / total)))
        chosen += rng.sample(members, want)
    rng.shuffle(chosen)
    return chosen


def verdict(stdout):
    """The test's verdict: every PIGLIT: line it printed, parsed, in order."""
    out = []
    for m in VERDICT.finditer(stdout):
        try:
            out.append(json.loads(m.group(1)))
        except ValueError:
            out.append(m.group(1))
    return out


def result_of(v):
    for item in reversed(v):
        if isinstance(item, dict) and "result" in item:
            return item["result"]
    return "none"


class Runner:
    def __init__(self, args):
        self.glcast = os.path.join(args.build, "glcast")
        self.shim = os.path.join(args.build, "libglcast.so")
        for f in (self.glcast, self.shim):
            if not os.path.exists(f):
                sys.exit(f"piglit.py: {f} is missing: build glcast first (scripts/build.sh)")
        self.out = args.out
        self.timeout = args.timeout
        self.display_env = None  # set once Xvfb runs
        # Divergences of open classes, listed with their class (name<TAB>class[,class]): counted apart.
        self.known = {}
        for line in open(args.known) if args.known else []:
            if line.strip() and not line.startswith("#"):
                name, classes = line.rstrip("\n").split("\t")
                self.known[name] = sorted(classes.split(","))

    def env(self, **extra):
        e = dict(self.display_env)
        e.update(extra)
        return e

    def headless(self):
        return {k: v for k, v in self.display_env.items() if k != "DISPLAY"}

    def alone(self, command, cwd):
        try:
            r = subprocess.run(command, capture_output=True, text=True, timeout=self.timeout, env=self.env(), cwd=cwd,
                               errors="replace")
            return r.returncode, r.stdout, r.stderr
        except subprocess.TimeoutExpired:
            return "timeout", "", ""

    def shimmed(self, command, cwd, capture, snapshots):
        env = self.env(LD_PRELOAD=self.shim, GLCAST_CAPTURE=capture, GLCAST_SNAPSHOT_DIR=snapshots)
        try:
            r = subprocess.run(command, capture_output=True, text=True, timeout=self.timeout * 2, env=env, cwd=cwd,
                               errors="replace")
            return r.returncode, r.stdout, r.stderr
        except subprocess.TimeoutExpired:
            return "timeout", "", ""

    def glcast_run(self, args, timeout=None):
        try:
            r = subprocess.run([self.glcast] + args, capture_output=True, text=True, timeout=timeout or self.timeout * 4,
                               env=self.headless(), errors="replace")
            return r.returncode, r.stdout, r.stderr
        except subprocess.TimeoutExpired:
            return "timeout", "", ""

    def run_test(self, index, name, command):
        try:
            return self.compare(index, name, command)
        except Exception as e:  # the harness's own failure is one row, not the end of the run
            return {"name": name, "group": group_of(name), "command": command, "classes": ["harness error"],
                    "error": f"{type(e).__name__}: {e}"}

    def compare(self, index, name, command):
        work = os.path.join(self.out, "tests", f"{index:05d}")
        shutil.rmtree(work, ignore_errors=True)
        os.makedirs(work)
        capture, snapshots = os.path.join(work, "capture.glcs"), os.path.join(work, "own")
        row = {"name": name, "group": group_of(name), "command": command}
        code, out, err = self.alone(command, PIGLIT_DIR)
        row["alone"] = {"exit": code, "verdict": verdict(out)}
        if code == "timeout":
            row["class"] = "slow alone"
            return row
        row["result"] = result_of(row["alone"]["verdict"])
        code2, out2, err2 = self.shimmed(command, PIGLIT_DIR, capture, snapshots)
        row["shim"] = {"exit": code2, "verdict": verdict(out2), "stderr": err2[-1500:]}
        classes = []
        if row["shim"]["verdict"] != row["alone"]["verdict"]:
            classes.append("verdict changed")
        if code2 != code:
            classes.append("exit status changed")
        if classes:  # the driver's own answer twice more, without glcast
            again = [self.alone(command, PIGLIT_DIR) for _ in range(2)]
            answers = {json.dumps([c, verdict(o)]) for c, o, _ in again} | {json.dumps([code, row["alone"]["verdict"]])}
            if len(answers) > 1:
                row["driver_differs"] = sorted(answers)
        row["captured"] = os.path.exists(capture)
        if row["captured"]:
            row["capture_bytes"] = os.path.getsize(capture)
            c, o, e = self.glcast_run(["dump", capture, "--summary"])
            row["complete"] = c == 0 and "cut" not in e
            if not row["complete"]:
                classes.append("capture cut")
                row["cut"] = e.strip()[-400:]
            frames = sorted(os.listdir(snapshots)) if os.path.isdir(snapshots) else []
            row["frames"] = len(frames)
            replay = ["replay", capture, "--backend", "egl", "--verify"] + (["--compare", snapshots] if frames else [])
            c, o, e = self.glcast_run(replay)
            row["replay"] = {"exit": c, "stdout": o[-600:], "stderr": e[-800:]}
            m = re.search(r"verified (\d+) replies: (\d+) differ", o)
            row["replies"], row["replies_differ"] = (int(m.group(1)), int(m.group(2))) if m else (0, None)
            m = re.search(r"compared (\d+) frames: (\d+) differ", o)
            row["frames_compared"], row["frames_differ"] = (int(m.group(1)), int(m.group(2))) if m else (0, 0)
            if row["replies_differ"]:
                classes.append("replies differ")
            if row["frames_differ"]:
                classes.append("frames differ")
                if self.own_frames_vary(command, work, snapshots):
                    row["driver_differs_frames"] = True
            if c != 0 and row["complete"] and not row["replies_differ"] and not row["frames_differ"]:
                classes.append("replay error")
            m = re.search(r"(\d+) unserialized on the master", o)
            row["unserialized"] = int(m.group(1)) if m else 0
        elif code2 == 0 and re.search(r"PIGLIT: \{\"result\": \"(pass|fail)\"", out2):
            row["note"] = "no GL call recorded"
        row["classes"] = classes
        row["explained"] = bool(classes) and (("driver_differs" in row and all(
            c in ("verdict changed", "exit status changed") for c in classes)) or (
            row.get("driver_differs_frames") and classes == ["frames differ"]))
        row["explained"] = row["explained"] or self.known.get(name) == sorted(classes)
        if not classes:
            shutil.rmtree(work, ignore_errors=True)  # keep only what a person has to look at
        return row

    def own_frames_vary(self, command, work, snapshots):
        """Captures the test a second time: do its own frames differ between two runs?"""
        second = os.path.join(work, "own-again")
        self.shimmed(command, PIGLIT_DIR, os.path.join(work, "again.glcs"), second)
        a = sorted(os.listdir(snapshots)) if os.path.isdir(snapshots) else []
        b = sorted(os.listdir(second)) if os.path.isdir(second) else []
        if a != b:
            return True
        for f in a:
            with open(os.path.join(snapshots, f), "rb") as x, open(os.path.join(second, f), "rb") as y:
                if x.read() != y.read():
                    return True
        return False


def table(rows):
    """Per group: tests run, verdicts and exits unchanged, captures complete, replays clean,
    replies equal, frames equal."""
    groups = collections.OrderedDict((g, collections.Counter()) for g in GROUPS + ["other"])
    for r in rows:
        c = groups[r["group"]]
        c["tests"] += 1
        if r.get("class") == "slow alone":
            c["slow"] += 1
            continue
        c["ran"] += r.get("result") != "skip"
        c["unchanged"] += not any(k in r.get("classes", []) for k in ("verdict changed", "exit status changed"))
        if r.get("captured"):
            c["captures"] += 1
            c["complete"] += bool(r.get("complete"))
            c["replays clean"] += r["replay"]["exit"] == 0
            c["replies"] += r.get("replies", 0)
            c["replies equal"] += r.get("replies_differ") == 0
            c["with frames"] += r.get("frames_compared", 0) > 0
            c["frames equal"] += r.get("frames_compared", 0) > 0 and r.get("frames_differ") == 0
    lines = ["| group | tests | ran (not skipped) | verdict and exit unchanged | captures | complete | "
             "replayed with exit 0 | replies equal (of captures) | tests with frames | frames equal |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    total = collections.Counter()
    for g, c in groups.items():
        if not c["tests"]:
            continue
        total.update(c)
        lines.append(f"| {g} | {c['tests']} | {c['ran']} | {c['unchanged']} | {c['captures']} | {c['complete']} | "
                     f"{c['replays clean']} | {c['replies equal']} | {c['with frames']} | {c['frames equal']} |")
    t = total
    lines.append(f"| **all** | {t['tests']} | {t['ran']} | {t['unchanged']} | {t['captures']} | {t['complete']} | "
                 f"{t['replays clean']} | {t['replies equal']} | {t['with frames']} | {t['frames equal']} |")
    return lines, total


def divergences(rows):
    out = []
    for r in rows:
        if r.get("classes"):
            why = "; ".join(r["classes"])
            if r.get("driver_differs"):
                why += f" — the driver alone answered {len(r['driver_differs'])} ways in 3 runs: " + \
                       " / ".join(r["driver_differs"])[:300]
            elif r.get("driver_differs_frames"):
                why += " — the test's own frames differ between two runs"
            out.append((r["name"], why, r.get("explained", False)))
        elif r.get("class") == "slow alone":
            out.append((r["name"], "slow alone (over the time limit without glcast): not compared", True))
    return out


def write_doc(path, rows, args, seconds):
    lines, total = table(rows)
    div = divergences(rows)
    text = [DOC_BEGIN, "",
            f"`scripts/piglit.py --profile {args.profile} " + (f"--sample {args.sample} --seed {args.seed}" if args.sample
                                                              else "") +
            f"` on {time.strftime('%Y-%m-%d')}: {total['tests']} tests in {seconds / 60:.0f} minutes, "
            f"{args.jobs} at a time, llvmpipe on Xvfb; captures replayed on EGL.", ""] + lines + [""]
    if div:
        text.append("Every divergence, with its class:")
        text.append("")
        text += [f"- `{n}`: {why}" + (" (the driver's own)" if explained else "") for n, why, explained in div]
    else:
        text.append("No divergence.")
    text += ["", DOC_END]
    doc = open(path).read() if os.path.exists(path) else ""
    if DOC_BEGIN in doc and DOC_END in doc:
        doc = doc[:doc.index(DOC_BEGIN)] + "\n".join(text) + doc[doc.index(DOC_END) + len(DOC_END):]
    else:
        doc += "\n" + "\n".join(text) + "\n"
    with open(path, "w") as f:
        f.write(doc)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--profile", default="quick")
    ap.add_argument("--sample", type=int, default=0, help="a seeded sample of about N tests (0: the whole profile)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", default="/tmp/glcast-piglit")
    ap.add_argument("--doc", default="", help="write the table into this Markdown file between its markers")
    ap.add_argument("--timeout", type=int, default=60, help="seconds a test may take alone")
    ap.add_argument("--only", default="", help="comma-separated test names instead of a sample")
    ap.add_argument("--known", default="", help="a list of divergences of classes still open (name<TAB>classes)")
    ap.add_argument("--minutes", type=float, default=0,
                    help="start no test after this many minutes; the table holds the tests that ran")
    args = ap.parse_args()
    args.build = os.path.abspath(args.build)
    args.out = os.path.abspath(args.out)
    tests = load_tests(args.profile)
    if args.only:
        wanted = set(args.only.split(","))
        tests = [t for t in tests if t[0] in wanted]
    elif args.sample:
        tests = sample(tests, args.sample, args.seed)
    os.makedirs(args.out, exist_ok=True)
    runner = Runner(args)
    rows = []
    lock = threading.Lock()
    started = time.time()
    results = open(os.path.join(args.out, "results.jsonl"), "w")
    with Xvfb():  # sets DISPLAY
        runner.display_env = dict(os.environ)
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            futures = [pool.submit(runner.run_test, i, name, cmd) for i, (name, cmd) in enumerate(tests)]
            for n, f in enumerate(concurrent.futures.as_completed(futures), 1):
                if f.cancelled():
                    continue
                row = f.result()
                if args.minutes and time.time() - started > args.minutes * 60:
                    for other in futures:
                        other.cancel()
                with lock:
                    rows.append(row)
                    results.write(json.dumps(row) + "\n")
                    results.flush()
                if row.get("classes"):
                    print(f"[{n}/{len(tests)}] {row['name']}: {'; '.join(row['classes'])} {row.get('error', '')}"
                          + (" (the driver's own)" if row.get("explained") else ""), flush=True)
                elif n % 25 == 0:
                    print(f"[{n}/{len(tests)}] {time.time() - started:.0f} s", flush=True)
    results.close()
    seconds = time.time() - started
    lines, total = table(rows)
    print("\n".join(lines))
    if args.doc:
        write_doc(args.doc, rows, args, seconds)
    failed = sum(1 for r in rows if r.get("classes") and not r.get("explained"))
    for r in rows:  # a listed divergence that is gone: the list must say so
        if r["name"] in runner.known and not r.get("classes"):
            print(f"{r['name']}: listed in {args.known} but no longer diverges: take it off the list")
            failed += 1
    print(f"{len(rows)} tests in {seconds:.0f} s; divergences not the driver's own: {failed}")
    print(f"{len(rows) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
