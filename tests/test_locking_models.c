/* The models of issue 12: the polar decomposition (against GSL's SVD on
 * random matrices, and its degenerate cases), co-rotational FEM (rigid
 * invariance, the frozen Hessian against the lecture's matrix, the gradient
 * equal to the frozen-R force, degenerate triangles) and the shape-matching
 * integrator (a rigid body stays rigid; momentum is conserved). The FD checks
 * of FEM's energy, gradient and exact Hessian are in test_energy_conformance.c
 * (the registry runs them on `fem` and `fem_frozen`). */
#include <criterion/criterion.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/polar.h>
#include "rng.h"
#include "support.h"

/* ---- polar decomposition ------------------------------------------------------- */

Test(polar, matches_gsl_svd_on_random_3x2_and_3x3) {
  cb_rng seed = cb_rng_raw(12);
  for (int trial = 0; trial < 200; trial++) {
    double F[6], A[9], R[9], sg[3];
    for (int i = 0; i < 6; i++) F[i] = 2 * cb_rng_uniform(&seed) - 1;
    for (int i = 0; i < 9; i++) A[i] = 2 * cb_rng_uniform(&seed) - 1;
    /* 3x2: R = U V^T from an independent GSL SVD */
    gsl_matrix *U = gsl_matrix_alloc(3, 2), *V = gsl_matrix_alloc(2, 2);
    gsl_vector *S = gsl_vector_alloc(2), *w = gsl_vector_alloc(2);
    for (int i = 0; i < 6; i++) gsl_matrix_set(U, (size_t)(i / 2), (size_t)(i % 2), F[i]);
    cr_assert_eq(gsl_linalg_SV_decomp(U, V, S, w), 0);
    cr_assert_eq(cb_polar32(F, R, sg), 0u);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 2; c++) {
        double want = 0;
        for (int k = 0; k < 2; k++)
          want += gsl_matrix_get(U, (size_t)r, (size_t)k) * gsl_matrix_get(V, (size_t)c, (size_t)k);
        cr_expect(fabs(R[2 * r + c] - want) < 1e-12, "3x2 trial %d: R(%d,%d) = %g, GSL %g", trial, r, c, R[2 * r + c],
                  want);
      }
    cr_expect(fabs(sg[0] - gsl_vector_get(S, 0)) < 1e-12 && fabs(sg[1] - gsl_vector_get(S, 1)) < 1e-12);
    gsl_matrix_free(U);
    gsl_matrix_free(V);
    gsl_vector_free(S);
    gsl_vector_free(w);
    /* 3x3: R = U diag(1, 1, sign det) V^T */
    gsl_matrix *U3 = gsl_matrix_alloc(3, 3), *V3 = gsl_matrix_alloc(3, 3);
    gsl_vector *S3 = gsl_vector_alloc(3), *w3 = gsl_vector_alloc(3);
    for (int i = 0; i < 9; i++) gsl_matrix_set(U3, (size_t)(i / 3), (size_t)(i % 3), A[i]);
    double det =
        A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) + A[2] * (A[3] * A[7] - A[4] * A[6]);
    cr_assert_eq(gsl_linalg_SV_decomp(U3, V3, S3, w3), 0);
    unsigned fl = cb_polar33(A, R, sg);
    cr_expect_eq((fl & CB_POLAR_REFLECTED) != 0, det < 0, "trial %d: det %g, flags %u", trial, det, fl);
    double d = det < 0 ? -1 : 1;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        double want = 0;
        for (int k = 0; k < 3; k++)
          want +=
              (k == 2 ? d : 1) * gsl_matrix_get(U3, (size_t)r, (size_t)k) * gsl_matrix_get(V3, (size_t)c, (size_t)k);
        cr_expect(fabs(R[3 * r + c] - want) < 1e-11, "3x3 trial %d: R(%d,%d) = %g, GSL %g", trial, r, c, R[3 * r + c],
                  want);
      }
    double dR =
        R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]);
    cr_expect(fabs(dR - 1) < 1e-12, "det R = %g", dR);
    gsl_matrix_free(U3);
    gsl_matrix_free(V3);
    gsl_vector_free(S3);
    gsl_vector_free(w3);
  }
}

