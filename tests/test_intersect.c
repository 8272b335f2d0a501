/* The exact predicates and the exact triangle-triangle test
 * (include/clothbench/intersect.h), and the intersection-count instrument
 * (lib/instruments/intersections.h).
 *
 * Expected answers come from hand geometry (touching at a vertex, along an
 * edge, coplanar overlap), from one-ulp moves computed with nextafter (the
 * moved point is on the far side by construction), from determinants of
 * integer-valued coordinates evaluated in __int128 (exact, independent of
 * the predicates' filter and of GMP), from an independent floating-point
 * crossing test on random triangles in general position (pairs it cannot
 * decide by a wide margin are skipped), and from brute-force all-pairs counts
 * against the instrument's broad phase. */
#include <criterion/criterion.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "intersections.h"
#include "rng.h"
#include "support.h"
#include <clothbench/intersect.h>
#include <clothbench/mesh.h>
#include <clothbench/status.h>

#define V(x, y, z) ((const double[3]){(x), (y), (z)})

static int tt(const double *a, const double *b, const double *c, const double *d, const double *e, const double *f) {
  /* the answer must not depend on the order of the triangles or of their vertices */
  int r = cb_tri_tri_intersect(a, b, c, d, e, f);
  cr_assert_eq(cb_tri_tri_intersect(d, e, f, a, b, c), r, "not symmetric");
  cr_assert_eq(cb_tri_tri_intersect(b, c, a, f, d, e), r, "depends on the vertex order");
  cr_assert_eq(cb_tri_tri_intersect(a, c, b, d, f, e), r, "depends on the orientation");
  return r;
}

static const double *T0 = (const double[]){0, 0, 0}, *T1 = (const double[]){1, 0, 0}, *T2 = (const double[]){0, 1, 0};

Test(intersect, touching_at_a_vertex_and_one_ulp_above) {
  /* a vertex of Q on the interior of P (z = 0), the rest above */
  cr_assert_eq(tt(T0, T1, T2, V(0.25, 0.25, 0), V(0.25, 0.25, 1), V(1, 1, 1)), 1);
  double up = nextafter(0.0, 1.0); /* the smallest subnormal: Q lifted by one ulp of 0 */
  cr_assert_eq(tt(T0, T1, T2, V(0.25, 0.25, up), V(0.25, 0.25, 1), V(1, 1, 1)), 0);
  /* the same at coordinates near 1e6: P at z = 1e6, Q's vertex one ulp above */
  double z = 1e6, zu = nextafter(1e6, 2e6);
  cr_assert_eq(tt(V(0, 0, z), V(1, 0, z), V(0, 1, z), V(0.25, 0.25, z), V(0.25, 0.25, z + 1), V(1, 1, z + 1)), 1);
  cr_assert_eq(tt(V(0, 0, z), V(1, 0, z), V(0, 1, z), V(0.25, 0.25, zu), V(0.25, 0.25, z + 1), V(1, 1, z + 1)), 0);
  /* vertex on vertex */
  cr_assert_eq(tt(T0, T1, T2, V(1, 0, 0), V(2, 0, 1), V(2, 1, 1)), 1);
  cr_assert_eq(tt(T0, T1, T2, V(nextafter(1.0, 2.0), 0, 0), V(2, 0, 1), V(2, 1, 1)), 0);
}

