#!/usr/bin/env python3
"""Simulated makespans of the whole run in N groups, from recorded cell times.

  scripts/makespan.py [--build BUILD] [--ns 2,4,8,16] DIR

DIR: a recorded run, either the work folder of a whole run
(scripts/parallel-run.sh all N or scripts/slurm-submit.sh all N;
scripts/all-run.sh), whose mode file says the run's mode, with every shard
unit's <experiment>.csv.cells (each cell's measured seconds, the last field
of its line) and every whole unit's 'seconds' (bending, which cannot shard);
or a results folder of make experiments, whose <experiment>.runtime files
list every cell's seconds (and bending's wall_s). For each N, the two plans
the runners can make now (scripts/lib/all-plan.py: by hints times the
recorded wall times, columns hints_s; and with --times DIR, by these
recorded cell times, columns times_s) are applied to the measured seconds:
the makespan is the largest group's sum. It is compared with the bound
max(total/N, the largest piece that must run as one: a cell, or a whole
experiment); the target is 1.2 x the bound. A simulation: process starts and
set-up outside the cells are not in it, and the times plan is judged on the
times it was made from. Also printed: the largest pieces, which set the bound
at large N.
"""
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
    rec_cells, rec_whole, mode = allplan.recorded_times(d)
    if mode is None:
        die("%s: neither a work folder of scripts/all-run.sh (no mode file) nor a results folder (no .runtime)" % d)
    if mode not in ("", "--quick", "--smoke"):
        die("%s/mode: '%s', expected -, --quick or --smoke" % (d, mode))
    # the measured pieces: (experiment, cell) -> seconds; whole experiments (no cell times) -> seconds
    cell_s = {(x, g): s for x, c in rec_cells.items() for g, s in c.items()}
    whole_s = {x: s for x, s in rec_whole.items() if x not in rec_cells}
    if not cell_s and not whole_s:
        die("%s: no recorded times (no <experiment>/shard-*/*.cells, no whole/seconds, no .runtime)" % d)
    total = sum(cell_s.values()) + sum(whole_s.values())
    pieces = sorted([(s, "%s cell %d" % k) for k, s in cell_s.items()] + [(s, "%s (whole)" % x) for x, s in whole_s.items()], reverse=True)
    print("recorded: %d cells and %d whole experiments, %.1f s in all (%s run; a simulation from these times)" %
          (len(cell_s), len(whole_s), total, mode.strip("-") or "full"))
    print("largest pieces that run as one: " + ", ".join("%s %.1f s" % (n, s) for s, n in pieces[:5]))
    print("%4s %10s %10s %10s %10s %8s %8s" % ("N", "total/N_s", "bound_s", "hints_s", "times_s", "hints/b", "times/b"))
    doc = os.path.join(root, "docs", "running.md")
    for n in ns:
        got = []
        for times in (None, (rec_cells, rec_whole, mode)):
            groups = [0.0] * n
            for g, x, j, k, cost, cells in allplan.plan(build, mode, n, doc, times):
                if j == 0:
                    if x not in whole_s:
                        die("%s: no recorded time of the whole experiment" % x)
                    groups[g - 1] += whole_s[x]
                else:
                    for c in cells:
                        if (x, c) not in cell_s:
                            die("%s cell %d: no recorded time (the run's cells differ from the program's now)" % (x, c))
                        groups[g - 1] += cell_s[(x, c)]
            got.append(max(groups))
        bound = max(total / n, pieces[0][0])
        print("%4d %10.2f %10.2f %10.2f %10.2f %8.3f %8.3f" % (n, total / n, bound, got[0], got[1], got[0] / bound, got[1] / bound))


main()