Test(polar, degenerate_inputs_give_finite_orthonormal_rotations) {
  double R[9], sg[3];
  const double zero32[6] = {0}, seg[6] = {1, 2, 0.5, 1, -1, -2}; /* rank 1: second column = 2 x the first */
  cr_expect_eq(cb_polar32(zero32, R, sg), (unsigned)CB_POLAR_RANK_DEFICIENT);
  cr_expect(R[0] == 1 && R[3] == 1 && R[1] == 0 && R[2] == 0 && R[4] == 0 && R[5] == 0);
  cr_expect_eq(cb_polar32(seg, R, sg), (unsigned)CB_POLAR_RANK_DEFICIENT);
  double c00 = R[0] * R[0] + R[2] * R[2] + R[4] * R[4], c11 = R[1] * R[1] + R[3] * R[3] + R[5] * R[5],
         c01 = R[0] * R[1] + R[2] * R[3] + R[4] * R[5];
  cr_expect(fabs(c00 - 1) < 1e-12 && fabs(c11 - 1) < 1e-12 && fabs(c01) < 1e-12, "R^T R = [%g %g; . %g]", c00, c01,
            c11);
  double nanF[6] = {NAN, 0, 0, 1, 0, 0};
  cb_polar32(nanF, R, sg);
  for (int i = 0; i < 6; i++) cr_expect(isfinite(R[i]));
  /* 3x3: zero, rank 1 and rank 2 (a planar cluster) */
  const double zero33[9] = {0}, rank1[9] = {1, 2, 3, 2, 4, 6, -1, -2, -3}, rank2[9] = {1, 0, 0, 0, 0, 1, 0, 0, 0};
  const double *cases[3] = {zero33, rank1, rank2};
  for (int k = 0; k < 3; k++) {
    cr_expect(cb_polar33(cases[k], R, sg) & CB_POLAR_RANK_DEFICIENT, "case %d", k);
    double dR =
        R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]);
    cr_expect(fabs(dR - 1) < 1e-12, "case %d: det R = %g", k, dR);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) {
        double s = R[a] * R[b] + R[3 + a] * R[3 + b] + R[6 + a] * R[6 + b];
        cr_expect(fabs(s - (a == b)) < 1e-12, "case %d: R^T R (%d,%d) = %g", k, a, b, s);
      }
  }
  /* rank 2: A e_x = e_x and A e_z = e_y, so R does the same (and e_y -> -e_z) */
  cb_polar33(rank2, R, sg);
  cr_expect(fabs(R[0] - 1) < 1e-12 && fabs(R[5] - 1) < 1e-12 && fabs(R[7] + 1) < 1e-12,
            "R = [%g %g %g; %g %g %g; %g %g %g]", R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8]);
}

/* ---- co-rotational FEM ------------------------------------------------------------ */

typedef struct {
  cb_mesh mesh;
  cb_topology topo;
  double mass[3];
  int free_index[3];
  cb_model model;
} one_triangle;

/* Right isosceles triangle, legs h along x and y, right angle at vertex 0. */
static void triangle(one_triangle *t, double h, int pin0) {
  memset(t, 0, sizeof *t);
  t->mesh.nv = 3;
  t->mesh.nt = 1;
  t->mesh.x = calloc(9, sizeof(double));
  t->mesh.tri = malloc(3 * sizeof(int));
  t->mesh.x[3] = h;
  t->mesh.x[7] = h;
  for (int i = 0; i < 3; i++) {
    t->mesh.tri[i] = i;
    t->mass[i] = 1;
  }
  cr_assert_eq(cb_topology_build(&t->mesh, &t->topo), CB_OK);
  int nf = 0;
  for (int i = 0; i < 3; i++) t->free_index[i] = (pin0 && i == 0) ? -1 : nf++;
  t->model = (cb_model){&t->mesh, &t->topo, t->mass, t->free_index, nf};
}
static void triangle_free(one_triangle *t) {
  cb_mesh_free(&t->mesh);
  cb_topology_free(&t->topo);
}

