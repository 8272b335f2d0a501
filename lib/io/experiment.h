/* What every experiment program shares: its command line, its CSV tables
 * (opened atomically with the provenance lines), progress, config loading
 * and sharding.
 *
 * Common options:
 *   --quick        reduced sweep (QUICK=1 in the environment does the same)
 *   --smoke        the smallest run that still writes every table and column:
 *                  one small cell of each sweep (make test's tier). Sets quick
 *                  too, so an experiment reads e->smoke only where its smoke
 *                  run must be smaller than its quick one.
 *   --out PATH     main CSV (default results/<name>.csv)
 *   --configs DIR  folder holding hanging.ini etc. (default configs)
 *   --shard I/N    run only shard I's share (I in 1..N) of the cells of the
 *                  experiment's sweeps (sweep.h): balanced by the cost hints
 *                  (default), or --shard-mode modulo, the cells with index
 *                  % N == I - 1; default --out is then
 *                  results/shard-<I>of<N>/<name>.csv. scripts/merge-shards.sh
 *                  merges the shards' CSVs into the unsharded ones.
 *   --shard-mode balanced|modulo
 *   --list-cells   prints every cell (global index, sweep group, sweep, index
 *                  in the sweep, cost hint, shard under --shard ./N, and 1
 *                  if the cell is timed, 0 if not: see
 *                  cb_experiment_timed_cells) and exits 0 without running a cell or writing a file
 *   --help         usage and what the experiment decides
 *
 * Tables: an experiment opens every CSV it writes with cb_experiment_table
 * before its first sweep, writes rows only from inside sweep cells, and ends
 * with cb_experiment_end, which commits (or on error drops) them all. Under
 * --shard, cb_experiment_end also writes <out>.cells: which cells this shard
 * ran and how many rows each wrote to each table (the merge's key; the CSVs
 * themselves are unchanged). */
#ifndef CB_EXPERIMENT_H
#define CB_EXPERIMENT_H

#include <stdio.h>

#include "config.h"
#include "outfile.h"
#include "progress.h"

enum { CB_EXPERIMENT_MAX_TABLES = 8 };
enum { CB_SHARD_BALANCED = 0, CB_SHARD_MODULO = 1 }; /* --shard-mode (sweep.h) */

typedef struct cb_experiment {
  const char *name;
  int quick;
  int smoke; /* --smoke: one small cell per sweep (implies quick = 1) */
  int scale; /* --scale or SCALE=1: the sizes past the full run's too (J4's 1024^2), where an experiment has them */
  char out[2048];
  const char *configs;
  int argc;
  char **argv;
  int shard, nshards;         /* --shard I/N: I in 1..N; 0 and 1 when not sharded */
  int shard_mode;             /* --shard-mode: CB_SHARD_BALANCED (default) or CB_SHARD_MODULO */
  int list_cells;             /* --list-cells: print the cells (hint, shard), run none, write nothing */
  int timed;                  /* 1 after cb_experiment_timed: it holds the CPU lock exclusively */
  int cell_locks;             /* 1 after cb_experiment_timed_cells: each cell takes the lock for itself */
  int lock_fd;                /* the CPU lock (cb_experiment_begin takes it shared), or -1 */
  int turn_fd;                /* the turnstile beside it (CB_CPU_LOCK.turn), or -1: see cb_experiment_timed_cells */
  int lock_held;              /* the lock this process holds now: 0 none, LOCK_SH or LOCK_EX */
  int waited_msg;             /* the "waiting for" message was printed once for cells */
  double cell_s[2];           /* wall seconds in this process's cells: [0] untimed, [1] timed */
  double lock_wait_s;         /* wall seconds spent waiting for the CPU lock (and its turnstile) */
  const char *const *untimed; /* cb_experiment_timed_cells: the sweeps whose cells time nothing */
  unsigned untimed_seen;      /* bit k: untimed[k] named a sweep that ran */
  cb_outfile csv;             /* for programs that write one CSV themselves (bench) */
  cb_progress progress;
  /* tables (cb_experiment_table), in the order opened */
  int ntables;
  cb_outfile table[CB_EXPERIMENT_MAX_TABLES];
  char table_name[CB_EXPERIMENT_MAX_TABLES][32]; /* "" = the main CSV, else its side suffix */
  /* sweep bookkeeping (sweep.c): cells declared so far over all sweeps, and
   * the "<cell> <rows per table>" lines of the cells this shard ran */
  long ncells;
  int nsweep_runs;    /* cb_sweep_run calls so far */
  double *shard_load; /* balanced mode: the hinted load of each shard so far */
  char *cells_log;
  size_t cells_len;
  FILE *cells;
  /* every cell this process ran, sharded or not: "cell <global> <timed> <seconds> <sweep>" lines of <out>.split */
  char *times_log;
  size_t times_len;
  FILE *times;
} cb_experiment;

