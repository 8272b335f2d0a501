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
 * setup_ms and counted in factor_ms.
 *
 * The estimate is amortised over Newton iterations and steps. factor()
 * keeps the Lanczos bounds [lo, hi] of eig(D^-1 A) and, while it reuses
 * them, moves them with Gershgorin's bound G = max_i sum_j |A_ij| / sqrt(D_ii
 * D_jj), one cheap pass over A:
 *   hi <- hi0 max(1, G / G0),   lo <- lo0 min(1, G0 / G)
 * (G0: G when Lanczos ran). On the lab cloth G / hi stays within 1.3-1.46 and
 * lo hi within 0.077-0.080 while the cloth stretches and hi grows from 2.2
 * to 3.1, so the moved bounds follow the spectrum, and they only ever widen
 * (the safe side). The diagonal alone is no guide: some D_ii move by
 * 25-100% from one step to the next.
 * Lanczos runs again when G has moved by more than RHO_REUSE_G (relative)
 * since G0, after RHO_REUSE_MAX factorisations, or when a solve on reused
 * bounds converged much more slowly than they predict: after k >=
 * RHO_CHECK_ITERS iterations a mean residual reduction per iteration worse
 * than sqrt(sigma), sigma being the predicted rate (Chebyshev:
 * rho / (1 + sqrt(1 - rho^2)); Jacobi: rho). It stays safe: a solve on
 * reused bounds whose residual grows past RHO_REUSE_GROWTH |r0| (or
 * diverges, or turns NaN) stops, estimates afresh and starts again from its
 * initial guess, so an underestimate is never left to fail. bench_core
 * measures what the rule saves and what it costs in residual.
 *
 * solver.alpha = auto (params.alpha = CB_AUTO) takes the weight from the same
 * bounds: alpha* = 2 / (lo + hi) minimises max |1 - alpha lambda| over
 * [lo, hi], giving rho = (hi - lo) / (hi + lo) < 1 for any SPD A. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/eigen.h>
#include "solver_iterative.h"
#include <clothbench/timer.h>

#define RHO_REUSE_MAX 30      /* factorisations on one estimate at most */
#define RHO_REUSE_G 0.25      /* Lanczos again when Gershgorin's bound moved by more than 25% */
#define RHO_CHECK_ITERS 8     /* iterations a solve needs before its rate is judged */
#define RHO_REUSE_GROWTH 10.0 /* a solve on a reused estimate restarts when |r| > 10 |r0| */

/* Lanczos settings of the rho estimate. */
static cb_lanczos_params rho_lanczos_params(void) {
  cb_lanczos_params lp = cb_lanczos_params_default();
  lp.max_steps = 300;
  lp.reorth = 0; /* the extremes converge without it, at O(n) per step */
  return lp;
}

typedef struct {
  int accelerated;
  int estimate;         /* rho = auto (Chebyshev) or alpha = auto: Lanczos bounds needed */
  double *dinv, *dhalf; /* D^-1 and D^-1/2 */
  double *r, *last, *work, *x0;
  double rho, alpha;            /* used by the solve */
  cb_sparse_sym S;              /* upper blocks of A, refreshed by factor */
  cb_lanczos_workspace lanczos; /* for the estimate, allocated once */
  /* the last estimate: widened bounds of eig(D^-1 A), factorisations on it, and whether a solve found it wrong */
  int have_bounds, reused, uses, stale;
  double lo, hi;       /* bounds in use */
  double lo0, hi0, g0; /* Lanczos's bounds, and Gershgorin's bound when it ran */
  double rel0;         /* relative residual of the solve's initial guess */
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
  w->x0 = cb_malloc((size_t)n, sizeof(double));
  s->work = w;
  if (!w->dinv || !w->dhalf || !w->r || !w->last || !w->work || !w->x0) return CB_ENOMEM;
  w->estimate = (accelerated && s->params.rho == CB_AUTO) || s->params.alpha == CB_AUTO;
  if (w->estimate) {
    cb_lanczos_params lp = rho_lanczos_params();
    int st = cb_lanczos_workspace_alloc(&w->lanczos, n, &lp);
    if (st) return st;
  }
  if (!(s->params.alpha > 0 || s->params.alpha == CB_AUTO))
    return cb_fail("%s: solver.alpha must be > 0 or auto, got %g", s->type->name, s->params.alpha);
  return CB_OK;
}

