/* locking, S1 (results/locking_shape.csv): shape matching under explicit
 * integration against springs, and the shape error at the end. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include <clothbench/timer.h>
#include <clothbench/polar.h>
#include "csv.h"
#include "bind.h"
#include "stability.h"

#include "locking.h"

/* ---- S1: shape matching under explicit integration --------------------------------- */

/* Distance to the best-fit rigid motion of the rest shape: min over rotations R and
 * translations t of sqrt(sum m_i |x_i - R X_i - t|^2 / sum m_i) (the mass-weighted
 * Procrustes fit: t from the centroids, R the polar rotation of sum m (x - c)(X - C)^T,
 * polar.h, planar and collinear shapes included), in m; *size the rest shape's RMS radius
 * sqrt(sum m |X - C|^2 / sum m) about its centroid C, in m. */
static double rigid_distance(const cb_scene *s, const double *x, double *size) {
  double c[3] = {0, 0, 0}, C[3] = {0, 0, 0}, M = 0, A[9] = {0}, R[9];
  const double *X = s->mesh.x;
  for (int i = 0; i < s->mesh.nv; i++) {
    M += s->mass[i];
    for (int a = 0; a < 3; a++) {
      c[a] += s->mass[i] * x[3 * i + a];
      C[a] += s->mass[i] * X[3 * i + a];
    }
  }
  if (!(M > 0)) {
    *size = NAN;
    return NAN;
  }
  for (int a = 0; a < 3; a++) {
    c[a] /= M;
    C[a] /= M;
  }
  double r2 = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    for (int a = 0; a < 3; a++) {
      r2 += s->mass[i] * (X[3 * i + a] - C[a]) * (X[3 * i + a] - C[a]);
      for (int b = 0; b < 3; b++) A[3 * a + b] += s->mass[i] * (x[3 * i + a] - c[a]) * (X[3 * i + b] - C[b]);
    }
  cb_polar33(A, R, NULL);
  double d2 = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    for (int a = 0; a < 3; a++) {
      double g = c[a];
      for (int b = 0; b < 3; b++) g += R[3 * a + b] * (X[3 * i + b] - C[b]);
      d2 += s->mass[i] * (x[3 * i + a] - g) * (x[3 * i + a] - g);
    }
  *size = sqrt(r2 / M);
  return sqrt(d2 / M);
}

/* ---- the S1 cell: the same simulated time at every dt, classified by growth rate ---------
 *
 * Every cell runs S1_T seconds of simulated time (steps = round(T/dt)), whatever its dt, so
 * that cells differ by dt only. The state is sampled at S1_SAMPLES evenly spaced times: the
 * energy ratio r = (E - E0)/S (the classifier of explicit_stability: diverged, which stops
 * the cell, at NaN or r > R_d), and the shape error d = rigid-fit distance / size. A
 * quantity a(t) grows by its envelope: A1 = max a over (T/4, T/2], A2 = max a over (T/2, T],
 *   exponent p = log2(A2/A1)   (a power law t^q gives p = q; exponential growth e^{lambda t}
 *                               gives p = lambda T / (2 ln 2), which grows with T)
 *   rate lambda = ln(A2/A1) / (T/2)  per second.
 * a is the energy excess max(r, 0) + S1_FLOOR_E and the shape error d + S1_FLOOR_D (floors
 * well above the start velocity's 1e-6 S, so that the jitter of a quantity near 0 is no
 * growth: an envelope must rise from its floor to 16 times it to count). A cell is
 *   diverged  as in explicit_stability (non-finite, or the energy rose by more than R_d S);
 *   unstable  if its energy rose by more than R_u S, or either envelope grew faster than any
 *             power t^S1_MAX_EXP (p > S1_MAX_EXP): exponential growth, an instability;
 *   falling   if neither, but its shape error at the end is beyond the bounds (max edge
 *             strain > 1 or rigid-fit distance > 0.5 of the size): the cloth falls from its
 *             pin or sags, growing like a power of t with its energy bounded. Not an
 *             instability (issue 31 §6: the chain at alpha = 0.01 falls while its energy
 *             goes down);
 *   stable    otherwise. */
#define S1_T 2.0 /* s: simulated time of every cell (--smoke: 0.5 s) */
#define S1_SAMPLES 64
#define S1_FLOOR_E 1e-2 /* energy excess: 1% of S */
#define S1_FLOOR_D 1e-4 /* shape error: 0.01% of the size */
#define S1_MAX_EXP 4.0
#define S1_MAX_STRAIN 1.0
#define S1_MAX_RIGID 0.5

