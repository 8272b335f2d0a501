/* The broad phase (include/clothbench/broadphase.h): its triangle pairs and
 * its VF/EE candidates against brute-force enumerations that build every
 * primitive's swept box directly from the positions (no tree, no ownership),
 * for self-contact and for two meshes, after builds and after refits; the
 * rebuild rule; no allocation in an update or a query; bad input. The float
 * boxes' ties (coordinates equal in float, not in double) against brute
 * force in double, and the candidate sets against the code before the float
 * boxes and the ring lists (bench/support/bp_old.c, linked in). */
#include <criterion/criterion.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bp_old.h"
#include "rng.h"
#include "support.h"
#include <clothbench/broadphase.h>
#include <clothbench/mesh.h>
#include <clothbench/status.h>
#include <clothbench/distance.h>

static cb_mesh grid(int n, int m, double size) {
  cb_grid_params gp = cb_grid_params_default();
  gp.n = n;
  gp.m = m;
  gp.size[0] = gp.size[1] = size;
  gp.plane = CB_PLANE_XY;
  cb_mesh mesh = {0};
  cr_assert_eq(cb_mesh_grid(&gp, &mesh), 0);
  return mesh;
}

/* the box of points pts (x0 and x1), grown by h a side */
static void box(const double *x0, const double *x1, const int *pts, int n, double h, double *b) {
  for (int k = 0; k < 3; k++) {
    b[k] = INFINITY;
    b[3 + k] = -INFINITY;
    for (int c = 0; c < n; c++)
      for (int s = 0; s < 2; s++) {
        const double *x = s ? x1 : x0;
        b[k] = fmin(b[k], x[3 * pts[c] + k]);
        b[3 + k] = fmax(b[3 + k], x[3 * pts[c] + k]);
      }
    b[k] -= h;
    b[3 + k] += h;
  }
}

static int overlaps(const double *a, const double *b) {
  for (int k = 0; k < 3; k++)
    if (a[k] > b[3 + k] || b[k] > a[3 + k]) return 0;
  return 1;
}

static int cmp_pair(const void *a, const void *b) {
  const long long *x = a, *y = b;
  return (*x > *y) - (*x < *y);
}

/* pairs as sorted 64-bit keys u * 2^32 + v */
static long long *keys(const int *pairs, long n) {
  long long *k = malloc((size_t)(n > 0 ? n : 1) * sizeof *k);
  for (long i = 0; i < n; i++) k[i] = (long long)pairs[2 * i] * 4294967296LL + pairs[2 * i + 1];
  qsort(k, (size_t)n, sizeof *k, cmp_pair);
  return k;
}

static void same_sets(const char *what, const int *got, long ngot, const int *want, long nwant) {
  cr_assert_eq(ngot, nwant, "%s: %ld pairs, brute force %ld", what, ngot, nwant);
  long long *a = keys(got, ngot), *b = keys(want, nwant);
  for (long i = 0; i < ngot; i++) cr_assert_eq(a[i], b[i], "%s: pair %ld differs", what, i);
  free(a);
  free(b);
}

typedef struct collect {
  int *p;
  long n, cap;
} collect;

static int collect_visit(void *ctx, int i, int j) {
  collect *c = ctx;
  if (c->n < c->cap) {
    c->p[2 * c->n] = i;
    c->p[2 * c->n + 1] = j;
  }
  c->n++;
  return 0;
}

/* Brute force self candidates of mesh m with edges E (ne), thickness d */
static void brute_self(const cb_mesh *m, const int *E, int ne, const double *x0, const double *x1, double d, int **vf,
                       long *nvf, int **ee, long *nee) {
  double h = 0.5 * d;
  *vf = malloc(sizeof(int) * 2 * (size_t)m->nv * (size_t)m->nt);
  *ee = malloc(sizeof(int) * 2 * (size_t)ne * (size_t)ne);
  *nvf = *nee = 0;
  for (int v = 0; v < m->nv; v++) {
    double bv[6], bf[6];
    box(x0, x1, &v, 1, h, bv);
    for (int f = 0; f < m->nt; f++) {
      const int *t = m->tri + 3 * f;
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      box(x0, x1, t, 3, h, bf);
      if (!overlaps(bv, bf)) continue;
      (*vf)[2 * *nvf] = v;
      (*vf)[2 * *nvf + 1] = f;
      (*nvf)++;
    }
  }
  for (int a = 0; a < ne; a++)
    for (int b = 0; b < ne; b++) {
      if (a == b) continue;
      const int *ea = E + 2 * a, *eb = E + 2 * b;
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      double ba[6], bb[6];
      box(x0, x1, ea, 2, h, ba);
      box(x0, x1, eb, 2, h, bb);
      if (!overlaps(ba, bb)) continue;
      (*ee)[2 * *nee] = a;
      (*ee)[2 * *nee + 1] = b;
      (*nee)++;
    }
}

