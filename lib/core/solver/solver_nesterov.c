/* Nesterov-accelerated Jacobi (`nesterov`): weighted Jacobi with Nesterov's
 * momentum (the lecture, "Accelerable: Chebyshev, Nesterov, Conjugate
 * Gradient"). Jacobi's step dx += alpha D^-1 r is a gradient step on
 * f(x) = 1/2 x^T A x - b^T x in the D-norm, i.e. on z = D^1/2 x, where f has
 * the Hessian D^-1/2 A D^-1/2 with the eigenvalues [mu, L] of D^-1 A.
 * Nesterov's constant-momentum scheme for an L-smooth, mu-strongly convex f
 * (Nesterov, "Introductory Lectures on Convex Optimization", 2004, section
 * 2.2.1, constant step scheme III) then reads:
 *
 *   x_-1 = x_0;  alpha = 1/L;  beta = (sqrt(L) - sqrt(mu)) / (sqrt(L) + sqrt(mu))
 *   for k = 0..K:
 *     y      = x_k + beta (x_k - x_k-1)
 *     x_k+1  = y + alpha D^-1 (b - A y)
 *     stop if |b - A x_k+1| / |b| <= tol (solver_iterative.h)
 *
 * and the error falls like (1 - sqrt(mu/L))^k: sqrt(kappa) iterations per
 * factor e instead of Jacobi's kappa (Chebyshev: about half of Nesterov's).
 * b - A y is linear in y, so it is (1 + beta) r_k - beta r_k-1 from the
 * residuals of the iterates, and an iteration costs one matrix-vector
 * product, as Jacobi's does.
 *
 * The momentum is constant, from a spectral estimate made in factor(), as for
 * Chebyshev with rho = auto: Lanczos on D^-1/2 A D^-1/2 (without
 * reorthogonalisation) gives Ritz values theta_min, theta_max, widened by
 * their residual bounds to L = theta_max + res_max and mu = theta_min -
 * res_min (or theta_min while the bottom is unresolved, res_min >= theta_min).
 * An L too large or a mu too small only slows the method down: for
 * alpha <= 1/lambda_max and any beta in [0, 1) every mode's error
 * e+ = t ((1 + beta) e - beta e-), t = 1 - alpha lambda in [0, 1), decays.
 * A Ritz value theta_min <= 0 proves A is not positive definite (CB_NOT_SPD).
 * The estimate's time is reported as setup_ms and counted in factor_ms. The
 * solver reads neither solver.alpha nor solver.rho. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/eigen.h>
#include "solver_iterative.h"
#include <clothbench/timer.h>

typedef struct {
  double *dinv, *dhalf; /* D^-1, D^-1/2 */
  double *xprev, *r, *rprev, *work;
  double alpha, beta;
  cb_lanczos_workspace lanczos;
} nesterov_work;

static cb_lanczos_params spectrum_params(void) {
  cb_lanczos_params lp = cb_lanczos_params_default();
  lp.max_steps = 300;
  lp.reorth = 0; /* the extremes converge without it, at O(n) per step */
  return lp;
}

static void nw_free(cb_solver *s) {
  nesterov_work *w = s->work;
  if (!w) return;
  free(w->dinv);
  free(w->dhalf);
  free(w->xprev);
  free(w->r);
  free(w->rprev);
  free(w->work);
  cb_lanczos_workspace_free(&w->lanczos);
  free(w);
  s->work = NULL;
}

static int nw_alloc(cb_solver *s, int n) {
  nesterov_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  s->work = w;
  w->dinv = cb_malloc((size_t)n, sizeof(double));
  w->dhalf = cb_malloc((size_t)n, sizeof(double));
  w->xprev = cb_malloc((size_t)n, sizeof(double));
  w->r = cb_malloc((size_t)n, sizeof(double));
  w->rprev = cb_malloc((size_t)n, sizeof(double));
  w->work = cb_malloc((size_t)n, sizeof(double));
  int st = !w->dinv || !w->dhalf || !w->xprev || !w->r || !w->rprev || !w->work ? CB_ENOMEM : CB_OK;
  if (st == CB_OK) {
    cb_lanczos_params lp = spectrum_params();
    st = cb_lanczos_workspace_alloc(&w->lanczos, n, &lp);
  }
  if (st) nw_free(s);
  return st;
}

