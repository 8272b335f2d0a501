/* The contact pair term (contact.h): the energy both responses are, a sum
 * over primitive pairs of a potential of their squared distance.
 *
 * Pairs. At every evaluation at x the broad phase (broadphase.h) is refitted
 * on the static boxes of x grown by the reach h (the thickness), and gives
 *   self:  vertex-face (v, f), v not a vertex of f; edge-edge (a, b) without a
 *          shared vertex (the broad phase leaves adjacent pairs out);
 *   cross: cloth vertex - obstacle face, obstacle vertex - cloth face, cloth
 *          edge - obstacle edge.
 * Pinned cloth vertices take part like free ones (their gradient entries are
 * written, their Hessian rows are eliminated); the obstacle's vertices are
 * not degrees of freedom. Recomputing the pairs at every evaluation (each
 * energy, gradient and Hessian call, every line-search trial) makes E a
 * function of x alone, so a line search compares energies of one function
 * and finite differences see the pairs that enter and leave; it costs one
 * refit and one traversal per call (the figures are in docs/contact.md).
 *
 * A pair (vertices q_0..q_3, 12 coordinates): s = d^2 of its classified case
 * (distance.h), gradient g_s and Hessian H_s; the potential f(s) with f', f''
 * (zero for s >= h^2); for mollified edge-edge pairs the mollifier e(x) with
 * g_e, H_e (distance.h, eps_x from the rest lengths), else e = 1:
 *   E_p = e f,
 *   g_p = e f' g_s + f g_e,
 *   H_p = e (f'' g_s g_s^T + f' H_s) + f H_e + f' (g_e g_s^T + g_s g_e^T).
 * H_p is projected (cb_projection_apply, 12 x 12) as the assembly asks.
 *
 * The matrix pattern is fixed at set-up (sparse.h), but contacts join
 * vertices no other term couples. The pattern holds every vertex pair of
 * every cloth triangle, and: every free-vertex pair when the model has at
 * most CB_CONTACT_DENSE_MAX free vertices (the conformance examples: exact
 * Hessians), else the pairs within reach at the rest shape. A pair whose
 * cross blocks (first primitive's vertices against the second's) are not
 * all in the pattern adds its two diagonal parts only, [H_AA 0; 0 H_BB]:
 * principal submatrices of the projected (PSD) H_p, so the sum stays PSD and
 * Newton's direction a descent direction; such pairs are counted
 * (cb_contact_stats.decoupled). Cloth-obstacle pairs never need one (the
 * obstacle has no rows).
 *
 * Step bound (the line-search filter, system.h): the broad phase on the swept
 * boxes of x -> x1 and additive CCD (accd below) on every candidate pair with
 * a free vertex; the bound is the smallest time of impact, at which every
 * pair keeps at least a tenth of its gap (ACCD stops there), so no step
 * reaches or crosses a contact; 1 without a hit. The obstacle is static
 * during the step. (The inclusion CCD of ccd.h spent its box budget on the
 * drop test's pairs, cloth edges parallel to the table's and vertices moving
 * in the plane of its sides: 413 s for one step at its default budget; with
 * 2e4 boxes a query, 1304 queries in 6 s and a hit at t = 0, a zero step;
 * docs/contact.md.) A pair
 * whose distance at x exceeds the sum of its two primitives' largest vertex
 * displacements (by 1%) cannot meet during the step (every point of a
 * primitive moves at most as far as its farthest vertex) and skips CCD.
 *
 * Friction (ipc with mu = contact.friction > 0; Li et al. 2020, section 5:
 * lagged, smoothed Coulomb friction). At the start of every step
 * (cb_contact_term_begin_step, the type's begin_step, which the integrator
 * wrapper calls at x^t) every pair within reach is frozen:
 *   lam   = -dE_p/dd = -2 d e f'(s): its normal force (the barrier's
 *           derivative in d = sqrt(s), the mollifier e held fixed),
 *   gam   its closest-point weights (closest_weights below), so that
 *           r = sum_a gam_a q_a joins the two closest points,
 *   P     two orthonormal tangents orthogonal to r (3 x 2),
 * and the obstacle's displacement over the step, o(t + dt) - o(t), from its
 * motion's closed form (obstacle.h; zero for a still one). The relative
 * tangential displacement of the pair over the step is then
 *   u(x) = P^T sum_a gam_a (x_a - x_a^t)   (obstacle vertices: their displacement),
 * linear in x: u = P^T sum_{cloth a} gam_a x_a + u0. With c = eps_v dt
 * (contact.epsv) and y = |u| the pair adds
 *   D = mu lam f0(y),
 *   f1(y) = 2y/c - y^2/c^2 (y < c), 1 (y >= c);  f0' = f1, f0(0) = c/3:
 *   f0(y) = -y^3/(3c^2) + y^2/c + c/3 (y < c), y (y >= c),
 *   dD/dx_a = mu lam gam_a P (f1(y)/y) u,         f1/y = 2/c - y/c^2, or 1/y,
 *   d2D/dx_a dx_b = mu lam gam_a gam_b P M P^T,  M = (f1/y) I + w2 u u^T,
 *   w2 = (f1'(y) y - f1(y))/y^3 = -1/(c^2 y) (y < c), -1/y^3 (y >= c).
 * M's eigenvalues are f1/y across u and f1/y + w2 y^2 = f1'(y) along it:
 * 2/c - y/c^2 > 0 and 2(1 - y/c)/c >= 0 below c, 1/y and 0 beyond. So the
 * lagged Hessian is PSD as it stands (rank 2 at most: the paper's projection
 * leaves it unchanged); under drop/mirror the eigenvalue along u is clamped at
 * 0 (or mirrored) anyway, for the round-off at y = c. D is C^1 in x (f1 is
 * continuous; f1' jumps at y = c). Pairs are frozen with the step's start
 * pairs: a pair that comes within reach during the step has no friction until
 * the next. The arrays are sized at set-up and grow (counted in grows) when a
 * step has more pairs. */
#include "contact_term.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/broadphase.h>
#include <clothbench/distance.h>
#include <clothbench/intersect.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "vec.h"

#define SAFE_MARGIN 1.01 /* the distance filter before CCD, with 1% for the round-off of d(0) */

/* A friction pair frozen at the start of a step (lagged): u(x) = P^T sum_a gam_a x_a + u0 over its cloth vertices. */
typedef struct {
  int vid[4];    /* cloth vertices (-1: the obstacle's) */
  double gam[4]; /* closest-point weights: r = sum_a gam_a q_a joins the two closest points at the start */
  double P[6];   /* tangent basis, columns P[0..2] and P[3..5]: orthonormal, orthogonal to r */
  double lam;    /* the pair's normal force at the start, N */
  double u0[2];  /* -P^T sum_cloth gam_a x_a(start) + P^T sum_obstacle gam_a (obstacle displacement)_a, m */
  int na;        /* the first primitive's vertices (1 point-triangle, 2 edge-edge) */
} fpair;
typedef struct cb_vpairs cb_vpairs; /* below, with vertex_collect */

typedef struct {
  cb_term base;
  cb_contact_params p;
  cb_contact_potential f;
  double reach;
  int mollify, ccd;
  int nv, nt;
  const int *tri;
  const int *free_index;
  int nfree;
  cb_broadphase *bp; /* the cloth's; NULL without triangles */
  const int *edges;
  int ne;
  double *el2; /* rest squared length of each cloth edge */
  cb_candidates self, cross;
  /* the obstacle (NULL bo: none) */
  cb_broadphase *bo;
  const double *ox; /* its positions */
  const int *otri;
  int onv, ont;
  const int *oedges;
  int one;
  double *oel2;
  /* an example's own obstacle */
  double *own_x;
  int *own_tri;
  const cb_sparse *A;
  cb_projection_work *pw;
  cb_contact_stats stats;
  /* friction ("Friction" above): the pairs frozen at the step's start */
  const cb_obstacle *obs; /* the scene's obstacle, for its motion (NULL: none, or an example's own, static) */
  double *odx;            /* 3 onv: the obstacle's displacement over the current step, m */
  double epsvh;           /* eps_v dt of the current step, m */
  fpair *fr;
  long nfr, cap_fr;
  cb_vpairs *vq; /* vertex block descent's collected pairs (vertex_collect; NULL until the first) */
} ct;

