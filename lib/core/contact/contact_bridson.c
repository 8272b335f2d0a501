/* `bridson` (contact.h): Bridson, Fedkiw & Anderson 2002, "Robust treatment
 * of collisions, contact and friction for cloth animation" (SIGGRAPH), as a
 * post-step response (scene.h) that filters every step of every integrator.
 *
 * The step. The integrator moved the cloth x0 -> x1 in time h and left it
 * the velocity v. The filter works on the step's average velocity
 * u = (x1 - x0)/h (the paper's v_{n+1/2}; x1 = x0 + h u), changes it by
 * impulses to u', and returns x1' = x0 + h u' and v' = v + (u' - u) (the
 * velocity changes carried to the end velocity, paper §6). Pinned vertices
 * and the obstacle's vertices take part with infinite mass (inverse mass 0):
 * they move as prescribed (the obstacle from its positions at t and t + h,
 * on the straight line between them) and no impulse changes them.
 *
 * Pairs are vertex-face (p; a, b, c) and edge-edge (a0, a1; b0, b1) of one
 * combined mesh, cloth then obstacle, from one broad phase (broadphase.h,
 * boxes grown by the thickness; adjacent pairs left out; pairs whose four
 * vertices all have infinite mass skipped). A pair's closest points give
 * weights alpha (point-face: 1, -w_a, -w_b, -w_c with w the closest point's
 * barycentric coordinates; edge-edge: 1 - s, s, -(1 - t), -t), so that
 *   r = sum_k alpha_k x_k       (closest point of the first primitive less the second's),
 *   d = |r|, n = r / d,  u_rel = sum_k alpha_k u_k,  u_N = u_rel . n,  u_T = u_rel - u_N n.
 * An impulse J on the pair gives vertex k the velocity change alpha_k w_k J
 * (w_k = 1/m_k, 0 for infinite mass), so u_rel changes by W J with
 * W = sum_k alpha_k^2 w_k: a change du of u_rel takes J = du / W (the least
 * kinetic energy that does it). sum_k alpha_k = 0, so sum_k m_k du_k = 0:
 * impulses between free vertices conserve linear momentum.
 *
 * (a) Repulsion (§7.2), at the step's start x0, for pairs with d < H
 *     (H = contact.thickness, overlap o = H - d):
 *       inelastic: if u_N < 0, du_N = -u_N (the approach stops);
 *       spring:    if u_N + du_N < 0.1 o / h, du_N += min(h k o W, 0.1 o / h - (u_N + du_N))
 *                  (the impulse h k o of a spring k = contact.stiffness, limited so the pair
 *                  separates by at most a tenth of the overlap in the step);
 *       friction:  u_T' = max(1 - mu du_N / |u_T|, 0) u_T  (Coulomb: the tangential change is
 *                  at most mu times the normal one; mu = contact.friction);
 *     du = du_N n + (u_T' - u_T), applied pair after pair (Gauss-Seidel).
 * (b) Collisions (§7.3): up to contact.bridson_iters passes. A pass takes the
 *     broad phase over the swept boxes of x0 -> x0 + h u and runs CCD on each
 *     candidate; a hit at time toi gets, with the geometry at x0 + toi h u
 *     and the current u, the inelastic impulse du_N = -u_N (if u_N < 0) and
 *     the same friction. A pass that finds no hit ends the stage: the step is
 *     free of collisions.
 * (c) Rigid impact zones (§7.4), the fail-safe, when the passes ran out: the
 *     four vertices of every pair that still collides are merged into zones
 *     (union-find; zones persist and grow over the zone passes), and each
 *     zone's velocities are replaced by its rigid motion,
 *       x_c = sum m x / M,  u_c = sum m u / M,  L = sum m (x - x_c) x (u - u_c),
 *       I = sum m (|r|^2 1 - r r^T),  omega = I^-1 L,  u_i = u_c + omega x (x_i - x_c),
 *     which keeps the zone's linear momentum M u_c and its angular momentum
 *     I omega = L. A zone with infinite-mass vertices (pins, the obstacle)
 *     takes the rigid motion fitted to those vertices alone (the limit of
 *     the formula as their masses grow without bound, equal among them) for
 *     its free vertices; the infinite-mass ones keep their own. Repeated
 *     until a pass's CCD finds nothing. The rigid velocity field moves the
 *     zone by the affine map 1 + t h [omega]x on the straight line
 *     (the paper turns it by exp(t h [omega]x); the straight line is what the
 *     CCD checks), whose singular values are 1 and sqrt(1 + (t h |omega|)^2):
 *     no distance inside a zone shrinks, so a zone never collides with
 *     itself: the zone passes skip the pairs inside a zone of free vertices
 *     only (for any omega: the field is rigid whatever its omega). A zone
 *     pass whose hits are all inside zones (only possible when prescribed
 *     vertices move non-rigidly, or ACCD's advance budget runs out on a gap
 *     far smaller than the motion, a conservative hit) cannot progress: the
 *     filter stops and the step's status is CB_NOT_CONVERGED
 *     (cb_bridson_stats.unresolved).
 *
 * CCD: additive CCD (Li, Kaufman & Jiang 2021, the method contact_term.c uses
 * for IPC's step bound), here with a minimum separation eta: the gap
 * g(t) = d(t) - eta, l = the largest relative displacement of the first
 * primitive's vertices plus the second's (a bound of how fast d can shrink
 * per unit t); from t = 0 it advances by 0.9 g / l (the first advance 0.9 g(0)
 * / l) until the gap is below 0.1 g(0) (a hit at the last time reached) or
 * t passes 1 (no hit). Between two samples d cannot shrink by more than
 * 0.9 g, so "no hit" means d > eta over the whole step. eta = 0.1 H, and at
 * most half the pair's distance at x0, so a pair that starts closer than
 * 0.1 H is not reported at t = 0 for being close. A pair whose distance at x0
 * exceeds eta plus the two primitives' largest displacements (by 1%) cannot
 * come within eta and skips the query.
 *
 * Everything is allocated at set-up; a step allocates only when the
 * candidate arrays overflow (grown, counted in cb_bridson_stats.grows). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact_keys.h"
#include <clothbench/broadphase.h>
#include <clothbench/intersect.h>
#include <clothbench/response.h>
#include <clothbench/status.h>
#include "vec.h"

#define GAP 0.1          /* ACCD stops when the gap is below GAP g(0) */
#define ACCD_MAX 2000    /* ACCD advances at most, then a hit at the time reached (conservative) */
#define ETA_FRAC 0.1     /* the CCD's minimum separation, a fraction of the thickness */
#define SAFE_MARGIN 1.01 /* the distance filter before CCD, with 1% for round-off */

