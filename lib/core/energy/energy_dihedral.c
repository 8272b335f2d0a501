/* Dihedral-angle (hinge) bending: one element per pair of neighbouring
 * triangles, the hinge energy of discrete shells (Grinspun et al. 2003,
 * "Discrete Shells", SCA):
 *
 *   E = k_b c_h (theta - theta_bar)^2 / 2,   c_h = 3 |e_bar|^2 / (A_bar_A + A_bar_B)
 *
 * k_b = material.bend_k in N m (J): c_h is dimensionless (a length squared
 * over an area), so E is in J for any mesh size. e_bar, A_bar and the rest
 * angle theta_bar are measured on the rest mesh, so a non-planar rest shape
 * is the lecture's "non-planar case" (theta_0).
 *
 * Vertices of a hinge: x0, x1 the shared edge e = x1 - x0, x2 the wing of
 * triangle A, x3 the wing of triangle B. With the unnormalised normals
 *   N_A = e x (x2 - x0),   N_B = (x3 - x0) x e
 * (equal for a flat hinge whose wings lie on the two sides of the edge),
 *   theta = atan2((N_A x N_B) . e/|e|, N_A . N_B)   in (-pi, pi],
 * robust for every angle (no acos of a rounded cosine). theta - theta_bar is
 * wrapped into (-pi, pi], so a fold through +-pi does not jump by 2 pi.
 *
 * Gradient (the lecture's u_i; Bridson et al. 2003): with
 *   G_A = -|e| N_A / |N_A|^2,   G_B = -|e| N_B / |N_B|^2,
 *   alpha_w = (x_w - x0) . e / |e|^2   (where the wing projects onto the edge),
 *   dtheta/dx2 = G_A,  dtheta/dx3 = G_B,
 *   dtheta/dx0 = (alpha_A - 1) G_A + (alpha_B - 1) G_B,
 *   dtheta/dx1 = -alpha_A G_A - alpha_B G_B,
 * so dE/dx_i = k_b c_h (theta - theta_bar) u_i with u_1, u_2 along the
 * normals and u_1 + u_2 + u_3 + u_4 = 0, as on the slide.
 *
 * Hessian, exact: H = k_b c_h (grad theta grad theta^T + (theta - theta_bar) d2theta),
 * d2theta by differentiating the gradient above in closed form (the second
 * derivative of theta of Tamstorf & Grinspun 2013, written through G_w and
 * alpha_w): with n = N/|N|, P = |e|/|N|^2 (I - 2 n n^T), R = N e^T / (|e| |N|^2),
 *   dG_A = -R de - P dN_A,   dN_A = [e]x dx2 + ([a]x - [e]x) dx0 - [a]x dx1,  a = x2 - x0,
 *   dN_B = -[e]x dx3 + ([e]x - [b]x) dx0 + [b]x dx1,                         b = x3 - x0,
 *   dalpha_w = (e . (dx_w - dx0) + (x_w - x0 - 2 alpha_w e) . de) / |e|^2,  de = dx1 - dx0.
 * tests/test_energy_conformance.c checks it against finite differences of the
 * gradient. It is indefinite in general, so each element is projected by the
 * shared projection (projection.h) the assembly asks for.
 *
 * Two Hessians (material.bend_hessian), two term types in this file:
 *   dihedral (`gauss-newton`, the default): with d = theta - theta_bar and
 *   c = k_b c_h, E = c d^2 / 2 is half the square of the residual
 *   r = sqrt(c) d, whose gradient is J = sqrt(c) grad theta. Gauss-Newton
 *   keeps J J^T and drops r d2r:
 *     exact:  d2E = c grad theta grad theta^T + c d d2theta
 *     H_GN  =       c grad theta grad theta^T
 *   v^T H_GN v = c (grad theta . v)^2 >= 0 for every v (c >= 0), so H_GN is
 *   positive semidefinite by construction: rank one, no projection, no
 *   eigen-decomposition. Its cost is that of the gradient plus one 12 x 12
 *   outer product. The dropped term c d d2theta vanishes at theta = theta_bar,
 *   where H_GN is the exact Hessian, and grows linearly with |d|: Newton with
 *   H_GN is a Gauss-Newton (quasi-Newton) method (CB_TERM_MODEL_HESSIAN),
 *   linearly convergent where the bending residual d is not small. On a
 *   single hinge with E > 0, grad E = c d grad theta gives
 *   H_GN = grad E grad E^T / (2E), which tests/test_energy_conformance.c
 *   checks against central differences of E.
 *   dihedral_exact (`exact`): the exact Hessian above, each element projected
 *   by the assembly's projection (integrator.definiteness drop/mirror: a GSL
 *   eigen-decomposition per hinge and assembly).
 *
 * Degenerate hinges: a rest hinge with a zero-length edge or a zero-area wing
 * is rejected when the term is built. During a run, a hinge whose current
 * edge or wing has collapsed (|e|^2 < 1e-24 |e_bar|^2, or |N|^2 < 1e-12
 * |e|^4: a wing of height below 1e-6 |e|) has no defined angle; it
 * contributes no energy, gradient or Hessian in that state (a documented
 * clamp), never a NaN. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>
#include "vec.h"

extern const cb_term_type cb_term_dihedral_type;       /* Gauss-Newton Hessian */
extern const cb_term_type cb_term_dihedral_exact_type; /* exact Hessian, projected per element */

