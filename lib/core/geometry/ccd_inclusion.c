/* Inclusion-based conservative CCD: branch and bound over (t, u, v) with
 * outward-rounded interval arithmetic (our own C after the idea of Wang,
 * Ferguson, Schneider, Panozzo 2021, "A Large-Scale Benchmark and an
 * Inclusion-Based Algorithm for Continuous Collision Detection").
 *
 * The separation vector. With x_k(t) = x_k + t (x_{k+4} - x_k):
 *   vf: F(t,u,v) = x_0(t) - [(1-u-v) x_1(t) + u x_2(t) + v x_3(t)],  u, v >= 0, u + v <= 1
 *       = D(t) + u E1(t) + v E2(t),  D = x_0 - x_1, E1 = x_1 - x_2, E2 = x_1 - x_3
 *   ee: F(t,u,v) = [(1-u) x_0(t) + u x_1(t)] - [(1-v) x_2(t) + v x_3(t)],  u, v in [0, 1]
 *       = D(t) + u E1(t) + v E2(t),  D = x_0 - x_2, E1 = x_1 - x_0, E2 = x_2 - x_3
 * Contact at t  <=>  min over (u, v) of |F(t,u,v)|_2 <= eta.
 *
 * Why corners suffice. Each component F_j is multilinear: of degree at most 1
 * in each of t, u, v separately (its monomials are 1, t, u, v, tu, tv). A
 * function affine in each variable separately takes its minimum and maximum
 * over a box at the box's vertices (fix two variables: affine in the third,
 * so extreme at an end; repeat). So the exact range of F_j over a box B is
 * [min, max] of its 8 corner values.
 *
 * Exclusion. If for some j every corner value of F_j is > eta, or every one
 * is < -eta, then |F|_2 >= |F_j| > eta on all of B: no contact in B. The
 * corner values are computed in interval arithmetic rounded outward (each
 * operation's double result r widened to [pred(r), succ(r)]: round to nearest
 * puts the exact value within half an ulp of r, so inside), starting from the
 * input intervals [lo, hi]; the enclosure of each corner value contains the
 * exact value for every input in the intervals. A box is excluded only when
 * the enclosures say so: no rounding can exclude a box that holds a contact.
 * The corners t, u, v are dyadic numbers (bisections of [0, 1], at most
 * MAX_DEPTH halvings), exact in double; u0 + v0 is exact too (<= 51 bits).
 * A vf box with u0 + v0 > 1 lies outside the triangle's parameter simplex and
 * is dropped; a box that straddles u + v = 1 is kept (its corners outside the
 * simplex only widen the range: still conservative).
 *
 * Search order and the time of impact. Depth first, the earlier half in t
 * first. A box is accepted as a hit, and best = min(best, its t0), when
 *  - a witness shows a contact at its latest time t1 (|F_j(t1, u, v)| <= eta
 *    for all j, in outward-rounded arithmetic, at the centre or a corner of
 *    its (u, v) box) and its t-width is at most tol (else t is halved, to
 *    localise the contact in time), or
 *  - the variation of F over it (from the enclosures' midpoints) is at most
 *    tol_abs in every component. Boxes with t0 >= best are pruned. At the end every (t, u, v) with
 * t < best lies in an excluded box, so the first contact t* >= best = toi.
 * Whatever the acceptance rule, only exclusion decides what is missed: the
 * acceptance rule only sets how many false positives there are. When the
 * budget runs out, toi = the smallest t0 among best and the boxes still on
 * the stack (every unexcluded box is there), still <= t*.
 *
 * What a hit means. An accepted box holds (t, u, v) with |F_j| <= eta + its
 * variation in every j, so the primitives came within eta + tol_abs in the
 * infinity norm (sqrt(3) (eta + tol_abs) in the 2-norm, plus rounding) at
 * some time in [toi, toi + box width]: the false positives are near misses
 * by at most that much, or the early toi of a slow approach.
 *
 * tol_abs = max(tol * extent, maxabs * 2^-50): extent is the largest side of
 * the box around the 8 points, maxabs their largest |coordinate| (below
 * maxabs * 2^-50 the enclosures' own rounding width dominates and no split
 * can make the variation smaller). No allocation: the stack of boxes is at
 * most 3 MAX_DEPTH + 1 deep (each split pushes one more, every box lies at
 * most 3 MAX_DEPTH halvings below the root). */