typedef struct {
  cb_contact_params p;
  const cb_obstacle *ob;
  int nv, N, T;   /* cloth vertices; combined vertices (cloth, then obstacle) and triangles */
  int *tri;       /* 3T: the cloth's, then the obstacle's shifted by nv */
  double *winv;   /* N: 1/m of free cloth vertices, 0 for pins and the obstacle */
  double *mass;   /* N: m (0 for infinite) */
  double *X0;     /* 3N: positions at the step's start */
  double *X1;     /* 3N: x0 + h u of the current pass */
  double *U, *U0; /* 3N: the average velocity, and as the integrator left it */
  cb_broadphase *bp;
  const int *edges;
  int ne;
  cb_candidates cand;
  int *parent;                    /* N: the impact zones (union-find) */
  double *zm, *zx, *zu, *zL, *zI; /* N, 3N, 3N, 3N, 9N: per zone root: weight, sum w x, sum w u, L, I */
  int *zfixed;                    /* N: per root, 1 if the zone has an infinite-mass vertex */
  int *zrigid; /* N: the zone each vertex moved rigidly in at the last rigid_zones (its root), -1 for none: a zone of
                  two or more vertices, all free */
  double t;    /* s, time reached */
  cb_bridson_stats stats;
} bridson_state;

/* ---- closest points ------------------------------------------------------- */

/* The parameter of the point of segment ab closest to p, in [0, 1]. */
static double seg_param(const double *p, const double *a, const double *b) {
  double ab[3], ap[3];
  cb_v3_sub(b, a, ab);
  cb_v3_sub(p, a, ap);
  double l2 = cb_v3_dot(ab, ab);
  if (!(l2 > 0)) return 0;
  double t = cb_v3_dot(ap, ab) / l2;
  return t < 0 ? 0 : t > 1 ? 1 : t;
}

/* |sum alpha_k q_k| and r = that vector, for the four points q. */
static double weighted(const double *const q[4], const double alpha[4], double *r) {
  for (int c = 0; c < 3; c++) r[c] = alpha[0] * q[0][c] + alpha[1] * q[1][c] + alpha[2] * q[2][c] + alpha[3] * q[3][c];
  return cb_v3_norm(r);
}

/* Point p, triangle (a, b, c): alpha = (1, -w_a, -w_b, -w_c) of the closest
 * point. Inside the face: the projection's barycentric coordinates from the
 * normal equations of min |a + s (b - a) + t (c - a) - p|^2; else the nearest
 * of the three edges' closest points. Returns the distance. */
