/* ccd-gen: writes the project's exact CCD query set (docs/geometry-ccd.md).
 *
 *   ccd-gen DIR     writes DIR/vf.csv, DIR/ee.csv (Wang et al. 2021's benchmark format)
 *                   and DIR/vf_truth.csv, DIR/ee_truth.csv (per query: case, truth, toi_lo, toi_hi)
 *
 * Every query's coordinates are doubles, written as exact rationals. The truth
 * is decided in exact rational arithmetic (GMP mpq), for eta = 0, by a branch
 * and bound over (t, u, v) in [0,1]^3 written independently of the library's
 * CCD (which rounds, and uses different rules to split and accept):
 *
 *   F(t,u,v) = C0 + t Ct + u (Cu + t Ctu) + v (Cv + t Ctv)   (3 components)
 *   vf: x0(t) - [(1-u-v) x1(t) + u x2(t) + v x3(t)], u, v >= 0, u + v <= 1
 *   ee: [(1-u) x0(t) + u x1(t)] - [(1-v) x2(t) + v x3(t)], u, v in [0, 1]
 *
 *  - exclusion: F_j is affine in each variable separately, so its range over a
 *    box is the hull of its 8 exact corner values; a box where some F_j has
 *    one strict sign at all corners holds no contact;
 *  - witness at a corner: F = 0 exactly at a corner inside the domain is a
 *    contact at that corner's t;
 *  - witness by Krawczyk's test: for the box X inside the domain, its midpoint
 *    m, Y ~ J(m)^-1 (rounded, then exact, nonsingular), and the exact interval
 *    Jacobian J(X), K = m - Y F(m) + (I - Y J(X))(X - m) inside the interior
 *    of X proves that F has a zero in X (Krawczyk 1969; Rump), a contact at a
 *    time <= X's t1.
 * Boxes are searched depth first, the earlier half in t first, pruned at
 * t0 >= toi_hi, split at the widest side down to 2^-40. The result: truth 1
 * with a certified bracket toi_lo <= t* <= toi_hi (toi_hi: a witness;
 * toi_lo: the earliest box not excluded), truth 0 when every box was
 * excluded, or undecided, and then the query is left out of the set (the
 * counts are printed). The hard cases are built with a known truth, which the
 * branch and bound must confirm, or the generator fails. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gmp.h>

#include "rng.h"

enum { VF = 0, EE = 1 };
#define MINW 0x1p-40
#define BUDGET 400000L

typedef struct {
  double t0, t1, u0, u1, v0, v1;
} box;

/* F's coefficients, exact: c[j][0..5] = C0, Ct, Cu, Ctu, Cv, Ctv of component j */
static mpq_t c[3][6];
static mpq_t T[24]; /* scratch */

static void coefficients(int kind, double x[8][3]) {
  static const int pairs[2][3][2] = {{{0, 1}, {1, 2}, {1, 3}}, {{0, 2}, {1, 0}, {2, 3}}};
  for (int j = 0; j < 3; j++)
    for (int term = 0; term < 3; term++) {
      int a = pairs[kind][term][0], b = pairs[kind][term][1];
      /* constant x_a - x_b; slope (x_{a+4} - x_a) - (x_{b+4} - x_b) */
      mpq_set_d(T[0], x[a][j]);
      mpq_set_d(T[1], x[b][j]);
      mpq_sub(c[j][2 * term], T[0], T[1]);
      mpq_set_d(T[2], x[a + 4][j]);
      mpq_set_d(T[3], x[b + 4][j]);
      mpq_sub(T[2], T[2], T[0]);
      mpq_sub(T[3], T[3], T[1]);
      mpq_sub(c[j][2 * term + 1], T[2], T[3]);
    }
}

/* out = F_j(t, u, v) */
static void eval(mpq_t out, int j, const mpq_t t, const mpq_t u, const mpq_t v) {
  mpq_mul(T[10], t, c[j][1]);
  mpq_add(out, c[j][0], T[10]); /* C0 + t Ct */
  mpq_mul(T[10], t, c[j][3]);
  mpq_add(T[10], T[10], c[j][2]);
  mpq_mul(T[10], T[10], u);
  mpq_add(out, out, T[10]); /* + u (Cu + t Ctu) */
  mpq_mul(T[10], t, c[j][5]);
  mpq_add(T[10], T[10], c[j][4]);
  mpq_mul(T[10], T[10], v);
  mpq_add(out, out, T[10]); /* + v (Cv + t Ctv) */
}

