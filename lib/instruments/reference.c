/* The converged implicit Euler step (see reference.h for the method and its
 * stopping rule). Its solve is independent of integrator_newton.c on
 * purpose (own Newton loop, own shift rule, own line search, always CHOLMOD),
 * so the reference does not share the code path of the methods it measures;
 * the objective it minimises -- F, grad F, xhat and v1 = (x1 - x0)/dt -- is
 * the shared one (objective.h), so every method is measured against the
 * same F. */
#include "reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/objective.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "vec.h"

enum { REF_MAX_HALVINGS = 60 };
#define REF_ARMIJO 1e-4 /* F(x + a dx) <= F(x) + 1e-4 a grad F . dx */
#define REF_FLAT 1e-12  /* |grad F . dx| / S below which F cannot resolve the decrease */
#define REF_MU_MAX 1e12 /* largest shift tried, in units of mu0 */

struct cb_reference {
  cb_scene *scene;
  cb_reference_params p;
  cb_solver *chol;
  cb_objective obj;    /* F, grad F, xhat of the step */
  double *x, *xt, *xs; /* 3*nv */
  double *gF, *dx;     /* 3*nfree */
};

cb_reference_params cb_reference_params_default(void) {
  cb_reference_params p = {.dt = 1.0 / 30, .tol = 1e-12, .tol_dx = 0, .max_iters = 500, .log = NULL, .log_ctx = NULL};
  return p;
}

void cb_reference_free(cb_reference *r) {
  if (!r) return;
  cb_solver_free(r->chol);
  cb_objective_free(&r->obj);
  free(r->x);
  free(r->xt);
  free(r->xs);
  free(r->gF);
  free(r->dx);
  free(r);
}

int cb_reference_alloc(cb_scene *s, const cb_reference_params *p, cb_reference **out) {
  *out = NULL;
  if (!(p->dt > 0) || !(p->tol >= 0) || !(p->tol_dx >= 0) || p->max_iters < 1)
    return cb_fail("reference: need dt > 0, tol >= 0, tol_dx >= 0, max_iters >= 1");
  cb_reference *r = cb_calloc(1, sizeof *r);
  if (!r) return CB_ENOMEM;
  r->scene = s;
  r->p = *p;
  if (r->p.tol_dx == 0) { /* 1e-12 x diagonal of the rest bounding box */
    double D = cb_mesh_bbox_diagonal(&s->mesh);
    r->p.tol_dx = 1e-12 * (D > 0 ? D : 1.0);
  }
  size_t n3 = (size_t)3 * s->mesh.nv, nf = (size_t)s->sys.A.n;
  int st = cb_objective_init(&r->obj, s);
  r->x = cb_malloc(n3, sizeof(double));
  r->xt = cb_malloc(n3, sizeof(double));
  r->xs = cb_malloc(n3, sizeof(double));
  r->gF = cb_malloc(nf ? nf : 1, sizeof(double));
  r->dx = cb_malloc(nf ? nf : 1, sizeof(double));
  if (st == CB_OK && (!r->x || !r->xt || !r->xs || !r->gF || !r->dx)) st = CB_ENOMEM;
  cb_solver_params sp = cb_solver_params_default();
  if (st == CB_OK) st = cb_solver_alloc("cholmod", &sp, s->sys.A.n, &r->chol);
  if (st == CB_OK) st = cb_solver_analyze(r->chol, &s->sys.A);
  if (st) {
    cb_reference_free(r);
    return st;
  }
  *out = r;
  return CB_OK;
}

const cb_reference_params *cb_reference_get_params(const cb_reference *r) { return &r->p; }

double cb_reference_objective(cb_reference *r, const double *x0, const double *v0, const double *x, double *gF) {
  cb_objective_begin(&r->obj, x0, v0, r->p.dt);
  return cb_objective_eval(&r->obj, x, gF, NULL);
}

static void move(const cb_scene *s, double *x, const double *base, const double *dx, double alpha) {
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) x[3 * i + a] = base[3 * i + a] + alpha * dx[3 * k + a];
  }
}

