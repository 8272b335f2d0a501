/* Bending models and the sphere collider (issue 11). Their gradients and
 * Hessians against finite differences come from tests/test_energy_conformance.c
 * (they are registered terms); here:
 *   - the dihedral gradient is parallel to the lecture's u_1..u_4, computed
 *     here from the slide's formulas (Bridson et al. 2003);
 *   - the quadratic energy is 0 on a flat hinge and after rigid motions;
 *   - on a grid bent isometrically onto a cylinder of radius R (axis along a
 *     grid axis, regular diagonals) only the n-2 interior columns of edges
 *     along the axis fold, each by exactly h/R, so the hinge energy is
 *     (n-2)(n-1) 3 h^2/(2 R^2) = 3 (n-2)/(n-1) A/(2 R^2), h = 1/(n-1): its
 *     ratio to the continuous 1/2 int |Delta x|^2 dA = A/(2R^2) tends to 3.
 *     The quadratic energy tends to the same, scales as 1/R^2 and with area;
 *   - `project` leaves no free vertex inside the sphere and corrects the
 *     velocity by (x_new - x)/dt; the penalty term counts its contacts. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/definiteness.h>
#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/material.h>
#include <clothbench/mesh.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include <clothbench/topology.h>
#include <clothbench/collider.h>
#include "rng.h"
#include "vec.h"

#include "support.h"

static const double PI = 3.14159265358979323846;

typedef struct {
  cb_mesh mesh;
  cb_topology topo;
  double *mass;
  int *fi;
  cb_model model;
} tmodel;

static void grid_model(tmodel *t, int n, double size) {
  memset(t, 0, sizeof *t);
  cb_grid_params g = cb_grid_params_default();
  g.n = g.m = n;
  g.size[0] = g.size[1] = size;
  g.plane = CB_PLANE_XY;
  cr_assert_eq(cb_mesh_grid(&g, &t->mesh), CB_OK);
  cr_assert_eq(cb_topology_build(&t->mesh, &t->topo), CB_OK);
  t->mass = malloc((size_t)t->mesh.nv * sizeof *t->mass);
  t->fi = malloc((size_t)t->mesh.nv * sizeof *t->fi);
  for (int i = 0; i < t->mesh.nv; i++) {
    t->mass[i] = 1;
    t->fi[i] = i;
  }
  t->model = (cb_model){&t->mesh, &t->topo, t->mass, t->fi, t->mesh.nv};
}

static void model_free(tmodel *t) {
  cb_topology_free(&t->topo);
  cb_mesh_free(&t->mesh);
  free(t->mass);
  free(t->fi);
}

Test(bending, dihedral_gradient_is_parallel_to_the_lecture_u) {
  tmodel t;
  grid_model(&t, 2, 1.0); /* two triangles, one hinge */
  cr_assert_eq(t.topo.np, 1);
  int v[4];
  cb_hinge_vertices(&t.topo, v);
  cb_term *term;
  cr_assert_eq(cb_hinge_term_alloc(&t.model, "bend", 0.7, &term), CB_OK);
  cb_rng seed = cb_rng_raw(5);
  for (int trial = 0; trial < 20; trial++) {
    double x[12];
    for (int i = 0; i < 12; i++) x[i] = t.mesh.x[i] + 0.25 * (cb_rng_uniform(&seed) - 0.5);
    double g[12] = {0};
    term->type->energy(term, x, g);
    /* the slide's labels: x1, x2 the wings, x3, x4 the edge, E = x4 - x3 */
    const double *x1 = x + 3 * v[2], *x2 = x + 3 * v[3], *x3 = x + 3 * v[0], *x4 = x + 3 * v[1];
    double E[3], a[3], b[3], N1[3], N2[3];
    cb_v3_sub(x4, x3, E);
    cb_v3_sub(x1, x3, a);
    cb_v3_sub(x1, x4, b);
    cb_v3_cross(a, b, N1);
    cb_v3_sub(x2, x4, a);
    cb_v3_sub(x2, x3, b);
    cb_v3_cross(a, b, N2);
    double lE = sqrt(cb_v3_dot(E, E)), n1 = cb_v3_dot(N1, N1), n2 = cb_v3_dot(N2, N2), u[4][3], d14[3], d24[3], d13[3],
           d23[3];
    cb_v3_sub(x1, x4, d14);
    cb_v3_sub(x2, x4, d24);
    cb_v3_sub(x1, x3, d13);
    cb_v3_sub(x2, x3, d23);
    for (int k = 0; k < 3; k++) {
      u[0][k] = lE * N1[k] / n1;
      u[1][k] = lE * N2[k] / n2;
      u[2][k] = cb_v3_dot(d14, E) / lE * N1[k] / n1 + cb_v3_dot(d24, E) / lE * N2[k] / n2;
      u[3][k] = -cb_v3_dot(d13, E) / lE * N1[k] / n1 - cb_v3_dot(d23, E) / lE * N2[k] / n2;
    }
    const int role[4] = {v[2], v[3], v[0], v[1]};
    double lambda = NAN;
    for (int i = 0; i < 4; i++) {
      const double *gi = g + 3 * role[i];
      double c[3];
      cb_v3_cross(gi, u[i], c);
      double gn = sqrt(cb_v3_dot(gi, gi)), un = sqrt(cb_v3_dot(u[i], u[i]));
      cr_expect(sqrt(cb_v3_dot(c, c)) <= 1e-9 * gn * un, "trial %d: grad at u_%d not parallel (|g x u| = %g)", trial,
                i + 1, sqrt(cb_v3_dot(c, c)));
      double l =
          cb_v3_dot(gi, u[i]) / cb_v3_dot(u[i], u[i]); /* grad_i E = lambda u_i, one lambda = k c (theta - theta_bar) */
      if (i == 0) lambda = l;
      else
        cr_expect(fabs(l - lambda) <= 1e-9 * fabs(lambda), "trial %d: u_%d scale %g, u_1 scale %g", trial, i + 1, l,
                  lambda);
    }
  }
  cb_term_free(term);
  model_free(&t);
}

