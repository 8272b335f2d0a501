/* Topology by sorted edge triples (lecture, "Topological Construction").
 *
 * The lecture's 5-vertex example is checked entry by entry against the
 * slide. Counts on grids and on hand-built unstructured meshes are checked
 * against Euler's formula, derived here:
 *   V - E + F = chi and 3F = 2E - B  =>  E = 3V - 3 chi - B,
 * so a disk (chi = 1) has E = 3V - 3 - B, an annulus (chi = 0) has E = 3V - B,
 * and k disjoint disks (chi = k) have E = 3V - 3k - B. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"
#include "rng.h"

/* ---- helpers ---------------------------------------------------------------- */

/* A mesh over caller-owned arrays (no line elements, not a grid). */
static cb_mesh wrap(int nv, double *x, int nt, int *tri) {
  cb_mesh m;
  memset(&m, 0, sizeof m);
  m.nv = nv;
  m.x = x;
  m.nt = nt;
  m.tri = tri;
  return m;
}

static cb_topology build(const cb_mesh *m) {
  cb_topology t;
  int st = cb_topology_build(m, &t);
  cr_assert_eq(st, CB_OK, "cb_topology_build: %s", cb_error_message());
  return t;
}

static int find_edge(const cb_topology *t, int a, int b) {
  int i = a < b ? a : b, j = a < b ? b : a;
  for (int e = 0; e < t->ne; e++)
    if (t->edge[2 * e] == i && t->edge[2 * e + 1] == j) return e;
  return -1;
}

static int tri_has(const int *tri, int v) { return tri[0] == v || tri[1] == v || tri[2] == v; }

/* Structural invariants every topology must satisfy. */
static void check_invariants(const cb_mesh *m, const cb_topology *t) {
  /* edges: i < j, strictly increasing lexicographically (sorted, unique) */
  for (int e = 0; e < t->ne; e++) {
    cr_assert(t->edge[2 * e] < t->edge[2 * e + 1], "edge %d not ordered", e);
    cr_assert(t->edge[2 * e] >= 0 && t->edge[2 * e + 1] < m->nv);
    if (e > 0) {
      int pi = t->edge[2 * e - 2], pj = t->edge[2 * e - 1], i = t->edge[2 * e], j = t->edge[2 * e + 1];
      cr_assert(pi < i || (pi == i && pj < j), "edges %d, %d not strictly sorted", e - 1, e);
    }
  }
  /* every triangle edge is listed */
  for (int f = 0; f < m->nt; f++)
    for (int k = 0; k < 3; k++)
      cr_assert(find_edge(t, m->tri[3 * f + k], m->tri[3 * f + (k + 1) % 3]) >= 0, "triangle %d edge %d missing", f, k);
  /* each pair: two distinct triangles that both hold the shared edge; the
   * opposite vertex is the third vertex of each */
  for (int p = 0; p < t->np; p++) {
    int e = t->pair_edge[p], i = t->edge[2 * e], j = t->edge[2 * e + 1];
    cr_assert(e >= 0 && e < t->ne);
    for (int s = 0; s < 2; s++) {
      int f = t->pair_tri[2 * p + s];
      cr_assert(f >= 0 && f < m->nt);
      const int *tri = m->tri + 3 * f;
      cr_assert(tri_has(tri, i) && tri_has(tri, j), "pair %d: triangle %d lacks edge %d-%d", p, f, i, j);
      int o = t->pair_opp[2 * p + s];
      cr_assert(tri_has(tri, o) && o != i && o != j, "pair %d: bad opposite vertex %d", p, o);
    }
    cr_assert(t->pair_tri[2 * p] < t->pair_tri[2 * p + 1], "pair %d: triangles not in sorted-triple order", p);
    if (p > 0) cr_assert(t->pair_edge[p - 1] < t->pair_edge[p], "pairs not in edge order");
  }
  for (int b = 0; b < t->nb; b++) {
    cr_assert(t->boundary[b] >= 0 && t->boundary[b] < t->ne);
    if (b > 0) cr_assert(t->boundary[b - 1] < t->boundary[b]);
  }
}

