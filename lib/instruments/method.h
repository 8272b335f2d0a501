/* Implicit Euler step methods for solver comparisons: Newton with K
 * iterations (K = 1 is Baraff-Witkin) or to convergence, with or without the
 * line search, over one of a fixed set of inner linear solves, and the
 * measurement of one step of such a method against the reference x*.
 *
 * Inner solves (the label is what CSVs carry):
 *   cholmod        sparse Cholesky (exact)
 *   cg32           CG from dx = 0, cut at 32 iterations (solver.tol = 1e-300)
 *   cheb32         Chebyshev-Jacobi, alpha = 1/3, rho = auto, cut at 32 iterations
 *   cg_tol         CG to relative residual 1e-8 (at most 10000 iterations)
 *   cheb_tol       Chebyshev-Jacobi, alpha = 1/3, rho = auto, to 1e-8 (at most 10000)
 *   cheb32_alpha1  Chebyshev-Jacobi as the lab configures it: alpha = 1, rho = auto
 * An inner solve cut at its max_iters is accepted by Newton (inexact Newton).
 *
 * Why alpha = 1/3 for Chebyshev-Jacobi: weighted Jacobi converges iff
 * alpha < 2/lambda_max(D^-1 A). For A = M/dt^2 + sum_e B_e with spring blocks
 * x^T B_e x = (x_i - x_j)^T H_e (x_i - x_j) <= 2 (x_i^T H_e x_i + x_j^T H_e x_j)
 * (H_e PSD under the drop fix), A <= 2 blockdiag(A), and a PSD 3x3 block B obeys
 * B <= 3 diag(B) (Cauchy-Schwarz), so lambda_max(D^-1 A) < 6 for every state:
 * alpha = 1/3 converges always. The measured lambda_max(D^-1 A) on the lab scene
 * goes from 2.2 at rest to 3.8 while the cloth swings, so no alpha fitted to
 * the initial matrix (e.g. 2/2.2) stays safe; and since lambda_min << lambda_max
 * the price of 1/3 instead of the optimal 2/(lambda_min + lambda_max) is about
 * sqrt(2) x in Chebyshev iterations at most. */
#ifndef CB_METHOD_H
#define CB_METHOD_H

#include <clothbench/integrator.h>
#include "reference.h"
#include <clothbench/scene.h>
#include <clothbench/solver.h>

#define CB_METHOD_CONVERGED_TOL 1e-8  /* "converged": relative |grad F| (integrator.tol default) */
#define CB_METHOD_CONVERGED_ITERS 100 /* and at most this many Newton iterations */
#define CB_METHOD_CHEB_ALPHA (1.0 / 3.0)

typedef struct cb_method {
  char name[32];    /* "newton_k1", ..., "newton_converged", "newton_converged_exact" */
  int K;            /* Newton iterations; 0 = converged (tol above) */
  int definiteness; /* cb_definiteness of every Newton update: CB_DEF_DROP, or CB_DEF_SHIFT (exact) */
  int line_search;  /* 0 or 1 */
  char inner[24];   /* inner-solve label (see above) */
  char solver[24];  /* registry name */
  cb_solver_params sp;
} cb_method;

/* Fills m for K (0 = converged), line search and an inner-solve label.
 * Returns CB_EINVAL for an unknown label. */
int cb_method_make(int K, int line_search, const char *inner, cb_method *m);
/* Converged Newton with the exact Hessian, shifted (mu I) only where A is not
 * SPD (definiteness shift): "newton_converged_exact". With the line search it
 * converges quadratically, so it is often the fastest converging variant that
 * the drop fix (linear convergence) is compared with. */
int cb_method_make_exact(int line_search, const char *inner, cb_method *m);

/* Newton integrator for the method on a scene at dt (the method's
 * definiteness, init predict, no tol_dx). For a fixed K, tol = 0: exactly K linear solves (unless
 * the gradient is exactly 0). hook may be NULL. */
int cb_method_integrator(const cb_method *m, cb_scene *s, double dt, cb_newton_hook hook, void *hook_ctx,
                         cb_integrator **out);

/* What one step of a method from (x0, v0) gives against x*. */
typedef struct cb_step_result {
  cb_step_stats st;     /* the integrator's statistics (status, times, iterations) */
  double step_error;    /* |x - x*|_M / |x* - x0|_M */
  double f_minus_fstar; /* F(x) - F(x*), J */
  double setup_ms;      /* part of factor_ms spent estimating rho (Chebyshev) */
  int ls_reduced;       /* Newton iterations whose line search took alpha < 1 */
} cb_step_result;

/* Work arrays for cb_method_step (3*nv each). */
typedef struct cb_method_work {
  double *x, *v;
  double setup_ms;
  int ls_reduced;
} cb_method_work;
int cb_method_work_alloc(const cb_scene *s, cb_method_work *w);
void cb_method_work_free(cb_method_work *w);
/* The hook that cb_method_step needs (pass it with &work to cb_method_integrator). */
void cb_method_hook(void *work, int event, const cb_newton_event *ev);

/* One step of it from (x0, v0), with the inner solver's carried state
 * dropped first (cb_solver_forget), so the result does not depend on how
 * many steps it made before; the result is compared with xstar (whose
 * objective value is Fstar, from cb_reference_objective). x_out (may be NULL)
 * receives the new positions. A failed step keeps its status and, when x is
 * finite, its error. */
int cb_method_step(cb_integrator *it, cb_method_work *w, cb_reference *ref, const double *x0, const double *v0,
                   const double *xstar, double Fstar, cb_step_result *out);

#endif
