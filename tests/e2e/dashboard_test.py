#!/usr/bin/python3
"""The wall's dashboard in a real browser (headless Chromium driven by its WebDriver, Debian's
chromium-driver and python3-selenium), on a running 2x2 wall with the swap barrier.

    dashboard_test.py          with GLCAST, APPS_DIR, OUT_DIR in the environment

- The dashboard binds 0.0.0.0, not loopback: without the token glcast run printed every request
  for the wall's data is refused (403); the page opened with it works.
- The page shows the four tiles with thumbnails, and each tile's thumbnail changes between two
  looks (its frame and its pixels).
- The fps plot has points and is drawn.
- Clicking "snow" switches it on; the reply names the master frame F it holds from. On the
  slaves' --out frames, all four tiles' frames from F on carry snow (differ from a replay of the
  same stream without effects) and no earlier frame does (equal to it).
- A dashboard on loopback needs no token but refuses a request naming another host (DNS
  rebinding).
"""
import json
import os
import re
import shutil
import subprocess
import sys
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ports import free_port_run  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ["APPS_DIR"]
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "dashboard")
TILES = ["top-left", "top-right", "bottom-left", "bottom-right"]
CONFIG = {"name": "dashboard-2x2", "canvas": {"width": 640, "height": 480}, "swap_barrier": True,
          "tiles": [{"name": n, "x": 320 * (i % 2), "y": 240 * (i // 2), "width": 320, "height": 240}
                    for i, n in enumerate(TILES)]}


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def http(url, headers=None, data=None):
    request = urllib.request.Request(url, headers=headers or {}, data=data)
    try:
        with urllib.request.urlopen(request, timeout=10) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()


def start_run(args, log_path, env):
    log = open(log_path, "w")
    proc = subprocess.Popen([GLCAST, "run"] + args, stdout=log, stderr=subprocess.STDOUT, env=env)
    deadline = time.time() + 60
    while time.time() < deadline:
        m = re.search(r"dashboard on (\S+)", open(log_path).read())
        if m:
            return proc, m.group(1)
        check(proc.poll() is None, f"glcast run ended before its dashboard: {open(log_path).read()}")
        time.sleep(0.1)
    raise AssertionError("no dashboard line within 60 s")


def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,1000"):
        options.add_argument(a)
    options.binary_location = "/usr/bin/chromium"
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def wait_for(what, predicate, seconds=30):
    from selenium.common.exceptions import WebDriverException
    deadline, last_error = time.time() + seconds, ""
    while time.time() < deadline:
        try:
            value = predicate()
            if value:
                return value
        except WebDriverException as e:  # the page is still building what is looked for
            last_error = str(e).splitlines()[0]
        time.sleep(0.2)
    raise AssertionError(f"waited {seconds} s for {what} {last_error}")


def look(driver):
    """Each tile's thumbnail: its frame and its pixels (a screenshot of the element)."""
    from selenium.webdriver.common.by import By
    out = {}
    for t in TILES:
        div = driver.find_element(By.ID, "tile-" + t)
        out[t] = (div.get_attribute("data-frame"), div.find_element(By.TAG_NAME, "img").screenshot_as_png)
    return out


def frame_png(folder, frame):
    return os.path.join(folder, "frame-%06d.png" % frame)


def same_pixels(a, b):
    # Both written by the same encoder with the same settings: equal files are equal pixels; for
    # files that differ glcast image compare says how.
    if open(a, "rb").read() == open(b, "rb").read():
        return True, 0
    r = subprocess.run([GLCAST, "image", "compare", a, b], capture_output=True, text=True)
    m = re.search(r"(\d+) pixels differ", r.stdout)
    check(m, f"compare {a} {b}: {r.stdout} {r.stderr}")
    return int(m.group(1)) == 0, int(m.group(1))


def dashboard_on_a_wall():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    config = os.path.join(OUT, "wall.json")
    json.dump(CONFIG, open(config, "w"))
    capture = os.path.join(OUT, "capture.glcs")
    port = free_port_run()
    env = dict(os.environ, GLCAST_CAPTURE=capture)
    run, url = start_run(["--config", config, "--backend", "egl", "--out", os.path.join(OUT, "tiles"), "--lockstep",
                          "--frames", "1200", "--dashboard", f"0.0.0.0:{port}", "--",
                          os.path.join(APPS, "ff_scene"), "--frames", "100000"], os.path.join(OUT, "run.log"), env)
    try:
        token = re.search(r"token=([0-9a-f]+)", url)
        check(token, f"a dashboard off loopback prints an address with its token: {url}")
        base = f"http://127.0.0.1:{port}"
        for path in ("/api/wall", "/api/status", "/api/thumbnail/top-left"):
            status, _ = http(base + path)
            check(status == 403, f"{path} without the token: HTTP {status}, not 403")
        status, _ = http(base + "/api/wall?token=" + "0" * 32)
        check(status == 403, f"a wrong token: HTTP {status}")
        status, body = http(base + "/api/wall?token=" + token.group(1))
        check(status == 200 and json.loads(body)["tiles"][0]["name"] == "top-left", f"with the token: {status} {body[:200]}")
        status, body = http(base + "/api/ctl?token=" + token.group(1), data=b"effects +rain")
        check(status == 403, f"a change without X-Glcast-Request (a form of another site): HTTP {status}")

        driver = browser()
        try:
            driver.get(url.replace("0.0.0.0", "127.0.0.1"))
            wait_for("the four thumbnails", lambda: all(f for f, _ in look(driver).values()))
            first = look(driver)
            time.sleep(2.5)
            second = look(driver)
            for t in TILES:
                check(int(second[t][0]) > int(first[t][0]), f"{t}: the thumbnail's frame went {first[t][0]} -> {second[t][0]}")
                check(second[t][1] != first[t][1], f"{t}: the thumbnail's pixels did not change")
            points = driver.execute_script("return Number(document.getElementById('fps-plot').dataset.points)")
            check(points >= 5, f"the fps plot has {points} points")
            drawn = driver.execute_script("""
                const c = document.getElementById('fps-plot');
                const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
                let lit = 0;
                for (let i = 3; i < d.length; i += 4) lit += d[i] > 0;
                return lit;""")
            check(drawn > 500, f"the fps plot has {drawn} drawn pixels")
            driver.find_element("id", "effect-snow").click()
            reply = wait_for("the wall's answer", lambda: driver.find_element("id", "reply").text)
            m = re.match(r"OK effects snow from frame (\d+) \(version 1\)$", reply)
            check(m, f"the reply to clicking snow: {reply!r}")
            switch = int(m.group(1))
            wait_for("the snow button on", lambda: "on" in driver.find_element("id", "effect-snow").get_attribute("class"))
            time.sleep(3)  # thumbnails with snow
            driver.save_screenshot(os.path.join(OUT, "dashboard.png"))
            print(f"dashboard: snow from frame {switch}; screenshot {OUT}/dashboard.png")
        finally:
            driver.quit()
        # (the wall's frames after the switch, with snow on four tiles: under the whole suite's load
        # they took more than 120 s once; the whole test takes 96 s alone)
        check(run.wait(timeout=300) == 0, f"glcast run: exit {run.returncode}")
    finally:
        if run.poll() is None:
            run.kill()
    log = open(os.path.join(OUT, "run.log")).read()
    for t in TILES:
        check(f"glcast slave {t}: effects snow from frame {switch}\n" in log, f"{t} did not say it switched at {switch}")

    # The same stream without effects, tile by tile: the frames before the switch.
    last = min(len(os.listdir(os.path.join(OUT, "tiles", t))) for t in TILES) - 1
    check(last > switch + 20, f"the wall ended at frame {last}, too soon after the switch at {switch}")
    for t in TILES:
        ref = os.path.join(OUT, "reference", t)
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--config", config, "--tile", t, "--out", ref,
                            "--frames", f"0:{switch + 20}"], capture_output=True, text=True, timeout=600)
        check(r.returncode == 0, f"replay of {t}: {r.stderr[-2000:]}")
        tiles = os.path.join(OUT, "tiles", t)
        for n in range(1, switch):
            same, differ = same_pixels(frame_png(tiles, n), frame_png(ref, n))
            check(same, f"{t}: frame {n}, before the switch at {switch}, differs from the replay without effects "
                        f"({differ} pixels)")
        for n in range(switch, switch + 21):
            same, differ = same_pixels(frame_png(tiles, n), frame_png(ref, n))
            check(differ > 320 * 240 // 100, f"{t}: frame {n}, from the switch at {switch} on, has no snow "
                                             f"({differ} pixels differ from the replay without effects)")
    print(f"dashboard: every tile's frames 1..{switch - 1} without snow, {switch}..{switch + 20} with it")


def loopback_needs_no_token():
    port = free_port_run()
    run, url = start_run(["--backend", "egl", "--frames", "600", "--dashboard", f"127.0.0.1:{port}", "--",
                          os.path.join(APPS, "ff_scene"), "--frames", "100000"], os.path.join(OUT, "loopback.log"),
                         dict(os.environ))
    try:
        check("token" not in url, f"a loopback dashboard printed a token: {url}")
        status, body = http(f"http://127.0.0.1:{port}/api/wall")
        check(status == 200 and json.loads(body)["tiles"][0]["name"] == "window", f"loopback: HTTP {status} {body[:200]}")
        status, _ = http(f"http://127.0.0.1:{port}/api/wall", headers={"Host": f"attacker.example:{port}"})
        check(status == 403, f"a request naming another host (DNS rebinding): HTTP {status}")
    finally:
        run.wait(timeout=120)


def main():
    with Xvfb():
        dashboard_on_a_wall()
        loopback_needs_no_token()
    print("dashboard: ok")


if __name__ == "__main__":
    main()
