/* The `shift` definiteness policy, on the solve side (solver_shift.c): the
 * exact Hessian is assembled, and the solve adds mu I to A, raising mu until
 * the factorisation (or CG) succeeds. The Newton integrator calls
 * cb_shift_solve for every policy, with a shift workspace only for `shift`. */
#ifndef CB_SOLVER_SHIFT_H
#define CB_SOLVER_SHIFT_H

#include "solver.h"
#include "sparse.h"

typedef struct cb_shift_params {
  double beta_rel; /* smallest nonzero shift beta = beta_rel * mean |A_ii|. Default 1e-3 */
  double grow;     /* mu is multiplied by this after each failed attempt (> 1). Default 2 */
  int max_tries;   /* factorisations per solve at most. Default 80 */
} cb_shift_params;

cb_shift_params cb_shift_params_default(void);

/* Workspace and warm start of the shift loop (one per integrator). */
typedef struct cb_shift {
  cb_shift_params p;
  int n;
  double *diag0;  /* n: A's diagonal before the shift */
  double mu_last; /* last nonzero shift that worked (warm start), N/m */
} cb_shift;

int cb_shift_alloc(int n, const cb_shift_params *p, cb_shift **out);
void cb_shift_free(cb_shift *s);

typedef struct cb_shift_stats {
  double mu;                  /* shift in the matrix that was solved, units of A (N/m); 0 = none */
  int factorizations;         /* factor calls (1 unless shift retried) */
  int linear_iters;           /* inner iterations of the solves, summed */
  double factor_ms, solve_ms; /* summed over attempts */
} cb_shift_stats;

/* Solves A dx = b (dx starts from 0, the lecture's choice for iterative
 * solvers): factor, then solve. With a shift workspace sh (NULL: no shift),
 * a CB_NOT_SPD from the factorisation or a CB_INDEFINITE from the solve makes
 * it retry with A + mu I (diag: index in A->val of each diagonal entry):
 *   mu_1 = max(beta, mu_last / grow), mu_{j+1} = grow * mu_j
 * until it succeeds (Nocedal & Wright, Numerical Optimization, Alg. 3.3,
 * warm-started like Levenberg-Marquardt's damping). A is left holding the
 * matrix that was solved. Returns the status of the last factor/solve. */
int cb_shift_solve(cb_shift *sh, cb_solver *solver, cb_sparse *A, const int *diag, const double *b, double *dx,
                   cb_shift_stats *st);

#endif