/* Triangles around each edge, counted by brute force (independent of the sort). */
static void brute_counts(const cb_mesh *m, int *ne, int *nb, int *np, int *nonman) {
  *ne = *nb = *np = *nonman = 0;
  for (int f = 0; f < m->nt; f++)
    for (int k = 0; k < 3; k++) {
      int a = m->tri[3 * f + k], b = m->tri[3 * f + (k + 1) % 3];
      /* count this edge once: at its first occurrence */
      int first = 1, cnt = 0;
      for (int g = 0; g < m->nt; g++)
        for (int l = 0; l < 3; l++) {
          int c = m->tri[3 * g + l], d = m->tri[3 * g + (l + 1) % 3];
          if ((c == a && d == b) || (c == b && d == a)) {
            cnt++;
            if (g * 3 + l < f * 3 + k) first = 0;
          }
        }
      if (!first) continue;
      (*ne)++;
      if (cnt == 1) (*nb)++;
      else if (cnt == 2) (*np)++;
      else (*nonman)++;
    }
}

static cb_mesh grid(int n, int m, cb_diagonal d) {
  cb_grid_params p = cb_grid_params_default();
  p.n = n;
  p.m = m;
  p.diagonal = d;
  cb_mesh g;
  cr_assert_eq(cb_mesh_grid(&p, &g), CB_OK);
  return g;
}

/* Zips ring A (a vertices from index ia) to ring B (b vertices from ib), both
 * running counter-clockwise from angle 0: a + b triangles. Returns the count. */
static int zip(int *tri, int ia, int a, int ib, int b) {
  int i = 0, j = 0, nt = 0;
  while (i < a || j < b) {
    int inner;
    if (i == a) inner = 0;
    else if (j == b) inner = 1;
    else inner = (i + 1) * b < (j + 1) * a; /* angle of A[i+1] < angle of B[j+1] */
    int *t = tri + 3 * nt++;
    t[0] = ia + i % a;
    t[1] = ib + j % b;
    if (inner) {
      t[2] = ia + (i + 1) % a;
      i++;
    } else {
      t[2] = ib + (j + 1) % b;
      j++;
    }
  }
  return nt;
}

static void ring_positions(double *x, int first, int count, double radius, double phase) {
  for (int k = 0; k < count; k++) {
    double th = phase + 6.283185307179586 * k / count;
    x[3 * (first + k)] = radius * cos(th);
    x[3 * (first + k) + 1] = radius * sin(th);
    x[3 * (first + k) + 2] = 0.1 * radius * radius; /* a shallow bowl, not flat */
  }
}

/* ---- the lecture's example ------------------------------------------------------ */

static double lecture_x[15] = {0, 0, 0, 1, 0, 0, 2, 1, 0, 1, 1, 0, 0, 1, 0};
static int lecture_tri[9] = {1, 2, 3, 0, 1, 3, 0, 3, 4};

Test(lecture, edges_exactly) {
  cb_mesh m = wrap(5, lecture_x, 3, lecture_tri);
  cb_topology t = build(&m);
  /* Edge list: {{0,1},{0,3},{0,4},{1,2},{1,3},{2,3},{3,4}} */
  static const int want[14] = {0, 1, 0, 3, 0, 4, 1, 2, 1, 3, 2, 3, 3, 4};
  cr_assert_eq(t.ne, 7);
  for (int k = 0; k < 14; k++) cr_expect_eq(t.edge[k], want[k], "edge[%d] = %d, expected %d", k, t.edge[k], want[k]);
  cb_topology_free(&t);
}