#include <clothbench/ccd.h>

#include <float.h>
#include <math.h>

#include <clothbench/status.h>

enum { MAX_DEPTH = 50, STACK = 3 * MAX_DEPTH + 4 };

typedef struct {
  double lo, hi;
} ival;

/* the neighbouring doubles: an exact result rounded to r lies in [down(r), up(r)] */
static inline double down(double r) { return nextafter(r, -INFINITY); }
static inline double up(double r) { return nextafter(r, INFINITY); }

/* r = fl(exact) and err = exact - r, known exactly (below): the interval [r, r] when the operation was exact,
 * else the side of r the exact value lies on, widened by one ulp */
static inline ival around(double r, double err) {
  if (err == 0.0) return (ival){r, r};
  return err > 0.0 ? (ival){r, up(r)} : (ival){down(r), r};
}
/* Knuth's TwoSum: s + e = a + b exactly (round to nearest, no overflow: |x| <= 2^503 here) */
static inline ival sum_lo(double a, double b) {
  double s = a + b, bb = s - a, e = (a - (s - bb)) + (b - bb);
  return around(s, e);
}
/* the product's error by fma (exact unless the product is near underflow: then widen both ways) */
static inline ival prod(double a, double b) {
  if (a == 0.0 || b == 0.0) return (ival){0.0, 0.0}; /* exact */
  double r = a * b;
  if (fabs(r) < 0x1p-900) return (ival){down(r), up(r)};
  return around(r, fma(a, b, -r));
}

static inline ival iv_sub(ival a, ival b) { return (ival){sum_lo(a.lo, -b.hi).lo, sum_lo(a.hi, -b.lo).hi}; }
static inline ival iv_add(ival a, ival b) { return (ival){sum_lo(a.lo, b.lo).lo, sum_lo(a.hi, b.hi).hi}; }
/* s a in [0, 1], s >= 0 exact: the product keeps the order of the ends */
static inline ival iv_scale(double s, ival a) {
  if (s == 0.0) return (ival){0.0, 0.0};
  if (s == 1.0) return a;
  return (ival){prod(s, a.lo).lo, prod(s, a.hi).hi};
}

typedef struct {
  double t0, t1, u0, u1, v0, v1;
  unsigned char dt, du, dv; /* halvings so far in each variable */
} box;

/* x_k(t) for the 4 points at one time t, component j, as intervals */
static void positions(const cb_ccd_query *q, double t, ival P[4][3]) {
  for (int k = 0; k < 4; k++)
    for (int j = 0; j < 3; j++) {
      ival a = {q->lo[k][j], q->hi[k][j]}, b = {q->lo[k + 4][j], q->hi[k + 4][j]};
      if (t == 0.0) P[k][j] = a;
      else if (t == 1.0) P[k][j] = b;
      else P[k][j] = iv_add(a, iv_scale(t, iv_sub(b, a))); /* x_k + t (x_{k+4} - x_k) */
    }
}

/* D, E1, E2 of the header comment at time t (intervals) */
static void terms(const cb_ccd_query *q, int kind, double t, ival D[3], ival E1[3], ival E2[3]) {
  ival P[4][3];
  positions(q, t, P);
  for (int j = 0; j < 3; j++) {
    if (kind == CB_CCD_VF) {
      D[j] = iv_sub(P[0][j], P[1][j]);
      E1[j] = iv_sub(P[1][j], P[2][j]);
      E2[j] = iv_sub(P[1][j], P[3][j]);
    } else {
      D[j] = iv_sub(P[0][j], P[2][j]);
      E1[j] = iv_sub(P[1][j], P[0][j]);
      E2[j] = iv_sub(P[2][j], P[3][j]);
    }
  }
}

