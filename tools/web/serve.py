#!/usr/bin/env python3
"""tools/web/serve.py - serve the web page (tools/web/), CesiumJS's built files and a
quantized-mesh tile set on 127.0.0.1, with the headers Cesium needs (docs/web.md).

  tools/web/serve.py TILESET_DIR [--imagery TMS_DIR] [--port N] [--port-file F]
                     [--cesium DIR] [--log F]

URL paths:
  /               tools/web/ (index.html, terrapatch_web.js)
  /cesium/        CesiumJS's Build/Cesium (default: the one tools/web_install.sh installed)
  /tiles/         TILESET_DIR (layer.json, errors.json, z/x/y.terrain)
  /imagery/       TMS_DIR (gdal2tiles.py --profile geodetic output), when given

A .terrain tile is sent as it lies on disk; when it is gzip-compressed (as `terrapatch export
--tiles quantized-mesh` writes it) with `Content-Encoding: gzip`, so that the browser inflates it,
and as `application/vnd.quantized-mesh`. The query string (`?v=1.0.0` in Cesium's tile URLs) is
ignored. Port 0 (the default) takes a free port; the URL is printed on stdout and the port
written to --port-file. Stops on SIGINT or SIGTERM. Exit 1 after one line when a folder is
missing; 2 on a usage error.
"""
import argparse
import http.server
import os
import signal
import socketserver
import sys
import urllib.parse

ME = "terrapatch: tools/web/serve.py"
HERE = os.path.dirname(os.path.abspath(__file__))

TYPES = {
    ".terrain": "application/vnd.quantized-mesh",
    ".json": "application/json",
    ".js": "text/javascript",
    ".mjs": "text/javascript",
    ".wasm": "application/wasm",
    ".xml": "application/xml",
    ".png": "image/png",
    ".jpg": "image/jpeg",
    ".css": "text/css",
    ".html": "text/html",
}


def default_cesium():
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    web = os.environ.get("TP_WEB_DIR") or os.path.join(cache, "terrapatch", "web")
    return os.path.join(web, "node_modules", "cesium", "Build", "Cesium")


class Handler(http.server.SimpleHTTPRequestHandler):
    roots = {}  # URL prefix (without slashes) -> folder; "" is the page's

    def translate_path(self, path):
        path = urllib.parse.unquote(urllib.parse.urlsplit(path).path)
        parts = [p for p in path.split("/") if p and p not in (".", "..")]
        root = self.roots[""]
        if parts and parts[0] in self.roots and parts[0] != "":
            root = self.roots[parts[0]]
            parts = parts[1:]
        return os.path.join(root, *parts)

    def guess_type(self, path):
        return TYPES.get(os.path.splitext(path)[1].lower(), "application/octet-stream")

    def end_headers(self):
        path = self.translate_path(self.path)
        if path.endswith(".terrain") and os.path.isfile(path):
            with open(path, "rb") as f:
                if f.read(2) == b"\x1f\x8b":
                    self.send_header("Content-Encoding", "gzip")
        self.send_header("Access-Control-Allow-Origin", "*")
        self.send_header("Cache-Control", "no-cache")
        super().end_headers()

    def log_message(self, fmt, *args):
        if self.server.log:
            self.server.log.write("%s %s\n" % (self.log_date_time_string(), fmt % args))
            self.server.log.flush()


class Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
    daemon_threads = True
    allow_reuse_address = True
    log = None


def main():
    ap = argparse.ArgumentParser(prog="tools/web/serve.py",
                                 description="serve the terrapatch web page and a tile set")
    ap.add_argument("tileset", help="the folder of layer.json and z/x/y.terrain")
    ap.add_argument("--imagery", help="a TMS folder (gdal2tiles.py --profile geodetic)")
    ap.add_argument("--port", type=int, default=0, help="port on 127.0.0.1 (default: a free one)")
    ap.add_argument("--port-file", help="write the port there once listening")
    ap.add_argument("--cesium", default=default_cesium(), help="CesiumJS's Build/Cesium folder")
    ap.add_argument("--log", help="append the requests to this file")
    a = ap.parse_args()
    roots = {"": HERE, "tiles": a.tileset, "cesium": a.cesium}
    if a.imagery:
        roots["imagery"] = a.imagery
    for name, d in roots.items():
        if not os.path.isdir(d):
            hint = " (run tools/web_install.sh)" if name == "cesium" else ""
            print("%s: %s: no such folder%s" % (ME, d, hint), file=sys.stderr)
            return 1
    if not os.path.isfile(os.path.join(a.tileset, "layer.json")):
        print("%s: %s: no layer.json (not a quantized-mesh tile set)" % (ME, a.tileset),
              file=sys.stderr)
        return 1
    Handler.roots = {k: os.path.abspath(v) for k, v in roots.items()}
    try:
        srv = Server(("127.0.0.1", a.port), Handler)
    except OSError as e:
        print("%s: cannot listen on 127.0.0.1:%d: %s" % (ME, a.port, e.strerror), file=sys.stderr)
        return 1
    if a.log:
        srv.log = open(a.log, "a")
    port = srv.server_address[1]
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    if a.port_file:
        tmp = a.port_file + ".tmp"
        with open(tmp, "w") as f:
            f.write("%d\n" % port)
        os.replace(tmp, a.port_file)
    print("http://127.0.0.1:%d/index.html?tiles=tiles/%s" % (port, "&imagery=imagery/"
                                                               if a.imagery else ""), flush=True)
    try:
        srv.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        srv.server_close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