/* EE pairs are unordered: (a, b) and (b, a) are one pair. Brute force lists
 * both orders; the broad phase one. Expand the broad phase's to both orders. */
static int *both_orders(const int *p, long n) {
  int *q = malloc(sizeof(int) * 4 * (size_t)(n > 0 ? n : 1));
  for (long i = 0; i < n; i++) {
    q[4 * i] = p[2 * i];
    q[4 * i + 1] = p[2 * i + 1];
    q[4 * i + 2] = p[2 * i + 1];
    q[4 * i + 3] = p[2 * i];
  }
  return q;
}

/* a crumpled sheet: random displacement of every vertex, and a motion */
static void crumple(cb_rng *g, const cb_mesh *m, double amp, double *x0, double *x1, double step) {
  for (int i = 0; i < 3 * m->nv; i++) {
    x0[i] = m->x[i] + amp * (cb_rng_uniform(g) - 0.5);
    x1[i] = x0[i] + step * (cb_rng_uniform(g) - 0.5);
  }
}

static void check_self(const cb_mesh *m, cb_broadphase *bp, const double *x0, const double *x1, double d) {
  int ne;
  const int *E = cb_broadphase_edges(bp, &ne);
  int *vf, *ee;
  long nvf, nee;
  brute_self(m, E, ne, x0, x1, d, &vf, &nvf, &ee, &nee);
  cb_candidates c;
  cr_assert_eq(cb_candidates_alloc(nvf + 10, 0, nee + 10, &c), 0);
  cr_assert_eq(cb_broadphase_self_candidates(bp, &c), 0, "%s", cb_error_message());
  same_sets("self vf", c.vf, c.nvf, vf, nvf);
  int *e2 = both_orders(c.ee, c.nee);
  same_sets("self ee (both orders)", e2, 2 * c.nee, ee, nee);
  free(e2);
  free(vf);
  free(ee);
  cb_candidates_free(&c);
}

Test(broadphase, self_candidates_match_brute_force_after_build_and_refit) {
  cb_mesh m = grid(9, 8, 1.0);
  int nv = m.nv;
  double *x0 = malloc(sizeof(double) * 3 * (size_t)nv), *x1 = malloc(sizeof(double) * 3 * (size_t)nv);
  cb_rng g = cb_rng_seed(5);
  const double d = 0.03;
  for (int leaf = 1; leaf <= 5; leaf += 2) {
    cb_broadphase_params p = cb_broadphase_params_default();
    p.thickness = d;
    p.leaf_size = leaf;
    cb_broadphase *bp;
    cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
    int ne;
    cb_broadphase_edges(bp, &ne);
    cr_assert_eq(ne, 8 * 8 + 9 * 7 + 8 * 7, "edges of a 9 x 8 grid: horizontal, vertical, diagonal");
    for (int round = 0; round < 4; round++) {
      crumple(&g, &m, 0.4, x0, x1, 0.05);
      cr_assert_eq(cb_broadphase_update(bp, x0, round == 3 ? NULL : x1), 0);
      check_self(&m, bp, x0, round == 3 ? x0 : x1, d);
    }
    cb_broadphase_free(bp);
  }
  free(x0);
  free(x1);
  cb_mesh_free(&m);
}

Test(broadphase, triangle_pairs_match_brute_force) {
  cb_mesh m = grid(7, 7, 1.0);
  double *x0 = malloc(sizeof(double) * 3 * (size_t)m.nv), *x1 = malloc(sizeof(double) * 3 * (size_t)m.nv);
  cb_rng g = cb_rng_seed(9);
  crumple(&g, &m, 0.5, x0, x1, 0.1);
  cb_broadphase_params p = cb_broadphase_params_default();
  p.thickness = 0.02;
  cb_broadphase *bp;
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
  cr_assert_eq(cb_broadphase_update(bp, x0, x1), 0);
  for (int skip = 0; skip < 2; skip++) {
    long cap = (long)m.nt * m.nt;
    int *want = malloc(sizeof(int) * 2 * (size_t)cap);
    long nwant = 0;
    for (int i = 0; i < m.nt; i++)
      for (int j = i + 1; j < m.nt; j++) {
        double bi[6], bj[6];
        box(x0, x1, m.tri + 3 * i, 3, 0.01, bi);
        box(x0, x1, m.tri + 3 * j, 3, 0.01, bj);
        int adj = 0;
        for (int s = 0; s < 3; s++)
          for (int t = 0; t < 3; t++) adj |= m.tri[3 * i + s] == m.tri[3 * j + t];
        if (overlaps(bi, bj) && !(skip && adj)) {
          want[2 * nwant] = i;
          want[2 * nwant + 1] = j;
          nwant++;
        }
      }
    collect c = {malloc(sizeof(int) * 2 * (size_t)cap), 0, cap};
    cr_assert_eq(cb_broadphase_self_pairs(bp, skip, collect_visit, &c), 0);
    same_sets(skip ? "non-adjacent triangle pairs" : "triangle pairs", c.p, c.n, want, nwant);
    free(c.p);
    free(want);
  }
  cb_broadphase_free(bp);
  free(x0);
  free(x1);
  cb_mesh_free(&m);
}

