/* Linear solvers: every registered solver against a dense GSL Cholesky solve
 * on small SPD systems (random, and real Newton matrices), CHOLMOD's residual
 * on the lab scene, and matrices that are not positive definite (small ones,
 * factorised simplicially, and large ones, factorised supernodally). */
#include <cholmod.h>
#include <criterion/criterion.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"
#include "rng.h"

/* ---- helpers ---------------------------------------------------------------- */

static void setup(void) { gsl_set_error_handler_off(); }

/* Block pattern over nblk blocks from a list of block pairs. */
static void pattern_matrix(int nblk, const int *pairs, int npairs, cb_sparse *A) {
  cb_pattern p;
  cr_assert_eq(cb_pattern_init(&p, nblk), CB_OK);
  for (int k = 0; k < npairs; k++) cr_assert_eq(cb_pattern_add(&p, pairs[2 * k], pairs[2 * k + 1]), CB_OK);
  cr_assert_eq(cb_sparse_from_pattern(&p, A), CB_OK);
  cb_pattern_free(&p);
}

/* Copies the dense S into the stored entries of A; S must vanish elsewhere. */
static void fill_from_dense(cb_sparse *A, const gsl_matrix *S) {
  double outside = 0;
  for (int j = 0; j < A->n; j++)
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++) A->val[p] = gsl_matrix_get(S, (size_t)A->rowi[p], (size_t)j);
  gsl_matrix *D = test_dense(A);
  for (size_t i = 0; i < S->size1; i++)
    for (size_t j = 0; j < S->size2; j++) {
      outside = fmax(outside, fabs(gsl_matrix_get(S, i, j) - gsl_matrix_get(D, i, j)));
    }
  cr_assert(outside == 0, "dense matrix has entries outside the pattern");
  gsl_matrix_free(D);
}

/* S = B^T B + n I with B uniform in [-1, 1]: SPD, every entry nonzero. */
static gsl_matrix *random_spd_full(size_t n, uint64_t seed0) {
  cb_rng seed = cb_rng_raw(seed0);
  gsl_matrix *B = gsl_matrix_alloc(n, n), *S = gsl_matrix_calloc(n, n);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) gsl_matrix_set(B, i, j, 2 * cb_rng_uniform(&seed) - 1);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) {
      double s = i == j ? (double)n : 0.0;
      for (size_t k = 0; k < n; k++) s += gsl_matrix_get(B, k, i) * gsl_matrix_get(B, k, j); /* (B^T B)_ij */
      gsl_matrix_set(S, i, j, s);
    }
  gsl_matrix_free(B);
  return S;
}

/* Random symmetric values on the sparse block pattern of A, made SPD by
 * strict diagonal dominance: S_ii = sum_j |S_ij| + 1 + u. */
static gsl_matrix *random_spd_on_pattern(const cb_sparse *A, uint64_t seed0) {
  cb_rng seed = cb_rng_raw(seed0);
  size_t n = (size_t)A->n;
  gsl_matrix *S = gsl_matrix_calloc(n, n);
  for (int j = 0; j < A->n; j++)
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++) {
      int i = A->rowi[p];
      if (i <= j) continue;
      double v = 2 * cb_rng_uniform(&seed) - 1;
      gsl_matrix_set(S, (size_t)i, (size_t)j, v);
      gsl_matrix_set(S, (size_t)j, (size_t)i, v);
    }
  for (size_t i = 0; i < n; i++) {
    double r = 0;
    for (size_t j = 0; j < n; j++) r += fabs(gsl_matrix_get(S, i, j));
    gsl_matrix_set(S, i, i, r + 1 + cb_rng_uniform(&seed));
  }
  return S;
}

/* Dense reference: x = S^-1 b by GSL Cholesky; also cond_2(S). */
static void dense_solve(const gsl_matrix *S, const double *b, double *x, double *cond) {
  size_t n = S->size1;
  gsl_matrix *L = gsl_matrix_alloc(n, n);
  gsl_matrix_memcpy(L, S);
  cr_assert_eq(gsl_linalg_cholesky_decomp1(L), GSL_SUCCESS, "reference matrix is not SPD");
  gsl_vector_const_view bv = gsl_vector_const_view_array(b, n);
  gsl_vector_view xv = gsl_vector_view_array(x, n);
  cr_assert_eq(gsl_linalg_cholesky_solve(L, &bv.vector, &xv.vector), GSL_SUCCESS);
  gsl_matrix_memcpy(L, S);
  gsl_vector *ev = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc(n);
  cr_assert_eq(gsl_eigen_symm(L, ev, ws), GSL_SUCCESS);
  *cond = gsl_vector_max(ev) / gsl_vector_min(ev);
  gsl_eigen_symm_free(ws);
  gsl_vector_free(ev);
  gsl_matrix_free(L);
}

