/* Weighted Jacobi and Chebyshev-accelerated Jacobi (lecture, "The Jacobi
 * Method" and "The Jacobi Method with Chebyshev Acceleration"):
 *
 *   dx <- 0; last <- 0
 *   for k = 0..K:
 *     r <- b - A dx;  if |r| / |b| <= tol: break
 *     omega = 1 (k = 0);  2/(2 - rho^2) (k = 1);  4/(4 - rho^2 omega) (k >= 2)
 *     old <- dx
 *     dx <- dx + alpha D^-1 r
 *     dx <- omega dx + (1 - omega) last
 *     last <- old
 *
 * Plain (weighted) Jacobi is the same loop with omega = 1 throughout. It
 * converges iff rho(I - alpha D^-1 A) < 1; for SPD A that holds for
 * 0 < alpha < 2 / lambda_max(D^-1 A), and vanilla alpha = 1 needs more
 * (e.g. diagonal dominance).
 *
 * rho is the spectral radius of the iteration matrix I - alpha D^-1 A:
 *   rho = max(|1 - alpha lambda_min|, |1 - alpha lambda_max|), lambda in eig(D^-1 A).
 * With solver.rho = auto, factor() estimates lambda_min and lambda_max by
 * Lanczos on the similar symmetric matrix D^-1/2 A D^-1/2 and widens them by
 * the Ritz residual bounds (Ritz values lie inside the spectrum, and an
 * underestimated rho makes Chebyshev diverge). The time is reported as
 * setup_ms and counted in factor_ms. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/eigen.h>
#include "solver_iterative.h"
#include <clothbench/timer.h>

/* Lanczos settings of the rho estimate. */
static cb_lanczos_params rho_lanczos_params(void) {
  cb_lanczos_params lp = cb_lanczos_params_default();
  lp.max_steps = 300;
  lp.reorth = 0; /* the extremes converge without it, at O(n) per step */
  return lp;
}

typedef struct {
  int accelerated;
  double *dinv, *dhalf; /* D^-1 and D^-1/2 */
  double *r, *last, *work;
  double rho;           /* used by Chebyshev */
  cb_lanczos_workspace lanczos; /* for rho = auto, allocated once */
} jacobi_work;

static int jw_alloc(cb_solver *s, int n, int accelerated) {
  jacobi_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  w->accelerated = accelerated;
  w->dinv = cb_malloc((size_t)n, sizeof(double));
  w->dhalf = cb_malloc((size_t)n, sizeof(double));
  w->r = cb_malloc((size_t)n, sizeof(double));
  w->last = cb_malloc((size_t)n, sizeof(double));
  w->work = cb_malloc((size_t)n, sizeof(double));
  s->work = w;
  if (!w->dinv || !w->dhalf || !w->r || !w->last || !w->work) return CB_ENOMEM;
  if (accelerated && s->params.rho == 0) {
    cb_lanczos_params lp = rho_lanczos_params();
    int st = cb_lanczos_workspace_alloc(&w->lanczos, n, &lp);
    if (st) return st;
  }
  if (!(s->params.alpha > 0)) return cb_fail("%s: solver.alpha must be > 0", s->type->name);
  return CB_OK;
}

static void jw_free(cb_solver *s) {
  jacobi_work *w = s->work;
  if (!w) return;
  free(w->dinv); free(w->dhalf); free(w->r); free(w->last); free(w->work);
  cb_lanczos_workspace_free(&w->lanczos);
  free(w);
  s->work = NULL;
}

static int jacobi_alloc(cb_solver *s, int n) {
  int st = jw_alloc(s, n, 0);
  if (st) jw_free(s);
  return st;
}

static int chebyshev_alloc(cb_solver *s, int n) {
  int st = jw_alloc(s, n, 1);
  if (st == CB_OK && s->params.rho != 0 && !(s->params.rho > 0 && s->params.rho < 1))
    st = cb_fail("chebyshev: solver.rho must be in (0, 1) or auto, got %g", s->params.rho);
  if (st) jw_free(s);
  return st;
}

static int jw_analyze(cb_solver *s, const cb_sparse *A) {
  (void)s;
  (void)A;
  return CB_OK;
}

/* rho(I - alpha D^-1 A) = max |1 - alpha lambda| over [lo, hi] (a convex
 * function of lambda, so the max is at an end). The widened interval uses the
 * Ritz residual bounds; D^-1 A of an SPD A has a positive spectrum, so a
 * residual bound larger than the smallest Ritz value (the bottom not yet
 * resolved, e.g. a very ill-conditioned A) keeps the Ritz value there instead
 * of reaching lo <= 0, which would give rho >= 1 and a false "Jacobi
 * diverges" (Chebyshev with a slightly low rho < 1 still converges). */
typedef struct {
  double alpha, rho_lo, rho_hi;
} rho_estimate;

static double rho_of(double alpha, double lo, double hi) { return fmax(fabs(1.0 - alpha * lo), fabs(1.0 - alpha * hi)); }

/* Sets the bounds; clamp: keep the Ritz value where the bottom is unresolved. */
static void rho_bounds(rho_estimate *e, const cb_eig_result *r, int clamp) {
  double lo = r->lmin - r->res_min;
  if (clamp && !(lo > 0) && r->lmin > 0) lo = r->lmin;
  e->rho_lo = rho_of(e->alpha, r->lmin, r->lmax);
  e->rho_hi = rho_of(e->alpha, lo, r->lmax + r->res_max);
}

