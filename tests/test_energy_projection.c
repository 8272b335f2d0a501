/* The shared element-Hessian projection (projection.c) and its link to the
 * definiteness policies.
 *
 * Expected matrices are built here from a chosen spectrum: H = Q diag(lambda)
 * Q^T with Q a product of Householder reflections of random vectors, so
 * clamp(H) = Q diag(max(lambda, 0)) Q^T and abs(H) = Q diag(|lambda|) Q^T
 * are known without any eigensolver. The spring's closed form (drop, mirror)
 * is compared with the generic projection of its exact 6x6 element. */
#include <criterion/criterion.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"
#include "support.h"

/* Q = product of 3 Householder reflections I - 2 v v^T / (v^T v), row-major n x n. */
static void random_orthogonal(int n, uint64_t seed0, double *Q) {
  cb_rng seed = cb_rng_raw(seed0);
  double *v = malloc((size_t)n * sizeof(double)), *R = malloc((size_t)n * n * sizeof(double));
  cr_assert(v && R);
  for (int i = 0; i < n * n; i++) Q[i] = (i % (n + 1)) == 0;
  for (int h = 0; h < 3; h++) {
    double vv = 0;
    for (int i = 0; i < n; i++) {
      v[i] = 2 * cb_rng_uniform(&seed) - 1;
      vv += v[i] * v[i];
    }
    for (int i = 0; i < n; i++) /* R = Q (I - 2 v v^T / vv) */
      for (int j = 0; j < n; j++) {
        double qv = 0;
        for (int k = 0; k < n; k++) qv += Q[n * i + k] * v[k];
        R[n * i + j] = Q[n * i + j] - 2 * qv * v[j] / vv;
      }
    memcpy(Q, R, (size_t)n * n * sizeof(double));
  }
  free(v);
  free(R);
}

/* H = Q diag(f(lambda)) Q^T, f: 0 identity, 1 clamp, 2 abs. */
static void compose(int n, const double *Q, const double *lambda, int f, double *H) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      double s = 0;
      for (int k = 0; k < n; k++) {
        double l = f == 1 ? fmax(lambda[k], 0) : f == 2 ? fabs(lambda[k]) : lambda[k];
        s += Q[n * i + k] * l * Q[n * j + k];
      }
      H[n * i + j] = s;
    }
  for (int i = 0; i < n; i++) /* exactly symmetric, as an assembled element is */
    for (int j = 0; j < i; j++) H[n * j + i] = H[n * i + j];
}

Test(projection, clamp_and_abs_match_the_chosen_spectrum) {
  static const int sizes[] = {3, 6, 9, 12};
  for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
    int n = sizes[s];
    double Q[144], lambda[12], H[144], P[144], E[144];
    random_orthogonal(n, 11 + s, Q);
    cb_rng seed = cb_rng_raw(100 + s);
    int neg = 0;
    for (int k = 0; k < n; k++) { /* eigenvalues in [-50, 100], every third one negative */
      lambda[k] = k % 3 == 1 ? -(1 + 49 * cb_rng_uniform(&seed)) : 1 + 99 * cb_rng_uniform(&seed);
      neg += lambda[k] < 0;
    }
    compose(n, Q, lambda, 0, H);
    cb_projection_work *w;
    cr_assert_eq(cb_projection_work_alloc(n, &w), CB_OK);
    for (int f = 1; f <= 2; f++) {
      memcpy(P, H, (size_t)n * n * sizeof(double));
      int changed = cb_projection_apply(f == 1 ? CB_PROJ_CLAMP : CB_PROJ_ABS, n, P, w);
      cr_expect_eq(changed, neg, "n = %d: %d eigenvalues changed, %d negative", n, changed, neg);
      compose(n, Q, lambda, f, E);
      double err = 0;
      for (int i = 0; i < n * n; i++) err = fmax(err, fabs(P[i] - E[i]));
      cr_expect(err <= 1e-12 * 100, "n = %d, %s: |P(H) - expected| = %.3g", n, cb_projection_names[f], err);
      for (int i = 0; i < n; i++)
        for (int j = 0; j < i; j++) cr_expect_eq(P[n * i + j], P[n * j + i], "P(H) symmetric");
    }
    memcpy(P, H, (size_t)n * n * sizeof(double));
    cr_expect_eq(cb_projection_apply(CB_PROJ_NONE, n, P, w), 0);
    cr_expect_eq(memcmp(P, H, (size_t)n * n * sizeof(double)), 0, "none leaves H untouched");
    cb_projection_work_free(w);
  }
}

