#!/usr/bin/env python3
"""Clients that hold a web server's connections (used by twin_web_slow_clients.sh).

  slow_clients.py hold PORT IDLE TRICKLING SECONDS   from 127.0.0.2: TRICKLING connections that send one byte
      of a request header every 2 s, then IDLE connections that send nothing; after SECONDS prints
      "open=N trickling_open=M" (connections the server has not closed) and exits.
  slow_clients.py headers PORT COUNT                 from 127.0.0.2: one request with COUNT header lines;
      prints the status code the server answers ("000": it closed without one).
"""
import socket
import sys
import time

ATTACKER = "127.0.0.2"  # not the normal client's 127.0.0.1, so the per-address cap does not refuse it


def connect(port):
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind((ATTACKER, 0))
    s.settimeout(5)
    s.connect(("127.0.0.1", port))
    s.setblocking(False)
    return s


def still_open(s):
    try:
        return s.recv(1, socket.MSG_PEEK) != b""
    except BlockingIOError:
        return True
    except OSError:
        return False


def hold(port, idle, trickling, seconds):
    request = b"GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + b"a" * 4096
    slow = [connect(port) for _ in range(trickling)]
    quiet = []
    for _ in range(idle):
        try:
            quiet.append(connect(port))
        except OSError:
            pass  # refused at connect (backlog): counted as not open
    print(f"connected trickling={len(slow)} idle={len(quiet)}", flush=True)
    end = time.monotonic() + seconds
    sent = 0
    while time.monotonic() < end:
        for s in slow:
            try:
                s.send(request[sent:sent + 1])
            except OSError:
                pass
        sent = min(sent + 1, len(request) - 1)
        time.sleep(2)
    open_slow = sum(still_open(s) for s in slow)
    open_all = open_slow + sum(still_open(s) for s in quiet)
    print(f"open={open_all} trickling_open={open_slow}", flush=True)


def headers(port, count):
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind((ATTACKER, 0))
    s.settimeout(10)
    s.connect(("127.0.0.1", port))
    try:
        s.sendall(b"GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\n" + b"X-A: b\r\n" * count + b"\r\n")
    except OSError:
        pass  # the server may close while the rest is still being sent; its answer is read below
    try:
        line = s.recv(64).split(b"\r\n")[0].split(b" ")
        print(line[1].decode() if len(line) > 1 else "000")
    except OSError:
        print("000")


if __name__ == "__main__":
    if sys.argv[1] == "hold":
        hold(int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]))
    else:
        headers(int(sys.argv[2]), int(sys.argv[3]))
