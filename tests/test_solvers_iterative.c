/* The registered iterative solvers and CHOLMOD against
 * independent dense GSL computations: solutions (GSL Cholesky), spectral
 * radii (GSL symmetric eigenvalues), and the statuses for divergence and
 * CG breakdown on constructed matrices. */
#include <criterion/criterion.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "capture.h"
#include "support.h"
#include "rng.h"

/* cb_sparse (3x3 block pattern) from a dense symmetric n x n matrix, n = 3 nblk. */
static void from_dense(const double *M, int nblk, cb_sparse *A) {
  int n = 3 * nblk;
  cb_pattern p;
  cr_assert_eq(cb_pattern_init(&p, nblk), CB_OK);
  for (int bi = 0; bi < nblk; bi++)
    for (int bj = bi; bj < nblk; bj++) {
      int nz = 0;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) nz |= M[(3 * bi + r) * n + 3 * bj + c] != 0;
      if (nz || bi == bj) cr_assert_eq(cb_pattern_add(&p, bi, bj), CB_OK);
    }
  cr_assert_eq(cb_sparse_from_pattern(&p, A), CB_OK);
  cb_pattern_free(&p);
  for (int j = 0; j < n; j++)
    for (int q = A->colp[j]; q < A->colp[j + 1]; q++) A->val[q] = M[A->rowi[q] * n + j];
}

/* A deterministic diagonally dominant SPD matrix: random symmetric off-diagonal
 * entries in [-1, 1] (about a third of them), a_ii = sum_j |a_ij| + 0.5. */
static void dd_matrix(int nblk, cb_sparse *A) {
  int n = 3 * nblk;
  double *M = calloc((size_t)n * n, sizeof(double));
  cb_rng rng = cb_rng_raw(12345);
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++) {
      double u = cb_rng_uniform(&rng);
      if (u < 0.33) M[i * n + j] = M[j * n + i] = 6 * u - 1; /* in [-1, 0.98] */
    }
  for (int i = 0; i < n; i++) {
    double r = 0.5;
    for (int j = 0; j < n; j++) r += i != j ? fabs(M[i * n + j]) : 0;
    M[i * n + i] = r;
  }
  from_dense(M, nblk, A);
  free(M);
}

static double *rhs(int n) {
  double *b = malloc((size_t)n * sizeof(double));
  for (int i = 0; i < n; i++) b[i] = sin(0.7 * i + 0.3) + 0.2;
  return b;
}

/* x = A^-1 b by GSL's dense Cholesky. */
static void dense_solve(const cb_sparse *A, const double *b, double *x) {
  gsl_matrix *D = test_dense(A);
  gsl_vector_const_view bv = gsl_vector_const_view_array(b, (size_t)A->n);
  gsl_vector_view xv = gsl_vector_view_array(x, (size_t)A->n);
  cr_assert_eq(gsl_linalg_cholesky_decomp1(D), 0, "GSL Cholesky failed: matrix not SPD");
  cr_assert_eq(gsl_linalg_cholesky_solve(D, &bv.vector, &xv.vector), 0);
  gsl_matrix_free(D);
}

/* Extreme eigenvalues of D^-1 A by GSL (dense, on D^-1/2 A D^-1/2). */
static void dense_jacobi_spectrum(const cb_sparse *A, double *lmin, double *lmax) {
  int n = A->n;
  gsl_matrix *D = test_dense(A);
  double *d = malloc((size_t)n * sizeof(double));
  for (int i = 0; i < n; i++) d[i] = 1 / sqrt(gsl_matrix_get(D, (size_t)i, (size_t)i));
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      gsl_matrix_set(D, (size_t)i, (size_t)j, gsl_matrix_get(D, (size_t)i, (size_t)j) * d[i] * d[j]);
  gsl_vector *ev = gsl_vector_alloc((size_t)n);
  gsl_eigen_symm_workspace *w = gsl_eigen_symm_alloc((size_t)n);
  cr_assert_eq(gsl_eigen_symm(D, ev, w), 0);
  *lmin = gsl_vector_min(ev);
  *lmax = gsl_vector_max(ev);
  gsl_eigen_symm_free(w);
  gsl_vector_free(ev);
  gsl_matrix_free(D);
  free(d);
}

