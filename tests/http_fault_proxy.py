#!/usr/bin/env python3
"""http_fault_proxy.py UPSTREAM_PORT PORT_FILE LOG [DELAY_S]: a delaying, fault-injecting HTTP
proxy in front of a web server on 127.0.0.1:UPSTREAM_PORT (tests/test_http_store.sh, issue 33).

Listens on 127.0.0.1 on a free port, which it writes to PORT_FILE once it accepts connections.
Every request waits DELAY_S (default 0.05) before it is forwarded, as a distant server would
answer. The path says what to do with it:

  /ok/NAME                       forward to /NAME
  /MODE/FROM-TO/NAME             forward to /NAME, but a GET whose Range starts at a byte in
                                 FROM..TO-1 gets the fault MODE:
      404, 500                   that status, no body
      reset                      the connection reset (RST) before any answer
      truncate                   the server's headers and the first 1/16 of its body, then the
                                 connection closed (a body cut short in the middle of a node)
      stall                      no answer for 60 s (the client's timeout must end it)
      garble                     the server's answer with every byte of its body inverted (a
                                 body damaged on the way: only the nodes' checksums can tell)
  /replace:OTHER/FROM-TO/NAME    forward to /NAME until a GET whose Range starts in FROM..TO-1,
                                 then every request (HEAD included) to /OTHER: a file replaced
                                 on the server between two reads

Each request is logged to LOG as one line: the time it was answered (s), method, path, Range,
status sent.
"""
import http.client
import os
import http.server
import re
import socket
import socketserver
import struct
import sys
import threading
import time

UPSTREAM = int(sys.argv[1])
PORT_FILE, LOG = sys.argv[2], sys.argv[3]
DELAY = float(sys.argv[4]) if len(sys.argv) > 4 else 0.05
replaced = set()  # paths of /replace:... whose switch happened
lock = threading.Lock()


def log(line):
    with lock, open(LOG, "a") as f:
        f.write("%.3f %s\n" % (time.time(), line))


class Handler(http.server.BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"

    def log_message(self, *args):
        pass

    def route(self):
        """(upstream path, fault or None)"""
        parts = self.path.lstrip("/").split("/")
        mode = parts[0]
        if mode == "ok":
            return "/" + "/".join(parts[1:]), None
        start = -1
        m = re.match(r"bytes=(\d+)-", self.headers.get("Range", ""))
        if m:
            start = int(m.group(1))
        lo, hi = (int(v) for v in parts[1].split("-"))
        due = self.command == "GET" and lo <= start < hi
        name = "/" + "/".join(parts[2:])
        if mode.startswith("replace:"):
            with lock:
                if due:
                    replaced.add(self.path)
                if self.path in replaced:
                    return "/" + mode[len("replace:"):], None
            return name, None
        return name, mode if due else None

    def answer(self, status):
        self.send_response(status)
        self.send_header("Content-Length", "0")
        self.end_headers()

    def do(self):
        time.sleep(DELAY)
        path, fault = self.route()
        rng = self.headers.get("Range", "-")
        if fault in ("404", "500"):
            log("%s %s %s %s" % (self.command, self.path, rng, fault))
            return self.answer(int(fault))
        if fault == "reset":
            log("%s %s %s reset" % (self.command, self.path, rng))
            self.connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER,
                                       struct.pack("ii", 1, 0))
            self.close_connection = True
            return
        if fault == "stall":
            log("%s %s %s stall" % (self.command, self.path, rng))
            time.sleep(60)
            self.close_connection = True
            return
        up = http.client.HTTPConnection("127.0.0.1", UPSTREAM, timeout=30)
        headers = {k: v for k, v in self.headers.items()
                   if k.lower() in ("range", "if-match", "if-unmodified-since", "if-range")}
        up.request(self.command, path, headers=headers)
        r = up.getresponse()
        body = r.read()
        log("%s %s %s %d" % (self.command, self.path, rng, r.status))
        self.send_response(r.status)
        for k, v in r.getheaders():
            if k.lower() not in ("connection", "keep-alive", "transfer-encoding", "server",
                                 "date"):
                self.send_header(k, v)
        self.end_headers()
        if self.command == "GET":
            if fault == "garble":
                body = bytes(b ^ 0xFF for b in body)
            if fault == "truncate" and len(body) > 1:
                self.wfile.write(body[: len(body) // 16])
                self.wfile.flush()
                self.close_connection = True
                self.connection.shutdown(socket.SHUT_RDWR)
                return
            self.wfile.write(body)
        up.close()

    do_GET = do
    do_HEAD = do


class Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
    daemon_threads = True
    allow_reuse_address = True


server = Server(("127.0.0.1", 0), Handler)
with open(PORT_FILE + ".tmp", "w") as f:
    f.write(str(server.server_address[1]))
os.rename(PORT_FILE + ".tmp", PORT_FILE)
server.serve_forever()