Test(broadphase, cloth_against_an_obstacle_matches_brute_force) {
  cb_mesh cloth = grid(8, 8, 1.0), obst = grid(5, 6, 1.2);
  cb_rng g = cb_rng_seed(13);
  double *a0 = malloc(sizeof(double) * 3 * (size_t)cloth.nv), *a1 = malloc(sizeof(double) * 3 * (size_t)cloth.nv);
  double *b0 = malloc(sizeof(double) * 3 * (size_t)obst.nv), *b1 = malloc(sizeof(double) * 3 * (size_t)obst.nv);
  crumple(&g, &cloth, 0.3, a0, a1, 0.1);
  crumple(&g, &obst, 0.3, b0, b1, 0.0);
  const double d = 0.05;
  cb_broadphase_params p = cb_broadphase_params_default();
  p.thickness = d;
  cb_broadphase *A, *B;
  cr_assert_eq(cb_broadphase_alloc(cloth.nv, cloth.nt, cloth.tri, &p, &A), 0);
  cr_assert_eq(cb_broadphase_alloc(obst.nv, obst.nt, obst.tri, &p, &B), 0);
  cr_assert_eq(cb_broadphase_update(A, a0, a1), 0);
  cr_assert_eq(cb_broadphase_update(B, b0, b1), 0);
  int nea, neb;
  const int *EA = cb_broadphase_edges(A, &nea), *EB = cb_broadphase_edges(B, &neb);
  long cap = 200000;
  int *vf = malloc(sizeof(int) * 2 * (size_t)cap), *fv = malloc(sizeof(int) * 2 * (size_t)cap),
      *ee = malloc(sizeof(int) * 2 * (size_t)cap);
  long nvf = 0, nfv = 0, nee = 0;
  double h = d / 2, bx[6], by[6];
  for (int v = 0; v < cloth.nv; v++)
    for (int f = 0; f < obst.nt; f++) {
      box(a0, a1, &v, 1, h, bx);
      box(b0, b1, obst.tri + 3 * f, 3, h, by);
      if (overlaps(bx, by)) vf[2 * nvf] = v, vf[2 * nvf + 1] = f, nvf++;
    }
  for (int v = 0; v < obst.nv; v++)
    for (int f = 0; f < cloth.nt; f++) {
      box(b0, b1, &v, 1, h, bx);
      box(a0, a1, cloth.tri + 3 * f, 3, h, by);
      if (overlaps(bx, by)) fv[2 * nfv] = v, fv[2 * nfv + 1] = f, nfv++;
    }
  for (int e = 0; e < nea; e++)
    for (int k = 0; k < neb; k++) {
      box(a0, a1, EA + 2 * e, 2, h, bx);
      box(b0, b1, EB + 2 * k, 2, h, by);
      if (overlaps(bx, by)) ee[2 * nee] = e, ee[2 * nee + 1] = k, nee++;
    }
  cr_assert_gt(nvf + nfv + nee, 100, "the meshes should be close (%ld)", nvf + nfv + nee);
  cb_candidates c;
  cr_assert_eq(cb_candidates_alloc(cap, cap, cap, &c), 0);
  cr_assert_eq(cb_broadphase_cross_candidates(A, B, &c), 0, "%s", cb_error_message());
  same_sets("cloth vertex - obstacle face", c.vf, c.nvf, vf, nvf);
  same_sets("obstacle vertex - cloth face", c.fv, c.nfv, fv, nfv);
  same_sets("edge - edge", c.ee, c.nee, ee, nee);
  cr_assert_neq(cb_broadphase_cross_candidates(A, A, &c), 0, "a cross query of one tree");
  cb_candidates_free(&c);
  free(vf);
  free(fv);
  free(ee);
  free(a0);
  free(a1);
  free(b0);
  free(b1);
  cb_broadphase_free(A);
  cb_broadphase_free(B);
  cb_mesh_free(&cloth);
  cb_mesh_free(&obst);
}