static double rel_diff(int n, const double *x, const double *y) {
  double e = 0, m = 0;
  for (int i = 0; i < n; i++) {
    e += (x[i] - y[i]) * (x[i] - y[i]);
    m += y[i] * y[i];
  }
  return sqrt(e / m);
}

/* Runs a solver from x = 0; returns its status, fills x and the iteration count. */
static int solve(const char *name, const cb_solver_params *p, const cb_sparse *A, const double *b, double *x,
                 int *iters, double *rho) {
  cb_solver *s = NULL;
  cr_assert_eq(cb_solver_alloc(name, p, A->n, &s), CB_OK, "%s: %s", name, cb_error_message());
  memset(x, 0, (size_t)A->n * sizeof(double));
  int st = cb_solver_analyze(s, A);
  if (st == CB_OK) st = cb_solver_factor(s, A);
  if (st == CB_OK) st = cb_solver_solve(s, A, b, x);
  if (iters) *iters = s->stats.iters;
  if (rho) *rho = s->stats.rho;
  cb_solver_free(s);
  return st;
}

/* The lab's cloth at 7x7 (141 DOFs), Newton system of step 10: SPD, not
 * diagonally dominant, vanilla Jacobi diverges on it. */
static cb_capture newton_case;
static void newton_setup(void) {
  cb_config c;
  test_config(&c, (const char *const[]){"mesh.n=7", "material.vertex_mass=1", "integrator.max_iters=5", NULL});
  cr_assert_eq(cb_capture_newton_system(&c, 10, 0, &newton_case), CB_OK, "%s", cb_error_message());
}
static void newton_teardown(void) { cb_capture_free(&newton_case); }

Test(solvers_iterative, every_solver_matches_dense_gsl_on_dd_matrix) {
  cb_sparse A;
  dd_matrix(10, &A);
  int n = A.n;
  double *b = rhs(n), *x = malloc((size_t)n * sizeof(double)), *xg = malloc((size_t)n * sizeof(double));
  dense_solve(&A, b, xg);
  /* strictly diagonally dominant: rho(I - D^-1 A) < 1, so vanilla alpha = 1 converges */
  for (int i = 0; cb_solver_types[i]; i++) {
    cb_solver_params p = cb_solver_params_default();
    p.alpha = 1; /* vanilla Jacobi (the default is auto) */
    p.tol = 1e-13;
    p.max_iters = 5000;
    int st = solve(cb_solver_types[i]->name, &p, &A, b, x, NULL, NULL);
    cr_expect_eq(st, CB_OK, "%s: status %s", cb_solver_types[i]->name, cb_status_name(st));
    cr_expect_lt(rel_diff(n, x, xg), 1e-10, "%s: |x - x_gsl|/|x_gsl| = %g", cb_solver_types[i]->name,
                 rel_diff(n, x, xg));
  }
  cb_sparse_free(&A);
  free(b);
  free(x);
  free(xg);
}

Test(solvers_iterative, every_solver_matches_dense_gsl_on_newton_matrix, .init = newton_setup,
     .fini = newton_teardown) {
  const cb_sparse *A = &newton_case.A;
  int n = A->n, bad;
  double ratio, lmin, lmax;
  cb_diag_dominance(A, &bad, &ratio);
  cr_assert_gt(bad, 0, "the captured matrix should not be diagonally dominant");
  dense_jacobi_spectrum(A, &lmin, &lmax);
  cr_assert_gt(lmin, 0);
  double *x = malloc((size_t)n * sizeof(double)), *xg = malloc((size_t)n * sizeof(double));
  dense_solve(A, newton_case.b, xg);
  for (int i = 0; cb_solver_types[i]; i++) {
    cb_solver_params p = cb_solver_params_default();
    p.tol = 1e-12;
    p.max_iters = 20000;
    p.alpha = 1 / lmax; /* rho(I - alpha D^-1 A) = 1 - lmin/lmax < 1: provably convergent */
    int st = solve(cb_solver_types[i]->name, &p, A, newton_case.b, x, NULL, NULL);
    cr_expect_eq(st, CB_OK, "%s: status %s", cb_solver_types[i]->name, cb_status_name(st));
    cr_expect_lt(rel_diff(n, x, xg), 1e-8, "%s: |x - x_gsl|/|x_gsl| = %g", cb_solver_types[i]->name,
                 rel_diff(n, x, xg));
  }
  free(x);
  free(xg);
}

