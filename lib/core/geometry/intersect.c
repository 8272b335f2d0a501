/* Exact orientation predicates (a floating-point filter with Shewchuk's error
 * bound, GMP rationals when it is inconclusive) and the exact closed
 * triangle-triangle test built on them. The reasoning behind each case is in
 * include/clothbench/intersect.h. */
#include <clothbench/intersect.h>

#include <gmp.h>
#include <math.h>

/* Shewchuk 1997, section 4: epsilon = 2^-53 (half an ulp of 1), and the
 * forward error bounds of the plain double evaluation:
 *   orient2d: |det - fl(det)| <= (3 + 16 eps) eps (|detleft| + |detright|)
 *   orient3d: |det - fl(det)| <= (7 + 56 eps) eps permanent
 * with the differences' rounding included. They hold without underflow and
 * overflow, so tiny or huge magnitudes take the exact path too. */
#define EPS 0x1p-53
#define CCW_BOUND ((3.0 + 16.0 * EPS) * EPS)
#define O3D_BOUND ((7.0 + 56.0 * EPS) * EPS)
#define TINY 0x1p-900 /* far above the subnormals: products of terms of this size do not underflow */
#define HUGE_ 0x1p+900

static _Thread_local long exact_calls;

long cb_orient_exact_calls(void) { return exact_calls; }
void cb_orient_exact_reset(void) { exact_calls = 0; }

/* ---- exact evaluation in rationals ---- */

static int orient2d_exact(const double *a, const double *b, const double *c) {
  exact_calls++;
  mpq_t u0, u1, v0, v1, l, r;
  mpq_inits(u0, u1, v0, v1, l, r, NULL);
  mpq_set_d(u0, a[0]);
  mpq_set_d(l, c[0]);
  mpq_sub(u0, u0, l); /* u = a - c */
  mpq_set_d(u1, a[1]);
  mpq_set_d(l, c[1]);
  mpq_sub(u1, u1, l);
  mpq_set_d(v0, b[0]);
  mpq_set_d(l, c[0]);
  mpq_sub(v0, v0, l); /* v = b - c */
  mpq_set_d(v1, b[1]);
  mpq_set_d(l, c[1]);
  mpq_sub(v1, v1, l);
  mpq_mul(l, u0, v1); /* det = u0 v1 - u1 v0 */
  mpq_mul(r, u1, v0);
  int s = mpq_cmp(l, r);
  mpq_clears(u0, u1, v0, v1, l, r, NULL);
  return (s > 0) - (s < 0);
}

static int orient3d_exact(const double *a, const double *b, const double *c, const double *d) {
  exact_calls++;
  mpq_t m[9], t, u, det, dk;
  for (int i = 0; i < 9; i++) mpq_init(m[i]);
  mpq_inits(t, u, det, dk, NULL);
  const double *row[3] = {a, b, c};
  for (int i = 0; i < 3; i++)
    for (int k = 0; k < 3; k++) { /* m[3i+k] = row_i[k] - d[k] */
      mpq_set_d(m[3 * i + k], row[i][k]);
      mpq_set_d(dk, d[k]);
      mpq_sub(m[3 * i + k], m[3 * i + k], dk);
    }
  /* det = m0 (m4 m8 - m5 m7) - m1 (m3 m8 - m5 m6) + m2 (m3 m7 - m4 m6) */
  mpq_set_ui(det, 0, 1);
  static const int cof[3][5] = {{0, 4, 8, 5, 7}, {1, 3, 8, 5, 6}, {2, 3, 7, 4, 6}};
  for (int i = 0; i < 3; i++) {
    mpq_mul(t, m[cof[i][1]], m[cof[i][2]]);
    mpq_mul(u, m[cof[i][3]], m[cof[i][4]]);
    mpq_sub(t, t, u);
    mpq_mul(t, t, m[cof[i][0]]);
    if (i == 1) mpq_sub(det, det, t);
    else mpq_add(det, det, t);
  }
  int s = mpq_sgn(det);
  for (int i = 0; i < 9; i++) mpq_clear(m[i]);
  mpq_clears(t, u, det, dk, NULL);
  return s;
}

