/* Extreme eigenvalues of symmetric operators: Lanczos for large sparse
 * problems, GSL's dense symmetric eigensolver for small ones (and to check
 * Lanczos where both run). Used for the spectral radius of Jacobi's
 * iteration matrix, the explicit stability limit 2/omega_max, and the
 * smallest eigenvalue of Newton's matrix. */
#ifndef CB_EIGEN_H
#define CB_EIGEN_H

#include "sparse.h"

/* y = Op x for a symmetric operator of size n. */
typedef void (*cb_linop)(void *ctx, const double *x, double *y);

struct cb_eig_result;

typedef struct cb_lanczos_params {
  int max_steps; /* Krylov dimension at most (capped at n). Default 300 */
  double tol;    /* stop when both extreme Ritz residuals |beta_k s_k| <= tol |theta|. Default 1e-8 */
  unsigned seed; /* start vector seed; fixed for reproducibility. Default 1 */
  int reorth;    /* 1: full reorthogonalisation (when the basis fits in 1 GiB); 0: none,
                    which still converges to the extreme eigenvalues, at O(n) per step. Default 1 */
  /* Optional stopping test on the current extremes (instead of tol on both):
   * returns non-zero when the caller has what it needs. Default NULL */
  int (*done)(void *ctx, const struct cb_eig_result *r);
  void *done_ctx;
} cb_lanczos_params;

cb_lanczos_params cb_lanczos_params_default(void);

typedef struct cb_eig_result {
  double lmin, lmax;       /* extreme Ritz values */
  double res_min, res_max; /* their residual bounds |beta_k s_k| */
  int steps;               /* Lanczos steps taken */
  int status;              /* CB_OK, or CB_NOT_CONVERGED if max_steps was reached */
  double ms;               /* wall time */
} cb_eig_result;

/* Lanczos, with or without full reorthogonalisation (see params.reorth).
 * Allocates its workspace for the call. */
int cb_lanczos(int n, cb_linop op, void *ctx, const cb_lanczos_params *p, cb_eig_result *out);

/* The same with a workspace allocated once (for callers inside a time step,
 * which must not allocate): its n, max_steps and reorth are fixed at alloc. */
typedef struct cb_lanczos_workspace {
  int n, m, reorth;
  double *Q, *w, *alpha, *beta, *tw;
  int *tiw;
} cb_lanczos_workspace;
int cb_lanczos_workspace_alloc(cb_lanczos_workspace *ws, int n, const cb_lanczos_params *p);
void cb_lanczos_workspace_free(cb_lanczos_workspace *ws);
int cb_lanczos_ws(cb_linop op, void *ctx, const cb_lanczos_params *p, cb_lanczos_workspace *ws, cb_eig_result *out);

/* Operators on a cb_sparse A with a positive diagonal scaling d (length n):
 * y = diag(d) A diag(d) x. With d = D^-1/2 this has the eigenvalues of
 * D^-1 A; with d = M^-1/2 those of M^-1 A. d = NULL means plain A. */
typedef struct cb_scaled_op {
  const cb_sparse *A;
  const double *d;
  double *work; /* n doubles */
} cb_scaled_op;
void cb_scaled_op_apply(void *ctx, const double *x, double *y);

/* Prepares a dense symmetric n x n matrix (row-major, row stride tda) for
 * GSL's symmetric eigensolvers, in place: scales it by a power of two (exact)
 * so that its largest entry has magnitude in [0.5, 1), and sets to zero the
 * entries below DBL_EPSILON^2 of that, far under the solvers' own round-off
 * (n DBL_EPSILON ||A||). GSL's implicit QR sweeps deflate only where
 * |e_i| < DBL_EPSILON (|d_i| + |d_i+1|), a bound that underflows to 0 on
 * subnormal numbers: unscaled, a matrix of entries near 1e-300 (a stiffness
 * of 1e-300) or 1e300 never deflates and the sweep loops for ever.
 * Returns the factor to multiply the computed eigenvalues by (eigenvectors
 * are unchanged); a zero matrix or one with a non-finite entry is left as it
 * is, and the factor is 1. Every gsl_eigen_symm / symmv call goes through it. */
double cb_eigen_prescale(double *a, size_t n, size_t tda);

/* All eigenvalues (ascending) of diag(d) A diag(d) by GSL's dense symmetric
 * solver; eval has n entries. Intended for n up to a few thousand. */
int cb_dense_eigenvalues(const cb_sparse *A, const double *d, double *eval);

#endif
