#include "progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <clothbench/status.h>
#include <clothbench/timer.h>

void cb_progress_start(cb_progress *p, const char *label, long total) {
  memset(p, 0, sizeof *p);
  snprintf(p->label, sizeof p->label, "%s", label);
  p->total = total;
  p->t0 = p->last = p->t_done = cb_now_ms();
  p->tty = isatty(fileno(stderr));
  const char *q = getenv("CB_QUIET");
  p->quiet = q && *q && strcmp(q, "0") != 0;
}

void cb_progress_start_cost(cb_progress *p, const char *label, long total, double cost_total) {
  cb_progress_start(p, label, total);
  p->cost_total = cost_total > 0 ? cost_total : 0;
}

/* seconds still to go, from what has completed so far */
static double eta_s(const cb_progress *p, double now) {
  if (p->done <= 0 || p->done >= p->total) return 0;
  if (p->cost_total > 0 && p->cost_done > 0) {
    double per_cost = (p->t_done - p->t0) / p->cost_done; /* ms per unit of cost, completed cells only */
    double left = per_cost * (p->cost_total - p->cost_done) - (now - p->t_done);
    return left > 0 ? left / 1e3 : 0;
  }
  return (now - p->t0) / 1e3 * (double)(p->total - p->done) / (double)p->done;
}

static void print(cb_progress *p, int final) {
  p->printed = 1;
  double now = cb_now_ms(), el = (now - p->t0) / 1e3;
  double frac = p->cost_total > 0 ? p->cost_done / p->cost_total
                : p->total > 0    ? (double)p->done / (double)p->total
                                  : 1.0;
  fprintf(stderr, "%s%s: %ld/%ld (%.0f%%) elapsed %.1fs eta %.1fs%s", p->tty ? "\r" : "", p->label, p->done, p->total,
          100.0 * (frac < 1 ? frac : 1), el, eta_s(p, now), p->tty && !final ? "   " : "\n");
  fflush(stderr);
}

void cb_progress_update(cb_progress *p, long done) {
  p->done = done;
  p->t_done = cb_now_ms();
  if (p->quiet) return;
  double now = p->t_done;
  if (now - p->last < (p->tty ? 200.0 : 15000.0)) return;
  p->last = now;
  print(p, 0);
}

void cb_progress_advance(cb_progress *p, double cost) {
  p->cost_done += cost;
  cb_progress_update(p, p->done + 1);
}

void cb_progress_end(cb_progress *p) {
  if (p->quiet || (!p->printed && cb_now_ms() - p->t0 < 2000.0)) return;
  p->done = p->total > p->done ? p->done : p->total;
  print(p, 1);
}