Test(projection, psd_matrix_is_left_bit_for_bit) {
  int n = 6;
  double Q[36], lambda[6] = {0.5, 3, 7, 11, 2e3, 1e4}, H[36], P[36];
  random_orthogonal(n, 7, Q);
  compose(n, Q, lambda, 0, H);
  cb_projection_work *w;
  cr_assert_eq(cb_projection_work_alloc(n, &w), CB_OK);
  for (int p = CB_PROJ_CLAMP; p <= CB_PROJ_ABS; p++) {
    memcpy(P, H, sizeof P);
    cr_expect_eq(cb_projection_apply((cb_projection)p, n, P, w), 0);
    cr_expect_eq(memcmp(P, H, sizeof P), 0, "%s changed an SPD matrix", cb_projection_names[p]);
  }
  cr_expect_lt(cb_projection_apply(CB_PROJ_CLAMP, 5, P, w), 0, "a workspace serves one size");
  cb_projection_work_free(w);
  cb_projection_work_free(NULL);
  cr_expect_lt(cb_projection_work_alloc(0, &w), 0);
}

Test(projection, eigenvalue_map_and_policy_mapping) {
  cr_expect_eq(cb_projection_eigenvalue(CB_PROJ_NONE, -3.5), -3.5);
  cr_expect_eq(cb_projection_eigenvalue(CB_PROJ_CLAMP, -3.5), 0.0);
  cr_expect_eq(cb_projection_eigenvalue(CB_PROJ_CLAMP, 2.25), 2.25);
  cr_expect_eq(cb_projection_eigenvalue(CB_PROJ_ABS, -3.5), 3.5);
  cr_expect_eq(cb_projection_eigenvalue(CB_PROJ_ABS, 2.25), 2.25);
  cr_expect_eq(cb_definiteness_projection(CB_DEF_NONE), CB_PROJ_NONE);
  cr_expect_eq(cb_definiteness_projection(CB_DEF_DROP), CB_PROJ_CLAMP);
  cr_expect_eq(cb_definiteness_projection(CB_DEF_MIRROR), CB_PROJ_ABS);
  cr_expect_eq(cb_definiteness_projection(CB_DEF_SHIFT), CB_PROJ_NONE, "shift shifts A in the solve");
  cr_expect_eq(cb_definiteness_projection(CB_DEF_CHOI_KO), CB_PROJ_NONE, "choi-ko is exact for its model");
  int n = 0;
  while (cb_projection_names[n]) n++;
  cr_expect_eq(n, CB_PROJ_COUNT);
}

/* One free spring (2-vertex chain, nothing pinned): the assembled matrix is
 * its 6x6 element. drop and mirror in closed form must equal the generic
 * projection of the exact element, compressed or stretched. */
Test(projection, spring_closed_form_equals_the_generic_projection) {
  const char *sets[] = {"mesh.type=chain",
                        "mesh.n=2",
                        "mesh.size=1",
                        "material.vertex_mass=1",
                        "scene.pins=none",
                        "scene.gravity=0 0 0",
                        "integrator.definiteness=none",
                        NULL};
  cb_scene *s = test_scene(sets);
  cr_assert_eq(s->sys.A.n, 6);
  cb_projection_work *w;
  cr_assert_eq(cb_projection_work_alloc(6, &w), CB_OK);
  static const double lengths[] = {0.3, 0.7, 0.99, 1.0, 1.4};
  static const double u[3] = {0.48, -0.6, 0.64}; /* unit */
  for (size_t c = 0; c < sizeof lengths / sizeof lengths[0]; c++) {
    double x[6];
    for (int a = 0; a < 3; a++) {
      x[a] = 0.3;
      x[3 + a] = 0.3 + lengths[c] * u[a];
    }
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
    gsl_matrix *Hx = test_dense(&s->sys.A);
    for (int d = CB_DEF_DROP; d <= CB_DEF_MIRROR; d++) {
      double P[36];
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) P[6 * i + j] = gsl_matrix_get(Hx, (size_t)i, (size_t)j);
      int changed = cb_projection_apply(cb_definiteness_projection((cb_definiteness)d), 6, P, w);
      cr_expect_eq(changed, lengths[c] < 1.0 ? 2 : 0, "l = %g: the transverse pair is the negative one", lengths[c]);
      cb_system_assemble(&s->sys, x, 0.0, (cb_definiteness)d, 0.0);
      gsl_matrix *Hd = test_dense(&s->sys.A);
      double err = 0;
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) err = fmax(err, fabs(P[6 * i + j] - gsl_matrix_get(Hd, (size_t)i, (size_t)j)));
      cr_expect(err <= 1e-12 * 8000 * 2, "l = %g, %s: closed form - projection = %.3g", lengths[c],
                cb_definiteness_names[d], err);
      gsl_matrix_free(Hd);
    }
    gsl_matrix_free(Hx);
  }
  cb_projection_work_free(w);
  cb_scene_free(s);
}