static mpq_t bt[2], bu[2], bv[2], val[8][3];

enum { EXCLUDED, CORNER_AT_T0, WITNESS, OPEN };

/* Krawczyk's test on box b (already inside the domain): 1 if F certainly has a zero in b */
static int krawczyk(const box *b) {
  mpq_t m[3], r[3], Fm[3], Y[3][3], lo, hi, x, y, s, cc;
  double lo_[3] = {b->t0, b->u0, b->v0}, hi_[3] = {b->t1, b->u1, b->v1};
  for (int i = 0; i < 3; i++) {
    mpq_inits(m[i], r[i], Fm[i], Y[i][0], Y[i][1], Y[i][2], NULL);
    mpq_set_d(m[i], 0.5 * (lo_[i] + hi_[i])); /* dyadic: exact */
    mpq_set_d(r[i], 0.5 * (hi_[i] - lo_[i]));
  }
  mpq_inits(lo, hi, x, y, s, cc, NULL);
  int ok = 0;
  /* J(m) in doubles, then Y = its inverse (any nonsingular Y will do: the test is exact) */
  double J[3][3];
  for (int j = 0; j < 3; j++) {
    eval(Fm[j], j, m[0], m[1], m[2]);
    /* dF/dt = Ct + u Ctu + v Ctv; dF/du = Cu + t Ctu; dF/dv = Cv + t Ctv, at m */
    mpq_mul(x, m[1], c[j][3]);
    mpq_mul(y, m[2], c[j][5]);
    mpq_add(x, x, y);
    mpq_add(x, x, c[j][1]);
    J[j][0] = mpq_get_d(x);
    mpq_mul(x, m[0], c[j][3]);
    mpq_add(x, x, c[j][2]);
    J[j][1] = mpq_get_d(x);
    mpq_mul(x, m[0], c[j][5]);
    mpq_add(x, x, c[j][4]);
    J[j][2] = mpq_get_d(x);
  }
  double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
               J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  if (!(fabs(det) > 1e-300) || !isfinite(det)) goto out;
  for (int i = 0; i < 3; i++)
    for (int k = 0; k < 3; k++) {
      int i1 = (k + 1) % 3, i2 = (k + 2) % 3, k1 = (i + 1) % 3, k2 = (i + 2) % 3;
      double cof = J[i1][k1] * J[i2][k2] - J[i1][k2] * J[i2][k1]; /* adjugate: Y(i,k) = cof(k,i) / det */
      double yik = cof / det;
      if (!isfinite(yik)) goto out;
      mpq_set_d(Y[i][k], yik);
    }
  /* det(Y) != 0, exactly */
  mpq_mul(x, Y[1][1], Y[2][2]);
  mpq_mul(y, Y[1][2], Y[2][1]);
  mpq_sub(x, x, y);
  mpq_mul(s, Y[0][0], x);
  mpq_mul(x, Y[1][0], Y[2][2]);
  mpq_mul(y, Y[1][2], Y[2][0]);
  mpq_sub(x, x, y);
  mpq_mul(x, Y[0][1], x);
  mpq_sub(s, s, x);
  mpq_mul(x, Y[1][0], Y[2][1]);
  mpq_mul(y, Y[1][1], Y[2][0]);
  mpq_sub(x, x, y);
  mpq_mul(x, Y[0][2], x);
  mpq_add(s, s, x);
  if (mpq_sgn(s) == 0) goto out;
  /* interval Jacobian J(X): entries affine in the box's variables, so hulls of end values */
  mpq_t JL[3][3], JH[3][3];
  for (int j = 0; j < 3; j++)
    for (int k = 0; k < 3; k++) mpq_inits(JL[j][k], JH[j][k], NULL);
  for (int j = 0; j < 3; j++) {
    int first = 1;
    for (int a = 0; a < 2; a++)
      for (int d = 0; d < 2; d++) {
        mpq_mul(x, bu[a], c[j][3]);
        mpq_mul(y, bv[d], c[j][5]);
        mpq_add(x, x, y);
        mpq_add(x, x, c[j][1]);
        if (first || mpq_cmp(x, JL[j][0]) < 0) mpq_set(JL[j][0], x);
        if (first || mpq_cmp(x, JH[j][0]) > 0) mpq_set(JH[j][0], x);
        first = 0;
      }
    for (int k = 1; k < 3; k++)
      for (int a = 0; a < 2; a++) {
        mpq_mul(x, bt[a], c[j][k == 1 ? 3 : 5]);
        mpq_add(x, x, c[j][k == 1 ? 2 : 4]);
        if (!a || mpq_cmp(x, JL[j][k]) < 0) mpq_set(JL[j][k], x);
        if (!a || mpq_cmp(x, JH[j][k]) > 0) mpq_set(JH[j][k], x);
      }
  }
  ok = 1;
  for (int i = 0; i < 3 && ok; i++) {
    /* c_i = m_i - (Y F(m))_i */
    mpq_set(cc, m[i]);
    for (int l = 0; l < 3; l++) {
      mpq_mul(x, Y[i][l], Fm[l]);
      mpq_sub(cc, cc, x);
    }
    /* s_i = sum_k |M_ik| r_k, M = I - Y J(X), |M_ik| = max(|lo|, |hi|) */
    mpq_set_ui(s, 0, 1);
    for (int k = 0; k < 3; k++) {
      mpq_set_ui(lo, i == k, 1);
      mpq_set_ui(hi, i == k, 1);
      for (int l = 0; l < 3; l++) {
        /* - Y_il [JL, JH] */
        int pos = mpq_sgn(Y[i][l]) >= 0;
        mpq_mul(x, Y[i][l], pos ? JH[l][k] : JL[l][k]);
        mpq_sub(lo, lo, x);
        mpq_mul(x, Y[i][l], pos ? JL[l][k] : JH[l][k]);
        mpq_sub(hi, hi, x);
      }
      mpq_abs(lo, lo);
      mpq_abs(hi, hi);
      mpq_mul(x, mpq_cmp(lo, hi) > 0 ? lo : hi, r[k]);
      mpq_add(s, s, x);
    }
    /* c - s > lo_i and c + s < hi_i */
    mpq_sub(x, cc, s);
    mpq_set_d(y, lo_[i]);
    if (mpq_cmp(x, y) <= 0) ok = 0;
    mpq_add(x, cc, s);
    mpq_set_d(y, hi_[i]);
    if (mpq_cmp(x, y) >= 0) ok = 0;
  }
  for (int j = 0; j < 3; j++)
    for (int k = 0; k < 3; k++) mpq_clears(JL[j][k], JH[j][k], NULL);
out:
  for (int i = 0; i < 3; i++) mpq_clears(m[i], r[i], Fm[i], Y[i][0], Y[i][1], Y[i][2], NULL);
  mpq_clears(lo, hi, x, y, s, cc, NULL);
  return ok;
}