const char *const cb_bend_hessian_names[] = {"gauss-newton", "exact", NULL};

int cb_hinge_term_is(const cb_term *t) {
  return t && (t->type == &cb_term_dihedral_type || t->type == &cb_term_dihedral_exact_type);
}

typedef struct {
  cb_term base;
  int nh;
  int *vert;         /* 4*nh: x0, x1 (edge), x2 (wing A), x3 (wing B) */
  double *c;         /* nh: k_b 3 |e_bar|^2 / (A_bar_A + A_bar_B), J */
  double *theta_bar; /* nh: rest angle, rad */
  double *e2_bar;    /* nh: rest |e|^2 */
  cb_stencil st;
  cb_projection_work *work; /* 12 x 12; used by one assembly at a time */
} hinge_term;

/* [v]x, row-major: [v]x u = v x u */
static inline void skew(const double *v, double *S) {
  S[0] = 0;
  S[1] = -v[2];
  S[2] = v[1];
  S[3] = v[2];
  S[4] = 0;
  S[5] = -v[0];
  S[6] = -v[1];
  S[7] = v[0];
  S[8] = 0;
}

/* Geometry of one hinge at positions p[4][3]. */
typedef struct {
  double e[3], a[3], b[3], NA[3], NB[3];
  double e2, le, nA2, nB2;
  double theta;
  double G[2][3]; /* G_A, G_B */
  double alpha[2];
  double grad[12]; /* dtheta/dx */
} hinge_geo;

/* Returns 0 if the hinge is degenerate in this state (see the header). */
static int hinge_eval(const double *p, double e2_bar, hinge_geo *g) {
  cb_v3_sub(p + 3, p, g->e);
  cb_v3_sub(p + 6, p, g->a);
  cb_v3_sub(p + 9, p, g->b);
  g->e2 = cb_v3_dot(g->e, g->e);
  if (!(g->e2 >= 1e-24 * e2_bar)) return 0;
  g->le = sqrt(g->e2);
  cb_v3_cross(g->e, g->a, g->NA);
  cb_v3_cross(g->b, g->e, g->NB);
  g->nA2 = cb_v3_dot(g->NA, g->NA);
  g->nB2 = cb_v3_dot(g->NB, g->NB);
  if (!(g->nA2 >= 1e-12 * g->e2 * g->e2) || !(g->nB2 >= 1e-12 * g->e2 * g->e2)) return 0;
  double cx[3];
  cb_v3_cross(g->NA, g->NB, cx);
  g->theta = atan2(cb_v3_dot(cx, g->e) / g->le, cb_v3_dot(g->NA, g->NB));
  for (int k = 0; k < 3; k++) {
    g->G[0][k] = -g->le * g->NA[k] / g->nA2;
    g->G[1][k] = -g->le * g->NB[k] / g->nB2;
  }
  g->alpha[0] = cb_v3_dot(g->a, g->e) / g->e2;
  g->alpha[1] = cb_v3_dot(g->b, g->e) / g->e2;
  for (int k = 0; k < 3; k++) {
    g->grad[k] = (g->alpha[0] - 1) * g->G[0][k] + (g->alpha[1] - 1) * g->G[1][k];
    g->grad[3 + k] = -g->alpha[0] * g->G[0][k] - g->alpha[1] * g->G[1][k];
    g->grad[6 + k] = g->G[0][k];
    g->grad[9 + k] = g->G[1][k];
  }
  return 1;
}