/* |b - A x| / |b| by our own loop over the CSC arrays (both triangles stored). */
static double residual(const cb_sparse *A, const double *b, const double *x) {
  double *r = malloc((size_t)A->n * sizeof(double));
  cr_assert(r);
  for (int i = 0; i < A->n; i++) r[i] = b[i];
  for (int j = 0; j < A->n; j++)
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++) r[A->rowi[p]] -= A->val[p] * x[j]; /* r -= A(:,j) x_j */
  double rn = 0, bn = 0;
  for (int i = 0; i < A->n; i++) {
    rn += r[i] * r[i];
    bn += b[i] * b[i];
  }
  free(r);
  return sqrt(rn / bn);
}

static double rel_err(const double *x, const double *y, int n) {
  double d = 0, m = 0;
  for (int i = 0; i < n; i++) {
    d += (x[i] - y[i]) * (x[i] - y[i]);
    m += y[i] * y[i];
  }
  return sqrt(d / m);
}

static cb_solver_params tight_params(void) {
  cb_solver_params p = cb_solver_params_default();
  p.tol = 1e-12;
  p.max_iters = 1000000;
  p.history_cap = 64;
  return p;
}

/* Extreme eigenvalues of D^-1 A (D = diag A), from the similar matrix
 * D^-1/2 A D^-1/2 by GSL. */
static void jacobi_spectrum(const gsl_matrix *S, double *lmin, double *lmax) {
  size_t n = S->size1;
  gsl_matrix *W = gsl_matrix_alloc(n, n);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++)
      gsl_matrix_set(W, i, j, gsl_matrix_get(S, i, j) / sqrt(gsl_matrix_get(S, i, i) * gsl_matrix_get(S, j, j)));
  gsl_vector *ev = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc(n);
  cr_assert_eq(gsl_eigen_symm(W, ev, ws), GSL_SUCCESS);
  *lmin = gsl_vector_min(ev);
  *lmax = gsl_vector_max(ev);
  gsl_eigen_symm_free(ws);
  gsl_vector_free(ev);
  gsl_matrix_free(W);
}

/* tight_params with a Jacobi weight that converges on S: vanilla alpha = 1
 * when rho(I - D^-1 A) < 1 comfortably (lambda_max(D^-1 A) < 1.9), otherwise
 * the optimal Richardson weight 2 / (lambda_min + lambda_max) (lecture: "the
 * use of alpha allows the method to converge even when A is positive definite
 * only"). Solvers that do not use alpha ignore it. */
static cb_solver_params params_for(const gsl_matrix *S) {
  cb_solver_params p = tight_params();
  double lmin, lmax;
  jacobi_spectrum(S, &lmin, &lmax);
  p.alpha = lmax < 1.9 ? 1.0 : 2.0 / (lmin + lmax);
  return p;
}

/* Solves A x = b with solver type `name` (analyze, factor, solve, with a zero
 * initial guess) and checks it against the dense Cholesky solution:
 *   relative residual <= max(10 tol, 1e-13),
 *   relative error    <= cond(A) * max(10 tol, 1e-13). */
