/* field, V1 (Chen et al. 2024): vertex block descent lowers F at every iteration and survives any start.
 *
 * rises: a trajectory of `frames` frames from the scene's initial state (and from the scrambled one) of
 *   vbd (the paper's method: no line search) and vbd with its per-vertex line search; a hook sees F at
 *   every iterate of every step and counts the rises F_k > F_{k-1} + 1e-12 max(|F_k|, |F_{k-1}|) (above
 *   F's round-off); max_rise_rel is the largest (F_k - F_{k-1}) / |F_{k-1}|.
 * scramble: every free vertex of the initial state displaced by a random vector of length up to the
 *   cloth's size L (direction uniform on the sphere, length uniform in [0, L]; the project's generator,
 *   rng.h, seeded per scene), at rest, then `frames` frames (40; --quick 20) of vbd, vbd line search,
 *   vbd-chebyshev (rho auto), jacobi-nl, chebyshev-nl (rho auto) and pd-chebyshev (rho auto) with the
 *   scene's damping. Diverged: a fatal status or a vertex beyond 1e3 L of the origin. A method that
 *   refuses the scene gets one row, status unsupported. The row keeps the mean |strain| of the springs
 *   at the start, after frames/2 frames (mid_strain) and at the end, and strain_normal, the mean |strain|
 *   after the same frames of the scene's own method from its unscrambled initial state. Whether that is a
 *   recovery is decided by one rule, in claims/check_field.c (V1 (b): no divergence, and the strain's
 *   excess over strain_normal down to a tenth or decaying at a rate of at least ln 10 per 10 s over the
 *   window's second half); this file only measures. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"

#include "csv.h"
#include "field.h"

static const char *const RISE_M[][3] = {{"vbd", "integrator.method=vbd", NULL},
                                        {"vbd line search", "integrator.method=vbd", "integrator.vbd_line_search=1"}};
/* the first NRISE scramble methods are RISE_M's (their scrambled runs are shared) */
static const char *const SCR_M[][3] = {{"vbd", "integrator.method=vbd", NULL},
                                       {"vbd line search", "integrator.method=vbd", "integrator.vbd_line_search=1"},
                                       {"vbd-chebyshev auto", "integrator.method=vbd-chebyshev", "integrator.rho=auto"},
                                       {"jacobi-nl", "integrator.method=jacobi-nl", NULL},
                                       {"chebyshev-nl auto", "integrator.method=chebyshev-nl", "integrator.rho=auto"},
                                       {"pd-chebyshev auto", "integrator.method=pd-chebyshev", "integrator.rho=auto"}};
enum { NRISE = 2, NSCR = 6 };

long fd_v1_cells(const fd_plan *p) { return p->nv1; }
static int frames_of(const fd_plan *p) { return p->smoke ? 4 : p->quick ? 20 : 40; }

typedef struct {
  double prev;
  int have, rises, step_rise;
  double max_rel;
} rise_t;

static void on_iter(void *ctx, int event, const cb_newton_event *ev) {
  rise_t *t = ctx;
  if (event != CB_NEWTON_GRADIENT) return;
  if (ev->iter > 0 && t->have) {
    double a = t->prev, b = ev->F;
    if (b > a + 1e-12 * fmax(fabs(a), fabs(b))) {
      t->rises++;
      t->step_rise = 1;
      if (fabs(a) > 0) t->max_rel = fmax(t->max_rel, (b - a) / fabs(a));
    }
  }
  t->prev = ev->F;
  t->have = 1;
}

/* frames of the method `sets` (plus the scene's own keys) from (x, v), in place; *run the frames that
 * ran, *div the first diverged frame (0: none), rise counts into rt (may be NULL: no hook), *mid the mean
 * |strain| after frames/2 frames (NaN if it did not get there), *dt the step */
