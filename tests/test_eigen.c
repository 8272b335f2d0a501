/* Extreme eigenvalues: cb_lanczos on cb_scaled_op against dense symmetric
 * eigenvalues computed here with GSL (and cb_dense_eigenvalues against the
 * same), for Newton matrices A = M/dt^2 + H, their Jacobi scaling
 * D^-1/2 A D^-1/2, and M^-1/2 H M^-1/2 (the explicit stability limit). */
#include <criterion/criterion.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"
#include "rng.h"
#include <clothbench/timer.h>

static void setup(void) { gsl_set_error_handler_off(); }

/* Ascending eigenvalues of diag(d) A diag(d) (d may be NULL), our own dense solve. */
static double *dense_spectrum(const cb_sparse *A, const double *d) {
  gsl_matrix *D = test_dense(A);
  size_t n = D->size1;
  if (d)
    for (size_t i = 0; i < n; i++)
      for (size_t j = 0; j < n; j++) gsl_matrix_set(D, i, j, gsl_matrix_get(D, i, j) * d[i] * d[j]);
  gsl_vector *ev = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc(n);
  cr_assert_eq(gsl_eigen_symm(D, ev, ws), GSL_SUCCESS);
  double *out = malloc(n * sizeof(double));
  cr_assert(out);
  for (size_t i = 0; i < n; i++) out[i] = gsl_vector_get(ev, i);
  for (size_t i = 1; i < n; i++)
    for (size_t j = i; j > 0 && out[j - 1] > out[j]; j--) {
      double t = out[j];
      out[j] = out[j - 1];
      out[j - 1] = t;
    }
  gsl_eigen_symm_free(ws);
  gsl_vector_free(ev);
  gsl_matrix_free(D);
  return out;
}

/* Scene at a jittered state with its matrix assembled. */
static cb_scene *scene_with_matrix(const char *const *sets, double amp, double mass_scale, cb_definiteness def,
                                   uint64_t seed0) {
  cb_rng seed = cb_rng_raw(seed0);
  cb_scene *s = test_scene(sets);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double));
  cr_assert(x);
  for (int i = 0; i < n3; i++) x[i] = s->x0[i] + amp * (2 * cb_rng_uniform(&seed) - 1);
  cb_system_assemble(&s->sys, x, mass_scale, def, 0.0);
  free(x);
  return s;
}

typedef struct {
  double lmin, lmax, emin, emax;
  int steps, status;
} eig_check;

/* Lanczos on diag(d) A diag(d) against the dense spectrum. */
static eig_check lanczos_vs_dense(const cb_sparse *A, const double *d, const cb_lanczos_params *p, const char *label) {
  double *work = malloc((size_t)A->n * sizeof(double));
  cr_assert(work);
  cb_scaled_op op = {A, d, work};
  cb_eig_result r;
  double t0 = cb_now_ms();
  int st = cb_lanczos(A->n, cb_scaled_op_apply, &op, p, &r);
  double elapsed = cb_now_ms() - t0; /* the call's own wall time, clocked here */
  cr_assert_eq(st, CB_OK, "%s: lanczos returned %d (%s)", label, st, cb_error_message());
  double *ev = dense_spectrum(A, d);
  eig_check c = {r.lmin, r.lmax, ev[0], ev[A->n - 1], r.steps, r.status};
  double scale = fmax(fabs(c.emin), fabs(c.emax));
  cr_log_info("%s: n = %d, %d steps, status %s: lmin %.12g (dense %.12g), lmax %.12g (dense %.12g)\n", label, A->n,
              r.steps, cb_status_name(r.status), r.lmin, c.emin, r.lmax, c.emax);
  cr_expect_eq(r.status, CB_OK, "%s: status %s after %d steps", label, cb_status_name(r.status), r.steps);
  cr_expect(r.steps >= 1 && r.steps <= p->max_steps && r.steps <= A->n, "%s: steps %d", label, r.steps);
  cr_expect(fabs(r.lmax - c.emax) <= 1e-6 * fabs(c.emax), "%s: lmax %.15g vs %.15g", label, r.lmax, c.emax);
  cr_expect(fabs(r.lmin - c.emin) <= 1e-6 * fmax(fabs(c.emin), 1e-3 * scale), "%s: lmin %.15g vs %.15g", label, r.lmin,
            c.emin);
  /* Ritz values lie inside the spectrum */
  cr_expect(r.lmin >= c.emin - 1e-10 * scale && r.lmax <= c.emax + 1e-10 * scale, "%s: Ritz values outside", label);
  /* converged means the reported residual bounds meet the tolerance */
  if (r.status == CB_OK && r.steps < A->n)
    cr_expect(r.res_min <= p->tol * fmax(fabs(r.lmin), fabs(r.lmax)) &&
                  r.res_max <= p->tol * fmax(fabs(r.lmin), fabs(r.lmax)),
              "%s: residual bounds %.3g %.3g", label, r.res_min, r.res_max);
  /* its reported time is the run's: positive (at least one product was done) and within the call's */
  cr_expect(r.ms > 0 && r.ms <= elapsed, "%s: reported %.6g ms, the call took %.6g ms", label, r.ms, elapsed);
  free(ev);
  free(work);
  return c;
}