Test(broadphase, refit_then_rebuild_when_the_sah_cost_grows) {
  cb_mesh m = grid(20, 20, 1.0);
  cb_broadphase_params p = cb_broadphase_params_default();
  p.rebuild_ratio = 1.5;
  cb_broadphase *bp;
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
  cr_assert_eq(cb_broadphase_update(bp, m.x, NULL), 0);
  const cb_broadphase_stats *s = cb_broadphase_stats_get(bp);
  cr_assert_eq(s->rebuilt, 1);
  cr_assert_eq(s->rebuilds, 1);
  /* balanced: 800 triangles, leaves of <= 4, depth <= log2(800/4) + 2 */
  cr_assert_leq(s->depth, (int)ceil(log2(800.0 / 4)) + 2);
  /* a rigid translation: the same tree, the same cost (translation changes no area) */
  double *x = malloc(sizeof(double) * 3 * (size_t)m.nv);
  for (int i = 0; i < 3 * m.nv; i++) x[i] = m.x[i] + (i % 3 == 2 ? 0.25 : 0.0);
  cr_assert_eq(cb_broadphase_update(bp, x, NULL), 0);
  cr_assert_eq(s->rebuilt, 0);
  cr_assert_float_eq(s->sah_cost, s->sah_built, 1e-12 * s->sah_built);
  /* scatter the vertices (vertex v takes the place of vertex 7919 v mod 400,
   * a permutation): a refitted tree's boxes now span the sheet, its cost
   * grows far past 1.5 x, and it rebuilds */
  for (int v = 0; v < m.nv; v++)
    for (int k = 0; k < 3; k++) x[3 * v + k] = m.x[3 * ((v * 7919) % m.nv) + k];
  cr_assert_eq(cb_broadphase_update(bp, x, NULL), 0);
  cr_assert_eq(s->rebuilt, 1, "cost %g, built %g", s->sah_cost, s->sah_built);
  cr_assert_eq(s->rebuilds, 2);
  cb_broadphase_invalidate(bp);
  cr_assert_eq(cb_broadphase_update(bp, x, NULL), 0);
  cr_assert_eq(s->rebuilt, 1);
  free(x);
  cb_broadphase_free(bp);
  cb_mesh_free(&m);
}

Test(broadphase, update_and_query_do_not_allocate) {
  cb_mesh m = grid(12, 12, 1.0);
  cb_broadphase_params p = cb_broadphase_params_default();
  p.thickness = 0.1;
  cb_broadphase *bp;
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
  cb_candidates c;
  cr_assert_eq(cb_candidates_alloc(100000, 0, 100000, &c), 0);
  cb_alloc_fail_at(LONG_MAX); /* count every cb_malloc/cb_calloc from here, fail none */
  cr_assert_eq(cb_broadphase_update(bp, m.x, NULL), 0);
  cr_assert_eq(cb_broadphase_update(bp, m.x, m.x), 0);
  cr_assert_eq(cb_broadphase_self_candidates(bp, &c), 0);
  long n = cb_alloc_count();
  cb_alloc_fail_at(0);
  cr_assert_eq(n, 0, "%ld allocations in update/query", n);
  cb_candidates_free(&c);
  cb_broadphase_free(bp);
  cb_mesh_free(&m);
}

Test(broadphase, capacity_overflow_counts_on_and_says_so) {
  cb_mesh m = grid(10, 10, 1.0);
  cb_broadphase_params p = cb_broadphase_params_default();
  p.thickness = 0.5; /* large: many candidates */
  cb_broadphase *bp;
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
  cr_assert_eq(cb_broadphase_update(bp, m.x, NULL), 0);
  cb_candidates big, small;
  cr_assert_eq(cb_candidates_alloc(1000000, 0, 1000000, &big), 0);
  cr_assert_eq(cb_candidates_alloc(10, 0, 10, &small), 0);
  cr_assert_eq(cb_broadphase_self_candidates(bp, &big), 0);
  cr_assert_eq(cb_broadphase_self_candidates(bp, &small), CB_ENOMEM);
  cr_assert(strstr(cb_error_message(), "capacity"), "%s", cb_error_message());
  cr_assert_eq(small.nvf, big.nvf, "the count goes on past the capacity");
  cr_assert_eq(small.nee, big.nee);
  cb_candidates_free(&big);
  cb_candidates_free(&small);
  cb_broadphase_free(bp);
  cb_mesh_free(&m);
}

