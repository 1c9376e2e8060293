"""Machines made here as network namespaces joined by a bridge, and the CURVE keys of a wall
across them: for the tests of walls across machines (wall_machines_test.py) and the chaos run
(scripts/chaos.py). Loopback and our own namespaces only: nothing leaves this machine."""
import contextlib
import json
import os
import shutil
import subprocess


def run(cmd, env=None, timeout=600):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


@contextlib.contextmanager
def bridged(addresses, tag, what):
    """One namespace per role of `addresses` ({role: IPv4 address}, a /24), each with a veth on
    one bridge, loopback up and multicast routed to its link. Yields {role: (namespace, link)}, or
    None after saying why namespaces cannot be made here (not root, no iproute2). The link is the
    bridge's end of the role's veth, in this (the outer) namespace: what it sends goes to the role."""
    if os.geteuid() != 0 or not shutil.which("ip"):
        print(f"SKIP: {what} needs root and iproute2 to make network namespaces")
        yield None
        return
    pid = os.getpid() % 100000
    made = {role: (f"glcast-{role}-{tag}{pid}", f"gco{tag}{i}{pid}"[:15]) for i, role in enumerate(addresses)}
    bridge = f"gcbr{tag}{pid}"[:15]
    setup = [["ip", "link", "add", bridge, "type", "bridge"], ["ip", "link", "set", bridge, "up"]]
    for i, (role, (n, outer)) in enumerate(made.items()):
        inner = f"gci{tag}{i}{pid}"[:15]
        setup += [["ip", "netns", "add", n],
                  ["ip", "link", "add", outer, "type", "veth", "peer", "name", inner],
                  ["ip", "link", "set", outer, "master", bridge], ["ip", "link", "set", outer, "up"],
                  ["ip", "link", "set", inner, "netns", n],
                  ["ip", "netns", "exec", n, "ip", "addr", "add", addresses[role] + "/24", "dev", inner],
                  ["ip", "netns", "exec", n, "ip", "link", "set", inner, "up"],
                  ["ip", "netns", "exec", n, "ip", "link", "set", "lo", "up"],
                  ["ip", "netns", "exec", n, "ip", "route", "add", "224.0.0.0/4", "dev", inner]]
    try:
        for cmd in setup:
            r = run(cmd)
            if r.returncode != 0:
                print(f"SKIP: cannot make the namespaces here ({' '.join(cmd)}: {r.stderr.strip()})")
                yield None
                return
        yield made
    finally:
        for n, _ in made.values():
            run(["ip", "netns", "del", n])
        run(["ip", "link", "del", bridge])


def wall_keys(glcast, out, displays, others=("stranger",)):
    """Keys made by glcast keygen: out/keys/master (master.key, authorized/DISPLAY.pub for each
    of `displays`), out/keys/DISPLAY (slave.key, master.pub) for each display and each of
    `others`, whose keys the master does not know. Returns {name: folder}."""
    dirs = {m: os.path.join(out, "keys", m) for m in ("master", *displays, *others)}
    for d in dirs.values():  # writable by no one else, or the keys in it are refused
        os.makedirs(d, mode=0o700)
    os.makedirs(os.path.join(dirs["master"], "authorized"), mode=0o700)

    def keygen(path):
        r = run([glcast, "keygen", path])
        if r.returncode != 0:
            raise AssertionError(f"glcast keygen {path} failed: {r.stderr}")

    keygen(os.path.join(dirs["master"], "master"))
    for m in (*displays, *others):
        keygen(os.path.join(dirs[m], "slave"))
        shutil.copy(os.path.join(dirs["master"], "master.pub"), dirs[m])
    for m in displays:
        shutil.copy(os.path.join(dirs[m], "slave.pub"), os.path.join(dirs["master"], "authorized", m + ".pub"))
    return dirs


def wall_config(out, name, master_address, port, tiles, tile_size):
    """A display config of a wall across these machines, written to OUT/wall.json: the swap
    barrier on, the master at master_address:port, `tiles` as {name: (machine, x, y)}, each
    tile_size (width, height), the canvas their extent."""
    w, h = tile_size
    config = {"name": name, "canvas": {"width": max(x for _, x, _ in tiles.values()) + w,
                                       "height": max(y for _, _, y in tiles.values()) + h},
              "swap_barrier": True, "master": {"address": master_address, "port": port},
              "tiles": [{"name": t, "machine": m, "x": x, "y": y, "width": w, "height": h}
                        for t, (m, x, y) in tiles.items()]}
    path = os.path.join(out, "wall.json")
    with open(path, "w") as f:
        json.dump(config, f, indent=1)
    return path