Test(fem, energy_is_zero_under_rigid_motions_and_the_gradient_is_the_frozen_R_force) {
  one_triangle t;
  triangle(&t, 0.3, 0);
  cb_term *f = NULL;
  cr_assert_eq(cb_fem_term_alloc(&t.model, "stretch", 700.0, CB_FEM_EXACT, &f), CB_OK);
  cb_rng seed = cb_rng_raw(5);
  for (int trial = 0; trial < 20; trial++) {
    /* a random rotation (GSL QR-free: Rodrigues about a random axis) and translation */
    double ax[3] = {cb_rng_uniform(&seed) - 0.5, cb_rng_uniform(&seed) - 0.5, cb_rng_uniform(&seed) - 0.5}, n = 0,
           th = 6 * cb_rng_uniform(&seed);
    for (int a = 0; a < 3; a++) n += ax[a] * ax[a];
    n = sqrt(n);
    for (int a = 0; a < 3; a++) ax[a] /= n;
    double K[9] = {0, -ax[2], ax[1], ax[2], 0, -ax[0], -ax[1], ax[0], 0}, Q[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double kk = 0;
        for (int k = 0; k < 3; k++) kk += K[3 * i + k] * K[3 * k + j];
        Q[3 * i + j] = (i == j) + sin(th) * K[3 * i + j] + (1 - cos(th)) * kk;
      }
    double x[9], g[9] = {0}, tr[3] = {cb_rng_uniform(&seed), cb_rng_uniform(&seed), cb_rng_uniform(&seed)};
    for (int v = 0; v < 3; v++)
      for (int a = 0; a < 3; a++)
        x[3 * v + a] = tr[a] + Q[3 * a] * t.mesh.x[3 * v] + Q[3 * a + 1] * t.mesh.x[3 * v + 1] +
                       Q[3 * a + 2] * t.mesh.x[3 * v + 2];
    double E = f->type->energy(f, x, g);
    cr_expect(fabs(E) < 1e-20, "trial %d: E = %g under a rigid motion", trial, E);
    for (int i = 0; i < 9; i++) cr_expect(fabs(g[i]) < 1e-9, "trial %d: grad %d = %g", trial, i, g[i]);
    /* deform, then compare with the lecture's force: f_1 = -mu (x1 - x0 - R(r1 - r0)) etc. (D_m = h I) */
    for (int i = 0; i < 9; i++) x[i] += 0.05 * (2 * cb_rng_uniform(&seed) - 1);
    memset(g, 0, sizeof g);
    f->type->energy(f, x, g);
    double h = 0.3, F[6], R[6];
    for (int r = 0; r < 3; r++) {
      F[2 * r] = (x[3 + r] - x[r]) / h;
      F[2 * r + 1] = (x[6 + r] - x[r]) / h;
    }
    cb_polar32(F, R, NULL);
    for (int r = 0; r < 3; r++) {
      double f1 = -700.0 * (x[3 + r] - x[r] - R[2 * r] * h), f2 = -700.0 * (x[6 + r] - x[r] - R[2 * r + 1] * h);
      cr_expect(fabs(-g[3 + r] - f1) < 1e-9 && fabs(-g[6 + r] - f2) < 1e-9 && fabs(-g[r] + f1 + f2) < 1e-9,
                "trial %d: FEM force differs from the frozen-R force", trial);
    }
  }
  cb_term_free(f);
  triangle_free(&t);
}

Test(fem, frozen_hessian_is_the_lectures_matrix) {
  one_triangle t;
  triangle(&t, 0.25, 0);
  cb_term *f = NULL;
  cr_assert_eq(cb_fem_term_alloc(&t.model, "stretch", 300.0, CB_FEM_FROZEN, &f), CB_OK);
  cr_expect(f->type->flags & CB_TERM_CONSTANT_HESSIAN);
  cb_system sys;
  cr_assert_eq(cb_system_init(&sys, &t.model, &f, 1), CB_OK);
  double x[9] = {0.1, 0.2, -0.3, 0.5, 0.1, 0.2, -0.1, 0.4, 0.3}; /* any x: the matrix is constant */
  cb_system_assemble(&sys, x, 0.0, CB_DEF_NONE, 0.0);
  gsl_matrix *H = test_dense(&sys.A);
  static const double L[3][3] = {{2, -1, -1}, {-1, 1, 0}, {-1, 0, 1}}; /* the slide's matrix, times mu */
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
          cr_expect(fabs(gsl_matrix_get(H, (size_t)(3 * a + r), (size_t)(3 * b + c)) - 300.0 * L[a][b] * (r == c)) <
                        1e-9,
                    "block (%d,%d) entry (%d,%d) = %g", a, b, r, c,
                    gsl_matrix_get(H, (size_t)(3 * a + r), (size_t)(3 * b + c)));
  gsl_matrix_free(H);
  cb_system_free(&sys);
  triangle_free(&t);
}

