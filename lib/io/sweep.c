#include "sweep.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <clothbench/status.h>

static double cell_cost(const cb_sweep *s, long i) {
  double c = s->cost ? s->cost(i, s->ctx) : 1.0;
  return c > 0 ? c : 0;
}

/* 1 if cell i of s is timed: its sweep's own answer, else by the sweep's name */
static int cell_timed(cb_experiment *e, const cb_sweep *s, long i) {
  return s->timed ? s->timed(i, s->ctx) != 0 : !cb_experiment_sweep_untimed(e, s->name);
}

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Runs one cell into per-table memory streams, then appends them in order.
 * Under --shard the cell's line of <out>.cells: its global index, the rows it
 * wrote to each table, the sweep group (the cb_sweep_run call), the sweep's
 * name and local index, the cost hint and the measured wall seconds. */
static int run_one(cb_experiment *e, const cb_sweep *s, long i, long global, double hint) {
  FILE *out[CB_EXPERIMENT_MAX_TABLES] = {NULL};
  char *buf[CB_EXPERIMENT_MAX_TABLES] = {NULL};
  size_t len[CB_EXPERIMENT_MAX_TABLES] = {0};
  int st = CB_OK;
  double secs = 0;
  for (int t = 0; st == CB_OK && t < e->ntables; t++)
    if (!(out[t] = open_memstream(&buf[t], &len[t]))) st = cb_fail_status(CB_ENOMEM, "out of memory for cell rows");
  if (st == CB_OK) {
    int timed = cell_timed(e, s, i);
    cb_experiment_cell_lock(e, timed);
    double t0 = now_s();
    st = s->run_cell(i, s->ctx, out);
    secs = now_s() - t0;
    cb_experiment_cell_unlock(e);
    e->cell_s[timed] += secs;
    /* the cell's kind as the lock saw it: with one lock for the whole process, the process's kind */
    int kind = e->cell_locks ? timed : e->timed;
    if (!e->times) e->times = open_memstream(&e->times_log, &e->times_len); /* none: <out>.split lacks the lines */
    if (e->times) {
      fprintf(e->times, "cell %ld %d %.6f ", global, kind, secs);
      for (const char *c = s->name; *c; c++) fputc(*c == ' ' || *c == '\t' || *c == '\n' ? '_' : *c, e->times);
      fputc('\n', e->times);
    }
    if (st) {
      char msg[1024];
      snprintf(msg, sizeof msg, "%s", cb_error_message());
      cb_fail_status(st, "%s cell %ld: %s", s->name, i, msg);
    }
  }
  for (int t = 0; t < e->ntables; t++)
    if (out[t] && fclose(out[t]) && st == CB_OK) st = cb_fail_status(CB_ENOMEM, "cell rows: write failed");
  if (st == CB_OK && e->shard) fprintf(e->cells, "%ld", global);
  for (int t = 0; t < e->ntables; t++) {
    if (st == CB_OK) {
      fwrite(buf[t], 1, len[t], e->table[t].f);
      long rows = 0;
      for (size_t k = 0; k < len[t]; k++) rows += buf[t][k] == '\n';
      if (e->shard) fprintf(e->cells, " %ld", rows);
    }
    free(buf[t]);
  }
  if (st == CB_OK && e->shard) {
    fprintf(e->cells, " %d ", e->nsweep_runs);
    for (const char *c = s->name; *c; c++) fputc(*c == ' ' || *c == '\t' || *c == '\n' ? '_' : *c, e->cells);
    fprintf(e->cells, " %ld %.17g %.6f\n", i, hint, secs);
  }
  return st;
}

typedef struct {
  long global;
  double cost;
} job;

/* largest cost first; equal costs in cell order (a total order: the sort's result does not depend on qsort) */
static int by_cost_desc(const void *a, const void *b) {
  const job *x = a, *y = b;
  if (x->cost != y->cost) return x->cost > y->cost ? -1 : 1;
  return (x->global > y->global) - (x->global < y->global);
}

/* The shard (0-based) of each of the n cells starting at global index base:
 * balanced, the longest-processing-time rule: the cells by decreasing cost
 * hint, each to the shard with the least hinted load so far (the lowest
 * shard on ties), the loads carried over from earlier cb_sweep_run calls;
 * modulo, global index mod N. Only (cells, hints, N) enter, so every shard
 * computes the same assignment without talking to the others. */
