#!/usr/bin/env python3
"""The plan of a whole run in N groups (scripts/lib/all.sh; not run by hand).

  all-plan.py BUILD MODE N DOC [--times CELLS_DIR]

Every experiment (experiments/*/main.c) is cut into units: a shardable one
into k = min(cells, 4N) shards of its own balanced assignment (--shard j/k,
so its merge is scripts/merge-shards.sh's, unchanged), one that cannot shard
(bending) is one unit. A unit's cost is its cells' hints over the
experiment's hint total, times the experiment's recorded wall seconds (the
run-time table of DOC, docs/running.md, the last full run: hints are
relative within one experiment only). The units go to the N groups by the
longest-processing-time rule (largest first, to the least-loaded group).
Prints one line per unit: "group experiment j k cost" (j = k = 0: whole).
"""
import os
import re
import subprocess
import sys


def die(msg):
    print("all-plan: " + msg, file=sys.stderr)
    sys.exit(1)


def list_cells(build, x, mode, shard):
    cmd = [os.path.join(build, x)] + ([mode] if mode else []) + ["--list-cells", "--out", "/tmp/cb-all-plan-%d.csv" % os.getpid()]
    if shard:
        cmd += ["--shard", shard]
    env = dict(os.environ, CB_QUIET="1", CB_CPU_LOCK="/tmp/cb-all-plan.lock")
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        return None
    return [line.split() for line in r.stdout.splitlines() if line.strip()]


def wall_seconds(doc):
    w = {}
    try:
        text = open(doc).read()
    except OSError:
        return w
    for m in re.finditer(r"^\| (\w+) \| full \| ([^|]*) \|", text, re.M):
        s = 0.0
        for v, u in re.findall(r"([0-9.]+) (h|min|s)\b", m.group(2)):
            s += float(v) * {"h": 3600, "min": 60, "s": 1}[u]
        w[m.group(1)] = s
    return w


def plan(build, mode, n, doc):
    """[(group, experiment, j, k, cost, [global cell indices])], in the order assigned."""
    names = sorted(d for d in os.listdir("experiments") if os.path.isfile(os.path.join("experiments", d, "main.c")))
    wall = wall_seconds(doc)
    units = []
    for x in names:
        if not os.access(os.path.join(build, x), os.X_OK):
            die("%s/%s: not built (run: make %s/%s)" % (build, x, build, x))
        w = max(wall.get(x, 1.0), 1.0)  # an experiment with no recorded time (or 0 s) weighs 1 s
        cells = list_cells(build, x, mode, None)
        if cells is None:
            die("%s --list-cells failed" % x)
        c = len(cells)
        k = min(c, 4 * n)
        listed = list_cells(build, x, mode, "1/%d" % k) if k >= 1 else None
        if listed is None:  # cannot shard: one unit
            units.append((w, x, 0, 0, [int(r[0]) for r in cells]))
            continue
        total = sum(float(r[4]) for r in listed) or 1.0
        load = [0.0] * (k + 1)
        members = [[] for _ in range(k + 1)]
        for r in listed:
            load[int(r[5])] += float(r[4])
            members[int(r[5])].append(int(r[0]))
        for j in range(1, k + 1):
            units.append((w * load[j] / total, x, j, k, members[j]))
    units.sort(key=lambda u: (-u[0], u[1], u[2]))
    groups = [0.0] * n
    out = []
    for cost, x, j, k, cells in units:
        g = min(range(n), key=lambda i: (groups[i], i))
        groups[g] += cost
        out.append((g + 1, x, j, k, cost, cells))
    return out


def main():
    if len(sys.argv) != 5:
        die("usage: all-plan.py BUILD MODE N DOC")
    for g, x, j, k, cost, _ in plan(sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]):
        print("%d %s %d %d %.3f" % (g, x, j, k, cost))


if __name__ == "__main__":
    main()