/* examines a box: EXCLUDED, CORNER_AT_T0 (F = 0 at a corner with t = t0), WITNESS (a contact at a time
 * <= *tw), or OPEN */
static int examine(int kind, const box *b, double *tw) {
  if (kind == VF && b->u0 + b->v0 > 1.0) return EXCLUDED;
  mpq_set_d(bt[0], b->t0);
  mpq_set_d(bt[1], b->t1);
  mpq_set_d(bu[0], b->u0);
  mpq_set_d(bu[1], b->u1);
  mpq_set_d(bv[0], b->v0);
  mpq_set_d(bv[1], b->v1);
  for (int k = 0; k < 8; k++)
    for (int j = 0; j < 3; j++) eval(val[k][j], j, bt[k >> 2], bu[(k >> 1) & 1], bv[k & 1]);
  for (int j = 0; j < 3; j++) {
    int pos = 1, neg = 1;
    for (int k = 0; k < 8; k++) {
      int sg = mpq_sgn(val[k][j]);
      pos &= sg > 0;
      neg &= sg < 0;
    }
    if (pos || neg) return EXCLUDED;
  }
  int found = 0;
  for (int k = 0; k < 8; k++) {
    double u = (k >> 1) & 1 ? b->u1 : b->u0, v = k & 1 ? b->v1 : b->v0, t = k >> 2 ? b->t1 : b->t0;
    if (kind == VF && u + v > 1.0) continue;
    if (mpq_sgn(val[k][0]) || mpq_sgn(val[k][1]) || mpq_sgn(val[k][2])) continue;
    if (t == b->t0) return CORNER_AT_T0;
    *tw = t;
    found = 1;
  }
  if (found) return WITNESS;
  int inside = kind == EE || b->u1 + b->v1 <= 1.0;
  double w = fmax(b->t1 - b->t0, fmax(b->u1 - b->u0, b->v1 - b->v0));
  if (inside && w <= 0.125 && krawczyk(b)) {
    *tw = b->t1;
    return WITNESS;
  }
  return OPEN;
}

