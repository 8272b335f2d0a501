/* Is a Newton matrix A positive definite? Three independent witnesses on the
 * same A (and b), for measurements only (never inside a solver):
 *
 *   CHOLMOD  LL' factorisation: a non-positive pivot is CB_NOT_SPD;
 *   eig      smallest eigenvalue of A: all eigenvalues by GSL's dense
 *            symmetric solver when n <= dense_max, else Lanczos (eigen.h),
 *            whose smallest Ritz value is >= the true one, so min_eig < 0
 *            proves A indefinite, and its residual bound is reported;
 *   CG       plain CG on A dx = b from dx = 0: a breakdown p^T A p <= 0
 *            (CB_INDEFINITE) is what an indefinite A does to CG.
 *
 * The probe owns its own CHOLMOD and CG instances (analysed once, for A's
 * fixed pattern), so probing never disturbs the integrator's solver. */
#ifndef CB_SPD_PROBE_H
#define CB_SPD_PROBE_H

#include <clothbench/eigen.h>
#include <clothbench/solver.h>
#include <clothbench/sparse.h>

typedef struct cb_spd_probe_params {
  int dense_max;             /* n <= dense_max: dense GSL eigenvalues; else Lanczos. Default 300 */
  cb_lanczos_params lanczos; /* Default max_steps 60, tol 1e-4, seed 1 */
  cb_solver_params cg;       /* CG run on (A, b). Default tol 1e-8, max_iters 1000 */
} cb_spd_probe_params;

cb_spd_probe_params cb_spd_probe_params_default(void);

enum { CB_PROBE_CHOLMOD = 1, CB_PROBE_EIG = 2, CB_PROBE_CG = 4 };

typedef struct cb_spd_probe_result {
  int cholmod_status; /* CB_OK or CB_NOT_SPD (CB_PROBE_CHOLMOD) */
  double min_eig;     /* smallest eigenvalue, units of A (CB_PROBE_EIG) */
  double min_eig_res; /* its residual bound: 0 when dense, |beta_k s_k| for Lanczos */
  int eig_dense;      /* 1 if min_eig came from the dense solver */
  int eig_status;     /* CB_OK, or CB_NOT_CONVERGED if Lanczos ran out of steps */
  int cg_status;      /* CB_OK, CB_NOT_CONVERGED, CB_INDEFINITE (breakdown), CB_DIVERGED (CB_PROBE_CG) */
  int cg_iters;
  double cg_rel_residual;
  double ms; /* wall time of the probe */
} cb_spd_probe_result;

typedef struct cb_spd_probe cb_spd_probe;

/* Analyses A's pattern once (A's values are not used). */
int cb_spd_probe_alloc(const cb_sparse *A, const cb_spd_probe_params *p, cb_spd_probe **out);
void cb_spd_probe_free(cb_spd_probe *pr);

/* Runs the witnesses selected by `what` (CB_PROBE_* bits) on A; b is needed
 * for CB_PROBE_CG only. Fields of witnesses not run are NaN / -1. */
int cb_spd_probe_run(cb_spd_probe *pr, const cb_sparse *A, const double *b, unsigned what, cb_spd_probe_result *r);

/* A restricted to the degrees of freedom i with keep[i] != 0 (keep = NULL:
 * all), densely: its smallest eigenvalue (GSL) and whether dense Cholesky
 * succeeds. For small systems such as a spring pair seen in 1D, 2D or 3D. */
int cb_dense_restricted_spd(const cb_sparse *A, const int *keep, double *min_eig, int *chol_ok);

#endif