static double point_triangle(const double *const q[4], double alpha[4], double *r) {
  const double *p = q[0], *a = q[1], *b = q[2], *c = q[3];
  double ab[3], ac[3], ap[3];
  cb_v3_sub(b, a, ab);
  cb_v3_sub(c, a, ac);
  cb_v3_sub(p, a, ap);
  double A = cb_v3_dot(ab, ab), B = cb_v3_dot(ab, ac), C = cb_v3_dot(ac, ac), det = A * C - B * B;
  if (det > 1e-14 * A * C) { /* a triangle with area */
    double e = cb_v3_dot(ab, ap), f = cb_v3_dot(ac, ap);
    double s = (C * e - B * f) / det, t = (A * f - B * e) / det; /* [A B; B C] (s, t) = (e, f) */
    if (s >= 0 && t >= 0 && s + t <= 1) {
      alpha[0] = 1, alpha[1] = -(1 - s - t), alpha[2] = -s, alpha[3] = -t;
      return weighted(q, alpha, r);
    }
  }
  double best = INFINITY, al[4], rr[3];
  for (int k = 0; k < 3; k++) { /* edges (a b), (b c), (c a) */
    int i = 1 + k, j = 1 + (k + 1) % 3;
    double s = seg_param(p, q[i], q[j]);
    al[0] = 1, al[1] = al[2] = al[3] = 0;
    al[i] = -(1 - s);
    al[j] = -s;
    double d = weighted(q, al, rr);
    if (d < best) {
      best = d;
      memcpy(alpha, al, sizeof al);
      memcpy(r, rr, sizeof rr);
    }
  }
  return best;
}

/* Edges (a0, a1), (b0, b1): alpha = (1 - s, s, -(1 - t), -t) of the closest
 * points. The squared distance is a convex quadratic of (s, t) on the unit
 * square: its minimum is the lines' closest pair if that lies inside (and
 * the edges are not parallel), else on the square's boundary, where one
 * parameter is 0 or 1 and the other the projection of that end point. */
static double edge_edge(const double *const q[4], double alpha[4], double *r) {
  double best = INFINITY, al[4], rr[3];
  double da[3], db[3], w[3];
  cb_v3_sub(q[1], q[0], da);
  cb_v3_sub(q[3], q[2], db);
  cb_v3_sub(q[0], q[2], w);
  double A = cb_v3_dot(da, da), B = cb_v3_dot(da, db), C = cb_v3_dot(db, db), D = cb_v3_dot(da, w),
         E = cb_v3_dot(db, w), det = A * C - B * B;
  if (det > 1e-14 * A * C) { /* minimise |w + s da - t db|^2: [A -B; -B C] (s, t) = (-D, E) */
    double s = (B * E - C * D) / det, t = (A * E - B * D) / det;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
      alpha[0] = 1 - s, alpha[1] = s, alpha[2] = -(1 - t), alpha[3] = -t;
      return weighted(q, alpha, r);
    }
  }
  for (int k = 0; k < 4; k++) { /* an end point against the other edge */
    int first = k < 2;
    const double *p = q[k], *e0 = q[first ? 2 : 0], *e1 = q[first ? 3 : 1];
    double s = seg_param(p, e0, e1);
    al[0] = al[1] = al[2] = al[3] = 0;
    if (first) {
      al[k] = 1, al[2] = -(1 - s), al[3] = -s;
    } else {
      al[k] = -1, al[0] = 1 - s, al[1] = s;
    }
    double d = weighted(q, al, rr);
    if (d < best) {
      best = d;
      memcpy(alpha, al, sizeof al);
      memcpy(r, rr, sizeof rr);
    }
  }
  return best;
}

static double closest(int ee, const double *const q[4], double alpha[4], double *r) {
  return ee ? edge_edge(q, alpha, r) : point_triangle(q, alpha, r);
}

/* ---- pairs ---------------------------------------------------------------- */

/* Candidate i (vertex-face pairs first, then edge-edge): its four combined vertex indices; returns 1 for edge-edge. */
static int pair_vertices(const bridson_state *b, long i, int idx[4]) {
  if (i < b->cand.nvf) {
    const int *pr = b->cand.vf + 2 * i, *f = b->tri + 3 * pr[1];
    idx[0] = pr[0], idx[1] = f[0], idx[2] = f[1], idx[3] = f[2];
    return 0;
  }
  const int *pr = b->cand.ee + 2 * (i - b->cand.nvf), *ea = b->edges + 2 * pr[0], *eb = b->edges + 2 * pr[1];
  idx[0] = ea[0], idx[1] = ea[1], idx[2] = eb[0], idx[3] = eb[1];
  return 1;
}