static void check_solver_on(const char *name, const cb_sparse *A, const gsl_matrix *S, const double *b,
                            const char *what, double *worst_err) {
  int n = A->n;
  double *x = calloc((size_t)n, sizeof(double)), *xr = malloc((size_t)n * sizeof(double)), cond;
  cr_assert(x && xr);
  dense_solve(S, b, xr, &cond);
  cb_solver_params p = params_for(S);
  cb_solver *s = NULL;
  cr_assert_eq(cb_solver_alloc(name, &p, n, &s), CB_OK, "%s: %s", name, cb_error_message());
  cr_assert_eq(cb_solver_analyze(s, A), CB_OK, "%s/%s analyze: %s", name, what, cb_error_message());
  int st = cb_solver_factor(s, A);
  cr_assert_eq(st, CB_OK, "%s/%s factor: status %s (%s)", name, what, cb_status_name(st), cb_error_message());
  st = cb_solver_solve(s, A, b, x);
  cr_assert_eq(st, CB_OK, "%s/%s solve: status %s (%s)", name, what, cb_status_name(st), cb_error_message());
  double tolx = fmax(10 * p.tol, 1e-13);
  double res = residual(A, b, x), err = rel_err(x, xr, n);
  cr_expect(res <= tolx, "%s/%s: relative residual %.3g > %.3g", name, what, res, tolx);
  cr_expect(err <= cond * tolx, "%s/%s: relative error %.3g > cond %.3g x %.3g", name, what, err, cond, tolx);
  /* the stats agree with our own residual and are filled in */
  cr_expect(s->stats.iters >= 1, "%s/%s: iters = %d", name, what, s->stats.iters);
  cr_expect(fabs(s->stats.rel_residual - res) <= 1e-3 * res + 1e-15, "%s/%s: stats.rel_residual %.3g vs %.3g", name,
            what, s->stats.rel_residual, res);
  cr_expect(s->stats.status == CB_OK);
  cr_expect(s->stats.history_len >= 1 && s->stats.history_len <= p.history_cap, "%s/%s: history_len %d", name, what,
            s->stats.history_len);
  if (s->stats.history_len >= 1 && s->stats.history_len < p.history_cap) /* not truncated: ends at the final residual */
    cr_expect(fabs(s->stats.history[s->stats.history_len - 1] - s->stats.rel_residual) <=
                  1e-12 + 1e-6 * s->stats.rel_residual,
              "%s/%s: last history entry %.3g is not the final residual %.3g", name, what,
              s->stats.history[s->stats.history_len - 1], s->stats.rel_residual);
  if (worst_err) *worst_err = fmax(*worst_err, err / cond);
  cb_solver_free(s);
  free(x);
  free(xr);
}

static double *random_vec(int n, uint64_t seed0) {
  cb_rng seed = cb_rng_raw(seed0);
  double *b = malloc((size_t)n * sizeof(double));
  cr_assert(b);
  for (int i = 0; i < n; i++) b[i] = 2 * cb_rng_uniform(&seed) - 1;
  return b;
}

/* ---- registry --------------------------------------------------------------- */

Test(solver, registry_is_consistent) {
  int n = 0;
  for (; cb_solver_types[n]; n++) {
    cr_expect_str_eq(cb_solver_name(n), cb_solver_types[n]->name);
    cr_expect_eq(cb_solver_type_find(cb_solver_types[n]->name), cb_solver_types[n]);
  }
  cr_expect(n >= 1);
  cr_expect_null(cb_solver_name(n));
  cr_expect_null(cb_solver_type_find("no-such-solver"));
  cb_solver *s = (cb_solver *)1;
  cr_expect_lt(cb_solver_alloc("no-such-solver", NULL, 3, &s), 0);
  cr_expect_null(s);
  cb_solver_free(NULL);
}

/* ---- every solver against dense Cholesky ------------------------------------- */

Test(solver, dense_block_pattern_random_spd, .init = setup) {
  const int nblk = 5;
  int pairs[2 * 10], np = 0;
  for (int i = 0; i < nblk; i++)
    for (int j = i + 1; j < nblk; j++) {
      pairs[2 * np] = i;
      pairs[2 * np + 1] = j;
      np++;
    }
  cb_sparse A;
  pattern_matrix(nblk, pairs, np, &A);
  cr_assert_eq(A.nnz, A.n * A.n);
  double worst = 0;
  for (int trial = 0; trial < 3; trial++) {
    gsl_matrix *S = random_spd_full((size_t)A.n, 11 + (uint64_t)trial);
    fill_from_dense(&A, S);
    double *b = random_vec(A.n, 100 + (uint64_t)trial);
    for (int k = 0; cb_solver_types[k]; k++) check_solver_on(cb_solver_types[k]->name, &A, S, b, "B^T B + nI", &worst);
    free(b);
    gsl_matrix_free(S);
  }
  cr_log_info("dense random SPD: worst relative error / cond = %.3g\n", worst);
  cb_sparse_free(&A);
}