/* Returns 0 to go on, 1 when --help or --version was printed (exit 0),
 * negative on a bad option (message printed; exit 1). about: a paragraph for
 * --help. Takes the CPU lock shared (see cb_experiment_timed). */
int cb_experiment_begin(cb_experiment *e, const char *name, const char *about, int argc, char **argv);

/* For an experiment whose numbers include wall times: converts the CPU lock
 * that cb_experiment_begin took shared into an exclusive one, waiting (with
 * a message) until no other clothbench experiment or bench runs, and holds it
 * to the end of the process. So under `make -j2 experiments` a timed
 * experiment never shares the CPU with another one, and an untimed one runs
 * beside other untimed ones only. The lock is the file CB_CPU_LOCK (default
 * /tmp/clothbench-cpu.lock); its use is recorded as "# cpu_lock:" in
 * every CSV. Call it right after cb_experiment_begin. */
void cb_experiment_timed(cb_experiment *e);

/* The finer alternative to cb_experiment_timed, for an experiment whose every
 * wall time is measured inside sweep cells: the lock is taken per cell, not
 * for the whole process. untimed names the sweeps whose cells measure no
 * wall time that a claim compares (NULL-terminated, or NULL for none; at
 * most 32; a name that matches no sweep of the run is an error at
 * cb_experiment_end, so a typo cannot pass). A sweep with a timed() callback
 * (sweep.h) decides per cell instead. A cell of any other sweep (the safe
 * default) holds the lock exclusively while it
 * runs; a cell of an untimed sweep holds it shared, beside other untimed
 * cells and experiments. So under
 * `make experiments JOBS=2` the untimed cells fill the other core and never
 * run beside a timed cell. Every acquisition passes a turnstile (the file
 * CB_CPU_LOCK.turn) that an exclusive waiter holds while it waits, so a
 * stream of shared cells cannot starve a timed one. Call it right after
 * cb_experiment_begin; the process's shared lock from cb_experiment_begin is
 * let go when the first sweep starts. */
void cb_experiment_timed_cells(cb_experiment *e, const char *const *untimed);
/* 1 if sweep is one of the untimed sweeps (cb_experiment_timed_cells). */
int cb_experiment_sweep_untimed(cb_experiment *e, const char *sweep);

/* For the sweep runner: the lock around one cell (exclusive when timed) and
 * its release; no-ops unless cb_experiment_timed_cells was called. */
void cb_experiment_cell_lock(cb_experiment *e, int timed);
void cb_experiment_cell_unlock(cb_experiment *e);
/* For the sweep runner: lets go of cb_experiment_begin's process-wide shared
 * lock once cells take their own (cb_experiment_timed_cells). */
void cb_experiment_cells_start(cb_experiment *e);

/* Opens a CSV at path (NULL = the main --out path): provenance lines,
 * "# experiment:", "# quick:", the caller's extra "# ..." lines (may be
 * NULL), then the header row. For programs that do not use the sweep runner:
 * under --shard (such a program cannot be sharded) it prints why and exits
 * with the usage code 1, and under --list-cells (it has no cells to list) it
 * exits 0, before anything is written. */
int cb_experiment_csv(cb_experiment *e, cb_outfile *o, const char *path, const char *extra, const char *header);

/* Opens table number e->ntables: the main CSV (name NULL) or the side table
 * <stem>_<name>.csv, with the provenance lines of cb_experiment_csv. Returns
 * the table's index (>= 0), the index sweep cells write it through, or a
 * negative status. */
int cb_experiment_table(cb_experiment *e, const char *name, const char *extra, const char *header);

/* st == 0: commits every table (and, under --shard, writes <out>.cells);
 * returns 0 or CB_EIO. st != 0: drops every table and returns st. Prints
 * "<name>: <message>" on any error. */
int cb_experiment_end(cb_experiment *e, int st);

/* <configs>/<file>, then the NULL-terminated "section.key=value" overrides.
 * Experiments load their scenes through cb_scene_decl_config (scene_decl.h). */
int cb_experiment_config(const cb_experiment *e, const char *file, const char *const *sets, cb_config *out);

/* Path of a side output next to the main CSV: results/<name>_<suffix>. */
void cb_experiment_side_path(const cb_experiment *e, const char *suffix, char *buf, size_t n);

#endif
