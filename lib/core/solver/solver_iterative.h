/* Shared by the iterative solvers (solver_jacobi.c: jacobi, chebyshev;
 * solver_sgs.c: sgs; solver_cg.c: cg, pcg; solver_nesterov.c: nesterov): the
 * stopping and divergence tests, and the residual history, so that every
 * iterative method stops and fails the same way.
 *
 *   converged: |r| / |b| <= tol
 *   diverged:  |r| > 1e6 |r0| (residual growth), or a NaN/Inf
 *   otherwise: CB_NOT_CONVERGED after max_iters */
#ifndef CB_SOLVER_ITERATIVE_H
#define CB_SOLVER_ITERATIVE_H

#include <math.h>

#include <clothbench/solver.h>
#include <clothbench/status.h>

#define CB_DIVERGENCE_GROWTH 1e6

/* Records the relative residual after k iterations (x = the iterate x_k,
 * handed to the optional monitor). Returns 1 when the iteration must stop,
 * with *status = CB_OK (converged) or CB_DIVERGED, and 0 to go on. */
static inline int cb_iter_stop(cb_solver *s, int k, double rnorm, double r0norm, double bnorm, const double *x,
                               int *status) {
  double rel = bnorm > 0 ? rnorm / bnorm : rnorm;
  s->stats.iters = k;
  s->stats.rel_residual = rel;
  if (s->stats.history && s->stats.history_len < s->params.history_cap) s->stats.history[s->stats.history_len++] = rel;
  if (s->params.monitor) s->params.monitor(s->params.monitor_ctx, k, rel, x);
  if (!isfinite(rnorm)) {
    *status = cb_fail_status(CB_DIVERGED, "%s: residual is NaN/Inf at iteration %d", s->type->name, k);
    return 1;
  }
  if (rel <= s->params.tol) {
    *status = CB_OK;
    return 1;
  }
  if (rnorm > CB_DIVERGENCE_GROWTH * r0norm) {
    *status = cb_fail_status(CB_DIVERGED, "%s: residual grew by more than %g at iteration %d", s->type->name,
                             CB_DIVERGENCE_GROWTH, k);
    return 1;
  }
  return 0;
}

#endif
