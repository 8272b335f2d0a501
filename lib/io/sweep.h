/* The sweep runner: an experiment describes its work as cells, the runner
 * executes them, shows one progress line for the whole experiment and writes
 * every cell's rows to the experiment's tables in cell order.
 *
 * A sweep (a phase of an experiment) is a count of cells and a callback
 * run_cell(i, ctx, out): cell i of the sweep writes its rows to out[t] for
 * table t (the index cb_experiment_table returned), and returns 0 or a
 * status (non-zero stops the run; the message names the sweep and cell).
 * A cell must not depend on another cell having run: under --shard I/N only
 * shard I's cells run. Which cells those are is a pure function of the
 * cells, their cost hints and N, so every shard computes it alone: by
 * default (--shard-mode balanced) the longest-processing-time rule, the
 * cells of a cb_sweep_run call by decreasing hint (cell order on ties), each
 * to the shard with the least hinted load so far (the lowest shard on ties);
 * with --shard-mode modulo the cells whose global index (counted over all
 * the sweeps of the experiment, in order) is I - 1 modulo N. A shared input
 * (a reference trajectory, a captured system) is computed by each cell that
 * needs it, or the cells that share it are made one cell.
 *
 * Cost hints are relative (any unit, one scale per experiment); they balance
 * the shards and weight the progress estimate. scripts/calibrate-hints
 * compares them with the seconds measured per cell (in <out>.cells).
 *
 * The runner buffers each cell's rows and appends them to the tables when
 * the cell ends, so the tables hold the rows in cell order; under --shard it
 * notes, per cell, how many rows went to each table, the hint and the
 * measured wall seconds (cb_experiment_end writes the note as <out>.cells),
 * which is what scripts/merge-shards.sh interleaves the shards by. The CSVs themselves are the same bytes as the
 * unsharded run's rows for those cells. */
#ifndef CB_SWEEP_H
#define CB_SWEEP_H

#include <stdio.h>

#include "experiment.h"
#include "scene_decl.h"

typedef struct cb_sweep {
  const char *name; /* the phase, e.g. "regime" (progress and errors) */
  long ncells;
  int (*run_cell)(long i, void *ctx, FILE *const *out);
  double (*cost)(long i, void *ctx); /* relative cost hint of cell i; NULL = 1 for every cell */
  void *ctx;
  /* Per cell, under cb_experiment_timed_cells: 1 if cell i measures a wall
   * time that a claim compares (it holds the CPU lock exclusively: nothing
   * runs beside it), 0 if it does not (shared: it runs beside other untimed
   * cells and experiments). NULL: every cell of the sweep is timed unless
   * the sweep is named in cb_experiment_timed_cells' untimed list. For a
   * sweep whose cells are of several kinds (explicit_stability's map: an
   * explicit sweep, Newton runs, E2 timings). */
  int (*timed)(long i, void *ctx);
} cb_sweep;

/* Runs the sweeps in order (the cells of this shard), with one progress line
 * over all of them, whose estimate is weighted by the cost hints. Every
 * table must be open before. Returns 0 or the first failing cell's status. */
int cb_sweep_run(cb_experiment *e, const cb_sweep *sweeps, int nsweeps);

/* The size of a declared scene, for cost hints: its config's vertices
 * (cb_scene_decl_vertices), grid side (mesh.n), vertices / 441 (the lab
 * cloth's 21^2, the unit the hints of newton_vs_bw and nonlinear are
 * measured in) and dt. Computed before any cell runs, so a bad declaration
 * fails there, naming the scene. Returns 0 or the config's error status. */
typedef struct cb_scene_size {
  long nv;
  int mesh_n;
  double rel, dt;
} cb_scene_size;
int cb_sweep_scene_size(const cb_experiment *e, const cb_scene_decl *d, cb_scene_size *out);

#endif
