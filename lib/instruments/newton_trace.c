#include "newton_trace.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include <clothbench/timer.h>

double cb_compressed_fraction(const cb_system *sys, const double *x) {
  int c = 0, n = 0;
  for (int k = 0; k < sys->nterms; k++) { /* every term that counts its indefinite elements (energy.h) */
    int ne;
    c += cb_term_count_indefinite(sys->terms[k], x, &ne);
    n += ne;
  }
  return n > 0 ? (double)c / n : 0.0;
}

int cb_newton_trace_init(cb_newton_trace *t, const cb_scene *scene, cb_system *ref, double dt, int cap,
                         unsigned what_used, unsigned what_exact, const cb_spd_probe_params *params) {
  memset(t, 0, sizeof *t);
  t->scene = scene;
  t->ref = ref;
  t->mass_scale = 1.0 / (dt * dt);
  t->what_used = what_used;
  t->what_exact = ref ? what_exact : 0;
  t->cap = cap;
  t->rows = cb_calloc((size_t)cap, sizeof *t->rows);
  if (!t->rows) return CB_ENOMEM;
  int st = cb_spd_probe_alloc(&scene->sys.A, params, &t->probe);
  if (st == CB_OK && ref) st = cb_spd_probe_alloc(&ref->A, params, &t->probe_ref);
  if (st) cb_newton_trace_free(t);
  return st;
}

void cb_newton_trace_free(cb_newton_trace *t) {
  cb_spd_probe_free(t->probe);
  cb_spd_probe_free(t->probe_ref);
  free(t->rows);
  memset(t, 0, sizeof *t);
}

/* Closes the open row: its wall time is the time since it was opened minus
 * the probe time spent since then. */
static void close_row(cb_newton_trace *t, double now) {
  if (!t->open) return;
  t->rows[t->nrows - 1].wall_ms = (now - t->t_mark) - (t->probe_ms - t->probe_ms_mark);
  t->open = 0;
}

void cb_newton_trace_begin_step(cb_newton_trace *t) {
  t->nrows = 0;
  t->open = 0;
  t->probe_ms = 0;
  t->t_mark = cb_now_ms(); /* the first gradient evaluation belongs to row 0 */
  t->probe_ms_mark = 0;
}

void cb_newton_trace_end_step(cb_newton_trace *t, int status) {
  close_row(t, cb_now_ms());
  if (t->nrows > 0 && !t->rows[t->nrows - 1].system) t->rows[t->nrows - 1].status = status;
}

void cb_newton_trace_hook(void *ctx, int event, const cb_newton_event *ev) {
  cb_newton_trace *t = ctx;
  double now = cb_now_ms();
  if (event == CB_NEWTON_GRADIENT) {
    double mark = t->nrows == 0 ? t->t_mark : now; /* row 0 includes the first gradient */
    close_row(t, now);
    if (t->nrows == t->cap) return; /* cannot happen with cap = max_iters + 1 */
    cb_newton_trace_row *r = &t->rows[t->nrows++];
    memset(r, 0, sizeof *r);
    r->iter = ev->iter;
    r->rel_grad = ev->rel_grad;
    r->grad_norm = ev->grad_norm;
    r->F = ev->F;
    r->status = CB_OK;
    r->used.min_eig = r->exact.min_eig = NAN;
    r->energy = cb_system_energy(&t->scene->sys, ev->x, NULL, NULL); /* measurement: timed as probe */
    r->compressed_frac = cb_compressed_fraction(&t->scene->sys, ev->x);
    t->t_mark = mark;
    t->probe_ms_mark = t->probe_ms;
    t->probe_ms += cb_now_ms() - now;
    t->open = 1;
    return;
  }
  if (event != CB_NEWTON_SOLVED || t->nrows == 0) return;
  cb_newton_trace_row *r = &t->rows[t->nrows - 1];
  r->system = 1;
  r->status = ev->status;
  r->mu = ev->shift_mu;
  r->linear_ok = ev->status == CB_OK || ev->status == CB_NOT_CONVERGED;
  int st = cb_spd_probe_run(t->probe, ev->A, ev->b, t->what_used, &r->used);
  if (st == CB_OK && t->ref) { /* the lecture's exact A at the same iterate */
    cb_system_assemble(t->ref, ev->x, t->mass_scale, CB_DEF_NONE, 0.0);
    st = cb_spd_probe_run(t->probe_ref, &t->ref->A, ev->b, t->what_exact, &r->exact);
    r->have_exact = st == CB_OK;
  }
  if (st < 0 && !t->error) t->error = st;
  t->probe_ms += cb_now_ms() - now;
}
