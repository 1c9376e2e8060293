#!/usr/bin/python3
"""chaos_stranger.py HOST PORT SECONDS: a stranger on a wall's network (scripts/chaos.py) floods
every socket of the master at HOST for SECONDS: the stream (PORT), the journal (PORT+1), the
keeper (PORT+2) and the control channel (PORT+3). In rounds, until the time is up:

- with a CURVE key the master does not know: a subscriber sending a thousand distinct 200-byte
  subscriptions, and dealers sending random multipart garbage and near-miss requests;
- the same without keys (ZeroMQ's NULL mechanism);
- raw TCP: connections that send random bytes, and connections opened and dropped at once.

Prints what it sent. Debian's python3-zmq (/usr/bin/python3)."""
import os
import random
import socket
import sys
import time

import zmq

REQUESTS = [b"SNAPSHOT", b"SINCE 0", b"SINCE 18446744073709551615", b"READY top-left", b"STATUS top-left live 1",
            b"DONE 1", b"TIME", b"HELLO", b"GO 1", b"\x00" * 64]


def flood_zmq(ctx, host, port, rng, keyed, sent):
    server_public = None
    if keyed:
        # A well-formed key pair the master has never seen; the master's public key is unknown to
        # a stranger, so it guesses one: the handshake fails either way, which is what must hold.
        server_public, _ = zmq.curve_keypair()
    sockets = []

    def make(kind, offset):
        s = ctx.socket(kind)
        s.setsockopt(zmq.LINGER, 0)
        s.setsockopt(zmq.SNDHWM, 1000)
        s.setsockopt(zmq.SNDTIMEO, 0)
        if keyed:
            public, secret = zmq.curve_keypair()
            s.curve_publickey, s.curve_secretkey, s.curve_serverkey = public, secret, server_public
        s.connect(f"tcp://{host}:{port + offset}")
        sockets.append(s)
        return s

    sub = make(zmq.SUB, 0)
    for i in range(1000):
        sub.setsockopt(zmq.SUBSCRIBE, b"%08d" % i + rng.randbytes(192))
        sent["subscriptions"] += 1
    for offset in (1, 2, 3):
        d = make(zmq.DEALER, offset)
        for _ in range(100):
            parts = [rng.choice(REQUESTS)] if rng.random() < 0.5 else \
                [rng.randbytes(rng.randrange(0, 4096)) for _ in range(rng.randrange(1, 20))]
            try:
                d.send_multipart(parts, flags=zmq.NOBLOCK)
                sent["messages"] += 1
            except zmq.Again:
                break
    time.sleep(0.2)
    for s in sockets:
        s.close()


def flood_tcp(host, port, rng, sent):
    for offset in range(4):
        for i in range(10):
            try:
                with socket.create_connection((host, port + offset), timeout=1) as c:
                    if i % 2:
                        c.sendall(rng.randbytes(rng.randrange(1, 65536)))
                        sent["raw bytes"] += 1
                    sent["tcp connections"] += 1
            except OSError:
                sent["tcp refused"] += 1


def main():
    host, port, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    rng = random.Random(os.getpid())
    ctx = zmq.Context()
    sent = {"subscriptions": 0, "messages": 0, "tcp connections": 0, "raw bytes": 0, "tcp refused": 0}
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        flood_zmq(ctx, host, port, rng, True, sent)
        flood_zmq(ctx, host, port, rng, False, sent)
        flood_tcp(host, port, rng, sent)
    ctx.term()
    print("stranger: " + ", ".join(f"{v} {k}" for k, v in sent.items()))


if __name__ == "__main__":
    main()