/* The candidates of the boxes of X0 (x1 NULL) or X0 -> x1; grows the arrays on overflow. */
static int find(bridson_state *b, const double *x1) {
  int st = cb_broadphase_update(b->bp, b->X0, x1);
  for (int tries = 0; st == CB_OK; tries++) {
    st = cb_broadphase_self_candidates(b->bp, &b->cand);
    if (st != CB_ENOMEM || tries == 4) break;
    long vf = 2 * b->cand.nvf, ee = 2 * b->cand.nee;
    cb_candidates n;
    if ((st = cb_candidates_alloc(vf > b->cand.cap_vf ? vf : b->cand.cap_vf, 0,
                                  ee > b->cand.cap_ee ? ee : b->cand.cap_ee, &n)))
      return st;
    cb_candidates_free(&b->cand);
    b->cand = n;
    b->stats.grows++;
    st = CB_OK;
  }
  return st;
}

/* Changes the pair's relative velocity by du (3): J = du / W onto the vertices; 0 if W = 0 (all infinite mass). */
static int impulse(bridson_state *b, const int idx[4], const double alpha[4], const double *du) {
  double W = 0;
  for (int k = 0; k < 4; k++) W += alpha[k] * alpha[k] * b->winv[idx[k]];
  if (!(W > 0)) return 0;
  for (int k = 0; k < 4; k++) {
    double c = alpha[k] * b->winv[idx[k]] / W; /* u_k += alpha_k w_k J, J = du / W */
    for (int a = 0; a < 3; a++) b->U[3 * idx[k] + a] += c * du[a];
  }
  return 1;
}

/* The relative velocity u_rel = sum alpha_k u_k, its normal part u_N along n, and W. */
static double relative(const bridson_state *b, const int idx[4], const double alpha[4], const double *n, double *urel,
                       double *W) {
  *W = 0;
  for (int a = 0; a < 3; a++) urel[a] = 0;
  for (int k = 0; k < 4; k++) {
    *W += alpha[k] * alpha[k] * b->winv[idx[k]];
    for (int a = 0; a < 3; a++) urel[a] += alpha[k] * b->U[3 * idx[k] + a];
  }
  return cb_v3_dot(urel, n);
}

/* du = duN n plus Coulomb friction on the tangential part of urel (uN its normal part): u_T' = max(1 - mu duN /
 * |u_T|, 0) u_T. */
static void with_friction(double mu, double duN, const double *n, const double *urel, double uN, double *du) {
  double uT[3], tn;
  for (int a = 0; a < 3; a++) uT[a] = urel[a] - uN * n[a];
  tn = cb_v3_norm(uT);
  double keep = tn > 0 ? fmax(1 - mu * duN / tn, 0.0) : 1.0;
  for (int a = 0; a < 3; a++) du[a] = duN * n[a] + (keep - 1) * uT[a];
}

static int all_fixed(const bridson_state *b, const int idx[4]) {
  return b->winv[idx[0]] == 0 && b->winv[idx[1]] == 0 && b->winv[idx[2]] == 0 && b->winv[idx[3]] == 0;
}

/* (a) Repulsion at X0 for the pairs closer than the thickness. */
static int repulsion(bridson_state *b, double h) {
  int st = find(b, NULL);
  if (st) return st;
  double H = b->p.thickness, k = b->p.stiffness;
  long n = b->cand.nvf + b->cand.nee;
  for (long i = 0; i < n; i++) {
    int idx[4], ee = pair_vertices(b, i, idx);
    if (all_fixed(b, idx)) continue;
    const double *q[4] = {b->X0 + 3 * idx[0], b->X0 + 3 * idx[1], b->X0 + 3 * idx[2], b->X0 + 3 * idx[3]};
    double alpha[4], r[3], urel[3], W, du[3];
    double d = closest(ee, q, alpha, r);
    if (!(d < H)) continue;
    b->stats.close++;
    b->stats.min_dist = fmin(b->stats.min_dist, d);
    if (!(d > 0)) continue; /* touching: no normal; the CCD passes and the zones take it */
    double nrm[3] = {r[0] / d, r[1] / d, r[2] / d};
    double uN = relative(b, idx, alpha, nrm, urel, &W);
    if (!(W > 0)) continue;
    double o = H - d, duN = uN < 0 ? -uN : 0, vmax = 0.1 * o / h;       /* inelastic: stop the approach */
    if (uN + duN < vmax) duN += fmin(h * k * o * W, vmax - (uN + duN)); /* the spring, limited */
    if (!(duN > 0)) continue;
    with_friction(b->p.friction, duN, nrm, urel, uN, du);
    b->stats.repulsions += impulse(b, idx, alpha, du);
  }
  return CB_OK;
}

