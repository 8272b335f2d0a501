/* Quasi-Newton implicit Euler: L-BFGS on the implicit-Euler objective with
 * projective dynamics' constant matrix as the initial Hessian (Liu, Bouaziz
 * and Kavan 2017, "Quasi-Newton methods for real-time simulation of
 * hyperelastic materials"; Nocedal and Wright, Numerical Optimization,
 * Algorithms 7.4 and 7.5).
 *
 *   F(x) = 1/(2 dt^2)|x - xhat|_M^2 + E(x)      (objective.h; every energy term counts)
 *   H0   = M/dt^2 + sum_springs k A A^T (x) I_3 + H_const    (pd_matrix.h), factorised once
 *          per integrator (init) with the linear solver (solver.method, CHOLMOD by default):
 *          with CHOLMOD the n x n P and one 3-column back-solve (Liu et al. 2017, sec. 3), else,
 *          or with integrator.pd_matrix = block, the 3n x 3n P (x) I_3
 *   x_0 = xhat;  g_k = grad F(x_k);  the last m pairs s_i = x_{i+1} - x_i, y_i = g_{i+1} - g_i
 *   two-loop recursion, newest pair first:
 *     q = g_k;  a_i = rho_i s_i.q,  q -= a_i y_i           (rho_i = 1/(y_i.s_i))
 *     r = H0^-1 q                                          (one back-solve)
 *     oldest first:  b = rho_i y_i.r,  r += (a_i - b) s_i
 *   d_k = -r;  x_{k+1} = x_k + alpha d_k, alpha from the line search;
 *   stop when |g_k| <= tol |g_0| (integrator.tol, Newton's), or when the largest
 *   component of the update |alpha d| is <= integrator.tol_dx (Newton's; for
 *   steps where |g_0| is round-off, e.g. from rest without gravity), or after
 *   integrator.iters iterations (status max_iters, as Newton at max_iters).
 *
 * Line search (integrator.lbfgs_line_search):
 *   armijo  backtracking alpha = 1, 1/2, 1/4, ... until
 *           F(x + alpha d) <= F(x) + 1e-4 alpha g.d                (default)
 *   wolfe   the strong Wolfe conditions, Armijo and |g(x + alpha d).d| <= 0.9 |g.d|,
 *           by doubling alpha while the curvature condition fails with F still
 *           decreasing, then bisection of the bracket (at most LS_MAX_TRIALS trials).
 * As in Newton's search (integrator_newton.c), a decrease below F's round-off,
 * |g.d| <= 1e-12 S (S the size of F's summands at the current iterate), takes
 * the full step untested.
 * A pair with y.s <= 1e-12 |y||s| (no positive curvature, e.g. a
 * non-convex stretch of E) is not stored, so the recursion's matrix stays
 * SPD; a direction that is not a descent direction (g.d >= 0) drops the
 * history and restarts from -H0^-1 g.
 *
 * Scope: any scene. H0 holds the spring terms' (stretch and bending springs)
 * and the constant-Hessian terms' stiffness; for the other terms (the exact
 * FEM, dihedral bending, the penalty collider) it holds only the mass part,
 * and the L-BFGS pairs must learn their curvature. No allocation in a step.
 * Step stats: newton_iters = iterations, rel_grad = rel_grad_hat =
 * |g_K|/|g_0|, ls_backtracks the rejected trials, linear_iters the solver's
 * iterations, assemble_ms the objective evaluations, solve_ms the back-solves.
 * The hook sees CB_NEWTON_GRADIENT at every iterate (iter 0 = xhat). */
#include <cblas.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "integrator_keys.h"

#include "pd_matrix.h"

enum { LS_ARMIJO = 0, LS_WOLFE = 1 };
enum { LS_MAX_TRIALS = 40 };
#define LS_FLAT 1e-12 /* |g.d| / S below which F cannot resolve the decrease (integrator_newton.c) */
#define C1 1e-4       /* Armijo's sufficient decrease */
#define C2 0.9        /* Wolfe's curvature (Nocedal and Wright's value for quasi-Newton methods) */

static const cb_lbfgs_params lbfgs_defaults = {.cookie = CB_PARAMS_COOKIE,
                                               .iters = 32,
                                               .tol = 1e-8,
                                               .tol_dx = 0,
                                               .window = 5,
                                               .line_search = LS_ARMIJO,
                                               .matrix = CB_PD_MATRIX_AUTO};

cb_lbfgs_params cb_lbfgs_params_default(void) { return lbfgs_defaults; }

const char *const cb_lbfgs_line_search_names[] = {"armijo", "wolfe", NULL};