Test(solvers_iterative, chebyshev_with_exact_rho_converges_faster_than_jacobi, .init = newton_setup,
     .fini = newton_teardown) {
  const cb_sparse *A = &newton_case.A;
  double lmin, lmax, *x = malloc((size_t)A->n * sizeof(double));
  dense_jacobi_spectrum(A, &lmin, &lmax);
  cb_solver_params p = cb_solver_params_default();
  p.tol = 1e-8;
  p.max_iters = 20000;
  p.alpha = 2 / (lmin + lmax);
  int ij, ic;
  cr_assert_eq(solve("jacobi", &p, A, newton_case.b, x, &ij, NULL), CB_OK);
  p.rho = fmax(fabs(1 - p.alpha * lmin), fabs(1 - p.alpha * lmax)); /* exact rho(I - alpha D^-1 A) from GSL */
  cr_assert_lt(p.rho, 1);
  cr_assert_eq(solve("chebyshev", &p, A, newton_case.b, x, &ic, NULL), CB_OK);
  cr_expect_lt(2 * ic, ij, "chebyshev %d iterations, jacobi %d", ic, ij);
  /* the theory: Jacobi's residual shrinks by about rho per step; Chebyshev's iteration count
   * is of the order sqrt of it (rate (1 - sqrt(1 - rho^2)) / rho) */
  double jac_pred = log(1e-8) / log(p.rho), cheb_rate = (1 - sqrt(1 - p.rho * p.rho)) / p.rho;
  cr_expect_lt(ij, 1.5 * jac_pred, "jacobi %d iterations, predicted about %g", ij, jac_pred);
  cr_expect_lt(ic, 1.5 * log(1e-8) / log(cheb_rate) + 10, "chebyshev %d iterations", ic);
  free(x);
}

Test(solvers_iterative, automatic_rho_within_2_percent_of_gsl, .init = newton_setup, .fini = newton_teardown) {
  const cb_sparse *A = &newton_case.A;
  double lmin, lmax, rho, *x = malloc((size_t)A->n * sizeof(double));
  dense_jacobi_spectrum(A, &lmin, &lmax);
  const double alphas[] = {2 / (lmin + lmax), 0.5 / lmax, 1.5 / lmax};
  for (int i = 0; i < 3; i++) {
    cb_solver_params p = cb_solver_params_default();
    p.alpha = alphas[i];
    p.max_iters = 20000;
    double exact = fmax(fabs(1 - p.alpha * lmin), fabs(1 - p.alpha * lmax));
    cr_assert_eq(solve("chebyshev", &p, A, newton_case.b, x, NULL, &rho), CB_OK);
    cr_expect_leq(fabs(rho - exact), 0.02 * exact, "alpha %g: auto rho %.6f, GSL %.6f", p.alpha, rho, exact);
  }
  free(x);
}

/* A chain Laplacian plus a tiny shift (condition ~1e5): 200 Lanczos steps do
 * not resolve the bottom of the spectrum, the Ritz residual exceeds the
 * smallest Ritz value, and widening it used to give rho >= 1 and a false
 * "Jacobi diverges". The estimate must stay below 1 and Chebyshev converge. */