Test(bending, quadratic_energy_is_zero_flat_and_under_rigid_motions) {
  tmodel t;
  grid_model(&t, 5, 1.0);
  cb_term *q;
  cr_assert_eq(cb_quadratic_bend_term_alloc(&t.model, "bend", 2.0, &q), CB_OK);
  int nv = t.mesh.nv;
  double *x = malloc((size_t)3 * nv * sizeof *x);
  cr_assert_float_eq(q->type->energy(q, t.mesh.x, NULL), 0.0, 1e-24);
  /* a rotation about (1, 2, 3) by 0.7 rad and a translation */
  double ax[3] = {1 / sqrt(14.0), 2 / sqrt(14.0), 3 / sqrt(14.0)}, c = cos(0.7), s = sin(0.7), R[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double skew = (i == j) ? 0 : ((i + 1) % 3 == j ? -ax[3 - i - j] : ax[3 - i - j]);
      R[3 * i + j] = c * (i == j) + (1 - c) * ax[i] * ax[j] + s * skew;
    }
  for (int i = 0; i < nv; i++)
    for (int a = 0; a < 3; a++)
      x[3 * i + a] = R[3 * a] * t.mesh.x[3 * i] + R[3 * a + 1] * t.mesh.x[3 * i + 1] +
                     R[3 * a + 2] * t.mesh.x[3 * i + 2] + (a + 1) * 0.3;
  double E = q->type->energy(q, x, NULL);
  cr_expect(fabs(E) < 1e-24, "rigid motion: E = %g", E);
  /* a flat in-plane shear changes the cotangents: not zero (the model assumes little stretching) */
  for (int i = 0; i < nv; i++) {
    x[3 * i] = t.mesh.x[3 * i] + 0.3 * t.mesh.x[3 * i + 1];
    x[3 * i + 1] = t.mesh.x[3 * i + 1];
    x[3 * i + 2] = 0;
  }
  cr_expect(q->type->energy(q, x, NULL) >= 0);
  free(x);
  cb_term_free(q);
  model_free(&t);
}