#define LP(f) offsetof(cb_lbfgs_params, f)
static const cb_param_key lbfgs_keys[] = {
    CB_KEY_ITERS(LP(iters)),
    CB_KEY_TOL(LP(tol)),
    CB_KEY_TOL_DX(LP(tol_dx)),
    {.name = "lbfgs_window",
     .kind = CB_PARAM_INT,
     .offset = LP(window),
     .def = "5",
     .unit = "pairs",
     .lo = 1,
     .hi = 1000,
     .doc = "lbfgs: the number m of (s, y) pairs kept (Liu et al. 2017 use 5)."},
    {.name = "lbfgs_line_search",
     .kind = CB_PARAM_CHOICE,
     .offset = LP(line_search),
     .def = "armijo",
     .unit = "-",
     .choices = cb_lbfgs_line_search_names,
     .doc = "lbfgs: `armijo` backtracking, or `wolfe` (the strong Wolfe conditions, c1 = 1e-4, c2 = 0.9)."},
    CB_KEY_PD_MATRIX(LP(matrix)),
    CB_KEY_END,
};
#undef LP

typedef struct {
  cb_objective obj;
  cb_pd_global H0;        /* H0 = P, factorised (n x n, or 3n x 3n blocks; pd_matrix.h) */
  int m;                  /* window */
  double *S, *Y;          /* m x 3 nfree, ring buffers */
  double *rho, *a;        /* m */
  int npairs, newest;     /* pairs stored, slot of the newest */
  double *g, *gt, *q, *d; /* 3 nfree: gradient, trial gradient, recursion, direction */
  double *xt;             /* 3 nv: trial iterate */
  double scale_t;         /* S (the size of F's summands) at the last trial */
  int filtered;           /* a term bounds the step (IPC's CCD): the line search starts at cb_system_max_step */
} lbfgs_work;

static void lb_free(cb_integrator *it) {
  lbfgs_work *w = it->state;
  cb_objective_free(&w->obj);
  cb_pd_global_free(&w->H0);
  free(w->S);
  free(w->Y);
  free(w->rho);
  free(w->a);
  free(w->g);
  free(w->gt);
  free(w->q);
  free(w->d);
  free(w->xt);
}

static int lb_init(cb_integrator *it) {
  const cb_lbfgs_params *p = it->type_params;
  lbfgs_work *w = it->state;
  const cb_scene *s = it->scene;
  if (p->iters < 1) return cb_fail("lbfgs: iters must be >= 1, got %d", p->iters);
  if (p->window < 1) return cb_fail("lbfgs: lbfgs_window must be >= 1, got %d", p->window);
  if (!(p->tol >= 0 && p->tol <= 1)) return cb_fail("lbfgs: tol must be in [0, 1], got %g", p->tol);
  if (p->line_search != LS_ARMIJO && p->line_search != LS_WOLFE)
    return cb_fail("lbfgs: unknown line search %d", p->line_search);
  int nf3 = 3 * s->model.nfree, nv3 = 3 * s->mesh.nv;
  size_t mn = (size_t)p->window * (size_t)nf3 + 1;
  w->m = p->window;
  int st = cb_objective_init(&w->obj, s);
  if (st) return st;
  w->S = cb_malloc(mn, sizeof(double));
  w->Y = cb_malloc(mn, sizeof(double));
  w->rho = cb_malloc((size_t)w->m, sizeof(double));
  w->a = cb_malloc((size_t)w->m, sizeof(double));
  w->g = cb_malloc((size_t)nf3 + 1, sizeof(double));
  w->gt = cb_malloc((size_t)nf3 + 1, sizeof(double));
  w->q = cb_malloc((size_t)nf3 + 1, sizeof(double));
  w->d = cb_malloc((size_t)nf3 + 1, sizeof(double));
  w->xt = cb_malloc((size_t)nv3 + 1, sizeof(double));
  if (!w->S || !w->Y || !w->rho || !w->a || !w->g || !w->gt || !w->q || !w->d || !w->xt) return CB_ENOMEM;
  for (int t = 0; t < it->sys->nterms; t++) w->filtered |= it->sys->terms[t]->type->max_step != NULL;
  st = cb_pd_global_init(&w->H0, it, 1, p->matrix); /* once per integrator */
  if (st)
    return cb_fail_status(st, "lbfgs: factorising its initial Hessian M/dt^2 + L failed (%s)", cb_status_name(st));
  return CB_OK;
}

/* xt = x + alpha d on the free DOFs (pinned vertices as in x). */
static void trial(const cb_scene *s, const double *x, const double *d, double alpha, double *xt) {
  memcpy(xt, x, (size_t)3 * s->mesh.nv * sizeof(double));
  for (int b = 0; b < s->model.nfree; b++)
    for (int a = 0; a < 3; a++) xt[3 * s->free_vertex[b] + a] += alpha * d[3 * b + a];
}