static double *diag_scaling(const cb_sparse *A) { /* |D|^-1/2 */
  double *d = malloc((size_t)A->n * sizeof(double));
  cr_assert(d);
  for (int j = 0; j < A->n; j++) {
    double a = 0;
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++)
      if (A->rowi[p] == j) a = A->val[p];
    cr_assert(a != 0);
    d[j] = 1 / sqrt(fabs(a));
  }
  return d;
}

Test(eigen, lanczos_extremes_of_a_newton_matrix, .init = setup) {
  const char *sets[] = {"mesh.n=10", "material.vertex_mass=1", "material.bend=spring", NULL};
  const double dt = 1.0 / 30;
  cb_scene *s = scene_with_matrix(sets, 0.3, 1 / (dt * dt), CB_DEF_DROP, 1);
  cb_lanczos_params p = cb_lanczos_params_default();
  eig_check c = lanczos_vs_dense(&s->sys.A, NULL, &p, "A = M/dt^2 + H");
  cr_expect(c.emin >= 900 - 1e-9, "drop: lambda_min(A) >= m/dt^2, got %.12g", c.emin);
  cb_scene_free(s);
}

Test(eigen, lanczos_extremes_of_the_jacobi_scaled_matrix, .init = setup) {
  const char *sets[] = {"mesh.n=9", "mesh.m=7", "mesh.diagonal=alternating", "material.density=2", NULL};
  const double dt = 1.0 / 30;
  cb_scene *s = scene_with_matrix(sets, 0.2, 1 / (dt * dt), CB_DEF_DROP, 2);
  double *d = diag_scaling(&s->sys.A);
  cb_lanczos_params p = cb_lanczos_params_default();
  eig_check c = lanczos_vs_dense(&s->sys.A, d, &p, "D^-1/2 A D^-1/2");
  /* the scaled matrix has unit diagonal, so its spectrum straddles 1 */
  cr_expect(c.emin < 1 && c.emax > 1);
  free(d);
  cb_scene_free(s);
}

Test(eigen, lanczos_explicit_stability_limit, .init = setup) {
  /* M^-1/2 H M^-1/2 with lumped masses: lambda_max = omega_max^2 */
  const char *sets[] = {"mesh.n=8", "material.density=0.5", "scene.pins=top-edge", NULL};
  cb_scene *s = scene_with_matrix(sets, 0.1, 0.0, CB_DEF_DROP, 3);
  double *d = malloc((size_t)s->sys.A.n * sizeof(double));
  cr_assert(d);
  for (int v = 0; v < s->mesh.nv; v++)
    if (s->free_index[v] >= 0)
      for (int a = 0; a < 3; a++) d[3 * s->free_index[v] + a] = 1 / sqrt(s->mass[v]);
  cb_lanczos_params p = cb_lanczos_params_default();
  eig_check c = lanczos_vs_dense(&s->sys.A, d, &p, "M^-1/2 H M^-1/2");
  cr_expect(c.emin >= -1e-9 * c.emax, "pinned, drop: H is PSD");
  cr_log_info("explicit stability limit 2/omega_max = %.6g s\n", 2 / sqrt(c.lmax));
  free(d);
  cb_scene_free(s);
}

