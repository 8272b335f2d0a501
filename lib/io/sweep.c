#include "sweep.h"

#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

static int mine(const cb_experiment *e, long global) {
  return !e->shard || global % e->nshards == e->shard - 1;
}

static double cell_cost(const cb_sweep *s, long i) {
  double c = s->cost ? s->cost(i, s->ctx) : 1.0;
  return c > 0 ? c : 0;
}

/* Runs one cell into per-table memory streams, then appends them in order. */
static int run_one(cb_experiment *e, const cb_sweep *s, long i, long global) {
  FILE *out[CB_EXPERIMENT_MAX_TABLES] = {NULL};
  char *buf[CB_EXPERIMENT_MAX_TABLES] = {NULL};
  size_t len[CB_EXPERIMENT_MAX_TABLES] = {0};
  int st = CB_OK;
  for (int t = 0; st == CB_OK && t < e->ntables; t++)
    if (!(out[t] = open_memstream(&buf[t], &len[t]))) st = cb_fail_status(CB_ENOMEM, "out of memory for cell rows");
  if (st == CB_OK) {
    st = s->run_cell(i, s->ctx, out);
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
  if (st == CB_OK && e->shard) fputc('\n', e->cells);
  return st;
}

int cb_sweep_run(cb_experiment *e, const cb_sweep *sweeps, int nsweeps) {
  if (e->shard && !e->cells && !(e->cells = open_memstream(&e->cells_log, &e->cells_len)))
    return cb_fail_status(CB_ENOMEM, "out of memory for the shard's cell list");
  long n = 0;
  double cost = 0;
  long base = e->ncells;
  for (int k = 0; k < nsweeps; k++)
    for (long i = 0; i < sweeps[k].ncells; i++, base++)
      if (mine(e, base)) {
        n++;
        cost += cell_cost(&sweeps[k], i);
      }
  char label[64];
  if (e->shard) snprintf(label, sizeof label, "%s (shard %d/%d)", e->name, e->shard, e->nshards);
  else snprintf(label, sizeof label, "%s", e->name);
  cb_progress_start_cost(&e->progress, label, n, cost);
  int st = CB_OK;
  for (int k = 0; st == CB_OK && k < nsweeps; k++)
    for (long i = 0; i < sweeps[k].ncells; i++, e->ncells++) {
      if (st != CB_OK || !mine(e, e->ncells)) continue;
      st = run_one(e, &sweeps[k], i, e->ncells);
      cb_progress_advance(&e->progress, cell_cost(&sweeps[k], i));
    }
  cb_progress_end(&e->progress);
  return st;
}