static int rho_done(void *ctx, const cb_eig_result *r) {
  rho_estimate *e = ctx;
  rho_bounds(e, r, 0);
  return r->lmin - r->res_min > 0 && e->rho_hi - e->rho_lo <= 1e-4 * e->rho_lo; /* rho known to 1e-4, relative */
}

/* With a workspace (ws, and work of n doubles) allocated at set-up. */
static int spectral_radius_ws(const cb_sparse *A, const double *dhalf, double alpha, cb_lanczos_workspace *ws,
                              double *work, double *rho, int *steps) {
  cb_scaled_op op = {A, dhalf, work};
  rho_estimate est = {alpha, 0, 0};
  cb_lanczos_params lp = rho_lanczos_params();
  lp.done = rho_done;
  lp.done_ctx = &est;
  cb_eig_result er;
  int st = cb_lanczos_ws(cb_scaled_op_apply, &op, &lp, ws, &er);
  if (st) return st;
  rho_bounds(&est, &er, 1);
  *rho = est.rho_hi;
  *steps = er.steps;
  return CB_OK;
}

int cb_jacobi_spectral_radius(const cb_sparse *A, const double *dhalf, double alpha, double *rho, int *steps) {
  cb_lanczos_params lp = rho_lanczos_params();
  cb_lanczos_workspace ws;
  double *work = cb_malloc((size_t)A->n, sizeof(double));
  int st = work ? cb_lanczos_workspace_alloc(&ws, A->n, &lp) : CB_ENOMEM;
  if (st == CB_OK) {
    st = spectral_radius_ws(A, dhalf, alpha, &ws, work, rho, steps);
    cb_lanczos_workspace_free(&ws);
  }
  free(work);
  return st;
}

static int jw_factor(cb_solver *s, const cb_sparse *A) {
  jacobi_work *w = s->work;
  for (int i = 0; i < A->n; i++) {
    double d = 0;
    for (int p = A->colp[i]; p < A->colp[i + 1]; p++)
      if (A->rowi[p] == i) d = A->val[p];
    if (!(d > 0)) return cb_fail_status(CB_NOT_SPD, "%s: diagonal entry %d is %g (not positive)", s->type->name, i, d);
    w->dinv[i] = 1.0 / d;
    w->dhalf[i] = 1.0 / sqrt(d);
  }
  s->stats.rho = 0;
  s->stats.rho_steps = 0;
  if (!w->accelerated) return CB_OK;
  if (s->params.rho > 0) {
    w->rho = s->stats.rho = s->params.rho;
    return CB_OK;
  }
  double t0 = cb_now_ms();
  int st = spectral_radius_ws(A, w->dhalf, s->params.alpha, &w->lanczos, w->work, &w->rho, &s->stats.rho_steps);
  s->stats.setup_ms = cb_now_ms() - t0;
  s->stats.rho = w->rho;
  if (st) return st;
  if (!(w->rho < 1))
    return cb_fail_status(CB_DIVERGED, "chebyshev: estimated rho(I - alpha D^-1 A) = %g >= 1: Jacobi diverges; "
                                       "lower solver.alpha below 2/lambda_max(D^-1 A)", w->rho);
  return CB_OK;
}

static int jw_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  jacobi_work *w = s->work;
  int n = A->n, status = CB_NOT_CONVERGED;
  double alpha = s->params.alpha, rho2 = w->rho * w->rho, omega = 1.0;
  double bnorm = 0;
  for (int i = 0; i < n; i++) bnorm += b[i] * b[i];
  bnorm = sqrt(bnorm);
  double r0 = cb_sparse_residual(A, b, x, w->r); /* r = b - A dx */
  if (cb_iter_stop(s, 0, r0, r0, bnorm, x, &status)) return status;
  status = CB_NOT_CONVERGED;
  memcpy(w->last, x, (size_t)n * sizeof(double));
  for (int k = 0; k < s->params.max_iters; k++) {
    if (w->accelerated) omega = k == 0 ? 1.0 : k == 1 ? 2.0 / (2.0 - rho2) : 4.0 / (4.0 - rho2 * omega);
    for (int i = 0; i < n; i++) {
      double xi = x[i] + alpha * w->dinv[i] * w->r[i];  /* dx + alpha D^-1 r */
      double xn = omega * xi + (1.0 - omega) * w->last[i]; /* omega dx + (1 - omega) last */
      w->last[i] = x[i];                                  /* last <- old */
      x[i] = xn;
    }
    double rn = cb_sparse_residual(A, b, x, w->r);
    if (cb_iter_stop(s, k + 1, rn, r0, bnorm, x, &status)) return status;
    status = CB_NOT_CONVERGED;
  }
  return status;
}

const cb_solver_type cb_solver_jacobi = {"jacobi", CB_SOLVER_USES_ALPHA, jacobi_alloc, jw_analyze, jw_factor, jw_solve, jw_free};
const cb_solver_type cb_solver_chebyshev = {"chebyshev", CB_SOLVER_USES_ALPHA | CB_SOLVER_USES_RHO, chebyshev_alloc, jw_analyze, jw_factor, jw_solve, jw_free};
