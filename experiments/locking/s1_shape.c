/* locking, S1 (results/locking_shape.csv): shape matching under explicit
 * integration against springs, and the shape error at the end. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
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

/* Cell i: "shape" scene i / (na + 1), method i % (na + 1) - 1 (-1: springs under
 * symplectic Euler, else shape matching at alpha[m]), every dt (one start state). */
int lk_s1_cell(long i, void *ctx, FILE *const *out) {
  int quick = *(const int *)ctx;
  FILE *f = out[T_SHAPE];
  double alphas[5] = {0.01, 0.03, 0.1, 0.3, 1};
  int na = quick ? 3 : 5, ndt = E.smoke ? 2 : quick ? 7 : 13;
  if (quick) {
    alphas[1] = 0.1;
    alphas[2] = 1;
  }
  cb_stability_params sp = cb_stability_params_default();
  sp.sim_time = quick ? 1.0 : 2.0;
  sp.min_steps = E.smoke ? 20 : 200;
  sp.max_steps = quick ? 1000 : 2000;
  sp.energy_every = 4;
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
      double *x0 = malloc(n3 * sizeof(double)), *v0 = calloc(n3, sizeof(double));
      memcpy(x0, s->mesh.x, n3 * sizeof(double)); /* the rest shape */
      double S0 = cb_stability_energy_scale(s, x0, v0);
      cb_stability_perturb(s, 1e-6 * S0, 1, v0);
      double S = cb_stability_energy_scale(s, x0, v0);
      cb_cell_work w;
      if ((bs = cb_cell_work_alloc(s, &w))) return bs;
      for (int j = 0; j < ndt; j++) {
        double dt = pow(10.0, -5.0 + 4.0 * j / (ndt - 1));
        cb_cell_result r;
        int rc = cb_stability_cell(it, dt, x0, v0, S, &sp, &w, &r);
        double smax, srms, size, none = cb_csv_na();
        lk_edge_strain(s, w.x, &smax, &srms);
        double rd = rigid_distance(s, w.x, &size);
        /* springs have no alpha; a cell that failed to run (rc) measured nothing */
        cb_csv_printf(f, "%s,%s,%.6g,%.17g,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.3f,%s\n", sc->label,
                      m >= 0 ? "shape_matching" : "spring_explicit", m >= 0 ? alphas[m] : none, dt,
                      rc ? "failed" : cb_cell_class_name(r.cls), rc ? none : r.max_energy_ratio,
                      rc ? none : r.final_energy_ratio, rc ? none : (double)r.steps, rc ? none : r.t_end,
                      rc               ? none
                      : isfinite(smax) ? smax
                                       : NAN,
                      rc               ? none
                      : isfinite(srms) ? srms
                                       : NAN,
                      rc             ? none
                      : isfinite(rd) ? rd
                                     : NAN,
                      rc             ? none
                      : isfinite(rd) ? rd / size
                                     : NAN,
                      rc ? none : r.wall_ms, rc ? cb_status_name(rc) : cb_status_name(r.step_status));
      }
      cb_cell_work_free(&w);
      free(x0);
      free(v0);
      cb_integrator_free(it);
      cb_scene_free(s);
    }
  }
  return 0;
}
