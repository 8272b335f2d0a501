/* contact.method = bridson (contact_bridson.c, docs/contact.md): Bridson,
 * Fedkiw & Anderson 2002's post-step filter.
 *
 * - Two triangles moving head-on through each other in one step end apart
 *   (the exact test, intersect.h) with bridson under every registered
 *   integrator, and intersect with contact.method = none; the impulses keep
 *   the pair's linear momentum (sum of m u, computed here).
 * - A rigid impact zone (bridson_iters = 0: the zones at once) keeps the
 *   zone's linear and angular momentum about its centre of mass, and moves
 *   rigidly ((u_i - u_j) . (x_i - x_j) = 0 for every vertex pair of the
 *   zone): with I nonsingular the two determine the rigid motion, so this is
 *   its closed form u_c = P / M, omega = I^-1 L.
 * - A sheet dropped on the table (configs/table.obj) under XPBD and under the
 *   explicit step intersects in no frame (cloth against table and cloth
 *   against itself, exactly, every frame) and rests on the top; with
 *   contact.method = none it falls through.
 * - Bad keys, and a start state that intersects or touches, give errors
 *   that name their key. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "intersections.h"
#include "support.h"

/* Triangle A (vertices 0-2) horizontal at y = 0.05 moving down, triangle B (3-5) upright in z = 0 below it, apex
 * at y = -0.05, moving up: in a step of 0.1 s at 1 m/s each, B's apex ends 0.05 m through A. */
static const char TWO_TRIANGLES[] = "v -0.5 0.05 -0.3\nv 0.5 0.05 -0.3\nv 0 0.05 0.5\n"
                                    "v 0 -0.05 0\nv -0.2 -0.5 0\nv 0.2 -0.5 0\n"
                                    "f 1 2 3\nf 4 5 6\n";

typedef struct {
  cb_scene *s;
  cb_integrator *it;
  double x0[18], x[18], v[18];
} pair_run;

/* One step of the two triangles, A at velocity (0, -1, 0) + spin x (x - c_A), B at (0, 1, 0); extra: more sets. */
static void pair_step(pair_run *r, const char *method, const char *integrator, const double spin[3],
                      const char *extra) {
  static char obj[512], file[600], meth[64], integ[64];
  snprintf(obj, sizeof obj, "%s", test_tmpfile(".obj", TWO_TRIANGLES));
  snprintf(file, sizeof file, "mesh.file=%s", obj);
  snprintf(meth, sizeof meth, "contact.method=%s", method);
  snprintf(integ, sizeof integ, "integrator.method=%s", integrator);
  const char *sets[] = {"mesh.type=obj",
                        file,
                        "scene.pins=none",
                        "scene.gravity=0 0 0",
                        "material.stretch_k=10",
                        "integrator.dt=0.1",
                        integ,
                        meth,
                        "contact.thickness=1e-3",
                        extra ? extra : "contact.friction=0",
                        NULL};
  r->s = test_scene(sets);
  remove(obj);
  r->it = test_integrator(sets, r->s, NULL, NULL);
  memcpy(r->x0, r->s->x0, sizeof r->x0);
  memcpy(r->x, r->x0, sizeof r->x);
  double cA[3] = {0, 0.05, -0.1 / 3};
  for (int i = 0; i < 6; i++) {
    double d[3], w[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++) d[a] = r->x0[3 * i + a] - cA[a];
    if (i < 3 && spin) {
      w[0] = spin[1] * d[2] - spin[2] * d[1];
      w[1] = spin[2] * d[0] - spin[0] * d[2];
      w[2] = spin[0] * d[1] - spin[1] * d[0];
    }
    for (int a = 0; a < 3; a++) r->v[3 * i + a] = (a == 1 ? (i < 3 ? -1.0 : 1.0) : 0.0) + w[a];
  }
  cb_step_stats st;
  int rc = cb_integrator_step(r->it, r->x, r->v, &st);
  /* a numerical status of the method itself (L-BFGS's line search on a force-free step) is not an error */
  cr_assert(rc >= 0, "%s, %s: status %d: %s", method, integrator, rc, cb_error_message());
}

static void pair_free(pair_run *r) {
  cb_integrator_free(r->it);
  cb_scene_free(r->s);
}

static int triangles_meet(const double *x) { return cb_tri_tri_intersect(x, x + 3, x + 6, x + 9, x + 12, x + 15); }

