/* The shared element-Hessian projection (projection.h).
 *
 *   H = V diag(lambda) V^T          (gsl_eigen_symmv: Householder
 *                                    tridiagonalisation + implicit QL)
 *   P(H) = V diag(f(lambda)) V^T,   f = max(., 0) (clamp) or |.| (abs)
 *
 * clamp is the nearest PSD matrix to H in the Frobenius norm (Higham 1988,
 * "Computing a nearest symmetric positive semidefinite matrix"); abs is the
 * "absolute value" modification of Newton's matrix (Nocedal & Wright,
 * Numerical Optimization, 2nd ed., Section 3.4), which keeps the curvature's
 * magnitude instead of discarding it. Both are the spring's `drop` and
 * `mirror` when applied to a spring element (its transverse eigenvalue
 * k(1 - L/l) is the only one that can be negative). */
#include <clothbench/projection.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/eigen.h>
#include <clothbench/status.h>

const char *const cb_projection_names[] = {"none", "clamp", "abs", NULL};

double cb_projection_eigenvalue(cb_projection p, double lambda) {
  switch (p) {
  case CB_PROJ_CLAMP: return lambda < 0 ? 0.0 : lambda; /* max(lambda, 0) */
  case CB_PROJ_ABS: return fabs(lambda);                /* |lambda| */
  default: return lambda;
  }
}

struct cb_projection_work {
  int n;
  gsl_matrix *A, *V;
  gsl_vector *lambda;
  gsl_eigen_symmv_workspace *ws;
};

void cb_projection_work_free(cb_projection_work *w) {
  if (!w) return;
  if (w->A) gsl_matrix_free(w->A);
  if (w->V) gsl_matrix_free(w->V);
  if (w->lambda) gsl_vector_free(w->lambda);
  if (w->ws) gsl_eigen_symmv_free(w->ws);
  free(w);
}

int cb_projection_work_alloc(int n, cb_projection_work **out) {
  *out = NULL;
  if (n < 1) return cb_fail("projection: matrix size must be >= 1, got %d", n);
  gsl_set_error_handler_off();
  cb_projection_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  w->n = n;
  /* GSL allocates with malloc; each call counts as one allocation of the
   * failure injection (status.h), which then skips it as if it returned NULL */
  size_t m = (size_t)n;
  if (!cb_alloc_tick()) w->A = gsl_matrix_alloc(m, m);
  if (w->A && !cb_alloc_tick()) w->V = gsl_matrix_alloc(m, m);
  if (w->V && !cb_alloc_tick()) w->lambda = gsl_vector_alloc(m);
  if (w->lambda && !cb_alloc_tick()) w->ws = gsl_eigen_symmv_alloc(m);
  if (!w->ws) {
    cb_projection_work_free(w);
    return cb_fail_status(CB_ENOMEM, "projection: out of memory for the %d x %d eigensolver workspace", n, n);
  }
  *out = w;
  return CB_OK;
}

int cb_projection_apply(cb_projection p, int n, double *H, cb_projection_work *w) {
  if (p == CB_PROJ_NONE) return 0;
  if (!w || n != w->n) return cb_fail("projection: a %d x %d matrix needs a workspace of that size", n, n);
  memcpy(w->A->data, H, (size_t)n * n * sizeof(double)); /* tda = n: gsl_matrix_alloc packs rows */
  double scale = cb_eigen_prescale(w->A->data, (size_t)n, (size_t)n);
  int st = gsl_eigen_symmv(w->A, w->lambda, w->V, w->ws); /* reads the lower triangle, overwrites A */
  if (st) return cb_fail("projection: gsl_eigen_symmv failed (%s)", gsl_strerror(st));
  double lmax = 0;
  for (int k = 0; k < n; k++) {
    gsl_vector_set(w->lambda, (size_t)k, scale * gsl_vector_get(w->lambda, (size_t)k));
    lmax = fmax(lmax, fabs(gsl_vector_get(w->lambda, (size_t)k)));
  }
  double tol = n * DBL_EPSILON * lmax; /* round-off of a zero eigenvalue: not counted as negative */
  int changed = 0;
  for (int k = 0; k < n; k++) {
    double l = gsl_vector_get(w->lambda, (size_t)k);
    changed += l < -tol;
    gsl_vector_set(w->lambda, (size_t)k, cb_projection_eigenvalue(p, l));
  }
  if (!changed) return 0; /* already PSD: H untouched */
  for (int i = 0; i < n; i++)
    for (int j = 0; j <= i; j++) {
      double s = 0;
      for (int k = 0; k < n; k++) /* P(H)_ij = sum_k V_ik f(lambda_k) V_jk */
        s += gsl_matrix_get(w->V, (size_t)i, (size_t)k) * gsl_vector_get(w->lambda, (size_t)k) *
             gsl_matrix_get(w->V, (size_t)j, (size_t)k);
      H[n * i + j] = H[n * j + i] = s;
    }
  return changed;
}