static int trajectory(const fd_plan *p, const cb_scene_decl *d, cb_scene *s, const char *const *sets, double *x,
                      double *v, int frames, double L, rise_t *rt, int *run, int *div, int *iters, int *steps_rise,
                      int *status, double *mid, double *dt) {
  static cb_config c;
  int st = cb_scene_decl_config(p->e, d, sets, &c);
  cb_integrator_params ip;
  if (st == CB_OK) st = cb_integrator_params_from_config(&c, &ip);
  if (st) return st;
  if (rt) {
    ip.hook = on_iter;
    ip.hook_ctx = rt;
  }
  cb_integrator *it = NULL;
  if ((st = cb_integrator_from_config(&c, s, &ip, &it))) return st;
  int n3 = 3 * s->mesh.nv;
  *run = *div = *iters = *steps_rise = 0;
  *status = CB_OK;
  *mid = NAN;
  *dt = c.dt;
  for (int f = 1; f <= frames; f++) {
    cb_step_stats ss;
    if (rt) rt->have = rt->step_rise = 0;
    int sst = cb_integrator_step(it, x, v, &ss);
    int far = 0;
    for (int k = 0; k < n3 && !far; k++) far = !(fabs(x[k]) <= 1e3 * L);
    if (cb_status_is_fatal(sst) || far) {
      *div = f;
      *status = cb_status_is_fatal(sst) ? sst : CB_DIVERGED;
      break;
    }
    *iters += ss.newton_iters;
    if (rt) *steps_rise += rt->step_rise;
    *run = f;
    if (f == frames / 2) {
      double mx;
      fd_strain(s, x, &mx, mid);
    }
  }
  cb_integrator_free(it);
  return CB_OK;
}

