/* The `shift` policy on the solve side: A + mu I until the factorisation
 * (or CG) succeeds (solver_shift.h).
 *
 *   mu_1 = max(beta, mu_last / grow),  mu_{j+1} = grow mu_j,
 *   beta = beta_rel * mean |A_ii|
 *
 * Nocedal & Wright, "Numerical Optimization" 2nd ed., Algorithm 3.3
 * (Cholesky with added multiple of the identity), warm-started from the last
 * shift that worked as Levenberg-Marquardt does with its damping. The
 * Hessian it shifts is the exact one (the policy's projection is none). */
#include <clothbench/solver_shift.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

cb_shift_params cb_shift_params_default(void) {
  cb_shift_params p = {.beta_rel = 1e-3, .grow = 2.0, .max_tries = 80};
  return p;
}

int cb_shift_alloc(int n, const cb_shift_params *p, cb_shift **out) {
  *out = NULL;
  cb_shift *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->p = p ? *p : cb_shift_params_default();
  if (!(s->p.grow > 1) || !(s->p.beta_rel > 0) || s->p.max_tries < 1) {
    free(s);
    return cb_fail("shift: need grow > 1, beta_rel > 0, max_tries >= 1");
  }
  s->n = n;
  s->diag0 = cb_malloc((size_t)(n > 0 ? n : 1), sizeof(double));
  if (!s->diag0) {
    free(s);
    return CB_ENOMEM;
  }
  *out = s;
  return CB_OK;
}

void cb_shift_free(cb_shift *s) {
  if (!s) return;
  free(s->diag0);
  free(s);
}

static int factor_solve(cb_solver *solver, const cb_sparse *A, const double *b, double *dx, cb_shift_stats *st) {
  int ls = cb_solver_factor(solver, A);
  st->factorizations++;
  st->factor_ms += solver->stats.factor_ms; /* includes any set-up such as a rho estimate */
  if (ls != CB_OK) return ls;
  memset(dx, 0, (size_t)A->n * sizeof(double)); /* iterative solvers start from dx = 0 */
  ls = cb_solver_solve(solver, A, b, dx);
  st->solve_ms += solver->stats.solve_ms;
  st->linear_iters += solver->stats.iters;
  return ls;
}

int cb_shift_solve(cb_shift *sh, cb_solver *solver, cb_sparse *A, const int *diag, const double *b, double *dx,
                   cb_shift_stats *st) {
  memset(st, 0, sizeof *st);
  int ls = factor_solve(solver, A, b, dx, st);
  if (!sh || (ls != CB_NOT_SPD && ls != CB_INDEFINITE)) return ls;
  if (sh->n != A->n || !diag) return cb_fail("shift: no workspace for a %d x %d matrix", A->n, A->n);
  double mean = 0;
  for (int i = 0; i < A->n; i++) {
    sh->diag0[i] = A->val[diag[i]];
    mean += fabs(sh->diag0[i]) / A->n;
  }
  double beta = sh->p.beta_rel * (mean > 0 ? mean : 1.0);
  double mu = fmax(beta, sh->mu_last / sh->p.grow);                         /* mu_1 = max(beta, mu_last / grow) */
  for (int tries = 1; tries < sh->p.max_tries; tries++, mu *= sh->p.grow) { /* mu_{j+1} = grow mu_j */
    for (int i = 0; i < A->n; i++) A->val[diag[i]] = sh->diag0[i] + mu;     /* A + mu I */
    st->mu = mu;
    ls = factor_solve(solver, A, b, dx, st);
    if (ls != CB_NOT_SPD && ls != CB_INDEFINITE) {
      if (ls == CB_OK || ls == CB_NOT_CONVERGED) sh->mu_last = mu;
      return ls;
    }
  }
  return cb_fail_status(ls, "shift: A + mu I still not positive definite at mu = %g after %d factorisations", st->mu,
                        st->factorizations);
}