/* theta - theta_bar wrapped into (-pi, pi]. */
static double wrap_angle(double d) {
  const double pi = 3.14159265358979323846;
  while (d > pi) d -= 2 * pi;
  while (d <= -pi) d += 2 * pi;
  return d;
}

static void load(const hinge_term *h, int e, const double *x, double *p) {
  for (int a = 0; a < 4; a++)
    for (int c = 0; c < 3; c++) p[3 * a + c] = x[3 * h->vert[4 * e + a] + c];
}

/* d2theta (12 x 12, row-major) of a non-degenerate hinge. */
static void hinge_d2theta(const hinge_geo *g, double *D) {
  /* J_w: the 3 x 12 Jacobian of G_w; dal_w: the gradient (12) of alpha_w */
  double J[2][36], dal[2][12];
  double Se[9], Sa[9], Sb[9];
  skew(g->e, Se);
  skew(g->a, Sa);
  skew(g->b, Sb);
  for (int w = 0; w < 2; w++) {
    const double *N = w == 0 ? g->NA : g->NB;
    double n2 = w == 0 ? g->nA2 : g->nB2;
    double P[9], R[9];
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        P[3 * r + c] = g->le / n2 * ((r == c) - 2 * N[r] * N[c] / n2);
        R[3 * r + c] = N[r] * g->e[c] / (g->le * n2);
      }
    /* dN/dx_v for v = 0..3 (3 x 3 each) */
    double dN[4][9];
    memset(dN, 0, sizeof dN);
    for (int k = 0; k < 9; k++) {
      if (w == 0) {
        dN[0][k] = Sa[k] - Se[k];
        dN[1][k] = -Sa[k];
        dN[2][k] = Se[k];
      } else {
        dN[0][k] = Se[k] - Sb[k];
        dN[1][k] = Sb[k];
        dN[3][k] = -Se[k];
      }
    }
    /* de/dx0 = -I, de/dx1 = I */
    for (int v = 0; v < 4; v++)
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
          double s = 0;
          for (int k = 0; k < 3; k++) s += P[3 * r + k] * dN[v][3 * k + c];
          double de = v == 0 ? -R[3 * r + c] : v == 1 ? R[3 * r + c] : 0.0;
          J[w][12 * r + 3 * v + c] = -de - s;
        }
    /* alpha = q . e / |e|^2, q = x_w - x0:
     * dalpha = (e . dq + (q - 2 alpha e) . de) / |e|^2, dq = dx_w - dx0, de = dx1 - dx0 */
    const double *q = w == 0 ? g->a : g->b;
    int wv = 2 + w;
    memset(dal[w], 0, sizeof dal[w]);
    for (int c = 0; c < 3; c++) {
      double t = (q[c] - 2 * g->alpha[w] * g->e[c]) / g->e2, u = g->e[c] / g->e2;
      dal[w][3 * wv + c] += u;
      dal[w][c] += -u - t;
      dal[w][3 + c] += t;
    }
  }
  /* rows of d(grad theta): x0: sum_w (alpha_w - 1) J_w + G_w dal_w^T;
   * x1: -sum_w alpha_w J_w + G_w dal_w^T; x2: J_A; x3: J_B */
  memset(D, 0, 144 * sizeof(double));
  for (int w = 0; w < 2; w++)
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 12; c++) {
        double jw = J[w][12 * r + c], gd = g->G[w][r] * dal[w][c];
        D[12 * r + c] += (g->alpha[w] - 1) * jw + gd;
        D[12 * (3 + r) + c] += -g->alpha[w] * jw - gd;
        D[12 * (6 + 3 * w + r) + c] += jw;
      }
  for (int i = 0; i < 12; i++) /* symmetric in exact arithmetic; remove the round-off */
    for (int j = 0; j < i; j++) {
      double m = 0.5 * (D[12 * i + j] + D[12 * j + i]);
      D[12 * i + j] = D[12 * j + i] = m;
    }
}