int fd_v1_cell(long i, void *ctx, FILE *const *out) {
  const fd_plan *p = ctx;
  const cb_scene_decl *d = p->decl[p->v1[i]];
  static cb_config c;
  cb_scene *s = NULL;
  int st = cb_scene_decl_build(p->e, d, NULL, &c, &s);
  if (st) return st;
  int n3 = 3 * s->mesh.nv, frames = frames_of(p);
  double L = fmax(c.mesh_size[0], c.mesh_size[1]);
  double *xi = malloc((size_t)n3 * sizeof(double)), *xr = malloc((size_t)n3 * sizeof(double)),
         *x = malloc((size_t)n3 * sizeof(double)), *v = malloc((size_t)n3 * sizeof(double));
  /* the end states of the rises' scrambled runs, which are the scramble table's runs of the same methods */
  double *xs_end[NRISE] = {malloc((size_t)n3 * sizeof(double)), malloc((size_t)n3 * sizeof(double))};
  int s_run[NRISE] = {0}, s_div[NRISE] = {0}, s_status[NRISE] = {0};
  double s_mid[NRISE] = {NAN, NAN}, dt = NAN;
  if (!xi || !xr || !x || !v || !xs_end[0] || !xs_end[1]) st = cb_fail_status(CB_ENOMEM, "out of memory");
  cb_run run;
  memset(&run, 0, sizeof run);
  cb_integrator *own = NULL;
  /* the initial state, and the scene's own method's strain after `frames` frames from it */
  double strain_normal = NAN, mx;
  if (st == CB_OK) st = cb_integrator_from_config(&c, s, NULL, &own);
  if (st == CB_OK) st = cb_run_init(&run, s, own);
  if (st == CB_OK) memcpy(xi, run.x, (size_t)n3 * sizeof(double));
  for (int f = 0; st == CB_OK && f < frames; f++) {
    int sst = cb_run_step(&run);
    if (cb_status_is_fatal(sst))
      st = cb_fail_status(sst, "scene %s: own method, frame %d: %s", d->label, f + 1, cb_status_name(sst));
  }
  if (st == CB_OK) fd_strain(s, run.x, &mx, &strain_normal);
  cb_run_free(&run);
  cb_integrator_free(own);
  /* the scrambled start: free vertices displaced by up to L */
  if (st == CB_OK) {
    cb_rng g = cb_rng_seed(20 + (uint64_t)i);
    memcpy(xr, xi, (size_t)n3 * sizeof(double));
    for (int b = 0; b < s->model.nfree; b++) {
      double z = 2 * cb_rng_uniform(&g) - 1, phi = 2 * 3.14159265358979323846 * cb_rng_uniform(&g),
             r = L * cb_rng_uniform(&g), q = sqrt(1 - z * z);
      double *xv = xr + 3 * s->free_vertex[b];
      xv[0] += r * q * cos(phi);
      xv[1] += r * q * sin(phi);
      xv[2] += r * z;
    }
  }
  double na = cb_csv_na();
  for (int m = 0; st == CB_OK && m < NRISE; m++)
    for (int start = 0; st == CB_OK && start < 2; start++) {
      memcpy(x, start ? xr : xi, (size_t)n3 * sizeof(double));
      memset(v, 0, (size_t)n3 * sizeof(double));
      rise_t rt = {0, 0, 0, 0, 0};
      int nrun, div, iters, srise, status;
      double mid;
      const char *sets[] = {RISE_M[m][1], RISE_M[m][2], NULL};
      st = trajectory(p, d, s, sets, x, v, frames, L, &rt, &nrun, &div, &iters, &srise, &status, &mid, &dt);
      if (st == CB_OK && start) {
        memcpy(xs_end[m], x, (size_t)n3 * sizeof(double));
        s_run[m] = nrun;
        s_div[m] = div;
        s_status[m] = status;
        s_mid[m] = mid;
      }
      if (st == CB_OK)
        cb_csv_printf(out[T_RISES], "%s,%s,%s,%d,%d,%d,%d,%d,%.17g,%d,%.17g,%s\n", d->label, RISE_M[m][0],
                      start ? "scrambled" : "initial", frames, nrun, iters, rt.rises, srise, rt.max_rel, div > 0,
                      div > 0 ? (double)div : na, cb_status_name(status));
    }
  double smax0, s0;
  if (st == CB_OK) fd_strain(s, xr, &smax0, &s0);
  for (int m = 0; st == CB_OK && m < NSCR; m++) {
    memcpy(x, xr, (size_t)n3 * sizeof(double));
    memset(v, 0, (size_t)n3 * sizeof(double));
    int nrun, div, iters, srise, status;
    double mid, mdt;
    const char *sets[] = {SCR_M[m][1], SCR_M[m][2], NULL};
    if (m < NRISE) { /* the same method from the same start: the rises' run (its hook only observed it) */
      memcpy(x, xs_end[m], (size_t)n3 * sizeof(double));
      nrun = s_run[m];
      div = s_div[m];
      status = s_status[m];
      mid = s_mid[m];
      mdt = dt;
    } else st = trajectory(p, d, s, sets, x, v, frames, L, NULL, &nrun, &div, &iters, &srise, &status, &mid, &mdt);
    if (st == CB_EINVAL) { /* the method refuses the scene (pd and the drape's dihedral bending): one row saying so */
      cb_error_clear();
      st = CB_OK;
      cb_csv_printf(out[T_SCRAMBLE], "%s,%s,%d,0,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,%.17g,unsupported\n",
                    d->label, SCR_M[m][0], frames, na, L, s0, na, na, strain_normal, na, na);
      continue;
    }
    if (st) break;
    double smax = na, smean = na;
    if (!div) fd_strain(s, x, &smax, &smean);
    cb_csv_printf(out[T_SCRAMBLE], "%s,%s,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%s\n", d->label,
                  SCR_M[m][0], frames, nrun, mdt, L, s0, div ? na : mid, smean, strain_normal, smax, div > 0,
                  div > 0 ? (double)div : na, cb_status_name(status));
  }
  free(xi);
  free(xr);
  free(xs_end[0]);
  free(xs_end[1]);
  free(x);
  free(v);
  cb_scene_free(s);
  return st;
}

/* cost hint: (2 x 2 + 6 + 1) trajectories of `frames` frames of ~32 iterations at ~3e-4 ms per vertex */
double fd_v1_cost(long i, void *ctx) {
  const fd_plan *p = ctx;
  return 100.0 + 10.0 * frames_of(p) * 32 * 3e-4 * p->nv[p->v1[i]];
}