typedef struct {
  int decided, truth;
  double lo, hi; /* toi bracket (dyadic, exact) when truth */
  long boxes;
} verdict;

static verdict decide(int kind, double x[8][3]) {
  coefficients(kind, x);
  static box stack[4096];
  int n = 0;
  stack[n++] = (box){0, 1, 0, 1, 0, 1};
  double U = INFINITY, L = INFINITY;
  long boxes = 0;
  int unresolved = 0;
  while (n > 0) {
    box b = stack[--n];
    if (b.t0 >= U) continue;
    if (++boxes > BUDGET) {
      unresolved = 1;
      L = fmin(L, b.t0);
      for (int i = 0; i < n; i++) L = fmin(L, stack[i].t0);
      break;
    }
    double tw = INFINITY;
    int e = examine(kind, &b, &tw);
    if (e == EXCLUDED) continue;
    if (e == CORNER_AT_T0) {
      U = fmin(U, b.t0);
      L = fmin(L, b.t0);
      continue;
    }
    if (e == WITNESS) U = fmin(U, tw);
    double wt = b.t1 - b.t0, wu = b.u1 - b.u0, wv = b.v1 - b.v0;
    if (fmax(wt, fmax(wu, wv)) <= MINW) {
      L = fmin(L, b.t0); /* not excluded, as small as boxes get */
      if (e != WITNESS) unresolved = 1;
      continue;
    }
    box lo = b, hi = b;
    if (wt >= wu && wt >= wv) lo.t1 = hi.t0 = 0.5 * (b.t0 + b.t1);
    else if (wu >= wv) lo.u1 = hi.u0 = 0.5 * (b.u0 + b.u1);
    else lo.v1 = hi.v0 = 0.5 * (b.v0 + b.v1);
    if (n + 2 > (int)(sizeof stack / sizeof *stack)) {
      fprintf(stderr, "ccd-gen: stack overflow\n");
      exit(1);
    }
    stack[n++] = hi;
    stack[n++] = lo;
  }
  verdict r = {0, 0, 0, 0, boxes};
  if (U <= 1.0) {
    r.decided = 1;
    r.truth = 1;
    r.hi = U;
    r.lo = fmin(L, U);
  } else if (!unresolved) {
    r.decided = 1;
  }
  (void)unresolved;
  return r;
}

/* ---- output ---------------------------------------------------------------------------------------------- */

static FILE *qf[2], *tf[2];
static int count[2], dropped[2];

static void put_rational(FILE *f, double d) {
  mpq_t q;
  mpq_init(q);
  mpq_set_d(q, d);
  gmp_fprintf(f, "%Zd,%Zd", mpq_numref(q), mpq_denref(q));
  mpq_clear(q);
}

/* expect: 1 or 0 (the construction's truth, which the exact search must confirm), -1 unknown */
static void add(int kind, const char *name, double x[8][3], int expect) {
  verdict v = decide(kind, x);
  if (!v.decided) {
    dropped[kind]++;
    fprintf(stderr, "ccd-gen: %s %s: undecided after %ld boxes, left out\n", kind ? "ee" : "vf", name, v.boxes);
    return;
  }
  if (expect >= 0 && v.truth != expect) {
    fprintf(stderr, "ccd-gen: %s %s: built as %s, the exact search says %s\n", kind ? "ee" : "vf", name,
            expect ? "hit" : "miss", v.truth ? "hit" : "miss");
    exit(1);
  }
  for (int k = 0; k < 8; k++) {
    for (int j = 0; j < 3; j++) {
      put_rational(qf[kind], x[k][j]);
      fputc(',', qf[kind]);
    }
    fprintf(qf[kind], "%d\n", v.truth);
  }
  fprintf(tf[kind], "%d,%s,%d,", count[kind], name, v.truth);
  if (v.truth) {
    put_rational(tf[kind], v.lo);
    fputc(',', tf[kind]);
    put_rational(tf[kind], v.hi);
  } else fputs(",,,", tf[kind]);
  fputc('\n', tf[kind]);
  count[kind]++;
}

