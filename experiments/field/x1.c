/* field, X1: the effective stiffness of PBD and XPBD (Macklin et al. 2016). For a scene (the hanging
 * strip, configs/chain20.ini, and the lab cloth) and a dt, the converged static state x_s under
 * gravity is found first (Newton at dt = 10 s with the velocity zeroed every step, until no vertex moves
 * by more than 1e-10 of the cloth's size: the minimiser of E, springs at their stiffness k). Then each
 * method, at K = 1 ... 100 iterations a step (one substep), starts at rest from x_s and runs for
 * settle_s seconds with velocity damping exp(-4 dt) per step (a decay e^-4 per second whatever dt), and
 * its static stretch is the mean over the last quarter of the frames of the mean |strain| of the
 * stretch springs. A method with the springs' stiffness keeps x_s's stretch; one that is softer (or
 * stiffer) sags more (less). Under the linear response of a stretch to its load,
 *   k_eff = k strain_ref / strain,     k_ratio = k_eff / k,
 * PBD runs at its default stiffness 1 (Mueller et al.'s per-iteration correction does not scale with dt).
 *
 * At convergence (kind "converged", what X1 decides on, check_field.c): the claim is about the stiffness
 * XPBD converges to, and at 1-100 iterations XPBD is not converged (the 20-link strip needs ~400
 * sweeps). Per scene and dt the iteration count K* is chosen from XPBD's constraint residual: one step
 * from x_s at rest with K = 1, 2, 4, ..., KMAX sweeps, K* the first whose last sweep's residual
 * max_c |C_c + alpha~ lambda_c| / L_c (cb_step_stats.constraint_residual) is at most RES_TOL = 1e-3 of
 * x_s's mean |strain| (so a residual moves the measured strain by about 0.1% of itself; XPBD resets
 * lambda every step, so every step needs as many sweeps as this one). Both methods then settle at K*
 * as above; the row keeps the largest residual over the settled frames (residual), and a scene whose
 * XPBD did not reach RES_TOL within KMAX gets status max_iters (CB_NOT_CONVERGED) on its converged rows. The 1-100
 * rows (kind "sweep") stay as the second figure: how fast each method approaches its K* value. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "field.h"

static const char *const DTS[] = {"1/30", "1/60", "1/120"};
enum { NDT = sizeof DTS / sizeof DTS[0] };
static const int KS[] = {1, 2, 5, 10, 20, 50, 100};
enum { NK = sizeof KS / sizeof KS[0] };
static const int KS_Q[] = {1, 10, 100};
static const char *const METHODS[] = {"pbd", "xpbd"};
#define RES_TOL 1e-3 /* K*: the constraint residual at most this fraction of the static mean |strain| */
static int kmax(const fd_plan *p) { return p->smoke ? 64 : 8192; }

static int ndt(const fd_plan *p) { return p->smoke ? 1 : NDT; }
long fd_x1_cells(const fd_plan *p) { return (long)p->nx1; }

static double settle_s(const fd_plan *p) { return p->smoke ? 0.2 : p->quick ? 1.0 : 2.0; }

/* the static state: Newton at dt = 1 s, v <- 0 every step, until it stops moving */
static int static_state(const fd_plan *p, const cb_scene_decl *d, cb_scene *s, double *xs) {
  static const char *const sets[] = {
      "integrator.method=newton", "integrator.dt=10",         "integrator.damping=0",         "integrator.max_iters=50",
      "integrator.tol=1e-10",     "integrator.line_search=1", "integrator.definiteness=drop", NULL};
  static cb_config c;
  int st = cb_scene_decl_config(p->e, d, sets, &c);
  cb_integrator *it = NULL;
  cb_run run;
  memset(&run, 0, sizeof run);
  if (st == CB_OK) st = cb_integrator_from_config(&c, s, NULL, &it);
  if (st == CB_OK) st = cb_run_init(&run, s, it);
  int n3 = 3 * s->mesh.nv, moved = 1;
  double size = fmax(c.mesh_size[0], c.mesh_size[1]);
  for (int f = 0; st == CB_OK && moved && f < 200; f++) {
    memcpy(xs, run.x, (size_t)n3 * sizeof(double));
    int sst = cb_run_step(&run);
    if (cb_status_is_fatal(sst))
      st = cb_fail_status(sst, "scene %s: static state, step %d: %s", d->label, f + 1, cb_status_name(sst));
    double dx = 0;
    for (int k = 0; k < n3; k++) dx = fmax(dx, fabs(run.x[k] - xs[k]));
    moved = dx > 1e-10 * size;
  }
  if (st == CB_OK && moved)
    st = cb_fail_status(CB_NOT_CONVERGED, "scene %s: static state still moving after 200 steps", d->label);
  if (st == CB_OK) memcpy(xs, run.x, (size_t)n3 * sizeof(double));
  cb_run_free(&run);
  cb_integrator_free(it);
  return st;
}

/* `method` at K sweeps a step (one substep) and dt_s from x_s at rest: with secs > 0, secs of frames
 * with the velocity damping exp(-4 dt) per step, *strain the mean over the last quarter of the frames of
 * the mean |strain| of the stretch springs; with secs <= 0, one step. *res the largest constraint
 * residual over the frames averaged (the one step's), *sst the first fatal step status (or CB_OK). */