Test(broadphase, bad_input) {
  cb_mesh m = grid(4, 4, 1.0);
  cb_broadphase *bp = (cb_broadphase *)1;
  cb_broadphase_params raw = {0};
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &raw, &bp), CB_EINVAL, "params without defaults");
  cr_assert_null(bp);
  cb_broadphase_params p = cb_broadphase_params_default();
  p.thickness = NAN;
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), CB_EINVAL);
  p = cb_broadphase_params_default();
  int bad[3] = {0, 1, 99};
  cr_assert_eq(cb_broadphase_alloc(m.nv, 1, bad, &p, &bp), CB_EINVAL);
  int rep[3] = {0, 1, 1};
  cr_assert_eq(cb_broadphase_alloc(m.nv, 1, rep, &p, &bp), CB_EINVAL);
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
  collect c = {NULL, 0, 0};
  cr_assert_eq(cb_broadphase_self_pairs(bp, 1, collect_visit, &c), CB_EINVAL, "query before an update");
  double *x = malloc(sizeof(double) * 3 * (size_t)m.nv);
  memcpy(x, m.x, sizeof(double) * 3 * (size_t)m.nv);
  x[5] = NAN;
  cr_assert_eq(cb_broadphase_update(bp, x, NULL), CB_EINVAL);
  cr_assert(strstr(cb_error_message(), "not finite"));
  cr_assert_eq(cb_broadphase_update(bp, m.x, x), CB_EINVAL, "NaN at the end of the step");
  free(x);
  cb_broadphase_free(bp);
  cb_broadphase_free(NULL);
  cb_mesh_free(&m);
}

/* ---- true contacts: every pair within d at the end of the step is a candidate ---- */

static int has_pair(const int *p, long n, int a, int b, int unordered) {
  for (long i = 0; i < n; i++)
    if ((p[2 * i] == a && p[2 * i + 1] == b) || (unordered && p[2 * i] == b && p[2 * i + 1] == a)) return 1;
  return 0;
}

/* The pairs of non-adjacent primitives whose distance at x (by the distance
 * module's classified cases, not by boxes) is below d, against the
 * candidates c: how many true pairs there are, and how many c lacks. */
static void true_contacts(const cb_mesh *m, const int *E, int ne, const double *x, double d, const cb_candidates *c,
                          long *ntrue, long *missing) {
  *ntrue = *missing = 0;
  double q[12];
  cb_distance_case dc;
  for (int v = 0; v < m->nv; v++)
    for (int f = 0; f < m->nt; f++) {
      const int *t = m->tri + 3 * f;
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      int id[4] = {v, t[0], t[1], t[2]};
      for (int k = 0; k < 4; k++) memcpy(q + 3 * k, x + 3 * id[k], 3 * sizeof(double));
      cr_assert_eq(cb_distance_point_triangle_case(q, &dc), 0);
      if (cb_distance_case_eval(&dc, 4, q, NULL, NULL) >= d * d) continue;
      (*ntrue)++;
      *missing += !has_pair(c->vf, c->nvf, v, f, 0);
    }
  for (int a = 0; a < ne; a++)
    for (int b = a + 1; b < ne; b++) {
      const int *ea = E + 2 * a, *eb = E + 2 * b;
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      int id[4] = {ea[0], ea[1], eb[0], eb[1]};
      for (int k = 0; k < 4; k++) memcpy(q + 3 * k, x + 3 * id[k], 3 * sizeof(double));
      cr_assert_eq(cb_distance_edge_edge_case(q, &dc), 0);
      if (cb_distance_case_eval(&dc, 4, q, NULL, NULL) >= d * d) continue;
      (*ntrue)++;
      *missing += !has_pair(c->ee, c->nee, a, b, 1);
    }
}

/* A sheet folded over itself: rows below n/2 flat at z = 0, the rows above
 * turned back over them at height gap (shifted by h/2 in y), jittered. */
static void fold(cb_rng *g, const cb_mesh *m, int n, double gap, double *x) {
  double h = 1.0 / (n - 1);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double *p = x + 3 * (j * n + i);
      int top = j >= n / 2;
      p[0] = m->x[3 * (j * n + i)] + 0.1 * h * (cb_rng_uniform(g) - 0.5);
      p[1] = (top ? (n - 1 - j) * h + 0.5 * h : j * h) + 0.1 * h * (cb_rng_uniform(g) - 0.5);
      p[2] = (top ? gap : 0.0) + 0.1 * h * (cb_rng_uniform(g) - 0.5);
    }
}