Test(eigen, lanczos_on_an_indefinite_matrix, .init = setup) {
  const char *sets[] = {"mesh.n=8", "material.vertex_mass=1", "scene.initial_scale=0.6", NULL};
  cb_scene *s = scene_with_matrix(sets, 0.02, 1.0, CB_DEF_NONE, 4);
  cb_lanczos_params p = cb_lanczos_params_default();
  eig_check c = lanczos_vs_dense(&s->sys.A, NULL, &p, "compressed, exact Hessian");
  cr_expect(c.emin < 0, "the compressed exact Newton matrix should be indefinite (lambda_min %.6g)", c.emin);
  cb_scene_free(s);
}

Test(eigen, lanczos_with_fewer_steps_than_unknowns, .init = setup) {
  /* 14x14 cloth: 582 unknowns, Krylov space capped at 300 */
  const char *sets[] = {"mesh.n=14", "material.vertex_mass=1", NULL};
  const double dt = 1.0 / 30;
  cb_scene *s = scene_with_matrix(sets, 0.2, 1 / (dt * dt), CB_DEF_DROP, 5);
  cr_assert_gt(s->sys.A.n, 300);
  cb_lanczos_params p = cb_lanczos_params_default();
  eig_check c = lanczos_vs_dense(&s->sys.A, NULL, &p, "A, n > max_steps");
  cr_expect_lt(c.steps, s->sys.A.n);
  double *d = diag_scaling(&s->sys.A);
  lanczos_vs_dense(&s->sys.A, d, &p, "D^-1/2 A D^-1/2, n > max_steps");
  free(d);
  cb_scene_free(s);
}

Test(eigen, lanczos_reports_not_converged_at_max_steps) {
  const char *sets[] = {"mesh.n=10", "material.vertex_mass=1", NULL};
  cb_scene *s = scene_with_matrix(sets, 0.3, 900, CB_DEF_DROP, 6);
  double *work = malloc((size_t)s->sys.A.n * sizeof(double));
  cr_assert(work);
  cb_scaled_op op = {&s->sys.A, NULL, work};
  cb_lanczos_params p = cb_lanczos_params_default();
  p.max_steps = 5;
  cb_eig_result r;
  cr_assert_eq(cb_lanczos(s->sys.A.n, cb_scaled_op_apply, &op, &p, &r), CB_OK);
  cr_expect_eq(r.status, CB_NOT_CONVERGED, "status %s", cb_status_name(r.status));
  cr_expect_eq(r.steps, 5);
  cr_expect(r.lmin <= r.lmax && isfinite(r.lmin) && isfinite(r.lmax));
  cr_expect(r.res_max > p.tol * fabs(r.lmax) || r.res_min > p.tol * fabs(r.lmax), "not converged but residuals small");
  free(work);
  cb_scene_free(s);
}