/* d = -H^-1 g by the two-loop recursion. Returns the linear solve's status. */
static int direction(cb_integrator *it, lbfgs_work *w, int nf3, cb_step_stats *st) {
  memcpy(w->q, w->g, (size_t)nf3 * sizeof(double));
  for (int c = 0; c < w->npairs; c++) { /* newest first */
    int i = (w->newest - c + w->m) % w->m;
    const double *si = w->S + (size_t)i * nf3, *yi = w->Y + (size_t)i * nf3;
    w->a[i] = w->rho[i] * cblas_ddot(nf3, si, 1, w->q, 1); /* a_i = rho_i s_i.q */
    cblas_daxpy(nf3, -w->a[i], yi, 1, w->q, 1);            /* q -= a_i y_i */
  }
  memset(w->d, 0, (size_t)nf3 * sizeof(double));
  int ls = cb_pd_global_solve(&w->H0, it, w->q, w->d, st); /* r = H0^-1 q */
  for (int c = w->npairs - 1; c >= 0; c--) {               /* oldest first */
    int i = (w->newest - c + w->m) % w->m;
    const double *si = w->S + (size_t)i * nf3, *yi = w->Y + (size_t)i * nf3;
    double b = w->rho[i] * cblas_ddot(nf3, yi, 1, w->d, 1); /* b = rho_i y_i.r */
    cblas_daxpy(nf3, w->a[i] - b, si, 1, w->d, 1);          /* r += (a_i - b) s_i */
  }
  cblas_dscal(nf3, -1.0, w->d, 1); /* d = -r */
  return ls;
}

/* F and its gradient at x + alpha d, into w->xt and w->gt; counts the time. */
static double eval_trial(lbfgs_work *w, const cb_scene *s, const double *x, double alpha, cb_step_stats *st) {
  double t0 = cb_now_ms();
  trial(s, x, w->d, alpha, w->xt);
  double F = cb_objective_eval(&w->obj, w->xt, w->gt, &w->scale_t);
  st->assemble_ms += cb_now_ms() - t0;
  return F;
}

/* The line search along w->d from x (F, slope = g.d < 0, scale S): on
 * success w->xt, w->gt hold the accepted point, *Fn its F, *alpha its step. */
static int line_search(lbfgs_work *w, const cb_scene *s, int kind, const double *x, double F, double slope,
                       double scale, int nf3, double *Fn, double *alpha, cb_step_stats *st) {
  double a = 1.0, amax = 1.0;
  if (w->filtered) { /* the line-search filter (system.h): no trial beyond the fraction no term forbids */
    trial(s, x, w->d, 1.0, w->xt);
    amax = cb_system_max_step(&s->sys, x, w->xt);
    if (!(amax > 0)) return CB_LS_FAILED;
    a = amax;
  }
  if (-slope <= LS_FLAT * scale) { /* the decrease is below F's round-off: the full step, untested */
    *Fn = eval_trial(w, s, x, a, st);
    *alpha = a;
    return CB_OK;
  }
  double lo = 0.0, hi = INFINITY;
  for (int trials = 0; trials < LS_MAX_TRIALS; trials++) {
    double Ft = eval_trial(w, s, x, a, st);
    if (!isfinite(Ft) || Ft > F + C1 * a * slope) { /* Armijo fails: shrink */
      hi = a;
    } else if (kind == LS_WOLFE) {
      double dslope = cblas_ddot(nf3, w->gt, 1, w->d, 1);
      if (fabs(dslope) <= C2 * -slope) {
        *Fn = Ft;
        *alpha = a;
        return CB_OK;
      }                                          /* strong Wolfe */
      if (dslope < 0 && a >= amax && amax < 1) { /* going down, but the filter allows no longer step */
        *Fn = Ft;
        *alpha = a;
        return CB_OK;
      }
      if (dslope < 0) lo = a; /* still going down: longer */
      else hi = a;            /* past the minimum along d: shorter */
    } else {
      *Fn = Ft;
      *alpha = a;
      return CB_OK;
    }
    st->ls_backtracks++;
    a = isinf(hi) ? 2.0 * a : 0.5 * (lo + hi);
    if (amax < 1 && a > amax) a = amax;
  }
  return CB_LS_FAILED;
}