Test(broadphase, every_true_contact_is_a_candidate_folded_and_random) {
  const int n = 12;
  cb_mesh m = grid(n, n, 1.0);
  double h = 1.0 / (n - 1), *x0 = malloc(sizeof(double) * 3 * (size_t)m.nv),
         *x1 = malloc(sizeof(double) * 3 * (size_t)m.nv);
  cb_rng g = cb_rng_seed(21);
  for (int mesh = 0; mesh < 4; mesh++) {
    double d;
    if (mesh < 2) { /* folded: the top layer comes down from 0.5 h to 0.15 h, d = 0.25 h */
      fold(&g, &m, n, 0.5 * h, x0);
      for (int v = 0; v < m.nv; v++) {
        memcpy(x1 + 3 * v, x0 + 3 * v, 3 * sizeof(double));
        if (v / n >= n / 2) x1[3 * v + 2] -= 0.35 * h;
      }
      d = 0.25 * h;
    } else { /* crumpled at random: crossings and near misses everywhere */
      crumple(&g, &m, 0.6, x0, x1, 0.1);
      d = 0.04;
    }
    cb_broadphase_params p = cb_broadphase_params_default();
    p.thickness = d;
    p.leaf_size = 1 + 3 * (mesh & 1);
    cb_broadphase *bp;
    cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
    cr_assert_eq(cb_broadphase_update(bp, x0, x1), 0);
    int ne;
    const int *E = cb_broadphase_edges(bp, &ne);
    cb_candidates c;
    cr_assert_eq(cb_candidates_alloc(200000, 0, 400000, &c), 0);
    cr_assert_eq(cb_broadphase_self_candidates(bp, &c), 0, "%s", cb_error_message());
    long ntrue, missing;
    true_contacts(&m, E, ne, x1, d, &c, &ntrue, &missing);
    cr_assert_gt(ntrue, 20, "mesh %d: the fixture should have contacts (%ld)", mesh, ntrue);
    cr_assert_eq(missing, 0, "mesh %d: %ld of %ld true contacts are not candidates", mesh, missing, ntrue);
    /* the check's own fixture: a broad phase for a smaller d (the boxes not
     * grown) lacks some of the pairs within d, and the check says so */
    cb_broadphase_params p0 = p;
    p0.thickness = 0.0;
    cb_broadphase *b0;
    cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p0, &b0), 0);
    cr_assert_eq(cb_broadphase_update(b0, x0, x1), 0);
    cr_assert_eq(cb_broadphase_self_candidates(b0, &c), 0);
    true_contacts(&m, E, ne, x1, d, &c, &ntrue, &missing);
    cr_assert_gt(missing, 0, "mesh %d: thickness 0 should miss some of the %ld pairs within d", mesh, ntrue);
    cb_broadphase_free(b0);
    cb_candidates_free(&c);
    cb_broadphase_free(bp);
  }
  free(x0);
  free(x1);
  cb_mesh_free(&m);
}

/* ---- float boxes: ties decided in double; the old code's sets ----------- */

/* Two separate triangles, the second shifted along axis k so that its box
 * starts gap after the first one's ends at 1.0: with gap = +-2^-40 both ends
 * round to 1.0f (a tie in float), and only the doubles know whether the boxes
 * overlap (gap < 0) or not (gap > 0). d = 0. */
