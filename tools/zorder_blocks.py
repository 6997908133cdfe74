#!/usr/bin/env python3
"""zorder_blocks.py STORE.tpt TRACE [BLOCK]: what a Z-order layout of a store's data section
would save a reader over HTTP (docs/PERFORMANCE.md, "Stores over HTTP"), simulated.

TRACE is `strace -f -e trace=pread64 -o TRACE terrapatch bench ... STORE.tpt` of a flight over
the local store: every pread64 inside the data section is one node's read (offset, bytes). The
nodes are found in the store's location table, then laid out again in Z-order (each scale from
the coarsest down, its nodes in Morton order of (column, row), each node's stored bytes as they
are), and the BLOCK-byte blocks (default 16384, /vsicurl/'s) the flight's nodes touch counted in
both layouts: a block is one range request, a run of consecutive blocks one merged request.
"""
import re
import struct
import sys

store, trace = sys.argv[1], sys.argv[2]
BLOCK = int(sys.argv[3]) if len(sys.argv) > 3 else 16384
META, LOC = 104, 24  # io/src/store_format.hpp: META_BYTES, LOC_BYTES

with open(store, "rb") as f:
    head = f.read(160)
    header_bytes = struct.unpack_from("<I", head, 12)[0]
    f.seek(0, 2)
    size = f.tell()
    # the geometry: n and the source size (io/src/store_format.hpp H_N, H_SRC_WIDTH/HEIGHT)
    n, sw, sh = struct.unpack_from("<III", head, 16)
    # the footer (its last 56 bytes): where the tables are (F_META_OFFSET, F_LOC_OFFSET)
    f.seek(size - 56)
    foot = f.read(56)
    meta_off, meta_bytes, loc_off, loc_bytes = struct.unpack_from("<QQQQ", foot, 0)
    count = meta_bytes // META
    f.seek(loc_off)
    locs = f.read(loc_bytes)
entries = [struct.unpack_from("<QI", locs, i * LOC) for i in range(count)]
data_offset = loc_off + loc_bytes

cols, rows = (sw - 1) >> n, (sh - 1) >> n
scales, first, ncols, nrows = 0, [], [], []
while True:  # core/src/tree.c: scale s holds (cols >> s) x (rows >> s) nodes while >= 1
    c, r = cols >> scales, rows >> scales
    if c < 1 or r < 1:
        break
    ncols.append(c), nrows.append(r)
    scales += 1
first = [0] * scales
nid = 0
for s in range(scales - 1, -1, -1):  # ids from the top scale down, row-major
    first[s] = nid
    nid += ncols[s] * nrows[s]
assert nid == count, "geometry: %d nodes computed, %d in the tables" % (nid, count)


def morton(c, r):
    z = 0
    for b in range(16):
        z |= ((c >> b) & 1) << (2 * b) | ((r >> b) & 1) << (2 * b + 1)
    return z


order = []
for s in range(scales - 1, -1, -1):
    ids = [(morton(c, r), first[s] + r * ncols[s] + c) for r in range(nrows[s]) for c in range(ncols[s])]
    order += [i for _, i in sorted(ids)]
z_at, at = {}, data_offset
for i in order:
    z_at[i] = at
    at += entries[i][1]

by_offset = {off: i for i, (off, _) in enumerate(entries)}
reads = []
pat = re.compile(r"pread64\(\d+, .*, (\d+), (\d+)\) = (\d+)")
for line in open(trace):
    m = pat.search(line)
    if m and int(m.group(2)) >= data_offset and int(m.group(2)) in by_offset:
        reads.append(by_offset[int(m.group(2))])
nodes = sorted(set(reads))


def blocks(at_of):
    b = set()
    for i in nodes:
        o, n_ = at_of(i), entries[i][1]
        b.update(range(o // BLOCK, (o + n_ - 1) // BLOCK + 1))
    runs = sum(1 for x in b if x - 1 not in b)
    return len(b), runs


band = blocks(lambda i: entries[i][0])
z = blocks(lambda i: z_at[i])
print("store: %d nodes, %d scales; flight: %d reads, %d distinct nodes (%.1f MB)" %
      (count, scales, len(reads), len(nodes), sum(entries[i][1] for i in nodes) / 1e6))
print("%d-byte blocks touched: band order %d (%d runs), Z-order %d (%d runs): %.2fx fewer blocks, "
      "%.2fx fewer runs" % (BLOCK, band[0], band[1], z[0], z[1], band[0] / z[0], band[1] / z[1]))