static double hinge_energy(const cb_term *t, const double *x, double *grad) {
  const hinge_term *h = (const hinge_term *)t;
  double E = 0;
  for (int e = 0; e < h->nh; e++) {
    double p[12];
    hinge_geo g;
    load(h, e, x, p);
    if (!hinge_eval(p, h->e2_bar[e], &g)) continue;
    double d = wrap_angle(g.theta - h->theta_bar[e]);
    E += 0.5 * h->c[e] * d * d;
    if (grad) {
      double ge[12];
      for (int k = 0; k < 12; k++) ge[k] = h->c[e] * d * g.grad[k];
      cb_stencil_add_gradient(&h->st, e, ge, grad);
    }
  }
  return E;
}

static int hinge_pattern(const cb_term *t, cb_pattern *p) {
  return cb_stencil_pattern(&((const hinge_term *)t)->st, p);
}

static int hinge_bind(cb_term *t, const cb_sparse *A) {
  char what[64];
  snprintf(what, sizeof what, "%s hinge", t->label);
  return cb_stencil_bind(&((hinge_term *)t)->st, A, what);
}

/* Hinge e's exact 12x12 Hessian c (grad theta grad theta^T + (theta - theta_bar) d2theta)
 * at x into H; 0 (H untouched) if the hinge is degenerate there. */
static int hinge_exact_hessian(const hinge_term *h, int e, const double *x, double *H) {
  double p[12], D[144];
  hinge_geo g;
  load(h, e, x, p);
  if (!hinge_eval(p, h->e2_bar[e], &g)) return 0;
  double d = wrap_angle(g.theta - h->theta_bar[e]);
  hinge_d2theta(&g, D);
  for (int i = 0; i < 12; i++)
    for (int j = 0; j < 12; j++) H[12 * i + j] = h->c[e] * (g.grad[i] * g.grad[j] + d * D[12 * i + j]);
  return 1;
}

static void hinge_hessian_exact(const cb_term *t, const double *x, cb_projection proj, double *val) {
  const hinge_term *h = (const hinge_term *)t;
  double H[144];
  for (int e = 0; e < h->nh; e++) {
    if (!cb_stencil_active(&h->st, e) || !hinge_exact_hessian(h, e, x, H)) continue;
    if (proj != CB_PROJ_NONE) cb_projection_apply(proj, 12, H, h->work);
    cb_stencil_add_hessian(&h->st, e, H, val);
  }
}

/* H_GN = c grad theta grad theta^T per hinge: PSD, so proj has nothing to do. */
static void hinge_hessian_gn(const cb_term *t, const double *x, cb_projection proj, double *val) {
  (void)proj;
  const hinge_term *h = (const hinge_term *)t;
  double H[144];
  for (int e = 0; e < h->nh; e++) {
    double p[12];
    hinge_geo g;
    if (!cb_stencil_active(&h->st, e)) continue;
    load(h, e, x, p);
    if (!hinge_eval(p, h->e2_bar[e], &g)) continue;
    for (int i = 0; i < 12; i++) {
      double ci = h->c[e] * g.grad[i];
      for (int j = 0; j < 12; j++) H[12 * i + j] = ci * g.grad[j];
    }
    cb_stencil_add_hessian(&h->st, e, H, val);
  }
}

/* Per-element access (vertex block descent): hinge e's energy, gradient
 * c d grad theta and Hessian (Gauss-Newton, or exact projected by proj);
 * zeros for a hinge degenerate in this state. */
static const cb_stencil *hinge_stencil(const cb_term *t) { return &((const hinge_term *)t)->st; }