enum { K_SELF_VF, K_SELF_EE, K_CROSS_VF, K_CROSS_FV, K_CROSS_EE, K_COUNT };

static ct *as_ct(const cb_term *t) { return (ct *)t; /* the term's scratch is its own, not its caller's */ }

static int grow(cb_candidates *c) {
  long vf = c->nvf > c->cap_vf ? 2 * c->nvf : c->cap_vf, fv = c->nfv > c->cap_fv ? 2 * c->nfv : c->cap_fv,
       ee = c->nee > c->cap_ee ? 2 * c->nee : c->cap_ee;
  cb_candidates n;
  int st = cb_candidates_alloc(vf, fv, ee, &n);
  if (st) return st;
  cb_candidates_free(c);
  *c = n;
  return CB_OK;
}

/* The candidates at x (x1 NULL: static boxes) or over x -> x1 (find: timed as the broad phase). */
static int find_untimed(ct *s, const double *x, const double *x1) {
  s->self.nvf = s->self.nee = s->cross.nvf = s->cross.nfv = s->cross.nee = 0;
  if (!s->bp) return CB_OK;
  int st = cb_broadphase_update(s->bp, x, x1);
  if (st) return st;
  for (int tries = 0;; tries++) {
    st = cb_broadphase_self_candidates(s->bp, &s->self);
    if (st != CB_ENOMEM || tries == 4) break;
    if ((st = grow(&s->self))) return st;
    s->stats.grows++;
  }
  if (st || !s->bo) return st;
  if ((st = cb_broadphase_update(s->bo, s->ox, NULL))) return st;
  for (int tries = 0;; tries++) {
    st = cb_broadphase_cross_candidates(s->bp, s->bo, &s->cross);
    if (st != CB_ENOMEM || tries == 4) break;
    if ((st = grow(&s->cross))) return st;
    s->stats.grows++;
  }
  return st;
}

static int find(ct *s, const double *x, const double *x1) {
  double t0 = cb_now_ms();
  int st = find_untimed(s, x, x1);
  s->stats.broad_ms += cb_now_ms() - t0;
  return st;
}

static long count(const ct *s, int kind) {
  switch (kind) {
  case K_SELF_VF: return s->self.nvf;
  case K_SELF_EE: return s->self.nee;
  case K_CROSS_VF: return s->cross.nvf;
  case K_CROSS_FV: return s->cross.nfv;
  default: return s->cross.nee;
  }
}

/* Pair i of a kind: its 12 coordinates at x (x1 != NULL: also at x1), its
 * cloth vertices (-1: the obstacle's), the edge-edge mollifier threshold
 * (0 for point-triangle pairs), and whether it is edge-edge. */
static int gather(const ct *s, int kind, long i, const double *x, const double *x1, double *q, double *q1, int *vid,
                  double *eps, int *oid) {
  const double *src[4];
  const double *src1[4];
  int ee = kind == K_SELF_EE || kind == K_CROSS_EE;
  *eps = 0;
  if (kind == K_SELF_VF || kind == K_CROSS_VF || kind == K_CROSS_FV) {
    const int *pr = (kind == K_SELF_VF ? s->self.vf : kind == K_CROSS_VF ? s->cross.vf : s->cross.fv) + 2 * i;
    int cloth_point = kind != K_CROSS_FV, cloth_face = kind != K_CROSS_VF;
    const int *f = (cloth_face ? s->tri : s->otri) + 3 * pr[1];
    vid[0] = cloth_point ? pr[0] : -1;
    if (oid) {
      oid[0] = cloth_point ? -1 : pr[0];
      for (int a = 0; a < 3; a++) oid[1 + a] = cloth_face ? -1 : f[a];
    }
    src[0] = (cloth_point ? x : s->ox) + 3 * pr[0];
    src1[0] = cloth_point && x1 ? x1 + 3 * pr[0] : src[0];
    for (int a = 0; a < 3; a++) {
      vid[1 + a] = cloth_face ? f[a] : -1;
      src[1 + a] = (cloth_face ? x : s->ox) + 3 * f[a];
      src1[1 + a] = cloth_face && x1 ? x1 + 3 * f[a] : src[1 + a];
    }
  } else {
    const int *pr = (kind == K_SELF_EE ? s->self.ee : s->cross.ee) + 2 * i;
    int other_cloth = kind == K_SELF_EE;
    const int *ea = s->edges + 2 * pr[0], *eb = (other_cloth ? s->edges : s->oedges) + 2 * pr[1];
    if (oid)
      for (int a = 0; a < 2; a++) {
        oid[a] = -1;
        oid[2 + a] = other_cloth ? -1 : eb[a];
      }
    for (int a = 0; a < 2; a++) {
      vid[a] = ea[a];
      src[a] = x + 3 * ea[a];
      src1[a] = x1 ? x1 + 3 * ea[a] : src[a];
      vid[2 + a] = other_cloth ? eb[a] : -1;
      src[2 + a] = (other_cloth ? x : s->ox) + 3 * eb[a];
      src1[2 + a] = other_cloth && x1 ? x1 + 3 * eb[a] : src[2 + a];
    }
    *eps = CB_MOLLIFIER_SCALE * s->el2[pr[0]] * (other_cloth ? s->el2[pr[1]] : s->oel2[pr[1]]);
  }
  for (int a = 0; a < 4; a++)
    for (int c = 0; c < 3; c++) {
      q[3 * a + c] = src[a][c];
      if (q1) q1[3 * a + c] = src1[a][c];
    }
  return ee;
}

/* The pair's energy; g (12) and H (144) unless NULL. Zero (g, H zero) out of reach. */
static double pair_eval(const ct *s, const double *q, int ee, double eps, double *g, double *H, double *dist2) {
  double gs[12], Hs[144];
  cb_distance_case c;
  int st = ee ? cb_distance_edge_edge_case(q, &c) : cb_distance_point_triangle_case(q, &c);
  if (g) memset(g, 0, sizeof gs);
  if (H) memset(H, 0, sizeof Hs);
  if (st) {
    *dist2 = NAN;
    return NAN;
  }
  /* the distance alone first: most candidates are out of reach, and their derivatives (the 12 x 12 pull-back of
   * the distance's Hessian) would be thrown away (vertex block descent's collected pairs are mostly out of reach: its
   * query radius is >= 5 reach); within reach, the same case evaluated again with them (the value is computed the same
   * way with or without derivatives, distance.c) */
  double sq = cb_distance_case_eval(&c, 4, q, NULL, NULL);
  *dist2 = sq;
  if (!(sq < s->reach * s->reach)) return 0.0;
  if (g || H) sq = cb_distance_case_eval(&c, 4, q, gs, H ? Hs : NULL);
  double f1, f2, f = s->f(&s->p, sq, &f1, &f2);
  double e = 1, ge[12] = {0}, He[144];
  int moll = ee && s->mollify;
  if (moll) { e = cb_edge_edge_mollifier(q, eps, g || H ? ge : NULL, H ? He : NULL); }
  if (g)
    for (int k = 0; k < 12; k++) g[k] = e * f1 * gs[k] + f * ge[k];
  if (H)
    for (int a = 0; a < 12; a++)
      for (int b = 0; b < 12; b++) {
        double h = e * (f2 * gs[a] * gs[b] + f1 * Hs[12 * a + b]);
        if (moll) h += f * He[12 * a + b] + f1 * (ge[a] * gs[b] + gs[a] * ge[b]);
        H[12 * a + b] = h;
      }
  return e * f;
}

