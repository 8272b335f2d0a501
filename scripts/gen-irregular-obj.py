#!/usr/bin/env python3
"""Writes an unstructured square cloth as OBJ (configs/drape_irregular.obj).

How it is made: n x n boundary-conforming points on the square's edges, plus
interior points placed by dart throwing (Poisson-disk sampling with minimum
distance 0.8 h, h = side/(n-1), a fixed seed), each with its mirror image
through the centre (so the mesh is symmetric under a half turn and the
frictionless drape keeps its centre of mass above the sphere's), then the Delaunay triangulation
of all points by the Bowyer-Watson algorithm (pure Python, no libraries).
The square is convex, so the Delaunay triangles are exactly the cloth.
Usage: scripts/gen-irregular-obj.py [N] [SIDE] [SEED] > out.obj
The mesh lies in the xz plane (y = 0), centred at the origin, as a grid
with mesh.plane = xz does."""
import math
import random
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 32
side = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
seed = int(sys.argv[3]) if len(sys.argv) > 3 else 11
rng = random.Random(seed)
h = side / (n - 1)
half = side / 2
pts = []
for i in range(n - 1):  # boundary, counter-clockwise, evenly spaced
    t = -half + i * h
    pts += [(t, -half), (half, t), (-t, half), (-half, -t)]
rmin = 0.8 * h
tries = 0
target = n * n
while len(pts) < target and tries < 200000:
    tries += 1
    p = (rng.uniform(-half + 0.5 * h, half - 0.5 * h), rng.uniform(-half + 0.5 * h, half - 0.5 * h))
    m = (-p[0], -p[1])  # and its mirror image through the centre
    if (2 * p[0]) ** 2 + (2 * p[1]) ** 2 >= rmin * rmin and \
            all((p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 >= rmin * rmin for q in pts):
        pts += [p, m]


def circum(a, b, c):
    ax, ay = a
    bx, by = b
    cx, cy = c
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    ux = ((ax * ax + ay * ay) * (by - cy) + (bx * bx + by * by) * (cy - ay) + (cx * cx + cy * cy) * (ay - by)) / d
    uy = ((ax * ax + ay * ay) * (cx - bx) + (bx * bx + by * by) * (ax - cx) + (cx * cx + cy * cy) * (bx - ax)) / d
    return ux, uy, (ax - ux) ** 2 + (ay - uy) ** 2


big = 10 * side
P = pts + [(-big, -big), (big, -big), (0, big)]
N = len(pts)
tris = {(N, N + 1, N + 2): circum(P[N], P[N + 1], P[N + 2])}
for i in range(N):
    x, y = P[i]
    bad = [t for t, (ux, uy, r2) in tris.items() if (x - ux) ** 2 + (y - uy) ** 2 < r2]
    edges = {}
    for t in bad:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            k = tuple(sorted(e))
            edges[k] = edges.get(k, 0) + 1
        del tris[t]
    for t in bad:
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if edges[tuple(sorted(e))] == 1:
                nt = (e[0], e[1], i)
                tris[nt] = circum(P[nt[0]], P[nt[1]], P[nt[2]])
out = sys.stdout
out.write("# unstructured %g m square cloth: %d vertices, point-symmetric Poisson-disk interior (seed %d), Delaunay (Bowyer-Watson)\n"
          % (side, N, seed))
out.write("# made by scripts/gen-irregular-obj.py %d %g %d\n" % (n, side, seed))
for x, z in pts:
    out.write("v %.9f 0 %.9f\n" % (x, z))
count = 0
for t in sorted(tris):
    if max(t) >= N:
        continue
    a, b, c = (P[k] for k in t)
    area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    if abs(area) < 1e-12 * side * side:
        continue
    o = t if area > 0 else (t[0], t[2], t[1])
    out.write("f %d %d %d\n" % (o[0] + 1, o[1] + 1, o[2] + 1))
    count += 1
sys.stderr.write("%d vertices, %d triangles\n" % (N, count))