Test(bridson, head_on_triangles_end_apart_under_every_integrator) {
  pair_run none;
  pair_step(&none, "none", "explicit", NULL, NULL);
  cr_expect(triangles_meet(none.x), "without contact the triangles should end intersecting (the fixture)");
  pair_free(&none);
  for (int k = 0; cb_integrator_name(k); k++) {
    const char *name = cb_integrator_name(k);
    pair_run b;
    pair_step(&b, "bridson", name, NULL, NULL);
    cr_expect(!triangles_meet(b.x), "%s: the triangles intersect after the bridson filter", name);
    const cb_bridson_stats *bs = cb_scene_bridson_stats(b.s);
    cr_assert_not_null(bs);
    cr_expect_gt(bs->collisions + bs->zone_passes, 0, "%s: no collision handled", name);
    /* the filter's impulses between free vertices keep sum m u, u = (x1 - x0)/dt, of the unfiltered step's */
    pair_run n;
    pair_step(&n, "none", name, NULL, NULL);
    for (int a = 0; a < 3; a++) {
      double P0 = 0, P1 = 0, scale = 0;
      for (int i = 0; i < 6; i++) {
        P0 += n.s->mass[i] * (n.x[3 * i + a] - n.x0[3 * i + a]) / 0.1;
        P1 += b.s->mass[i] * (b.x[3 * i + a] - b.x0[3 * i + a]) / 0.1;
        scale += b.s->mass[i];
      }
      cr_expect(fabs(P1 - P0) <= 1e-12 * scale, "%s: momentum %c %.17g -> %.17g", name, "xyz"[a], P0, P1);
    }
    pair_free(&n);
    pair_free(&b);
  }
}

/* The zone's momenta about its centre of mass from positions x0 and velocities u = (x - x0)/dt. */
static void momenta(const pair_run *r, const double *x, double *P, double *L, double *xc) {
  double M = 0;
  for (int a = 0; a < 3; a++) P[a] = L[a] = xc[a] = 0;
  for (int i = 0; i < 6; i++) {
    M += r->s->mass[i];
    for (int a = 0; a < 3; a++) {
      P[a] += r->s->mass[i] * (x[3 * i + a] - r->x0[3 * i + a]) / 0.1;
      xc[a] += r->s->mass[i] * r->x0[3 * i + a];
    }
  }
  for (int a = 0; a < 3; a++) xc[a] /= M;
  for (int i = 0; i < 6; i++) {
    double d[3], u[3];
    for (int a = 0; a < 3; a++) {
      d[a] = r->x0[3 * i + a] - xc[a];
      u[a] = (x[3 * i + a] - r->x0[3 * i + a]) / 0.1 - P[a] / M;
    }
    L[0] += r->s->mass[i] * (d[1] * u[2] - d[2] * u[1]);
    L[1] += r->s->mass[i] * (d[2] * u[0] - d[0] * u[2]);
    L[2] += r->s->mass[i] * (d[0] * u[1] - d[1] * u[0]);
  }
}

