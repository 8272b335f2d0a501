/* The primitive-pair distances (distance.h), for every registered pair
 * (the loops run over cb_distance_types[], not a list kept here):
 *   - gradient against central differences of the distance, Hessian against
 *     central differences of the gradient, in every case the classifier
 *     produces (random configurations, counted per case: every case of the
 *     known pairs must be met), relative tolerances;
 *   - the Hessian is symmetric;
 *   - the distance against dense sampling of the two primitives: the sampled
 *     minimum is never below it, and lies within (sqrt(d^2) + delta)^2, delta
 *     the sampling's covering radius, which shrinks as the sampling refines;
 *   - closed forms for one configuration per case, parallel and collinear
 *     edges, degenerate triangles, and non-finite input.
 * Then the edge-edge mollifier: closed form, finite differences, C^1 at eps_x. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <clothbench/distance.h>
#include <clothbench/status.h>
#include "rng.h"

/* ---- helpers --------------------------------------------------------------- */

static double maxabs(int n, const double *a) {
  double m = 0;
  for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i]));
  return m;
}

/* A key of a case: the form and its vertex list, as text. */
static void case_key(const cb_distance_case *c, char *buf, size_t n) {
  int k = cb_distance_form_nverts(c->form), o = snprintf(buf, n, "%s", cb_distance_form_name(c->form));
  for (int i = 0; i < k; i++) o += snprintf(buf + o, n - (size_t)o, " %d", c->v[i]);
}

static int same_case(const cb_distance_case *a, const cb_distance_case *b) {
  if (a->form != b->form) return 0;
  for (int i = 0; i < cb_distance_form_nverts(a->form); i++)
    if (a->v[i] != b->v[i]) return 0;
  return 1;
}

/* Whether every +-h perturbation of every coordinate keeps x's case (the
 * finite differences then see one smooth formula). */
static int case_stable(const cb_distance_type *t, const double *x, double h) {
  cb_distance_case c0, c1;
  double y[12];
  t->classify(x, &c0);
  for (int i = 0; i < 3 * t->nverts; i++)
    for (int s = -1; s <= 1; s += 2) {
      memcpy(y, x, sizeof y);
      y[i] += s * h;
      t->classify(y, &c1);
      if (!same_case(&c0, &c1)) return 0;
    }
  return 1;
}

/* Central differences at x of the type's distance (gradient) and gradient
 * (Hessian), against the analytic ones; relative to the largest entry. */
static void check_fd(const cb_distance_type *t, const double *x, const char *what) {
  int n = 3 * t->nverts;
  double g[12], H[144], y[12], gp[12], gm[12];
  t->gradient(x, g);
  t->hessian(x, H);
  double h = 1e-6, gmax = maxabs(n, g), Hmax = maxabs(n * n, H);
  for (int i = 0; i < n; i++) {
    memcpy(y, x, sizeof y);
    y[i] = x[i] + h;
    double fp = t->distance(y);
    t->gradient(y, gp);
    y[i] = x[i] - h;
    double fm = t->distance(y);
    t->gradient(y, gm);
    double fd = (fp - fm) / (2 * h); /* d f / d x_i */
    cr_assert(fabs(fd - g[i]) <= 1e-6 * gmax + 1e-9, "%s %s: gradient %d: analytic %.12g, FD %.12g", t->name, what, i,
              g[i], fd);
    for (int j = 0; j < n; j++) {
      double fdh = (gp[j] - gm[j]) / (2 * h); /* d g_j / d x_i = H(j, i) */
      cr_assert(fabs(fdh - H[j * n + i]) <= 1e-5 * Hmax + 1e-8, "%s %s: Hessian (%d,%d): analytic %.12g, FD %.12g",
                t->name, what, j, i, H[j * n + i], fdh);
    }
  }
  for (int i = 0; i < n; i++)
    for (int j = 0; j < i; j++)
      cr_assert(fabs(H[i * n + j] - H[j * n + i]) <= 1e-13 * Hmax, "%s %s: Hessian not symmetric at (%d,%d)", t->name,
                what, i, j);
}

/* A point of the simplex of k vertices p (k = 1, 2, 3) at lattice point (i,
 * j) of an N-subdivision: barycentrics (N - i - j, i, j) / N. */