/* ---- friction ------------------------------------------------------------------ */

/* The closest-point weights of a classified pair: gam (4, by pair vertex) with r = sum_a gam_a q_a the vector
 * from the second primitive's closest point to the first's. Per form (distance.h):
 *   point-point (p, q):           r = p - q
 *   point-line (p, e0, e1):       r = p - ((1 - t) e0 + t e1),          t = (p - e0).(e1 - e0) / |e1 - e0|^2
 *   point-plane (p, t0, t1, t2):  r = p - (t0 + b1 (t1 - t0) + b2 (t2 - t0)), (b1, b2) the least-squares
 *                                 coordinates of p - t0 in the triangle's plane (its 2x2 normal equations)
 *   line-line (a0, a1, b0, b1):   r = (a0 + sa (a1 - a0)) - (b0 + sb (b1 - b0)), (sa, sb) the lines' closest
 *                                 parameters (the 2x2 normal equations of |a0 - b0 + sa da - sb db|^2)
 * Returns nonzero for a degenerate form (a zero determinant), which the classifiers never choose. */
static int closest_weights(const cb_distance_case *c, const double *q, double *gam) {
  double w[4] = {0, 0, 0, 0};
  const double *v0 = q + 3 * c->v[0], *v1 = q + 3 * c->v[1], *v2 = q + 3 * c->v[2], *v3 = q + 3 * c->v[3];
  switch (c->form) {
  case CB_DIST_POINT_POINT:
    w[0] = 1;
    w[1] = -1;
    break;
  case CB_DIST_POINT_LINE: {
    double e[3], r0[3];
    cb_v3_sub(v2, v1, e);
    cb_v3_sub(v0, v1, r0);
    double ee = cb_v3_dot(e, e);
    if (!(ee > 0)) return 1;
    double t = cb_v3_dot(r0, e) / ee;
    w[0] = 1;
    w[1] = -(1 - t);
    w[2] = -t;
    break;
  }
  case CB_DIST_POINT_PLANE: {
    double e1[3], e2[3], r0[3];
    cb_v3_sub(v2, v1, e1);
    cb_v3_sub(v3, v1, e2);
    cb_v3_sub(v0, v1, r0);
    double a = cb_v3_dot(e1, e1), b = cb_v3_dot(e1, e2), d = cb_v3_dot(e2, e2), det = a * d - b * b;
    if (!(det > 0)) return 1;
    double p1 = cb_v3_dot(e1, r0), p2 = cb_v3_dot(e2, r0);
    double b1 = (d * p1 - b * p2) / det, b2 = (a * p2 - b * p1) / det;
    w[0] = 1;
    w[1] = -(1 - b1 - b2);
    w[2] = -b1;
    w[3] = -b2;
    break;
  }
  default: { /* line-line */
    double da[3], db[3], r0[3];
    cb_v3_sub(v1, v0, da);
    cb_v3_sub(v3, v2, db);
    cb_v3_sub(v0, v2, r0);
    double a = cb_v3_dot(da, da), b = cb_v3_dot(da, db), d = cb_v3_dot(db, db), det = a * d - b * b;
    if (!(det > 0)) return 1;
    double p1 = -cb_v3_dot(da, r0), p2 = cb_v3_dot(db, r0);
    double sa = (d * p1 + b * p2) / det, sb = (b * p1 + a * p2) / det; /* [a -b; -b d] [sa sb] = [p1 p2] */
    w[0] = 1 - sa;
    w[1] = sa;
    w[2] = -(1 - sb);
    w[3] = -sb;
    break;
  }
  }
  for (int a = 0; a < 4; a++) gam[a] = 0;
  for (int k = 0; k < cb_distance_form_nverts(c->form); k++) gam[c->v[k]] += w[k];
  return 0;
}

/* Two orthonormal vectors P[0..2], P[3..5] orthogonal to the unit vector n. */
static void tangent_basis(const double *n, double *P) {
  int k = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : fabs(n[1]) <= fabs(n[2]) ? 1 : 2;
  double ax[3] = {0, 0, 0}, e1[3], e2[3];
  ax[k] = 1;
  cb_v3_cross(n, ax, e1);
  double l = cb_v3_norm(e1);
  for (int c = 0; c < 3; c++) e1[c] /= l;
  cb_v3_cross(n, e1, e2);
  for (int c = 0; c < 3; c++) {
    P[c] = e1[c];
    P[3 + c] = e2[c];
  }
}

/* The pair's friction D = mu lam f0(|u|) at x; g (12) and H (144, the pair's vertices, the 2x2 core projected by
 * proj) unless NULL; *sliding = |u| >= eps_v dt. Formulas in "Friction" above. */
static double fric_eval(const ct *s, const fpair *f, const double *x, cb_projection proj, double *g, double *H,
                        int *sliding) {
  double u[2] = {f->u0[0], f->u0[1]};
  for (int a = 0; a < 4; a++)
    if (f->vid[a] >= 0) {
      const double *xa = x + 3 * f->vid[a];
      u[0] += f->gam[a] * cb_v3_dot(f->P, xa);
      u[1] += f->gam[a] * cb_v3_dot(f->P + 3, xa);
    }
  double y = sqrt(u[0] * u[0] + u[1] * u[1]), c = s->epsvh, ml = s->p.friction * f->lam;
  int slide = y >= c;
  if (sliding) *sliding = slide;
  double f0 = slide ? y : -y * y * y / (3 * c * c) + y * y / c + c / 3;
  double w = slide ? 1 / y : 2 / c - y / (c * c); /* f1(y) / y */
  if (g) {
    double t[3];
    for (int k = 0; k < 3; k++) t[k] = ml * w * (f->P[k] * u[0] + f->P[3 + k] * u[1]); /* mu lam f1/y P u */
    for (int a = 0; a < 4; a++)
      for (int k = 0; k < 3; k++) g[3 * a + k] = f->gam[a] * t[k];
  }
  if (H) {
    /* M = w I + w2 u u^T, w2 = (f1' y - f1) / y^3: its eigenvalues w + w2 y^2 (along u) and w (across) */
    double M[4] = {w, 0, 0, w};
    if (y > 0) {
      double w2 = slide ? -1 / (y * y * y) : -1 / (c * c * y), l1 = w + w2 * y * y;
      if (proj == CB_PROJ_CLAMP) l1 = fmax(l1, 0);
      else if (proj == CB_PROJ_ABS) l1 = fabs(l1);
      double uh[2] = {u[0] / y, u[1] / y};
      for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) M[2 * i + j] += (l1 - w) * uh[i] * uh[j];
    }
    double K[9]; /* P M P^T */
    for (int r = 0; r < 3; r++)
      for (int cc = 0; cc < 3; cc++) {
        double pr[2] = {f->P[r], f->P[3 + r]}, pc[2] = {f->P[cc], f->P[3 + cc]};
        K[3 * r + cc] = pr[0] * (M[0] * pc[0] + M[1] * pc[1]) + pr[1] * (M[2] * pc[0] + M[3] * pc[1]);
      }
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++)
        for (int r = 0; r < 3; r++)
          for (int cc = 0; cc < 3; cc++) H[(3 * a + r) * 12 + 3 * b + cc] = ml * f->gam[a] * f->gam[b] * K[3 * r + cc];
  }
  return ml * f0;
}