/* Additive CCD with minimum separation eta of the pair q0 -> q0 + D (12 each): 1 and *toi on a hit. */
static int accd(int ee, const double *q0, const double *D, double eta, double *toi) {
  double Dr[12], mean[3] = {0, 0, 0}, lA = 0, lB = 0, q[12], alpha[4], r[3];
  int na = ee ? 2 : 1;
  for (int a = 0; a < 4; a++)
    for (int c = 0; c < 3; c++) mean[c] += 0.25 * D[3 * a + c];
  for (int a = 0; a < 4; a++) {
    for (int c = 0; c < 3; c++) Dr[3 * a + c] = D[3 * a + c] - mean[c]; /* a common translation keeps d */
    double m = cb_v3_norm(Dr + 3 * a);
    if (a < na) lA = fmax(lA, m);
    else lB = fmax(lB, m);
  }
  const double *qp[4] = {q, q + 3, q + 6, q + 9};
  memcpy(q, q0, sizeof q);
  double g0 = closest(ee, qp, alpha, r) - eta, l = lA + lB;
  *toi = 0;
  if (!(g0 > 0)) return 1;
  if (!(l > 0)) return 0; /* a rigid translation: d does not change */
  double t = 0, tl = (1 - GAP) * g0 / l;
  for (int it = 0; it < ACCD_MAX; it++) {
    for (int k = 0; k < 12; k++) q[k] = q0[k] + (t + tl) * Dr[k];
    double g = closest(ee, qp, alpha, r) - eta;
    if (!(g == g)) break; /* NaN: stop where it was still certain */
    if (t > 0 && g < GAP * g0) break;
    t += tl;
    if (t > 1) return 0;
    tl = 0.9 * g / l; /* d shrinks by at most l per unit t: the gap stays above 0.1 g */
  }
  *toi = t;
  return 1;
}