Test(broadphase, float_ties_are_decided_in_double) {
  const double g = 0x1p-40;
  cr_assert_eq((float)1.0, (float)(1.0 + g), "the fixture: 1 and 1 + 2^-40 tie in float");
  cr_assert_eq((float)1.0, (float)(1.0 - g), "the fixture: 1 and 1 - 2^-40 tie in float");
  const int tri[6] = {0, 1, 2, 3, 4, 5};
  /* a triangle spanning [0, 1] on every axis; the copy spans [1 + gap, 2 + gap] on axis k, [0, 1] on the others */
  const double base[9] = {0, 0, 0, 1, 0.5, 0.25, 0.5, 1, 1};
  for (int k = 0; k < 3; k++)
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      double x[18];
      memcpy(x, base, sizeof base);
      memcpy(x + 9, base, sizeof base);
      for (int v = 3; v < 6; v++) x[3 * v + k] += 1.0 + sgn * g;
      cb_broadphase_params p = cb_broadphase_params_default();
      p.leaf_size = 1;
      cb_broadphase *bp;
      cr_assert_eq(cb_broadphase_alloc(6, 2, tri, &p, &bp), 0);
      cr_assert_eq(cb_broadphase_update(bp, x, NULL), 0);
      long cap = 16;
      collect c = {malloc(sizeof(int) * 2 * (size_t)cap), 0, cap};
      cr_assert_eq(cb_broadphase_self_pairs(bp, 0, collect_visit, &c), 0);
      cr_assert_eq(c.n, sgn < 0 ? 1 : 0, "axis %d, gap %+g: %ld triangle pairs, want %d", k, sgn * g, c.n, sgn < 0);
      cb_mesh m = {.nv = 6, .nt = 2, .tri = (int *)tri};
      check_self(&m, bp, x, x, 0.0);
      cb_candidates cc;
      cr_assert_eq(cb_candidates_alloc(16, 0, 16, &cc), 0);
      cr_assert_eq(cb_broadphase_self_candidates(bp, &cc), 0);
      /* overlapping by 2^-40: the vertex at 1 + ... of the copy lies in the first box (vertex 3's box starts
       * at 1 - 2^-40 on axis k and sits inside [0, 1] on the others), so there is at least one candidate */
      if (sgn < 0) cr_assert_gt(cc.nvf + cc.nee, 0, "axis %d: overlapping boxes gave no candidate", k);
      else cr_assert_eq(cc.nvf + cc.nee, 0, "axis %d: separate boxes gave %ld candidates", k, cc.nvf + cc.nee);
      cb_candidates_free(&cc);
      free(c.p);
      cb_broadphase_free(bp);
    }
}

/* A crumpled sheet squeezed into a few float ulps: coordinates 1 + 2^-19 u,
 * u in [0, 1) on a 2^-40 grid, so that the floats take a handful of values
 * per axis and most box comparisons tie in float. Candidates and triangle
 * pairs against brute force in double; the fixture is checked to be one where
 * a float-only test would answer differently. */
Test(broadphase, quantised_coordinates_with_float_ties_match_brute_force) {
  cb_mesh m = grid(8, 8, 1.0);
  double *x0 = malloc(sizeof(double) * 3 * (size_t)m.nv), *x1 = malloc(sizeof(double) * 3 * (size_t)m.nv);
  cb_rng g = cb_rng_seed(77);
  const double d = 0x1p-22;
  for (int r = 0; r < 3; r++) {
    crumple(&g, &m, 0.6, x0, x1, 0.2);
    for (int i = 0; i < 3 * m.nv; i++) {
      x0[i] = 1.0 + ldexp(round(ldexp(x0[i] * 0x1p-19, 40)), -40);
      x1[i] = 1.0 + ldexp(round(ldexp(x1[i] * 0x1p-19, 40)), -40);
    }
    /* the fixture: box comparisons (triangle boxes, grown by d/2) that tie in float but not in double */
    long ties = 0;
    for (int i = 0; i < m.nt; i++)
      for (int j = 0; j < m.nt; j++) {
        double bi[6], bj[6];
        box(x0, x1, m.tri + 3 * i, 3, 0.5 * d, bi);
        box(x0, x1, m.tri + 3 * j, 3, 0.5 * d, bj);
        for (int k = 0; k < 3; k++) ties += bi[k] != bj[3 + k] && (float)bi[k] == (float)bj[3 + k];
      }
    cr_assert_gt(ties, 100, "round %d: the fixture should have float ties (%ld)", r, ties);
    for (int leaf = 1; leaf <= 4; leaf += 3) {
      cb_broadphase_params p = cb_broadphase_params_default();
      p.thickness = d;
      p.leaf_size = leaf;
      cb_broadphase *bp;
      cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &bp), 0);
      cr_assert_eq(cb_broadphase_update(bp, x0, x1), 0);
      check_self(&m, bp, x0, x1, d);
      cb_broadphase_free(bp);
    }
  }
  free(x0);
  free(x1);
  cb_mesh_free(&m);
}

static void same_unordered(const char *what, const int *a, long na, const int *b, long nb) {
  int *a2 = both_orders(a, na), *b2 = both_orders(b, nb);
  same_sets(what, a2, 2 * na, b2, 2 * nb);
  free(a2);
  free(b2);
}

/* The candidates, the triangle pairs and the cross candidates of the code
 * before the float boxes and the ring lists (bench/support/bp_old.c): equal
 * sets (EE pairs unordered), on a folded sheet pressed together (the bench's
 * kind of scene, 3 362 triangles) and a crumpled one, after a build and after
 * refits. */
