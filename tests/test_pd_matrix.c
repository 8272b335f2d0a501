/* Projective dynamics' constant matrix P and its two storages (pd_matrix.h;
 * issue 31 §1):
 *  - the scalar n x n P has the closed-form entries: P_ii = m_i/dt^2 + k deg(i),
 *    P_ij = -k per spring, so a row sums to m_i/dt^2 + k (pinned neighbours);
 *  - the block matrix is P (x) I_3 of the scalar one, entry for entry (exact),
 *    with the constant Hessians of quadratic bending and frozen FEM too;
 *  - the Kronecker check refuses a block that is not s I_3;
 *  - CHOLMOD's 3-column solve agrees with three 1-column solves and with a dense
 *    GSL solve;
 *  - pd, pd-chebyshev and lbfgs give the same positions over a run on both paths
 *    up to rounding (the largest difference is printed), and report their path. */
#include <criterion/criterion.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"
#include "../lib/core/integrator/pd_matrix.h"

#define GRID "mesh.n=7", "mesh.size=1", "material.vertex_mass=0.02", "material.stretch_k=400"
#define DT 0.02

/* Entry (i, j) of a scalar CSC matrix, 0 if absent. */
static double scalar_at(const cb_sparse *P, int i, int j) {
  for (int q = P->colp[j]; q < P->colp[j + 1]; q++)
    if (P->rowi[q] == i) return P->val[q];
  return 0.0;
}

Test(pd_matrix, scalar_p_has_the_closed_form_entries) {
  const char *sets[] = {GRID, "scene.pins=top-edge", NULL};
  cb_scene *s = test_scene(sets);
  cb_sparse P;
  cr_assert_eq(cb_pd_matrix_build_scalar(s, DT, 0, &P), CB_OK);
  int nf = s->model.nfree;
  cr_assert_eq(P.n, nf);
  cr_assert_null(P.bcolp);
  /* degrees and pinned neighbours counted here from the mesh's triangles (each interior edge seen twice) */
  int nv = s->mesh.nv, *adj = calloc((size_t)nv * nv, sizeof(int));
  cr_assert(adj);
  for (int t = 0; t < s->mesh.nt; t++)
    for (int a = 0; a < 3; a++) {
      int i = s->mesh.tri[3 * t + a], j = s->mesh.tri[3 * t + (a + 1) % 3];
      adj[i * nv + j] = adj[j * nv + i] = 1;
    }
  double k = 400;
  for (int bi = 0; bi < nf; bi++) {
    int i = s->free_vertex[bi], deg = 0, pinned = 0;
    double rowsum = 0.0;
    for (int j = 0; j < nv; j++) {
      if (!adj[i * nv + j]) continue;
      deg++;
      int bj = s->free_index[j];
      if (bj < 0) pinned++;
      else cr_expect_float_eq(scalar_at(&P, bi, bj), -k, 1e-12 * k, "P(%d,%d)", bi, bj);
    }
    double mi = s->mass[i] / (DT * DT);
    cr_expect_float_eq(scalar_at(&P, bi, bi), mi + k * deg, 1e-12 * (mi + k * deg), "P(%d,%d)", bi, bi);
    for (int q = P.colp[bi]; q < P.colp[bi + 1]; q++) rowsum += P.val[q];
    cr_expect_float_eq(rowsum, mi + k * pinned, 1e-9 * (mi + k * deg), "row %d sums to m/dt^2 + k (pinned)", bi);
  }
  int free_pairs = 0; /* springs with both ends free: two off-diagonal entries each, and nothing else */
  for (int i = 0; i < nv; i++)
    for (int j = i + 1; j < nv; j++) free_pairs += adj[i * nv + j] && s->free_index[i] >= 0 && s->free_index[j] >= 0;
  cr_expect_eq(P.nnz, nf + 2 * free_pairs);
  for (int j = 0; j < nf; j++)
    for (int q = P.colp[j]; q < P.colp[j + 1]; q++)
      if (P.rowi[q] != j)
        cr_expect(adj[s->free_vertex[P.rowi[q]] * nv + s->free_vertex[j]], "entry (%d,%d) is not a spring", P.rowi[q],
                  j);
  free(adj);
  cb_sparse_free(&P);
  cb_scene_free(s);
}