static void jw_free(cb_solver *s) {
  jacobi_work *w = s->work;
  if (!w) return;
  free(w->dinv);
  free(w->dhalf);
  free(w->r);
  free(w->last);
  free(w->work);
  free(w->x0);
  cb_sparse_sym_free(&w->S);
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
  if (st == CB_OK && s->params.rho != CB_AUTO && !(s->params.rho > 0 && s->params.rho < 1))
    st = cb_fail("chebyshev: solver.rho must be in (0, 1) or auto, got %g", s->params.rho);
  if (st) jw_free(s);
  return st;
}

static int jw_analyze(cb_solver *s, const cb_sparse *A) {
  jacobi_work *w = s->work;
  cb_sparse_sym_free(&w->S);
  w->have_bounds = 0;
  return cb_sparse_sym_alloc(&w->S, A);
}

/* y = D^-1/2 A D^-1/2 x on the upper-block copy (Lanczos operator). */
typedef struct {
  const cb_sparse_sym *S;
  const double *d;
  double *work;
} sym_scaled_op;

static void sym_scaled_apply(void *ctx, const double *x, double *y) {
  sym_scaled_op *o = ctx;
  for (int i = 0; i < o->S->n; i++) o->work[i] = o->d[i] * x[i];
  cb_sparse_sym_matvec(o->S, o->work, y);
  for (int i = 0; i < o->S->n; i++) y[i] *= o->d[i]; /* y = D A D x */
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

static double rho_of(double alpha, double lo, double hi) {
  return fmax(fabs(1.0 - alpha * lo), fabs(1.0 - alpha * hi));
}

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

/* Widened bounds [lo, hi] of eig(D^-1 A) from a Lanczos run (the same
 * clamp as rho_bounds). */
static void widened(const cb_eig_result *r, double *lo, double *hi) {
  *lo = r->lmin - r->res_min;
  if (!(*lo > 0) && r->lmin > 0) *lo = r->lmin;
  *hi = r->lmax + r->res_max;
}

/* alpha* = 2 / (lo + hi): the weight with the smallest rho over [lo, hi]. */
static double alpha_star(double lo, double hi) { return 2.0 / (lo + hi); }

/* The same test for alpha = auto: rho at alpha* of the current bounds. */
static int rho_done_auto(void *ctx, const cb_eig_result *r) {
  rho_estimate *e = ctx;
  double lo, hi;
  widened(r, &lo, &hi);
  if (!(r->lmin - r->res_min > 0)) return 0;
  e->alpha = alpha_star(lo, hi);
  return rho_done(ctx, r);
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

/* Gershgorin's bound on lambda_max(D^-1/2 A D^-1/2): max_i sum_j |A_ij| d_i d_j
 * (d = D^-1/2), from the upper blocks (each off-diagonal block counts for
 * its rows and, transposed, for its columns). work: n doubles. */
static double gershgorin_max(const cb_sparse_sym *S, const double *d, double *work) {
  memset(work, 0, (size_t)S->n * sizeof(double));
  for (int bj = 0; bj < S->nblk; bj++)
    for (int k = S->bcolp[bj]; k < S->bcolp[bj + 1]; k++) {
      int bi = S->brow[k];
      const double *a = S->val + 9 * (size_t)k;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
          int i = 3 * bi + r, j = 3 * bj + c;
          double v = fabs(a[3 * r + c]) * d[i] * d[j];
          work[i] += v;
          if (bi != bj) work[j] += v;
        }
    }
  double g = 0;
  for (int i = 0; i < S->n; i++) g = fmax(g, work[i]);
  return g;
}

/* A fresh estimate on the upper-block copy: sets w->lo and w->hi. For
 * alpha = auto the Lanczos stopping test uses alpha* of the current Ritz
 * values (rho_done needs a weight). */
static int estimate(cb_solver *s) {
  jacobi_work *w = s->work;
  sym_scaled_op op = {&w->S, w->dhalf, w->work};
  rho_estimate est = {s->params.alpha > 0 ? s->params.alpha : 1.0, 0, 0};
  cb_lanczos_params lp = rho_lanczos_params();
  lp.done = s->params.alpha > 0 ? rho_done : rho_done_auto;
  lp.done_ctx = &est;
  cb_eig_result er;
  double t0 = cb_now_ms();
  int st = cb_lanczos_ws(sym_scaled_apply, &op, &lp, &w->lanczos, &er);
  s->stats.rho_ms += cb_now_ms() - t0;
  s->stats.rho_steps += er.steps;
  s->stats.rho_estimates++;
  if (st) return st;
  widened(&er, &w->lo0, &w->hi0);
  w->lo = w->lo0;
  w->hi = w->hi0;
  w->g0 = gershgorin_max(&w->S, w->dhalf, w->work);
  w->have_bounds = 1;
  w->uses = 0;
  w->stale = 0;
  return CB_OK;
}

/* alpha and rho from the bounds; CB_DIVERGED when rho >= 1. */
static int use_bounds(cb_solver *s) {
  jacobi_work *w = s->work;
  w->alpha = s->params.alpha > 0 ? s->params.alpha : alpha_star(w->lo, w->hi);
  s->stats.alpha = w->alpha;
  if (!w->accelerated) return CB_OK;
  w->rho = s->params.rho > 0 ? s->params.rho : rho_of(w->alpha, w->lo, w->hi);
  s->stats.rho = w->rho;
  if (!(w->rho < 1))
    return cb_fail_status(CB_DIVERGED,
                          "chebyshev: estimated rho(I - alpha D^-1 A) = %g >= 1: Jacobi diverges; "
                          "lower solver.alpha below 2/lambda_max(D^-1 A) or set it to auto",
                          w->rho);
  return CB_OK;
}

static int jw_factor(cb_solver *s, const cb_sparse *A) {
  jacobi_work *w = s->work;
  if (!w->S.bcolp) { /* analyze was skipped: build the pattern now */
    int st = cb_sparse_sym_alloc(&w->S, A);
    if (st) return st;
  }
  for (int i = 0; i < A->n; i++) {
    double d = 0;
    for (int p = A->colp[i]; p < A->colp[i + 1]; p++)
      if (A->rowi[p] == i) d = A->val[p];
    if (!(d > 0)) return cb_fail_status(CB_NOT_SPD, "%s: diagonal entry %d is %g (not positive)", s->type->name, i, d);
    w->dinv[i] = 1.0 / d;
    w->dhalf[i] = 1.0 / sqrt(d);
  }
  cb_sparse_sym_fill(&w->S, A);
  s->stats.rho = 0;
  s->stats.rho_steps = 0;
  s->stats.rho_estimates = 0;
  s->stats.rho_ms = 0;
  w->alpha = s->stats.alpha = s->params.alpha == CB_AUTO ? 0 : s->params.alpha; /* 0 until estimated */
  w->rho = s->params.rho == CB_AUTO ? 0 : s->params.rho;
  if (!w->estimate) {
    if (w->accelerated) s->stats.rho = w->rho;
    return CB_OK;
  }
  /* reuse the last bounds, moved with Gershgorin's bound, unless a solve
   * found them wrong, they are old, or G has moved too far */
  int fresh = !w->have_bounds || !s->params.rho_reuse || w->stale || w->uses >= RHO_REUSE_MAX;
  if (!fresh) {
    double g = gershgorin_max(&w->S, w->dhalf, w->work);
    fresh = !(fabs(g - w->g0) <= RHO_REUSE_G * w->g0);
    w->hi = w->hi0 * fmax(1.0, g / w->g0); /* hi <- hi0 max(1, G/G0) */
    w->lo = w->lo0 * fmin(1.0, w->g0 / g); /* lo <- lo0 min(1, G0/G) */
  }
  w->reused = !fresh;
  if (fresh) {
    int st = estimate(s);
    s->stats.setup_ms = s->stats.rho_ms;
    if (st) return st;
  }
  w->uses++;
  return use_bounds(s);
}

/* One run of the iteration from the guess in x. On a reused estimate
 * (guard = 1) a residual above RHO_REUSE_GROWTH |r0| stops it with
 * CB_DIVERGED, so that the caller re-estimates. */
static int jw_iterate(cb_solver *s, const double *b, double bnorm, double *x, int guard) {
  jacobi_work *w = s->work;
  int n = w->S.n, status = CB_NOT_CONVERGED;
  double alpha = w->alpha, rho2 = w->rho * w->rho, omega = 1.0;
  double r0 = cb_sparse_sym_residual(&w->S, b, x, w->r); /* r = b - A dx */
  w->rel0 = bnorm > 0 ? r0 / bnorm : r0;
  if (cb_iter_stop(s, 0, r0, r0, bnorm, x, &status)) return status;
  status = CB_NOT_CONVERGED;
  memcpy(w->last, x, (size_t)n * sizeof(double));
  for (int k = 0; k < s->params.max_iters; k++) {
    if (w->accelerated) omega = k == 0 ? 1.0 : k == 1 ? 2.0 / (2.0 - rho2) : 4.0 / (4.0 - rho2 * omega);
    for (int i = 0; i < n; i++) {
      double xi = x[i] + alpha * w->dinv[i] * w->r[i];     /* dx + alpha D^-1 r */
      double xn = omega * xi + (1.0 - omega) * w->last[i]; /* omega dx + (1 - omega) last */
      w->last[i] = x[i];                                   /* last <- old */
      x[i] = xn;
    }
    double rn = cb_sparse_sym_residual(&w->S, b, x, w->r);
    if (guard && !(rn <= RHO_REUSE_GROWTH * r0)) return CB_DIVERGED; /* also NaN */
    if (cb_iter_stop(s, k + 1, rn, r0, bnorm, x, &status)) return status;
    status = CB_NOT_CONVERGED;
  }
  return status;
}

static int jw_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  jacobi_work *w = s->work;
  int n = A->n;
  double bnorm = 0;
  for (int i = 0; i < n; i++) bnorm += b[i] * b[i];
  bnorm = sqrt(bnorm);
  int guard = w->reused; /* bounds reused for rho or alpha */
  if (guard) memcpy(w->x0, x, (size_t)n * sizeof(double));
  int status = jw_iterate(s, b, bnorm, x, guard);
  if (guard && status == CB_DIVERGED) { /* the reused bounds were wrong: estimate afresh, start again */
    cb_error_clear();
    w->reused = 0;
    s->stats.history_len = 0;
    int st = estimate(s);
    if (st == CB_OK) st = use_bounds(s);
    if (st) return st;
    memcpy(x, w->x0, (size_t)n * sizeof(double));
    status = jw_iterate(s, b, bnorm, x, 0);
  }
  /* judge the bounds by the rate this solve reached (see the header) */
  if (w->estimate && s->stats.iters >= RHO_CHECK_ITERS) {
    double rho = w->accelerated ? w->rho : rho_of(w->alpha, w->lo, w->hi);
    double sigma = w->accelerated ? rho / (1.0 + sqrt(1.0 - rho * rho)) : rho;
    double rate = pow(s->stats.rel_residual / w->rel0, 1.0 / s->stats.iters);
    if (!(rate <= sqrt(sigma))) w->stale = 1;
  }
  return status;
}

/* The reused bounds are the only thing carried between factorisations. */
static void jw_forget(cb_solver *s) {
  jacobi_work *w = s->work;
  w->have_bounds = 0;
  w->stale = 0;
  w->uses = 0;
}

const cb_solver_type cb_solver_jacobi = {
    .name = "jacobi",
    .flags = CB_SOLVER_USES_ALPHA,
    .alloc = jacobi_alloc,
    .analyze = jw_analyze,
    .factor = jw_factor,
    .solve = jw_solve,
    .free = jw_free,
    .forget = jw_forget,
};
const cb_solver_type cb_solver_chebyshev = {
    .name = "chebyshev",
    .flags = CB_SOLVER_USES_ALPHA | CB_SOLVER_USES_RHO,
    .alloc = chebyshev_alloc,
    .analyze = jw_analyze,
    .factor = jw_factor,
    .solve = jw_solve,
    .free = jw_free,
    .forget = jw_forget,
};
