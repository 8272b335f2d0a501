/* One linear solve traced iteration by iteration against a reference
 * solution x*: for the error-against-time curves of the linear solvers.
 *
 * cb_trace_solve allocates the named solver, runs analyze, factor and one
 * solve of A x = b from x = 0 (the Newton loop's start), and records rows
 *   iter, rel_residual |b - A x_k|/|b|, wall_ms, error |x_k - x*| / |x*|
 * through the solver's per-iteration monitor. wall_ms is cumulative and
 * includes the set-up: factor_ms (the preconditioner, the diagonal, or
 * Chebyshev's rho estimate) plus the solve time up to iteration k, minus the
 * tracer's own time (the error norm and the bookkeeping), which is measured
 * and subtracted. The one-off symbolic analysis (CHOLMOD's ordering) is not
 * counted; it is returned as analyze_ms.
 *
 * Rows are thinned geometrically so that long runs stay readable: every
 * iteration up to keep_all, then iteration k when k >= growth x the last
 * kept one; always kept are the first iteration with rel_residual <=
 * mark_tol and the last iteration. A direct solve gives one row (iter 1). A
 * set-up that fails (not SPD, Chebyshev's rho >= 1) gives one row at iter 0
 * (x = 0) with its status. Rows are allocated before the solve; nothing is
 * allocated inside it. */
#ifndef CB_SOLVE_TRACE_H
#define CB_SOLVE_TRACE_H

#include <clothbench/solver.h>
#include <clothbench/sparse.h>

typedef struct cb_trace_params {
  int keep_all;    /* keep every iteration up to this one. Default 100 */
  double growth;   /* then keep k when k >= growth * (last kept). Default 1.05 */
  double mark_tol; /* also keep the first iteration with rel_residual <= mark_tol. Default 1e-6 */
  double mark_err; /* > 0: also keep the first iteration with error <= mark_err, which is then computed at
                      every iteration until it is found (cb_trace.iter_err). Default 0 (off) */
} cb_trace_params;

cb_trace_params cb_trace_params_default(void);

typedef struct cb_trace_row {
  int iter;
  double rel_residual;
  double wall_ms; /* cumulative, including set-up */
  double error;   /* |x_k - x*| / |x*| */
} cb_trace_row;

typedef struct cb_trace {
  int status;        /* status of the factor (if it failed) or of the solve */
  int iters;         /* iterations done (1 for a direct solve) */
  double analyze_ms; /* symbolic analysis, not in wall_ms */
  double setup_ms;   /* factor_ms: in every row's wall_ms */
  double rho_ms;     /* part of setup_ms spent estimating Chebyshev's rho */
  double rho;        /* Chebyshev: the rho used (estimated or given); else 0 */
  double wall_ms;    /* total: setup + solve, tracer time subtracted */
  int iter_err;      /* the first iteration with error <= mark_err, or -1 (also for a direct solve) */
  int nrows;
  cb_trace_row *rows;
} cb_trace;

/* p: the solver's parameters (its monitor is replaced by the tracer's);
 * xref: x* (n doubles), or NULL to leave error = NaN; x (n doubles, may be
 * NULL): receives the final iterate. Returns 0 if the run was carried out
 * (its outcome, even a divergence, is in out->status), negative on bad input
 * or memory. */
int cb_trace_solve(const char *solver, const cb_solver_params *p, const cb_sparse *A, const double *b,
                   const double *xref, const cb_trace_params *tp, double *x, cb_trace *out);
void cb_trace_free(cb_trace *t);

/* The reference x* for the error column: the CHOLMOD solution refined once,
 * x* = x + A^-1 (b - A x), so that CHOLMOD's own row shows its true error
 * instead of 0. Returns CB_NOT_SPD if A has no Cholesky factor. */
int cb_trace_reference(const cb_sparse *A, const double *b, double *xref);

/* One untraced solve, timed as a user meets it: a fresh solver, analyze (the
 * symbolic analysis: CHOLMOD's ordering), factor and one solve from x = 0,
 * with no monitor. error: |x - x*| / |x*| of the result when xref is given,
 * else NaN. Returns as cb_trace_solve (the outcome is in out->status). */
typedef struct cb_timed_solve {
  int status, iters;
  double analyze_ms, factor_ms, solve_ms, total_ms; /* total = analyze + factor + solve */
  double error, factor_nnz;
} cb_timed_solve;
int cb_trace_timed_solve(const char *solver, const cb_solver_params *p, const cb_sparse *A, const double *b,
                         const double *xref, cb_timed_solve *out);

/* Asymptotic rate of a traced run: the geometric mean of the residual ratios
 * over its tail, (r_N / r_j)^(1/(N - j)), N = the last iteration and j the
 * last kept iteration <= (1 - tail) N (tail = 0.25: the last quarter).
 * NaN if the run has fewer than 2 iterations. */
double cb_trace_rate(const cb_trace_row *rows, int nrows, double tail);

/* The same over a window: rows j and m = the last kept iterations <= f0 N
 * and <= f1 N (0 <= f0 < f1 <= 1), rate (r_m / r_j)^(1/(m - j)). A run has
 * settled on its asymptotic rate when the windows [1/2, 3/4] and [3/4, 1]
 * agree. NaN if the window holds no iteration. */
double cb_trace_rate_window(const cb_trace_row *rows, int nrows, double f0, double f1);

/* The row at iteration k, or the last row before it (NULL if none). */
const cb_trace_row *cb_trace_at(const cb_trace *t, int k);

#endif
