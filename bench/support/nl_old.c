/* The old lab-frame kernel (nl_old.h): the code of energy_spring.c,
 * energy_gravity.c, objective.c and integrator_nljacobi.c's iterate as they
 * were before the structure-of-arrays kernel: one spring at a time, its
 * gradient scattered to both ends; gravity, the objective and the update
 * each a separate pass. */
#include "nl_old.h"

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

static double old_spring_energy(const cb_term *t, const double *x, double *grad) {
  int ns;
  const int *ends;
  const double *rest;
  double k;
  cb_spring_term_springs(t, &ns, &ends, &rest, &k);
  double E = 0.0;
  for (int e = 0; e < ns; e++) {
    int i = ends[2 * e], j = ends[2 * e + 1];
    double d[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double stretch = l - rest[e];
    double c = k * stretch / l;
    E += 0.5 * k * stretch * stretch;
    if (grad) {
      double g[6];
      for (int a = 0; a < 3; a++) {
        g[a] = c * d[a];
        g[3 + a] = -(c * d[a]);
      }
      const int v[2] = {i, j}; /* cb_stencil_add_gradient with k = 2 */
      for (int a = 0; a < 2; a++)
        for (int b = 0; b < 3; b++) grad[3 * v[a] + b] += g[3 * a + b];
    }
  }
  return E;
}

static double old_gravity_energy(const cb_scene *s, const double *x, double *grad) {
  const double *m = s->model.mass, *g = s->gravity;
  double E = 0.0;
  for (int i = 0; i < s->mesh.nv; i++) {
    E -= m[i] * (g[0] * x[3 * i] + g[1] * x[3 * i + 1] + g[2] * x[3 * i + 2]);
    if (grad)
      for (int a = 0; a < 3; a++) grad[3 * i + a] -= m[i] * g[a];
  }
  return E;
}

static double old_objective_eval(cb_old_lab *o, const double *x, double *gF) {
  const cb_scene *s = o->s;
  double inv_dt2 = 1.0 / (o->obj.dt * o->obj.dt);
  memset(o->grad, 0, (size_t)3 * s->mesh.nv * sizeof(double)); /* cb_system_energy */
  double E = 0.0;
  for (int k = 0; k < s->sys.nterms; k++)
    E += s->sys.terms[k]->type == cb_term_gravity ? old_gravity_energy(s, x, o->grad)
                                                  : old_spring_energy(s->sys.terms[k], x, o->grad);
  double inertia = 0.0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) {
      double d = x[3 * i + a] - o->obj.xhat[3 * i + a];
      inertia += s->mass[i] * d * d;
      gF[3 * k + a] = s->mass[i] * d * inv_dt2 + o->grad[3 * i + a];
    }
  }
  return 0.5 * inv_dt2 * inertia + E;
}

int cb_old_lab_init(cb_old_lab *o, const cb_scene *s, double dt, double damping, int iters, double alpha, double rho) {
  memset(o, 0, sizeof *o);
  for (int t = 0; t < s->sys.nterms; t++) {
    const cb_term *term = s->sys.terms[t];
    if (term->type != cb_term_gravity && (term->type != cb_term_spring || cb_spring_term_is_choi_ko(term)))
      return cb_fail("old lab kernel: term '%s' is neither a linear spring term nor gravity", term->label);
  }
  o->s = s;
  o->dt = dt;
  o->damping = damping;
  o->iters = iters;
  o->alpha = alpha;
  o->rho = rho;
  int nf = s->model.nfree, nv = s->mesh.nv;
  if (cb_objective_init(&o->obj, s)) return -1;
  o->grad = malloc((size_t)3 * nv * sizeof(double));
  o->gF = malloc(((size_t)3 * nf + 1) * sizeof(double));
  o->xprev = malloc((size_t)3 * nv * sizeof(double));
  o->dinv = malloc(((size_t)nf + 1) * sizeof(double));
  if (!o->grad || !o->gF || !o->xprev || !o->dinv) return cb_fail("old lab kernel: out of memory");
  for (int b = 0; b < nf; b++) { /* the lab diagonal m/dt^2 + 4k */
    int i = s->free_vertex[b];
    o->dinv[b] = 1.0 / (s->mass[i] / (dt * dt) + 4.0 * s->def.stretch_k);
  }
  return 0;
}

int cb_old_lab_step(cb_old_lab *o, double *x, double *v, double *Fout, double *rel_grad) {
  const cb_scene *s = o->s;
  int nf = s->model.nfree, nf3 = 3 * nf;
  for (int k = 0; k < nf; k++) /* cb_integrator_step's damping */
    for (int a = 0; a < 3; a++) v[3 * s->free_vertex[k] + a] *= o->damping;
  cb_objective_begin(&o->obj, x, v, o->dt);
  cb_objective_guess(&o->obj, x, 1);
  memcpy(o->xprev, x, (size_t)3 * s->mesh.nv * sizeof(double));
  double omega = 1.0, g0 = 0.0, alpha = o->alpha;
  int status = CB_OK;
  for (int k = 0;; k++) {
    double F = old_objective_eval(o, x, o->gF);
    double gn = cblas_dnrm2(nf3, o->gF, 1);
    if (k == 0) g0 = gn;
    *Fout = F;
    *rel_grad = g0 > 0 ? gn / g0 : 0.0;
    if (!isfinite(F) || !isfinite(gn)) {
      status = CB_DIVERGED;
      break;
    }
    if (k == o->iters) break;
    omega = cb_chebyshev_omega(k, o->rho, omega);
    double dmax = 0.0, d2 = 0.0;
    for (int b = 0; b < nf; b++) {
      double *xi = x + 3 * s->free_vertex[b], *xp = o->xprev + 3 * s->free_vertex[b];
      const double *g = o->gF + 3 * b;
      double step[3];
      for (int a = 0; a < 3; a++) step[a] = o->dinv[b] * g[a];
      for (int a = 0; a < 3; a++) {
        double xk = xi[a];
        double xn = omega * (xk - alpha * step[a]) + (1.0 - omega) * xp[a];
        double dx = xn - xk;
        d2 += dx * dx;
        if (fabs(dx) > dmax) dmax = fabs(dx);
        xp[a] = xk;
        xi[a] = xn;
      }
    }
    (void)d2;
  }
  cb_objective_velocity(&o->obj, x, v);
  int post = cb_scene_post_step(s, o->obj.x0, x, v, o->dt); /* the step's start, kept by the objective */
  return status == CB_OK && post ? post : status;
}

void cb_old_lab_free(cb_old_lab *o) {
  cb_objective_free(&o->obj);
  free(o->grad);
  free(o->gF);
  free(o->xprev);
  free(o->dinv);
}