/* Energy of the n x n grid of side L bent onto a cylinder of radius R. */
static double cylinder_energy(const char *model, int n, double L, double R) {
  tmodel t;
  grid_model(&t, n, L);
  cb_term *term;
  cr_assert_eq(cb_bend_term_alloc(model, &t.model, 1.0, &term), CB_OK);
  int nv = t.mesh.nv;
  double *x = malloc((size_t)3 * nv * sizeof *x);
  for (int i = 0; i < nv; i++) {
    double u = t.mesh.x[3 * i], v = t.mesh.x[3 * i + 1];
    x[3 * i] = R * sin(u / R);
    x[3 * i + 1] = v;
    x[3 * i + 2] = R * (1 - cos(u / R));
  }
  double E = term->type->energy(term, x, NULL);
  free(x);
  cb_term_free(term);
  model_free(&t);
  return E;
}

Test(bending, hinge_and_quadratic_on_cylinders_tend_to_three_times_the_continuous_energy) {
  const int ns[] = {8, 16, 32, 64};
  double prev = 0;
  for (int k = 0; k < 4; k++) {
    int n = ns[k];
    double cont = 1.0 / (2 * 0.8 * 0.8), want = 3.0 * (n - 2) / (n - 1);
    double rd = cylinder_energy("dihedral", n, 1.0, 0.8) / cont, rq = cylinder_energy("quadratic", n, 1.0, 0.8) / cont;
    cr_expect(fabs(rd - want) <= 1e-9 * want, "n = %d: hinge ratio %.12g, derived 3(n-2)/(n-1) = %.12g", n, rd, want);
    cr_expect(fabs(rq - want) <= 0.02 * want, "n = %d: quadratic ratio %.6g, hinge %.6g", n, rq, want);
    cr_expect(rq > prev, "n = %d: quadratic ratio %.6g does not grow toward 3", n, rq);
    prev = rq;
  }
  cr_expect(fabs(prev - 3) < 0.05, "n = 64: quadratic ratio %.6g, limit 3", prev);
}

Test(bending, quadratic_cylinder_energy_scales_as_inverse_R_squared_and_with_area) {
  double e1 = cylinder_energy("quadratic", 33, 1.0, 1.0), e2 = cylinder_energy("quadratic", 33, 1.0, 0.5);
  cr_expect(fabs(e2 / e1 - 4) < 0.02, "E(R/2)/E(R) = %.6g, expected about 4", e2 / e1);
  /* twice the side at the same spacing: four times the area; boundary columns: derived ratio
   * 4 (2n-3)/(2n-2) / ((n-2)/(n-1)) with the interior-column count of the hinge formula */
  double a1 = cylinder_energy("quadratic", 17, 1.0, 2.0), a2 = cylinder_energy("quadratic", 33, 2.0, 2.0);
  double want = 4.0 * (31.0 / 32.0) / (15.0 / 16.0);
  cr_expect(fabs(a2 / a1 - want) < 0.02 * want, "E(4A)/E(A) = %.6g, expected %.6g", a2 / a1, want);
}

