#!/usr/bin/env python3
"""The plan of a whole run in N groups (scripts/all-run.sh plan; not run by hand).

  all-plan.py BUILD MODE N DOC [--times DIR]

Every experiment (experiments/*/main.c) is cut into units: a shardable one
into k shards of its own balanced assignment (--shard j/k, so its merge is
scripts/merge-shards.sh's, unchanged), one that cannot shard (bending) is one
unit. The units go to the N groups by the longest-processing-time rule
(largest first, to the least-loaded group). Prints one line per unit:
"group experiment j k cost" (j = k = 0: whole).

A unit's cost, without --times: its cells' hints over the experiment's hint
total, times the experiment's recorded wall seconds (the run-time table of
DOC, docs/running.md, the last full run: hints are relative within one
experiment only); k = min(cells, 4N).

With --times DIR, a recorded run of the same mode (recorded_times below: a
results folder whose <experiment>.runtime files list every cell's seconds,
or a whole-run work folder of scripts/all-run.sh): an experiment whose every
cell has a recorded time is balanced by those times. Its unit's cost is the
sum of its cells' recorded seconds, and k is the smallest of min(cells, 4N),
min(cells, 8N) and cells whose largest unit is at most max(its largest cell,
the recorded total / 4N); at k = cells each unit is one cell (the balanced
assignment gives every cell its own shard), so the groups are the
longest-processing-time rule on the cells themselves. An experiment without
a full set of recorded times (a cell added since, another mode) falls back
to the hints; a whole unit costs its recorded wall seconds.
"""
import glob
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


def recorded_times(d):
    """({experiment: {global cell: seconds}}, {experiment: whole seconds}, mode or None) of a recorded run:
    DIR/<x>.runtime "cell <index> <timed> <seconds> <sweep>" lines and wall_s (make experiments), or
    DIR/<x>/shard-*/<x>.csv.cells (each line's last field) and DIR/<x>/whole/seconds (scripts/all-run.sh)."""
    cells, whole, mode = {}, {}, None
    try:
        names = sorted(os.listdir(d))
    except OSError:
        die("--times %s: not a folder" % d)
    if os.path.exists(os.path.join(d, "mode")):
        m = open(os.path.join(d, "mode")).read().strip()
        mode = "" if m == "-" else m
    for f in names:
        p = os.path.join(d, f)
        if f.endswith(".runtime") and os.path.isfile(p):
            x, c, wall, quick = f[: -len(".runtime")], {}, None, None
            for ln in open(p).read().splitlines():
                r = ln.split()
                try:
                    if len(r) == 5 and r[0] == "cell":
                        c[int(r[1])] = float(r[3])
                    elif len(r) == 2 and r[0] == "wall_s:":
                        wall = float(r[1])
                    elif len(r) == 2 and r[0] == "quick:":
                        quick = int(r[1])
                except ValueError:
                    die("%s: not a run-time file (line '%s')" % (p, ln))
            if c:
                cells[x] = c
            if wall is not None:
                whole[x] = wall
            if quick is not None and mode is None:
                mode = "--quick" if quick else ""
        elif os.path.isdir(p) and f not in ("logs", "locks", "jobs"):
            w = os.path.join(p, "whole", "seconds")
            if os.path.exists(w):
                whole[f] = float(open(w).read())
            for sh in sorted(glob.glob(os.path.join(p, "shard-*", f + ".csv.cells"))):
                for line in open(sh).read().splitlines()[2:]:
                    r = line.split()
                    cells.setdefault(f, {})[int(r[0])] = float(r[-1])
    return cells, whole, mode


def units_of(build, x, mode, k, cost_of):
    """The k units (--shard j/k) of experiment x: [(cost, j, [global cells])], or None if it cannot shard."""
    listed = list_cells(build, x, mode, "1/%d" % k) if k >= 1 else None
    if listed is None:
        return None
    members = [[] for _ in range(k + 1)]
    for r in listed:
        members[int(r[5])].append((int(r[0]), float(r[4])))
    return [(sum(cost_of(g, h) for g, h in members[j]), j, [g for g, _ in members[j]]) for j in range(1, k + 1)]


def plan(build, mode, n, doc, times=None):
    """[(group, experiment, j, k, cost, [global cell indices])], in the order assigned. times: recorded_times()."""
    names = sorted(d for d in os.listdir("experiments") if os.path.isfile(os.path.join("experiments", d, "main.c")))
    wall = wall_seconds(doc)
    rec_cells, rec_whole = (times[0], times[1]) if times else ({}, {})
    units = []
    for x in names:
        if not os.access(os.path.join(build, x), os.X_OK):
            die("%s/%s: not built (run: make %s/%s)" % (build, x, build, x))
        cells = list_cells(build, x, mode, None)
        if cells is None:
            die("%s --list-cells failed" % x)
        c = len(cells)
        rec = rec_cells.get(x, {})
        if c and all(int(r[0]) in rec for r in cells) and len(rec) == c:  # balanced by the recorded cell times
            total = sum(rec.values())
            target = max(max(rec.values()), total / (4 * n))
            got = None
            for k in sorted({min(c, 4 * n), min(c, 8 * n), c}):
                got = units_of(build, x, mode, k, lambda g, h: rec[g])
                if got is None or max(u[0] for u in got) <= target:
                    break
            if got is not None:
                units += [(cost, x, j, len(got), members) for cost, j, members in got]
                continue
        w = max(wall.get(x, 1.0), 1.0)  # an experiment with no recorded time (or 0 s) weighs 1 s
        k = min(c, 4 * n)
        got = units_of(build, x, mode, k, lambda g, h: h)
        if got is None:  # cannot shard: one unit
            units.append((rec_whole.get(x, w), x, 0, 0, [int(r[0]) for r in cells]))
            continue
        hint_total = sum(u[0] for u in got) or 1.0
        units += [(w * cost / hint_total, x, j, k, members) for cost, j, members in got]
    units.sort(key=lambda u: (-u[0], u[1], u[2]))
    groups = [0.0] * n
    out = []
    for cost, x, j, k, cells in units:
        g = min(range(n), key=lambda i: (groups[i], i))
        groups[g] += cost
        out.append((g + 1, x, j, k, cost, cells))
    return out


def main():
    args = sys.argv[1:]
    times = None
    if len(args) == 6 and args[4] == "--times":
        times = recorded_times(args[5])
        if times[2] is not None and (times[2] != args[1] if times[2] != "--quick" else args[1] == ""):  # .runtime: quick or not
            die("--times %s: a %s run, the plan is for a %s run" % (args[5], times[2].strip("-") or "full",
                                                                    args[1].strip("-") or "full"))
        args = args[:4]
    if len(args) != 4:
        die("usage: all-plan.py BUILD MODE N DOC [--times DIR]")
    for g, x, j, k, cost, _ in plan(args[0], args[1], int(args[2]), args[3], times):
        print("%d %s %d %d %.3f" % (g, x, j, k, cost))


if __name__ == "__main__":
    main()