int cb_reference_step(cb_reference *r, const double *x0, const double *v0, double *xstar, cb_reference_stats *st) {
  memset(st, 0, sizeof *st);
  double t0 = cb_now_ms();
  cb_scene *s = r->scene;
  cb_sparse *A = &s->sys.A;
  int n3 = 3 * s->mesh.nv, nf = A->n;
  double dt = r->p.dt;
  cb_objective_begin(&r->obj, x0, v0, dt); /* xhat = x0 + dt v0 */
  cb_objective_guess(&r->obj, r->x, 1);    /* x(0) = xhat, as the integrator's "predict" */
  double g0 = 0, alpha = 1.0, mu = 0;
  double mbar = cb_free_mass(s) / (s->model.nfree > 0 ? s->model.nfree : 1);
  double mu0 = 1e-3 * mbar / (dt * dt); /* first shift: 1e-3 of the mean mass term */
  int status = CB_NOT_CONVERGED, dx_small = 0, hessian = 0;
  for (int k = 0;; k++) {
    double S = 0, F = cb_objective_eval(&r->obj, r->x, r->gF, &S);
    double gn = sqrt(cb_vec_dot(nf, r->gF, r->gF));
    if (k == 0) g0 = gn;
    st->F = F;
    st->grad_norm = gn;
    st->rel_grad = g0 > 0 ? gn / g0 : 0;
    st->iters = k;
    if (r->p.log) r->p.log(r->p.log_ctx, k, gn, st->rel_grad, F, alpha, hessian);
    if (!isfinite(F) || !isfinite(gn)) {
      status = CB_DIVERGED;
      break;
    }
    if (gn <= r->p.tol * g0 || gn == 0) {
      status = CB_OK;
      break;
    }
    if (dx_small) {
      status = CB_OK;
      st->by_dx = 1;
      break;
    }
    if (k == r->p.max_iters) {
      status = CB_NOT_CONVERGED;
      break;
    }

    /* A = M/dt^2 + H(x): exact Hessian if SPD, else the drop fix */
    cb_system_assemble(&s->sys, r->x, 1.0 / (dt * dt), CB_DEF_NONE, 0.0);
    int fs = cb_solver_factor(r->chol, A);
    hessian = 1;
    if (fs == CB_NOT_SPD) { /* A + mu I, mu = mu_prev/4 (or mu0) growing x4 until CHOLMOD succeeds */
      hessian = 2;
      st->not_spd_fallbacks++;
      mu = mu > 0 ? mu / 4 : mu0;
      for (; fs == CB_NOT_SPD && mu <= REF_MU_MAX * mu0; mu *= 4) {
        cb_system_assemble(&s->sys, r->x, 1.0 / (dt * dt), CB_DEF_NONE, mu);
        fs = cb_solver_factor(r->chol, A);
        if (fs == CB_OK) break;
      }
      if (fs == CB_NOT_SPD) { /* last resort: the drop fix (A = M/dt^2 + PSD) */
        cb_system_assemble(&s->sys, r->x, 1.0 / (dt * dt), CB_DEF_DROP, 0.0);
        fs = cb_solver_factor(r->chol, A);
      }
      if (mu > st->max_shift) st->max_shift = mu;
    }
    if (fs == CB_OK) {
      for (int i = 0; i < nf; i++) r->gF[i] = -r->gF[i]; /* b = -grad F */
      fs = cb_solver_solve(r->chol, A, r->gF, r->dx);
      for (int i = 0; i < nf; i++) r->gF[i] = -r->gF[i];
    }
    if (fs) {
      status = fs > 0 ? fs : CB_LINEAR_FAILED;
      break;
    }

    double slope = cb_vec_dot(nf, r->gF, r->dx); /* grad F . dx < 0 for SPD A */
    if (!(slope < 0)) {
      status = CB_LS_FAILED;
      break;
    }
    alpha = 1.0;
    int ok = -slope <= REF_FLAT * S; /* decrease below F's round-off: full step */
    memcpy(r->xt, r->x, (size_t)n3 * sizeof(double));
    if (ok) move(s, r->xt, r->x, r->dx, 1.0);
    for (int h = 0; !ok && h <= REF_MAX_HALVINGS; h++, alpha *= 0.5) {
      move(s, r->xt, r->x, r->dx, alpha);
      double Ft = cb_objective_eval(&r->obj, r->xt, NULL, NULL);
      if (Ft <= F + REF_ARMIJO * alpha * slope) ok = 1;
      else st->ls_backtracks++;
      if (ok) break;
    }
    if (!ok) {
      status = CB_LS_FAILED;
      break;
    }
    double dmax = 0;
    for (int i = 0; i < nf; i++) dmax = fmax(dmax, fabs(alpha * r->dx[i]));
    st->last_dx = dmax;
    memcpy(r->x, r->xt, (size_t)n3 * sizeof(double));
    if (dmax <= r->p.tol_dx) dx_small = 1;
  }
  memcpy(xstar, r->x, (size_t)n3 * sizeof(double));
  st->status = status;
  st->wall_ms = cb_now_ms() - t0;
  return status;
}

double cb_mnorm_diff(const cb_scene *s, const double *a, const double *b) {
  double sum = 0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int c = 0; c < 3; c++) {
      double d = a[3 * i + c] - b[3 * i + c];
      sum += s->mass[i] * d * d; /* sum_i m_i |a_i - b_i|^2 */
    }
  }
  return sqrt(sum);
}

double cb_step_error(const cb_scene *s, const double *x, const double *xstar, const double *x0) {
  double num = cb_mnorm_diff(s, x, xstar), den = cb_mnorm_diff(s, xstar, x0);
  return den > 0 ? num / den : num; /* |x - x*|_M / |x* - x0|_M */
}

double cb_free_mass(const cb_scene *s) {
  double m = 0;
  for (int k = 0; k < s->model.nfree; k++) m += s->mass[s->free_vertex[k]];
  return m;
}

int cb_reference_advance(cb_reference *r, double *x, double *v, cb_reference_stats *st) {
  int status = cb_reference_step(r, x, v, r->xs, st);
  cb_objective_velocity(&r->obj, r->xs, v); /* v1 = (x1 - x0)/dt; pins keep their v0 */
  memcpy(x, r->xs, (size_t)3 * r->scene->mesh.nv * sizeof(double));
  return status;
}

double cb_state_energy(const cb_scene *s, const double *x, const double *v) {
  return cb_scene_kinetic(s, v) + cb_system_energy(&s->sys, x, NULL, NULL);
}