/* The block P equals scalar P (x) I_3 exactly, with and without the constant Hessians. */
static void expect_kronecker_of_scalar(const char *const *sets, int with_constant) {
  cb_scene *s = test_scene(sets);
  cb_sparse P, B;
  cr_assert_eq(cb_pd_matrix_build_scalar(s, DT, with_constant, &P), CB_OK);
  cr_assert_eq(cb_pd_matrix_build(s, DT, with_constant, &B), CB_OK);
  cr_assert_eq(B.nblk, P.n);
  double scale = 0.0;
  for (int q = 0; q < P.nnz; q++) scale = fmax(scale, fabs(P.val[q]));
  for (int bj = 0; bj < B.nblk; bj++)
    for (int k = B.bcolp[bj]; k < B.bcolp[bj + 1]; k++) {
      int bi = B.brow[k], slot, stride;
      cb_sparse_block_slot(&B, bi, bj, &slot, &stride);
      double p = scalar_at(&P, bi, bj);
      for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
          cr_expect(fabs(B.val[slot + c * stride + r] - (r == c ? p : 0.0)) <= 1e-15 * scale,
                    "block (%d,%d) entry (%d,%d): %.17g vs %.17g", bi, bj, r, c, B.val[slot + c * stride + r],
                    r == c ? p : 0.0);
    }
  cr_expect(cb_pd_matrix_is_kronecker(&B, B.val, NULL));
  cr_expect_leq(9 * P.nnz, B.nnz, "the block matrix holds the scalar one's entries 9 times (or more)");
  cb_sparse_free(&P);
  cb_sparse_free(&B);
  cb_scene_free(s);
}

Test(pd_matrix, block_p_is_scalar_p_kron_i3) {
  const char *springs[] = {GRID, NULL};
  expect_kronecker_of_scalar(springs, 0);
  const char *quad[] = {GRID, "material.bend=quadratic", "material.bend_k=0.01", NULL};
  expect_kronecker_of_scalar(quad, 1);
  const char *fem[] = {GRID, "material.stretch=fem", "material.fem_hessian=frozen", "material.bend=quadratic", NULL};
  expect_kronecker_of_scalar(fem, 1);
}

Test(pd_matrix, kronecker_check_refuses_a_block_that_is_not_s_i3) {
  cb_pattern pat;
  cb_sparse A;
  cr_assert_eq(cb_pattern_init(&pat, 2), CB_OK);
  cr_assert_eq(cb_pattern_add(&pat, 0, 1), CB_OK);
  cr_assert_eq(cb_sparse_from_pattern(&pat, &A), CB_OK);
  cb_pattern_free(&pat);
  const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int bi = 0; bi < 2; bi++)
    for (int bj = 0; bj < 2; bj++) {
      int slot, stride;
      cr_assert_geq(cb_sparse_block_slot(&A, bi, bj, &slot, &stride), 0);
      cb_sparse_add_block(A.val, slot, stride, I3, bi == bj ? 2.0 : -1.0);
    }
  int bad;
  cr_expect(cb_pd_matrix_is_kronecker(&A, A.val, &bad));
  cr_expect_eq(bad, -1);
  int slot, stride;
  cb_sparse_block_slot(&A, 0, 1, &slot, &stride);
  A.val[slot + 1 * stride + 0] = 1e-300; /* one off-diagonal entry of block (0, 1), however small */
  cr_expect_not(cb_pd_matrix_is_kronecker(&A, A.val, &bad));
  cr_expect_eq(bad, 1);
  A.val[slot + 1 * stride + 0] = 0.0;
  A.val[slot + 2 * stride + 2] = -1.0 + 1e-15; /* unequal diagonal */
  cr_expect_not(cb_pd_matrix_is_kronecker(&A, A.val, &bad));
  cb_sparse_free(&A);
}

