#!/usr/bin/env python3
"""Writes the unit UV sphere of RINGS rings and SECTORS sectors as an OBJ (outward faces), and with
--stretch Z a copy with z scaled by Z (a non-conformal edit of it): the large meshes of the 1M-face
spin and snap rows in docs/performance.md.

    bench/uv_sphere.py 501 1000 sphere1m.obj                 # 500,002 vertices, 1,000,000 faces
    bench/uv_sphere.py 501 1000 stretch1m.obj --stretch 1.5
"""
import argparse
import math

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("rings", type=int)
ap.add_argument("sectors", type=int)
ap.add_argument("out")
ap.add_argument("--stretch", type=float, default=1.0)
a = ap.parse_args()
r, s = a.rings, a.sectors
if r < 2 or s < 3:
    ap.error("needs at least 2 rings and 3 sectors")
with open(a.out, "w") as f:
    w = f.write
    w(f"v 0 0 {a.stretch!r}\n")
    for i in range(1, r):
        th = math.pi * i / r
        z, st = math.cos(th) * a.stretch, math.sin(th)
        for j in range(s):
            ph = 2 * math.pi * j / s
            w(f"v {st * math.cos(ph)!r} {st * math.sin(ph)!r} {z!r}\n")
    w(f"v 0 0 {-a.stretch!r}\n")
    last = 2 + (r - 1) * s

    def idx(i, j):  # 1-based OBJ index of ring i (1 .. r-1), sector j
        return 2 + (i - 1) * s + (j % s)

    for j in range(s):
        w(f"f 1 {idx(1, j)} {idx(1, j + 1)}\n")
    for i in range(1, r - 1):
        for j in range(s):
            p, q, u, v = idx(i, j), idx(i, j + 1), idx(i + 1, j), idx(i + 1, j + 1)
            w(f"f {p} {u} {q}\nf {q} {u} {v}\n")
    for j in range(s):
        w(f"f {last} {idx(r - 1, j + 1)} {idx(r - 1, j)}\n")