Test(solver, sparse_block_pattern_random_spd, .init = setup) {
  /* 40 blocks in a ring plus random chords */
  const int nblk = 40;
  int pairs[2 * 80], np = 0;
  cb_rng seed = cb_rng_raw(5);
  for (int i = 0; i < nblk; i++) {
    pairs[2 * np] = i;
    pairs[2 * np + 1] = (i + 1) % nblk;
    np++;
  }
  for (int k = 0; k < 30; k++) {
    int i = (int)(cb_rng_uniform(&seed) * nblk), j = (int)(cb_rng_uniform(&seed) * nblk);
    if (i == j) continue;
    pairs[2 * np] = i;
    pairs[2 * np + 1] = j;
    np++;
  }
  cb_sparse A;
  pattern_matrix(nblk, pairs, np, &A);
  cr_assert_lt(A.nnz, A.n * A.n / 2, "pattern should be sparse");
  for (int trial = 0; trial < 3; trial++) {
    gsl_matrix *S = random_spd_on_pattern(&A, 21 + (uint64_t)trial);
    fill_from_dense(&A, S);
    double *b = random_vec(A.n, 200 + (uint64_t)trial);
    for (int k = 0; cb_solver_types[k]; k++) check_solver_on(cb_solver_types[k]->name, &A, S, b, "ring+chords", NULL);
    free(b);
    gsl_matrix_free(S);
  }
  cb_sparse_free(&A);
}

/* Newton matrices M/dt^2 + H(x) of small scenes at jittered states. */
Test(solver, newton_matrices_from_scenes, .init = setup) {
  const char *const variants[][6] = {
      {"mesh.n=5", "mesh.m=4", "scene.pins=top-corners", "integrator.definiteness=drop", NULL, NULL},
      {"mesh.n=4", "mesh.m=6", "scene.pins=none", "material.bend=spring", "scene.initial_scale=1.2", NULL},
      {"mesh.n=6", "mesh.diagonal=alternating", "scene.pins=top-edge", "scene.initial_scale=0.9", NULL, NULL},
  };
  double worst = 0;
  for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
    cb_scene *sc = test_scene(variants[v]);
    int n3 = 3 * sc->mesh.nv;
    double *x = malloc((size_t)n3 * sizeof(double));
    cr_assert(x);
    cb_rng seed = cb_rng_raw(300 + v);
    for (int i = 0; i < n3; i++) x[i] = sc->x0[i] + 0.2 * (2 * cb_rng_uniform(&seed) - 1);
    const double dt = 1.0 / 30;
    /* drop keeps A SPD whatever the state */
    cb_system_assemble(&sc->sys, x, 1.0 / (dt * dt), CB_DEF_DROP, 0.0);
    gsl_matrix *S = test_dense(&sc->sys.A);
    double *b = random_vec(sc->sys.A.n, 400 + v);
    for (int k = 0; cb_solver_types[k]; k++)
      check_solver_on(cb_solver_types[k]->name, &sc->sys.A, S, b, variants[v][0], &worst);
    free(b);
    gsl_matrix_free(S);
    free(x);
    cb_scene_free(sc);
  }
  cr_log_info("Newton matrices: worst relative error / cond = %.3g\n", worst);
}

/* One analyze, then several factor/solve rounds with new values on the same
 * pattern (what the Newton loop does), and two right-hand sides per factor. */
Test(solver, refactor_on_a_fixed_pattern, .init = setup) {
  const char *sets[] = {"mesh.n=6", "mesh.m=5", "material.bend=spring", "scene.pins=0 5", NULL};
  cb_scene *sc = test_scene(sets);
  int n3 = 3 * sc->mesh.nv, n = sc->sys.A.n;
  double *x = malloc((size_t)n3 * sizeof(double)), *sol = malloc((size_t)n * sizeof(double));
  double *ref = malloc((size_t)n * sizeof(double));
  cr_assert(x && sol && ref);
  for (int k = 0; cb_solver_types[k]; k++) {
    const char *name = cb_solver_types[k]->name;
    /* one weight for all rounds: the smallest that the rounds need */
    cb_solver_params p = tight_params();
    cb_rng seed = cb_rng_raw(77);
    for (int round = 0; round < 4; round++) {
      for (int i = 0; i < n3; i++) x[i] = sc->x0[i] * (1 + 0.1 * round) + 0.3 * (2 * cb_rng_uniform(&seed) - 1);
      cb_system_assemble(&sc->sys, x, 900.0 / (1 + round), CB_DEF_DROP, 0.0);
      gsl_matrix *S = test_dense(&sc->sys.A);
      p.alpha = fmin(p.alpha, params_for(S).alpha);
      gsl_matrix_free(S);
    }
    cb_solver *s = NULL;
    cr_assert_eq(cb_solver_alloc(name, &p, n, &s), CB_OK);
    cr_assert_eq(cb_solver_analyze(s, &sc->sys.A), CB_OK);
    seed = cb_rng_raw(77);
    for (int round = 0; round < 4; round++) {
      for (int i = 0; i < n3; i++) x[i] = sc->x0[i] * (1 + 0.1 * round) + 0.3 * (2 * cb_rng_uniform(&seed) - 1);
      cb_system_assemble(&sc->sys, x, 900.0 / (1 + round), CB_DEF_DROP, 0.0);
      gsl_matrix *S = test_dense(&sc->sys.A);
      int fs = cb_solver_factor(s, &sc->sys.A);
      cr_assert_eq(fs, CB_OK, "%s round %d: %s (%s)", name, round, cb_status_name(fs), cb_error_message());
      for (int rhs = 0; rhs < 2; rhs++) {
        double *b = random_vec(n, 1000 + 10 * (uint64_t)round + (uint64_t)rhs), cond;
        dense_solve(S, b, ref, &cond);
        memset(sol, 0, (size_t)n * sizeof(double));
        int st = cb_solver_solve(s, &sc->sys.A, b, sol);
        cr_assert_eq(st, CB_OK, "%s round %d rhs %d: %s (%s)", name, round, rhs, cb_status_name(st),
                     cb_error_message());
        double err = rel_err(sol, ref, n);
        cr_expect(err <= cond * fmax(10 * p.tol, 1e-13), "%s round %d rhs %d: error %.3g (cond %.3g)", name, round, rhs,
                  err, cond);
        free(b);
      }
      gsl_matrix_free(S);
    }
    cb_solver_free(s);
  }
  free(x);
  free(sol);
  free(ref);
  cb_scene_free(sc);
}