static int settle_run(const fd_plan *p, const cb_scene_decl *d, cb_scene *s, const double *xs, double *x, double *v,
                      const char *method, int K, const char *dt_s, double secs, cb_config *c, double *strain,
                      double *res, int *sst) {
  double dt;
  cb_parse_double(dt_s, &dt);
  char s1[64], s2[64], s3[64], s4[64];
  snprintf(s1, sizeof s1, "integrator.method=%s", method);
  snprintf(s2, sizeof s2, "integrator.iters=%d", K);
  snprintf(s3, sizeof s3, "integrator.dt=%s", dt_s);
  snprintf(s4, sizeof s4, "integrator.damping=%.17g", exp(-4.0 * dt));
  const char *sets[] = {s1, s2, s3, s4, "integrator.substeps=1", NULL};
  cb_integrator *it = NULL;
  int st = cb_scene_decl_config(p->e, d, sets, c);
  if (st == CB_OK) st = cb_integrator_from_config(c, s, NULL, &it);
  if (st) return st;
  int n3 = 3 * s->mesh.nv;
  memcpy(x, xs, (size_t)n3 * sizeof(double));
  memset(v, 0, (size_t)n3 * sizeof(double));
  int frames = secs > 0 ? (int)lround(secs / c->dt) : 1, from = secs > 0 ? frames - frames / 4 : 0, navg = 0;
  double sum = 0;
  *sst = CB_OK;
  *res = 0;
  for (int f = 0; f < frames; f++) {
    cb_step_stats ss;
    *sst = cb_integrator_step(it, x, v, &ss);
    if (cb_status_is_fatal(*sst)) break;
    if (f >= from) {
      double mx, mean;
      fd_strain(s, x, &mx, &mean);
      sum += mean;
      navg++;
      *res = fmax(*res, ss.constraint_residual);
    }
  }
  cb_integrator_free(it);
  if (strain) *strain = navg ? sum / navg : NAN;
  if (cb_status_is_fatal(*sst)) *res = NAN;
  return CB_OK;
}

/* Cell i: scene x1[i]: its static state (the same for every dt: found once), then per dt both methods
 * at every K of the table and at K* (its converged rows). */
int fd_x1_cell(long i, void *ctx, FILE *const *out) {
  const fd_plan *p = ctx;
  const cb_scene_decl *d = p->decl[p->x1[i]];
  static cb_config c;
  cb_scene *s = NULL;
  int st = cb_scene_decl_build(p->e, d, NULL, &c, &s);
  if (st) return st;
  int n3 = 3 * s->mesh.nv;
  double *xs = malloc((size_t)n3 * sizeof(double)), *x = malloc((size_t)n3 * sizeof(double)),
         *v = malloc((size_t)n3 * sizeof(double));
  if (!xs || !x || !v) st = cb_fail_status(CB_ENOMEM, "out of memory");
  if (st == CB_OK) st = static_state(p, d, s, xs);
  double ref_max, ref = NAN, settle = settle_s(p);
  if (st == CB_OK) fd_strain(s, xs, &ref_max, &ref);
  const int *ks = p->quick ? KS_Q : KS;
  int nk = p->smoke ? 2 : p->quick ? 3 : NK;
  for (int di = 0; st == CB_OK && di < ndt(p); di++) {
    /* K*: the first K = 2^j whose one step from x_s at rest has XPBD's residual <= RES_TOL ref */
    int kconv = 1, reached = 0;
    for (; st == CB_OK && !reached && kconv <= kmax(p); kconv *= 2) {
      double res;
      int sst;
      st = settle_run(p, d, s, xs, x, v, "xpbd", kconv, DTS[di], -1.0, &c, NULL, &res, &sst);
      reached = st == CB_OK && !cb_status_is_fatal(sst) && res <= RES_TOL * ref;
      if (reached) break;
    }
    if (!reached) kconv = kmax(p);
    for (int m = 0; st == CB_OK && m < 2; m++)
      for (int kk = 0; st == CB_OK && kk <= nk; kk++) {
        int K = kk < nk ? ks[kk] : kconv, sst;
        double strain, res;
        st = settle_run(p, d, s, xs, x, v, METHODS[m], K, DTS[di], settle, &c, &strain, &res, &sst);
        if (st) break;
        double k = s->def.stretch_k, na = cb_csv_na();
        int ok = !cb_status_is_fatal(sst) && isfinite(strain) && strain > 0;
        int status = cb_status_is_fatal(sst) ? sst : kk == nk && !reached ? CB_NOT_CONVERGED : CB_OK;
        cb_csv_printf(out[T_X1], "%s,%s,%s,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%s\n", d->label,
                      METHODS[m], kk < nk ? "sweep" : "converged", c.dt, K, k, settle, ref, ok ? strain : na,
                      ok ? k * ref / strain : na, ok ? ref / strain : na, res, cb_status_name(status));
      }
  }
  free(xs);
  free(x);
  free(v);
  cb_scene_free(s);
  return st;
}

/* cost hint: per dt, settle_s / dt frames x the iterations of every K and of K* (~1000 assumed) x the
 * springs (~3 per vertex) at 5e-6 ms */
double fd_x1_cost(long i, void *ctx) {
  const fd_plan *p = ctx;
  double c = 50.0;
  for (int di = 0; di < ndt(p); di++)
    c += 2 * settle_s(p) * 30.0 * (1 << di) * (p->quick ? 1111 : 1188) * 3 * p->nv[p->x1[i]] * 5e-6;
  return c;
}
