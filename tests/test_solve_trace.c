/* Traced solves (lib/instruments/solve_trace.c): rows, thinning, timing, error column. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "capture.h"
#include "solve_trace.h"
#include "spectrum.h"
#include "support.h"

static cb_capture cap;
static void setup(void) {
  cb_config c;
  test_config(&c, (const char *const[]){"mesh.n=8", "material.vertex_mass=1", "integrator.max_iters=5", NULL});
  cr_assert_eq(cb_capture_newton_system(&c, 6, 0, &cap), CB_OK, "%s", cb_error_message());
}
static void teardown(void) { cb_capture_free(&cap); }

static double rel_err(int n, const double *x, const double *y) {
  double e = 0, m = 0;
  for (int i = 0; i < n; i++) {
    e += (x[i] - y[i]) * (x[i] - y[i]);
    m += y[i] * y[i];
  }
  return sqrt(e / m);
}

Test(solve_trace, reference_is_cholmod_refined, .init = setup, .fini = teardown) {
  int n = cap.A.n;
  double *x = malloc((size_t)n * sizeof(double)), *r = malloc((size_t)n * sizeof(double));
  cr_assert_eq(cb_trace_reference(&cap.A, cap.b, x), CB_OK);
  double rn = cb_sparse_residual(&cap.A, cap.b, x, r), bn = 0;
  for (int i = 0; i < n; i++) bn += cap.b[i] * cap.b[i];
  cr_expect_lt(rn / sqrt(bn), 1e-14);
  free(x);
  free(r);
}

Test(solve_trace, rows_of_an_iterative_solve, .init = setup, .fini = teardown) {
  int n = cap.A.n;
  double *xref = malloc((size_t)n * sizeof(double)), *x = malloc((size_t)n * sizeof(double)),
         *d = malloc((size_t)n * sizeof(double));
  cr_assert_eq(cb_trace_reference(&cap.A, cap.b, xref), CB_OK);
  cb_spectrum sp;
  cb_jacobi_scaling(&cap.A, d);
  cr_assert_eq(cb_spectrum_lanczos(&cap.A, d, &sp), CB_OK);
  cb_solver_params p = cb_solver_params_default();
  p.alpha = 2 / (sp.lmin + sp.lmax);
  p.tol = 1e-10;
  p.max_iters = 100000;
  cb_trace_params tp = {.keep_all = 20, .growth = 1.2, .mark_tol = 1e-6};
  cb_trace t;
  cr_assert_eq(cb_trace_solve("jacobi", &p, &cap.A, cap.b, xref, &tp, x, &t), CB_OK);
  cr_assert_eq(t.status, CB_OK);
  cr_assert_gt(t.iters, 100, "a long enough run to be thinned");
  cr_expect_eq(t.rows[0].iter, 0);
  cr_expect_float_eq(t.rows[0].rel_residual, 1.0, 1e-12);
  cr_expect_float_eq(t.rows[0].error, 1.0, 1e-12); /* x = 0 */
  cr_expect_eq(t.rows[t.nrows - 1].iter, t.iters, "the last iteration is kept");
  cr_expect_float_eq(t.rows[t.nrows - 1].error, rel_err(n, x, xref), 1e-14);
  int mark = 0;
  for (int i = 1; i < t.nrows; i++) {
    const cb_trace_row *a = &t.rows[i - 1], *b = &t.rows[i];
    cr_expect_gt(b->iter, a->iter);
    cr_expect_geq(b->wall_ms, a->wall_ms, "cumulative time");
    if (b->iter <= 20) cr_expect_eq(b->iter, a->iter + 1, "every iteration up to keep_all");
    else if (i < t.nrows - 1 && !(b->rel_residual <= 1e-6 && a->rel_residual > 1e-6))
      cr_expect_geq(b->iter, (int)ceil(1.2 * a->iter), "geometric thinning: %d after %d", b->iter, a->iter);
    mark += b->rel_residual <= 1e-6 && a->rel_residual > 1e-6;
  }
  /* the first row under 1e-6 is the first iteration under 1e-6 */
  cr_expect_eq(mark, 1);
  cr_expect_lt(t.nrows, 20 + 4 + (int)ceil(log(t.iters / 21.0) / log(1.2)) + 2);
  cr_expect_leq(t.rows[t.nrows - 1].wall_ms, t.wall_ms + 1e-9);
  /* the tail rate of a Jacobi run is rho(I - alpha D^-1 A) */
  double rho = cb_jacobi_rho(sp.lmin, sp.lmax, p.alpha), rate = cb_trace_rate(t.rows, t.nrows, 0.25);
  cr_expect_lt(fabs(log(rate) / log(rho) - 1), 0.05, "rate %.6f, rho %.6f", rate, rho);
  const cb_trace_row *at = cb_trace_at(&t, 50); /* the last kept row at or before iteration 50 */
  cr_assert_not_null(at);
  cr_expect_leq(at->iter, 50);
  cr_expect(at == &t.rows[t.nrows - 1] || at[1].iter > 50);
  cb_trace_free(&t);
  free(xref);
  free(x);
  free(d);
}