Test(solvers_iterative, automatic_rho_with_unresolved_bottom_stays_below_one) {
  int nb = 400, n = 3 * nb;
  cb_pattern pt;
  cb_pattern_init(&pt, nb);
  for (int b = 0; b + 1 < nb; b++) cb_pattern_add(&pt, b, b + 1);
  cb_sparse A;
  cr_assert_eq(cb_sparse_from_pattern(&pt, &A), CB_OK);
  cb_pattern_free(&pt);
  const double D[9] = {2 + 1e-7, 0, 0, 0, 2 + 1e-7, 0, 0, 0, 2 + 1e-7}, O[9] = {-1, 0, 0, 0, -1, 0, 0, 0, -1};
  for (int b = 0; b < nb; b++) {
    int slot, stride;
    cb_sparse_block_slot(&A, b, b, &slot, &stride);
    cb_sparse_add_block(A.val, slot, stride, D, 1);
    if (b + 1 == nb) continue;
    cb_sparse_block_slot(&A, b, b + 1, &slot, &stride);
    cb_sparse_add_block(A.val, slot, stride, O, 1);
    cb_sparse_block_slot(&A, b + 1, b, &slot, &stride);
    cb_sparse_add_block(A.val, slot, stride, O, 1);
  }
  /* lambda(D^-1 A) = (1e-7 + 2 - 2 cos(k pi / (nb + 1))) / (2 + 1e-7), k = 1..nb */
  double lmin = (1e-7 + 2 - 2 * cos(acos(-1.0) / (nb + 1))) / (2 + 1e-7);
  cb_solver_params p = cb_solver_params_default();
  p.alpha = 0.9;
  p.tol = 1e-6;
  p.max_iters = 20000;
  double rho, *b = rhs(n), *x = malloc((size_t)n * sizeof(double));
  int iters, st = solve("chebyshev", &p, &A, b, x, &iters, &rho);
  cr_expect_eq(st, CB_OK, "status %s: %s", cb_status_name(st), cb_error_message());
  cr_expect(rho > 0.999 && rho < 1, "rho %.8f (true %.8f)", rho, 1 - 0.9 * lmin);
  cb_sparse_free(&A);
  free(b);
  free(x);
}

Test(solvers_iterative, jacobi_divergence_is_a_status, .init = newton_setup, .fini = newton_teardown) {
  const cb_sparse *A = &newton_case.A;
  double lmin, lmax, *x = malloc((size_t)A->n * sizeof(double));
  dense_jacobi_spectrum(A, &lmin, &lmax);
  cr_assert_gt(fabs(1 - lmax), 1, "vanilla Jacobi should diverge here: rho(I - D^-1 A) = %g", fabs(1 - lmax));
  cb_solver_params p = cb_solver_params_default();
  p.alpha = 1; /* vanilla Jacobi (the default, auto, converges here) */
  p.max_iters = 100000;
  int iters;
  cr_expect_eq(solve("jacobi", &p, A, newton_case.b, x, &iters, NULL), CB_DIVERGED);
  /* residual growth 1e6 at the predicted rate, not after max_iters */
  cr_expect_lt(iters, 2 * log(1e6) / log(fabs(1 - lmax)) + 20, "stopped after %d iterations", iters);
  p.alpha = 1.1 * 2 / lmax; /* past the limit 2 / lambda_max */
  cr_expect_eq(solve("jacobi", &p, A, newton_case.b, x, NULL, NULL), CB_DIVERGED);
  cr_expect_eq(solve("chebyshev", &p, A, newton_case.b, x, NULL, NULL), CB_DIVERGED); /* auto rho >= 1 */
  p.rho = 0.95;
  cr_expect_eq(solve("chebyshev", &p, A, newton_case.b, x, NULL, NULL), CB_DIVERGED);
  free(x);
}

Test(solvers_iterative, nan_right_hand_side_is_diverged_not_a_crash) {
  cb_sparse A;
  dd_matrix(4, &A);
  double *b = rhs(A.n), *x = malloc((size_t)A.n * sizeof(double));
  b[3] = NAN;
  int nit = 0;
  for (int i = 0; cb_solver_types[i]; i++) { /* every registered iterative solver */
    if (cb_solver_types[i]->flags & CB_SOLVER_DIRECT) continue;
    const char *name = cb_solver_types[i]->name;
    cb_solver_params p = cb_solver_params_default();
    int st = solve(name, &p, &A, b, x, NULL, NULL);
    cr_expect_eq(st, CB_DIVERGED, "%s: status %s", name, cb_status_name(st));
    nit++;
  }
  cr_expect_geq(nit, 4, "jacobi, chebyshev, cg and pcg at least");
  cb_sparse_free(&A);
  free(b);
  free(x);
}