static int grow_friction(ct *s) {
  long cap = s->cap_fr > 0 ? 2 * s->cap_fr : 64;
  fpair *n = cb_malloc((size_t)cap, sizeof *n);
  if (!n) return CB_ENOMEM;
  if (s->nfr > 0) memcpy(n, s->fr, (size_t)s->nfr * sizeof *n);
  free(s->fr);
  s->fr = n;
  s->cap_fr = cap;
  return CB_OK;
}

int cb_contact_term_begin_step(cb_term *t, const double *x, double dt) {
  if (!cb_contact_term_is(t)) return cb_fail("contact: not a contact term");
  ct *s = as_ct(t);
  s->nfr = s->stats.friction_pairs = 0;
  if (!(s->p.friction > 0)) return CB_OK;
  if (!(dt > 0) || !isfinite(dt)) return cb_fail("contact.friction: needs a time step dt > 0, got %g", dt);
  s->epsvh = s->p.epsv * dt;
  if (s->obs) { /* the obstacle's displacement over the step, from its motion's closed form */
    cb_obstacle_positions(s->obs, s->obs->t + dt, s->odx);
    for (int k = 0; k < 3 * s->onv; k++) s->odx[k] -= s->ox[k];
  }
  int st = find(s, x, NULL);
  if (st) return st;
  double q[12], eps, t0 = cb_now_ms();
  int vid[4], oid[4];
  for (int kind = 0; kind < K_COUNT && !st; kind++)
    for (long i = 0; i < count(s, kind); i++) {
      int ee = gather(s, kind, i, x, NULL, q, NULL, vid, &eps, oid);
      cb_distance_case c;
      if ((st = ee ? cb_distance_edge_edge_case(q, &c) : cb_distance_point_triangle_case(q, &c))) break;
      double sq = cb_distance_case_eval(&c, 4, q, NULL, NULL);
      if (!(sq < s->reach * s->reach) || !(sq > 0)) continue;
      double f1, f2, e = 1;
      s->f(&s->p, sq, &f1, &f2);
      if (ee && s->mollify) e = cb_edge_edge_mollifier(q, eps, NULL, NULL);
      fpair fp;
      fp.lam = -2 * sqrt(sq) * e * f1; /* -dE_p/dd at fixed mollifier: the pair's normal force */
      if (!(fp.lam > 0) || !isfinite(fp.lam)) continue;
      if (closest_weights(&c, q, fp.gam)) continue;
      double r[3] = {0, 0, 0};
      for (int a = 0; a < 4; a++)
        for (int k = 0; k < 3; k++) r[k] += fp.gam[a] * q[3 * a + k];
      double rn = cb_v3_norm(r);
      if (!(rn > 0)) continue;
      for (int k = 0; k < 3; k++) r[k] /= rn;
      tangent_basis(r, fp.P);
      fp.u0[0] = fp.u0[1] = 0;
      fp.na = ee ? 2 : 1;
      for (int a = 0; a < 4; a++) {
        fp.vid[a] = vid[a];
        const double *d = vid[a] >= 0 ? q + 3 * a : s->odx + 3 * oid[a];
        double sg = vid[a] >= 0 ? -fp.gam[a] : fp.gam[a];
        fp.u0[0] += sg * cb_v3_dot(fp.P, d);
        fp.u0[1] += sg * cb_v3_dot(fp.P + 3, d);
      }
      if (s->nfr == s->cap_fr) {
        if ((st = grow_friction(s))) break;
        s->stats.grows++;
      }
      s->fr[s->nfr++] = fp;
    }
  s->stats.barrier_ms += cb_now_ms() - t0;
  if (st) return st;
  s->stats.friction_pairs = s->nfr;
  return CB_OK;
}

double cb_contact_energy(const cb_term *t, const double *x, double *grad) {
  ct *s = as_ct(t);
  if (find(s, x, NULL)) return NAN;
  double E = 0, g[12], q[12], eps, d2, t0 = cb_now_ms();
  int vid[4];
  s->stats.candidates = s->stats.active = s->stats.mollified = 0;
  s->stats.min_dist = INFINITY;
  for (int kind = 0; kind < K_COUNT; kind++)
    for (long i = 0; i < count(s, kind); i++) {
      int ee = gather(s, kind, i, x, NULL, q, NULL, vid, &eps, NULL);
      double Ep = pair_eval(s, q, ee, eps, grad ? g : NULL, NULL, &d2);
      s->stats.candidates++;
      if (d2 < s->stats.min_dist * s->stats.min_dist) s->stats.min_dist = sqrt(d2);
      if (Ep == 0 && d2 >= s->reach * s->reach) continue;
      s->stats.active++;
      if (ee && s->mollify && cb_edge_edge_cross_squared(q, NULL, NULL) < eps) s->stats.mollified++;
      E += Ep;
      if (grad)
        for (int a = 0; a < 4; a++)
          if (vid[a] >= 0)
            for (int c = 0; c < 3; c++) grad[3 * vid[a] + c] += g[3 * a + c];
    }
  double Ef = 0; /* the friction pairs frozen at the step's start */
  long sliding = 0;
  for (long i = 0; i < s->nfr; i++) {
    const fpair *f = &s->fr[i];
    int sl;
    Ef += fric_eval(s, f, x, CB_PROJ_NONE, grad ? g : NULL, NULL, &sl);
    sliding += sl;
    if (grad)
      for (int a = 0; a < 4; a++)
        if (f->vid[a] >= 0)
          for (int c = 0; c < 3; c++) grad[3 * f->vid[a] + c] += g[3 * a + c];
  }
  s->stats.sliding = sliding;
  s->stats.friction_energy = Ef;
  s->stats.barrier_ms += cb_now_ms() - t0;
  return E + Ef;
}

static int add_pair_blocks(const ct *s, cb_pattern *p, int a, int b) {
  return cb_pattern_add(p, s->free_index[a], s->free_index[b]);
}

int cb_contact_pattern(const cb_term *t, cb_pattern *p) {
  ct *s = as_ct(t);
  int st = CB_OK;
  for (int f = 0; f < s->nt && !st; f++)
    for (int a = 0; a < 3 && !st; a++) st = add_pair_blocks(s, p, s->tri[3 * f + a], s->tri[3 * f + (a + 1) % 3]);
  if (st) return st;
  if (s->nfree <= CB_CONTACT_DENSE_MAX) {
    for (int a = 0; a < s->nv && !st; a++)
      for (int b = a + 1; b < s->nv && !st; b++) st = add_pair_blocks(s, p, a, b);
    return st;
  }
  const double *x = s->base.model->mesh->x; /* the pairs within reach at the rest shape */
  if ((st = find(s, x, NULL))) return st;
  double q[12], eps, d2;
  int vid[4];
  for (int kind = 0; kind < K_COUNT && !st; kind++)
    for (long i = 0; i < count(s, kind) && !st; i++) {
      int ee = gather(s, kind, i, x, NULL, q, NULL, vid, &eps, NULL);
      pair_eval(s, q, ee, eps, NULL, NULL, &d2);
      if (!(d2 < s->reach * s->reach)) continue;
      for (int a = 0; a < 4 && !st; a++)
        for (int b = a + 1; b < 4 && !st; b++)
          if (vid[a] >= 0 && vid[b] >= 0) st = add_pair_blocks(s, p, vid[a], vid[b]);
    }
  return st;
}

int cb_contact_bind(cb_term *t, const cb_sparse *A) {
  as_ct(t)->A = A;
  return CB_OK;
}