/* Widened bounds [mu, L] of the spectrum of D^-1 A from the Ritz values. */
static void bounds(const cb_eig_result *e, double *mu, double *L) {
  *L = e->lmax + e->res_max;
  *mu = e->lmin - e->res_min;
  if (!(*mu > 0)) *mu = e->lmin; /* bottom not resolved yet: keep the Ritz value */
}

/* Done when the widened condition number L/mu is known to 1%: beta depends
 * on its square root. */
static int spectrum_done(void *ctx, const cb_eig_result *e) {
  (void)ctx;
  double mu, L;
  bounds(e, &mu, &L);
  return e->lmin - e->res_min > 0 && e->lmin > 0 && (L / mu) <= 1.01 * (e->lmax / e->lmin);
}

static int nw_factor(cb_solver *s, const cb_sparse *A) {
  nesterov_work *w = s->work;
  for (int i = 0; i < A->n; i++) {
    int q = cb_sparse_diag_index(A, i);
    double d = q >= 0 ? A->val[q] : 0;
    if (!(d > 0)) return cb_fail_status(CB_NOT_SPD, "nesterov: diagonal entry %d is %g (not positive)", i, d);
    w->dinv[i] = 1.0 / d;
    w->dhalf[i] = 1.0 / sqrt(d);
  }
  double t0 = cb_now_ms();
  cb_scaled_op op = {A, w->dhalf, w->work};
  cb_lanczos_params lp = spectrum_params();
  lp.done = spectrum_done;
  cb_eig_result e;
  int st = cb_lanczos_ws(cb_scaled_op_apply, &op, &lp, &w->lanczos, &e);
  s->stats.setup_ms = cb_now_ms() - t0;
  s->stats.rho = 0;
  s->stats.rho_steps = e.steps;
  if (st) return st;
  if (!(e.lmin > 0))
    return cb_fail_status(CB_NOT_SPD, "nesterov: D^-1 A has the Ritz value %g <= 0: A is not positive definite",
                          e.lmin);
  double mu, L;
  bounds(&e, &mu, &L);
  w->alpha = 1.0 / L;                                    /* alpha = 1/L */
  w->beta = (sqrt(L) - sqrt(mu)) / (sqrt(L) + sqrt(mu)); /* beta = (sqrt L - sqrt mu) / (sqrt L + sqrt mu) */
  return CB_OK;
}

static int nw_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  nesterov_work *w = s->work;
  int n = A->n, status = CB_NOT_CONVERGED;
  double alpha = w->alpha, beta = w->beta, bnorm = 0;
  for (int i = 0; i < n; i++) bnorm += b[i] * b[i];
  bnorm = sqrt(bnorm);
  double r0 = cb_sparse_residual(A, b, x, w->r); /* r_0 = b - A x_0 */
  if (cb_iter_stop(s, 0, r0, r0, bnorm, x, &status)) return status;
  status = CB_NOT_CONVERGED;
  memcpy(w->xprev, x, (size_t)n * sizeof(double)); /* x_-1 = x_0 */
  memcpy(w->rprev, w->r, (size_t)n * sizeof(double));
  for (int k = 0; k < s->params.max_iters; k++) {
    for (int i = 0; i < n; i++) {
      double y = x[i] + beta * (x[i] - w->xprev[i]);        /* y = x_k + beta (x_k - x_k-1) */
      double ry = w->r[i] + beta * (w->r[i] - w->rprev[i]); /* b - A y = r_k + beta (r_k - r_k-1) */
      w->xprev[i] = x[i];
      w->rprev[i] = w->r[i];
      x[i] = y + alpha * w->dinv[i] * ry; /* x_k+1 = y + alpha D^-1 (b - A y) */
    }
    double rn = cb_sparse_residual(A, b, x, w->r); /* r_k+1 = b - A x_k+1 */
    if (cb_iter_stop(s, k + 1, rn, r0, bnorm, x, &status)) return status;
    status = CB_NOT_CONVERGED;
  }
  return status;
}

const cb_solver_type cb_solver_nesterov = {
    .name = "nesterov",
    .flags = 0,
    .alloc = nw_alloc,
    .factor = nw_factor,
    .solve = nw_solve,
    .free = nw_free,
};