Test(bending, b1_restoring_force_slopes_near_flat) {
  tmodel t;
  grid_model(&t, 2, 1.0);
  int v[4];
  cb_hinge_vertices(&t.topo, v);
  /* fold the wing v[3] about the edge v[0]-v[1] by phi; the force on it */
  const char *models[] = {"spring", "dihedral", "quadratic"};
  const double want[] = {3, 1, 1};
  for (int m = 0; m < 3; m++) {
    cb_term *term;
    cr_assert_eq(cb_bend_term_alloc(models[m], &t.model, 1.0, &term), CB_OK);
    double F[2];
    for (int k = 0; k < 2; k++) {
      double phi = (k ? 4.0 : 2.0) * PI / 180, x[12], g[12] = {0};
      memcpy(x, t.mesh.x, sizeof x);
      const double *o = t.mesh.x + 3 * v[0];
      double e[3], w[3], n[3];
      cb_v3_sub(t.mesh.x + 3 * v[1], o, e);
      double le = sqrt(cb_v3_dot(e, e));
      for (int a = 0; a < 3; a++) e[a] /= le;
      cb_v3_sub(t.mesh.x + 3 * v[3], o, w);
      double along = cb_v3_dot(w, e), r[3];
      for (int a = 0; a < 3; a++) r[a] = w[a] - along * e[a];
      cb_v3_cross(e, r, n);
      for (int a = 0; a < 3; a++) x[3 * v[3] + a] = o[a] + along * e[a] + cos(phi) * r[a] + sin(phi) * n[a];
      term->type->energy(term, x, g);
      /* the restoring part: along dx3/dphi = cos(phi) n - sin(phi) r (|r| = |n|, the arm) */
      double tan_[3], lr = sqrt(cb_v3_dot(r, r));
      for (int a = 0; a < 3; a++) tan_[a] = (cos(phi) * n[a] - sin(phi) * r[a]) / lr;
      F[k] = fabs(cb_v3_dot(g + 3 * v[3], tan_));
    }
    double slope = log(F[1] / F[0]) / log(2.0);
    cr_expect(fabs(slope - want[m]) < 0.05, "%s: slope %.4f, expected %g", models[m], slope, want[m]);
    cb_term_free(term);
  }
  model_free(&t);
}

Test(bending, project_leaves_no_vertex_inside_and_corrects_velocity) {
  cb_scene_def d = cb_scene_def_default();
  d.grid.n = d.grid.m = 9;
  d.grid.size[0] = d.grid.size[1] = 1.0;
  d.pins = "corners";
  d.collider = "project";
  d.sphere = (cb_sphere){
      .centre = {0.1, -0.2, 0.05}, .radius = 0.3, .thickness = 0.01, .stiffness = 0, .velocity = {0, 0.5, 0}};
  cb_scene *s;
  cr_assert_eq(cb_scene_build(&d, &s, NULL), CB_OK, "%s", cb_error_message());
  int nv = s->mesh.nv;
  double *x = malloc((size_t)3 * nv * sizeof *x), *v = calloc((size_t)3 * nv, sizeof *v),
         *x0 = malloc((size_t)3 * nv * sizeof *x0);
  memcpy(x, s->x0, (size_t)3 * nv * sizeof *x);
  memcpy(x0, x, (size_t)3 * nv * sizeof *x);
  double dt = 0.1, c[3] = {0.1, -0.2 + 0.5 * dt, 0.05}, R = 0.31; /* the sphere after one step */
  int inside = 0;
  for (int i = 0; i < nv; i++) {
    double dd[3];
    cb_v3_sub(x + 3 * i, c, dd);
    inside += s->free_index[i] >= 0 && cb_v3_dot(dd, dd) < R * R;
  }
  cr_assert_gt(inside, 0, "the test needs vertices inside the sphere");
  cr_assert_eq(cb_scene_post_step(s, x0, x, v, dt), CB_OK);
  cr_expect_eq(cb_scene_contacts(s, x), inside);
  for (int i = 0; i < nv; i++) {
    double dd[3];
    cb_v3_sub(x + 3 * i, c, dd);
    if (s->free_index[i] >= 0)
      cr_expect(sqrt(cb_v3_dot(dd, dd)) >= R * (1 - 1e-12), "vertex %d inside: %g", i, sqrt(cb_v3_dot(dd, dd)));
    for (int a = 0; a < 3; a++)
      cr_expect(fabs(v[3 * i + a] - (x[3 * i + a] - x0[3 * i + a]) / dt) < 1e-12, "vertex %d: velocity not corrected",
                i);
  }
  free(x);
  free(v);
  free(x0);
  cb_scene_free(s);
}

