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
  p->t0 = p->last = cb_now_ms();
  p->tty = isatty(fileno(stderr));
  const char *q = getenv("CB_QUIET");
  p->quiet = q && *q && strcmp(q, "0") != 0;
}

static void print(cb_progress *p, int final) {
  p->printed = 1;
  double el = (cb_now_ms() - p->t0) / 1e3;
  double eta = p->done > 0 && p->total > p->done ? el * (double)(p->total - p->done) / (double)p->done : 0;
  fprintf(stderr, "%s%s: %ld/%ld (%.0f%%) elapsed %.1fs eta %.1fs%s", p->tty ? "\r" : "", p->label, p->done,
          p->total, p->total > 0 ? 100.0 * (double)p->done / (double)p->total : 100.0, el, eta,
          p->tty && !final ? "   " : "\n");
  fflush(stderr);
}

void cb_progress_update(cb_progress *p, long done) {
  p->done = done;
  if (p->quiet) return;
  double now = cb_now_ms();
  if (now - p->last < (p->tty ? 200.0 : 15000.0)) return;
  p->last = now;
  print(p, 0);
}

void cb_progress_end(cb_progress *p) {
  if (p->quiet || (!p->printed && cb_now_ms() - p->t0 < 2000.0)) return;
  p->done = p->total > p->done ? p->done : p->total;
  print(p, 1);
}