/* [[I, 2I], [2I, I]]: eigenvalues 3 and -1, diagonal blocks SPD. With
 * b = (e1, -e1), b^T A b = -2: the first CG step breaks down. */
Test(solvers_iterative, cg_breakdown_on_indefinite_matrix_is_a_status) {
  double M[36] = {0};
  for (int i = 0; i < 6; i++) M[i * 6 + i] = 1;
  for (int i = 0; i < 3; i++) M[i * 6 + i + 3] = M[(i + 3) * 6 + i] = 2;
  cb_sparse A;
  from_dense(M, 2, &A);
  double b[6] = {1, 0, 0, -1, 0, 0}, x[6];
  int iters;
  cr_expect_eq(solve("cg", NULL, &A, b, x, &iters, NULL), CB_INDEFINITE);
  cr_expect_eq(iters, 0);
  cr_expect_eq(solve("pcg", NULL, &A, b, x, NULL, NULL), CB_INDEFINITE);
  cr_expect_eq(solve("cholmod", NULL, &A, b, x, NULL, NULL), CB_NOT_SPD);
  cb_sparse_free(&A);
}

typedef struct {
  int calls, last_k, n;
  double x[64];
} monitor_log;
static void log_monitor(void *ctx, int k, double rel, const double *x) {
  monitor_log *m = ctx;
  cr_assert_eq(k, m->calls, "monitor called out of order");
  cr_assert(rel >= 0);
  m->calls++;
  m->last_k = k;
  memcpy(m->x, x, (size_t)m->n * sizeof(double));
}

Test(solvers_iterative, monitor_sees_every_iterate) {
  cb_sparse A;
  dd_matrix(5, &A);
  double *b = rhs(A.n), x[64];
  for (int i = 0; cb_solver_types[i]; i++) { /* every registered iterative solver */
    if (cb_solver_types[i]->flags & CB_SOLVER_DIRECT) continue;
    const char *name = cb_solver_types[i]->name;
    monitor_log m = {.n = A.n};
    cb_solver_params p = cb_solver_params_default();
    p.monitor = log_monitor;
    p.monitor_ctx = &m;
    int iters;
    cr_assert_eq(solve(name, &p, &A, b, x, &iters, NULL), CB_OK, "%s: %s", name, cb_error_message());
    cr_expect_eq(m.calls, iters + 1, "%s: %d calls for %d iterations", name, m.calls, iters);
    cr_expect_eq(memcmp(m.x, x, (size_t)A.n * sizeof(double)), 0, "%s: last iterate differs from the result", name);
  }
  cb_sparse_free(&A);
  free(b);
}

/* One sgs iteration from x = 0 against the same two block sweeps done
 * densely by GSL: with A = L + B + L^T (B the 3x3 block diagonal, L the
 * strictly lower block triangle), the forward sweep solves (B + L) x' = b and
 * the backward sweep (B + L^T) x'' = b - L x' (LU solves of the dense block
 * triangles). */