/* ---- filtered predicates ---- */

/* x y == 0 exactly because a factor is 0, not by underflow (for finite
 * doubles x - y == 0 only if x == y: gradual underflow) */
static int zero_prod(double x, double y) { return x == 0.0 || y == 0.0; }

int cb_orient2d(const double *a, const double *b, const double *c) {
  double detleft = (a[0] - c[0]) * (b[1] - c[1]);
  double detright = (a[1] - c[1]) * (b[0] - c[0]);
  double det = detleft - detright;
  double detsum = fabs(detleft) + fabs(detright);
  if (detsum > TINY && detsum < HUGE_) {
    double bound = CCW_BOUND * detsum;
    if (det > bound) return 1;
    if (-det > bound) return -1;
  } else if (detsum == 0.0 && zero_prod(a[0] - c[0], b[1] - c[1]) && zero_prod(a[1] - c[1], b[0] - c[0])) {
    return 0; /* both products have an exactly zero factor: det = 0 exactly */
  }
  return orient2d_exact(a, b, c);
}

int cb_orient3d(const double *a, const double *b, const double *c, const double *d) {
  double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  double cdxady = cdx * ady, adxcdy = adx * cdy;
  double adxbdy = adx * bdy, bdxady = bdx * ady;
  /* det = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady) */
  double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  double perm = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) + (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
  if (perm > TINY && perm < HUGE_) {
    double bound = O3D_BOUND * perm;
    if (det > bound) return 1;
    if (-det > bound) return -1;
  } else if (perm == 0.0 && (adz == 0.0 || (zero_prod(bdx, cdy) && zero_prod(cdx, bdy))) &&
             (bdz == 0.0 || (zero_prod(cdx, ady) && zero_prod(adx, cdy))) &&
             (cdz == 0.0 || (zero_prod(adx, bdy) && zero_prod(bdx, ady)))) {
    return 0; /* every term has an exactly zero factor (e.g. four points in one z plane) */
  }
  return orient3d_exact(a, b, c, d);
}

/* ---- 2D pieces, on the projection that drops axis k ---- */

static void proj(const double *p, int k, double *out) {
  out[0] = p[k == 0 ? 1 : 0];
  out[1] = p[k == 2 ? 1 : 2];
}

/* lexicographic order (x, then y): monotone along any line */
static int lex_cmp(const double *a, const double *b) {
  if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
  if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
  return 0;
}

/* x on the line of (c, d) lies on the closed segment */
static int between(const double *c, const double *d, const double *x) {
  const double *lo = lex_cmp(c, d) <= 0 ? c : d, *hi = lo == c ? d : c;
  return lex_cmp(lo, x) <= 0 && lex_cmp(x, hi) <= 0;
}

/* closed segments (a, b) and (c, d) in the plane */
static int seg2(const double *a, const double *b, const double *c, const double *d) {
  int o1 = cb_orient2d(a, b, c), o2 = cb_orient2d(a, b, d);
  if (o1 * o2 > 0) return 0;
  int o3 = cb_orient2d(c, d, a), o4 = cb_orient2d(c, d, b);
  if (o3 * o4 > 0) return 0;
  if ((o1 || o2) && (o3 || o4)) return 1; /* not all on one line: the lines cross within both */
  int pa = lex_cmp(a, b) == 0, pc = lex_cmp(c, d) == 0;
  if (pa && pc) return lex_cmp(a, c) == 0;
  if (pa) return o3 == 0 && between(c, d, a);
  if (pc) return o1 == 0 && between(a, b, c);
  /* o1 = o2 = 0 (c, d on the line ab) or o3 = o4 = 0: all four on one line */
  const double *alo = lex_cmp(a, b) <= 0 ? a : b, *ahi = alo == a ? b : a;
  const double *clo = lex_cmp(c, d) <= 0 ? c : d, *chi = clo == c ? d : c;
  return lex_cmp(alo, chi) <= 0 && lex_cmp(clo, ahi) <= 0;
}