static double hinge_element(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H,
                            int exact) {
  const hinge_term *h = (const hinge_term *)t;
  double p[12];
  hinge_geo geo;
  memset(g, 0, 12 * sizeof(double));
  memset(H, 0, 144 * sizeof(double));
  load(h, e, x, p);
  if (!hinge_eval(p, h->e2_bar[e], &geo)) return 0.0;
  double d = wrap_angle(geo.theta - h->theta_bar[e]);
  for (int k = 0; k < 12; k++) g[k] = h->c[e] * d * geo.grad[k];
  if (exact) {
    hinge_exact_hessian(h, e, x, H);
    if (proj != CB_PROJ_NONE) cb_projection_apply(proj, 12, H, h->work);
  } else {
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) H[12 * i + j] = h->c[e] * geo.grad[i] * geo.grad[j];
  }
  return 0.5 * h->c[e] * d * d;
}
/* Its vertex a's part (cb_term_type.element_vertex): Gauss-Newton's block
 * c grad_a theta grad_a theta^T alone; the exact block from the exact
 * Hessian (its second derivatives couple the vertices), only when asked. */
static double hinge_element_vertex(const cb_term *t, int e, int a, const double *x, double *g, double *H, int exact) {
  const hinge_term *h = (const hinge_term *)t;
  double p[12];
  hinge_geo geo;
  if (g) memset(g, 0, 3 * sizeof(double));
  if (H) memset(H, 0, 9 * sizeof(double));
  load(h, e, x, p);
  if (!hinge_eval(p, h->e2_bar[e], &geo)) return 0.0;
  double d = wrap_angle(geo.theta - h->theta_bar[e]);
  const double *ga = geo.grad + 3 * a;
  if (g)
    for (int k = 0; k < 3; k++) g[k] = h->c[e] * d * ga[k];
  if (H && exact) {
    double He[144] = {0};
    hinge_exact_hessian(h, e, x, He);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) H[3 * i + j] = He[12 * (3 * a + i) + 3 * a + j];
  } else if (H) {
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) H[3 * i + j] = h->c[e] * ga[i] * ga[j];
  }
  return 0.5 * h->c[e] * d * d;
}
static double hinge_vertex_gn(const cb_term *t, int e, int a, const double *x, double *g, double *H) {
  return hinge_element_vertex(t, e, a, x, g, H, 0);
}
static double hinge_vertex_exact(const cb_term *t, int e, int a, const double *x, double *g, double *H) {
  return hinge_element_vertex(t, e, a, x, g, H, 1);
}
static double hinge_element_gn(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  return hinge_element(t, e, x, proj, g, H, 0);
}
static double hinge_element_exact(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  return hinge_element(t, e, x, proj, g, H, 1);
}

static void hinge_free(cb_term *t) {
  hinge_term *h = (hinge_term *)t;
  free(h->vert);
  free(h->c);
  free(h->theta_bar);
  free(h->e2_bar);
  cb_stencil_free(&h->st);
  cb_projection_work_free(h->work);
  free(h);
}

int cb_hinge_vertices(const cb_topology *tp, int *vert) {
  for (int p = 0; p < tp->np; p++) {
    int ed = tp->pair_edge[p];
    vert[4 * p] = tp->edge[2 * ed];
    vert[4 * p + 1] = tp->edge[2 * ed + 1];
    vert[4 * p + 2] = tp->pair_opp[2 * p];
    vert[4 * p + 3] = tp->pair_opp[2 * p + 1];
  }
  return tp->np;
}