static void simplex_point(int k, const double *p, int N, int i, int j, double *out) {
  for (int a = 0; a < 3; a++) {
    if (k == 1) out[a] = p[a];
    else if (k == 2) out[a] = ((N - i) * p[a] + i * p[3 + a]) / N;
    else out[a] = ((N - i - j) * p[a] + i * p[3 + a] + j * p[6 + a]) / N;
  }
}

/* The lattice points of a k-simplex with N subdivisions: a point of the
 * simplex is within (longest edge) / N of one (a segment: half that). */
static double sampled_min(int ka, const double *A, int kb, const double *B, int N) {
  double best = INFINITY, pa[3], pb[3];
  int na = ka == 1 ? 0 : N, nb = kb == 1 ? 0 : N;
  for (int i = 0; i <= na; i++)
    for (int j = 0; j <= (ka == 3 ? na - i : 0); j++) {
      simplex_point(ka, A, N, i, j, pa);
      for (int k = 0; k <= nb; k++)
        for (int l = 0; l <= (kb == 3 ? nb - k : 0); l++) {
          simplex_point(kb, B, N, k, l, pb);
          double d[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
          best = fmin(best, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
  return best;
}

static double longest_edge(int k, const double *p) {
  double m = 0;
  for (int i = 0; i < k; i++)
    for (int j = 0; j < i; j++) {
      double d[3] = {p[3 * i] - p[3 * j], p[3 * i + 1] - p[3 * j + 1], p[3 * i + 2] - p[3 * j + 2]};
      m = fmax(m, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
  return m;
}

static void random_pair(cb_rng *r, int n, double *x) {
  for (int i = 0; i < n; i++) x[i] = 2 * cb_rng_uniform(r) - 1;
}

/* The cases a known pair has (vertex/edge/face regions and so on). */
static int expected_cases(const char *name) {
  if (!strcmp(name, "point-point")) return 1;
  if (!strcmp(name, "point-edge")) return 3;     /* two ends, the open segment */
  if (!strcmp(name, "point-triangle")) return 7; /* 3 vertices, 3 edges, the face */
  if (!strcmp(name, "edge-edge")) return 9;      /* 4 end-end, 4 end-edge, line-line */
  return 1;
}

/* ---- every registered pair ----------------------------------------------- */

Test(distance, registry) {
  int n = 0;
  for (int k = 0; cb_distance_types[k]; k++, n++) {
    const cb_distance_type *t = cb_distance_types[k];
    cr_assert(t->name && t->nverts >= 2 && t->nverts <= 4 && t->na >= 1 && t->na < t->nverts && t->na <= 3 &&
              t->nverts - t->na <= 3);
    cr_assert(t->classify && t->distance && t->gradient && t->hessian, "%s: a missing function", t->name);
    cr_assert_eq(cb_distance_type_find(t->name), t);
  }
  cr_assert_geq(n, 4);
  cr_assert_null(cb_distance_type_find("no-such-pair"));
}

Test(distance, finite_differences_in_every_case) {
  for (int k = 0; cb_distance_types[k]; k++) {
    const cb_distance_type *t = cb_distance_types[k];
    cb_rng r = cb_rng_seed(100 + (uint64_t)k);
    char seen[16][48];
    int nseen = 0;
    for (int trial = 0; trial < 4000; trial++) {
      double x[12] = {0};
      random_pair(&r, 3 * t->nverts, x);
      if (t->distance(x) < 1e-4) continue; /* away from contact: the squared distance is smooth there */
      if (!case_stable(t, x, 1e-5)) continue;
      cb_distance_case c;
      cr_assert_eq(t->classify(x, &c), CB_OK);
      char key[48];
      case_key(&c, key, sizeof key);
      int found = 0;
      for (int s = 0; s < nseen; s++) found |= !strcmp(seen[s], key);
      if (found && trial % 10) continue; /* each case once, then every 10th trial */
      if (!found && nseen < 16) snprintf(seen[nseen++], sizeof seen[0], "%s", key);
      check_fd(t, x, key);
    }
    cr_assert_eq(nseen, expected_cases(t->name), "%s: %d cases met, expected %d", t->name, nseen,
                 expected_cases(t->name));
  }
}

Test(distance, against_dense_sampling) {
  for (int k = 0; cb_distance_types[k]; k++) {
    const cb_distance_type *t = cb_distance_types[k];
    cb_rng r = cb_rng_seed(200 + (uint64_t)k);
    int ka = t->na, kb = t->nverts - t->na;
    for (int trial = 0; trial < 60; trial++) {
      double x[12] = {0};
      random_pair(&r, 3 * t->nverts, x);
      double d2 = t->distance(x), d = sqrt(d2), prev_gap = INFINITY;
      for (int N = 8; N <= (ka + kb >= 5 ? 64 : 256); N *= 2) {
        double s2 = sampled_min(ka, x, kb, x + 3 * ka, N);
        double delta = (longest_edge(ka, x) + longest_edge(kb, x + 3 * ka)) / N; /* covering radius, both */
        cr_assert(s2 >= d2 - 1e-12, "%s: sampled minimum %.17g below the distance %.17g", t->name, s2, d2);
        cr_assert(s2 <= (d + delta) * (d + delta) + 1e-12, "%s: sampled %.17g, distance %.17g, delta %g (N %d)",
                  t->name, s2, d2, delta, N);
        double gap = s2 - d2;
        cr_assert(gap <= prev_gap + 1e-15, "%s: the sampled gap grew with N", t->name);
        prev_gap = gap;
      }
    }
  }
}

Test(distance, non_finite_input) {
  for (int k = 0; cb_distance_types[k]; k++) {
    const cb_distance_type *t = cb_distance_types[k];
    for (int bad = 0; bad < 2; bad++) {
      double x[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, g[12], H[144];
      x[3 * t->nverts - 1] = bad ? INFINITY : NAN;
      cb_distance_case c;
      cr_assert_eq(t->classify(x, &c), CB_EINVAL, "%s", t->name);
      cr_assert(strstr(cb_error_message(), "not finite"), "%s: %s", t->name, cb_error_message());
      cr_assert(isnan(t->distance(x)));
      cr_assert(isnan(t->gradient(x, g)) && isnan(g[0]));
      cr_assert(isnan(t->hessian(x, H)) && isnan(H[0]));
    }
  }
}

/* ---- closed forms, case by case ---------------------------------------- */

static void expect(const cb_distance_type *t, const double *x, cb_distance_form form, const int *v, double d2) {
  cb_distance_case c;
  cr_assert_eq(t->classify(x, &c), CB_OK);
  char key[48];
  case_key(&c, key, sizeof key);
  cr_assert_eq(c.form, form, "%s: case %s, expected form %s", t->name, key, cb_distance_form_name(form));
  for (int i = 0; i < cb_distance_form_nverts(form); i++) cr_assert_eq(c.v[i], v[i], "%s: case %s", t->name, key);
  cr_assert(fabs(t->distance(x) - d2) <= 1e-14 * fmax(1, d2), "%s: %.17g, expected %.17g", t->name, t->distance(x), d2);
}

Test(distance, point_triangle_cases) {
  const cb_distance_type *t = &cb_distance_point_triangle;
  /* triangle (0,0,0), (1,0,0), (0,1,0) in z = 0 */
  double x[12] = {0.2, 0.3, 0.5, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  expect(t, x, CB_DIST_POINT_PLANE, (int[]){0, 1, 2, 3}, 0.25);
  x[0] = -1, x[1] = -2, x[2] = 2; /* beyond t0 */
  expect(t, x, CB_DIST_POINT_POINT, (int[]){0, 1}, 1 + 4 + 4);
  x[0] = 2, x[1] = -1, x[2] = 0; /* beyond t1 */
  expect(t, x, CB_DIST_POINT_POINT, (int[]){0, 2}, 1 + 1);
  x[0] = -0.5, x[1] = 3, x[2] = 1; /* beyond t2 */
  expect(t, x, CB_DIST_POINT_POINT, (int[]){0, 3}, 0.25 + 4 + 1);
  x[0] = 0.5, x[1] = -2, x[2] = 1; /* below edge t0 t1 */
  expect(t, x, CB_DIST_POINT_LINE, (int[]){0, 1, 2}, 4 + 1);
  x[0] = -3, x[1] = 0.25, x[2] = -1; /* beside edge t2 t0 */
  expect(t, x, CB_DIST_POINT_LINE, (int[]){0, 3, 1}, 9 + 1);
  x[0] = 1, x[1] = 1, x[2] = 2; /* beyond edge t1 t2: the line x + y = 1 at distance 1/sqrt 2 */
  expect(t, x, CB_DIST_POINT_LINE, (int[]){0, 2, 3}, 0.5 + 4);
  /* a point on the face: zero */
  double on[12] = {0.25, 0.25, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  expect(t, on, CB_DIST_POINT_PLANE, (int[]){0, 1, 2, 3}, 0);
  /* degenerate triangles: collinear (no face) and a single point */
  double line[12] = {0.5, 1, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0};
  expect(t, line, CB_DIST_POINT_LINE, (int[]){0, 1, 2}, 1);
  double dot[12] = {1, 2, 2, 3, 3, 3, 3, 3, 3, 3, 3, 3};
  cb_distance_case c;
  cr_assert_eq(t->classify(dot, &c), CB_OK);
  cr_assert_eq(c.form, CB_DIST_POINT_POINT);
  cr_assert_float_eq(t->distance(dot), 4 + 1 + 1, 1e-14);
}

Test(distance, edge_edge_cases) {
  const cb_distance_type *t = &cb_distance_edge_edge;
  /* a along x at z = 0, b along y at z = 1, crossing: line-line, d = 1 */
  double x[12] = {-1, 0, 0, 1, 0, 0, 0, -1, 1, 0, 1, 1};
  expect(t, x, CB_DIST_LINE_LINE, (int[]){0, 1, 2, 3}, 1);
  /* b shifted past a1: a1 against edge b */
  double y[12] = {-1, 0, 0, 1, 0, 0, 3, -1, 1, 3, 1, 1};
  expect(t, y, CB_DIST_POINT_LINE, (int[]){1, 2, 3}, 4 + 1);
  /* b shifted past a1 and beyond b1: a1 against b1 */
  double z[12] = {-1, 0, 0, 1, 0, 0, 3, -3, 1, 3, -2, 1};
  expect(t, z, CB_DIST_POINT_POINT, (int[]){1, 3}, 4 + 4 + 1);
  /* b's end b0 over the middle of a: b0 against edge a */
  double w[12] = {-1, 0, 0, 1, 0, 0, 0.25, 0, 1, 0.25, 0, 3};
  expect(t, w, CB_DIST_POINT_LINE, (int[]){2, 0, 1}, 1);
  /* parallel edges, overlapping: an endpoint against the other edge, d = 1 */
  double par[12] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 1.5, 1, 0};
  cb_distance_case c;
  cr_assert_eq(t->classify(par, &c), CB_OK);
  cr_assert(c.form == CB_DIST_POINT_LINE || c.form == CB_DIST_POINT_POINT);
  cr_assert_float_eq(t->distance(par), 1, 1e-14);
  /* parallel, apart along their line: end to end */
  double apart[12] = {0, 0, 0, 1, 0, 0, 3, 1, 0, 4, 1, 0};
  expect(t, apart, CB_DIST_POINT_POINT, (int[]){1, 2}, 4 + 1);
  /* antiparallel and collinear, overlapping: zero */
  double col[12] = {0, 0, 0, 2, 0, 0, 3, 0, 0, 1, 0, 0};
  cr_assert_eq(t->classify(col, &c), CB_OK);
  cr_assert(c.form != CB_DIST_LINE_LINE);
  cr_assert_float_eq(t->distance(col), 0, 1e-15);
  /* a zero-length edge is a point */
  double pt[12] = {0.5, 2, 0, 0.5, 2, 0, 0, 0, 0, 1, 0, 0};
  expect(t, pt, CB_DIST_POINT_LINE, (int[]){0, 2, 3}, 4);
}

/* Nearly parallel edges: the line-line formula holds while sin^2 > CB_DIST_PARALLEL and agrees with the
 * closed form; its derivatives pass finite differences at moderate angles. */
Test(distance, nearly_parallel_edges) {
  const cb_distance_type *t = &cb_distance_edge_edge;
  for (double th = 1e-1; th > 1e-6; th *= 0.1) {
    /* a along x through the origin; b through (0, 0, 1) at angle th in the xy-plane's direction */
    double x[12] = {-1, 0, 0, 1, 0, 0, -cos(th), -sin(th), 1, cos(th), sin(th), 1};
    expect(t, x, CB_DIST_LINE_LINE, (int[]){0, 1, 2, 3}, 1);
    if (th >= 1e-3) check_fd(t, x, "nearly parallel");
  }
}

/* ---- the mollifier ------------------------------------------------------- */

Test(distance, mollifier_closed_form) {
  double rest[12] = {0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 3, 1}; /* |a| = 2, |b| = 3 */
  double eps = cb_edge_edge_mollifier_threshold(rest);
  cr_assert_float_eq(eps, 1e-3 * 4 * 9, 1e-18);
  for (double th = 0; th < 0.5; th += 0.01) {
    /* a = 2 (1,0,0), b = 3 (cos th, sin th, 0): c = 36 sin^2 th */
    double x[12] = {0, 0, 0, 2, 0, 0, 0, 0, 1, 3 * cos(th), 3 * sin(th), 1};
    double c = 36 * sin(th) * sin(th);
    cr_assert(fabs(cb_edge_edge_cross_squared(x, NULL, NULL) - c) <= 1e-13 * fmax(c, 1));
    double e = c < eps ? -c * c / (eps * eps) + 2 * c / eps : 1;
    cr_assert(fabs(cb_edge_edge_mollifier(x, eps, NULL, NULL) - e) <= 1e-12, "th %g: %.17g, expected %.17g", th,
              cb_edge_edge_mollifier(x, eps, NULL, NULL), e);
  }
  double x[12] = {0, 0, 0, 2, 0, 0, 0, 0, 1, 3, 0, 1}, g[12];
  cr_assert_eq(cb_edge_edge_mollifier(x, eps, g, NULL), 0); /* parallel: 0 */
  cr_assert(isnan(cb_edge_edge_mollifier(x, 0, NULL, NULL)));
  cr_assert(isnan(cb_edge_edge_mollifier(x, -1, g, NULL)) && isnan(g[0]));
}

Test(distance, mollifier_finite_differences) {
  double eps = 0.05;
  cb_rng r = cb_rng_seed(7);
  int inside = 0;
  for (int trial = 0; trial < 400; trial++) {
    double x[12], g[12], H[144], y[12], gp[12], gm[12];
    random_pair(&r, 12, x);
    double c = cb_edge_edge_cross_squared(x, NULL, NULL);
    if (!(c < 0.95 * eps) && trial % 20) continue; /* mostly the mollified band */
    if (fabs(c - eps) < 1e-3) continue;
    inside += c < eps;
    cb_edge_edge_mollifier(x, eps, g, H);
    double h = 1e-6, gmax = maxabs(12, g), Hmax = maxabs(144, H);
    for (int i = 0; i < 12; i++) {
      memcpy(y, x, sizeof y);
      y[i] = x[i] + h;
      double fp = cb_edge_edge_mollifier(y, eps, gp, NULL);
      y[i] = x[i] - h;
      double fm = cb_edge_edge_mollifier(y, eps, gm, NULL);
      cr_assert(fabs((fp - fm) / (2 * h) - g[i]) <= 1e-6 * gmax + 1e-9, "gradient %d", i);
      for (int j = 0; j < 12; j++)
        cr_assert(fabs((gp[j] - gm[j]) / (2 * h) - H[j * 12 + i]) <= 1e-5 * Hmax + 1e-8, "Hessian (%d,%d)", j, i);
    }
    /* the cross term c's own derivatives */
    double gc[12], Hc[144];
    cb_edge_edge_cross_squared(x, gc, Hc);
    for (int i = 0; i < 12; i++) {
      memcpy(y, x, sizeof y);
      y[i] = x[i] + h;
      double cp = cb_edge_edge_cross_squared(y, gp, NULL);
      y[i] = x[i] - h;
      double cm = cb_edge_edge_cross_squared(y, gm, NULL);
      cr_assert(fabs((cp - cm) / (2 * h) - gc[i]) <= 1e-6 * maxabs(12, gc) + 1e-9);
      for (int j = 0; j < 12; j++)
        cr_assert(fabs((gp[j] - gm[j]) / (2 * h) - Hc[j * 12 + i]) <= 1e-5 * maxabs(144, Hc) + 1e-8);
    }
  }
  cr_assert_gt(inside, 20);
}

/* C^1 at c = eps_x: the value tends to 1 and the gradient to 0 from below. */
Test(distance, mollifier_c1_at_threshold) {
  double eps = 0.01, g[12];
  /* a = (1,0,0), b = (cos th, sin th, 0): c = sin^2 th; th just below asin(sqrt eps) */
  double th = asin(sqrt(eps)) * (1 - 1e-9);
  double x[12] = {0, 0, 0, 1, 0, 0, 0, 0, 1, cos(th), sin(th), 1};
  double e = cb_edge_edge_mollifier(x, eps, g, NULL);
  cr_assert(fabs(e - 1) < 1e-12);
  cr_assert(maxabs(12, g) < 1e-6);
}