/* ---- CHOLMOD on the lab scene --------------------------------------------------- */

Test(solver, cholmod_residual_on_the_hanging_scene, .init = setup) {
  /* configs/hanging.ini: 21x21, 10 m, 1 kg per vertex, k = 8000, top corners, dt = 1/30 */
  const char *sets[] = {"mesh.n=21",
                        "mesh.size=10",
                        "mesh.plane=xz",
                        "material.vertex_mass=1",
                        "material.stretch_k=8000",
                        "scene.pins=top-corners",
                        "integrator.dt=1/30",
                        NULL};
  cb_scene *sc = test_scene(sets);
  int n3 = 3 * sc->mesh.nv, n = sc->sys.A.n;
  cr_assert_eq(n, 3 * (21 * 21 - 2));
  double *x = malloc((size_t)n3 * sizeof(double)), *sol = calloc((size_t)n, sizeof(double));
  cr_assert(x && sol);
  cb_rng seed = cb_rng_raw(9); /* edges are 0.5 m */
  const double dt = 1.0 / 30;
  cb_solver *s = NULL;
  cb_solver_params p = tight_params();
  cr_assert_eq(cb_solver_alloc("cholmod", &p, n, &s), CB_OK);
  cr_assert_eq(cb_solver_analyze(s, &sc->sys.A), CB_OK);
  double worst = 0;
  for (int d = 0; d < CB_DEF_COUNT; d++) {
    /* drop: any state (A is SPD by construction); none: a stretched state
     * (compressed springs could make the exact A indefinite) */
    seed = cb_rng_raw(9);
    double scale = d == CB_DEF_DROP ? 1.0 : 1.1, amp = d == CB_DEF_DROP ? 0.3 : 0.02;
    for (int i = 0; i < n3; i++) x[i] = scale * sc->x0[i] + amp * (2 * cb_rng_uniform(&seed) - 1);
    cb_system_assemble(&sc->sys, x, 1.0 / (dt * dt), (cb_definiteness)d, 0.0);
    int st = cb_solver_factor(s, &sc->sys.A);
    cr_assert_eq(st, CB_OK, "def=%s: %s (%s)", cb_definiteness_names[d], cb_status_name(st), cb_error_message());
    for (int rhs = 0; rhs < 3; rhs++) {
      double *b = random_vec(n, 500 + 10 * (uint64_t)d + (uint64_t)rhs);
      cr_assert_eq(cb_solver_solve(s, &sc->sys.A, b, sol), CB_OK);
      double res = residual(&sc->sys.A, b, sol);
      worst = fmax(worst, res);
      cr_expect(res <= 1e-10, "def=%s rhs %d: relative residual %.3g", cb_definiteness_names[d], rhs, res);
      cr_expect(s->stats.factor_nnz >= sc->sys.A.nnz / 2, "factor_nnz %.0f", s->stats.factor_nnz);
      free(b);
    }
  }
  cr_log_info("cholmod on the 21x21 hanging scene: worst relative residual %.3g\n", worst);
  cb_solver_free(s);
  free(x);
  free(sol);
  cb_scene_free(sc);
}