static int lb_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  lbfgs_work *w = it->state;
  const cb_lbfgs_params *p = it->type_params;
  const cb_scene *s = it->scene;
  cb_newton_hook hook = it->params.hook;
  int nf3 = 3 * s->model.nfree;
  cb_objective_begin(&w->obj, x, v, it->params.dt);
  cb_objective_guess(&w->obj, x, 1); /* x_0 = xhat */
  if (w->filtered) { /* the predictor filtered as a step: x_0 = x0 + a (xhat - x0) on the free vertices */
    double a = cb_system_max_step(&s->sys, w->obj.x0, x);
    if (!(a > 0)) a = 0;
    for (int b = 0; a < 1 && b < s->model.nfree; b++) {
      int i = s->free_vertex[b];
      for (int c = 0; c < 3; c++) x[3 * i + c] = w->obj.x0[3 * i + c] + a * (x[3 * i + c] - w->obj.x0[3 * i + c]);
    }
  }
  w->npairs = 0;
  w->newest = w->m - 1;
  double t0 = cb_now_ms(), scale = 0.0;
  double F = cb_objective_eval(&w->obj, x, w->g, &scale);
  st->assemble_ms += cb_now_ms() - t0;
  double g0 = cblas_dnrm2(nf3, w->g, 1), gn = g0;
  cb_newton_event ev;
  memset(&ev, 0, sizeof ev);
  ev.alpha = 1.0;
  int status = CB_NOT_CONVERGED, k = 0;
  for (;; k++) {
    st->F = F;
    st->grad_norm = gn;
    st->rel_grad = st->rel_grad_hat = g0 > 0 ? gn / g0 : 0.0;
    st->newton_iters = k;
    if (!isfinite(F) || !isfinite(gn)) {
      status = CB_DIVERGED;
      break;
    }
    if (hook) {
      ev.iter = k;
      ev.F = F;
      ev.grad_norm = gn;
      ev.rel_grad = st->rel_grad;
      ev.x = x;
      hook(it->params.hook_ctx, CB_NEWTON_GRADIENT, &ev);
    }
    if (gn <= p->tol * g0 || nf3 == 0) {
      status = CB_OK;
      break;
    }
    if (k == p->iters) break; /* max_iters */
    int ls = direction(it, w, nf3, st);
    if (ls != CB_OK && ls != CB_NOT_CONVERGED) {
      status = ls == CB_ENOMEM ? CB_ENOMEM : CB_LINEAR_FAILED;
      break;
    }
    double slope = cblas_ddot(nf3, w->g, 1, w->d, 1);
    if (!(slope < 0) && w->npairs > 0) { /* not a descent direction: drop the history, -H0^-1 g */
      w->npairs = 0;
      ls = direction(it, w, nf3, st);
      if (ls != CB_OK && ls != CB_NOT_CONVERGED) {
        status = ls == CB_ENOMEM ? CB_ENOMEM : CB_LINEAR_FAILED;
        break;
      }
      slope = cblas_ddot(nf3, w->g, 1, w->d, 1);
    }
    if (!(slope < 0)) {
      status = CB_LS_FAILED;
      break;
    }
    double Fn, alpha;
    if (line_search(w, s, p->line_search, x, F, slope, scale, nf3, &Fn, &alpha, st) != CB_OK) {
      status = CB_LS_FAILED;
      break;
    }
    /* the new pair: s = alpha d, y = g_new - g */
    int slot = (w->newest + 1) % w->m;
    double *si = w->S + (size_t)slot * nf3, *yi = w->Y + (size_t)slot * nf3;
    for (int i = 0; i < nf3; i++) {
      si[i] = alpha * w->d[i];
      yi[i] = w->gt[i] - w->g[i];
    }
    double ys = cblas_ddot(nf3, yi, 1, si, 1);
    if (ys > 1e-12 * cblas_dnrm2(nf3, yi, 1) * cblas_dnrm2(nf3, si, 1)) { /* positive curvature: keep it */
      w->rho[slot] = 1.0 / ys;
      w->newest = slot;
      if (w->npairs < w->m) w->npairs++;
    }
    ev.step_max = fabs(alpha) * fabs(w->d[cblas_idamax(nf3, w->d, 1)]);
    ev.alpha = alpha;
    memcpy(x, w->xt, (size_t)3 * s->mesh.nv * sizeof(double));
    memcpy(w->g, w->gt, (size_t)nf3 * sizeof(double));
    F = Fn;
    scale = w->scale_t;
    gn = cblas_dnrm2(nf3, w->g, 1);
    if (p->tol_dx > 0 && ev.step_max <= p->tol_dx) { /* converged by its step size */
      st->F = F;
      st->grad_norm = gn;
      st->rel_grad = st->rel_grad_hat = g0 > 0 ? gn / g0 : 0.0;
      st->newton_iters = k + 1;
      status = isfinite(F) && isfinite(gn) ? CB_OK : CB_DIVERGED;
      break;
    }
  }
  cb_objective_velocity(&w->obj, x, v);
  return status;
}

const cb_integrator_type cb_integrator_lbfgs = {
    .name = "lbfgs",
    .flags = CB_INTEGRATOR_LINEAR_SOLVER | CB_INTEGRATOR_STEP_FILTER,
    .size = sizeof(lbfgs_work),
    .params_size = sizeof(cb_lbfgs_params),
    .params_default = &lbfgs_defaults,
    .keys = lbfgs_keys,
    .init = lb_init,
    .step = lb_step,
    .free = lb_free,
};