/* ---- the cases ------------------------------------------------------------------------------------------- */

static cb_rng rng;

/* the case at scale s (a power of 2: exact), with its axes permuted and signs flipped (exact) */
static void add_variants(int kind, const char *name, double base[8][3], int expect) {
  static const double scales[3] = {1.0, 0x1p20, 0x1p-20}; /* about 1, 1e6, 1e-6 */
  static const char *const sname[3] = {"", "@1e6", "@1e-6"};
  for (int si = 0; si < 3; si++)
    for (int rep = 0; rep < 2; rep++) {
      int perm[3] = {0, 1, 2};
      double sign[3] = {1, 1, 1};
      if (rep) {
        for (int i = 2; i > 0; i--) {
          int j = (int)(cb_rng_next(&rng) % (uint64_t)(i + 1)), tmp = perm[i];
          perm[i] = perm[j];
          perm[j] = tmp;
        }
        for (int i = 0; i < 3; i++) sign[i] = cb_rng_next(&rng) & 1 ? -1.0 : 1.0;
      }
      double x[8][3];
      for (int k = 0; k < 8; k++)
        for (int j = 0; j < 3; j++) x[k][j] = sign[j] * scales[si] * base[k][perm[j]];
      char full[128];
      snprintf(full, sizeof full, "%s%s%s", name, sname[si], rep ? "/perm" : "");
      add(kind, full, x, expect);
    }
}

/* base case from the 4 points at t = 0 and their positions at t = 1 */
static void hard(int kind, const char *name, double a[4][3], double b[4][3], int expect) {
  double x[8][3];
  memcpy(x, a, sizeof(double[4][3]));
  memcpy(x + 4, b, sizeof(double[4][3]));
  add_variants(kind, name, x, expect);
}