/* ---- solver.denormals ------------------------------------------------------------ */

#if defined(__SSE2__)
#include <xmmintrin.h>

/* [2 t 0; t 2 0; 0 0 1] with a subnormal t, b = (0, 1, 0): x0 = -t/4 is
 * subnormal too. flush (the default) reads t as zero and returns x0 = 0
 * exactly; keep returns the IEEE value. Either way the caller's
 * floating-point control word is the same after the call as before. */
Test(solver, cholmod_denormals_flush_or_keep, .init = setup) {
  const double t = 1e-310;
  cr_assert(fpclassify(t) == FP_SUBNORMAL);
  cb_sparse A;
  pattern_matrix(1, NULL, 0, &A);
  gsl_matrix *S = gsl_matrix_calloc(3, 3);
  gsl_matrix_set(S, 0, 0, 2);
  gsl_matrix_set(S, 1, 1, 2);
  gsl_matrix_set(S, 2, 2, 1);
  gsl_matrix_set(S, 0, 1, t);
  gsl_matrix_set(S, 1, 0, t);
  fill_from_dense(&A, S);
  for (int flush = 0; flush <= 1; flush++) {
    cb_solver_params p = cb_solver_params_default();
    cr_expect_eq(p.flush_denormals, 1, "flush is the default");
    p.flush_denormals = flush;
    cb_solver *s = NULL;
    cr_assert_eq(cb_solver_alloc("cholmod", &p, 3, &s), CB_OK);
    cr_assert_eq(cb_solver_analyze(s, &A), CB_OK);
    unsigned csr = _mm_getcsr();
    cr_assert_eq(cb_solver_factor(s, &A), CB_OK);
    double b[3] = {0, 1, 0}, x[3] = {1, 1, 1};
    cr_assert_eq(cb_solver_solve(s, &A, b, x), CB_OK);
    /* the control bits (rounding, masks, FTZ, DAZ); the low 6 are sticky exception flags */
    cr_expect_eq(_mm_getcsr() & ~0x3fu, csr & ~0x3fu, "flush=%d: control word %#x after the calls, %#x before", flush,
                 _mm_getcsr(), csr);
    cr_expect(fabs(x[1] - 0.5) <= 1e-15 && x[2] == 0, "flush=%d: x = %g %g %g", flush, x[0], x[1], x[2]);
    if (flush) cr_expect(x[0] == 0, "flush: x0 = %g, expected exactly 0", x[0]);
    else
      cr_expect(fpclassify(x[0]) == FP_SUBNORMAL && fabs(x[0] + t / 4) <= 1e-3 * t / 4, "keep: x0 = %g, expected %g",
                x[0], -t / 4);
    cb_solver_free(s);
  }
  gsl_matrix_free(S);
  cb_sparse_free(&A);
}
#endif

/* ---- not positive definite ------------------------------------------------------ */

/* Whether CHOLMOD, left to its defaults, factorises A supernodally. */
static int cholmod_is_supernodal(const cb_sparse *A) {
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  cholmod_sparse s;
  memset(&s, 0, sizeof s);
  s.nrow = s.ncol = (size_t)A->n;
  s.nzmax = (size_t)A->nnz;
  s.p = A->colp;
  s.i = A->rowi;
  s.x = A->val;
  s.stype = 1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  cholmod_factor *L = cholmod_analyze(&s, &c);
  cr_assert(L);
  int super = L->is_super;
  cholmod_free_factor(&L, &c);
  cholmod_finish(&c);
  return super;
}

