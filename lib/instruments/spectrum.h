/* The spectrum that decides Jacobi and Chebyshev: the extreme eigenvalues of
 * D^-1 A for an SPD A (D = diag(A)), through the similar symmetric matrix
 * D^-1/2 A D^-1/2. More generally of diag(d) A diag(d) for any positive d
 * (d = c^-1/2 for the constant diagonal c I of the GAMES103 lab's iteration).
 *
 * Weighted Jacobi x <- x + alpha D^-1 (b - A x) has the iteration matrix
 * I - alpha D^-1 A, whose spectral radius is
 *   rho(alpha) = max(|1 - alpha lambda_min|, |1 - alpha lambda_max|)
 * (lambda = eigenvalues of D^-1 A). It converges iff rho < 1, i.e. for
 * 0 < alpha < 2 / lambda_max; rho is smallest at alpha* = 2/(lambda_min +
 * lambda_max), where rho* = (lambda_max - lambda_min)/(lambda_max + lambda_min).
 *
 * Two ways to get lambda_min and lambda_max:
 *   lanczos: Lanczos on diag(d) A diag(d) for the top, and shift-invert
 *            Lanczos (on its inverse diag(1/d) A^-1 diag(1/d), applied with a
 *            CHOLMOD factor of A) for the bottom, whose smallest eigenvalue
 *            plain Lanczos resolves only slowly on ill-conditioned A. Each
 *            comes with a bound from its Ritz residual.
 *   dense:   GSL's dense symmetric eigensolver (n up to a few thousand). */
#ifndef CB_SPECTRUM_H
#define CB_SPECTRUM_H

#include <clothbench/sparse.h>

typedef struct cb_spectrum {
  double lmin, lmax;        /* smallest and largest eigenvalue of diag(d) A diag(d) */
  double res_min, res_max;  /* error bounds: an eigenvalue lies within res of each (0 for dense) */
  int steps_min, steps_max; /* Lanczos steps for each end (0 for dense) */
  double ms;                /* wall time, ms */
} cb_spectrum;

/* d = D^-1/2 (n doubles): d_i = 1/sqrt(a_ii). CB_NOT_SPD if some a_ii <= 0. */
int cb_jacobi_scaling(const cb_sparse *A, double *d);

/* Lanczos (top) and shift-invert Lanczos (bottom), see above. d = NULL
 * means plain A. Returns CB_NOT_SPD if A has no Cholesky factor. */
int cb_spectrum_lanczos(const cb_sparse *A, const double *d, cb_spectrum *out);

/* GSL dense symmetric eigensolver (all eigenvalues, O(n^3)). */
int cb_spectrum_dense(const cb_sparse *A, const double *d, cb_spectrum *out);

/* rho(I - alpha D^-1 A) = max(|1 - alpha lmin|, |1 - alpha lmax|). */
double cb_jacobi_rho(double lmin, double lmax, double alpha);

#endif
