#!/usr/bin/env python3
"""Immersive walls (docs/immersive.md), end to end: tests/apps_extra/pillars.c --markers captured
under Xvfb, its tiles replayed headless with display configs whose screens are given in metres.

    immersive_test.py CASE      with GLCAST, APPS_DIR, OUT_DIR in the environment

cave_metres: the four-sided CAVE in metres (display_configs/cave-4-metres.json) with the eye at
  the room's origin shows on every wall what the angle-based display_configs/cave-4.json shows.
head_poses_replay: poses played from a file (glcast replay --head-poses) move the eye at the frames
  they are stamped with, and each holds until the next.
head_poses_run: the same poses played by glcast run (--head-poses) reach two slaves with the swap
  barrier's GO and change both at the frame they are stamped with.
tracker_run: a live tracker bridge (scripts/tracker_bridge.py) pushes poses to glcast run's pose
  socket: every frame shows one pose on both walls alike, in the order sent, and the last holds
  after the bridge stops.
stereo_disparity: a point 2.5 m away behind a screen 1.5 m away shows in the two eyes with the
  disparity the eye separation predicts, within 1 px, in every stereo mode: one eye per tile,
  side by side, top and bottom, quad-buffer; the anaglyph is exactly the eyes' channels.
stereo_window: a stereo tile on a display (Xvfb): the eyes headless, the composed frame in a window,
  equal to the headless frame; quad-buffer refused where there is no stereo visual.
stereo_effects: the injected passes in both eyes: the spectral snow layer identical (on the screen's
  plane), the cover on the floor in both eyes alike.
stereo_run: stereo on a live wall (glcast run) with recorded head poses: a side-by-side tile's left
  half equals a left-eye tile pixel for pixel, each eye's markers where that frame's pose puts them.
cave_effects_eye_moved: with the eye 0.5 m off the origin along z too, every wall's floor holds the
  snow cover pass's snow.
culling: a program that culls outside its own view (pillars --cull) leaves turned tiles without
  what it culled; with a wider field of view in the program (--fov 170) the tiles within it get
  it back, in the same places.
cave_eye_moved_ff, _shader, _mvp: with the viewer 0.5 m off the origin, every marker point lands
  within 1 pixel of where the generalized perspective projection, computed here from the corners
  alone, puts it on each wall, and on no wall that does not see it; by fixed function, by a GLSL
  program with its projection in a uniform, and by one with projection * view * model premultiplied.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
CONFIGS = os.path.join(ROOT, "display_configs")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "immersive")
WALLS = ["front", "left", "right", "floor"]

# tests/apps_extra/pillars.c MARKERS: position (eye space, here metres) and colour.
MARKERS = [((0.0, 0.0, -2.5), (0, 0, 255)), ((0.4, 0.3, -1.2), (255, 0, 0)), ((-1.2, 0.2, -0.4), (255, 255, 0)),
           ((1.2, -0.3, 0.5), (0, 255, 0)), ((0.3, -1.2, -0.3), (255, 0, 255))]
NEAR = 0.5  # pillars' near plane: nearer points are clipped on every tile


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def run(cmd, env=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def capture(name, flags, frames=2):
    out = os.path.join(OUT, name)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    path = os.path.join(out, "capture.glcs")
    r = run([GLCAST, "capture", "-o", path, "--frames", str(frames), "--", os.path.join(APPS, "pillars")] +
            flags + ["--markers", "--size", "400x300", "--frames", str(frames + 1)])
    check(r.returncode == 0, f"capture failed: {r.stderr[-3000:]}")
    return out, path


def replay_tile(capture_path, config, tile, out, frame=1, extra=(), last=None):
    r = run([GLCAST, "replay", capture_path, "--config", config, "--tile", tile, "--frames", f"{frame}:{last or frame}",
             "--out", out] + list(extra), env={k: v for k, v in os.environ.items() if k != "DISPLAY"})
    check(r.returncode == 0, f"replay of {tile} failed: {r.stderr[-3000:]}")
    return os.path.join(out, f"frame-{frame:06d}.png")


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def on_screen(screen, eye, p, width, height):
    """Where the eye's ray through room point p meets the screen, in pixels from the top left;
    None when the screen does not show it (behind the eye, nearer than the near plane, off the
    screen)."""
    bl, br, tl = screen["bottom_left"], screen["bottom_right"], screen["top_left"]
    across, up = sub(br, bl), sub(tl, bl)
    n = cross(across, up)
    n = tuple(c / dot(n, n) ** 0.5 for c in n)
    depth = -dot(sub(p, eye), n)  # along the screen's normal, away from the viewer
    if depth < NEAR:
        return None
    t = -dot(sub(bl, eye), n) / depth
    hit = sub(tuple(e + t * d for e, d in zip(eye, sub(p, eye))), bl)
    u, v = dot(hit, across) / dot(across, across), dot(hit, up) / dot(up, up)
    if not (0 <= u <= 1 and 0 <= v <= 1):
        return None
    return u * width, (1 - v) * height


def found(image, colour):
    """The centre of the pixels of exactly `colour` (pixel centres at +0.5) and their count."""
    w, h, rows = image
    xs = ys = n = 0
    for y in range(h):
        row = rows[y]
        for x in range(w):
            if tuple(row[x][:3]) == colour:
                xs, ys, n = xs + x + 0.5, ys + y + 0.5, n + 1
    return (xs / n, ys / n, n) if n else None


def markers_where_predicted(name, config_path, images, eye=None, least=5):
    config = json.load(open(config_path))
    eye = eye or tuple(config.get("viewer", {}).get("position", [0, 0, 0]))
    worst, seen = 0.0, 0
    for tile in config["tiles"]:
        image = read_png(images[tile["name"]])
        for position, colour in MARKERS:
            want = on_screen(tile["screen"], eye, position, tile["width"], tile["height"])
            got = found(image, colour)
            if want is None:
                check(got is None, f"{name}: {tile['name']} shows marker {colour}, which it cannot see from {eye}")
                continue
            margin = 8  # a point cut by the tile's edge has its centre elsewhere
            if not (margin < want[0] < tile["width"] - margin and margin < want[1] < tile["height"] - margin):
                continue
            check(got is not None, f"{name}: {tile['name']} lacks marker {colour}, expected at {want}")
            error = ((got[0] - want[0]) ** 2 + (got[1] - want[1]) ** 2) ** 0.5
            check(error <= 1.0, f"{name}: {tile['name']}: marker {colour} at ({got[0]:.2f}, {got[1]:.2f}), "
                                f"the projection puts it at ({want[0]:.2f}, {want[1]:.2f}): {error:.2f} px off")
            worst, seen = max(worst, error), seen + 1
    print(f"{name}: {seen} markers on the walls, each within {worst:.2f} px of its predicted place")
    check(seen >= least, f"{name}: only {seen} markers checked")


def case_cave_metres():
    out, path = capture("cave_metres", [])
    for wall in WALLS:
        a = replay_tile(path, os.path.join(CONFIGS, "cave-4.json"), wall, os.path.join(out, "angles", wall))
        b = replay_tile(path, os.path.join(CONFIGS, "cave-4-metres.json"), wall, os.path.join(out, "metres", wall))
        r = run([GLCAST, "image", "compare", a, b])
        print(f"cave_metres {wall}: {r.stdout.strip()}")
        check(r.returncode == 0, f"{wall}: the wall in metres differs from the angle-based one: {r.stdout} {r.stderr}")
    images = {w: os.path.join(out, "metres", w, "frame-000001.png") for w in WALLS}
    markers_where_predicted("cave_metres", os.path.join(CONFIGS, "cave-4-metres.json"), images)


def moved_config(out, position):
    config = json.load(open(os.path.join(CONFIGS, "cave-4-metres.json")))
    config["viewer"]["position"] = position
    path = os.path.join(out, "cave-moved.json")
    with open(path, "w") as f:
        json.dump(config, f)
    return path


def cave_eye_moved(name, flags):
    out, path = capture(name, flags)
    config = moved_config(out, [0.3, 0.4, 0.0])  # 0.5 m from the origin
    images = {w: replay_tile(path, config, w, os.path.join(out, w)) for w in WALLS}
    markers_where_predicted(name, config, images)


def case_cave_eye_moved_ff():
    cave_eye_moved("cave_eye_moved_ff", [])


def case_cave_eye_moved_shader():
    cave_eye_moved("cave_eye_moved_shader", ["--shader"])


def case_cave_eye_moved_mvp():
    cave_eye_moved("cave_eye_moved_mvp", ["--mvp"])


def write_poses(path, poses):
    with open(path, "w") as f:
        for frame, position, *separation in poses:
            pose = {"frame": frame, "position": position, "orientation": [1, 0, 0, 0]}
            if separation:
                pose["eye_separation"] = separation[0]
            f.write(json.dumps(pose) + "\n")


def case_head_poses_replay():
    # A recorded head: each pose changes every wall at the frame it is stamped with, and holds.
    out, path = capture("head_poses_replay", [], frames=6)
    poses = os.path.join(out, "poses.jsonl")
    write_poses(poses, [(2, [0.3, 0.4, 0.0]), (4, [-0.2, 0.1, 0.3])])
    config = os.path.join(CONFIGS, "cave-4-metres.json")
    for w in WALLS:
        replay_tile(path, config, w, os.path.join(out, w), frame=1, last=5, extra=["--head-poses", poses])
    for frame, eye in [(1, (0, 0, 0)), (2, (0.3, 0.4, 0.0)), (3, (0.3, 0.4, 0.0)), (4, (-0.2, 0.1, 0.3)), (5, (-0.2, 0.1, 0.3))]:
        images = {w: os.path.join(out, w, f"frame-{frame:06d}.png") for w in WALLS}
        markers_where_predicted(f"head_poses_replay frame {frame}", config, images, eye)


def case_head_poses_run():
    # The same, live: glcast run hands each frame's pose to both slaves with the swap barrier's GO.
    out = os.path.join(OUT, "head_poses_run")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    config = json.load(open(os.path.join(CONFIGS, "cave-4-metres.json")))
    config["tiles"] = [t for t in config["tiles"] if t["name"] in ("front", "left")]
    config["swap_barrier"] = False  # --head-poses turns it on
    config_path = os.path.join(out, "two-walls.json")
    with open(config_path, "w") as f:
        json.dump(config, f)
    poses = os.path.join(out, "poses.jsonl")
    # (frame 0's pose reaches the slaves before their first frame, which no GO precedes: before,
    # it held from frame 1 on)
    write_poses(poses, [(0, [0.2, -0.1, 0.1]), (2, [0.3, 0.4, 0.0]), (4, [-0.2, 0.1, 0.3])])
    r = run([GLCAST, "run", "--config", config_path, "--backend", "egl", "--out", out, "--head-poses", poses,
             "--frames", "6", "--", os.path.join(APPS, "pillars"), "--markers", "--size", "400x300", "--frames", "8"])
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    for frame, eye in [(0, (0.2, -0.1, 0.1)), (1, (0.2, -0.1, 0.1)), (2, (0.3, 0.4, 0.0)), (3, (0.3, 0.4, 0.0)),
                       (4, (-0.2, 0.1, 0.3)), (5, (-0.2, 0.1, 0.3))]:
        images = {w: os.path.join(out, w, f"frame-{frame:06d}.png") for w in ("front", "left")}
        markers_where_predicted(f"head_poses_run frame {frame}", config_path, images, eye, least=2)


def which_eye(config, images, candidates):
    """The candidate eye whose projection puts every visible marker within 1 px on every tile,
    or None."""
    for eye in candidates:
        fits = True
        for tile in config["tiles"]:
            image = images[tile["name"]]
            for position, colour in MARKERS:
                want = on_screen(tile["screen"], eye, position, tile["width"], tile["height"])
                got = found(image, colour)
                if want is None or not (8 < want[0] < tile["width"] - 8 and 8 < want[1] < tile["height"] - 8):
                    continue
                if got is None or ((got[0] - want[0]) ** 2 + (got[1] - want[1]) ** 2) ** 0.5 > 1.0:
                    fits = False
        if fits:
            return eye
    return None


def case_tracker_run():
    # A live tracker: a bridge (scripts/tracker_bridge.py) pushes pose A, then B, then stops. Every
    # frame shows one pose on both walls alike (the barrier's GO carries it), A before B, and B
    # holds after the bridge has stopped.
    out = os.path.join(OUT, "tracker_run")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    config = json.load(open(os.path.join(CONFIGS, "cave-4-metres.json")))
    config["tiles"] = [dict(t, width=384, height=384) for t in config["tiles"] if t["name"] in ("front", "left")]
    config["viewer"]["tracker"] = f"ipc://{out}/poses"
    config_path = os.path.join(out, "tracked.json")
    with open(config_path, "w") as f:
        json.dump(config, f)
    frames = 600  # longer than the bridge sends: the last pose must hold after it stops
    wall = subprocess.Popen([GLCAST, "run", "--config", config_path, "--backend", "egl", "--out", out, "--frames",
                             str(frames), "--", os.path.join(APPS, "pillars"), "--markers", "--size", "400x300",
                             "--frames", str(frames + 2)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # The bridge starts once the wall shows frames, so that every pose it sends meets some.
    for _ in range(600):
        if os.path.exists(os.path.join(out, "left", "frame-000002.png")) or wall.poll() is not None:
            break
        time.sleep(0.1)
    python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable  # Debian's: python3-zmq
    bridge = subprocess.Popen([python, os.path.join(ROOT, "scripts", "tracker_bridge.py"), config["viewer"]["tracker"]],
                              stdin=subprocess.PIPE, text=True)
    a, b = (0.3, 0.4, 0.0), (-0.2, 0.1, 0.3)
    for eye, seconds in ((a, 1.5), (b, 0.5)):
        for _ in range(int(seconds / 0.02)):
            bridge.stdin.write(json.dumps({"position": eye, "orientation": [1, 0, 0, 0]}) + "\n")
            bridge.stdin.flush()
            time.sleep(0.02)
    bridge.stdin.close()
    check(bridge.wait(timeout=30) == 0, "the bridge failed")
    stopped = time.time()
    stdout, stderr = wall.communicate(timeout=600)
    check(wall.returncode == 0, f"glcast run failed: {stderr[-3000:]}")
    taken = re.search(r"pose socket: (\d+) poses taken, (\d+) refused", stderr)
    check(taken and int(taken.group(1)) > 50 and taken.group(2) == "0", f"the pose socket: {taken and taken.group(0)}")
    seen, after_stop = [], 0
    for frame in sorted(set(range(0, frames, 6)) | set(range(frames - 5, frames))):
        images = {}
        for t in config["tiles"]:
            path = os.path.join(out, t["name"], f"frame-{frame:06d}.png")
            images[t["name"]] = read_png(path)
        eye = which_eye(config, images, [(0, 0, 0), a, b])
        check(eye is not None, f"tracker_run: frame {frame} shows no one pose on both walls")
        if os.path.getmtime(path) > stopped + 0.5:  # shown well after the bridge went
            check(eye == b, f"tracker_run: frame {frame}, after the bridge stopped, shows {eye}, not its last pose")
            after_stop += 1
        if not seen or seen[-1][0] != eye:
            seen.append([eye, frame, frame])
        seen[-1][2] = frame
    print("tracker_run: " + ", ".join(f"frames {f0}-{f1} eye {e}" for e, f0, f1 in seen) +
          f"; {after_stop} frames checked from 0.5 s after the bridge stopped")
    check(after_stop >= 3, "tracker_run: the program ended before the bridge had stopped long enough")
    order = [e for e, _, _ in seen]
    check(order[-1] == b and order.index(b) > order.index(a) if a in order else False,
          f"tracker_run: poses in the order {order}; A then B, B last, expected")
    check(len(order) == len(set(order)), f"tracker_run: a pose came back: {order}")


FRONT = {"bottom_left": [-1.5, -1.5, -1.5], "bottom_right": [1.5, -1.5, -1.5], "top_left": [-1.5, 1.5, -1.5]}
SEPARATION = 0.064


def stereo_config(out):
    # One front wall, 1024x1024 per eye, shown as every kind of stereo tile.
    tiles = [{"name": "left", "width": 1024, "height": 1024, "eye": "left", "screen": FRONT},
             {"name": "right", "width": 1024, "height": 1024, "eye": "right", "screen": FRONT},
             {"name": "side-by-side", "width": 2048, "height": 1024, "stereo": "side-by-side", "screen": FRONT},
             {"name": "top-bottom", "width": 1024, "height": 2048, "stereo": "top-bottom", "screen": FRONT},
             {"name": "anaglyph", "width": 1024, "height": 1024, "stereo": "anaglyph", "screen": FRONT},
             {"name": "quad-buffer", "width": 1024, "height": 1024, "stereo": "quad-buffer", "screen": FRONT}]
    config = {"name": "stereo", "tiles": tiles, "viewer": {"position": [0, 0, 0], "eye_separation": SEPARATION}}
    path = os.path.join(out, "stereo.json")
    with open(path, "w") as f:
        json.dump(config, f)
    return path


def crop(image, x, y, w, h):
    _, _, rows = image
    return w, h, [row[x:x + w] for row in rows[y:y + h]]


def case_stereo_disparity():
    # The blue marker straight ahead, 2.5 m away behind a screen 1.5 m away: each eye sees it where
    # its ray meets the screen, the left eye's image to the left (positive parallax).
    out, path = capture("stereo_disparity", [])
    config = stereo_config(out)
    eyes = {"left": (-SEPARATION / 2, 0, 0), "right": (SEPARATION / 2, 0, 0)}
    marker = MARKERS[0]
    want = {e: on_screen(FRONT, eyes[e], marker[0], 1024, 1024) for e in eyes}
    predicted = want["left"][0] - want["right"][0]
    images = {}
    for tile in ("left", "right", "side-by-side", "top-bottom", "anaglyph", "quad-buffer"):
        replay_tile(path, config, tile, os.path.join(out, tile))
    images["passive"] = (read_png(os.path.join(out, "left", "frame-000001.png")),
                         read_png(os.path.join(out, "right", "frame-000001.png")))
    sbs = read_png(os.path.join(out, "side-by-side", "frame-000001.png"))
    images["side-by-side"] = (crop(sbs, 0, 0, 1024, 1024), crop(sbs, 1024, 0, 1024, 1024))
    tb = read_png(os.path.join(out, "top-bottom", "frame-000001.png"))
    images["top-bottom"] = (crop(tb, 0, 0, 1024, 1024), crop(tb, 0, 1024, 1024, 1024))
    images["quad-buffer"] = (read_png(os.path.join(out, "quad-buffer", "frame-000001-left.png")),
                             read_png(os.path.join(out, "quad-buffer", "frame-000001-right.png")))
    for mode, (left, right) in images.items():
        l, r = found(left, marker[1]), found(right, marker[1])
        check(l and r, f"{mode}: the marker is missing in an eye")
        disparity = l[0] - r[0]
        print(f"stereo_disparity {mode}: left eye at ({l[0]:.2f}, {l[1]:.2f}), right at ({r[0]:.2f}, {r[1]:.2f}): "
              f"disparity {disparity:.2f} px, predicted {predicted:.2f}")
        check(abs(disparity - predicted) <= 1.0, f"{mode}: disparity {disparity:.2f} px, predicted {predicted:.2f}")
        for eye, got in (("left", l), ("right", r)):
            check(abs(got[0] - want[eye][0]) <= 1.0 and abs(got[1] - want[eye][1]) <= 1.0,
                  f"{mode}: the {eye} eye's marker at {got[:2]}, predicted {want[eye]}")
    # The anaglyph: red from the left eye's image, green and blue from the right eye's, exactly.
    (_, _, ana), (_, _, lrows), (_, _, rrows) = (read_png(os.path.join(out, "anaglyph", "frame-000001.png")),
                                                 *images["passive"])
    wrong = sum(1 for y in range(1024) for x in range(1024)
                if tuple(ana[y][x][:3]) != (lrows[y][x][0], rrows[y][x][1], rrows[y][x][2]))
    print(f"stereo_disparity anaglyph: {wrong} pixels differ from (left red, right green, right blue)")
    check(wrong == 0, f"anaglyph: {wrong} pixels are not the eyes' channels")


def case_stereo_window():
    # A stereo tile on a display: the eyes replay headless (EGL), the composed frame goes to a
    # window (its GLX context on a thread of its own); the frames equal the headless ones.
    # Quad-buffer needs a stereo visual, which Xvfb does not offer: refused, saying so.
    out, path = capture("stereo_window", [])
    config = stereo_config(out)
    headless = replay_tile(path, config, "side-by-side", os.path.join(out, "headless"))
    r = run([GLCAST, "replay", path, "--config", config, "--tile", "side-by-side", "--backend", "window", "--frames", "1:1",
             "--out", os.path.join(out, "window")])
    check(r.returncode == 0, f"the stereo window failed: {r.stderr[-2000:]}")
    same = run([GLCAST, "image", "compare", headless, os.path.join(out, "window", "frame-000001.png")])
    check(same.returncode == 0, f"the windowed stereo tile's frame differs: {same.stdout}")
    r = run([GLCAST, "replay", path, "--config", config, "--tile", "quad-buffer", "--backend", "window"])
    check(r.returncode == 1 and "quad-buffer stereo: this display offers no stereo visual" in r.stderr,
          f"quad-buffer on Xvfb: exit {r.returncode}, {r.stderr[-500:]}")
    print("stereo_window: side by side through a window as headless; quad-buffer refused: " + r.stderr.strip()[:120])


def case_stereo_effects():
    # The injected passes in both eyes: the particles, 3D in the program's world, have each
    # eye's parallax; the spectral layer, a texture over the canvas, is the same in both eyes
    # (it lies on the screen's plane); the cover lies on the scene in both.
    out, path = capture("stereo_effects", [])
    config = stereo_config(out)
    plain = read_png(replay_tile(path, config, "side-by-side", os.path.join(out, "plain")))
    snow = read_png(replay_tile(path, config, "side-by-side", os.path.join(out, "snow"),
                                extra=["--effects", "snow,cover", "--effect-param", "snow.particles=0"]))
    (_, _, p), (_, _, s) = plain, snow
    sky, differ, covered = [0, 0], 0, [0, 0]
    for y in range(0, 1024, 2):
        for x in range(0, 1024, 2):
            if tuple(p[y][x][:3]) == (0, 0, 0) and tuple(p[y][x + 1024][:3]) == (0, 0, 0):
                sky[0] += 1
                differ += tuple(s[y][x][:3]) != tuple(s[y][x + 1024][:3])
            for eye in (0, 1):
                covered[eye] += tuple(p[y][x + 1024 * eye][:3]) == (90, 90, 90) and s[y][x + 1024 * eye][2] > 150
    print(f"stereo_effects: {sky[0]} sky pixels seen by both eyes, {differ} differ in the spectral layer; "
          f"floor pixels under cover: left {covered[0]}, right {covered[1]}")
    check(differ == 0, "the spectral layer differs between the eyes")
    check(min(covered) > 20000 and abs(covered[0] - covered[1]) < 0.05 * max(covered), f"cover per eye: {covered}")


def case_stereo_run():
    # Stereo on a live wall with a recorded head: a side-by-side tile and a left-eye tile, two
    # slaves through the barrier. At every frame the side-by-side tile's left half is the
    # left-eye tile's picture, pixel for pixel, and each eye's marker lies where the pose of that
    # frame and the eye separation put it; the pose of frame 2 also widens the eyes to 0.2 m.
    out = os.path.join(OUT, "stereo_run")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    config = {"name": "stereo-run", "tiles": [
        {"name": "both", "width": 1024, "height": 512, "stereo": "side-by-side", "screen": FRONT},
        {"name": "left-eye", "width": 512, "height": 512, "eye": "left", "screen": FRONT}],
        "viewer": {"eye_separation": SEPARATION}}
    config_path = os.path.join(out, "stereo-run.json")
    with open(config_path, "w") as f:
        json.dump(config, f)
    poses = os.path.join(out, "poses.jsonl")
    write_poses(poses, [(2, [0.3, 0.4, 0.0], 0.2)])
    r = run([GLCAST, "run", "--config", config_path, "--backend", "egl", "--out", out, "--head-poses", poses,
             "--frames", "4", "--", os.path.join(APPS, "pillars"), "--markers", "--size", "400x300", "--frames", "6"])
    check(r.returncode == 0, f"glcast run failed: {r.stderr[-3000:]}")
    for frame, head, separation in ((1, (0, 0, 0), SEPARATION), (3, (0.3, 0.4, 0.0), 0.2)):
        both = read_png(os.path.join(out, "both", f"frame-{frame:06d}.png"))
        alone = read_png(os.path.join(out, "left-eye", f"frame-{frame:06d}.png"))
        halves = (crop(both, 0, 0, 512, 512), crop(both, 512, 0, 512, 512))
        check(halves[0][2] == alone[2], f"frame {frame}: the stereo tile's left half is not the left-eye tile's picture")
        for eye, half in zip((-1, 1), halves):
            position = (head[0] + eye * separation / 2, head[1], head[2])
            for marker, colour in MARKERS[:2]:
                want = on_screen(FRONT, position, marker, 512, 512)
                got = found(half, colour)
                check(got and abs(got[0] - want[0]) <= 1 and abs(got[1] - want[1]) <= 1,
                      f"frame {frame}, eye {eye}: marker {colour} at {got}, predicted {want}")
        print(f"stereo_run frame {frame}: left half = left-eye tile; both eyes' markers where head {head} and "
              f"separation {separation} put them")


def case_cave_effects_eye_moved():
    # The injected passes on every wall with the eye off the origin (also along z): each wall's
    # floor holds snow cover. Before, an eye moved along z left the turned walls' frames "without
    # a perspective view" (the program's projection, recovered from the corrected one GL keeps in
    # floats, had 1e-8 where a perspective projection has 0) and they got none.
    out, path = capture("cave_effects_eye_moved", [])
    config = moved_config(out, [0.4, 0.3, 0.5])
    covered = {}
    for wall in WALLS:
        _, _, rows = read_png(replay_tile(path, config, wall, os.path.join(out, wall), extra=["--effects", "cover"]))
        covered[wall] = sum(1 for row in rows for px in row if px[0] > 180 and px[1] > 180 and px[2] > 180)
    print(f"cave_effects_eye_moved: snow-white pixels per wall {covered}")
    check(all(n > 250000 for n in covered.values()), f"a wall without cover: {covered}")
    # The floor wall sees nothing but the floor (and a marker): all of it, the part behind the
    # program's camera too (before, the cover's visibility test compared -z, negative there).
    check(covered["floor"] > 0.9 * 1024 * 1024, f"the floor wall is covered in {covered['floor']} pixels only")


def pillar_colour(k):  # tests/apps_extra/pillars.c
    return (40 + 16 * k, 200 - 12 * k, 255 - 20 * k)


def case_culling():
    # A program that culls (pillars --cull: nothing outside its own 60-degree view is drawn) leaves
    # the tiles that look elsewhere without what it culled; the remedy a site has: a wider field
    # of view in the program. glcast turns any projection, so the tiles show the same pillars in
    # the same places, and only what lies outside the wider view is still missing.
    out = os.path.join(OUT, "culling")
    shutil.rmtree(out, ignore_errors=True)
    config = os.path.join(CONFIGS, "cylinder-360.json")
    seen = {}
    for name, flags in (("all", []), ("culled", ["--cull"]), ("culled-wide", ["--cull", "--fov", "170"])):
        d = os.path.join(out, name)
        r = run([GLCAST, "run", "--config", config, "--backend", "egl", "--out", d, "--frames", "1", "--",
                 os.path.join(APPS, "pillars")] + flags + ["--size", "400x300", "--frames", "3"])
        check(r.returncode == 0, f"{name}: glcast run failed: {r.stderr[-2000:]}")
        seen[name] = []
        for i in range(6):
            _, _, rows = read_png(os.path.join(d, f"yaw{60 * i:03d}", "frame-000000.png"))
            seen[name].append(tuple(rows[1200 * 30 // 50 - 100][800][:3]) == pillar_colour(2 * i))
    print("culling: the pillar at each tile's centre (yaw 0, 60, ..., 300) shown: " +
          "; ".join(f"{k} {['yes' if v else 'no' for v in s]}" for k, s in seen.items()))
    check(all(seen["all"]), "without culling every tile shows its pillar")
    check(seen["culled"] == [True, False, False, False, False, False], "culled: only the front tile keeps its pillar")
    check(seen["culled-wide"] == [True, True, False, False, False, True],
          "culled with a 170-degree view: the tiles at +-60 degrees get theirs back, the back ones not")


if __name__ == "__main__":
    with Xvfb():
        globals()["case_" + sys.argv[1]]()
    print("PASS")