static void hard_vf(void) {
  /* triangle (0,0,0), (1,0,0), (0,1,0) in z = 0 unless said otherwise */
#define TRI \
  {0, 0, 0}, {1, 0, 0}, { 0, 1, 0 }
  const double d12 = 1e-12, d30 = 1e-30;
  struct {
    const char *name;
    double a[4][3], b[4][3];
    int expect;
  } cs[] = {
      {"face_t0_leaving", {{.25, .25, 0}, TRI}, {{.25, .25, 1}, TRI}, 1},
      {"face_t1_arriving", {{.25, .25, 1}, TRI}, {{.25, .25, 0}, TRI}, 1},
      {"face_crossing_t_half", {{.25, .25, 1}, TRI}, {{.25, .25, -1}, TRI}, 1},
      {"vertex_t1", {{0, 0, 1}, TRI}, {{0, 0, 0}, TRI}, 1},
      {"vertex_t0", {{1, 0, 0}, TRI}, {{1, 0, 1}, TRI}, 1},
      {"edge_t1", {{.5, .5, 1}, TRI}, {{.5, .5, 0}, TRI}, 1},
      {"edge_t0", {{.5, 0, 0}, TRI}, {{.5, 0, -1}, TRI}, 1},
      {"edge_crossing_t_half", {{.5, 0, 1}, TRI}, {{.5, 0, -1}, TRI}, 1},
      {"vertex_crossing_t_half", {{0, 1, 1}, TRI}, {{0, 1, -1}, TRI}, 1},
      {"coplanar_entering_edge_t_half", {{.5, -1, 0}, TRI}, {{.5, 1, 0}, TRI}, 1},
      {"coplanar_arriving_edge_t1", {{.5, -1, 0}, TRI}, {{.5, 0, 0}, TRI}, 1},
      {"coplanar_miss", {{2, -1, 0}, TRI}, {{2, 1, 0}, TRI}, 0},
      {"coplanar_moving_triangle",
       {{-1, .25, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}},
       {{1, .25, 0}, {-1, 0, 0}, {0, 0, 0}, {-1, 1, 0}},
       1},
      {"coplanar_inside_static", {{.25, .25, 0}, TRI}, {{.25, .25, 0}, TRI}, 1},
      {"no_motion_miss", {{.25, .25, 1}, TRI}, {{.25, .25, 1}, TRI}, 0},
      {"no_motion_above_vertex_miss", {{0, 0, d12}, TRI}, {{0, 0, d12}, TRI}, 0},
      {"degenerate_segment_hit",
       {{.5, 0, 1}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}},
       {{.5, 0, -1}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}},
       1},
      {"degenerate_segment_miss_1e-12",
       {{.5, d12, 1}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}},
       {{.5, d12, -1}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}},
       0},
      {"degenerate_point_hit",
       {{0, 0, 1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
       {{0, 0, -1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
       1},
      {"degenerate_point_miss_1e-30",
       {{d30, 0, 1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
       {{d30, 0, -1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
       0},
      {"near_miss_edge_1e-12", {{-d12, .25, 1}, TRI}, {{-d12, .25, -1}, TRI}, 0},
      {"near_miss_edge_1e-30", {{-d30, .25, 1}, TRI}, {{-d30, .25, -1}, TRI}, 0},
      {"near_miss_vertex_1e-12", {{-d12, -d12, 1}, TRI}, {{-d12, -d12, -1}, TRI}, 0},
      {"stops_short_1e-12", {{.25, .25, 1}, TRI}, {{.25, .25, d12}, TRI}, 0},
      {"stops_short_1e-30", {{.25, .25, 1}, TRI}, {{.25, .25, d30}, TRI}, 0},
      {"starts_past_1e-30", {{.25, .25, -d30}, TRI}, {{.25, .25, -1}, TRI}, 0},
      {"triangle_moves_onto_point_t1", {{.25, .25, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}}, {{.25, .25, 0}, TRI}, 1},
      {"both_move_meet_t_half",
       {{.25, .25, 1}, {0, 0, -1}, {1, 0, -1}, {0, 1, -1}},
       {{.25, .25, -1}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}},
       1},
  };
  for (size_t i = 0; i < sizeof cs / sizeof *cs; i++) hard(VF, cs[i].name, cs[i].a, cs[i].b, cs[i].expect);
#undef TRI
}

static void hard_ee(void) {
  const double d12 = 1e-12, d30 = 1e-30;
  struct {
    const char *name;
    double a[4][3], b[4][3];
    int expect;
  } cs[] = {
      {"crossing_t_half",
       {{-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}},
       {{-1, 0, 0}, {1, 0, 0}, {0, -1, -1}, {0, 1, -1}},
       1},
      {"touch_t0", {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}}, {{-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}}, 1},
      {"touch_t1", {{-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}}, {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}}, 1},
      {"endpoint_on_edge_t1",
       {{-1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}},
       {{-1, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}},
       1},
      {"endpoint_endpoint_t_half",
       {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {1, 1, 1}},
       {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {1, 1, -1}},
       1},
      {"endpoint_endpoint_t0",
       {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {2, 1, 0}},
       {{0, 0, 1}, {1, 0, 1}, {1, 0, 0}, {2, 1, 0}},
       1},
      {"parallel_overlap_t1",
       {{0, 0, 0}, {1, 0, 0}, {.5, 0, 1}, {1.5, 0, 1}},
       {{0, 0, 0}, {1, 0, 0}, {.5, 0, 0}, {1.5, 0, 0}},
       1},
      {"parallel_crossing_t_half",
       {{0, 0, 0}, {1, 0, 0}, {.5, 0, 1}, {1.5, 0, 1}},
       {{0, 0, 0}, {1, 0, 0}, {.5, 0, -1}, {1.5, 0, -1}},
       1},
      {"parallel_disjoint",
       {{0, 0, 0}, {1, 0, 0}, {2, 0, 1}, {3, 0, 1}},
       {{0, 0, 0}, {1, 0, 0}, {2, 0, -1}, {3, 0, -1}},
       0},
      {"parallel_miss_1e-12",
       {{0, 0, 0}, {1, 0, 0}, {0, d12, 1}, {1, d12, 1}},
       {{0, 0, 0}, {1, 0, 0}, {0, d12, -1}, {1, d12, -1}},
       0},
      {"collinear_sliding_t_half",
       {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {4, 0, 0}},
       {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 0}},
       1},
      {"collinear_stops_short_1e-12",
       {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {4, 0, 0}},
       {{0, 0, 0}, {1, 0, 0}, {1 + 0x1p-40, 0, 0}, {2 + 0x1p-40, 0, 0}},
       0},
      {"collinear_overlap_static",
       {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {3, 0, 0}},
       {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {3, 0, 0}},
       1},
      {"no_motion_miss",
       {{-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}},
       {{-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}},
       0},
      {"near_miss_1e-30",
       {{-1, 0, 0}, {1, 0, 0}, {0, -1, d30}, {0, 1, d30}},
       {{-1, 0, 0}, {1, 0, 0}, {0, -1, d30}, {0, 1, d30}},
       0},
      {"passing_beyond_end_1e-12",
       {{-1, 0, 0}, {1, 0, 0}, {1 + 0x1p-40, -1, 1}, {1 + 0x1p-40, 1, 1}},
       {{-1, 0, 0}, {1, 0, 0}, {1 + 0x1p-40, -1, -1}, {1 + 0x1p-40, 1, -1}},
       0},
      {"passing_beyond_end_1e-30",
       {{-1, 0, 0}, {0, 0, 0}, {d30, -1, 1}, {d30, 1, 1}},
       {{-1, 0, 0}, {0, 0, 0}, {d30, -1, -1}, {d30, 1, -1}},
       0},
      {"degenerate_edge_point_hit",
       {{0, 0, 0}, {0, 0, 0}, {-1, 0, 1}, {1, 0, 1}},
       {{0, 0, 0}, {0, 0, 0}, {-1, 0, -1}, {1, 0, -1}},
       1},
      {"degenerate_both_points_t_half",
       {{0, 0, 1}, {0, 0, 1}, {0, 0, -1}, {0, 0, -1}},
       {{0, 0, -1}, {0, 0, -1}, {0, 0, 1}, {0, 0, 1}},
       1},
      {"degenerate_points_miss_1e-12",
       {{d12, 0, 1}, {d12, 0, 1}, {0, 0, -1}, {0, 0, -1}},
       {{d12, 0, -1}, {d12, 0, -1}, {0, 0, 1}, {0, 0, 1}},
       0},
      {"coplanar_rotating_hit",
       {{-1, 0, 0}, {1, 0, 0}, {2, -1, 0}, {2, 1, 0}},
       {{-1, 0, 0}, {1, 0, 0}, {-2, -1, 0}, {-2, 1, 0}},
       1},
  };
  for (size_t i = 0; i < sizeof cs / sizeof *cs; i++) hard(EE, cs[i].name, cs[i].a, cs[i].b, cs[i].expect);
}

/* exact det of the 3x3 matrix of rows r0, r1, r2 (small integers and halves: exact in double) */
static double det3(const double *r0, const double *r1, const double *r2) {
  return r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0]) +
         r0[2] * (r1[0] * r2[1] - r1[1] * r2[0]);
}

