/* Kinematic obstacle meshes (obstacle.h) and the `mesh` collider:
 *   - the motion against a rotation built here independently (an orthonormal
 *     frame about the axis, not Rodrigues' formula), rigidity, a point on the
 *     axis, a full turn, velocities against central differences of positions;
 *   - the scene: the obstacle is moved to the run's time after every step,
 *     the cloth's trajectory is the one without it (no response yet), and
 *     the shipped configs/ meshes load;
 *   - bad input: a missing file, a broken OBJ, a degenerate triangle, a NaN
 *     coordinate, a file without triangles, non-finite or zero motion
 *     parameters; each a clear error naming its key. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <clothbench/obstacle.h>
#include "support.h"

#define PI 3.14159265358979323846

static const char *const TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

static cb_obstacle *tetra(const cb_obstacle_params *motion) {
  cb_obstacle_params p = *motion;
  char path[256];
  snprintf(path, sizeof path, "%s", test_tmpfile(".obj", TETRA));
  p.file = path;
  cb_obstacle *o = NULL;
  int st = cb_obstacle_alloc(&p, &o);
  remove(path);
  cr_assert_eq(st, CB_OK, "%s", cb_error_message());
  return o;
}

/* R(a, th) r by components in the frame (a, e1, e2), e1 = a x (a helper
 * not parallel to a) normalised, e2 = a x e1: r = ra a + r1 e1 + r2 e2 turns
 * to ra a + (r1 cos - r2 sin) e1 + (r1 sin + r2 cos) e2. */
static void rotate_frame(const double *axis, double th, const double *r, double *out) {
  double l = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  double a[3] = {axis[0] / l, axis[1] / l, axis[2] / l};
  double h[3] = {fabs(a[0]) < 0.9 ? 1 : 0, fabs(a[0]) < 0.9 ? 0 : 1, 0};
  double e1[3] = {a[1] * h[2] - a[2] * h[1], a[2] * h[0] - a[0] * h[2], a[0] * h[1] - a[1] * h[0]};
  double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (int k = 0; k < 3; k++) e1[k] /= l1;
  double e2[3] = {a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2], a[0] * e1[1] - a[1] * e1[0]};
  double ra = 0, r1 = 0, r2 = 0;
  for (int k = 0; k < 3; k++) ra += r[k] * a[k], r1 += r[k] * e1[k], r2 += r[k] * e2[k];
  double c = cos(th), s = sin(th);
  for (int k = 0; k < 3; k++) out[k] = ra * a[k] + (r1 * c - r2 * s) * e1[k] + (r1 * s + r2 * c) * e2[k];
}