Test(solver, cholmod_small_indefinite_matrix_is_not_spd, .init = setup) {
  cb_sparse A;
  pattern_matrix(1, NULL, 0, &A);
  cr_assert_eq(A.n, 3);
  /* [1 2 0; 2 1 0; 0 0 1]: eigenvalues -1, 1, 3 */
  gsl_matrix *S = gsl_matrix_calloc(3, 3);
  gsl_matrix_set(S, 0, 0, 1);
  gsl_matrix_set(S, 1, 1, 1);
  gsl_matrix_set(S, 2, 2, 1);
  gsl_matrix_set(S, 0, 1, 2);
  gsl_matrix_set(S, 1, 0, 2);
  fill_from_dense(&A, S);
  cr_assert(!cholmod_is_supernodal(&A), "a 3x3 matrix should be factorised simplicially");
  cb_solver *s = NULL;
  cr_assert_eq(cb_solver_alloc("cholmod", NULL, 3, &s), CB_OK);
  cr_assert_eq(cb_solver_analyze(s, &A), CB_OK);
  cr_expect_eq(cb_solver_factor(s, &A), CB_NOT_SPD);
  cr_expect_eq(s->stats.status, CB_NOT_SPD);
  double b[3] = {1, 2, 3}, x[3] = {0, 0, 0};
  cr_expect_eq(cb_solver_solve(s, &A, b, x), CB_NOT_SPD, "solve after a failed factorisation");
  /* semidefinite (a zero pivot) is not positive definite either: [1 1; 1 1] + e3 e3^T */
  gsl_matrix_set(S, 0, 1, 1);
  gsl_matrix_set(S, 1, 0, 1);
  fill_from_dense(&A, S);
  cr_expect_eq(cb_solver_factor(s, &A), CB_NOT_SPD, "singular PSD matrix");
  /* the same solver recovers on SPD values */
  gsl_matrix_set(S, 0, 1, 0.5);
  gsl_matrix_set(S, 1, 0, 0.5);
  fill_from_dense(&A, S);
  cr_expect_eq(cb_solver_factor(s, &A), CB_OK);
  cr_expect_eq(cb_solver_solve(s, &A, b, x), CB_OK);
  /* [1 .5 0; .5 1 0; 0 0 1] x = (1, 2, 3): x = (0, 2, 3) */
  cr_expect(fabs(x[0] - 0.0) <= 1e-15 && fabs(x[1] - 2.0) <= 1e-15 && fabs(x[2] - 3.0) <= 1e-15, "x = %g %g %g", x[0],
            x[1], x[2]);
  cb_solver_free(s);
  gsl_matrix_free(S);
  cb_sparse_free(&A);
}

Test(solver, cholmod_large_indefinite_newton_matrix_is_not_spd, .init = setup) {
  /* A flat 64x64 cloth compressed to half its size: every spring has
   * l = L/2, so its transverse coefficient is k(1 - L/l) = -k, and for an
   * out-of-plane displacement field v, v^T H v = -k sum (v_i - v_j)^2 < 0.
   * With the exact Hessian and a tiny mass term, A is indefinite. */
  const char *sets[] = {"mesh.n=64", "scene.initial_scale=0.5", "material.vertex_mass=1", "scene.pins=top-corners",
                        NULL};
  cb_scene *sc = test_scene(sets);
  cb_sparse *A = &sc->sys.A;
  cb_system_assemble(&sc->sys, sc->x0, 1e-6, CB_DEF_NONE, 0.0);
  cr_assert(cholmod_is_supernodal(A), "the 64x64 grid should be factorised supernodally");
  cb_solver *s = NULL;
  cr_assert_eq(cb_solver_alloc("cholmod", NULL, A->n, &s), CB_OK);
  cr_assert_eq(cb_solver_analyze(s, A), CB_OK);
  int st = cb_solver_factor(s, A);
  cr_expect_eq(st, CB_NOT_SPD, "factor returned %s", cb_status_name(st));
  double *b = random_vec(A->n, 3), *x = calloc((size_t)A->n, sizeof(double));
  cr_assert(x);
  cr_expect_eq(cb_solver_solve(s, A, b, x), CB_NOT_SPD, "solve after a failed supernodal factorisation");
  /* recovery on the same symbolic analysis: the SPD Newton matrix with drop */
  const double dt = 1.0 / 30;
  cb_system_assemble(&sc->sys, sc->x0, 1.0 / (dt * dt), CB_DEF_DROP, 0.0);
  st = cb_solver_factor(s, A);
  cr_expect_eq(st, CB_OK, "refactor after failure: %s (%s)", cb_status_name(st), cb_error_message());
  if (st == CB_OK) {
    cr_expect_eq(cb_solver_solve(s, A, b, x), CB_OK);
    double res = residual(A, b, x);
    cr_expect(res <= 1e-10, "residual after recovery %.3g", res);
  }
  free(b);
  free(x);
  cb_solver_free(s);
  cb_scene_free(sc);
}

/* Every solver meets an indefinite matrix without crashing: a positive status,
 * or (if it claims success) a solution with a small residual. Iterative
 * solvers are capped at a moderate number of iterations here. */