int cb_hinge_term_alloc(const cb_model *m, const char *label, double k, cb_term **out) {
  *out = NULL;
  if (!(k >= 0) || !isfinite(k)) return cb_fail("%s hinges: stiffness must be >= 0, got %g", label, k);
  hinge_term *h = cb_calloc(1, sizeof *h);
  if (!h) return CB_ENOMEM;
  h->base.type = &cb_term_dihedral_type;
  h->base.model = m;
  snprintf(h->base.label, sizeof h->base.label, "%s", label);
  int nh = m->topo->np;
  h->nh = nh;
  h->vert = cb_malloc((size_t)4 * (nh > 0 ? nh : 1), sizeof(int));
  h->c = cb_malloc((size_t)(nh > 0 ? nh : 1), sizeof(double));
  h->theta_bar = cb_malloc((size_t)(nh > 0 ? nh : 1), sizeof(double));
  h->e2_bar = cb_malloc((size_t)(nh > 0 ? nh : 1), sizeof(double));
  if (!h->vert || !h->c || !h->theta_bar || !h->e2_bar || cb_stencil_init(&h->st, 4, nh, h->vert, m->free_index) ||
      cb_projection_work_alloc(12, &h->work)) {
    hinge_free(&h->base);
    return CB_ENOMEM;
  }
  cb_hinge_vertices(m->topo, h->vert);
  for (int e = 0; e < nh; e++) {
    double p[12];
    load(h, e, m->mesh->x, p);
    hinge_geo g;
    double e2[3];
    cb_v3_sub(p + 3, p, e2);
    double l2 = cb_v3_dot(e2, e2);
    if (!(l2 > 0) || !hinge_eval(p, l2, &g)) {
      int v0 = h->vert[4 * e], v1 = h->vert[4 * e + 1];
      hinge_free(&h->base);
      return cb_fail("%s hinge %d on edge (%d, %d): degenerate rest shape (zero-length edge or zero-area triangle)",
                     label, e, v0, v1);
    }
    h->e2_bar[e] = l2;
    h->theta_bar[e] = g.theta;
    /* A_A + A_B = (|N_A| + |N_B|) / 2 */
    h->c[e] = k * 3.0 * l2 / (0.5 * (sqrt(g.nA2) + sqrt(g.nB2)));
  }
  *out = &h->base;
  return CB_OK;
}

int cb_hinge_term_set_hessian(cb_term *t, cb_bend_hessian kind) {
  if (!cb_hinge_term_is(t)) return cb_fail("material.bend_hessian: %s is not a dihedral term", t ? t->label : "(null)");
  if (kind != CB_BEND_GAUSS_NEWTON && kind != CB_BEND_EXACT)
    return cb_fail("material.bend_hessian: unknown Hessian %d", (int)kind);
  t->type = kind == CB_BEND_EXACT ? &cb_term_dihedral_exact_type : &cb_term_dihedral_type;
  return CB_OK;
}

int cb_hinge_term_count_indefinite(const cb_term *t, const double *x, int *nhinges) {
  *nhinges = 0;
  if (!cb_hinge_term_is(t)) return 0;
  const hinge_term *h = (const hinge_term *)t;
  *nhinges = h->nh;
  double H[144];
  int count = 0;
  for (int e = 0; e < h->nh; e++) {
    if (!hinge_exact_hessian(h, e, x, H)) continue;
    count += cb_projection_apply(CB_PROJ_CLAMP, 12, H, h->work) > 0;
  }
  return count;
}

/* Examples: hinges across every pair with k_b = 0.37 N m, with either Hessian. */
static int hinge_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  return cb_hinge_term_alloc(m, "bend", 0.37, out);
}
static int hinge_exact_example(const cb_model *m, int i, cb_term **out) {
  int st = hinge_example(m, i, out);
  if (st == CB_OK) st = cb_hinge_term_set_hessian(*out, CB_BEND_EXACT);
  return st;
}

const cb_term_type cb_term_dihedral_type = {.name = "dihedral",
                                            .flags = CB_TERM_MODEL_HESSIAN,
                                            .energy = hinge_energy,
                                            .pattern = hinge_pattern,
                                            .bind = hinge_bind,
                                            .hessian = hinge_hessian_gn,
                                            .free = hinge_free,
                                            .stencil = hinge_stencil,
                                            .element = hinge_element_gn,
                                            .element_vertex = hinge_vertex_gn,
                                            .nexamples = 1,
                                            .example = hinge_example,
                                            .indefinite = cb_hinge_term_count_indefinite};
const cb_term_type cb_term_dihedral_exact_type = {.name = "dihedral_exact",
                                                  .energy = hinge_energy,
                                                  .pattern = hinge_pattern,
                                                  .bind = hinge_bind,
                                                  .hessian = hinge_hessian_exact,
                                                  .free = hinge_free,
                                                  .stencil = hinge_stencil,
                                                  .element = hinge_element_exact,
                                                  .element_vertex = hinge_vertex_exact,
                                                  .nexamples = 1,
                                                  .example = hinge_exact_example,
                                                  .indefinite = cb_hinge_term_count_indefinite};
