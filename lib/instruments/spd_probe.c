#include "spd_probe.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/eigen.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

struct cb_spd_probe {
  cb_spd_probe_params p;
  cb_solver *chol, *cg;
  double *eval, *work, *dx; /* n each */
};

cb_spd_probe_params cb_spd_probe_params_default(void) {
  cb_spd_probe_params p;
  p.dense_max = 300;
  p.lanczos = cb_lanczos_params_default();
  p.lanczos.max_steps = 60;
  p.lanczos.tol = 1e-4;
  p.cg = cb_solver_params_default();
  p.cg.tol = 1e-8;
  p.cg.max_iters = 1000;
  return p;
}

void cb_spd_probe_free(cb_spd_probe *pr) {
  if (!pr) return;
  cb_solver_free(pr->chol);
  cb_solver_free(pr->cg);
  free(pr->eval);
  free(pr->work);
  free(pr->dx);
  free(pr);
}

int cb_spd_probe_alloc(const cb_sparse *A, const cb_spd_probe_params *p, cb_spd_probe **out) {
  *out = NULL;
  cb_spd_probe *pr = cb_calloc(1, sizeof *pr);
  if (!pr) return CB_ENOMEM;
  pr->p = p ? *p : cb_spd_probe_params_default();
  size_t n = (size_t)(A->n > 0 ? A->n : 1);
  pr->eval = cb_malloc(n, sizeof(double));
  pr->work = cb_malloc(n, sizeof(double));
  pr->dx = cb_malloc(n, sizeof(double));
  int st = (!pr->eval || !pr->work || !pr->dx) ? CB_ENOMEM : CB_OK;
  if (st == CB_OK) st = cb_solver_alloc("cholmod", NULL, A->n, &pr->chol);
  if (st == CB_OK) st = cb_solver_analyze(pr->chol, A);
  if (st == CB_OK) st = cb_solver_alloc("cg", &pr->p.cg, A->n, &pr->cg);
  if (st == CB_OK) st = cb_solver_analyze(pr->cg, A);
  if (st) {
    cb_spd_probe_free(pr);
    return st;
  }
  *out = pr;
  return CB_OK;
}

int cb_spd_probe_run(cb_spd_probe *pr, const cb_sparse *A, const double *b, unsigned what, cb_spd_probe_result *r) {
  double t0 = cb_now_ms();
  r->cholmod_status = -1;
  r->min_eig = r->min_eig_res = NAN;
  r->eig_dense = 0;
  r->eig_status = -1;
  r->cg_status = -1;
  r->cg_iters = 0;
  r->cg_rel_residual = NAN;
  int st = CB_OK;
  if (what & CB_PROBE_CHOLMOD) {
    int s = cb_solver_factor(pr->chol, A);
    if (s != CB_OK && s != CB_NOT_SPD) st = s;
    r->cholmod_status = s;
  }
  if ((what & CB_PROBE_EIG) && st == CB_OK) {
    if (A->n <= pr->p.dense_max) {
      st = cb_dense_eigenvalues(A, NULL, pr->eval);
      r->min_eig = pr->eval[0]; /* ascending */
      r->min_eig_res = 0;
      r->eig_dense = 1;
      r->eig_status = st;
    } else {
      cb_scaled_op op = {A, NULL, pr->work};
      cb_eig_result e;
      st = cb_lanczos(A->n, cb_scaled_op_apply, &op, &pr->p.lanczos, &e);
      r->min_eig = e.lmin; /* smallest Ritz value >= lambda_min(A) */
      r->min_eig_res = e.res_min;
      r->eig_status = st ? st : e.status;
    }
  }
  if ((what & CB_PROBE_CG) && st == CB_OK) {
    int s = cb_solver_factor(pr->cg, A);
    if (s == CB_OK) {
      memset(pr->dx, 0, (size_t)A->n * sizeof(double)); /* from dx = 0, as Newton does */
      s = cb_solver_solve(pr->cg, A, b, pr->dx);
    }
    r->cg_status = s;
    r->cg_iters = pr->cg->stats.iters;
    r->cg_rel_residual = s == CB_OK || s == CB_NOT_CONVERGED ? pr->cg->stats.rel_residual : NAN;
    if (s < 0) st = s;
  }
  cb_error_clear(); /* the breakdowns above are results, not errors */
  r->ms = cb_now_ms() - t0;
  return st;
}

int cb_dense_restricted_spd(const cb_sparse *A, const int *keep, double *min_eig, int *chol_ok) {
  int *map = cb_malloc((size_t)(A->n > 0 ? A->n : 1), sizeof(int));
  if (!map) return CB_ENOMEM;
  int m = 0;
  for (int i = 0; i < A->n; i++) map[i] = (!keep || keep[i]) ? m++ : -1;
  if (m == 0) {
    free(map);
    return cb_fail("restricted matrix is empty");
  }
  gsl_matrix *D = gsl_matrix_calloc((size_t)m, (size_t)m), *C = gsl_matrix_alloc((size_t)m, (size_t)m);
  gsl_vector *ev = gsl_vector_alloc((size_t)m);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc((size_t)m);
  int st = (!D || !C || !ev || !ws) ? cb_fail_status(CB_ENOMEM, "restricted eigenvalues: out of memory") : CB_OK;
  if (st == CB_OK) {
    cb_sparse_to_dense(A, NULL, map, D->data, D->tda);
    gsl_matrix_memcpy(C, D);
    gsl_error_handler_t *old = gsl_set_error_handler_off();
    *chol_ok = gsl_linalg_cholesky_decomp1(C) == GSL_SUCCESS; /* GSL_EDOM: not positive definite */
    double scale = cb_eigen_prescale(D->data, (size_t)m, D->tda);
    if (gsl_eigen_symm(D, ev, ws)) st = cb_fail("gsl_eigen_symm failed");
    gsl_set_error_handler(old);
    if (st == CB_OK) *min_eig = scale * gsl_vector_min(ev);
  }
  free(map);
  gsl_matrix_free(D);
  gsl_matrix_free(C);
  gsl_vector_free(ev);
  if (ws) gsl_eigen_symm_free(ws);
  return st;
}