/* the coplanarity cubic f(t) = det(x1 - x0, x2 - x0, x3 - x0)(t) (vf and ee alike, up to sign and order) */
static double coplanarity(double x[8][3], double t) {
  double p[4][3], r[3][3];
  for (int k = 0; k < 4; k++)
    for (int j = 0; j < 3; j++) p[k][j] = x[k][j] + t * (x[k + 4][j] - x[k][j]);
  for (int k = 0; k < 3; k++)
    for (int j = 0; j < 3; j++) r[k][j] = p[k + 1][j] - p[0][j];
  return det3(r[0], r[1], r[2]);
}

/* Queries whose coplanarity cubic has a double (order 2) or triple root at t = 1/2: small-integer motions
 * found by random search. f(1/2 + s) = a s^3 + b s^2 + c s + d; with h = 1/2, P = f(1/2+h) - f(1/2-h),
 * Q = f(1/2+2h) - f(1/2-2h): d = 0 and c = 0 <=> f(1/2) = 0 and Q = 8P; and b = 0 <=> f(1) + f(0) = 0. */
static void multiple_roots(int kind, int order, int want) {
  int got = 0;
  for (long it = 0; it < 20000000 && got < want; it++) {
    double x[8][3];
    for (int k = 0; k < 8; k++)
      for (int j = 0; j < 3; j++) x[k][j] = k % 4 == 0 ? 0.0 : (double)((int)(cb_rng_next(&rng) % 5) - 2);
    if (coplanarity(x, 0.5) != 0) continue;
    double P = coplanarity(x, 1) - coplanarity(x, 0), Q = coplanarity(x, 1.5) - coplanarity(x, -0.5);
    if (Q != 8 * P) continue;
    int triple = coplanarity(x, 1) + coplanarity(x, 0) == 0;
    if (triple != (order == 3)) continue;
    if (coplanarity(x, 0) == 0 && coplanarity(x, 1) == 0 && coplanarity(x, 0.25) == 0) continue; /* f = 0 */
    char name[64];
    snprintf(name, sizeof name, "%s_root_t_half_%d", order == 3 ? "triple" : "double", got);
    add(kind, name, x, -1);
    got++;
  }
}