/* x in the closed, non-degenerate triangle (p0, p1, p2) */
static int in_tri2(const double *x, const double *p0, const double *p1, const double *p2) {
  int s0 = cb_orient2d(p0, p1, x), s1 = cb_orient2d(p1, p2, x), s2 = cb_orient2d(p2, p0, x);
  return !((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0));
}

/* closed segments in space */
static int seg3(const double *a, const double *b, const double *c, const double *d) {
  if (cb_orient3d(a, b, c, d)) return 0;
  for (int k = 0; k < 3; k++) {
    double a2[2], b2[2], c2[2], d2[2];
    proj(a, k, a2);
    proj(b, k, b2);
    proj(c, k, c2);
    proj(d, k, d2);
    if (!seg2(a2, b2, c2, d2)) return 0;
  }
  return 1;
}

/* The axis whose projection keeps the triangle's area (exactly non-zero), or
 * -1 if the triangle is degenerate (collinear points). */
static int tri_axis(const double *p0, const double *p1, const double *p2) {
  for (int k = 0; k < 3; k++) {
    double a[2], b[2], c[2];
    proj(p0, k, a);
    proj(p1, k, b);
    proj(p2, k, c);
    if (cb_orient2d(a, b, c)) return k;
  }
  return -1;
}

static int seg_tri(const double *a, const double *b, const double *p0, const double *p1, const double *p2, int axis) {
  if (axis < 0) return seg3(a, b, p0, p1) || seg3(a, b, p1, p2) || seg3(a, b, p2, p0);
  int sa = cb_orient3d(p0, p1, p2, a), sb = cb_orient3d(p0, p1, p2, b);
  if (sa * sb > 0) return 0;
  if (sa || sb) { /* the line ab meets the plane once, within the segment */
    int s0 = cb_orient3d(a, b, p0, p1), s1 = cb_orient3d(a, b, p1, p2), s2 = cb_orient3d(a, b, p2, p0);
    return !((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0));
  }
  double a2[2], b2[2], q0[2], q1[2], q2[2]; /* in the plane */
  proj(a, axis, a2);
  proj(b, axis, b2);
  proj(p0, axis, q0);
  proj(p1, axis, q1);
  proj(p2, axis, q2);
  return in_tri2(a2, q0, q1, q2) || in_tri2(b2, q0, q1, q2) || seg2(a2, b2, q0, q1) || seg2(a2, b2, q1, q2) ||
         seg2(a2, b2, q2, q0);
}

int cb_seg_tri_intersect(const double *a, const double *b, const double *p0, const double *p1, const double *p2) {
  return seg_tri(a, b, p0, p1, p2, tri_axis(p0, p1, p2));
}

/* all of q strictly on one side of the plane of p (p non-degenerate) */
static int one_side(const double *p0, const double *p1, const double *p2, const double *q0, const double *q1,
                    const double *q2) {
  int s0 = cb_orient3d(p0, p1, p2, q0);
  if (!s0) return 0;
  int s1 = cb_orient3d(p0, p1, p2, q1);
  if (s1 != s0) return 0;
  return cb_orient3d(p0, p1, p2, q2) == s0;
}

int cb_tri_tri_intersect(const double *p0, const double *p1, const double *p2, const double *q0, const double *q1,
                         const double *q2) {
  int ap = tri_axis(p0, p1, p2), aq = tri_axis(q0, q1, q2);
  if (ap >= 0 && one_side(p0, p1, p2, q0, q1, q2)) return 0;
  if (aq >= 0 && one_side(q0, q1, q2, p0, p1, p2)) return 0;
  const double *P[3] = {p0, p1, p2}, *Q[3] = {q0, q1, q2};
  for (int k = 0; k < 3; k++)
    if (seg_tri(P[k], P[(k + 1) % 3], q0, q1, q2, aq)) return 1;
  for (int k = 0; k < 3; k++)
    if (seg_tri(Q[k], Q[(k + 1) % 3], p0, p1, p2, ap)) return 1;
  return 0;
}