Test(intersect, touching_along_an_edge_and_near_misses) {
  /* Q's vertex on P's hypotenuse x + y = 1 (0.5 + 0.5 = 1 exactly) */
  cr_assert_eq(tt(T0, T1, T2, V(0.5, 0.5, 0), V(1, 1, 1), V(1, 1, -1)), 1);
  double h = nextafter(0.5, 1.0); /* (h, h): x + y = 1 + 2^-52 > 1, just outside */
  cr_assert_eq(tt(T0, T1, T2, V(h, h, 0), V(1, 1, 1), V(1, 1, -1)), 0);
  /* an edge of Q crossing P's edge y = 0 at (0.5, 0, 0), Q in the half space y <= 0 */
  cr_assert_eq(tt(T0, T1, T2, V(0.5, 0, -1), V(0.5, 0, 1), V(0.5, -1, 0)), 1);
  double m = nextafter(0.0, -1.0);
  cr_assert_eq(tt(T0, T1, T2, V(0.5, m, -1), V(0.5, m, 1), V(0.5, -1, 0)), 0);
  /* an edge of Q lying in P's plane across P's interior */
  cr_assert_eq(tt(T0, T1, T2, V(0.1, 0.1, 0), V(0.3, 0.3, 0), V(0.2, 0.2, 1)), 1);
  /* a proper piercing, and the same triangle moved clear */
  cr_assert_eq(tt(T0, T1, T2, V(0.2, 0.2, -1), V(0.3, 0.2, 1), V(0.2, 0.3, 1)), 1);
  cr_assert_eq(tt(T0, T1, T2, V(2.2, 0.2, -1), V(2.3, 0.2, 1), V(2.2, 0.3, 1)), 0);
}

Test(intersect, coplanar_overlap_touching_and_near_miss) {
  cr_assert_eq(tt(T0, T1, T2, V(0.2, 0.2, 0), V(1.2, 0.2, 0), V(0.2, 1.2, 0)), 1); /* overlap */
  cr_assert_eq(tt(T0, T1, T2, V(0.1, 0.1, 0), V(0.2, 0.1, 0), V(0.1, 0.2, 0)), 1); /* Q inside P */
  cr_assert_eq(tt(T0, T1, T2, V(1, 0, 0), V(2, 0, 0), V(1.5, 1, 0)), 1);           /* at a vertex */
  cr_assert_eq(tt(T0, T1, T2, V(1, 0, 0), V(0, 1, 0), V(1, 1, 0)), 1);             /* along an edge */
  double u = nextafter(1.0, 2.0);
  cr_assert_eq(tt(T0, T1, T2, V(u, 0, 0), V(2, 0, 0), V(1.5, 1, 0)), 0);
  /* the hypotenuse's mirror moved out by one ulp in x and y: x + y > 1 on all of Q */
  double h = nextafter(0.5, 1.0);
  cr_assert_eq(tt(T0, T1, T2, V(h, h, 0), V(2, 1, 0), V(1, 2, 0)), 0);
  cr_assert_eq(tt(T0, T1, T2, V(0.5, 0.5, 0), V(2, 1, 0), V(1, 2, 0)), 1);
  /* coplanar in a tilted plane (x + y + z = 1, exact in binary at these points) */
  cr_assert_eq(tt(V(1, 0, 0), V(0, 1, 0), V(0, 0, 1), V(0.5, 0.5, 0), V(0.5, 0, 0.5), V(0, 0.5, 0.5)), 1);
  cr_assert_eq(tt(V(1, 0, 0), V(0, 1, 0), V(0, 0, 1), V(1, 1, -1), V(2, 0, -1), V(2, 1, -2)), 0);
}

Test(intersect, degenerate_triangles) {
  /* a "triangle" on a segment through P, and moved aside */
  cr_assert_eq(tt(T0, T1, T2, V(0.2, 0.2, -1), V(0.2, 0.2, 1), V(0.2, 0.2, 0.5)), 1);
  cr_assert_eq(tt(T0, T1, T2, V(2, 2, -1), V(2, 2, 1), V(2, 2, 0.5)), 0);
  /* a point triangle on P's edge, and one ulp off it */
  cr_assert_eq(tt(T0, T1, T2, V(0.5, 0, 0), V(0.5, 0, 0), V(0.5, 0, 0)), 1);
  double m = nextafter(0.0, -1.0);
  cr_assert_eq(tt(T0, T1, T2, V(0.5, m, 0), V(0.5, m, 0), V(0.5, m, 0)), 0);
  /* two collinear segment-triangles overlapping on a line, and apart on it */
  cr_assert_eq(tt(V(0, 0, 0), V(1, 1, 1), V(2, 2, 2), V(1.5, 1.5, 1.5), V(3, 3, 3), V(4, 4, 4)), 1);
  cr_assert_eq(tt(V(0, 0, 0), V(1, 1, 1), V(2, 2, 2), V(2.5, 2.5, 2.5), V(3, 3, 3), V(4, 4, 4)), 0);
}