typedef struct {
  const char *cls;
  long steps;
  double t_end, max_ratio, final_ratio, e_exp, d_exp, d_rate, e_rate, wall_ms;
  int step_status;
} s1_result;

/* envelope growth of a[0..n) sampled at t[0..n) over (T/4, T/2] and (T/2, T]: *p the exponent, *rate per s */
static void s1_growth(const double *t, const double *a, int n, double T, double *p, double *rate) {
  double a1 = 0, a2 = 0;
  for (int i = 0; i < n; i++) {
    if (t[i] > T / 4 && t[i] <= T / 2 * (1 + 1e-12)) a1 = fmax(a1, a[i]);
    else if (t[i] > T / 2 * (1 + 1e-12)) a2 = fmax(a2, a[i]);
  }
  *p = a1 > 0 && a2 > 0 ? log2(a2 / a1) : NAN;
  *rate = a1 > 0 && a2 > 0 ? log(a2 / a1) / (T / 2) : NAN;
}

static int s1_run(cb_integrator *it, double dt, double T, const double *x0, const double *v0, double S,
                  const cb_stability_params *sp, cb_cell_work *w, double *buf, s1_result *r) {
  const cb_scene *s = it->scene;
  size_t n3 = 3 * (size_t)s->mesh.nv;
  memset(r, 0, sizeof *r);
  it->params.dt = dt;
  memcpy(w->x, x0, n3 * sizeof(double));
  memcpy(w->v, v0, n3 * sizeof(double));
  double E0 = cb_system_energy(&s->sys, w->x, NULL, NULL) + cb_scene_kinetic(s, w->v), size;
  long n = lround(T / dt);
  if (n < 1) n = 1;
  long every = (n + S1_SAMPLES - 1) / S1_SAMPLES; /* at most S1_SAMPLES samples, the last at the end */
  double *ts = buf, *ae = buf + S1_SAMPLES + 1, *ad = buf + 2 * (S1_SAMPLES + 1);
  int ns = 0, failed = 0;
  cb_classifier c;
  cb_classifier_init(&c);
  double t0 = cb_now_ms();
  for (long k = 0; k < n; k++) {
    cb_step_stats st;
    int rc = cb_integrator_step(it, w->x, w->v, &st);
    r->steps = k + 1;
    if (rc != CB_OK) r->step_status = rc;
    if (rc == CB_DIVERGED) {
      cb_classifier_push(&c, sp, NAN);
      break;
    }
    if (rc != CB_OK && rc != CB_NOT_CONVERGED) {
      failed = 1;
      break;
    }
    if ((k + 1) % every == 0 || k + 1 == n) {
      double En = cb_system_energy(&s->sys, w->x, NULL, NULL) + cb_scene_kinetic(s, w->v), q = (En - E0) / S;
      double d = rigid_distance(s, w->x, &size) / size;
      if (ns <= S1_SAMPLES) {
        ts[ns] = (double)(k + 1) * dt;
        ae[ns] = fmax(q, 0) + S1_FLOOR_E;
        ad[ns] = (isfinite(d) ? d : INFINITY) + S1_FLOOR_D;
        ns++;
      }
      if (cb_classifier_push(&c, sp, q)) break;
    }
  }
  r->wall_ms = cb_now_ms() - t0;
  r->t_end = (double)r->steps * dt;
  r->max_ratio = c.max_ratio;
  r->final_ratio = c.samples ? c.last_ratio : 0.0;
  s1_growth(ts, ae, ns, T, &r->e_exp, &r->e_rate);
  s1_growth(ts, ad, ns, T, &r->d_exp, &r->d_rate);
  double smax, srms, d = rigid_distance(s, w->x, &size) / size;
  lk_edge_strain(s, w->x, &smax, &srms);
  if (failed) r->cls = "failed";
  else if (c.cls == CB_CELL_DIVERGED) r->cls = "diverged";
  else if (c.cls == CB_CELL_UNSTABLE || r->e_exp > S1_MAX_EXP || r->d_exp > S1_MAX_EXP) r->cls = "unstable";
  else if (!(smax <= S1_MAX_STRAIN && d <= S1_MAX_RIGID)) r->cls = "falling";
  else r->cls = "stable";
  return CB_OK;
}

/* Cell i: "shape" scene i / (na + 1), method i % (na + 1) - 1 (-1: springs under
 * symplectic Euler, else shape matching at alpha[m]), every dt (one start state), each
 * over the same simulated time. */
