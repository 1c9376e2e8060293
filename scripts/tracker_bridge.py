#!/usr/bin/python3
"""A tracker bridge for an immersive wall (docs/immersive.md): pushes head poses to the pose
socket of `glcast run` (--tracker, or the config's viewer.tracker). This one reads them as JSON
lines on stdin, {"position": [x, y, z], "orientation": [w, x, y, z]}, metres and a unit
quaternion; a site puts its tracker's callback (VRPN, OpenXR, a motion-capture SDK) where the
loop reads a line.

    tracker_bridge.py ENDPOINT [KEYS_DIR] < poses.jsonl

With KEYS_DIR (a wall with keys): the bridge's pair KEYS_DIR/slave.key, the wall's KEYS_DIR/master.pub,
made with `glcast keygen`; its slave.pub goes among the wall's authorized keys.
"""
import json
import sys
import time

import zmq  # Debian: python3-zmq


def key(path, name):
    for line in open(path):
        if line.split("=")[0].strip() == name:
            return line.split("=", 1)[1].strip().encode()
    raise SystemExit(f"{path}: no {name} line")


def main():
    push = zmq.Context().socket(zmq.PUSH)
    if len(sys.argv) > 2:
        push.curve_secretkey = key(f"{sys.argv[2]}/slave.key", "secret-key")
        push.curve_publickey = key(f"{sys.argv[2]}/slave.key", "public-key")
        push.curve_serverkey = key(f"{sys.argv[2]}/master.pub", "public-key")
    push.connect(sys.argv[1])
    for line in sys.stdin:
        pose = json.loads(line)  # where a tracker's callback would hand over its pose
        message = {"position": pose["position"], "orientation": pose["orientation"], "time": time.time()}
        if "eye_separation" in pose:  # the eyes' distance, changed while running
            message["eye_separation"] = pose["eye_separation"]
        push.send_string(json.dumps(message))
    push.close(linger=2000)  # the last poses still go out


if __name__ == "__main__":
    main()
