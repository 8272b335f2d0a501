/* Capture of a Newton system through the integrator's hook (see capture.h). */
#include "capture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bind.h"
#include <clothbench/integrator.h>
#include <clothbench/run.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

typedef struct {
  cb_capture *c;
  int cur_step; /* the step being simulated */
  int done;     /* 1 once the system has been copied */
} capture_ctx;

static void capture_hook(void *ctx, int event, const cb_newton_event *ev) {
  capture_ctx *k = ctx;
  cb_capture *c = k->c;
  if (event != CB_NEWTON_SYSTEM || k->done || k->cur_step != c->step || ev->iter != c->iter) return;
  memcpy(c->A.val, ev->A->val, (size_t)ev->A->nnz * sizeof(double)); /* the pattern is the scene's */
  memcpy(c->b, ev->b, (size_t)ev->A->n * sizeof(double));
  memcpy(c->x, ev->x, (size_t)3 * c->scene->mesh.nv * sizeof(double));
  k->done = 1;
}

int cb_capture_newton_system(const cb_config *cfg, int step, int iter, cb_capture *out) {
  memset(out, 0, sizeof *out);
  if (step < 0 || iter < 0) return cb_fail("capture: step and iter must be >= 0 (got %d, %d)", step, iter);
  double t0 = cb_now_ms();
  int st = cb_scene_from_config(cfg, &out->scene);
  if (st) return st;
  cb_scene *s = out->scene;
  out->step = step;
  out->iter = iter;
  out->A = s->sys.A; /* pattern borrowed */
  out->A.val = cb_malloc((size_t)s->sys.A.nnz, sizeof(double));
  out->b = cb_malloc((size_t)s->sys.A.n, sizeof(double));
  out->x = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
  if (!out->A.val || !out->b || !out->x) {
    cb_capture_free(out);
    return CB_ENOMEM;
  }
  capture_ctx k = {out, 0, 0};
  cb_integrator_params ip;
  st = cb_integrator_params_from_config(cfg, &ip);
  if (st) {
    cb_capture_free(out);
    return st;
  }
  ip.hook = capture_hook;
  ip.hook_ctx = &k;
  cb_integrator *it = NULL;
  st = cb_integrator_from_config(cfg, s, &ip, &it);
  if (st) {
    cb_capture_free(out);
    return st;
  }
  cb_run r;
  st = cb_run_init(&r, s, it);
  for (int n = 0; st == CB_OK && n <= step && !k.done; n++) {
    k.cur_step = n;
    out->t_s = r.t;
    int ss = cb_run_step(&r);
    if (cb_status_is_fatal(ss) && !k.done)
      st = cb_fail_status(ss, "capture: step %d ended with status %s before the capture", n, cb_status_name(ss));
  }
  if (st == CB_OK && !k.done)
    st = cb_fail_status(CB_NOT_CONVERGED, "capture: step %d ended before Newton iteration %d", step, iter);
  cb_run_free(&r);
  cb_integrator_free(it);
  out->sim_ms = cb_now_ms() - t0;
  if (st) cb_capture_free(out);
  return st;
}

void cb_capture_free(cb_capture *c) {
  if (!c) return;
  free(c->A.val);
  free(c->b);
  free(c->x);
  cb_scene_free(c->scene);
  memset(c, 0, sizeof *c);
}

void cb_diag_dominance(const cb_sparse *A, int *violating_rows, double *max_ratio) {
  int bad = 0;
  double worst = 0;
  for (int j = 0; j < A->n; j++) { /* symmetric: column j = row j */
    double d = 0, off = 0;
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++) {
      if (A->rowi[p] == j) d = A->val[p];
      else off += fabs(A->val[p]);
    }
    if (d < off) bad++;
    double ratio = d > 0 ? off / d : INFINITY; /* sum_{i != j} |a_ij| / a_jj */
    if (ratio > worst) worst = ratio;
  }
  *violating_rows = bad;
  *max_ratio = worst;
}