/* exact integer determinants: gcc's 128-bit integers */
__extension__ typedef __int128 i128;
static int sign128(i128 v) { return (v > 0) - (v < 0); }

Test(intersect, orient2d_exact_where_doubles_fail) {
  /* Shewchuk's example: points near (0.5, 0.5) on a grid of 2^-53 against
   * the line through (12, 12) and (24, 24). Scaled by 2^53 every coordinate
   * is an integer below 2^58, so the determinant is exact in __int128. */
  const double s = 0x1p53;
  int wrong_naive = 0;
  for (int i = 0; i < 64; i++)
    for (int j = 0; j < 64; j++) {
      double p[2] = {0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53}, q[2] = {12, 12}, r[2] = {24, 24};
      i128 px = (i128)(p[0] * s), py = (i128)(p[1] * s), qx = (i128)(q[0] * s), qy = (i128)(q[1] * s),
           rx = (i128)(r[0] * s), ry = (i128)(r[1] * s);
      i128 det = (px - rx) * (qy - ry) - (py - ry) * (qx - rx); /* det[p - r; q - r] */
      int want = sign128(det);
      cr_assert_eq(cb_orient2d(p, q, r), want, "orient2d at (%d, %d)", i, j);
      double naive = (p[0] - r[0]) * (q[1] - r[1]) - (p[1] - r[1]) * (q[0] - r[0]);
      wrong_naive += ((naive > 0) - (naive < 0)) != want;
    }
  cr_assert_gt(wrong_naive, 0, "the example should defeat plain double evaluation");
}

Test(intersect, orient3d_against_int128) {
  /* random integer points (|coordinate| < 2^30) scaled by a power of two, and
   * nearly coplanar ones (d = a + b - c + a one-unit nudge) */
  cb_rng g = cb_rng_seed(7);
  for (int it = 0; it < 4000; it++) {
    long long P[4][3];
    for (int k = 0; k < 3; k++)
      for (int i = 0; i < 3; i++) P[i][k] = (long long)(cb_rng_next(&g) >> 34) - (1LL << 29);
    for (int k = 0; k < 3; k++)
      P[3][k] = P[0][k] + P[1][k] - P[2][k] + (it % 3 == 0 && k == 1 ? (long long)(it % 5) - 2 : 0);
    double scale = ldexp(1.0, (int)(it % 41) - 20), D[4][3];
    for (int i = 0; i < 4; i++)
      for (int k = 0; k < 3; k++) D[i][k] = (double)P[i][k] * scale;
    i128 m[3][3];
    for (int i = 0; i < 3; i++)
      for (int k = 0; k < 3; k++) m[i][k] = (i128)(P[i][k] - P[3][k]);
    i128 det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    cr_assert_eq(cb_orient3d(D[0], D[1], D[2], D[3]), sign128(det), "case %d", it);
  }
  cr_assert_gt(cb_orient_exact_calls(), 0, "the coplanar cases should reach the exact path");
}

/* An independent test for triangles in general position: Q meets P iff an
 * edge of one crosses the interior of the other; computed in doubles with the
 * segment-plane parameter and barycentric coordinates, and -1 when a quantity
 * is within a wide margin of its threshold (undecided: skipped). */
