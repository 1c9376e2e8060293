"""Ports for tests that listen on TCP: a run of free ones, found by binding, never a port
computed from the process id (which another test, or another program's outgoing connection,
may hold: a wall whose stream port was taken ran its program unseen until the test timed out)."""
import socket


def free_port_run(n=1):
    """A port P with P..P+n-1 free now (each bound and released)."""
    for _ in range(100):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if port + n > 65535:
            continue
        try:
            for i in range(n):
                with socket.socket() as t:
                    t.bind(("127.0.0.1", port + i))
            return port
        except OSError:
            continue
    raise RuntimeError(f"no run of {n} free ports")
