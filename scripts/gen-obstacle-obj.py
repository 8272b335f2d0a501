#!/usr/bin/env python3
"""Writes the small obstacle meshes of configs/ as OBJ (issue 33 §5).

  table     a table: a top 1.2 x 0.04 x 0.8 m whose upper face is at y = 0,
            on four legs 0.05 x 0.05 m, 0.7 m long, set in 0.05 m from the
            corners; every part a closed box (8 vertices, 12 triangles), the
            parts disjoint boxes that touch (legs meet the top's lower face).
  cylinder  a closed cylinder of radius R (default 0.1 m) and length L
            (default 1.2 m) along z, centred on the origin: N (default 24)
            vertices around each end circle, the sides as 2N triangles, each
            end cap a fan of N triangles about its centre vertex.
  sphere    a UV sphere of radius R (default 0.3 m, Codim-IPC's sphere1K_0.3)
            centred on the origin, poles on the y axis (so a turn about y
            keeps the poles in place): N (default 32) segments around, M
            (default 16) rings from pole to pole, (M - 1) N + 2 vertices.

Triangles are counter-clockwise seen from outside (outward normals).
Usage: scripts/gen-obstacle-obj.py table > configs/table.obj
       scripts/gen-obstacle-obj.py cylinder [R] [L] [N] > configs/cylinder.obj
       scripts/gen-obstacle-obj.py sphere [R] [N] [M] > configs/sphere.obj"""
import math
import sys


def box(lo, hi, base):
    """Vertices and outward triangles of the axis-aligned box [lo, hi], indices from base (0-based)."""
    v = [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    # vertex index = 4 ix + 2 iy + iz; each face as a quad, counter-clockwise from outside
    quads = [(0, 1, 3, 2), (4, 6, 7, 5),  # x = lo, x = hi
             (0, 4, 5, 1), (2, 3, 7, 6),  # y = lo, y = hi
             (0, 2, 6, 4), (1, 5, 7, 3)]  # z = lo, z = hi
    t = []
    for a, b, c, d in quads:
        t += [(base + a, base + b, base + c), (base + a, base + c, base + d)]
    return v, t


def table():
    top = ((-0.6, -0.04, -0.4), (0.6, 0.0, 0.4))
    parts = [top]
    for sx in (-1, 1):
        for sz in (-1, 1):
            cx, cz = sx * (0.6 - 0.05 - 0.025), sz * (0.4 - 0.05 - 0.025)
            parts.append(((cx - 0.025, -0.74, cz - 0.025), (cx + 0.025, -0.04, cz + 0.025)))
    verts, tris = [], []
    for lo, hi in parts:
        v, t = box(lo, hi, len(verts))
        verts += v
        tris += t
    return "a table: top 1.2 x 0.04 x 0.8 m, upper face at y = 0, four legs 0.7 m", verts, tris


def cylinder(R=0.1, L=1.2, N=24):
    verts, tris = [], []
    for end in (-1, 1):
        for k in range(N):
            a = 2 * math.pi * k / N
            verts.append((R * math.cos(a), R * math.sin(a), end * L / 2))
    verts += [(0.0, 0.0, -L / 2), (0.0, 0.0, L / 2)]
    c0, c1 = 2 * N, 2 * N + 1
    for k in range(N):
        k1 = (k + 1) % N
        a, b, c, d = k, k1, N + k1, N + k  # side quad, outward
        tris += [(a, b, c), (a, c, d)]
        tris.append((c0, k1, k))  # z = -L/2 cap, normal -z
        tris.append((c1, N + k, N + k1))  # z = +L/2 cap, normal +z
    return "a closed cylinder along z: radius %g m, length %g m, %d segments" % (R, L, N), verts, tris


def sphere(R=0.3, N=32, M=16):
    verts, tris = [(0.0, R, 0.0)], []  # vertex 0: the north pole (+y)
    for i in range(1, M):  # rings of N vertices at polar angle pi i / M
        th = math.pi * i / M
        for k in range(N):
            a = 2 * math.pi * k / N
            verts.append((R * math.sin(th) * math.cos(a), R * math.cos(th), -R * math.sin(th) * math.sin(a)))
    verts.append((0.0, -R, 0.0))
    south = len(verts) - 1

    def ring(i, k):
        return 1 + (i - 1) * N + k % N

    for k in range(N):  # outward: counter-clockwise seen from outside (the angle a turns counter-clockwise about +y)
        tris.append((0, ring(1, k), ring(1, k + 1)))
        tris.append((south, ring(M - 1, k + 1), ring(M - 1, k)))
        for i in range(1, M - 1):
            a, b, c, d = ring(i, k), ring(i + 1, k), ring(i + 1, k + 1), ring(i, k + 1)
            tris += [(a, b, c), (a, c, d)]
    return "a UV sphere: radius %g m, %d segments, %d rings, poles on y" % (R, N, M), verts, tris


def main():
    what = sys.argv[1] if len(sys.argv) > 1 else ""
    if what == "table":
        title, v, t = table()
    elif what == "cylinder":
        args = [float(a) for a in sys.argv[2:4]] + [int(a) for a in sys.argv[4:5]]
        title, v, t = cylinder(*args)
    elif what == "sphere":
        args = [float(a) for a in sys.argv[2:3]] + [int(a) for a in sys.argv[3:5]]
        title, v, t = sphere(*args)
    else:
        sys.exit("usage: gen-obstacle-obj.py table | cylinder [R] [L] [N] | sphere [R] [N] [M]")
    out = ["# %s (scripts/gen-obstacle-obj.py %s)" % (title, " ".join(sys.argv[1:])),
           "# %d vertices, %d triangles" % (len(v), len(t))]
    out += ["v %.9g %.9g %.9g" % p for p in v]
    out += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in t]
    sys.stdout.write("\n".join(out) + "\n")


main()