Test(bending, penalty_counts_contacts_and_rejects_a_moving_sphere) {
  cb_scene_def d = cb_scene_def_default();
  d.grid.n = d.grid.m = 9;
  d.grid.size[0] = d.grid.size[1] = 1.0;
  d.collider = "penalty";
  d.sphere =
      (cb_sphere){.centre = {0, -0.2, 0}, .radius = 0.3, .thickness = 0.01, .stiffness = 100, .velocity = {0, 0, 0}};
  cb_scene *s;
  cr_assert_eq(cb_scene_build(&d, &s, NULL), CB_OK, "%s", cb_error_message());
  int inside = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    double dd[3];
    cb_v3_sub(s->x0 + 3 * i, d.sphere.centre, dd);
    inside += cb_v3_dot(dd, dd) < 0.31 * 0.31;
  }
  cr_expect_gt(inside, 0);
  cr_expect_eq(cb_scene_contacts(s, s->x0), inside);
  cb_scene_free(s);
  d.sphere.velocity[1] = 1;
  const char *key = NULL;
  cr_expect_neq(cb_scene_build(&d, &s, &key), CB_OK);
  cr_expect_str_eq(key, "collider.velocity");
  d.sphere.velocity[1] = 0;
  d.sphere.radius = 0;
  cr_expect_neq(cb_scene_build(&d, &s, &key), CB_OK);
  cr_expect_str_eq(key, "collider.radius");
}

/* `project` runs after the steps of both integrators: a cloth falling onto the
 * sphere for 0.5 s ends with no free vertex inside, explicit or implicit. */
Test(bending, project_works_under_explicit_and_newton) {
  const char *methods[] = {"explicit", "newton"};
  for (int m = 0; m < 2; m++) {
    cb_scene_def d = cb_scene_def_default();
    d.grid.n = d.grid.m = 8;
    d.grid.size[0] = d.grid.size[1] = 1.0;
    d.pins = "none";
    d.stretch_k = 100;
    d.density = 0.2;
    d.collider = "project";
    d.sphere =
        (cb_sphere){.centre = {0, -0.3, 0}, .radius = 0.25, .thickness = 0, .stiffness = 0, .velocity = {0, 0, 0}};
    cb_scene *s;
    cr_assert_eq(cb_scene_build(&d, &s, NULL), CB_OK, "%s", cb_error_message());
    cb_integrator_params ip = cb_integrator_params_default();
    ip.dt = m ? 1.0 / 60 : 1e-3;
    cb_solver_params sp = cb_solver_params_default();
    cb_integrator *it;
    cr_assert_eq(cb_integrator_alloc(methods[m], s, &ip, NULL, "cholmod", &sp, &it), CB_OK, "%s", cb_error_message());
    int nv = s->mesh.nv, contacts = 0;
    double *x = malloc((size_t)3 * nv * sizeof *x), *v = calloc((size_t)3 * nv, sizeof *v);
    memcpy(x, s->x0, (size_t)3 * nv * sizeof *x);
    for (int k = 0; k < (int)lround(0.5 / ip.dt); k++) {
      cb_step_stats st;
      cr_assert(!cb_status_is_fatal(cb_integrator_step(it, x, v, &st)), "%s: step %d failed", methods[m], k);
      if (cb_scene_contacts(s, x) > contacts) contacts = cb_scene_contacts(s, x);
    }
    cr_expect_gt(contacts, 0, "%s: the cloth never touched the sphere", methods[m]);
    for (int i = 0; i < nv; i++) {
      double dd[3] = {x[3 * i], x[3 * i + 1] + 0.3, x[3 * i + 2]};
      cr_expect(sqrt(cb_v3_dot(dd, dd)) >= 0.25 * (1 - 1e-12), "%s: vertex %d inside", methods[m], i);
    }
    free(x);
    free(v);
    cb_integrator_free(it);
    cb_scene_free(s);
  }
}

/* Near-flat, folded to +-pi and collapsed hinges: finite energy, gradient and
 * Hessian (the documented clamp: a collapsed wing contributes nothing). */
