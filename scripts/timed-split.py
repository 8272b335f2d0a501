#!/usr/bin/env python3
"""Seconds in timed and untimed cells, per experiment, and the whole run's lower bound on C cores.

  scripts/timed-split.py [--cores C] [--shares DIR] [--doc FILE] RESULTS_DIR

RESULTS_DIR holds a run's <experiment>.runtime files (make experiments writes
them: "wall_s:", then the process's <out>.split: "timed_cells_s:",
"untimed_cells_s:", "cell_locks:" and one "cell <index> <timed> <seconds>
<sweep>" line per cell). A cell is timed when it holds the CPU lock
exclusively (it times a comparison: nothing runs beside it), untimed when it
holds it shared (lib/io/experiment.h, cb_experiment_timed_cells).

Per experiment: timed = the seconds of its timed cells; untimed = those of
its untimed cells plus the time outside cells (process start, set-up, writing
the CSVs), which holds no exclusive lock; the seconds it waited for the lock
("lock_wait_s:") are not work and count for neither. An experiment that locks as a whole
(bending; or any experiment in a run made before it locked per cell) counts
its whole wall time as timed (or, holding the lock shared, as untimed).

--shares DIR: for an experiment that RESULTS_DIR recorded before it locked per
cell while DIR's run locked it per cell, its cell seconds are split by DIR's
untimed share of cell seconds instead (an estimate; the row says so).

The bound. make experiments runs each experiment as one process (its cells one
after another), or as several (RUN_SHARDS: its .runtime then records
"processes:", "untimed_work_s:" over all of them and "longest_untimed_s:", one
process's share), and at most C processes at a time. A timed cell has the machine to
itself, so during the T seconds of timed cells nothing else runs, and all
untimed work (U seconds in all) happens in the other wall - T seconds: on at
most C cores, so U <= C (wall - T), and one process's untimed seconds u
run one after another, so u <= wall - T. So

  wall >= T + max(U / C, the largest u of one experiment).

It assumes untimed work is no slower beside other work than alone (two cores
share caches and memory bandwidth: it is a little slower), so it is a lower
bound, not a prediction. --doc FILE writes the table between FILE's
<!-- timed-split:begin --> and <!-- timed-split:end --> markers.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cbreadme import write_block  # noqa: E402


def die(msg):
    print("timed-split: " + msg, file=sys.stderr)
    sys.exit(2)


def read_runtime(path):
    """{'wall', 'timed', 'untimed', 'cell_locks', 'quick', 'cells': [(index, timed, seconds, sweep)]} or None."""
    try:
        lines = open(path).read().splitlines()
    except OSError:
        return None
    r = {"cells": []}
    for ln in lines:
        f = ln.split()
        try:
            if f and f[0] == "cell" and len(f) == 5:
                r["cells"].append((int(f[1]), int(f[2]), float(f[3]), f[4]))
            elif len(f) == 2 and f[0].endswith(":"):
                r[f[0][:-1]] = float(f[1])
        except ValueError:
            die("%s: not a run-time file (line '%s')" % (path, ln))
    if "wall_s" not in r:
        die("%s: no wall_s line" % path)
    return r


def split(r):
    """(timed, untimed, cell seconds, per cell) of one recorded run, or None when it records no split."""
    if "timed_cells_s" not in r:
        return None
    t, u = r["timed_cells_s"], r["untimed_cells_s"]
    return t, u, t + u, int(r.get("cell_locks", 0))


def fmt(s):
    if s >= 60:
        return "%d min %02d s" % (s // 60, round(s % 60)) if round(s % 60) < 60 else "%d min 00 s" % (s // 60 + 1)
    return "%.1f s" % s


def table(results, cores, shares):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    names = sorted(d for d in os.listdir(os.path.join(root, "experiments"))
                   if os.path.isfile(os.path.join(root, "experiments", d, "main.c")))
    rows = []
    for x in names:
        r = read_runtime(os.path.join(results, x + ".runtime"))
        if r is None:
            continue
        wall, sp = r["wall_s"], split(r)
        if sp is None:  # no split recorded: the whole wall time, of unknown kind, counted timed (the safe side)
            rows.append((x, wall, wall, 0.0, "no split recorded: all counted timed", 0.0))
            continue
        t, u, cells, per_cell = sp
        if "untimed_work_s" in r:  # run as several processes (scripts/shard-runtime.sh)
            n = int(r.get("processes", 1))
            rows.append((x, wall, t, r["untimed_work_s"], "recorded per cell, %d processes" % n,
                         r.get("longest_untimed_s", r["untimed_work_s"])))
            continue
        outside = max(wall - cells - r.get("lock_wait_s", 0.0), 0.0)  # waiting for the lock is not work
        src = "recorded per cell" if per_cell else "locks as a whole"
        if not per_cell and shares:
            q = read_runtime(os.path.join(shares, x + ".runtime"))
            qs = split(q) if q else None
            if qs and qs[3] and qs[2] > 0:
                share = qs[1] / qs[2]
                t, u = cells * (1 - share), cells * share
                per_cell = 1
                src = "estimated: %.0f %% untimed, the share in %s" % (100 * share, os.path.basename(os.path.normpath(shares)))
        if per_cell:
            rows.append((x, wall, t, u + outside, src, u + outside))
        elif t > 0:  # one exclusive lock for the whole process
            rows.append((x, wall, wall, 0.0, src + " (timed)", 0.0))
        else:
            rows.append((x, wall, 0.0, wall, src + " (untimed)", wall))
    if not rows:
        die("%s: no <experiment>.runtime files" % results)
    T = sum(r[2] for r in rows)
    U = sum(r[3] for r in rows)
    longest = max(rows, key=lambda r: r[5])
    b = T + max(U / cores, longest[5])
    out = ["| experiment | wall time | timed | untimed | source |", "|---|---|---|---|---|"]
    for x, wall, t, u, src, _ in rows:
        out.append("| %s | %s | %s | %s | %s |" % (x, fmt(wall), fmt(t), fmt(u), src))
    out.append("| all, one after another | %s | %s | %s | |" % (fmt(sum(r[1] for r in rows)), fmt(T), fmt(U)))
    out.append("")
    out.append("Lower bound on %d cores: timed + max(untimed/%d, one process's untimed) = %s + max(%s, %s (%s)) "
               "= **%s**." % (cores, cores, fmt(T), fmt(U / cores), fmt(longest[5]), longest[0], fmt(b)))
    return "\n".join(out) + "\n", b


def main():
    args = sys.argv[1:]
    cores, shares, doc = 2, None, None
    while args and args[0].startswith("--"):
        if len(args) < 2:
            die("%s needs a value" % args[0])
        if args[0] == "--cores":
            try:
                cores = int(args[1])
            except ValueError:
                cores = 0
            if cores < 1:
                die("--cores '%s': expected a positive number" % args[1])
        elif args[0] == "--shares":
            shares = args[1]
        elif args[0] == "--doc":
            doc = args[1]
        else:
            die("unknown option " + args[0])
        args = args[2:]
    if len(args) != 1:
        die("usage: timed-split.py [--cores C] [--shares DIR] [--doc FILE] RESULTS_DIR")
    text, _ = table(args[0], cores, shares)
    if doc:
        opts = ("" if cores == 2 else " --cores %d" % cores) + (" --shares " + shares if shares else "")
        head = "Generated by `scripts/timed-split.py%s --doc %s %s`.\n\n" % (opts, doc, args[0])
        return write_block(doc, "timed-split", head + text, "timed-split")
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