Test(solver, every_solver_survives_indefinite_matrices, .init = setup) {
  const char *sets[] = {"mesh.n=12", "scene.initial_scale=0.5", "material.vertex_mass=1", "scene.pins=none", NULL};
  cb_scene *sc = test_scene(sets);
  cb_sparse *A = &sc->sys.A;
  cb_system_assemble(&sc->sys, sc->x0, 1e-6, CB_DEF_NONE, 0.0);
  double *b = random_vec(A->n, 4), *x = malloc((size_t)A->n * sizeof(double));
  cr_assert(x);
  for (int k = 0; cb_solver_types[k]; k++) {
    const char *name = cb_solver_types[k]->name;
    cb_solver_params p = cb_solver_params_default();
    p.tol = 1e-10;
    p.max_iters = 5000;
    cb_solver *s = NULL;
    cr_assert_eq(cb_solver_alloc(name, &p, A->n, &s), CB_OK);
    cr_assert_eq(cb_solver_analyze(s, A), CB_OK);
    memset(x, 0, (size_t)A->n * sizeof(double));
    int st = cb_solver_factor(s, A);
    cr_expect_geq(st, 0, "%s: factor returned an error %d instead of a status", name, st);
    if (st == CB_OK) {
      st = cb_solver_solve(s, A, b, x);
      cr_expect_geq(st, 0, "%s: solve returned an error %d", name, st);
    }
    if (st == CB_OK)
      cr_expect(residual(A, b, x) <= 1e-8, "%s claims success with residual %.3g", name, residual(A, b, x));
    else
      cr_expect(st == CB_NOT_SPD || st == CB_INDEFINITE || st == CB_DIVERGED || st == CB_NOT_CONVERGED,
                "%s: unexpected status %s", name, cb_status_name(st));
    cb_solver_free(s);
  }
  free(b);
  free(x);
  cb_scene_free(sc);
}

/* The upper-block product of the iterative solvers against the dense product
 * y_i = sum_j S_ij x_j of the same random SPD matrix (ring + chords pattern),
 * and against the full-storage kernel on a Newton matrix of the lab scene. */
Test(solver, symmetric_storage_product_matches_dense, .init = setup) {
  const int nblk = 30;
  int pairs[2 * 60], np = 0;
  cb_rng seed = cb_rng_raw(11);
  for (int i = 0; i < nblk; i++) {
    pairs[2 * np] = i;
    pairs[2 * np + 1] = (i + 1) % nblk;
    np++;
  }
  for (int k = 0; k < 25; k++) {
    int i = (int)(cb_rng_uniform(&seed) * nblk), j = (int)(cb_rng_uniform(&seed) * nblk);
    if (i != j) {
      pairs[2 * np] = i;
      pairs[2 * np + 1] = j;
      np++;
    }
  }
  cb_sparse A;
  pattern_matrix(nblk, pairs, np, &A);
  gsl_matrix *S = random_spd_on_pattern(&A, 77);
  fill_from_dense(&A, S);
  cb_sparse_sym U;
  cr_assert_eq(cb_sparse_sym_alloc(&U, &A), CB_OK);
  cr_assert_lt(U.nub, A.nnz / 9, "the upper blocks are fewer than all blocks");
  cb_sparse_sym_fill(&U, &A);
  double *x = random_vec(A.n, 78), *y = malloc((size_t)A.n * sizeof(double)), *r = malloc((size_t)A.n * sizeof(double));
  cr_assert(y && r);
  cb_sparse_sym_matvec(&U, x, y);
  double err = 0, scale = 0;
  for (int i = 0; i < A.n; i++) {
    double yi = 0;
    for (int j = 0; j < A.n; j++) yi += gsl_matrix_get(S, (size_t)i, (size_t)j) * x[j];
    err = fmax(err, fabs(y[i] - yi));
    scale = fmax(scale, fabs(yi));
  }
  cr_expect(err <= 1e-13 * scale, "symmetric product differs from the dense one by %.3g (scale %.3g)", err, scale);
  double rn = cb_sparse_sym_residual(&U, y, x, r); /* b = A x exactly: r = 0 up to round-off */
  cr_expect(rn <= 1e-13 * scale * sqrt(A.n), "residual of b = A x is %.3g", rn);
  cr_expect_eq(cb_sparse_sym_matvec_bytes(&U), (size_t)U.nub * 76 + (size_t)(nblk + 1) * 4 + (size_t)A.n * 16);
  cb_sparse_sym_free(&U);
  free(x);
  free(y);
  free(r);
  gsl_matrix_free(S);
  cb_sparse_free(&A);
}