Test(bending, dihedral_is_finite_flat_folded_and_degenerate) {
  tmodel t;
  grid_model(&t, 2, 1.0);
  int v[4];
  cb_hinge_vertices(&t.topo, v);
  cb_term *h;
  cr_assert_eq(cb_hinge_term_alloc(&t.model, "bend", 1.0, &h), CB_OK);
  cb_system sys;
  cr_assert_eq(cb_system_init(&sys, &t.model, &h, 1), CB_OK);
  for (int c = 0; c < 4; c++) {
    double x[12];
    memcpy(x, t.mesh.x, sizeof x);
    const double *o = t.mesh.x + 3 * v[0], *p = t.mesh.x + 3 * v[1], *w = t.mesh.x + 3 * v[2];
    if (c == 1) x[3 * v[3] + 2] += 1e-13; /* flat to round-off */
    if (c == 2)                           /* fold to pi: wing B onto wing A */
      for (int a = 0; a < 3; a++) x[3 * v[3] + a] = w[a];
    if (c == 3) /* wing A collapsed onto the edge's midpoint */
      for (int a = 0; a < 3; a++) x[3 * v[2] + a] = 0.5 * (o[a] + p[a]);
    double g[12] = {0}, E = cb_system_energy(&sys, x, g, NULL);
    cr_expect(isfinite(E), "case %d: E = %g", c, E);
    for (int i = 0; i < 12; i++) cr_expect(isfinite(g[i]), "case %d: gradient %d = %g", c, i, g[i]);
    cb_system_assemble(&sys, x, 0.0, CB_DEF_DROP, 0.0);
    for (int i = 0; i < sys.A.nnz; i++) cr_expect(isfinite(sys.A.val[i]), "case %d: Hessian entry %d", c, i);
    if (c == 2) cr_expect(E > 0, "a fold to pi has energy");
    if (c == 3) cr_expect_eq(E, 0.0, "a collapsed wing contributes nothing");
  }
  cb_system_free(&sys);
  model_free(&t);
}

/* material.bend_hessian: the dihedral term is the Gauss-Newton type by default and the exact one on
 * request; a config names only the two choices, and a scene def with another name fails at that key. */
Test(bending, bend_hessian_picks_the_dihedral_term_type) {
  static const char *const names[3] = {NULL, "gauss-newton", "exact"}, *const types[3] = {"dihedral", "dihedral",
                                                                                          "dihedral_exact"};
  for (int k = 0; k < 3; k++) {
    char set[64];
    snprintf(set, sizeof set, "material.bend_hessian=%s", names[k] ? names[k] : "gauss-newton");
    const char *sets[] = {"mesh.n=4", "material.bend=dihedral", k ? set : NULL, NULL};
    cb_config c;
    test_config(&c, sets);
    cb_scene *s = NULL;
    cr_assert_eq(cb_scene_from_config(&c, &s), CB_OK, "%s", cb_error_message());
    int found = 0;
    for (int i = 0; i < s->sys.nterms; i++)
      if (strcmp(s->sys.terms[i]->label, "bend") == 0) {
        found = 1;
        cr_expect_str_eq(s->sys.terms[i]->type->name, types[k]);
        cr_expect(cb_hinge_term_is(s->sys.terms[i]));
      }
    cr_expect(found);
    cb_scene_free(s);
  }
  cb_config c;
  const char *none[] = {NULL};
  test_config(&c, none);
  cr_expect_neq(cb_config_set(&c, "material.bend_hessian=projected"), CB_OK, "only gauss-newton and exact");
  cb_scene_def d = cb_scene_def_default();
  d.grid.n = d.grid.m = 4;
  d.bend = "dihedral";
  d.bend_hessian = "projected";
  cb_scene *s = NULL;
  const char *key = NULL;
  cr_expect_neq(cb_scene_build(&d, &s, &key), CB_OK);
  cr_expect_str_eq(key, "material.bend_hessian");
  cr_expect_null(s);
  d.bend = "quadratic"; /* other models have one Hessian: the key does not apply */
  cr_expect_eq(cb_scene_build(&d, &s, &key), CB_OK, "%s", cb_error_message());
  cb_scene_free(s);
  cb_term *t = NULL;
  tmodel tm;
  grid_model(&tm, 2, 1.0);
  cr_assert_eq(cb_bend_term_alloc("quadratic", &tm.model, 1.0, &t), CB_OK);
  cr_expect_neq(cb_hinge_term_set_hessian(t, CB_BEND_EXACT), CB_OK, "a quadratic term has no dihedral Hessian");
  cb_term_free(t);
  model_free(&tm);
}
