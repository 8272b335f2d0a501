/* field, X2: small steps (Macklin et al. 2019). From the scene's start state, one frame of XPBD as n
 * substeps of one iteration ("nx1") and as one step of n iterations ("1xn"), n = 1, 2, 4, ..., 64: equal
 * work (n constraint sweeps). Per variant: the largest edge stretch at the frame's end (max over the
 * stretch springs of |x_i - x_j|/L - 1; the converged step's own is ref_max_stretch), the step error
 * against the converged implicit-Euler step of the whole frame, relative |grad F| of the frame's F,
 * and the wall time, the two variants of each n timed in interleaved rounds (the stretch is that of the
 * first timed run's end state: the step is deterministic, so it is not run again for it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "field.h"

static int nmax(const fd_plan *p) { return p->smoke ? 2 : 64; }

int fd_x2_cell(long i, void *ctx, FILE *const *out) {
  const fd_plan *p = ctx;
  const cb_scene_decl *d = p->decl[p->x2[i]];
  cb_step_state S;
  int st = fd_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  double ref_max, ref_mean;
  fd_strain(S.s, S.xstar, &ref_max, &ref_mean);
  double *xend[2] = {malloc((size_t)S.n3 * sizeof(double)), malloc((size_t)S.n3 * sizeof(double))};
  if (!xend[0] || !xend[1]) st = cb_fail_status(CB_ENOMEM, "out of memory");
  for (int n = 1; st == CB_OK && n <= nmax(p); n *= 2) {
    char a[64], b[64];
    snprintf(a, sizeof a, "integrator.substeps=%d", n);
    snprintf(b, sizeof b, "integrator.iters=%d", n);
    const char *nx1[] = {"integrator.method=xpbd", a, "integrator.iters=1", NULL};
    const char *onexn[] = {"integrator.method=xpbd", "integrator.substeps=1", b, NULL};
    const char *const *sets[] = {nx1, onexn};
    cb_step_result r[2];
    double *const xe[] = {xend[0], xend[1]};
    st = cb_step_time_group_ex(p->quick, INFINITY, &S, sets, NULL, 2, r, xe);
    for (int v = 0; st == CB_OK && v < 2; v++) {
      double mx, mean; /* the stretch of the step's end state (its first timed run's) */
      fd_strain(S.s, xend[v], &mx, &mean);
      cb_csv_printf(out[T_X2], "%s,%ld,%d,%s,%d,%d,", d->label, (long)S.s->mesh.nv, n, v ? "1xn" : "nx1", v ? 1 : n,
                    v ? n : 1);
      cb_timing_csv_repeats(out[T_X2], &r[v].wall);
      cb_csv_printf(out[T_X2], ",%.17g,%.17g,%.17g,%.17g,%s\n", r[v].error, mx, ref_max, r[v].rel_grad,
                    cb_status_name(r[v].status));
    }
  }
  free(xend[0]);
  free(xend[1]);
  cb_step_state_free(&S);
  return st;
}

/* cost hint: 2 x (1 + 2 + ... + 64) sweeps x 3 rounds x the springs (~3 per vertex) at 5e-6 ms, plus the state */
double fd_x2_cost(long i, void *ctx) {
  const fd_plan *p = ctx;
  return 300.0 + 2 * 127 * 4 * 3 * p->nv[p->x2[i]] * 5e-6 + 0.5 * p->nv[p->x2[i]];
}
