/* The implicit-Euler objective (objective.h). The operation order is the
 * one Newton and the reference step always used, so their results are
 * unchanged bit for bit. */
#include <clothbench/objective.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

int cb_objective_init(cb_objective *o, const cb_scene *s) {
  memset(o, 0, sizeof *o);
  size_t n3 = (size_t)3 * s->mesh.nv;
  o->scene = s;
  o->x0 = cb_malloc(n3, sizeof(double));
  o->xhat = cb_malloc(n3, sizeof(double));
  o->g = cb_malloc(n3, sizeof(double));
  if (!o->x0 || !o->xhat || !o->g) {
    cb_objective_free(o);
    return CB_ENOMEM;
  }
  return CB_OK;
}

void cb_objective_free(cb_objective *o) {
  if (!o) return;
  free(o->x0);
  free(o->xhat);
  free(o->g);
  o->x0 = o->xhat = o->g = NULL;
}

void cb_objective_begin(cb_objective *o, const double *x0, const double *v0, double dt) {
  int n3 = 3 * o->scene->mesh.nv;
  o->dt = dt;
  memcpy(o->x0, x0, (size_t)n3 * sizeof(double));
  for (int i = 0; i < n3; i++) o->xhat[i] = x0[i] + dt * v0[i]; /* xhat = x0 + dt v0 */
}

void cb_objective_guess(const cb_objective *o, double *x, int predict) {
  const cb_scene *s = o->scene;
  size_t n3 = (size_t)3 * s->mesh.nv;
  memcpy(x, predict ? o->xhat : o->x0, n3 * sizeof(double));
  for (int k = 0; k < s->npinned; k++) /* pins at their prescribed positions x0 + dt v0 */
    memcpy(x + 3 * s->pinned[k], o->xhat + 3 * s->pinned[k], 3 * sizeof(double));
}

double cb_objective_eval(cb_objective *o, const double *x, double *gF, double *scale) {
  const cb_scene *s = o->scene;
  double inv_dt2 = 1.0 / (o->dt * o->dt);
  double per[CB_MAX_TERMS];
  double E = cb_system_energy(&s->sys, x, gF ? o->g : NULL, per);
  double inertia = 0.0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) {
      double d = x[3 * i + a] - o->xhat[3 * i + a];
      inertia += s->mass[i] * d * d;                                      /* |x - xhat|_M^2 */
      if (gF) gF[3 * k + a] = s->mass[i] * d * inv_dt2 + o->g[3 * i + a]; /* M(x - xhat)/dt^2 + dE/dx */
    }
  }
  if (scale) {
    *scale = 0.5 * inv_dt2 * inertia;
    for (int t = 0; t < s->sys.nterms; t++) *scale += fabs(per[t]);
  }
  return 0.5 * inv_dt2 * inertia + E;
}

void cb_objective_velocity(const cb_objective *o, const double *x, double *v) {
  const cb_scene *s = o->scene;
  for (int k = 0; k < s->model.nfree; k++) { /* v1 = (x1 - x0)/dt; pinned vertices keep their v0 */
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) v[3 * i + a] = (x[3 * i + a] - o->x0[3 * i + a]) / o->dt;
  }
}

double cb_chebyshev_omega(int k, double rho, double omega_prev) {
  if (k == 0) return 1.0;
  if (k == 1) return 2.0 / (2.0 - rho * rho);  /* omega_1 = 2/(2 - rho^2) */
  return 4.0 / (4.0 - rho * rho * omega_prev); /* omega_k = 4/(4 - rho^2 omega_{k-1}) */
}

double cb_rho_from_updates(const double *d, int n) {
  if (n < 4) return 0.0;
  int a = n / 2, b = n - 1;
  if (!(d[a] > 0) || !(d[b] > 0) || !isfinite(d[a]) || !isfinite(d[b])) return 0.0;
  double rho = pow(d[b] / d[a], 1.0 / (b - a)); /* (d_{n-1}/d_{n/2})^(1/(n-1-n/2)) */
  if (!isfinite(rho) || rho < 0) return 0.0;
  return rho > 0.9999 ? 0.9999 : rho;
}