static int edge_cross(const double *a, const double *b, const double *p, const double *q, const double *r) {
  double u[3], v[3], n[3];
  for (int k = 0; k < 3; k++) {
    u[k] = q[k] - p[k];
    v[k] = r[k] - p[k];
  }
  n[0] = u[1] * v[2] - u[2] * v[1];
  n[1] = u[2] * v[0] - u[0] * v[2];
  n[2] = u[0] * v[1] - u[1] * v[0];
  double da = 0, db = 0, nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; k++) {
    da += n[k] * (a[k] - p[k]);
    db += n[k] * (b[k] - p[k]);
  }
  const double tol = 1e-9 * nn;
  if (fabs(da) < tol || fabs(db) < tol) return -1;
  if ((da > 0) == (db > 0)) return 0;
  double t = da / (da - db), x[3];
  for (int k = 0; k < 3; k++) x[k] = a[k] + t * (b[k] - a[k]);
  /* barycentric coordinates of x: areas against n */
  double w[3];
  const double *tri[3] = {p, q, r};
  for (int i = 0; i < 3; i++) {
    const double *s0 = tri[(i + 1) % 3], *s1 = tri[(i + 2) % 3];
    double e0[3], e1[3];
    for (int k = 0; k < 3; k++) {
      e0[k] = s0[k] - x[k];
      e1[k] = s1[k] - x[k];
    }
    double c[3] = {e0[1] * e1[2] - e0[2] * e1[1], e0[2] * e1[0] - e0[0] * e1[2], e0[0] * e1[1] - e0[1] * e1[0]};
    w[i] = (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / (nn * nn);
  }
  for (int i = 0; i < 3; i++)
    if (fabs(w[i]) < 1e-9) return -1;
  return w[0] > 0 && w[1] > 0 && w[2] > 0;
}

static int reference_tt(const double *const *P, const double *const *Q) {
  int any = 0;
  for (int side = 0; side < 2; side++) {
    const double *const *A = side ? Q : P, *const *B = side ? P : Q;
    for (int k = 0; k < 3; k++) {
      int r = edge_cross(A[k], A[(k + 1) % 3], B[0], B[1], B[2]);
      if (r < 0) return -1;
      any |= r;
    }
  }
  return any;
}

Test(intersect, random_pairs_against_an_independent_test) {
  cb_rng g = cb_rng_seed(11);
  int decided = 0, hits = 0;
  for (int it = 0; it < 20000; it++) {
    double p[9], q[9];
    for (int k = 0; k < 9; k++) {
      p[k] = cb_rng_uniform(&g);
      q[k] = cb_rng_uniform(&g) + 0.3;
    }
    const double *P[3] = {p, p + 3, p + 6}, *Q[3] = {q, q + 3, q + 6};
    int want = reference_tt(P, Q);
    if (want < 0) continue;
    decided++;
    hits += want;
    cr_assert_eq(cb_tri_tri_intersect(p, p + 3, p + 6, q, q + 3, q + 6), want, "pair %d", it);
  }
  cr_assert_gt(decided, 19000);
  cr_assert_gt(hits, 1000, "too few intersecting pairs to mean anything (%d)", hits);
  cr_assert_lt(hits, decided - 1000);
}

/* ---- the instrument ---- */

static long brute_count(const cb_mesh *m, const double *x) {
  long n = 0;
  for (int i = 0; i < m->nt; i++)
    for (int j = i + 1; j < m->nt; j++) {
      const int *a = m->tri + 3 * i, *b = m->tri + 3 * j;
      int adj = 0;
      for (int s = 0; s < 3; s++)
        for (int t = 0; t < 3; t++) adj |= a[s] == b[t];
      if (adj) continue;
      n += cb_tri_tri_intersect(x + 3 * a[0], x + 3 * a[1], x + 3 * a[2], x + 3 * b[0], x + 3 * b[1], x + 3 * b[2]);
    }
  return n;
}

static cb_mesh grid(int n, int m) {
  cb_grid_params gp = cb_grid_params_default();
  gp.n = n;
  gp.m = m;
  gp.plane = CB_PLANE_XY;
  gp.size[0] = n - 1; /* unit cells: vertex (i, j) at (i, j) - centre */
  gp.size[1] = m - 1;
  cb_mesh mesh = {0};
  cr_assert_eq(cb_mesh_grid(&gp, &mesh), 0);
  return mesh;
}