/* Adds the pair's 12 x 12 H (PSD) to the matrix values: the blocks of its cloth vertices (vid >= 0, free). The
 * first primitive is vertices 0..na-1; if a cross block (first against second) is missing from the pattern, only
 * the two diagonal parts are added (principal submatrices: still PSD). Returns 1 then, else 0. */
static int scatter(const ct *s, const int *vid, int na, const double *H, double *val) {
  int fi[4], slot[16], stride[16], missing = 0;
  for (int a = 0; a < 4; a++) fi[a] = vid[a] >= 0 ? s->free_index[vid[a]] : -1;
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 4; b++) {
      slot[4 * a + b] = -1;
      if (fi[a] < 0 || fi[b] < 0) continue;
      cb_sparse_block_slot(s->A, fi[a], fi[b], &slot[4 * a + b], &stride[4 * a + b]);
      if (slot[4 * a + b] < 0 && (a < na) != (b < na)) missing = 1;
    }
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 4; b++) {
      if (slot[4 * a + b] < 0 || (missing && (a < na) != (b < na))) continue;
      double B[9];
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) B[3 * r + c] = H[(3 * a + r) * 12 + 3 * b + c];
      cb_sparse_add_block(val, slot[4 * a + b], stride[4 * a + b], B, 1.0);
    }
  return missing;
}

void cb_contact_hessian(const cb_term *t, const double *x, cb_projection proj, double *val) {
  ct *s = as_ct(t);
  if (find(s, x, NULL)) return;
  double H[144], q[12], eps, d2, t0 = cb_now_ms();
  int vid[4];
  s->stats.decoupled = 0;
  for (int kind = 0; kind < K_COUNT; kind++)
    for (long i = 0; i < count(s, kind); i++) {
      int ee = gather(s, kind, i, x, NULL, q, NULL, vid, &eps, NULL);
      pair_eval(s, q, ee, eps, NULL, H, &d2);
      if (!(d2 < s->reach * s->reach)) continue;
      if (cb_projection_apply(proj, 12, H, s->pw) < 0) continue;
      s->stats.decoupled += scatter(s, vid, ee ? 2 : 1, H, val);
    }
  for (long i = 0; i < s->nfr; i++) { /* friction: P M P^T blocks, M's 2x2 core projected in closed form */
    const fpair *f = &s->fr[i];
    fric_eval(s, f, x, proj, NULL, H, NULL);
    s->stats.decoupled += scatter(s, f->vid, f->na, H, val);
  }
  s->stats.barrier_ms += cb_now_ms() - t0;
}

/* Additive CCD (Li, Kaufman & Jiang 2021, Codim-IPC, Algorithm 1) of one
 * pair moving linearly q0 -> q1 (12 coordinates each, first primitive na
 * vertices): the displacements less their mean (the pair's relative motion),
 * l = max over the first primitive's |D_a| + max over the second's |D_b|, an
 * upper bound of how fast the distance can shrink per unit t. From t = 0 it
 * advances by 0.9 d(t) / l (the first advance (1 - ACCD_GAP) d(0) / l), each
 * advance shorter than the gap allows, so no contact is passed, until the gap
 * is below ACCD_GAP d(0) (toi = that t) or t passes 1 (no hit: 1).
 * ACCD_MAX_ITERS advances at most, then the t reached (conservative). */
#define ACCD_GAP 0.1
#define ACCD_MAX_ITERS 10000
static double accd(const ct *s, const double *q0, const double *q1, int ee, long *iters) {
  double D[12], mean[3] = {0, 0, 0}, lA = 0, lB = 0;
  int na = ee ? 2 : 1;
  for (int a = 0; a < 4; a++)
    for (int c = 0; c < 3; c++) mean[c] += 0.25 * (q1[3 * a + c] - q0[3 * a + c]);
  for (int a = 0; a < 4; a++) {
    double n2 = 0;
    for (int c = 0; c < 3; c++) {
      D[3 * a + c] = q1[3 * a + c] - q0[3 * a + c] - mean[c];
      n2 += D[3 * a + c] * D[3 * a + c];
    }
    if (a < na) lA = fmax(lA, sqrt(n2));
    else lB = fmax(lB, sqrt(n2));
  }
  double l = lA + lB, q[12], d2;
  if (!(l > 0)) return 1.0; /* a rigid translation of the pair: its distance does not change */
  for (int k = 0; k < 12; k++) q[k] = q0[k];
  pair_eval(s, q, ee, 0, NULL, NULL, &d2);
  if (!(d2 > 0)) return 0.0; /* touching already (or a NaN) */
  double d0 = sqrt(d2), t = 0, tl = (1 - ACCD_GAP) * d0 / l;
  for (int it = 0; it < ACCD_MAX_ITERS; it++) {
    (*iters)++;
    for (int k = 0; k < 12; k++) q[k] += tl * D[k];
    pair_eval(s, q, ee, 0, NULL, NULL, &d2);
    double d = sqrt(d2);
    if (!(d2 >= 0)) return t; /* NaN: stop where it was still certain */
    if (t > 0 && d < ACCD_GAP * d0) return t;
    t += tl;
    if (t > 1) return 1.0;
    tl = 0.9 * d / l;
  }
  return t;
}

double cb_contact_max_step(const cb_term *t, const double *x, const double *x1) {
  ct *s = as_ct(t);
  s->stats.ccd_queries = 0;
  s->stats.ccd_iters = 0;
  s->stats.max_step = 1.0;
  if (!s->ccd) return 1.0;
  if (find(s, x, x1)) return 0.0;
  double q0[12], q1[12], eps, toi = 1.0, t0 = cb_now_ms();
  int vid[4];
  for (int kind = 0; kind < K_COUNT; kind++)
    for (long i = 0; i < count(s, kind); i++) {
      int ee = gather(s, kind, i, x, x1, q0, q1, vid, &eps, NULL), moving = 0;
      for (int a = 0; a < 4; a++) moving |= vid[a] >= 0 && s->free_index[vid[a]] >= 0;
      if (!moving) continue;
      /* a point of a primitive moves at most its vertices' largest displacement, so the distance at time t is at
       * least d(0) - t (m_A + m_B): no contact in [0, 1] when d(0) > m_A + m_B (no CCD query needed) */
      double mA = 0, mB = 0, d2;
      for (int a = 0; a < 4; a++) {
        double m2 = 0;
        for (int c = 0; c < 3; c++) m2 += (q1[3 * a + c] - q0[3 * a + c]) * (q1[3 * a + c] - q0[3 * a + c]);
        if (a < (ee ? 2 : 1)) mA = fmax(mA, sqrt(m2));
        else mB = fmax(mB, sqrt(m2));
      }
      pair_eval(s, q0, ee, eps, NULL, NULL, &d2);
      if (sqrt(d2) > SAFE_MARGIN * (mA + mB)) continue;
      s->stats.ccd_queries++;
      double tp = accd(s, q0, q1, ee, &s->stats.ccd_iters);
      if (tp < toi) toi = tp;
    }
  s->stats.ccd_ms += cb_now_ms() - t0;
  s->stats.max_step = toi;
  return toi;
}

int cb_contact_indefinite(const cb_term *t, const double *x, int *nelements) {
  ct *s = as_ct(t);
  *nelements = 0;
  if (find(s, x, NULL)) return 0;
  double H[144], q[12], eps, d2;
  int vid[4], n = 0;
  for (int kind = 0; kind < K_COUNT; kind++)
    for (long i = 0; i < count(s, kind); i++) {
      int ee = gather(s, kind, i, x, NULL, q, NULL, vid, &eps, NULL);
      pair_eval(s, q, ee, eps, NULL, H, &d2);
      if (!(d2 < s->reach * s->reach)) continue;
      (*nelements)++;
      n += cb_projection_apply(CB_PROJ_CLAMP, 12, H, s->pw) > 0;
    }
  return n;
}