/* The root of i's impact zone (path halving). */
static int uf_find(int *parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

/* One CCD pass over X0 -> X0 + h U: impulses at the hits (zones == 0), or the hits' vertices merged into zones
 * (zones == 1; *merged counts the unions that joined two zones). Returns the status; *hits the pairs that hit. */
static int ccd_pass(bridson_state *b, double h, int zones, long *hits, long *merged) {
  int N3 = 3 * b->N;
  for (int i = 0; i < N3; i++) b->X1[i] = b->X0[i] + h * b->U[i];
  int st = find(b, b->X1);
  if (st) return st;
  double H = b->p.thickness;
  long n = b->cand.nvf + b->cand.nee;
  *hits = *merged = 0;
  for (long i = 0; i < n; i++) {
    int idx[4], ee = pair_vertices(b, i, idx);
    if (all_fixed(b, idx)) continue;
    int z = b->zrigid[idx[0]];
    if (z >= 0 && b->zrigid[idx[1]] == z && b->zrigid[idx[2]] == z && b->zrigid[idx[3]] == z)
      continue; /* inside a rigidly moving zone: no distance shrinks (the header) */
    double q0[12], D[12], mA = 0, mB = 0, alpha[4], r[3];
    for (int a = 0; a < 4; a++) {
      for (int c = 0; c < 3; c++) {
        q0[3 * a + c] = b->X0[3 * idx[a] + c];
        D[3 * a + c] = h * b->U[3 * idx[a] + c];
      }
      double m = cb_v3_norm(D + 3 * a);
      if (a < (ee ? 2 : 1)) mA = fmax(mA, m);
      else mB = fmax(mB, m);
    }
    const double *qp[4] = {q0, q0 + 3, q0 + 6, q0 + 9};
    double d0 = closest(ee, qp, alpha, r), eta = fmin(ETA_FRAC * H, 0.5 * d0), toi;
    if (d0 - eta > SAFE_MARGIN * (mA + mB)) continue; /* cannot come within eta */
    b->stats.ccd_queries++;
    if (!accd(ee, q0, D, eta, &toi)) continue;
    (*hits)++;
    if (zones) {
      for (int a = 1; a < 4; a++) {
        int ra = uf_find(b->parent, idx[0]), rb = uf_find(b->parent, idx[a]);
        if (ra != rb) {
          b->parent[rb] = ra;
          (*merged)++;
        }
      }
      continue;
    }
    double qt[12], urel[3], W, du[3];
    for (int k = 0; k < 12; k++) qt[k] = q0[k] + toi * D[k];
    const double *qtp[4] = {qt, qt + 3, qt + 6, qt + 9};
    double d = closest(ee, qtp, alpha, r);
    if (!(d > 0)) continue; /* no normal at toi: left to the zones */
    double nrm[3] = {r[0] / d, r[1] / d, r[2] / d};
    double uN = relative(b, idx, alpha, nrm, urel, &W);
    if (!(uN < 0) || !(W > 0)) continue;
    with_friction(b->p.friction, -uN, nrm, urel, uN, du); /* inelastic: u_N -> 0, and friction */
    b->stats.collisions += impulse(b, idx, alpha, du);
  }
  return CB_OK;
}

/* (c) Each zone's velocities replaced by its rigid motion (the header's formulas). */
static void rigid_zones(bridson_state *b) {
  int N = b->N;
  for (int i = 0; i < N; i++) {
    b->zm[i] = 0;
    b->zfixed[i] = 0;
    for (int a = 0; a < 3; a++) b->zx[3 * i + a] = b->zu[3 * i + a] = b->zL[3 * i + a] = 0;
    for (int a = 0; a < 9; a++) b->zI[9 * i + a] = 0;
  }
  for (int i = 0; i < N; i++)
    if (b->winv[i] == 0) b->zfixed[uf_find(b->parent, i)] = 1;
      /* weight: m for an all-free zone; 1 for the infinite-mass vertices of a zone that has them, 0 for its free ones
       */
#define WEIGHT(i, root) (b->zfixed[root] ? (b->winv[i] == 0 ? 1.0 : 0.0) : b->mass[i])
  for (int i = 0; i < N; i++) {
    int z = uf_find(b->parent, i);
    double w = WEIGHT(i, z);
    b->zm[z] += w;
    for (int a = 0; a < 3; a++) {
      b->zx[3 * z + a] += w * b->X0[3 * i + a];
      b->zu[3 * z + a] += w * b->U[3 * i + a];
    }
  }
  for (int z = 0; z < N; z++)
    if (b->zm[z] > 0)
      for (int a = 0; a < 3; a++) b->zx[3 * z + a] /= b->zm[z], b->zu[3 * z + a] /= b->zm[z]; /* x_c, u_c */
  for (int i = 0; i < N; i++) {
    int z = uf_find(b->parent, i);
    double w = WEIGHT(i, z), r[3], du[3], rxu[3];
    if (w == 0) continue;
    for (int a = 0; a < 3; a++) {
      r[a] = b->X0[3 * i + a] - b->zx[3 * z + a];
      du[a] = b->U[3 * i + a] - b->zu[3 * z + a];
    }
    cb_v3_cross(r, du, rxu);
    double r2 = cb_v3_dot(r, r);
    for (int a = 0; a < 3; a++) {
      b->zL[3 * z + a] += w * rxu[a]; /* L = sum w r x (u - u_c) */
      for (int c = 0; c < 3; c++) b->zI[9 * z + 3 * a + c] += w * ((a == c) * r2 - r[a] * r[c]); /* I */
    }
  }
#undef WEIGHT
  int nz = 0, nzv = 0;
  for (int i = 0; i < N; i++) {
    int z = uf_find(b->parent, i);
    if (z == i && b->zm[z] > 0) { /* omega = I^-1 L, once per zone, into zL (Tikhonov 1e-12 tr I for rank-
                                     deficient I: a collinear zone has no inertia, and L no part, along its line) */
      double *I = b->zI + 9 * z, tr = I[0] + I[4] + I[8], M[9], *L = b->zL + 3 * z, w[3] = {0, 0, 0};
      for (int a = 0; a < 9; a++) M[a] = I[a] + (a % 4 == 0 ? 1e-12 * tr : 0);
      double c0 = M[4] * M[8] - M[5] * M[7], c1 = M[5] * M[6] - M[3] * M[8], c2 = M[3] * M[7] - M[4] * M[6];
      double det = M[0] * c0 + M[1] * c1 + M[2] * c2;
      if (tr > 0 && fabs(det) > 0) { /* the inverse by cofactors (M symmetric) */
        double inv[9] = {c0, M[2] * M[7] - M[1] * M[8], M[1] * M[5] - M[2] * M[4],
                         c1, M[0] * M[8] - M[2] * M[6], M[2] * M[3] - M[0] * M[5],
                         c2, M[1] * M[6] - M[0] * M[7], M[0] * M[4] - M[1] * M[3]};
        for (int a = 0; a < 3; a++) w[a] = (inv[3 * a] * L[0] + inv[3 * a + 1] * L[1] + inv[3 * a + 2] * L[2]) / det;
      }
      memcpy(L, w, sizeof w);
    }
  }
  /* zones of two or more vertices: the free vertices take u_c + omega x (x - x_c) */
  for (int i = 0; i < N; i++) b->zm[i] = 0; /* now: vertex counts per root */
  for (int i = 0; i < N; i++) b->zm[uf_find(b->parent, i)] += 1;
  for (int i = 0; i < N; i++) {
    int z = uf_find(b->parent, i);
    if (z == i && b->zm[z] > 1) nz++;
    b->zrigid[i] = b->zm[z] > 1 && !b->zfixed[z] ? z : -1;
    if (b->zm[z] < 2 || b->winv[i] == 0) continue;
    nzv += i < b->nv;
    double r[3], wxr[3];
    for (int a = 0; a < 3; a++) r[a] = b->X0[3 * i + a] - b->zx[3 * z + a];
    cb_v3_cross(b->zL + 3 * z, r, wxr);
    for (int a = 0; a < 3; a++) b->U[3 * i + a] = b->zu[3 * z + a] + wxr[a];
  }
  b->stats.zones = nz;
  b->stats.zone_vertices = nzv;
}

/* ---- the response --------------------------------------------------------- */

static void bridson_free(cb_response *r) {
  bridson_state *b = r->state;
  if (!b) return;
  free(b->tri);
  free(b->winv);
  free(b->mass);
  free(b->X0);
  free(b->X1);
  free(b->U);
  free(b->U0);
  cb_broadphase_free(b->bp);
  cb_candidates_free(&b->cand);
  free(b->parent);
  free(b->zm);
  free(b->zx);
  free(b->zu);
  free(b->zL);
  free(b->zI);
  free(b->zfixed);
  free(b->zrigid);
}

/* Counts the intersecting triangle pairs at X0 that involve the cloth (the obstacle's own pairs, e.g. a table's legs
 * touching its top, are not the filter's business). */
typedef struct {
  const bridson_state *b;
  int cloth_nt;
  long n;
} start_ctx;

static int start_visit(void *vctx, int i, int j) {
  start_ctx *c = vctx;
  if (i >= c->cloth_nt && j >= c->cloth_nt) return 0;
  const int *p = c->b->tri + 3 * i, *q = c->b->tri + 3 * j;
  const double *X = c->b->X0;
  c->n += cb_tri_tri_intersect(X + 3 * p[0], X + 3 * p[1], X + 3 * p[2], X + 3 * q[0], X + 3 * q[1], X + 3 * q[2]);
  return 0;
}

static int bridson_init(cb_response *r, const cb_response_view *s, const void *params) {
  bridson_state *b = r->state;
  if (!params) return cb_fail("contact.method: bridson needs its parameters");
  b->p = *(const cb_contact_params *)params;
  int st = cb_contact_params_check("bridson", &b->p);
  if (st) return st;
  if (s->mesh->nt == 0)
    return cb_fail("contact.method: bridson needs a triangle mesh (the cloth has no triangles: no faces or edges to "
                   "collide)");
  b->ob = s->obstacle;
  int onv = b->ob ? b->ob->mesh.nv : 0, ont = b->ob ? b->ob->mesh.nt : 0;
  b->nv = s->mesh->nv;
  b->N = b->nv + onv;
  b->T = s->mesh->nt + ont;
  size_t N = (size_t)b->N;
  b->tri = cb_malloc((size_t)3 * b->T, sizeof(int));
  b->winv = cb_calloc(N, sizeof(double));
  b->mass = cb_calloc(N, sizeof(double));
  b->X0 = cb_calloc(3 * N, sizeof(double));
  b->X1 = cb_calloc(3 * N, sizeof(double));
  b->U = cb_calloc(3 * N, sizeof(double));
  b->U0 = cb_calloc(3 * N, sizeof(double));
  b->parent = cb_malloc(N, sizeof(int));
  b->zm = cb_malloc(N, sizeof(double));
  b->zx = cb_malloc(3 * N, sizeof(double));
  b->zu = cb_malloc(3 * N, sizeof(double));
  b->zL = cb_malloc(3 * N, sizeof(double));
  b->zI = cb_malloc(9 * N, sizeof(double));
  b->zfixed = cb_malloc(N, sizeof(int));
  b->zrigid = cb_malloc(N, sizeof(int));
  if (!b->zrigid || !b->tri || !b->winv || !b->mass || !b->X0 || !b->X1 || !b->U || !b->U0 || !b->parent || !b->zm ||
      !b->zx || !b->zu || !b->zL || !b->zI || !b->zfixed)
    return CB_ENOMEM;
  memcpy(b->tri, s->mesh->tri, (size_t)3 * s->mesh->nt * sizeof(int));
  for (int k = 0; k < 3 * ont; k++) b->tri[3 * s->mesh->nt + k] = b->ob->mesh.tri[k] + b->nv;
  for (int i = 0; i < b->nv; i++)
    if (s->free_index[i] >= 0) {
      b->mass[i] = s->mass[i];
      b->winv[i] = 1.0 / s->mass[i];
    }
  cb_broadphase_params bp = cb_broadphase_params_default();
  bp.thickness = b->p.thickness;
  if ((st = cb_broadphase_alloc(b->N, b->T, b->tri, &bp, &b->bp))) return st;
  b->edges = cb_broadphase_edges(b->bp, &b->ne);
  long cap = 16L * (b->N + b->T) + 64;
  if ((st = cb_candidates_alloc(cap, 0, 2 * cap, &b->cand))) return st;
  /* the start state: the filter keeps crossings from being made, it does not undo one (closed triangles: touching
   * counts, as for the exact check every frame) */
  memcpy(b->X0, s->x0, (size_t)3 * b->nv * sizeof(double));
  if (b->ob) cb_obstacle_positions(b->ob, 0, b->X0 + 3 * b->nv);
  if ((st = cb_broadphase_update(b->bp, b->X0, NULL)))
    return cb_fail("contact.method: bridson: the start state has a coordinate that is not finite");
  start_ctx c = {b, s->mesh->nt, 0};
  cb_broadphase_self_pairs(b->bp, 1, start_visit, &c);
  if (c.n > 0)
    return cb_fail("contact.method: bridson: the start state intersects (%ld triangle pairs, cloth with itself or with "
                   "the obstacle; touching counts): the filter keeps crossings from being made and cannot undo one",
                   c.n);
  return CB_OK;
}

static int bridson_apply(cb_response *r, const cb_response_view *s, const double *x_start, double *x, double *v,
                         double h) {
  bridson_state *b = r->state;
  int nv = b->nv, N3 = 3 * b->N;
  double t0 = b->t;
  b->t += h;
  memset(&b->stats, 0, sizeof b->stats);
  b->stats.min_dist = INFINITY;
  if (!(h > 0)) return CB_OK;
  if (!cb_vec_all_finite(3 * nv, x) || !cb_vec_all_finite(3 * nv, x_start)) return CB_DIVERGED;
  /* x0 and u = (x1 - x0)/h: the cloth's from the step, the obstacle's from its positions at t0 and t0 + h */
  memcpy(b->X0, x_start, (size_t)3 * nv * sizeof(double));
  for (int i = 0; i < 3 * nv; i++) b->U[i] = (x[i] - x_start[i]) / h;
  if (b->ob) {
    cb_obstacle_positions(b->ob, t0, b->X0 + 3 * nv);
    cb_obstacle_positions(b->ob, t0 + h, b->X1 + 3 * nv);
    for (int i = 3 * nv; i < N3; i++) b->U[i] = (b->X1[i] - b->X0[i]) / h;
  }
  memcpy(b->U0, b->U, (size_t)N3 * sizeof(double));
  for (int i = 0; i < b->N; i++) b->zrigid[i] = -1;
  int st = repulsion(b, h);
  long hits = 1, merged = 0;
  for (int pass = 0; st == CB_OK && pass < b->p.bridson_iters && hits > 0; pass++) {
    st = ccd_pass(b, h, 0, &hits, &merged);
    b->stats.passes++;
  }
  if (st == CB_OK && hits > 0) { /* (c) the fail-safe */
    for (int i = 0; i < b->N; i++) b->parent[i] = i;
    for (;;) {
      st = ccd_pass(b, h, 1, &hits, &merged);
      if (st || hits == 0) break;
      b->stats.zone_passes++;
      if (merged == 0) { /* every hit inside a zone: rigid fits cannot separate them */
        b->stats.unresolved = 1;
        break;
      }
      rigid_zones(b);
    }
  }
  if (st) return st == CB_EINVAL ? CB_DIVERGED : st;
  for (int i = 0; i < nv; i++) {
    if (s->free_index[i] < 0) continue; /* pins move as prescribed */
    for (int a = 0; a < 3; a++) {
      int k = 3 * i + a;
      x[k] = b->X0[k] + h * b->U[k];
      v[k] += b->U[k] - b->U0[k];
    }
  }
  return b->stats.unresolved ? CB_NOT_CONVERGED : CB_OK;
}

static const cb_response_type bridson_response = {.name = "contact-bridson",
                                                  .size = sizeof(bridson_state),
                                                  .init = bridson_init,
                                                  .apply = bridson_apply,
                                                  .free = bridson_free};

const cb_bridson_stats *cb_bridson_stats_of(const cb_response *r) {
  return r->type == &bridson_response ? &((const bridson_state *)r->state)->stats : NULL;
}

static const cb_param_key bridson_keys[] = {
    CB_KEY_CONTACT_THICKNESS,
    CB_KEY_CONTACT_FRICTION,
    CB_KEY_CONTACT_STIFFNESS,
    {.name = "bridson_iters",
     .kind = CB_PARAM_INT,
     .offset = CB_CKEY(bridson_iters),
     .def = "10",
     .unit = "passes",
     .lo = 0,
     .hi = 1000000,
     .doc = "bridson: CCD impulse passes per step before the rigid impact zones take the collisions left (0: the "
            "zones at once)."},
    CB_KEY_CONTACT_END,
};

const cb_contact_type cb_contact_bridson = {
    .name = "bridson", .keys = bridson_keys, .term_alloc = NULL, .response = &bridson_response, .friction = 1};