Test(bridson, rigid_impact_zone_keeps_momentum_and_moves_rigidly) {
  const double spin[3] = {0.3, 2.0, -0.5};
  const char *methods[] = {"explicit", "xpbd"};
  for (int m = 0; m < 2; m++) {
    pair_run n, b;
    pair_step(&n, "none", methods[m], spin, NULL);
    pair_step(&b, "bridson", methods[m], spin, "contact.bridson_iters=0");
    const cb_bridson_stats *bs = cb_scene_bridson_stats(b.s);
    cr_assert_not_null(bs);
    cr_expect_gt(bs->zone_passes, 0, "%s: no zone pass", methods[m]);
    /* the zone: B's apex (3), which goes through A's face, and A (0-2); B's base (4, 5) stays out */
    cr_expect_eq(bs->zones, 1, "%s: %d zones", methods[m], bs->zones);
    cr_expect_eq(bs->zone_vertices, 4, "%s: the zone has %d vertices", methods[m], bs->zone_vertices);
    for (int k = 12; k < 18; k++)
      cr_expect(b.x[k] == n.x[k], "%s: x[%d] of B's base changed: %.17g -> %.17g", methods[m], k, n.x[k], b.x[k]);
    cr_expect(!triangles_meet(b.x), "%s: the zone still intersects", methods[m]);
    double P0[3], L0[3], c0[3], P1[3], L1[3], c1[3];
    momenta(&n, n.x, P0, L0, c0);
    momenta(&b, b.x, P1, L1, c1);
    cr_expect(fabs(L0[0]) + fabs(L0[1]) + fabs(L0[2]) > 1e-3, "the fixture needs angular momentum");
    for (int a = 0; a < 3; a++) {
      cr_expect(fabs(P1[a] - P0[a]) <= 1e-12, "%s: P_%c %.17g -> %.17g", methods[m], "xyz"[a], P0[a], P1[a]);
      cr_expect(fabs(L1[a] - L0[a]) <= 1e-12, "%s: L_%c %.17g -> %.17g", methods[m], "xyz"[a], L0[a], L1[a]);
    }
    /* rigid: (u_i - u_j) . (x_i - x_j) = 0 for every pair of the zone */
    for (int i = 0; i < 4; i++)
      for (int j = i + 1; j < 4; j++) {
        double dot = 0;
        for (int a = 0; a < 3; a++)
          dot += ((b.x[3 * i + a] - b.x0[3 * i + a]) - (b.x[3 * j + a] - b.x0[3 * j + a])) / 0.1 *
                 (b.x0[3 * i + a] - b.x0[3 * j + a]);
        cr_expect(fabs(dot) <= 1e-12, "%s: vertices %d, %d: (u_i - u_j).(x_i - x_j) = %g", methods[m], i, j, dot);
      }
    pair_free(&n);
    pair_free(&b);
  }
}

typedef struct {
  long frames_hit, worst;
  double ymin, ymax;
  int bad_steps, zone_steps;
} drop_result;

/* A 10 x 10 sheet 0.8 m wide (the table's depth) falls from 0.1 m above the table's top (y = -0.1) for the
 * given steps; every frame checked exactly. */