Test(solvers_iterative, sgs_iteration_is_a_forward_then_a_backward_block_sweep, .init = newton_setup,
     .fini = newton_teardown) {
  const cb_sparse *A = &newton_case.A;
  size_t n = (size_t)A->n;
  gsl_matrix *D = test_dense(A), *F = gsl_matrix_calloc(n, n), *G = gsl_matrix_calloc(n, n);
  gsl_matrix *Lo = gsl_matrix_calloc(n, n);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) {
      double a = gsl_matrix_get(D, i, j);
      if (j / 3 <= i / 3) gsl_matrix_set(F, i, j, a); /* B + L */
      if (j / 3 >= i / 3) gsl_matrix_set(G, i, j, a); /* B + L^T */
      if (j / 3 < i / 3) gsl_matrix_set(Lo, i, j, a); /* L */
    }
  gsl_permutation *perm = gsl_permutation_alloc(n);
  gsl_vector *x1 = gsl_vector_alloc(n), *rhs2 = gsl_vector_alloc(n), *x2 = gsl_vector_alloc(n);
  gsl_vector_const_view bv = gsl_vector_const_view_array(newton_case.b, n);
  int sign;
  cr_assert_eq(gsl_linalg_LU_decomp(F, perm, &sign), 0);
  cr_assert_eq(gsl_linalg_LU_solve(F, perm, &bv.vector, x1), 0); /* (B + L) x' = b */
  gsl_vector_memcpy(rhs2, &bv.vector);
  gsl_blas_dgemv(CblasNoTrans, -1.0, Lo, x1, 1.0, rhs2); /* b - L x' */
  cr_assert_eq(gsl_linalg_LU_decomp(G, perm, &sign), 0);
  cr_assert_eq(gsl_linalg_LU_solve(G, perm, rhs2, x2), 0); /* (B + L^T) x'' = b - L x' */
  cb_solver_params p = cb_solver_params_default();
  p.max_iters = 1;
  double *x = malloc(n * sizeof(double));
  int iters, st = solve("sgs", &p, A, newton_case.b, x, &iters, NULL);
  cr_expect(st == CB_NOT_CONVERGED && iters == 1, "status %s after %d iterations", cb_status_name(st), iters);
  cr_expect_lt(rel_diff((int)n, x, x2->data), 1e-12, "|x_sgs - x_gsl| / |x_gsl| = %g", rel_diff((int)n, x, x2->data));
  gsl_matrix_free(D);
  gsl_matrix_free(F);
  gsl_matrix_free(G);
  gsl_matrix_free(Lo);
  gsl_permutation_free(perm);
  gsl_vector_free(x1);
  gsl_vector_free(rhs2);
  gsl_vector_free(x2);
  free(x);
}

/* Nesterov's constant-momentum Jacobi with alpha = 1/lambda_max and
 * beta = (sqrt kappa - 1)/(sqrt kappa + 1), kappa = cond(D^-1 A) from GSL:
 * its error falls like (1 - 1/sqrt kappa)^k, so it needs about
 * sqrt(kappa) ln(1/tol) iterations, far fewer than Jacobi's kappa ln(1/tol)
 * at its best weight, and at least as many as Chebyshev's
 * (sqrt(kappa)/2) ln(1/tol). */
Test(solvers_iterative, nesterov_iterations_follow_the_square_root_of_the_condition_number, .init = newton_setup,
     .fini = newton_teardown) {
  const cb_sparse *A = &newton_case.A;
  double lmin, lmax, *x = malloc((size_t)A->n * sizeof(double));
  dense_jacobi_spectrum(A, &lmin, &lmax);
  double kappa = lmax / lmin, tol = 1e-8;
  cb_solver_params p = cb_solver_params_default();
  p.tol = tol;
  p.max_iters = 20000;
  int in, ij, ic;
  cr_assert_eq(solve("nesterov", &p, A, newton_case.b, x, &in, NULL), CB_OK, "%s", cb_error_message());
  p.alpha = 2 / (lmin + lmax);
  cr_assert_eq(solve("jacobi", &p, A, newton_case.b, x, &ij, NULL), CB_OK);
  cr_assert_eq(solve("chebyshev", &p, A, newton_case.b, x, &ic, NULL), CB_OK);
  double pred = log(1 / tol) / -log(1 - 1 / sqrt(kappa)); /* (1 - 1/sqrt kappa)^k = tol */
  cr_log_info("kappa %.4g: nesterov %d iterations (predicted %.0f), jacobi %d, chebyshev %d\n", kappa, in, pred, ij,
              ic);
  cr_expect_lt(in, 1.5 * pred + 10, "nesterov %d iterations, predicted about %.0f", in, pred);
  cr_expect_lt(2 * in, ij, "nesterov %d iterations, jacobi %d", in, ij);
  cr_expect_geq(in, ic, "nesterov %d iterations, chebyshev %d", in, ic);
  free(x);
}