Test(solve_trace, direct_solve_is_one_row_and_failures_keep_a_row, .init = setup, .fini = teardown) {
  int n = cap.A.n;
  double *xref = malloc((size_t)n * sizeof(double));
  cr_assert_eq(cb_trace_reference(&cap.A, cap.b, xref), CB_OK);
  cb_trace t;
  cr_assert_eq(cb_trace_solve("cholmod", NULL, &cap.A, cap.b, xref, NULL, NULL, &t), CB_OK);
  cr_expect_eq(t.nrows, 1);
  cr_expect_eq(t.rows[0].iter, 1);
  cr_expect_lt(t.rows[0].error, 1e-12);
  cr_expect_gt(t.rows[0].error, 0, "refined reference: CHOLMOD's own error shows");
  cb_trace_free(&t);
  /* Chebyshev with alpha past 2/lambda_max: its rho estimate is >= 1, the set-up fails */
  cb_solver_params p = cb_solver_params_default();
  p.alpha = 5;
  cr_assert_eq(cb_trace_solve("chebyshev", &p, &cap.A, cap.b, xref, NULL, NULL, &t), CB_OK);
  cr_expect_eq(t.status, CB_DIVERGED);
  cr_expect_eq(t.nrows, 1);
  cr_expect_eq(t.rows[0].iter, 0);
  cb_trace_free(&t);
  cr_expect_lt(cb_trace_solve("no_such_solver", NULL, &cap.A, cap.b, xref, NULL, NULL, &t), 0);
  cb_trace_free(&t);
  free(xref);
}

/* mark_err: the first iteration with error <= mark_err is kept and reported (checked against a run
 * that keeps every iteration), and an untimed-monitor solve of exactly that many iterations
 * (cb_trace_timed_solve) ends at the same error. */
Test(solve_trace, first_iteration_under_an_error_target, .init = setup, .fini = teardown) {
  int n = cap.A.n;
  double *xref = malloc((size_t)n * sizeof(double));
  cr_assert_eq(cb_trace_reference(&cap.A, cap.b, xref), CB_OK);
  cb_solver_params p = cb_solver_params_default();
  p.tol = 1e-14;
  p.max_iters = 5000;
  cb_trace_params thin = {.keep_all = 0, .growth = 2, .mark_tol = 1e-6, .mark_err = 1e-5},
                  every = {.keep_all = 5000, .growth = 2, .mark_tol = 1e-6, .mark_err = 0};
  cb_trace a, b;
  cr_assert_eq(cb_trace_solve("cg", &p, &cap.A, cap.b, xref, &thin, NULL, &a), CB_OK);
  cr_assert_eq(cb_trace_solve("cg", &p, &cap.A, cap.b, xref, &every, NULL, &b), CB_OK);
  cr_expect_eq(b.iter_err, -1, "mark_err = 0: off");
  int first = -1;
  for (int i = 0; i < b.nrows && first < 0; i++)
    if (b.rows[i].error <= 1e-5) first = b.rows[i].iter;
  cr_assert_gt(first, 1);
  cr_expect_eq(a.iter_err, first, "traced %d, every row %d", a.iter_err, first);
  const cb_trace_row *r = cb_trace_at(&a, first);
  cr_assert(r && r->iter == first, "the marked iteration is a row");
  cr_expect_leq(r->error, 1e-5);
  cb_solver_params q = p;
  q.tol = 0;
  q.max_iters = first;
  cb_timed_solve ts;
  cr_assert_eq(cb_trace_timed_solve("cg", &q, &cap.A, cap.b, xref, &ts), CB_OK);
  cr_expect_eq(ts.iters, first);
  cr_expect_float_eq(ts.error, r->error, 1e-12 + 1e-9 * r->error);
  cr_expect(ts.total_ms > 0 && fabs(ts.total_ms - (ts.analyze_ms + ts.factor_ms + ts.solve_ms)) < 1e-9);
  cb_trace_free(&a);
  cb_trace_free(&b);
  free(xref);
}