Test(lecture, neighbouring_triangles_exactly) {
  cb_mesh m = wrap(5, lecture_x, 3, lecture_tri);
  cb_topology t = build(&m);
  /* Neighbouring triangle list: {{1,2},{0,1}} — sorted triples {0,3,1},{0,3,2}
   * and {1,3,0},{1,3,1} */
  cr_assert_eq(t.np, 2);
  cr_expect_eq(t.pair_tri[0], 1);
  cr_expect_eq(t.pair_tri[1], 2);
  cr_expect_eq(t.pair_tri[2], 0);
  cr_expect_eq(t.pair_tri[3], 1);
  /* shared edges {0,3} (edge 1) and {1,3} (edge 4) */
  cr_expect_eq(t.pair_edge[0], 1);
  cr_expect_eq(t.pair_edge[1], 4);
  /* opposite vertices: across {0,3}, triangle {0,1,3} has 1 and {0,3,4} has 4;
   * across {1,3}, triangle {1,2,3} has 2 and {0,1,3} has 0 */
  cr_expect_eq(t.pair_opp[0], 1);
  cr_expect_eq(t.pair_opp[1], 4);
  cr_expect_eq(t.pair_opp[2], 2);
  cr_expect_eq(t.pair_opp[3], 0);
  cb_topology_free(&t);
}

Test(lecture, boundary_and_counts) {
  cb_mesh m = wrap(5, lecture_x, 3, lecture_tri);
  cb_topology t = build(&m);
  /* one triangle each: {0,1} {0,4} {1,2} {2,3} {3,4} = edges 0 2 3 5 6 */
  static const int want[5] = {0, 2, 3, 5, 6};
  cr_assert_eq(t.nb, 5);
  for (int k = 0; k < 5; k++) cr_expect_eq(t.boundary[k], want[k], "boundary[%d] = %d", k, t.boundary[k]);
  cr_expect_eq(t.nonmanifold, 0);
  cr_expect_eq(cb_topology_components(&m, &t), 1);
  cr_expect_eq(cb_topology_boundary_loops(&m, &t), 1);
  cr_expect_eq(t.ne, 3 * m.nv - 3 - t.nb, "Euler: 7 = 3*5 - 3 - 5");
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

Test(lecture, independent_of_winding_and_rotation) {
  /* Reversed winding and rotated corners give the same edges and pairs. */
  int tri[9] = {3, 2, 1, 1, 3, 0, 4, 3, 0};
  cb_mesh m = wrap(5, lecture_x, 3, tri);
  cb_topology t = build(&m);
  static const int want[14] = {0, 1, 0, 3, 0, 4, 1, 2, 1, 3, 2, 3, 3, 4};
  cr_assert_eq(t.ne, 7);
  for (int k = 0; k < 14; k++) cr_expect_eq(t.edge[k], want[k]);
  cr_assert_eq(t.np, 2);
  static const int pt[4] = {1, 2, 0, 1}, po[4] = {1, 4, 2, 0};
  for (int k = 0; k < 4; k++) {
    cr_expect_eq(t.pair_tri[k], pt[k]);
    cr_expect_eq(t.pair_opp[k], po[k]);
  }
  cb_topology_free(&t);
}

/* ---- Euler counts on grids ------------------------------------------------------ */

Test(euler, grids_both_diagonals) {
  static const int sizes[][2] = {{2, 2}, {2, 5}, {3, 3}, {4, 7}, {10, 10}, {21, 21}, {33, 6}};
  for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++)
    for (int d = 0; d < 2; d++) {
      int n = sizes[k][0], mm = sizes[k][1];
      cb_mesh g = grid(n, mm, (cb_diagonal)d);
      cb_topology t = build(&g);
      /* hand counts: (n-1)m horizontal + n(m-1) vertical + (n-1)(m-1) diagonal
       * edges; the perimeter has 2(n-1) + 2(m-1) edges */
      int ne = (n - 1) * mm + n * (mm - 1) + (n - 1) * (mm - 1);
      int nb = 2 * (n - 1) + 2 * (mm - 1);
      cr_expect_eq(t.ne, ne, "%dx%d diag %d: ne %d, expected %d", n, mm, d, t.ne, ne);
      cr_expect_eq(t.nb, nb, "%dx%d diag %d: nb %d, expected %d", n, mm, d, t.nb, nb);
      cr_expect_eq(t.np, ne - nb);
      cr_expect_eq(t.nonmanifold, 0);
      cr_expect_eq(t.ne, 3 * g.nv - 3 - t.nb, "%dx%d diag %d: Euler", n, mm, d);
      cr_expect_eq(cb_topology_components(&g, &t), 1);
      cr_expect_eq(cb_topology_boundary_loops(&g, &t), 1);
      if (n * mm <= 100) check_invariants(&g, &t);
      cb_topology_free(&t);
      cb_mesh_free(&g);
    }
}