static int assign(cb_experiment *e, const cb_sweep *sweeps, int nsweeps, long base, long n, int *owner) {
  if (e->shard_mode == CB_SHARD_MODULO) {
    for (long g = 0; g < n; g++) owner[g] = (int)((base + g) % e->nshards);
    return CB_OK;
  }
  if (!e->shard_load && !(e->shard_load = calloc((size_t)e->nshards, sizeof *e->shard_load)))
    return cb_fail_status(CB_ENOMEM, "out of memory for the shard loads");
  job *jobs = malloc((size_t)(n ? n : 1) * sizeof *jobs);
  if (!jobs) return cb_fail_status(CB_ENOMEM, "out of memory for the shard assignment");
  long g = 0;
  for (int k = 0; k < nsweeps; k++)
    for (long i = 0; i < sweeps[k].ncells; i++, g++) jobs[g] = (job){g, cell_cost(&sweeps[k], i)};
  qsort(jobs, (size_t)n, sizeof *jobs, by_cost_desc);
  for (long j = 0; j < n; j++) {
    int best = 0;
    for (int s = 1; s < e->nshards; s++)
      if (e->shard_load[s] < e->shard_load[best]) best = s;
    owner[jobs[j].global] = best;
    e->shard_load[best] += jobs[j].cost;
  }
  free(jobs);
  return CB_OK;
}

int cb_sweep_run(cb_experiment *e, const cb_sweep *sweeps, int nsweeps) {
  if (e->shard && !e->cells && !(e->cells = open_memstream(&e->cells_log, &e->cells_len)))
    return cb_fail_status(CB_ENOMEM, "out of memory for the shard's cell list");
  long total = 0;
  for (int k = 0; k < nsweeps; k++) {
    total += sweeps[k].ncells;
    (void)cb_experiment_sweep_untimed(e, sweeps[k].name); /* a declared sweep: its untimed name is a real one */
  }
  int *owner = NULL;
  if (e->shard) {
    if (!(owner = malloc((size_t)(total ? total : 1) * sizeof *owner)))
      return cb_fail_status(CB_ENOMEM, "out of memory for the shard assignment");
    int st = assign(e, sweeps, nsweeps, e->ncells, total, owner);
    if (st) {
      free(owner);
      return st;
    }
  }
  if (e->list_cells) { /* --list-cells: every cell, its hint and its shard; nothing runs */
    long g = 0;
    for (int k = 0; k < nsweeps; k++)
      for (long i = 0; i < sweeps[k].ncells; i++, g++) {
        printf("%ld %d ", e->ncells + g, e->nsweep_runs);
        for (const char *c = sweeps[k].name; *c; c++) putchar(*c == ' ' || *c == '\t' || *c == '\n' ? '_' : *c);
        printf(" %ld %.17g %d %d\n", i, cell_cost(&sweeps[k], i), owner ? owner[g] + 1 : 1,
               e->cell_locks ? cell_timed(e, &sweeps[k], i) : e->timed);
      }
    e->ncells += total;
    e->nsweep_runs++;
    free(owner);
    return fflush(stdout) ? cb_fail_status(CB_EIO, "--list-cells: write to stdout failed") : CB_OK;
  }
  long n = 0, g = 0;
  double cost = 0;
  for (int k = 0; k < nsweeps; k++)
    for (long i = 0; i < sweeps[k].ncells; i++, g++)
      if (!owner || owner[g] == e->shard - 1) {
        n++;
        cost += cell_cost(&sweeps[k], i);
      }
  char label[64];
  if (e->shard) snprintf(label, sizeof label, "%s (shard %d/%d)", e->name, e->shard, e->nshards);
  else snprintf(label, sizeof label, "%s", e->name);
  cb_experiment_cells_start(e);
  cb_progress_start_cost(&e->progress, label, n, cost);
  int st = CB_OK;
  g = 0;
  for (int k = 0; st == CB_OK && k < nsweeps; k++)
    for (long i = 0; i < sweeps[k].ncells; i++, g++, e->ncells++) {
      if (st != CB_OK || (owner && owner[g] != e->shard - 1)) continue;
      double c = cell_cost(&sweeps[k], i);
      st = run_one(e, &sweeps[k], i, e->ncells, c);
      cb_progress_advance(&e->progress, c);
    }
  cb_progress_end(&e->progress);
  e->nsweep_runs++;
  free(owner);
  return st;
}

int cb_sweep_scene_size(const cb_experiment *e, const cb_scene_decl *d, cb_scene_size *out) {
  static cb_config c; /* large: not on the stack */
  int st = cb_scene_decl_config(e, d, NULL, &c);
  *out = st ? (cb_scene_size){0, 0, 0, 0} : (cb_scene_size){cb_scene_decl_vertices(&c), c.mesh_n, 0, c.dt};
  out->rel = (double)out->nv / 441;
  return st;
}