static void vpairs_free(cb_vpairs *q);

void cb_contact_free(cb_term *t) {
  ct *s = as_ct(t);
  if (!s) return;
  cb_broadphase_free(s->bp);
  cb_broadphase_free(s->bo);
  cb_candidates_free(&s->self);
  cb_candidates_free(&s->cross);
  cb_projection_work_free(s->pw);
  vpairs_free(s->vq);
  free(s->el2);
  free(s->oel2);
  free(s->own_x);
  free(s->own_tri);
  free(s->odx);
  free(s->fr);
  free(s);
}

static double *edge_lengths2(const int *edges, int ne, const double *x) {
  double *l = cb_malloc((size_t)(ne > 0 ? ne : 1), sizeof(double));
  if (!l) return NULL;
  for (int e = 0; e < ne; e++) {
    const double *a = x + 3 * edges[2 * e], *b = x + 3 * edges[2 * e + 1];
    l[e] = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
  }
  return l;
}

static cb_broadphase_params bp_params(const ct *s) {
  cb_broadphase_params bp = cb_broadphase_params_default();
  bp.thickness = s->reach;
  return bp;
}

int cb_contact_term_alloc(const cb_model *m, const cb_term_type *type, const cb_contact_params *p,
                          cb_contact_potential f, double reach, int mollify, int ccd, cb_term **out) {
  *out = NULL;
  if (!(reach > 0) || !isfinite(reach)) return cb_fail("contact.thickness: must be > 0, got %g", reach);
  ct *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->base.type = type;
  s->base.model = m;
  snprintf(s->base.label, sizeof s->base.label, "contact");
  s->p = *p;
  s->f = f;
  s->reach = reach;
  s->mollify = mollify;
  s->ccd = ccd;
  s->nv = m->mesh->nv;
  s->nt = m->mesh->nt;
  s->tri = m->mesh->tri;
  s->free_index = m->free_index;
  s->nfree = m->nfree;
  s->stats.max_step = 1.0;
  s->stats.min_dist = INFINITY;
  int st = cb_projection_work_alloc(12, &s->pw);
  if (!st && s->nt > 0) {
    cb_broadphase_params bp = bp_params(s);
    st = cb_broadphase_alloc(s->nv, s->nt, s->tri, &bp, &s->bp);
    if (!st) {
      s->edges = cb_broadphase_edges(s->bp, &s->ne);
      s->el2 = edge_lengths2(s->edges, s->ne, m->mesh->x);
      if (!s->el2) st = CB_ENOMEM;
    }
    long cap = 16L * (s->nv + s->nt) + 64;
    if (!st) st = cb_candidates_alloc(cap, 0, 2 * cap, &s->self);
    if (!st && p->friction > 0) { /* the friction pairs' set-up capacity */
      s->fr = cb_malloc((size_t)cap, sizeof *s->fr);
      s->cap_fr = cap;
      if (!s->fr) st = CB_ENOMEM;
    }
  }
  if (st) {
    cb_contact_free(&s->base);
    return st;
  }
  *out = &s->base;
  return CB_OK;
}

/* The obstacle of nv vertices at x (positions read at every evaluation) and
 * nt triangles tri, rest shape xr (for the mollifier's edge lengths). */
static int set_obstacle(ct *s, int nv, int nt, const int *tri, const double *x, const double *xr) {
  cb_broadphase_free(s->bo);
  s->bo = NULL;
  free(s->oel2);
  s->oel2 = NULL;
  free(s->odx);
  s->odx = NULL;
  s->obs = NULL;
  s->nfr = 0;
  cb_candidates_free(&s->cross);
  if (!s->bp || nt == 0) return CB_OK; /* no cloth triangles: the cloth has no faces or edges to meet it with */
  cb_broadphase_params bp = bp_params(s);
  int st = cb_broadphase_alloc(nv, nt, tri, &bp, &s->bo);
  if (st) return st;
  s->oedges = cb_broadphase_edges(s->bo, &s->one);
  s->oel2 = edge_lengths2(s->oedges, s->one, xr);
  s->odx = cb_calloc((size_t)3 * nv, sizeof(double)); /* zero: static, unless a scene obstacle's motion says */
  if (!s->oel2 || !s->odx) return CB_ENOMEM;
  s->ox = x;
  s->otri = tri;
  s->onv = nv;
  s->ont = nt;
  long cap = 16L * (s->nv + s->nt + nv + nt) + 64;
  return cb_candidates_alloc(cap, cap, 2 * cap, &s->cross);
}

int cb_contact_term_set_obstacle(cb_term *t, const cb_obstacle *o) {
  if (!cb_contact_term_is(t)) return cb_fail("contact: not a contact term");
  ct *s = as_ct(t);
  if (!o) return set_obstacle(s, 0, 0, NULL, NULL, NULL);
  int st = set_obstacle(s, o->mesh.nv, o->mesh.nt, o->mesh.tri, o->x, o->mesh.x);
  if (!st && s->bo) s->obs = o;
  return st;
}

typedef struct {
  const ct *s;
  const double *x;
  int cross;
  long n;
} ix_ctx;

static int ix_visit(void *vctx, int i, int j) {
  ix_ctx *c = vctx;
  const int *a = c->s->tri + 3 * i, *b = (c->cross ? c->s->otri : c->s->tri) + 3 * j;
  const double *y = c->cross ? c->s->ox : c->x;
  c->n +=
      cb_tri_tri_intersect(c->x + 3 * a[0], c->x + 3 * a[1], c->x + 3 * a[2], y + 3 * b[0], y + 3 * b[1], y + 3 * b[2]);
  return 0;
}

int cb_contact_term_intersections(const cb_term *t, const double *x, long *count) {
  *count = 0;
  if (!cb_contact_term_is(t)) return cb_fail("contact: not a contact term");
  ct *s = as_ct(t);
  if (!s->bp) return CB_OK;
  int st = cb_broadphase_update(s->bp, x, NULL);
  if (st) return st;
  ix_ctx c = {s, x, 0, 0};
  cb_broadphase_self_pairs(s->bp, 1, ix_visit, &c);
  if (s->bo) {
    if ((st = cb_broadphase_update(s->bo, s->ox, NULL))) return st;
    c.cross = 1;
    cb_broadphase_cross_pairs(s->bp, s->bo, ix_visit, &c);
  }
  *count = c.n;
  return CB_OK;
}

int cb_contact_term_is(const cb_term *t) { return t && t->type->energy == cb_contact_energy; }

const cb_contact_stats *cb_contact_term_stats(const cb_term *t) {
  return cb_contact_term_is(t) ? &as_ct(t)->stats : NULL;
}