Test(intersections, random_meshes_match_brute_force) {
  cb_rng g = cb_rng_seed(3);
  long total = 0;
  for (int round = 0; round < 6; round++) {
    cb_mesh m = grid(8 + round, 7);
    /* crumple: every vertex moved at random by up to 1.5 cells (many crossings) */
    for (int i = 0; i < 3 * m.nv; i++) m.x[i] += 3.0 * (cb_rng_uniform(&g) - 0.5);
    if (round == 5) /* and a flat one whose vertices sit on a coarse grid: touching boxes, coplanar pairs */
      for (int i = 0; i < m.nv; i++) {
        m.x[3 * i] = floor(m.x[3 * i]);
        m.x[3 * i + 1] = floor(m.x[3 * i + 1]);
        m.x[3 * i + 2] = 0;
      }
    cb_intersections ix;
    cr_assert_eq(cb_intersections_init(&ix, &m), 0);
    long got;
    cr_assert_eq(cb_intersections_count(&ix, m.x, &got), 0);
    long want = brute_count(&m, m.x);
    cr_assert_eq(got, want, "round %d: %ld intersecting pairs, brute force %ld", round, got, want);
    total += want;
    cb_intersections_free(&ix);
    cb_mesh_free(&m);
  }
  cr_assert_gt(total, 50, "the random meshes should intersect (%ld)", total);
}

/* A 9 x 21 grid folded at row 10 onto itself with a gap g: rows j > 10 go
 * back over rows 20 - j at height g. Intersection-free. Then one top vertex,
 * far from the fold and the border, is pushed through the bottom layer to
 * z = -g: each of its six triangles now crosses z = 0 over the bottom
 * layer's interior, so each meets at least one bottom triangle (and no pair
 * shares a vertex), and the count is at least 6. */
Test(intersections, folded_sheet_with_a_known_crossing) {
  cb_mesh m = grid(9, 21);
  const double g = 0.25;
  for (int j = 0; j < 21; j++)
    for (int i = 0; i < 9; i++) {
      double *p = m.x + 3 * (j * 9 + i);
      p[0] = i;
      p[1] = j <= 10 ? j : 20 - j + 0.3; /* the top layer shifted by 0.3 cells: no vertex above a vertex */
      p[2] = j <= 10 ? 0 : g;
    }
  /* the fold row 10 -> 11 climbs from z = 0 to g over 0.7 cells: a ramp, no crossing */
  cb_intersections ix;
  cr_assert_eq(cb_intersections_init(&ix, &m), 0);
  long got;
  cr_assert_eq(cb_intersections_count(&ix, m.x, &got), 0);
  cr_assert_eq(got, 0, "the folded sheet with a gap should not intersect (%ld)", got);
  cr_assert_eq(brute_count(&m, m.x), 0);
  int v = 15 * 9 + 4; /* top layer, row 15 (above bottom row 5.3), column 4 */
  m.x[3 * v + 2] = -g;
  cr_assert_eq(cb_intersections_count(&ix, m.x, &got), 0);
  long want = brute_count(&m, m.x);
  cr_assert_eq(got, want);
  cr_assert_geq(got, 6, "six triangles cross the bottom layer (%ld pairs)", got);
  cr_assert_leq(got, 6 * 8, "each crossing is shorter than a cell: a handful of bottom triangles each (%ld)", got);
  /* back in place: none again (the tree refits) */
  m.x[3 * v + 2] = g;
  cr_assert_eq(cb_intersections_count(&ix, m.x, &got), 0);
  cr_assert_eq(got, 0);
  cb_intersections_free(&ix);
  cb_mesh_free(&m);
}

Test(intersections, nan_position_is_an_error_not_a_count) {
  cb_mesh m = grid(4, 4);
  cb_intersections ix;
  cr_assert_eq(cb_intersections_init(&ix, &m), 0);
  m.x[7] = NAN;
  long got = 123;
  cr_assert_eq(cb_intersections_count(&ix, m.x, &got), CB_EINVAL);
  cr_assert_eq(got, -1);
  cr_assert(strstr(cb_error_message(), "not finite"), "message: %s", cb_error_message());
  m.x[7] = INFINITY;
  cr_assert_eq(cb_intersections_count(&ix, m.x, &got), CB_EINVAL);
  cb_intersections_free(&ix);
  cb_mesh_free(&m);
}