/* F at u, v from D, E1, E2: D + u E1 + v E2 (u, v in [0, 1]; the scale takes u, v >= 0 as given) */
static inline ival corner(ival D, ival E1, ival E2, double u, double v) {
  return iv_add(iv_add(D, iv_scale(u, E1)), iv_scale(v, E2));
}

enum { EXCLUDED = 0, ACCEPTED = 1, SPLIT = 2 };

/* Whether the box certainly holds a contact at its latest time t1: |F_j(t1, u, v)| <= eta for every j at
 * the centre or a corner (u, v) of its parameter box (inside the simplex for vf), in outward-rounded
 * arithmetic. The corners catch contacts that touch the eta-cube exactly at a box's side. */
static int witness(const cb_ccd_query *q, int kind, const box *b, double eta) {
  ival D[3], E1[3], E2[3];
  terms(q, kind, b->t1, D, E1, E2);
  const double us[5] = {0.5 * (b->u0 + b->u1), b->u0, b->u0, b->u1, b->u1};
  const double vs[5] = {0.5 * (b->v0 + b->v1), b->v0, b->v1, b->v0, b->v1};
  for (int k = 0; k < 5; k++) {
    if (kind == CB_CCD_VF && us[k] + vs[k] > 1.0) continue;
    int in = 1;
    for (int j = 0; j < 3 && in; j++) {
      ival f = corner(D[j], E1[j], E2[j], us[k], vs[k]);
      in = f.lo >= -eta && f.hi <= eta;
    }
    if (in) return 1;
  }
  return 0;
}

/* Examines box b: EXCLUDED, ACCEPTED, or SPLIT with *dim the variable to halve (0 t, 1 u, 2 v). */
static int examine(const cb_ccd_query *q, int kind, const box *b, double eta, double tol_abs, double tol_t, int *dim) {
  if (kind == CB_CCD_VF && b->u0 + b->v0 > 1.0) return EXCLUDED; /* outside the simplex */
  double mid[8][3];                                              /* corner c = 4 it + 2 iu + iv */
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int it = 0; it < 2; it++) {
    ival D[3], E1[3], E2[3];
    terms(q, kind, it ? b->t1 : b->t0, D, E1, E2);
    for (int iu = 0; iu < 2; iu++)
      for (int iv = 0; iv < 2; iv++) {
        double u = iu ? b->u1 : b->u0, v = iv ? b->v1 : b->v0;
        for (int j = 0; j < 3; j++) {
          ival f = corner(D[j], E1[j], E2[j], u, v);
          lo[j] = fmin(lo[j], f.lo);
          hi[j] = fmax(hi[j], f.hi);
          mid[4 * it + 2 * iu + iv][j] = 0.5 * f.lo + 0.5 * f.hi;
        }
      }
  }
  for (int j = 0; j < 3; j++)
    if (lo[j] > eta || hi[j] < -eta) return EXCLUDED; /* |F| >= |F_j| > eta on the whole box */
  if (witness(q, kind, b, eta)) {
    /* a contact (within eta in every component) at t1: localise it in time, the earlier half first */
    if (b->t1 - b->t0 <= tol_t || b->dt >= MAX_DEPTH) return ACCEPTED;
    *dim = 0;
    return SPLIT;
  }
  /* variation of F over the box and each variable's share: the largest change of a component between two
   * corners that differ in that variable only */
  double var = 0.0, share[3] = {0.0, 0.0, 0.0};
  for (int j = 0; j < 3; j++) {
    double mn = INFINITY, mx = -INFINITY;
    for (int c = 0; c < 8; c++) {
      mn = fmin(mn, mid[c][j]);
      mx = fmax(mx, mid[c][j]);
      for (int d = 0; d < 3; d++) {
        int bit = 4 >> d;
        if (!(c & bit)) share[d] = fmax(share[d], fabs(mid[c | bit][j] - mid[c][j]));
      }
    }
    var = fmax(var, mx - mn);
  }
  if (var <= tol_abs) return ACCEPTED;
  const unsigned char depth[3] = {b->dt, b->du, b->dv};
  int best = -1;
  for (int d = 0; d < 3; d++)
    if (depth[d] < MAX_DEPTH && (best < 0 || share[d] > share[best])) best = d;
  if (best < 0) return ACCEPTED; /* as small as boxes get: cannot exclude, so a (conservative) hit */
  *dim = best;
  return SPLIT;
}