Test(eigen, lanczos_is_exact_on_an_invariant_start) {
  /* A = 2.5 I (diagonal blocks only): the first Krylov vector is an eigenvector */
  cb_pattern pat;
  cb_sparse A;
  cr_assert_eq(cb_pattern_init(&pat, 4), CB_OK);
  cr_assert_eq(cb_sparse_from_pattern(&pat, &A), CB_OK);
  cb_pattern_free(&pat);
  for (int j = 0; j < A.n; j++)
    for (int p = A.colp[j]; p < A.colp[j + 1]; p++) A.val[p] = A.rowi[p] == j ? 2.5 : 0.0;
  double work[12];
  cb_scaled_op op = {&A, NULL, work};
  cb_eig_result r;
  cr_assert_eq(cb_lanczos(A.n, cb_scaled_op_apply, &op, NULL, &r), CB_OK);
  cr_expect_eq(r.status, CB_OK);
  cr_expect_eq(r.steps, 1);
  cr_expect(fabs(r.lmin - 2.5) <= 1e-14 && fabs(r.lmax - 2.5) <= 1e-14, "lmin %.17g lmax %.17g", r.lmin, r.lmax);
  cb_sparse_free(&A);
}

Test(eigen, lanczos_is_deterministic_and_seed_independent, .init = setup) {
  const char *sets[] = {"mesh.n=9", "material.vertex_mass=1", NULL};
  cb_scene *s = scene_with_matrix(sets, 0.3, 900, CB_DEF_DROP, 7);
  double *work = malloc((size_t)s->sys.A.n * sizeof(double));
  cr_assert(work);
  cb_scaled_op op = {&s->sys.A, NULL, work};
  cb_lanczos_params p = cb_lanczos_params_default();
  cb_eig_result a, b, c;
  cr_assert_eq(cb_lanczos(s->sys.A.n, cb_scaled_op_apply, &op, &p, &a), CB_OK);
  cr_assert_eq(cb_lanczos(s->sys.A.n, cb_scaled_op_apply, &op, &p, &b), CB_OK);
  cr_expect(a.lmin == b.lmin && a.lmax == b.lmax && a.steps == b.steps, "same seed, different result");
  p.seed = 12345;
  cr_assert_eq(cb_lanczos(s->sys.A.n, cb_scaled_op_apply, &op, &p, &c), CB_OK);
  cr_expect(fabs(c.lmax - a.lmax) <= 1e-6 * fabs(a.lmax) && fabs(c.lmin - a.lmin) <= 1e-6 * fabs(a.lmin),
            "seed changes the answer: %.15g/%.15g vs %.15g/%.15g", c.lmin, c.lmax, a.lmin, a.lmax);
  free(work);
  cb_scene_free(s);
}

Test(eigen, dense_eigenvalues_match_an_independent_gsl_solve, .init = setup) {
  const char *sets[] = {"mesh.n=6", "mesh.m=5", "material.bend=spring", "scene.initial_scale=0.8", NULL};
  cb_scene *s = scene_with_matrix(sets, 0.1, 50, CB_DEF_NONE, 8);
  int n = s->sys.A.n;
  double *d = diag_scaling(&s->sys.A);
  for (int pass = 0; pass < 2; pass++) {
    const double *dd = pass ? d : NULL;
    double *ev = malloc((size_t)n * sizeof(double)), *ref = dense_spectrum(&s->sys.A, dd);
    cr_assert(ev);
    cr_assert_eq(cb_dense_eigenvalues(&s->sys.A, dd, ev), CB_OK);
    double scale = fmax(fabs(ref[0]), fabs(ref[n - 1]));
    for (int i = 0; i < n; i++) {
      cr_expect(fabs(ev[i] - ref[i]) <= 1e-10 * scale, "pass %d eigenvalue %d: %.15g vs %.15g", pass, i, ev[i], ref[i]);
      if (i) cr_expect(ev[i] >= ev[i - 1], "not ascending at %d", i);
    }
    /* trace check, independent of any eigensolver */
    double tr = 0, sum = 0;
    for (int j = 0; j < n; j++) {
      for (int p = s->sys.A.colp[j]; p < s->sys.A.colp[j + 1]; p++)
        if (s->sys.A.rowi[p] == j) tr += s->sys.A.val[p] * (dd ? dd[j] * dd[j] : 1.0);
      sum += ev[j];
    }
    cr_expect(fabs(tr - sum) <= 1e-10 * fabs(tr), "trace %.15g vs sum of eigenvalues %.15g", tr, sum);
    free(ev);
    free(ref);
  }
  free(d);
  cb_scene_free(s);
}