/* A matrix that is not positive definite stops nesterov in factor(): its
 * Lanczos estimate finds a Ritz value <= 0 of D^-1 A ([[I, 2I], [2I, I]]:
 * eigenvalues 3 and -1, positive diagonal). sgs's diagonal blocks (I) are SPD,
 * so it starts, and its residual grows: diverged, never a crash. */
Test(solvers_iterative, nesterov_and_sgs_on_an_indefinite_matrix_give_a_status) {
  double M[36] = {0};
  for (int i = 0; i < 6; i++) M[i * 6 + i] = 1;
  for (int i = 0; i < 3; i++) M[i * 6 + i + 3] = M[(i + 3) * 6 + i] = 2;
  cb_sparse A;
  from_dense(M, 2, &A);
  double b[6] = {1, 0, 0, -1, 0, 0}, x[6];
  cr_expect_eq(solve("nesterov", NULL, &A, b, x, NULL, NULL), CB_NOT_SPD);
  cb_solver_params p = cb_solver_params_default();
  p.max_iters = 1000;
  cr_expect_eq(solve("sgs", &p, &A, b, x, NULL, NULL), CB_DIVERGED);
  cb_sparse_free(&A);
}

/* The amortised estimate (alpha = auto, rho = auto): a second factorisation
 * of the same matrix reuses the bounds (no Lanczos run) and still solves to
 * the tolerance; a matrix assembled at a stretched state (wider spectrum)
 * is still solved to the tolerance, whether the moved bounds fit or the
 * solve has to re-estimate. Residuals are checked with the full-storage
 * product, not the solver's own. */
Test(iterative, amortised_rho_estimate_reuses_and_stays_safe) {
  const char *sets[] = {"mesh.n=10", NULL};
  cb_scene *sc = test_scene(sets);
  cb_sparse *A = &sc->sys.A;
  int n = A->n, nv3 = 3 * sc->mesh.nv;
  cb_system_assemble(&sc->sys, sc->x0, 900.0, CB_DEF_DROP, 0.0);
  cb_solver_params p = cb_solver_params_default();
  p.alpha = CB_AUTO;
  p.rho = CB_AUTO;
  p.tol = 1e-10;
  p.max_iters = 20000;
  cb_solver *s = NULL;
  cr_assert_eq(cb_solver_alloc("chebyshev", &p, n, &s), CB_OK);
  cr_assert_eq(cb_solver_analyze(s, A), CB_OK);
  double *b = malloc((size_t)n * sizeof(double)), *x = calloc((size_t)n, sizeof(double)),
         *w = malloc((size_t)n * sizeof(double));
  double *xs = malloc((size_t)nv3 * sizeof(double));
  cr_assert(b && x && w && xs);
  for (int i = 0; i < n; i++) b[i] = sin(0.37 * i) + 0.5;
  for (int round = 0; round < 3; round++) {
    if (round == 2) { /* stretch the cloth by 40% about its first vertex: stiffer, wider spectrum */
      for (int i = 0; i < nv3; i++) xs[i] = sc->x0[i % 3] + 1.4 * (sc->x0[i] - sc->x0[i % 3]);
      cb_system_assemble(&sc->sys, xs, 900.0, CB_DEF_DROP, 0.0);
    }
    cr_assert_eq(cb_solver_factor(s, A), CB_OK, "round %d: %s", round, cb_error_message());
    if (round == 0) cr_expect_eq(s->stats.rho_estimates, 1, "the first factorisation estimates");
    if (round == 1) cr_expect_eq(s->stats.rho_estimates, 0, "the same matrix reuses the bounds");
    cr_expect(s->stats.alpha > 0 && s->stats.alpha < 1, "alpha* = %g", s->stats.alpha);
    memset(x, 0, (size_t)n * sizeof(double));
    int st = cb_solver_solve(s, A, b, x);
    cr_expect_eq(st, CB_OK, "round %d: status %s (%s)", round, cb_status_name(st), cb_error_message());
    double res = cb_relative_residual(A, b, x, w);
    cr_expect(res <= 1.01e-10, "round %d: residual %.3g", round, res);
  }
  free(b);
  free(x);
  free(w);
  free(xs);
  cb_solver_free(s);
  cb_scene_free(sc);
}