static int run(const cb_ccd_query *q, int kind, const cb_ccd_params *p, cb_ccd_result *r) {
  double mn[3], mx[3], maxabs = 0.0;
  for (int j = 0; j < 3; j++) {
    mn[j] = INFINITY;
    mx[j] = -INFINITY;
    for (int k = 0; k < 8; k++) {
      mn[j] = fmin(mn[j], q->lo[k][j]);
      mx[j] = fmax(mx[j], q->hi[k][j]);
      maxabs = fmax(maxabs, fmax(fabs(q->lo[k][j]), fabs(q->hi[k][j])));
    }
  }
  double extent = fmax(mx[0] - mn[0], fmax(mx[1] - mn[1], mx[2] - mn[2]));
  double tol_abs = fmax(p->tol * extent, maxabs * 0x1p-50);

  box stack[STACK];
  int n = 0;
  stack[n++] = (box){0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0, 0, 0};
  double best = INFINITY;
  long boxes = 0;
  int status = CB_OK;
  while (n > 0) {
    box b = stack[--n];
    if (b.t0 >= best) continue; /* cannot hold an earlier contact */
    if (boxes >= p->max_boxes) {
      /* budget spent: every box not excluded is b or on the stack */
      best = fmin(best, b.t0);
      for (int i = 0; i < n; i++) best = fmin(best, stack[i].t0);
      status = CB_NOT_CONVERGED;
      break;
    }
    boxes++;
    int dim = 0, e = examine(q, kind, &b, p->eta, tol_abs, p->tol, &dim);
    if (e == EXCLUDED) continue;
    if (e == ACCEPTED) {
      best = b.t0; /* < best, by the test above */
      if (best == 0.0) break;
      continue;
    }
    box lo = b, hi = b;
    if (dim == 0) {
      double m = 0.5 * (b.t0 + b.t1); /* exact: dyadic, at most MAX_DEPTH bits */
      lo.t1 = hi.t0 = m;
      lo.dt = hi.dt = (unsigned char)(b.dt + 1);
    } else if (dim == 1) {
      double m = 0.5 * (b.u0 + b.u1);
      lo.u1 = hi.u0 = m;
      lo.du = hi.du = (unsigned char)(b.du + 1);
    } else {
      double m = 0.5 * (b.v0 + b.v1);
      lo.v1 = hi.v0 = m;
      lo.dv = hi.dv = (unsigned char)(b.dv + 1);
    }
    /* n <= 3 MAX_DEPTH here: the stack holds at most one box per halving above b */
    stack[n++] = hi; /* the later (or other) half waits */
    stack[n++] = lo; /* the earlier half first */
  }
  r->boxes = boxes;
  r->hit = best <= 1.0;
  r->toi = r->hit ? best : 1.0;
  return status;
}

static int vf(const cb_ccd_query *q, const cb_ccd_params *p, cb_ccd_result *r) { return run(q, CB_CCD_VF, p, r); }
static int ee(const cb_ccd_query *q, const cb_ccd_params *p, cb_ccd_result *r) { return run(q, CB_CCD_EE, p, r); }

const cb_ccd_type cb_ccd_inclusion = {.name = "inclusion", .vf = vf, .ee = ee};
