#!/usr/bin/env python3
"""Simulated makespans of the whole run in N groups, from recorded cell times.

  scripts/makespan.py [--build BUILD] [--ns 2,4,8,16] DIR

DIR: the work folder of a whole run (scripts/parallel-run.sh all N or
scripts/slurm-submit.sh all N; scripts/all-run.sh), whose plan says the run's
mode. Its recorded times: every shard unit's <experiment>.csv.cells (each
cell's measured seconds, the last field of its line) and every whole unit's
'seconds' (bending, which cannot shard). For each N, the plan the runners
would make now (scripts/lib/all-plan.py: units balanced by hints times the
recorded wall times) is applied to the measured seconds: the makespan is the
largest group's sum. It is compared with the bound max(total/N, the largest
piece that must run as one: a cell, or a whole experiment). A simulation:
process starts and setup outside the cells are not in it. Also printed: the
largest pieces, which set the bound at large N.
"""
import glob
import importlib.util
import os
import sys


def die(msg):
    print("makespan: " + msg, file=sys.stderr)
    sys.exit(2)


def main():
    args = sys.argv[1:]
    build, ns = os.environ.get("BUILD", "build"), [2, 4, 8, 16]
    while args and args[0].startswith("--"):
        if args[0] == "--build" and len(args) > 1:
            build = args[1]
            args = args[2:]
        elif args[0] == "--ns" and len(args) > 1:
            try:
                ns = [int(v) for v in args[1].split(",")]
            except ValueError:
                die("--ns '%s': expected numbers such as 2,4,8,16" % args[1])
            if not ns or min(ns) < 1:
                die("--ns: each N must be positive")
            args = args[2:]
        else:
            die("unknown option " + args[0])
    if len(args) != 1:
        die("usage: makespan.py [--build BUILD] [--ns 2,4,8,16] DIR")
    d = args[0]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    spec = importlib.util.spec_from_file_location("allplan", os.path.join(root, "scripts", "lib", "all-plan.py"))
    allplan = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(allplan)
    try:
        mode = open(os.path.join(d, "mode")).read().strip()
    except OSError:
        die("%s/mode: missing (not a work folder of scripts/all-run.sh)" % d)
    if mode not in ("-", "--quick", "--smoke"):
        die("%s/mode: '%s', expected -, --quick or --smoke" % (d, mode))
    mode = "" if mode == "-" else mode
    # the measured pieces: (experiment, cell) -> seconds; whole experiments -> seconds
    cell_s, whole_s = {}, {}
    for x in sorted(os.listdir(d)):
        if not os.path.isdir(os.path.join(d, x)) or x in ("logs", "locks", "jobs"):
            continue
        w = os.path.join(d, x, "whole", "seconds")
        if os.path.exists(w):
            whole_s[x] = float(open(w).read())
            continue
        for f in glob.glob(os.path.join(d, x, "shard-*", x + ".csv.cells")):
            for line in open(f).read().splitlines()[2:]:
                r = line.split()
                cell_s[(x, int(r[0]))] = float(r[-1])
    if not cell_s and not whole_s:
        die("%s: no recorded times (no <experiment>/shard-*/*.cells, no whole/seconds)" % d)
    total = sum(cell_s.values()) + sum(whole_s.values())
    pieces = sorted([(s, "%s cell %d" % k) for k, s in cell_s.items()] + [(s, "%s (whole)" % x) for x, s in whole_s.items()], reverse=True)
    print("recorded: %d cells and %d whole experiments, %.1f s in all (%s run; a simulation from these times)" %
          (len(cell_s), len(whole_s), total, mode.strip("-") or "full"))
    print("largest pieces that run as one: " + ", ".join("%s %.1f s" % (n, s) for s, n in pieces[:5]))
    print("%4s %12s %12s %12s %8s" % ("N", "makespan_s", "total/N_s", "bound_s", "ratio"))
    for n in ns:
        groups = [0.0] * n
        for g, x, j, k, cost, cells in allplan.plan(build, mode, n, os.path.join(root, "docs", "running.md")):
            if j == 0:
                if x not in whole_s:
                    die("%s: no recorded time of the whole experiment" % x)
                groups[g - 1] += whole_s[x]
            else:
                for c in cells:
                    if (x, c) not in cell_s:
                        die("%s cell %d: no recorded time (the run's cells differ from the program's now)" % (x, c))
                    groups[g - 1] += cell_s[(x, c)]
        bound = max(total / n, pieces[0][0])
        print("%4d %12.2f %12.2f %12.2f %8.3f" % (n, max(groups), total / n, bound, max(groups) / bound))


main()