Test(pd_matrix, cholmod_three_columns_match_one_column_solves_and_gsl) {
  const char *sets[] = {GRID, NULL};
  cb_scene *s = test_scene(sets);
  cb_sparse P;
  cr_assert_eq(cb_pd_matrix_build_scalar(s, DT, 0, &P), CB_OK);
  int n = P.n;
  cb_solver *sv;
  cb_solver_params sp = cb_solver_params_default();
  cr_assert_eq(cb_solver_alloc("cholmod", &sp, n, &sv), CB_OK);
  cr_assert_eq(cb_solver_analyze(sv, &P), CB_OK);
  cr_assert_eq(cb_solver_factor(sv, &P), CB_OK);
  double *b = malloc(3 * (size_t)n * sizeof(double)), *x = malloc(3 * (size_t)n * sizeof(double)),
         *x1 = malloc((size_t)n * sizeof(double));
  cr_assert(b && x && x1);
  for (int i = 0; i < 3 * n; i++) b[i] = sin(1.0 + 0.7 * i) * (1 + i % 5);
  cr_assert_eq(cb_solver_solve_n(sv, &P, 3, b, x), CB_OK);
  cr_expect_lt(sv->stats.rel_residual, 1e-12, "residual %g", sv->stats.rel_residual);
  gsl_matrix *D = gsl_matrix_calloc((size_t)n, (size_t)n);
  cr_assert(D);
  for (int j = 0; j < n; j++)
    for (int q = P.colp[j]; q < P.colp[j + 1]; q++) gsl_matrix_set(D, (size_t)P.rowi[q], (size_t)j, P.val[q]);
  cr_assert_eq(gsl_linalg_cholesky_decomp1(D), 0);
  gsl_vector *g = gsl_vector_alloc((size_t)n);
  for (int c = 0; c < 3; c++) {
    cr_assert_eq(cb_solver_solve(sv, &P, b + (size_t)c * n, x1), CB_OK);
    gsl_vector_const_view bc = gsl_vector_const_view_array(b + (size_t)c * n, (size_t)n);
    gsl_linalg_cholesky_solve(D, &bc.vector, g);
    double xs = 0.0;
    for (int i = 0; i < n; i++) xs = fmax(xs, fabs(gsl_vector_get(g, (size_t)i)));
    for (int i = 0; i < n; i++) {
      cr_expect(fabs(x[(size_t)c * n + i] - x1[i]) <= 1e-13 * xs, "column %d row %d: %g vs %g", c, i,
                x[(size_t)c * n + i], x1[i]);
      cr_expect(fabs(x[(size_t)c * n + i] - gsl_vector_get(g, (size_t)i)) <= 1e-11 * xs, "column %d row %d vs GSL", c,
                i);
    }
  }
  sv->params.residual = 0; /* not computed: NaN, never a stale number */
  cr_assert_eq(cb_solver_solve_n(sv, &P, 3, b, x), CB_OK);
  cr_expect(isnan(sv->stats.rel_residual));
  gsl_vector_free(g);
  gsl_matrix_free(D);
  free(b);
  free(x);
  free(x1);
  cb_solver_free(sv);
  cb_sparse_free(&P);
  cb_scene_free(s);
}

/* Runs n steps of the integrator the sets name; returns x and the last step's stats. */
static double *run(const char *const *sets, int n, cb_step_stats *last) {
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  size_t n3 = (size_t)3 * s->mesh.nv;
  double *x = malloc(n3 * sizeof(double)), *v = malloc(n3 * sizeof(double));
  cr_assert(x && v);
  memcpy(x, s->x0, n3 * sizeof(double));
  memcpy(v, s->v0, n3 * sizeof(double));
  for (int k = 0; k < n; k++) {
    int st = cb_integrator_step(it, x, v, last);
    cr_assert(st == CB_OK || st == CB_NOT_CONVERGED, "step %d: %s", k, cb_status_name(st));
  }
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
  return x;
}