static double rnd(double a, double b) { return a + (b - a) * cb_rng_uniform(&rng); }

static void random_queries(int kind, const char *name, int n, double motion, double scale) {
  for (int i = 0; i < n; i++) {
    double x[8][3];
    for (int k = 0; k < 4; k++)
      for (int j = 0; j < 3; j++) {
        x[k][j] = scale * rnd(-1, 1);
        x[k + 4][j] = motion < 0 ? scale * rnd(-1, 1) : x[k][j] + scale * motion * rnd(-1, 1);
      }
    char full[64];
    snprintf(full, sizeof full, "%s_%d", name, i);
    add(kind, full, x, -1);
  }
}

static FILE *open_out(const char *dir, const char *name) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  if (!f) {
    fprintf(stderr, "ccd-gen: %s: %s\n", path, strerror(errno));
    exit(3);
  }
  return f;
}

int main(int argc, char **argv) {
  if (argc != 2 || argv[1][0] == '-') {
    fprintf(stderr, "usage: ccd-gen DIR   (writes DIR/{vf,ee}.csv and DIR/{vf,ee}_truth.csv)\n");
    return argc == 2 && !strcmp(argv[1], "--help") ? 0 : 2;
  }
  for (int i = 0; i < 24; i++) mpq_init(T[i]);
  for (int j = 0; j < 3; j++)
    for (int k = 0; k < 6; k++) mpq_init(c[j][k]);
  for (int i = 0; i < 2; i++) mpq_inits(bt[i], bu[i], bv[i], NULL);
  for (int k = 0; k < 8; k++)
    for (int j = 0; j < 3; j++) mpq_init(val[k][j]);
  rng = cb_rng_seed(33);
  const char *dir = argv[1];
  qf[VF] = open_out(dir, "vf.csv");
  qf[EE] = open_out(dir, "ee.csv");
  tf[VF] = open_out(dir, "vf_truth.csv");
  tf[EE] = open_out(dir, "ee_truth.csv");
  for (int k = 0; k < 2; k++) fprintf(tf[k], "query,case,truth,toi_lo_num,toi_lo_den,toi_hi_num,toi_hi_den\n");
  hard_vf();
  hard_ee();
  for (int kind = 0; kind < 2; kind++) {
    multiple_roots(kind, 2, 6);
    multiple_roots(kind, 3, 3);
    random_queries(kind, "random_large_motion", 200, -1, 1.0);
    random_queries(kind, "random_small_motion", 200, 0.2, 1.0);
    random_queries(kind, "random_1e6", 50, 0.5, 1e6);
    random_queries(kind, "random_1e-6", 50, 0.5, 1e-6);
  }
  for (int k = 0; k < 2; k++)
    if (fclose(qf[k]) || fclose(tf[k])) {
      fprintf(stderr, "ccd-gen: write error\n");
      return 3;
    }
  fprintf(stderr, "ccd-gen: vf %d queries (%d undecided, left out), ee %d queries (%d undecided, left out)\n",
          count[VF], dropped[VF], count[EE], dropped[EE]);
  return 0;
}