static drop_result drop(const char *method, const char *integrator, const char *dt, int steps) {
  const char *const sets[] = {"mesh.n=10",
                              "mesh.size=0.8",
                              "mesh.plane=xz",
                              "material.density=0.2",
                              "material.stretch_k=500",
                              "scene.pins=none",
                              integrator,
                              "integrator.iters=20",
                              dt,
                              "collider.type=mesh",
                              "collider.file=configs/table.obj",
                              "collider.centre=0 -0.1 0",
                              method,
                              "contact.thickness=5e-3",
                              "contact.friction=0.3",
                              NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  cb_intersections self;
  cr_assert_eq(cb_intersections_init(&self, &s->mesh), CB_OK);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = malloc((size_t)n3 * sizeof(double));
  cr_assert(x && v);
  memcpy(x, s->x0, (size_t)n3 * sizeof(double));
  memcpy(v, s->v0, (size_t)n3 * sizeof(double));
  drop_result r = {0};
  for (int k = 0; k < steps; k++) {
    cb_step_stats st;
    int rc = cb_integrator_step(it, x, v, &st);
    r.bad_steps += rc != CB_OK;
    const cb_bridson_stats *bs = cb_scene_bridson_stats(s);
    r.zone_steps += bs && bs->zone_passes > 0;
    long nself = 0, ncross = test_cross_intersections(s, x);
    cr_assert_eq(cb_intersections_count(&self, x, &nself), CB_OK);
    r.frames_hit += ncross + nself > 0;
    if (ncross + nself > r.worst) r.worst = ncross + nself;
  }
  r.ymin = INFINITY;
  r.ymax = -INFINITY;
  for (int i = 0; i < s->mesh.nv; i++) {
    r.ymin = fmin(r.ymin, x[3 * i + 1]);
    r.ymax = fmax(r.ymax, x[3 * i + 1]);
  }
  free(x);
  free(v);
  cb_intersections_free(&self);
  cb_integrator_free(it);
  cb_scene_free(s);
  return r;
}

Test(bridson, sheet_on_the_table_never_intersects, .timeout = 600) {
  struct {
    const char *integrator, *dt;
    int steps;
  } runs[] = {{"integrator.method=xpbd", "integrator.dt=1/60", 60},
              {"integrator.method=explicit", "integrator.dt=1e-3", 400}};
  for (int k = 0; k < 2; k++) {
    drop_result b = drop("contact.method=bridson", runs[k].integrator, runs[k].dt, runs[k].steps);
    cr_expect_eq(b.bad_steps, 0, "%s: %d steps not ok", runs[k].integrator, b.bad_steps);
    cr_expect_eq(b.frames_hit, 0, "%s: %ld frames intersect (worst %ld pairs)", runs[k].integrator, b.frames_hit,
                 b.worst);
    cr_expect(b.ymin > -0.1 && b.ymax < -0.1 + 0.02, "%s: the sheet ends at y in [%g, %g], not on the top (y = -0.1)",
              runs[k].integrator, b.ymin, b.ymax);
    drop_result n = drop("contact.method=none", runs[k].integrator, runs[k].dt, runs[k].steps);
    cr_expect(n.frames_hit > 0 || n.ymax < -0.14, "%s without contact: did not go through the table",
              runs[k].integrator);
    if (!getenv("CB_QUIET"))
      printf("bridson drop, %s: 0 of %d frames intersect, %d steps used zones, ends at y in [%.5f, %.5f]; without "
             "contact %ld frames intersect\n",
             runs[k].integrator, runs[k].steps, b.zone_steps, b.ymin, b.ymax, n.frames_hit);
  }
}

Test(bridson, bad_keys_name_themselves) {
  test_expect_config_error((const char *const[]){"contact.method=bridson", "contact.bridson_iters=-1", NULL}, "contact."
                                                                                                              "bridson_"
                                                                                                              "iters");
  test_expect_config_error((const char *const[]){"contact.method=bridson", "contact.bridson_iters=2.5", NULL}, "contact"
                                                                                                               ".bridso"
                                                                                                               "n_"
                                                                                                               "iters");
  test_expect_config_error((const char *const[]){"contact.method=bridson", "contact.thickness=0", NULL}, "contact."
                                                                                                         "thickness");
  test_expect_config_error((const char *const[]){"contact.method=bridson", "contact.friction=-0.2", NULL}, "contact."
                                                                                                           "friction");
  test_expect_config_error((const char *const[]){"contact.method=bridson", "contact.stiffness=0", NULL}, "contact."
                                                                                                         "stiffness");
  /* a chain has no triangles to collide */
  test_expect_config_error(
      (const char *const[]){"contact.method=bridson", "mesh.type=chain", "material.vertex_mass=1", NULL}, "con"
                                                                                                          "tac"
                                                                                                          "t."
                                                                                                          "met"
                                                                                                          "ho"
                                                                                                          "d");
  /* a start state that intersects the table's top (a sheet 1 m wide inside its 0.8 m deep top crosses its sides) or
   * touches it (on its plane): the filter cannot undo a crossing */
  const char *const heights[] = {"collider.centre=0 0.02 0", "collider.centre=0 0 0"};
  for (int h = 0; h < 2; h++)
    test_expect_config_error((const char *const[]){"contact.method=bridson", "mesh.n=6", "mesh.size=1", "mesh.plane=xz",
                                                   "scene.pins=none", "collider.type=mesh",
                                                   "collider.file=configs/table.obj", heights[h], NULL},
                             "contact.method");
  /* friction is bridson's and ipc's: the penalty still refuses it */
  test_expect_config_error((const char *const[]){"contact.method=penalty", "contact.friction=0.4", NULL}, "contact."
                                                                                                          "friction");
  cb_contact_params p = cb_contact_params_default();
  p.friction = 0.4;
  cr_expect_eq(cb_contact_params_check("bridson", &p), CB_OK, "%s", cb_error_message());
  p.bridson_iters = -3;
  cr_expect_neq(cb_contact_params_check("bridson", &p), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.bridson_iters"), "%s", cb_error_message());
  p = cb_contact_params_default();
  p.thickness = NAN;
  cr_expect_neq(cb_contact_params_check("bridson", &p), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.thickness"), "%s", cb_error_message());
  /* the response's own check, for a definition built without a config */
  cb_scene_def d = cb_scene_def_default();
  d.contact = "bridson";
  d.contact_params.bridson_iters = -1;
  cb_scene *s = NULL;
  const char *key = NULL;
  cr_expect_neq(cb_scene_build(&d, &s, &key), CB_OK);
  cr_expect(key && !strcmp(key, "contact.bridson_iters"), "key %s: %s", key ? key : "(null)", cb_error_message());
  cb_scene_free(s);
}