static double dist(const double *a, const double *b) {
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

Test(obstacle, motion_closed_form) {
  cb_obstacle_params p = cb_obstacle_params_default();
  double axis[3] = {1, 2, -0.5}, c[3] = {0.3, -1, 2}, v[3] = {0.1, -0.2, 0.05};
  memcpy(p.axis, axis, sizeof axis);
  memcpy(p.centre, c, sizeof c);
  memcpy(p.velocity, v, sizeof v);
  p.omega = 1.7;
  cb_obstacle *o = tetra(&p);
  cr_assert_eq(o->mesh.nv, 4);
  cr_assert_eq(o->mesh.nt, 4);
  double x[12], xw[3];
  for (double t = 0; t < 10; t += 0.37) {
    cb_obstacle_positions(o, t, x);
    for (int i = 0; i < 4; i++) {
      rotate_frame(axis, p.omega * t, o->mesh.x + 3 * i, xw); /* R X_i */
      for (int k = 0; k < 3; k++)
        cr_assert(fabs(x[3 * i + k] - (c[k] + t * v[k] + xw[k])) < 1e-13, "t %g vertex %d: %.17g vs %.17g", t, i,
                  x[3 * i + k], c[k] + t * v[k] + xw[k]);
    }
    for (int i = 0; i < 4; i++) /* rigid */
      for (int j = 0; j < i; j++)
        cr_assert(fabs(dist(x + 3 * i, x + 3 * j) - dist(o->mesh.x + 3 * i, o->mesh.x + 3 * j)) < 1e-14);
  }
  /* vertex 0 is the frame's origin, on the axis: it only translates */
  cb_obstacle_positions(o, 2.5, x);
  for (int k = 0; k < 3; k++) cr_assert(fabs(x[k] - (c[k] + 2.5 * v[k])) < 1e-15);
  /* a full turn: the rest shape again, translated */
  double T = 2 * PI / p.omega;
  cb_obstacle_positions(o, T, x);
  for (int i = 0; i < 12; i++) cr_assert(fabs(x[i] - (o->mesh.x[i] + c[i % 3] + T * v[i % 3])) < 1e-13);
  /* advance sets x and t */
  cb_obstacle_advance(o, 0.9);
  cb_obstacle_positions(o, 0.9, x);
  cr_assert_eq(o->t, 0.9);
  cr_assert_arr_eq(o->x, x, sizeof x);
  /* velocities: central differences of positions */
  double vel[12], xp[12], xm[12], h = 1e-5;
  for (double t = 0.1; t < 5; t += 1.3) {
    cb_obstacle_velocities(o, t, vel);
    cb_obstacle_positions(o, t + h, xp);
    cb_obstacle_positions(o, t - h, xm);
    for (int i = 0; i < 12; i++) cr_assert(fabs((xp[i] - xm[i]) / (2 * h) - vel[i]) < 1e-8, "t %g: %d", t, i);
  }
  cb_obstacle_free(o);
  cb_obstacle_free(NULL);
}

Test(obstacle, translation_only) {
  cb_obstacle_params p = cb_obstacle_params_default();
  p.axis[0] = p.axis[1] = p.axis[2] = 0; /* no axis needed without rotation */
  p.velocity[0] = 2;
  p.velocity[2] = -1;
  cb_obstacle *o = tetra(&p);
  double x[12], v[12];
  cb_obstacle_positions(o, 1.5, x);
  cb_obstacle_velocities(o, 1.5, v);
  for (int i = 0; i < 4; i++) {
    cr_assert_eq(x[3 * i], o->mesh.x[3 * i] + 3);
    cr_assert_eq(x[3 * i + 1], o->mesh.x[3 * i + 1]);
    cr_assert_eq(x[3 * i + 2], o->mesh.x[3 * i + 2] - 1.5);
    cr_assert(v[3 * i] == 2 && v[3 * i + 1] == 0 && v[3 * i + 2] == -1);
  }
  cb_obstacle_free(o);
}

/* ---- in a scene ----------------------------------------------------------- */

Test(obstacle, moved_every_step_and_no_response) {
  char obj[256], sfile[300];
  snprintf(obj, sizeof obj, "%s", test_tmpfile(".obj", TETRA));
  snprintf(sfile, sizeof sfile, "collider.file=%s", obj);
  const char *with[] = {"mesh.n=5",
                        "mesh.size=1",
                        "collider.type=mesh",
                        sfile,
                        "collider.centre=0 -2 0",
                        "collider.axis=0 0 1",
                        "collider.angular_speed=3",
                        "collider.velocity=0.5 0 0",
                        "integrator.dt=0.01",
                        NULL};
  const char *without[] = {"mesh.n=5", "mesh.size=1", "integrator.dt=0.01", NULL};
  cb_scene *s = test_scene(with), *s0 = test_scene(without);
  remove(obj);
  const cb_obstacle *o = cb_scene_obstacle(s);
  cr_assert_not_null(o);
  cr_assert_null(cb_scene_obstacle(s0));
  cb_integrator *it = test_integrator(with, s, NULL, NULL), *it0 = test_integrator(without, s0, NULL, NULL);
  int n = 3 * s->mesh.nv;
  double *x = malloc(n * sizeof(double)), *v = malloc(n * sizeof(double));
  double *x0 = malloc(n * sizeof(double)), *v0 = malloc(n * sizeof(double));
  memcpy(x, s->x0, n * sizeof(double));
  memcpy(v, s->v0, n * sizeof(double));
  memcpy(x0, s0->x0, n * sizeof(double));
  memcpy(v0, s0->v0, n * sizeof(double));
  cb_step_stats st;
  double expect[12];
  for (int k = 1; k <= 5; k++) {
    cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
    cr_assert_eq(cb_integrator_step(it0, x0, v0, &st), CB_OK);
    cr_assert_arr_eq(x, x0, n * sizeof(double), "step %d: the obstacle changed the cloth", k);
    double t = 0;
    for (int j = 0; j < k; j++) t += 0.01; /* the response's clock: a sum of dt */
    cr_assert_eq(o->t, t);
    for (int i = 0; i < 4; i++) { /* c + t v + R(z, 3t) X_i, written out for the z axis */
      const double *X = o->mesh.x + 3 * i;
      expect[3 * i] = 0 + 0.5 * t + cos(3 * t) * X[0] - sin(3 * t) * X[1];
      expect[3 * i + 1] = -2 + sin(3 * t) * X[0] + cos(3 * t) * X[1];
      expect[3 * i + 2] = X[2];
    }
    for (int i = 0; i < 12; i++) cr_assert(fabs(o->x[i] - expect[i]) < 1e-14, "step %d coordinate %d", k, i);
  }
  cr_assert_eq(cb_scene_contacts(s, x), 0);
  free(x), free(v), free(x0), free(v0);
  cb_integrator_free(it);
  cb_integrator_free(it0);
  cb_scene_free(s);
  cb_scene_free(s0);
}

/* cb_scene_obstacle_set_time: the obstacle back at an earlier time (the closed form of the motion test above), and the
 * next step moves it on from there by dt, as the first time; a scene without an obstacle ignores it. */
Test(obstacle, rewind_repeats_a_step) {
  char obj[256], sfile[300];
  snprintf(obj, sizeof obj, "%s", test_tmpfile(".obj", TETRA));
  snprintf(sfile, sizeof sfile, "collider.file=%s", obj);
  const char *with[] = {"mesh.n=5",
                        "mesh.size=1",
                        "collider.type=mesh",
                        sfile,
                        "collider.centre=0 -2 0",
                        "collider.axis=0 0 1",
                        "collider.angular_speed=3",
                        "integrator.dt=0.01",
                        NULL};
  cb_scene *s = test_scene(with);
  remove(obj);
  const cb_obstacle *o = cb_scene_obstacle(s);
  cr_assert_not_null(o);
  cb_integrator *it = test_integrator(with, s, NULL, NULL);
  int n = 3 * s->mesh.nv;
  double *x = malloc(n * sizeof(double)), *v = malloc(n * sizeof(double));
  double *xs = malloc(n * sizeof(double)), *vs = malloc(n * sizeof(double)), *x1 = malloc(n * sizeof(double));
  double o1[12];
  memcpy(x, s->x0, n * sizeof(double));
  memcpy(v, s->v0, n * sizeof(double));
  cb_step_stats st;
  cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
  double t1 = o->t; /* the state after one step: saved */
  memcpy(xs, x, n * sizeof(double));
  memcpy(vs, v, n * sizeof(double));
  cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
  memcpy(x1, x, n * sizeof(double));
  memcpy(o1, o->x, sizeof o1);
  for (int k = 0; k < 3; k++) cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
  cb_scene_obstacle_set_time(s, t1);
  cr_assert_eq(o->t, t1);
  for (int i = 0; i < 4; i++) { /* R(z, 3 t1) X_i + c, written out */
    const double *X = o->mesh.x + 3 * i;
    cr_assert(fabs(o->x[3 * i] - (cos(3 * t1) * X[0] - sin(3 * t1) * X[1])) < 1e-14);
    cr_assert(fabs(o->x[3 * i + 1] - (-2 + sin(3 * t1) * X[0] + cos(3 * t1) * X[1])) < 1e-14);
  }
  /* the second step again from the saved state: the same cloth and the same obstacle, bit for bit */
  memcpy(x, xs, n * sizeof(double));
  memcpy(v, vs, n * sizeof(double));
  cr_assert_eq(cb_integrator_step(it, x, v, &st), CB_OK);
  cr_assert_arr_eq(x, x1, n * sizeof(double));
  cr_assert_arr_eq(o->x, o1, sizeof o1);
  cr_assert_eq(o->t, t1 + 0.01);
  const char *without[] = {"mesh.n=5", "mesh.size=1", NULL};
  cb_scene *s0 = test_scene(without);
  cb_scene_obstacle_set_time(s0, 1.0); /* no obstacle: nothing to do */
  cr_assert_null(cb_scene_obstacle(s0));
  free(x), free(v), free(xs), free(vs), free(x1);
  cb_integrator_free(it);
  cb_scene_free(s);
  cb_scene_free(s0);
}

Test(obstacle, shipped_meshes_load) {
  static const struct {
    const char *file;
    int nv, nt;
    double lo[3], hi[3];
  } meshes[] = {{"configs/table.obj", 40, 60, {-0.6, -0.74, -0.4}, {0.6, 0, 0.4}},
                {"configs/cylinder.obj", 50, 96, {-0.1, -0.1, -0.6}, {0.1, 0.1, 0.6}}};
  for (size_t m = 0; m < sizeof meshes / sizeof meshes[0]; m++) {
    cb_obstacle_params p = cb_obstacle_params_default();
    p.file = meshes[m].file;
    cb_obstacle *o = NULL;
    cr_assert_eq(cb_obstacle_alloc(&p, &o), CB_OK, "%s", cb_error_message());
    cr_assert_eq(o->mesh.nv, meshes[m].nv, "%s", p.file);
    cr_assert_eq(o->mesh.nt, meshes[m].nt, "%s", p.file);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, vol = 0;
    for (int i = 0; i < o->mesh.nv; i++)
      for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], o->mesh.x[3 * i + k]), hi[k] = fmax(hi[k], o->mesh.x[3 * i + k]);
    for (int k = 0; k < 3; k++) cr_assert(fabs(lo[k] - meshes[m].lo[k]) < 1e-9 && fabs(hi[k] - meshes[m].hi[k]) < 1e-9);
    for (int t = 0; t < o->mesh.nt; t++) { /* closed and outward: the divergence theorem's volume is positive */
      const double *a = o->mesh.x + 3 * o->mesh.tri[3 * t], *b = o->mesh.x + 3 * o->mesh.tri[3 * t + 1],
                   *c = o->mesh.x + 3 * o->mesh.tri[3 * t + 2];
      vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
              a[2] * (b[0] * c[1] - b[1] * c[0])) /
             6;
    }
    if (m == 0) cr_assert(fabs(vol - (1.2 * 0.04 * 0.8 + 4 * 0.05 * 0.05 * 0.7)) < 1e-12, "table volume %g", vol);
    else /* a regular 24-gon prism: (N/2) R^2 sin(2 pi/N) L */
      cr_assert(fabs(vol - 12 * 0.01 * sin(2 * PI / 24) * 1.2) < 1e-8, "cylinder volume %g", vol);
    cb_obstacle_free(o);
  }
}