Test(fem, degenerate_triangles_are_counted_and_stay_finite) {
  one_triangle t;
  triangle(&t, 0.3, 0);
  cb_term *f = NULL;
  cr_assert_eq(cb_fem_term_alloc(&t.model, "stretch", 500.0, CB_FEM_EXACT, &f), CB_OK);
  cb_system sys;
  cr_assert_eq(cb_system_init(&sys, &t.model, &f, 1), CB_OK);
  double collinear[9] = {0, 0, 0, 0.3, 0, 0, 0.6, 0, 0}, point[9] = {0}, inverted[9] = {0, 0, 0, 0.3, 0, 0, 0, -0.3, 0};
  const double *xs[3] = {collinear, point, inverted};
  for (int k = 0; k < 3; k++) {
    int nt;
    int bad = cb_fem_term_degenerate(f, xs[k], &nt);
    cr_expect_eq(nt, 1);
    cr_expect_eq(bad, k < 2 ? 1 : 0, "case %d: %d degenerate", k, bad); /* a flipped triangle is a rotated one */
    double g[9] = {0};
    double E = cb_system_energy(&sys, xs[k], g, NULL);
    cr_expect(isfinite(E), "case %d: E = %g", k, E);
    for (int i = 0; i < 9; i++) cr_expect(isfinite(g[i]), "case %d: grad NaN", k);
    cb_system_assemble(&sys, xs[k], 0.0, CB_DEF_DROP, 0.0);
    for (int i = 0; i < sys.A.nnz; i++) cr_expect(isfinite(sys.A.val[i]), "case %d: Hessian NaN", k);
  }
  /* a flipped triangle in its plane has zero energy: a 180 degree turn about the x axis */
  cr_expect(fabs(cb_system_energy(&sys, inverted, NULL, NULL)) < 1e-20);
  /* the point: sum (sigma - 1)^2 = 2, E = 2 mu A */
  cr_expect(fabs(cb_system_energy(&sys, point, NULL, NULL) - 2 * 500.0 * 0.045) < 1e-12);
  cb_system_free(&sys);
  triangle_free(&t);
  /* a zero-area rest triangle is rejected */
  triangle(&t, 0.3, 0);
  t.mesh.x[7] = 0;
  t.mesh.x[6] = 0.6;
  cr_expect_neq(cb_fem_term_alloc(&t.model, "stretch", 500.0, CB_FEM_EXACT, &f), CB_OK);
  cr_expect(strstr(cb_error_message(), "zero rest area"));
  triangle_free(&t);
}

Test(fem, scene_builds_fem_from_material_stretch) {
  const char *sets[] = {"mesh.n=5", "material.stretch=fem", "material.fem_hessian=frozen", NULL};
  cb_scene *s = test_scene(sets);
  cr_expect(cb_term_type_find("fem_frozen") == s->sys.terms[0]->type);
  cb_scene_free(s);
  const char *chain[] = {"mesh.type=chain", "mesh.n=4", "material.vertex_mass=1", "material.stretch=fem", NULL};
  cb_config c;
  test_config(&c, chain);
  cr_expect_neq(cb_scene_from_config(&c, &s), CB_OK);
  cr_expect(strstr(cb_error_message(), "material.stretch"), "%s", cb_error_message());
}

/* ---- shape matching ------------------------------------------------------------------- */

static void momenta(const cb_scene *s, const double *x, const double *v, double P[3], double L[3]) {
  for (int a = 0; a < 3; a++) P[a] = L[a] = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    const double *p = x + 3 * i, *u = v + 3 * i;
    double m = s->mass[i];
    for (int a = 0; a < 3; a++) P[a] += m * u[a];
    L[0] += m * (p[1] * u[2] - p[2] * u[1]);
    L[1] += m * (p[2] * u[0] - p[0] * u[2]);
    L[2] += m * (p[0] * u[1] - p[1] * u[0]);
  }
}