int lk_s1_cell(long i, void *ctx, FILE *const *out) {
  int quick = *(const int *)ctx;
  FILE *f = out[T_SHAPE];
  double alphas[5] = {0.01, 0.03, 0.1, 0.3, 1};
  int na = quick ? 3 : 5, ndt = E.smoke ? 2 : quick ? 5 : 13; /* dt: 1/2 (quick) or 1/4 decade apart */
  if (quick) {
    alphas[1] = 0.1;
    alphas[2] = 1;
  }
  /* --smoke: dt 1e-3 and 1e-1 s over 0.5 s; --quick: 1e-3 .. 1e-1 s; else 1e-4 .. 1e-1 s (the upper three decades
   * of explicit_stability's range, which hold both scenes' explicit limits, near 5e-3 s); every cell S1_T. dt =
   * 1e-5 over 2 s would be 200 000 steps a cell, ~100 s for shape matching on the cloth (0.5 ms a step) */
  double T = E.smoke ? 0.5 : S1_T, lo = E.smoke || quick ? -3.0 : -4.0;
  cb_stability_params sp = cb_stability_params_default(); /* R_u, R_d */
  const cb_scene_decl *sc = &SCENES[shape_idx[i / (na + 1)]].scene;
  {
    int m = E.smoke ? na - 1 : (int)(i % (na + 1)) - 1; /* smoke: the one cell is shape matching at alpha = 1 */
    {
      char sa[48];
      snprintf(sa, sizeof sa, "integrator.shape_alpha=%.17g", m >= 0 ? alphas[m] : 1.0);
      const char *sets[10] = {m >= 0 ? "integrator.method=shape_matching" : "integrator.method=explicit", sa};
      int k = 2;
      if (m >= 0) sets[k++] = "material.stretch_k=0"; /* shape matching has no elastic energy of its own */
      sets[k] = NULL;
      cb_config c;
      cb_scene *s = NULL;
      cb_integrator *it = NULL;
      int bs = cb_scene_decl_build(&E, sc, sets, &c, &s);
      if (bs) return bs;
      cb_integrator_params ip;
      cb_integrator_params_from_config(&c, &ip);
      if ((bs = cb_integrator_from_config(&c, s, &ip, &it))) {
        cb_scene_free(s);
        return bs;
      }
      size_t n3 = 3 * (size_t)s->mesh.nv;
      double *x0 = malloc(n3 * sizeof(double)), *v0 = calloc(n3, sizeof(double)),
             *buf = malloc(3 * (S1_SAMPLES + 1) * sizeof(double));
      cb_cell_work w = {0};
      if (!x0 || !v0 || !buf || (bs = cb_cell_work_alloc(s, &w))) {
        free(x0);
        free(v0);
        free(buf);
        cb_integrator_free(it);
        cb_scene_free(s);
        return bs ? bs : CB_ENOMEM;
      }
      memcpy(x0, s->mesh.x, n3 * sizeof(double)); /* the rest shape */
      double S0 = cb_stability_energy_scale(s, x0, v0);
      cb_stability_perturb(s, 1e-6 * S0, 1, v0);
      double S = cb_stability_energy_scale(s, x0, v0);
      for (int j = 0; j < ndt; j++) {
        double dt = pow(10.0, lo + (-1.0 - lo) * j / (ndt - 1));
        s1_result r;
        int rc = s1_run(it, dt, T, x0, v0, S, &sp, &w, buf, &r);
        double smax, srms, size, none = cb_csv_na();
        lk_edge_strain(s, w.x, &smax, &srms);
        double rd = rigid_distance(s, w.x, &size);
        /* springs have no alpha; a cell that failed to run (rc) measured nothing */
#define FIN(v) (rc ? none : isfinite(v) ? (v) : NAN)
        cb_csv_printf(f,
                      "%s,%s,%.6g,%.17g,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                      "%.3f,%s\n",
                      sc->label, m >= 0 ? "shape_matching" : "spring_explicit", m >= 0 ? alphas[m] : none, dt,
                      rc ? "failed" : r.cls, rc ? none : r.max_ratio, rc ? none : r.final_ratio,
                      rc ? none : (double)r.steps, rc ? none : r.t_end, T, FIN(smax), FIN(srms), FIN(rd),
                      FIN(rd / size), FIN(r.e_exp), FIN(r.d_exp), FIN(r.d_rate), rc ? none : r.wall_ms,
                      rc ? cb_status_name(rc) : cb_status_name(r.step_status));
#undef FIN
      }
      cb_cell_work_free(&w);
      free(x0);
      free(v0);
      free(buf);
      cb_integrator_free(it);
      cb_scene_free(s);
    }
  }
  return 0;
}