Test(broadphase, candidates_equal_the_code_before_float_boxes) {
  const int n = 42;
  cb_mesh m = grid(n, n, 1.0);
  double h = 1.0 / (n - 1), *x0 = malloc(sizeof(double) * 3 * (size_t)m.nv),
         *x1 = malloc(sizeof(double) * 3 * (size_t)m.nv), *y0 = malloc(sizeof(double) * 3 * (size_t)m.nv),
         *y1 = malloc(sizeof(double) * 3 * (size_t)m.nv);
  cb_rng g = cb_rng_seed(4242);
  cb_broadphase_params p = cb_broadphase_params_default();
  p.thickness = 0.25 * h;
  cb_broadphase *nb, *nb2;
  cb_oldbp *ob, *ob2;
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &nb), 0);
  cr_assert_eq(cb_oldbp_alloc(m.nv, m.nt, m.tri, &p, &ob), 0);
  cr_assert_eq(cb_broadphase_alloc(m.nv, m.nt, m.tri, &p, &nb2), 0);
  cr_assert_eq(cb_oldbp_alloc(m.nv, m.nt, m.tri, &p, &ob2), 0);
  cb_candidates cn, co;
  cr_assert_eq(cb_candidates_alloc(60L * m.nt, 60L * m.nt, 120L * m.nt, &cn), 0);
  cr_assert_eq(cb_candidates_alloc(60L * m.nt, 60L * m.nt, 120L * m.nt, &co), 0);
  long total = 0;
  for (int round = 0; round < 6; round++) {
    if (round < 3) { /* folded, the top layer coming down */
      fold(&g, &m, n, 0.5 * h, x0);
      for (int v = 0; v < m.nv; v++) {
        memcpy(x1 + 3 * v, x0 + 3 * v, 3 * sizeof(double));
        if (v / n >= n / 2) x1[3 * v + 2] -= (0.1 + 0.1 * round) * h;
      }
    } else {
      crumple(&g, &m, 3 * h, x0, x1, h);
    }
    crumple(&g, &m, 3 * h, y0, y1, h);
    cr_assert_eq(cb_broadphase_update(nb, x0, x1), 0);
    cr_assert_eq(cb_oldbp_update(ob, x0, x1), 0);
    cr_assert_eq(cb_broadphase_update(nb2, y0, y1), 0);
    cr_assert_eq(cb_oldbp_update(ob2, y0, y1), 0);
    cr_assert_eq(cb_broadphase_self_candidates(nb, &cn), 0, "%s", cb_error_message());
    cr_assert_eq(cb_oldbp_self_candidates(ob, &co), 0, "%s", cb_error_message());
    cr_assert_gt(cn.nvf, 100, "round %d: the fixture should have candidates", round);
    same_sets("self vf, new against old", cn.vf, cn.nvf, co.vf, co.nvf);
    same_unordered("self ee, new against old", cn.ee, cn.nee, co.ee, co.nee);
    total += cn.nvf + cn.nee;
    for (int skip = 0; skip < 2; skip++) {
      long cap = 40L * m.nt;
      collect a = {malloc(sizeof(int) * 2 * (size_t)cap), 0, cap}, b = {malloc(sizeof(int) * 2 * (size_t)cap), 0, cap};
      cr_assert_eq(cb_broadphase_self_pairs(nb, skip, collect_visit, &a), 0);
      cr_assert_eq(cb_oldbp_self_pairs(ob, skip, collect_visit, &b), 0);
      cr_assert_leq(a.n, cap);
      same_sets("triangle pairs, new against old", a.p, a.n, b.p, b.n);
      free(a.p);
      free(b.p);
    }
    cr_assert_eq(cb_broadphase_cross_candidates(nb, nb2, &cn), 0, "%s", cb_error_message());
    cr_assert_eq(cb_oldbp_cross_candidates(ob, ob2, &co), 0, "%s", cb_error_message());
    same_sets("cross vf, new against old", cn.vf, cn.nvf, co.vf, co.nvf);
    same_sets("cross fv, new against old", cn.fv, cn.nfv, co.fv, co.nfv);
    same_sets("cross ee, new against old", cn.ee, cn.nee, co.ee, co.nee);
  }
  cr_assert_gt(total, 10000);
  cb_candidates_free(&cn);
  cb_candidates_free(&co);
  cb_broadphase_free(nb);
  cb_broadphase_free(nb2);
  cb_oldbp_free(ob);
  cb_oldbp_free(ob2);
  free(x0);
  free(x1);
  free(y0);
  free(y1);
  cb_mesh_free(&m);
}
