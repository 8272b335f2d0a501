/* Extreme eigenvalues of diag(d) A diag(d) (see spectrum.h). */
#include "spectrum.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/eigen.h>
#include <clothbench/solver.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

int cb_jacobi_scaling(const cb_sparse *A, double *d) {
  for (int i = 0; i < A->n; i++) {
    int p = cb_sparse_diag_index(A, i);
    double a = p >= 0 ? A->val[p] : 0.0;
    if (!(a > 0)) return cb_fail_status(CB_NOT_SPD, "diagonal entry %d is %g (not positive)", i, a);
    d[i] = 1.0 / sqrt(a); /* D^-1/2 */
  }
  return CB_OK;
}

double cb_jacobi_rho(double lmin, double lmax, double alpha) {
  return fmax(fabs(1.0 - alpha * lmin), fabs(1.0 - alpha * lmax)); /* rho(I - alpha D^-1 A) */
}

/* y = diag(1/d) A^-1 diag(1/d) x = (diag(d) A diag(d))^-1 x, by a Cholesky solve. */
typedef struct {
  const cb_sparse *A;
  const double *d;
  cb_solver *chol;
  double *work, *z;
} inverse_op;

static void inverse_apply(void *ctx, const double *x, double *y) {
  inverse_op *o = ctx;
  int n = o->A->n;
  for (int i = 0; i < n; i++) o->work[i] = o->d ? x[i] / o->d[i] : x[i];
  cb_solver_solve(o->chol, o->A, o->work, o->z); /* z = A^-1 diag(1/d) x */
  for (int i = 0; i < n; i++) y[i] = o->d ? o->z[i] / o->d[i] : o->z[i];
}

int cb_spectrum_lanczos(const cb_sparse *A, const double *d, cb_spectrum *out) {
  double t0 = cb_now_ms();
  memset(out, 0, sizeof *out);
  int n = A->n;
  double *work = cb_malloc((size_t)n, sizeof(double)), *z = cb_malloc((size_t)n, sizeof(double));
  cb_solver *chol = NULL;
  int st = (!work || !z) ? CB_ENOMEM : CB_OK;
  /* The top of D^-1 A is well separated and converges in a few dozen steps;
   * cb_lanczos also waits for the bottom end, which plain Lanczos resolves
   * slowly, so the step count is capped and the top's own bound reported.
   * The inverse's top (1/lambda_min) converges quickly by construction. */
  cb_lanczos_params top_p = cb_lanczos_params_default(), inv_p = top_p;
  top_p.max_steps = 120;
  top_p.tol = 1e-10;
  inv_p.max_steps = 120;
  inv_p.tol = 1e-7;
  cb_eig_result top, inv;
  if (st == CB_OK) { /* top: Lanczos on diag(d) A diag(d) */
    cb_scaled_op op = {A, d, work};
    st = cb_lanczos(n, cb_scaled_op_apply, &op, &top_p, &top);
  }
  if (st == CB_OK) st = cb_solver_alloc("cholmod", NULL, n, &chol);
  if (st == CB_OK) st = cb_solver_analyze(chol, A);
  if (st == CB_OK) st = cb_solver_factor(chol, A);
  if (st == CB_OK) { /* bottom: the top of the inverse, mu_max = 1 / lambda_min */
    inverse_op op = {A, d, chol, work, z};
    st = cb_lanczos(n, inverse_apply, &op, &inv_p, &inv);
  }
  if (st == CB_OK) {
    double mu = inv.lmax, r = inv.res_max;
    out->lmax = top.lmax;
    out->res_max = top.res_max;
    out->steps_max = top.steps;
    out->lmin = 1.0 / mu;
    /* an eigenvalue of the inverse lies in [mu - r, mu + r], so one of A's lies in
     * [1/(mu + r), 1/(mu - r)]: the bound on lambda_min is 1/(mu - r) - 1/mu */
    out->res_min = r < mu ? 1.0 / (mu - r) - 1.0 / mu : INFINITY;
    out->steps_min = inv.steps;
  }
  cb_solver_free(chol);
  free(work);
  free(z);
  out->ms = cb_now_ms() - t0;
  return st;
}

int cb_spectrum_dense(const cb_sparse *A, const double *d, cb_spectrum *out) {
  double t0 = cb_now_ms();
  memset(out, 0, sizeof *out);
  double *ev = cb_malloc((size_t)A->n, sizeof(double));
  if (!ev) return CB_ENOMEM;
  int st = cb_dense_eigenvalues(A, d, ev);
  if (st == CB_OK) {
    out->lmin = ev[0];
    out->lmax = ev[A->n - 1];
    out->res_min = out->res_max = 0;
    out->steps_min = out->steps_max = 0;
  }
  free(ev);
  out->ms = cb_now_ms() - t0;
  return st;
}