int cb_contact_example(const cb_model *m, int i, const cb_term_type *type, cb_contact_potential f, int mollify, int ccd,
                       const cb_contact_params *p, cb_term **out) {
  int st = cb_contact_term_alloc(m, type, p, f, p->thickness, mollify, ccd, out);
  if (st || i != 0) return st;
  ct *s = as_ct(*out);
  const cb_mesh *mesh = m->mesh;
  int nv = mesh->nv, nt = mesh->nt;
  /* the normal: the sum of the triangles' area vectors (z for a chain) and the centroid */
  double n[3] = {0, 0, 0}, c[3] = {0, 0, 0};
  for (int k = 0; k < nt; k++) {
    const double *a = mesh->x + 3 * mesh->tri[3 * k], *b = mesh->x + 3 * mesh->tri[3 * k + 1],
                 *d = mesh->x + 3 * mesh->tri[3 * k + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    n[0] += u[1] * w[2] - u[2] * w[1];
    n[1] += u[2] * w[0] - u[0] * w[2];
    n[2] += u[0] * w[1] - u[1] * w[0];
  }
  double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(nn > 0)) {
    n[0] = n[1] = 0;
    n[2] = nn = 1;
  }
  for (int a = 0; a < 3; a++) n[a] /= nn;
  for (int k = 0; k < nv; k++)
    for (int a = 0; a < 3; a++) c[a] += mesh->x[3 * k + a] / nv;
  s->own_x = cb_malloc((size_t)3 * (nv > 0 ? nv : 1), sizeof(double));
  s->own_tri = cb_malloc((size_t)3 * (nt > 0 ? nt : 1), sizeof(int));
  if (!s->own_x || !s->own_tri) {
    cb_contact_free(*out);
    *out = NULL;
    return CB_ENOMEM;
  }
  memcpy(s->own_tri, mesh->tri, (size_t)3 * nt * sizeof(int));
  double th = 0.01, ct_ = cos(th), st_ = sin(th), off = 0.25;
  for (int k = 0; k < nv; k++) { /* c + R(n, th)(X - c) + off n, Rodrigues */
    double r[3] = {mesh->x[3 * k] - c[0], mesh->x[3 * k + 1] - c[1], mesh->x[3 * k + 2] - c[2]};
    double nxr[3] = {n[1] * r[2] - n[2] * r[1], n[2] * r[0] - n[0] * r[2], n[0] * r[1] - n[1] * r[0]};
    double nr = n[0] * r[0] + n[1] * r[1] + n[2] * r[2];
    for (int a = 0; a < 3; a++)
      s->own_x[3 * k + a] = c[a] + r[a] * ct_ + nxr[a] * st_ + n[a] * nr * (1 - ct_) + off * n[a];
  }
  st = set_obstacle(s, nv, nt, s->own_tri, s->own_x, s->own_x);
  if (st) {
    cb_contact_free(*out);
    *out = NULL;
  }
  return st;
}

/* ---- vertex block descent's per-vertex access (energy.h: vertex_collect, vertex_blocks, vertex_bound,
 * intersections; docs/contact.md, "VBD") ----
 *
 * Collect at x_c: the pairs within the query radius r_q = max(reach / (1 - 2 gamma), move / gamma), gamma =
 * CB_CONTACT_VBD_GAMMA, move the largest move the caller expects of a vertex (so that a vertex with nothing within
 * r_q is not held back), found by two trees of their own (cloth and obstacle, boxes grown by r_q; the term's trees
 * keep the reach), each with its distance d_p at x_c, and each cloth vertex's list of the pairs it is in that can
 * come within reach, (1 - 2 gamma) d_p <= reach (the others only bound; they stay out of reach, below). The bound
 * of vertex v is
 *   b_v = gamma min(r_q, min over the collected pairs p that contain v of d_p).
 * Why it is conservative (the Offset Geometric Contact argument, Chen et al. 2025): let every vertex stay within
 * b_v of its place at x_c. A point of a primitive (a vertex, or a convex combination of an edge's or a face's
 * vertices) then stays within the largest b of that primitive's vertices of where it was, so a pair's distance
 * shrinks by at most b_A + b_B (its two primitives' largest bounds; 0 for the obstacle, static during a step):
 *   - a collected pair: every vertex of it has b <= gamma d_p, so d >= (1 - 2 gamma) d_p > 0 for gamma < 1/2;
 *   - a pair not collected: d_p >= r_q at x_c (the broad phase is conservative) and every b <= gamma r_q, so
 *     d >= (1 - 2 gamma) r_q = reach: the pair stays out of reach, its energy 0.
 * The balls |x_v - x_v(c)| <= b_v are convex, so this holds on every straight path between two such states (all
 * vertices moving at once, or one at a time): no contact is reached, none crossed, without CCD; and the collected
 * set holds every pair with nonzero energy there, so vertex_blocks is the term's own gradient block (the energy of
 * the pairs v is in) and the pairs' energies sum to E (each counted once per vertex that asks). gamma = 0.4 leaves
 * every collected pair at least 0.2 d_p apart, every other 1 reach; r_q >= 5 reach.
 *
 * vertex_blocks(v, x): over v's collected pairs, the pair's energy E_p at x (the obstacle's coordinates from x_c),
 * its gradient g_p (12) and Hessian H_p (12 x 12) as the term computes them (pair_eval: e f, e f' g_s + f g_e, ...),
 * and v's parts: g += (g_p)_a, H += P((H_p)_aa), a = v's place in the pair, P the 3x3 projection asked for (clamp:
 * each pair's diagonal block made PSD, so that the sum with the inertia M/dt^2 stays SPD; for a point-plane pair
 * the vertex's exact block (4 s f'' + 2 f') n n^T is already PSD for both responses, since the penalty and the
 * barrier are convex in d). */
#define VBD_QUERY_FACTOR (1.0 / (1.0 - 2.0 * CB_CONTACT_VBD_GAMMA))

typedef struct {
  int vid[4];    /* cloth vertices, -1 for the obstacle's */
  int ee;        /* edge-edge */
  double eps;    /* the mollifier's threshold (edge-edge) */
  double q0[12]; /* the pair at the collect (the obstacle's coordinates are read from here) */
} vpair;

struct cb_vpairs {
  double radius;          /* r_q, m */
  cb_broadphase *bp, *bo; /* the cloth's and the obstacle's trees, boxes grown by r_q */
  const double *bo_x;     /* the obstacle positions bo was built for (a new obstacle rebuilds it) */
  int bo_nv, bo_nt;
  long npairs, cap;
  vpair *pairs;
  int *ptr, *list;         /* nv + 1; 4 cap: 4 j + a for pair j's vertex a */
  double *bound;           /* nv, m */
  cb_projection_work *pw3; /* 3x3 projection */
};

static void vpairs_free(cb_vpairs *q) {
  if (!q) return;
  cb_broadphase_free(q->bp);
  cb_broadphase_free(q->bo);
  free(q->pairs);
  free(q->ptr);
  free(q->list);
  free(q->bound);
  cb_projection_work_free(q->pw3);
  free(q);
}

/* The collect's structures: allocated at the first collect (vertex block descent's set-up calls it once), the
 * obstacle's tree again when the term's obstacle has changed. */
static int vpairs_ready(ct *s) {
  int st = CB_OK;
  if (!s->vq) {
    cb_vpairs *q = cb_calloc(1, sizeof *q);
    if (!q) return CB_ENOMEM;
    q->radius = VBD_QUERY_FACTOR * s->reach;
    q->cap = 16L * (s->nv + s->nt) + 64;
    q->pairs = cb_malloc((size_t)q->cap, sizeof(vpair));
    q->list = cb_malloc(4 * (size_t)q->cap, sizeof(int));
    q->ptr = cb_calloc((size_t)s->nv + 1, sizeof(int));
    q->bound = cb_malloc((size_t)s->nv + 1, sizeof(double));
    if (!q->pairs || !q->list || !q->ptr || !q->bound) st = CB_ENOMEM;
    if (!st) st = cb_projection_work_alloc(3, &q->pw3);
    if (!st && s->nt > 0) {
      cb_broadphase_params bp = cb_broadphase_params_default();
      bp.thickness = q->radius;
      st = cb_broadphase_alloc(s->nv, s->nt, s->tri, &bp, &q->bp);
    }
    if (st) {
      vpairs_free(q);
      return st;
    }
    s->vq = q;
  }
  cb_vpairs *q = s->vq;
  if (s->bo && (q->bo_x != s->ox || q->bo_nv != s->onv || q->bo_nt != s->ont || !q->bo)) {
    cb_broadphase_free(q->bo);
    q->bo = NULL;
    cb_broadphase_params bp = cb_broadphase_params_default();
    bp.thickness = q->radius;
    if ((st = cb_broadphase_alloc(s->onv, s->ont, s->otri, &bp, &q->bo))) return st;
    q->bo_x = s->ox;
    q->bo_nv = s->onv;
    q->bo_nt = s->ont;
  }
  return CB_OK;
}