Test(shape_matching, a_rigid_body_stays_rigid_without_external_force) {
  const char *sets[] = {"mesh.n=6",
                        "mesh.size=1",
                        "scene.gravity=0 0 0",
                        "scene.pins=none",
                        "integrator.method=shape_matching",
                        "integrator.shape_alpha=0.7",
                        "integrator.dt=0.01",
                        NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = calloc((size_t)n3, sizeof(double));
  double c = cos(0.8), sn = sin(0.8);
  for (int i = 0; i < s->mesh.nv; i++) { /* rotated about y and moving at a uniform velocity */
    const double *r = s->mesh.x + 3 * i;
    x[3 * i] = c * r[0] + sn * r[2] + 0.3;
    x[3 * i + 1] = r[1] - 0.2;
    x[3 * i + 2] = -sn * r[0] + c * r[2];
    v[3 * i] = 0.5;
    v[3 * i + 1] = -0.25;
    v[3 * i + 2] = 0.1;
  }
  cb_step_stats st;
  for (int k = 0; k < 100; k++) cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
  for (int e = 0; e < s->topo.ne; e++) { /* every edge keeps its rest length */
    int i = s->topo.edge[2 * e], j = s->topo.edge[2 * e + 1];
    double l = 0, L = 0;
    for (int a = 0; a < 3; a++) {
      l += (x[3 * i + a] - x[3 * j + a]) * (x[3 * i + a] - x[3 * j + a]);
      L += (s->mesh.x[3 * i + a] - s->mesh.x[3 * j + a]) * (s->mesh.x[3 * i + a] - s->mesh.x[3 * j + a]);
    }
    cr_expect(fabs(sqrt(l) - sqrt(L)) < 1e-12, "edge %d: %g vs %g", e, sqrt(l), sqrt(L));
  }
  for (int i = 0; i < s->mesh.nv; i++) cr_expect(fabs(v[3 * i] - 0.5) < 1e-12 && fabs(v[3 * i + 1] + 0.25) < 1e-12);
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}

Test(shape_matching, conserves_linear_and_angular_momentum) {
  const char *sets[] = {"mesh.n=7",
                        "mesh.size=1",
                        "scene.gravity=0 0 0",
                        "scene.pins=none",
                        "integrator.method=shape_matching",
                        "integrator.shape_alpha=0.4",
                        "integrator.dt=0.01",
                        "material.density=0.3",
                        NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = malloc((size_t)n3 * sizeof(double));
  cb_rng seed = cb_rng_raw(3);
  for (int i = 0; i < n3; i++) { /* deformed and spinning */
    x[i] = s->mesh.x[i] * (1 + 0.2 * (i % 3 == 0)) + 0.03 * (2 * cb_rng_uniform(&seed) - 1);
    v[i] = 0.5 * (2 * cb_rng_uniform(&seed) - 1);
  }
  double P0[3], L0[3], P[3], L[3];
  momenta(s, x, v, P0, L0);
  cb_step_stats st;
  for (int k = 0; k < 200; k++) cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
  momenta(s, x, v, P, L);
  for (int a = 0; a < 3; a++) {
    cr_expect(fabs(P[a] - P0[a]) < 1e-12, "P[%d]: %.17g -> %.17g", a, P0[a], P[a]);
    cr_expect(fabs(L[a] - L0[a]) < 1e-12, "L[%d]: %.17g -> %.17g", a, L0[a], L[a]);
  }
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}

Test(shape_matching, alpha_out_of_range_is_a_config_error) {
  cb_config c;
  cb_config_defaults(&c);
  cr_expect_neq(cb_config_set(&c, "integrator.shape_alpha=0"), CB_OK);
  cr_expect_neq(cb_config_set(&c, "integrator.shape_alpha=1.5"), CB_OK);
  cr_expect_eq(cb_config_set(&c, "integrator.shape_alpha=0.01"), CB_OK);
}

/* A constant Newton matrix (every Hessian term constant: frozen-R FEM and
 * gravity) is factorised once and reused over iterations and steps at the
 * same dt; a change of dt refactorises; springs factorise every iteration. */
Test(fem, newton_factorises_a_constant_matrix_once) {
  const char *sets[] = {"mesh.n=6",
                        "mesh.size=1",
                        "material.stretch=fem",
                        "material.fem_hessian=frozen",
                        "material.stretch_k=500",
                        "integrator.max_iters=100",
                        "integrator.tol=1e-10",
                        NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = calloc((size_t)n3, sizeof(double));
  memcpy(x, s->x0, (size_t)n3 * sizeof(double));
  int total = 0;
  for (int k = 0; k < 3; k++) {
    cb_step_stats st;
    memset(&st, 0, sizeof st);
    cb_integrator_step(it, x, v, &st);
    cr_expect(st.newton_iters > 1, "step %d: %d iterations", k, st.newton_iters);
    cr_expect_eq(st.factorizations, k == 0 ? 1 : 0, "step %d: %d factorisations", k, st.factorizations);
    total += st.factorizations;
  }
  it->params.dt *= 0.5;
  cb_step_stats st;
  memset(&st, 0, sizeof st);
  cb_integrator_step(it, x, v, &st);
  cr_expect_eq(st.factorizations, 1, "a new dt refactorises");
  cr_expect_eq(total, 1);
  cb_integrator_free(it);
  cb_scene_free(s);
  const char *springs[] = {"mesh.n=6", "mesh.size=1", "material.stretch_k=500", NULL};
  s = test_scene(springs);
  it = test_integrator(springs, s, NULL, NULL);
  memcpy(x, s->x0, (size_t)n3 * sizeof(double));
  memset(v, 0, (size_t)n3 * sizeof(double));
  memset(&st, 0, sizeof st);
  cb_integrator_step(it, x, v, &st);
  cr_expect_eq(st.factorizations, st.newton_iters, "springs: one factorisation per iteration");
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}

/* A run under shape matching is held to kinetic + gravity: the scene's springs,
 * which shape matching does not use, stretch far past the divergence bound on
 * the lab scene, and that is not a divergence. */
Test(shape_matching, a_run_bounds_its_own_energy_not_the_scenes_springs) {
  const char *sets[] = {"mesh.n=11", "material.vertex_mass=1", "integrator.method=shape_matching",
                        "integrator.shape_alpha=0.5", NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  cb_run r;
  cr_assert_eq(cb_run_init(&r, s, it), CB_OK);
  double worst = 0;
  for (int k = 0; k < 60; k++) {
    cr_assert_eq(cb_run_step(&r), CB_OK, "step %d", k);
    worst = fmax(worst, r.elastic);
  }
  cr_expect(worst > r.bound, "the springs' energy %g stays under the bound %g: the test shows nothing", worst, r.bound);
  cb_run_free(&r);
  cb_integrator_free(it);
  cb_scene_free(s);
}

/* Issue 21 defect 5: shape matching skips the scene's energy terms, so with
 * the penalty collider the cloth fell through the sphere while `contacts`
 * counted them. It is refused with the reason and the fix; the project
 * response (after the step) still runs, and keeps the cloth outside. */
Test(shape_matching, refuses_the_penalty_collider_and_honours_project) {
  const char *pen[] = {"mesh.n=6",
                       "mesh.size=1",
                       "mesh.plane=xz",
                       "scene.pins=none",
                       "integrator.method=shape_matching",
                       "integrator.dt=0.01",
                       "collider.type=penalty",
                       "collider.centre=0 -0.6 0",
                       "collider.radius=0.5",
                       NULL};
  cb_config c;
  test_config(&c, pen);
  cb_scene *s = test_scene(pen);
  cb_integrator_params ip;
  cb_integrator_params_from_config(&c, &ip);
  cb_integrator *it = NULL;
  cr_assert_neq(cb_integrator_from_config(&c, s, &ip, &it), CB_OK);
  cr_expect(strstr(cb_error_message(), "penalty collider") && strstr(cb_error_message(), "collider.type = project"),
            "%s", cb_error_message());
  cb_scene_free(s);
  const char *prj[] = {"mesh.n=6",
                       "mesh.size=1",
                       "mesh.plane=xz",
                       "scene.pins=none",
                       "integrator.method=shape_matching",
                       "integrator.dt=0.01",
                       "collider.type=project",
                       "collider.centre=0 -0.6 0",
                       "collider.radius=0.5",
                       NULL};
  s = test_scene(prj);
  it = test_integrator(prj, s, NULL, NULL);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = calloc((size_t)n3, sizeof(double));
  memcpy(x, s->x0, (size_t)n3 * sizeof(double));
  cb_step_stats st;
  for (int k = 0; k < 200; k++)
    cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK); /* 2 s: far through without it */
  double dmin = INFINITY;
  for (int i = 0; i < s->mesh.nv; i++) {
    double d = sqrt(x[3 * i] * x[3 * i] + (x[3 * i + 1] + 0.6) * (x[3 * i + 1] + 0.6) + x[3 * i + 2] * x[3 * i + 2]);
    dmin = fmin(dmin, d);
  }
  cr_expect(dmin > 0.49 && dmin < 0.6, "closest vertex %g m from the centre (radius 0.5)", dmin);
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}