Test(euler, grid_boundary_is_the_perimeter) {
  const int n = 6, mm = 4;
  cb_mesh g = grid(n, mm, CB_DIAG_ALTERNATING);
  cb_topology t = build(&g);
  for (int b = 0; b < t.nb; b++) {
    int e = t.boundary[b], u = t.edge[2 * e], v = t.edge[2 * e + 1];
    int ui = u % n, uj = u / n, vi = v % n, vj = v / n;
    int on_perimeter =
        (uj == 0 && vj == 0) || (uj == mm - 1 && vj == mm - 1) || (ui == 0 && vi == 0) || (ui == n - 1 && vi == n - 1);
    cr_expect(on_perimeter && abs(ui - vi) + abs(uj - vj) == 1, "boundary edge %d-%d is not a perimeter edge", u, v);
  }
  cb_topology_free(&t);
  cb_mesh_free(&g);
}

/* ---- unstructured disks ------------------------------------------------------------ */

Test(euler, wheel) {
  /* centre 0 and a rim of 7: V = 8, E = 7 spokes + 7 rim = 14, B = 7 */
  enum { K = 7 };
  double x[3 * (K + 1)] = {0};
  int tri[3 * K];
  ring_positions(x, 1, K, 1.0, 0.3);
  for (int k = 0; k < K; k++) {
    tri[3 * k] = 0;
    tri[3 * k + 1] = 1 + k;
    tri[3 * k + 2] = 1 + (k + 1) % K;
  }
  cb_mesh m = wrap(K + 1, x, K, tri);
  cb_topology t = build(&m);
  cr_expect_eq(t.ne, 14);
  cr_expect_eq(t.nb, 7);
  cr_expect_eq(t.np, 7);
  cr_expect_eq(t.ne, 3 * m.nv - 3 - t.nb);
  cr_expect_eq(cb_topology_components(&m, &t), 1);
  cr_expect_eq(cb_topology_boundary_loops(&m, &t), 1);
  /* every pair is across a spoke {0, k}; its opposite vertices are the rim
   * neighbours of k */
  for (int p = 0; p < t.np; p++) {
    int e = t.pair_edge[p], k = t.edge[2 * e + 1] - 1;
    cr_expect_eq(t.edge[2 * e], 0, "pair %d is not across a spoke", p);
    int o0 = t.pair_opp[2 * p], o1 = t.pair_opp[2 * p + 1];
    int prev = 1 + (k + K - 1) % K, next = 1 + (k + 1) % K;
    cr_expect((o0 == prev && o1 == next) || (o0 == next && o1 == prev), "spoke %d: opposite %d %d", k, o0, o1);
  }
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

Test(euler, concentric_rings_disk) {
  /* centre + rings of 5, 9 and 14 vertices, fanned and zipped:
   * V = 29, F = 5 + (5+9) + (9+14) = 42, B = 14 (outer ring),
   * E = V + F - 1 = 70 = 3*29 - 3 - 14, interior edges 56. */
  double x[3 * 29];
  int tri[3 * 42];
  x[0] = x[1] = x[2] = 0;
  ring_positions(x, 1, 5, 1.0, 0.0);
  ring_positions(x, 6, 9, 2.0, 0.0);
  ring_positions(x, 15, 14, 3.0, 0.0);
  int nt = 0;
  for (int k = 0; k < 5; k++, nt++) {
    tri[3 * nt] = 0;
    tri[3 * nt + 1] = 1 + k;
    tri[3 * nt + 2] = 1 + (k + 1) % 5;
  }
  nt += zip(tri + 3 * nt, 1, 5, 6, 9);
  nt += zip(tri + 3 * nt, 6, 9, 15, 14);
  cr_assert_eq(nt, 42);
  cb_mesh m = wrap(29, x, 42, tri);
  for (int f = 0; f < 42; f++) cr_assert(cb_mesh_triangle_area(&m, x, f) > 1e-3, "triangle %d degenerate", f);
  cb_topology t = build(&m);
  cr_expect_eq(t.ne, 70);
  cr_expect_eq(t.nb, 14);
  cr_expect_eq(t.np, 56);
  cr_expect_eq(t.nonmanifold, 0);
  cr_expect_eq(t.ne, 3 * m.nv - 3 - t.nb);
  cr_expect_eq(cb_topology_components(&m, &t), 1);
  cr_expect_eq(cb_topology_boundary_loops(&m, &t), 1);
  /* the boundary edges are exactly the outer ring's */
  for (int b = 0; b < t.nb; b++) {
    int e = t.boundary[b];
    cr_expect(t.edge[2 * e] >= 15 && t.edge[2 * e + 1] >= 15, "boundary edge %d-%d is not on the rim", t.edge[2 * e],
              t.edge[2 * e + 1]);
  }
  int ne, nb, np, nm;
  brute_counts(&m, &ne, &nb, &np, &nm);
  cr_expect(ne == t.ne && nb == t.nb && np == t.np && nm == t.nonmanifold);
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

Test(euler, jittered_random_diagonals) {
  /* a 9 x 7 grid with jittered vertices and each quad split along a random
   * diagonal: still a disk, so E = 3V - 3 - B with B = 2*8 + 2*6 = 28 */
  for (unsigned seed = 1; seed <= 5; seed++) {
    enum { N = 9, M = 7 };
    cb_rng s = cb_rng_seed(seed);
    double x[3 * N * M];
    int tri[3 * 2 * (N - 1) * (M - 1)], nt = 0;
    for (int j = 0; j < M; j++)
      for (int i = 0; i < N; i++) {
        x[3 * (j * N + i)] = i + 0.3 * (cb_rng_uniform(&s) - 0.5);
        x[3 * (j * N + i) + 1] = j + 0.3 * (cb_rng_uniform(&s) - 0.5);
        x[3 * (j * N + i) + 2] = 0.2 * cb_rng_uniform(&s);
      }
    for (int j = 0; j + 1 < M; j++)
      for (int i = 0; i + 1 < N; i++) {
        int a = j * N + i, b = a + 1, c = a + N + 1, d = a + N;
        int *t = tri + 3 * nt;
        if (cb_rng_next(&s) >> 63) {
          t[0] = a;
          t[1] = b;
          t[2] = c;
          t[3] = a;
          t[4] = c;
          t[5] = d;
        } else {
          t[0] = a;
          t[1] = b;
          t[2] = d;
          t[3] = b;
          t[4] = c;
          t[5] = d;
        }
        nt += 2;
      }
    cb_mesh m = wrap(N * M, x, nt, tri);
    cb_topology t = build(&m);
    cr_expect_eq(t.nb, 28, "seed %u", seed);
    cr_expect_eq(t.ne, 3 * N * M - 3 - 28, "seed %u: ne %d", seed, t.ne);
    cr_expect_eq(t.np, t.ne - 28);
    cr_expect_eq(cb_topology_components(&m, &t), 1);
    cr_expect_eq(cb_topology_boundary_loops(&m, &t), 1);
    int ne, nb, np, nm;
    brute_counts(&m, &ne, &nb, &np, &nm);
    cr_expect(ne == t.ne && nb == t.nb && np == t.np && nm == 0, "seed %u: brute %d %d %d", seed, ne, nb, np);
    check_invariants(&m, &t);
    cb_topology_free(&t);
  }
}

/* ---- not disks -------------------------------------------------------------------- */

Test(euler, annulus_is_not_a_disk) {
  /* rings of 6 (inner hole) and 10 zipped: V = 16, F = 16, every vertex on a
   * boundary: B = 16 (6 inner + 10 outer), E = (3F + B)/2 = 32.
   * chi = V - E + F = 0, so E = 3V - B = 32, while the disk formula would
   * give 3V - 3 - B = 29. */
  double x[3 * 16];
  int tri[3 * 16];
  ring_positions(x, 0, 6, 1.0, 0.0);
  ring_positions(x, 6, 10, 2.0, 0.0);
  int nt = zip(tri, 0, 6, 6, 10);
  cr_assert_eq(nt, 16);
  cb_mesh m = wrap(16, x, nt, tri);
  cb_topology t = build(&m);
  cr_expect_eq(t.ne, 32);
  cr_expect_eq(t.nb, 16);
  cr_expect_eq(t.np, 16);
  cr_expect_neq(t.ne, 3 * m.nv - 3 - t.nb, "an annulus must not satisfy the disk formula");
  cr_expect_eq(t.ne, 3 * m.nv - t.nb, "E = 3V - 3chi - B with chi = 0");
  cr_expect_eq(cb_topology_components(&m, &t), 1);
  cr_expect_eq(cb_topology_boundary_loops(&m, &t), 2);
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

Test(euler, two_components) {
  /* the lecture mesh (V=5, E=7, B=5) plus a separate square of two triangles
   * (V=4, E=5, B=4): chi = 2, E = 3V - 6 - B = 27 - 6 - 9 = 12 */
  double x[27];
  memcpy(x, lecture_x, sizeof lecture_x);
  double sq[12] = {5, 0, 0, 6, 0, 0, 6, 1, 0, 5, 1, 0};
  memcpy(x + 15, sq, sizeof sq);
  int tri[15] = {1, 2, 3, 0, 1, 3, 0, 3, 4, 5, 6, 7, 5, 7, 8};
  cb_mesh m = wrap(9, x, 5, tri);
  cb_topology t = build(&m);
  cr_expect_eq(t.ne, 12);
  cr_expect_eq(t.nb, 9);
  cr_expect_eq(t.np, 3);
  cr_expect_eq(t.ne, 3 * m.nv - 3 * 2 - t.nb);
  cr_expect_eq(cb_topology_components(&m, &t), 2);
  cr_expect_eq(cb_topology_boundary_loops(&m, &t), 2);
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

/* ---- non-manifold edges ------------------------------------------------------------- */

Test(nonmanifold, three_pages_on_one_edge) {
  /* triangles {0,1,2} {0,1,3} {0,1,4} share edge {0,1}: 1 non-manifold edge,
   * 6 boundary edges, no neighbouring pairs */
  double x[15] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
  int tri[9] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
  cb_mesh m = wrap(5, x, 3, tri);
  cb_topology t = build(&m);
  cr_expect_eq(t.nonmanifold, 1);
  cr_expect_eq(t.ne, 7);
  cr_expect_eq(t.nb, 6);
  cr_expect_eq(t.np, 0);
  for (int b = 0; b < t.nb; b++)
    cr_expect_neq(t.boundary[b], find_edge(&t, 0, 1), "the non-manifold edge is no boundary");
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

Test(nonmanifold, counted_per_edge) {
  /* a fin of two triangles on a square: {0,1,2} {0,2,3} is a square, and
   * {0,2,4} {0,2,5} {1,2,4}... : edge {0,2} has 4 triangles, edge {2,4} has
   * 2, edge {0,4} has 1 */
  double x[18] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1, 0.5, 0.5, -1};
  int tri[15] = {0, 1, 2, 0, 2, 3, 0, 2, 4, 0, 2, 5, 1, 2, 4};
  cb_mesh m = wrap(6, x, 5, tri);
  cb_topology t = build(&m);
  int ne, nb, np, nm;
  brute_counts(&m, &ne, &nb, &np, &nm);
  /* by hand: edges 01 02 03 04 05 12 14 23 24 25 = 10; {0,2} non-manifold;
   * pairs {1,2} (tris 0,4) and {2,4} (tris 2,4); the rest boundary (7) */
  cr_expect_eq(ne, 10);
  cr_expect_eq(nm, 1);
  cr_expect_eq(np, 2);
  cr_expect_eq(nb, 7);
  cr_expect_eq(t.ne, 10);
  cr_expect_eq(t.nonmanifold, 1);
  cr_expect_eq(t.np, 2);
  cr_expect_eq(t.nb, 7);
  check_invariants(&m, &t);
  cb_topology_free(&t);
}

Test(nonmanifold, two_such_edges) {
  /* two separate "books" of three pages each */
  double x[30] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1,
                  5, 0, 0, 6, 0, 0, 5.5, 1, 0, 5.5, -1, 0, 5.5, 0, 1};
  int tri[18] = {0, 1, 2, 0, 1, 3, 0, 1, 4, 5, 6, 7, 5, 6, 8, 5, 6, 9};
  cb_mesh m = wrap(10, x, 6, tri);
  cb_topology t = build(&m);
  cr_expect_eq(t.nonmanifold, 2);
  cr_expect_eq(t.ne, 14);
  cr_expect_eq(cb_topology_components(&m, &t), 2);
  cb_topology_free(&t);
}

/* ---- line elements ---------------------------------------------------------------- */

Test(lines, chain_has_edges_but_no_faces) {
  cb_mesh c;
  cr_assert_eq(cb_mesh_chain(6, 1.0, CB_PLANE_YZ, &c), CB_OK);
  cb_topology t = build(&c);
  cr_expect_eq(t.ne, 5);
  cr_expect_eq(t.nb, 0, "a segment is not a boundary edge");
  cr_expect_eq(t.np, 0);
  cr_expect_eq(t.nonmanifold, 0);
  for (int e = 0; e < 5; e++) cr_expect(t.edge[2 * e] == e && t.edge[2 * e + 1] == e + 1);
  cr_expect_eq(cb_topology_components(&c, &t), 1);
  cb_topology_free(&t);
  cb_mesh_free(&c);
}

Test(lines, segment_on_a_triangle_edge_is_not_a_new_edge) {
  /* triangle {0,1,2}, segment {1,0} along its edge and a dangling {2,3} */
  double x[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 2, 0};
  int tri[3] = {0, 1, 2}, lines[4] = {1, 0, 2, 3};
  cb_mesh m = wrap(4, x, 1, tri);
  m.nl = 2;
  m.lines = lines;
  cb_topology t = build(&m);
  cr_expect_eq(t.ne, 4);
  cr_expect_eq(t.nb, 3);
  cr_expect_eq(t.np, 0);
  cr_expect_eq(t.nonmanifold, 0);
  cr_expect(find_edge(&t, 2, 3) >= 0);
  cr_expect_eq(cb_topology_components(&m, &t), 1);
  cb_topology_free(&t);
}

Test(topology, free_is_safe) {
  cb_mesh m = wrap(5, lecture_x, 3, lecture_tri);
  cb_topology t = build(&m);
  cb_topology_free(&t);
  cb_topology_free(&t);
  cb_topology_free(NULL);
}
