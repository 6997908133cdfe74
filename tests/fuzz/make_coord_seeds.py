#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_coord_line (corpus/fuzz_coord_line/) from the coordinate test
sets in data/coord (see its README.md): each seed is one byte choosing the mode
(byte % 6: 0..3 --to geo/utm/mgrs/ecef, 4 --geodesic, 5 tp_mgrs_reverse; byte / 6 % 12 the MGRS
precision) and one input line. Usage: make_coord_seeds.py SHARED_COORD_DIR OUT_DIR"""
import hashlib
import os
import sys

src, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
seeds = []


def add(mode, precision, line):
    seeds.append(bytes([mode + 6 * precision]) + line.encode())


def lines(name, n):
    with open(os.path.join(src, name)) as f:
        return [l.split() for l in f if l.strip() and not l.startswith("#")][:n]


for f in lines("utm_mgrs_edgecases_geoconvert212.txt", 12):  # LAT LON ZONE E N MGRS
    add(0, 0, " ".join(f[0:2]))
    add(2, 5, " ".join(f[0:2]))
    add(1, 0, " ".join(f[2:5]))
    add(3, 0, " ".join(f[0:2]) + " 1234.5")
    add(0, 0, f[5])
    add(5, 1, f[5])
for f in lines("mgrs_boundary84_disagreements.txt", 4):  # LAT LON MGRS MGRS
    add(5, 0, f[2])
    add(5, 1, f[3])
    add(2, 11, " ".join(f[0:2]))
for f in lines("GeodTest-short.first2000.dat", 6):  # LAT1 LON1 AZI1 LAT2 LON2 ...
    add(4, 0, " ".join([f[0], f[1], f[3], f[4]]))
for f in lines("TMcoords_lite.first2000.txt", 4):
    add(1, 0, " ".join(f[0:2]))
# the shapes the parser tells apart, good and bad
for mode, line in [(0, "n 2000000 1333272.296"), (0, "s 2746000 1515000"), (0, "33T"),
                   (0, "38smb4488"), (0, "-33.9 18.4"), (0, "1e3 2E-2"), (0, "91 0"),
                   (0, "33n 500000"), (0, "61n 500000 0"), (0, "33x 1 2"), (0, "nan inf"),
                   (0, "0x10 5"), (2, "0 -180"), (1, "84 0"), (1, "-80.000001 0"),
                   (5, "INV"), (5, "BAN0000000000"), (5, "ZAA0000033272"), (5, "33TWN 00"),
                   (4, "0 0 91 0"), (4, "1 2 3"), (0, "45\t7"), (0, "")]:
    add(mode, 5, line)
for s in seeds:
    with open(os.path.join(out, hashlib.sha1(s).hexdigest()), "wb") as f:
        f.write(s)
print(f"{len(seeds)} seeds in {out}")