/* Issue 21, defect 3: GSL's symmetric QR sweeps never deflated a matrix of
 * entries near 1e-300 (the deflation bound underflows) and looped for ever in
 * cb_projection_apply and cb_dense_eigenvalues. The shared prescale makes the
 * eigenvalues scale with the matrix, from 1e-300 to 1e300, in bounded time. */
static void rotated_diagonal(double s, double *H) { /* Q diag(3, -1, 2, 0.5) Q^T, times s */
  const double lam[4] = {3, -1, 2, 0.5};
  double Q[16] = {0};
  for (int i = 0; i < 4; i++) Q[5 * i] = 1;
  const double c = cos(0.7), sn = sin(0.7), c2 = cos(1.9), s2 = sin(1.9);
  double G[16], R[16] = {c, -sn, 0, 0, sn, c, 0, 0, 0, 0, c2, -s2, 0, 0, s2, c2};
  double P[16] = {1, 0, 0, 0, 0, c2, 0, -s2, 0, 0, 1, 0, 0, s2, 0, c2};
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      G[4 * i + j] = 0;
      for (int k = 0; k < 4; k++) G[4 * i + j] += R[4 * i + k] * P[4 * k + j];
    }
  memcpy(Q, G, sizeof Q);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      H[4 * i + j] = 0;
      for (int k = 0; k < 4; k++) H[4 * i + j] += s * Q[4 * i + k] * lam[k] * Q[4 * j + k];
    }
}

Test(eigen, prescale_keeps_tiny_and_huge_matrices_solvable, .init = setup, .timeout = 20) {
  cb_projection_work *w;
  cr_assert_eq(cb_projection_work_alloc(4, &w), CB_OK);
  double ref[16];
  rotated_diagonal(1.0, ref);
  cr_assert_eq(cb_projection_apply(CB_PROJ_CLAMP, 4, ref, w), 1, "one negative eigenvalue at scale 1");
  const double scales[] = {1e-300, 1e-310, 1e-200, 1e300};
  for (int t = 0; t < 4; t++) {
    double s = scales[t], H[16];
    rotated_diagonal(s, H);
    double A[16];
    memcpy(A, H, sizeof A);
    double f = cb_eigen_prescale(A, 4, 4), amax = 0;
    for (int i = 0; i < 16; i++) amax = fmax(amax, fabs(A[i]));
    cr_expect(amax >= 0.5 && amax < 1, "scale %g: largest entry %g after the prescale", s, amax);
    cr_expect(f > 0 && fabs(f * amax) > 0, "scale %g: factor %g", s, f);
    cr_assert_eq(cb_projection_apply(CB_PROJ_CLAMP, 4, H, w), 1, "scale %g: the negative eigenvalue is not found", s);
    for (int i = 0; i < 16; i++) /* 1e-310 is subnormal: only ~14 significant bits are left */
      cr_expect(fabs(H[i] / s - ref[i]) <= (s < 1e-307 ? 1e-3 : 1e-10) * 3, "scale %g entry %d: %.10g vs %.10g", s, i,
                H[i] / s, ref[i]);
  }
  cb_projection_work_free(w);
  double z[16] = {0};
  cr_expect_eq(cb_eigen_prescale(z, 4, 4), 1.0, "a zero matrix is left as it is");
}

/* The 9 x 9 element Hessian of a fem triangle at material.stretch_k = 1e-300
 * (entries near 2^-997 and subnormal ones), on which gsl_eigen_symmv looped
 * for ever before the prescale (issue 21, defect 3). */