/* The largest |x_scalar - x_block| over a run of one method, relative to the mesh size (1 m). */
static double path_difference(const char *method, const char *extra, const char *extra2, int steps) {
  char m[64];
  snprintf(m, sizeof m, "integrator.method=%s", method);
  const char *scal[] = {"mesh.n=15",
                        "mesh.size=1",
                        "material.vertex_mass=0.01",
                        "material.stretch_k=1000",
                        "integrator.dt=0.02",
                        "integrator.iters=10",
                        m,
                        extra,
                        extra2,
                        NULL};
  const char *blk[] = {"mesh.n=15",
                       "mesh.size=1",
                       "material.vertex_mass=0.01",
                       "material.stretch_k=1000",
                       "integrator.dt=0.02",
                       "integrator.iters=10",
                       m,
                       "integrator.pd_matrix=block",
                       extra,
                       extra2,
                       NULL};
  cb_step_stats a, b;
  double *xa = run(scal, steps, &a), *xb = run(blk, steps, &b);
  cr_expect_eq(a.global_path, CB_GLOBAL_SCALAR, "%s: auto path %s", method, cb_global_path_name(a.global_path));
  cr_expect_eq(b.global_path, CB_GLOBAL_BLOCK, "%s: block path %s", method, cb_global_path_name(b.global_path));
  double d = 0.0;
  for (int i = 0; i < 3 * 225; i++) d = fmax(d, fabs(xa[i] - xb[i]));
  free(xa);
  free(xb);
  return d;
}

Test(pd_matrix, both_paths_give_the_same_run_up_to_rounding) {
  const int steps = 60; /* 1.2 s of a 15^2 cloth falling from its top corners */
  double dpd = path_difference("pd", "integrator.iters=10", "integrator.iters=10", steps);
  double dpc = path_difference("pd-chebyshev", "integrator.rho=0.9", "integrator.iters=10", steps);
  double dlb = path_difference("lbfgs", "integrator.iters=10", "integrator.tol=0", steps);
  double dlq = path_difference("lbfgs", "material.bend=quadratic", "material.bend_k=0.001", steps);
  printf("pd_matrix: largest |x_scalar - x_block| over %d steps (15^2, 1 m): pd %.3g m, pd-chebyshev %.3g m, "
         "lbfgs %.3g m, lbfgs with quadratic bending %.3g m\n",
         steps, dpd, dpc, dlb, dlq);
  /* round-off of a back-solve is ~1e-16 relative; 60 steps of a stable iteration keep it far below 1e-9 m */
  cr_expect_lt(dpd, 1e-9);
  cr_expect_lt(dpc, 1e-9);
  cr_expect_lt(dlb, 1e-9);
  cr_expect_lt(dlq, 1e-9);
  cr_expect_gt(dpd + dpc + dlb + dlq, 0.0, "the two paths are different computations (their rounding differs)");
}

Test(pd_matrix, an_iterative_solver_keeps_the_block_path) {
  const char *sets[] = {GRID, "integrator.method=pd", "integrator.iters=3", "solver.method=pcg", NULL};
  cb_step_stats st;
  double *x = run(sets, 2, &st);
  cr_expect_eq(st.global_path, CB_GLOBAL_BLOCK);
  free(x);
  const char *newton[] = {GRID, "integrator.method=newton", NULL};
  x = run(newton, 1, &st);
  cr_expect_eq(st.global_path, CB_GLOBAL_NONE);
  cr_expect_str_eq(cb_global_path_name(CB_GLOBAL_SCALAR), "scalar");
  cr_expect_null(cb_global_path_name(3));
  free(x);
}