/* The candidates at x within r_q, into the term's scratch (self, cross; every evaluation refills it). */
static int vpairs_find_untimed(ct *s, const double *x) {
  cb_vpairs *q = s->vq;
  s->self.nvf = s->self.nee = s->cross.nvf = s->cross.nfv = s->cross.nee = 0;
  int st = cb_broadphase_update(q->bp, x, NULL);
  for (int tries = 0; !st; tries++) {
    st = cb_broadphase_self_candidates(q->bp, &s->self);
    if (st != CB_ENOMEM || tries == 4) break;
    if ((st = grow(&s->self))) return st;
    s->stats.grows++;
  }
  if (st || !s->bo) return st;
  if ((st = cb_broadphase_update(q->bo, s->ox, NULL))) return st;
  for (int tries = 0;; tries++) {
    st = cb_broadphase_cross_candidates(q->bp, q->bo, &s->cross);
    if (st != CB_ENOMEM || tries == 4) break;
    if ((st = grow(&s->cross))) return st;
    s->stats.grows++;
  }
  return st;
}

static int vpairs_find(ct *s, const double *x) {
  double t0 = cb_now_ms();
  int st = vpairs_find_untimed(s, x);
  s->stats.broad_ms += cb_now_ms() - t0;
  return st;
}

static int vpairs_grow(cb_vpairs *q) {
  long cap = 2 * q->cap;
  vpair *p = cb_realloc(q->pairs, (size_t)cap, sizeof(vpair));
  if (!p) return CB_ENOMEM;
  q->pairs = p;
  int *l = cb_realloc(q->list, 4 * (size_t)cap, sizeof(int));
  if (!l) return CB_ENOMEM;
  q->list = l;
  q->cap = cap;
  return CB_OK;
}

int cb_contact_vertex_collect(const cb_term *t, const double *x, double move) {
  ct *s = as_ct(t);
  if (s->p.friction > 0) /* the per-vertex blocks carry the barrier or penalty only: never a silent frictionless run */
    return cb_fail_status(CB_EINVAL,
                          "contact.friction: %g: vertex block descent's contact blocks have no friction yet (only 0 "
                          "is accepted with integrator.method = vbd; Newton with ipc has it)",
                          s->p.friction);
  int st = vpairs_ready(s);
  if (st) return st;
  cb_vpairs *q = s->vq;
  q->npairs = 0;
  q->radius = VBD_QUERY_FACTOR * s->reach;
  if (move / CB_CONTACT_VBD_GAMMA > q->radius && isfinite(move)) q->radius = move / CB_CONTACT_VBD_GAMMA;
  if (q->bp && (st = cb_broadphase_set_thickness(q->bp, q->radius))) return st;
  if (q->bo && (st = cb_broadphase_set_thickness(q->bo, q->radius))) return st;
  for (int v = 0; v < s->nv; v++) q->bound[v] = CB_CONTACT_VBD_GAMMA * q->radius;
  memset(q->ptr, 0, ((size_t)s->nv + 1) * sizeof(int));
  if (s->nt > 0 && (st = vpairs_find(s, x))) return st;
  double r2 = q->radius * q->radius;
  for (int kind = 0; kind < K_COUNT; kind++)
    for (long i = 0; i < count(s, kind); i++) {
      vpair p;
      double d2;
      p.ee = gather(s, kind, i, x, NULL, p.q0, NULL, p.vid, &p.eps, NULL);
      int moving = 0;
      for (int a = 0; a < 4; a++) moving |= p.vid[a] >= 0 && s->free_index[p.vid[a]] >= 0;
      if (!moving) continue;
      pair_eval(s, p.q0, p.ee, p.eps, NULL, NULL, &d2);
      if (d2 >= r2) continue;
      double d = d2 > 0 ? sqrt(d2) : 0; /* a NaN distance (a degenerate primitive) freezes the pair's vertices */
      for (int a = 0; a < 4; a++)
        if (p.vid[a] >= 0) q->bound[p.vid[a]] = fmin(q->bound[p.vid[a]], CB_CONTACT_VBD_GAMMA * d);
      /* a pair with (1 - 2 gamma) d_p above the reach stays out of reach while every vertex keeps its bound (the
       * argument above): it lowers the bounds but has no energy, so vertex_blocks need not visit it (a large move
       * widens r_q, and most pairs are then of this kind); the margin 1e-6 keeps rounding on the safe side */
      if ((1.0 - 2.0 * CB_CONTACT_VBD_GAMMA) * d > s->reach * (1.0 + 1e-6)) continue;
      if (q->npairs == q->cap) {
        if ((st = vpairs_grow(q))) return st;
        s->stats.grows++;
      }
      q->pairs[q->npairs++] = p;
      for (int a = 0; a < 4; a++)
        if (p.vid[a] >= 0) q->ptr[p.vid[a] + 1]++;
    }
  for (int v = 0; v < s->nv; v++) q->ptr[v + 1] += q->ptr[v];
  for (long j = 0; j < q->npairs; j++) /* fill, then shift back: ptr[v] is v's start again after the loop */
    for (int a = 0; a < 4; a++)
      if (q->pairs[j].vid[a] >= 0) q->list[q->ptr[q->pairs[j].vid[a]]++] = (int)(4 * j + a);
  for (int v = s->nv; v > 0; v--) q->ptr[v] = q->ptr[v - 1];
  q->ptr[0] = 0;
  return CB_OK;
}

double cb_contact_vertex_blocks(const cb_term *t, int v, const double *x, cb_projection proj, double *g, double *H) {
  ct *s = as_ct(t);
  const cb_vpairs *q = s->vq;
  double E = 0, gp[12], Hp[144], qq[12], d2;
  if (g) memset(g, 0, 3 * sizeof(double));
  if (H) memset(H, 0, 9 * sizeof(double));
  if (!q || v < 0 || v >= s->nv) return 0.0;
  for (int r = q->ptr[v]; r < q->ptr[v + 1]; r++) {
    const vpair *p = &q->pairs[q->list[r] / 4];
    int a = q->list[r] % 4;
    for (int b = 0; b < 4; b++)
      for (int c = 0; c < 3; c++) qq[3 * b + c] = p->vid[b] >= 0 ? x[3 * p->vid[b] + c] : p->q0[3 * b + c];
    E += pair_eval(s, qq, p->ee, p->eps, g ? gp : NULL, H ? Hp : NULL, &d2);
    if (!(d2 < s->reach * s->reach))
      continue; /* out of reach: zero energy and blocks (a NaN distance: pair_eval's NaN) */
    if (g)
      for (int c = 0; c < 3; c++) g[c] += gp[3 * a + c];
    if (H) {
      double B[9];
      for (int c = 0; c < 3; c++)
        for (int e = 0; e < 3; e++) B[3 * c + e] = Hp[(3 * a + c) * 12 + 3 * a + e];
      if (proj != CB_PROJ_NONE) cb_projection_apply(proj, 3, B, q->pw3);
      for (int c = 0; c < 9; c++) H[c] += B[c];
    }
  }
  return E;
}

double cb_contact_vertex_bound(const cb_term *t, int v) {
  const ct *s = as_ct(t);
  if (!s->vq || v < 0 || v >= s->nv) return 0.0; /* nothing collected: no move is known safe */
  return s->vq->bound[v];
}