/* ---- bad input ------------------------------------------------------------ */

static void expect_obj_error(const char *text, const char *needle) {
  char obj[256], set[300];
  const char *path = "/nonexistent/obstacle.obj";
  if (text) {
    snprintf(obj, sizeof obj, "%s", test_tmpfile(".obj", text));
    path = obj;
  }
  snprintf(set, sizeof set, "collider.file=%s", path);
  const char *sets[] = {"mesh.n=4", "collider.type=mesh", set, NULL};
  cb_config c;
  test_config(&c, sets);
  cb_scene *s = NULL;
  int st = cb_scene_from_config(&c, &s);
  if (text) remove(obj);
  cr_assert_lt(st, 0, "%s: built", needle);
  cr_assert_null(s);
  cr_assert(strstr(cb_error_message(), "collider.file"), "no key in: %s", cb_error_message());
  cr_assert(strstr(cb_error_message(), needle), "'%s' not in: %s", needle, cb_error_message());
}

Test(obstacle, bad_files) {
  expect_obj_error(NULL, "/nonexistent/obstacle.obj");
  expect_obj_error("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "the file has 2 vertices"); /* broken: index 3 of 2 */
  expect_obj_error("v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:");              /* broken: a vertex of two numbers */
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "area");           /* degenerate: collinear */
  expect_obj_error("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "finite");       /* NaN */
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces");                /* points only */
  expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 3\n", "line elements");
  /* no file at all */
  const char *sets[] = {"mesh.n=4", "collider.type=mesh", NULL};
  cb_config c;
  test_config(&c, sets);
  cb_scene *s = NULL;
  cr_assert_eq(cb_scene_from_config(&c, &s), CB_EINVAL);
  cr_assert(strstr(cb_error_message(), "collider.file: required"), "%s", cb_error_message());
}

static void expect_param_error(cb_obstacle_params p, const char *key) {
  char obj[256];
  snprintf(obj, sizeof obj, "%s", test_tmpfile(".obj", TETRA));
  p.file = obj;
  cb_obstacle *o = NULL;
  int st = cb_obstacle_alloc(&p, &o);
  remove(obj);
  cr_assert_eq(st, CB_EINVAL, "%s: accepted", key);
  cr_assert_null(o);
  cr_assert(strncmp(cb_error_message(), key, strlen(key)) == 0, "'%s' does not start: %s", key, cb_error_message());
}

Test(obstacle, bad_motion) {
  cb_obstacle_params p = cb_obstacle_params_default();
  p.centre[1] = NAN;
  expect_param_error(p, "collider.centre");
  p = cb_obstacle_params_default();
  p.velocity[2] = INFINITY;
  expect_param_error(p, "collider.velocity");
  p = cb_obstacle_params_default();
  p.axis[0] = NAN;
  expect_param_error(p, "collider.axis");
  p = cb_obstacle_params_default();
  p.omega = NAN;
  expect_param_error(p, "collider.angular_speed");
  p = cb_obstacle_params_default();
  p.omega = 1;
  p.axis[0] = p.axis[1] = p.axis[2] = 0;
  expect_param_error(p, "collider.axis");
  p = cb_obstacle_params_default();
  p.omega = 1;
  p.axis[0] = 1e300, p.axis[1] = 1e300;
  expect_param_error(p, "collider.axis");
  p = cb_obstacle_params_default();
  p.file = NULL;
  cb_obstacle *o = NULL;
  cr_assert_eq(cb_obstacle_alloc(&p, &o), CB_EINVAL);
  cr_assert(strstr(cb_error_message(), "collider.file"));
  /* through the scene: the key a caller should point at */
  cb_scene_def d = cb_scene_def_default();
  d.collider = "mesh";
  d.obstacle.file = "/nonexistent.obj";
  cb_scene *s = NULL;
  const char *key = NULL;
  cr_assert_lt(cb_scene_build(&d, &s, &key), 0);
  cr_assert_str_eq(key, "collider.file");
  char obj[256];
  snprintf(obj, sizeof obj, "%s", test_tmpfile(".obj", TETRA));
  d.obstacle.file = obj;
  d.obstacle.omega = 2;
  d.obstacle.axis[0] = d.obstacle.axis[1] = d.obstacle.axis[2] = 0;
  cr_assert_eq(cb_scene_build(&d, &s, &key), CB_EINVAL);
  remove(obj);
  cr_assert_str_eq(key, "collider.axis");
}