Test(eigen, projection_of_a_subnormal_fem_hessian_terminates, .init = setup, .timeout = 20) {
  double H[81] = {0x1.56e1fc2f8f35ap-997,
                  -0x0p+0,
                  0x0.0000000bc95e4p-1022,
                  -0x1.56e1fc2f8f359p-997,
                  0x0p+0,
                  -0x0.000000078024cp-1022,
                  -0x0.00000016806e2p-1022,
                  0x0p+0,
                  -0x0.0000000449399p-1022,
                  -0x0p+0,
                  0x0p+0,
                  -0x0p+0,
                  0x0p+0,
                  0x0.0000001bdbf62p-1022,
                  0x0p+0,
                  0x0p+0,
                  -0x0.000000156e1fcp-1022,
                  0x0p+0,
                  0x0.0000000bc95e4p-1022,
                  -0x0p+0,
                  0x1.56e1fc2f8f35ap-998,
                  0x1.56e1fc2f8f359p-998,
                  0x0p+0,
                  -0x1.56e1fc2f8f359p-998,
                  -0x1.56e1fc2f8f35ap-998,
                  0x0p+0,
                  -0x0.0000001f12e14p-1022,
                  -0x1.56e1fc2f8f359p-997,
                  0x0p+0,
                  0x1.56e1fc2f8f359p-998,
                  0x1.01297d23ab683p-996,
                  0x0p+0,
                  -0x1.56e1fc2f8f35ap-998,
                  -0x1.56e1fc2f8f358p-998,
                  0x0p+0,
                  -0x0.0000000336eb3p-1022,
                  0x0p+0,
                  0x0.0000001bdbf62p-1022,
                  0x0p+0,
                  0x0p+0,
                  -0x0.000000449398dp-1022,
                  0x0p+0,
                  0x0p+0,
                  0x0.0000001bdbf62p-1022,
                  0x0p+0,
                  -0x0.000000078024cp-1022,
                  0x0p+0,
                  -0x1.56e1fc2f8f359p-998,
                  -0x1.56e1fc2f8f35ap-998,
                  0x0p+0,
                  0x1.01297d23ab684p-996,
                  0x1.56e1fc2f8f35ap-998,
                  0x0p+0,
                  -0x1.56e1fc2f8f35ap-997,
                  -0x0.00000016806e2p-1022,
                  0x0p+0,
                  -0x1.56e1fc2f8f35ap-998,
                  -0x1.56e1fc2f8f358p-998,
                  0x0p+0,
                  0x1.56e1fc2f8f35ap-998,
                  0x1.56e1fc2f8f35ap-998,
                  0x0p+0,
                  0x0.0000000336eb2p-1022,
                  0x0p+0,
                  -0x0.000000156e1fcp-1022,
                  0x0p+0,
                  0x0p+0,
                  0x0.0000001bdbf62p-1022,
                  0x0p+0,
                  0x0p+0,
                  0x0p+0,
                  0x0p+0,
                  -0x0.0000000449399p-1022,
                  0x0p+0,
                  -0x0.0000001f12e14p-1022,
                  -0x0.0000000336eb3p-1022,
                  0x0p+0,
                  -0x1.56e1fc2f8f35ap-997,
                  0x0.0000000336eb2p-1022,
                  0x0p+0,
                  0x1.56e1fc2f8f35ap-997};
  cb_projection_work *w;
  cr_assert_eq(cb_projection_work_alloc(9, &w), CB_OK);
  double H0[81];
  memcpy(H0, H, sizeof H);
  int changed = cb_projection_apply(CB_PROJ_CLAMP, 9, H, w);
  cr_expect_geq(changed, 0, "projection failed: %s", cb_error_message());
  double amax = 0, dmax = 0;
  for (int i = 0; i < 81; i++) {
    cr_expect(isfinite(H[i]), "entry %d is %g", i, H[i]);
    amax = fmax(amax, fabs(H0[i]));
    dmax = fmax(dmax, fabs(H[i] - H0[i]));
  }
  cr_expect(dmax <= 1e-12 * amax, "a PSD element Hessian changed by %g (largest entry %g)", dmax, amax);
  cb_projection_work_free(w);
}
