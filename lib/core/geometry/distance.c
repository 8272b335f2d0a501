/* The smooth distance formulas and the pair registry (distance.h).
 *
 * Every form is a function of a few difference vectors, each a fixed linear
 * combination of the form's vertices (A below: rows = difference vectors,
 * columns = vertices, entries -1, 0, 1):
 *
 *   point-point   v = p - q                                    f = |v|^2
 *   point-line    v = p - e0,  u = e1 - e0                     f = C / L
 *   point-plane   v = p - t0,  u = t1 - t0,  w = t2 - t0       f = s^2 / N
 *   line-line     v = a0 - b0, u = a1 - a0,  w = b1 - b0       f = s^2 / N
 *
 * with c = v x u, C = |c|^2, L = |u|^2; n = u x w, s = v . n, N = |n|^2.
 * The derivatives are taken with respect to the difference vectors (6 or 9
 * variables) and pulled back: with J = A (x) I_3 constant,
 *   grad_x f = J^T grad f,   hess_x f = J^T (hess f) J.
 *
 * Derivatives of the pieces ([a]x is the cross-product matrix, [a]x b = a x b):
 *   c = v x u:  dc/dv = -[u]x,  dc/du = [v]x
 *   C:  grad_v C = 2 u x c,  grad_u C = -2 v x c,
 *       hess C = 2 Jc^T Jc + 2 sum_k c_k hess c_k, where the second term is
 *       -2[c]x in the (v,u) block and +2[c]x in the (u,v) block
 *       (sum_k c_k d2 c_k / dv_i du_j = eps_ijk c_k = -([c]x)_ij).
 *   s = v . (u x w) = det[v u w]:  grad_v s = n, grad_u s = w x v, grad_w s = v x u;
 *       hess s: (v,u) = -[w]x, (v,w) = [u]x, (u,w) = -[v]x, the transposes below
 *       the diagonal, zero diagonal blocks.
 *   N = |u x w|^2 is C of the pair (u, w).
 *   Quotients:  f = s^2/N:
 *       grad f = (2s/N) grad s - (s^2/N^2) grad N
 *       hess f = (2/N) gs gs^T + (2s/N) hess s - (2s/N^2)(gs gN^T + gN gs^T)
 *                + (2 s^2/N^3) gN gN^T - (s^2/N^2) hess N
 *     f = C/L:
 *       grad f = grad C / L - (C/L^2) grad L
 *       hess f = hess C / L - (gC gL^T + gL gC^T)/L^2 + (2C/L^3) gL gL^T - (C/L^2) hess L
 *     with grad_u L = 2u, hess L = 2 I in the (u,u) block.
 * Source: the formulas are the textbook point/line/plane distances; the
 * per-case structure is IPC's (Li et al. 2020, "Incremental Potential
 * Contact", section 4 and its supplement); the derivatives are ours, checked
 * by central differences in tests/test_distance.c. */
#include <clothbench/distance.h>

#include <math.h>
#include <string.h>

#include "vec.h"

int cb_distance_form_nverts(cb_distance_form f) {
  static const int n[] = {2, 3, 4, 4};
  return (unsigned)f < 4 ? n[f] : 0;
}

const char *cb_distance_form_name(cb_distance_form f) {
  static const char *const names[] = {"point-point", "point-line", "point-plane", "line-line"};
  return (unsigned)f < 4 ? names[f] : "unknown";
}

/* out (3x3, row-major) += s [a]x */
static void add_crossmat(double *out, int ld, const double *a, double s) {
  out[0 * ld + 1] += -s * a[2];
  out[0 * ld + 2] += s * a[1];
  out[1 * ld + 0] += s * a[2];
  out[1 * ld + 2] += -s * a[0];
  out[2 * ld + 0] += -s * a[1];
  out[2 * ld + 1] += s * a[0];
}

/* C = |v x u|^2 over the 6 variables (v, u): value, gradient gC[6], Hessian HC[36]. */
static double cross2(const double *v, const double *u, double *gC, double *HC) {
  double c[3];
  cb_v3_cross(v, u, c);
  double C = cb_v3_dot(c, c);
  if (gC) {
    double uc[3], vc[3];
    cb_v3_cross(u, c, uc);
    cb_v3_cross(v, c, vc);
    for (int a = 0; a < 3; a++) {
      gC[a] = 2 * uc[a];      /* grad_v C = 2 u x c */
      gC[3 + a] = -2 * vc[a]; /* grad_u C = -2 v x c */
    }
  }
  if (HC) {
    /* Jc = [-[u]x | [v]x] (3 x 6) */
    double J[3 * 6] = {0};
    add_crossmat(J, 6, u, -1.0);
    add_crossmat(J + 3, 6, v, 1.0);
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        double s = 0;
        for (int k = 0; k < 3; k++) s += J[k * 6 + i] * J[k * 6 + j];
        HC[i * 6 + j] = 2 * s; /* 2 Jc^T Jc */
      }
    add_crossmat(HC + 3, 6, c, -2.0);    /* (v,u) block: -2[c]x */
    add_crossmat(HC + 3 * 6, 6, c, 2.0); /* (u,v) block: +2[c]x */
  }
  return C;
}

/* f = s^2/N, s = v.(u x w), N = |u x w|^2, over the 9 variables (v, u, w). */
static double triple_form(const double *v, const double *u, const double *w, double *g, double *H) {
  double n[3];
  cb_v3_cross(u, w, n);
  double s = cb_v3_dot(v, n);
  double gN6[6], HN6[36];
  double N = cross2(u, w, (g || H) ? gN6 : NULL, H ? HN6 : NULL);
  double f = s * s / N;
  if (!g && !H) return f;
  double gs[9], gN[9] = {0};
  double wv[3], vu[3];
  cb_v3_cross(w, v, wv);
  cb_v3_cross(v, u, vu);
  for (int a = 0; a < 3; a++) {
    gs[a] = n[a];
    gs[3 + a] = wv[a];
    gs[6 + a] = vu[a];
    gN[3 + a] = gN6[a];
    gN[6 + a] = gN6[3 + a];
  }
  if (g)
    for (int i = 0; i < 9; i++) g[i] = 2 * s / N * gs[i] - s * s / (N * N) * gN[i];
  if (H) {
    double Hs[81] = {0}, HN[81] = {0};
    add_crossmat(Hs + 0 * 9 + 3, 9, w, -1.0); /* (v,u) = -[w]x */
    add_crossmat(Hs + 3 * 9 + 0, 9, w, 1.0);  /* (u,v) = its transpose */
    add_crossmat(Hs + 0 * 9 + 6, 9, u, 1.0);  /* (v,w) = [u]x */
    add_crossmat(Hs + 6 * 9 + 0, 9, u, -1.0);
    add_crossmat(Hs + 3 * 9 + 6, 9, v, -1.0); /* (u,w) = -[v]x */
    add_crossmat(Hs + 6 * 9 + 3, 9, v, 1.0);
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) HN[(3 + i) * 9 + 3 + j] = HN6[i * 6 + j];
    double N2 = N * N, N3 = N2 * N;
    for (int i = 0; i < 9; i++)
      for (int j = 0; j < 9; j++)
        H[i * 9 + j] = 2 / N * gs[i] * gs[j] + 2 * s / N * Hs[i * 9 + j] -
                       2 * s / N2 * (gs[i] * gN[j] + gN[i] * gs[j]) + 2 * s * s / N3 * gN[i] * gN[j] -
                       s * s / N2 * HN[i * 9 + j];
  }
  return f;
}

/* f = |v x u|^2 / |u|^2 over the 6 variables (v, u). */
static double line_form(const double *v, const double *u, double *g, double *H) {
  double gC[6], HC[36];
  double C = cross2(v, u, (g || H) ? gC : NULL, H ? HC : NULL), L = cb_v3_dot(u, u);
  double f = C / L;
  if (!g && !H) return f;
  double gL[6] = {0, 0, 0, 2 * u[0], 2 * u[1], 2 * u[2]};
  if (g)
    for (int i = 0; i < 6; i++) g[i] = gC[i] / L - C / (L * L) * gL[i];
  if (H)
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        double HL = (i >= 3 && i == j) ? 2.0 : 0.0;
        H[i * 6 + j] = HC[i * 6 + j] / L - (gC[i] * gL[j] + gL[i] * gC[j]) / (L * L) +
                       2 * C / (L * L * L) * gL[i] * gL[j] - C / (L * L) * HL;
      }
  return f;
}

/* Pull back the derivatives in nk difference vectors to nv vertices through
 * A (nk x nv): g = J^T gs, H = J^T Hs J with J = A (x) I_3. */
static void pullback(int nk, int nv, const double *A, const double *gs, const double *Hs, double *g, double *H) {
  int m = 3 * nk, n = 3 * nv;
  if (g)
    for (int i = 0; i < nv; i++)
      for (int a = 0; a < 3; a++) {
        double s = 0;
        for (int k = 0; k < nk; k++) s += A[k * nv + i] * gs[3 * k + a];
        g[3 * i + a] = s;
      }
  if (H)
    for (int i = 0; i < nv; i++)
      for (int a = 0; a < 3; a++)
        for (int j = 0; j < nv; j++)
          for (int b = 0; b < 3; b++) {
            double s = 0;
            for (int k = 0; k < nk; k++) {
              if (A[k * nv + i] == 0) continue;
              for (int l = 0; l < nk; l++) s += A[k * nv + i] * A[l * nv + j] * Hs[(3 * k + a) * m + 3 * l + b];
            }
            H[(3 * i + a) * n + 3 * j + b] = s;
          }
}

double cb_distance_form_eval(cb_distance_form f, const double *x, double *g, double *H) {
  double gs[9], Hs[81], d[9];
  double *gp = (g || H) ? gs : NULL, *Hp = H ? Hs : NULL;
  switch (f) {
  case CB_DIST_POINT_POINT: {
    static const double A[] = {1, -1};
    cb_v3_sub(x, x + 3, d);
    for (int a = 0; a < 3; a++) gs[a] = 2 * d[a]; /* grad |v|^2 = 2v, hess = 2I */
    memset(Hs, 0, 9 * sizeof(double));
    Hs[0] = Hs[4] = Hs[8] = 2;
    pullback(1, 2, A, gs, Hs, g, H);
    return cb_v3_dot(d, d);
  }
  case CB_DIST_POINT_LINE: {
    static const double A[] = {1, -1, 0, /* v = p - e0 */
                               0, -1, 1 /* u = e1 - e0 */};
    cb_v3_sub(x, x + 3, d);
    cb_v3_sub(x + 6, x + 3, d + 3);
    double r = line_form(d, d + 3, gp, Hp);
    pullback(2, 3, A, gs, Hs, g, H);
    return r;
  }
  case CB_DIST_POINT_PLANE: {
    static const double A[] = {1, -1, 0, 0, /* v = p - t0 */
                               0, -1, 1, 0, /* u = t1 - t0 */
                               0, -1, 0, 1 /* w = t2 - t0 */};
    cb_v3_sub(x, x + 3, d);
    cb_v3_sub(x + 6, x + 3, d + 3);
    cb_v3_sub(x + 9, x + 3, d + 6);
    double r = triple_form(d, d + 3, d + 6, gp, Hp);
    pullback(3, 4, A, gs, Hs, g, H);
    return r;
  }
  case CB_DIST_LINE_LINE: {
    static const double A[] = {1,  0, -1, 0, /* v = a0 - b0 */
                               -1, 1, 0,  0, /* u = a1 - a0 */
                               0,  0, -1, 1 /* w = b1 - b0 */};
    cb_v3_sub(x, x + 6, d);
    cb_v3_sub(x + 3, x, d + 3);
    cb_v3_sub(x + 9, x + 6, d + 6);
    double r = triple_form(d, d + 3, d + 6, gp, Hp);
    pullback(3, 4, A, gs, Hs, g, H);
    return r;
  }
  }
  return NAN;
}

double cb_distance_case_eval(const cb_distance_case *c, int nverts, const double *x, double *g, double *H) {
  int k = cb_distance_form_nverts(c->form), n = 3 * nverts;
  double xs[12], gs[12], Hs[144];
  for (int i = 0; i < k; i++) memcpy(xs + 3 * i, x + 3 * c->v[i], 3 * sizeof(double));
  double f = cb_distance_form_eval(c->form, xs, g ? gs : NULL, H ? Hs : NULL);
  if (g) {
    memset(g, 0, (size_t)n * sizeof(double));
    for (int i = 0; i < k; i++)
      for (int a = 0; a < 3; a++) g[3 * c->v[i] + a] += gs[3 * i + a];
  }
  if (H) {
    memset(H, 0, (size_t)n * (size_t)n * sizeof(double));
    for (int i = 0; i < k; i++)
      for (int a = 0; a < 3; a++)
        for (int j = 0; j < k; j++)
          for (int b = 0; b < 3; b++)
            H[(3 * c->v[i] + a) * n + 3 * c->v[j] + b] += Hs[(3 * i + a) * (3 * k) + 3 * j + b];
  }
  return f;
}

/* ---- the registry: one line per primitive pair ---------------------------- */
const cb_distance_type *const cb_distance_types[] = {&cb_distance_point_point, &cb_distance_point_edge,
                                                     &cb_distance_point_triangle, &cb_distance_edge_edge,
                                                     /* one line per primitive pair, above this line */
                                                     NULL};

const cb_distance_type *cb_distance_type_find(const char *name) {
  for (int k = 0; cb_distance_types[k]; k++)
    if (strcmp(cb_distance_types[k]->name, name) == 0) return cb_distance_types[k];
  return NULL;
}

/* ---- the mollifier --------------------------------------------------------- */

double cb_edge_edge_mollifier_threshold(const double *x_rest) {
  double a[3], b[3];
  cb_v3_sub(x_rest + 3, x_rest, a);
  cb_v3_sub(x_rest + 9, x_rest + 6, b);
  return CB_MOLLIFIER_SCALE * cb_v3_dot(a, a) * cb_v3_dot(b, b); /* eps_x = 1e-3 |a|^2 |b|^2 */
}

double cb_edge_edge_cross_squared(const double *x, double *g, double *H) {
  static const double A[] = {-1, 1, 0,  0, /* a = a1 - a0 */
                             0,  0, -1, 1 /* b = b1 - b0 */};
  double d[6], gs[6], Hs[36];
  cb_v3_sub(x + 3, x, d);
  cb_v3_sub(x + 9, x + 6, d + 3);
  double c = cross2(d, d + 3, (g || H) ? gs : NULL, H ? Hs : NULL); /* c = |a x b|^2 */
  pullback(2, 4, A, gs, Hs, g, H);
  return c;
}

double cb_edge_edge_mollifier(const double *x, double eps_x, double *g, double *H) {
  if (!(eps_x > 0)) {
    if (g)
      for (int i = 0; i < 12; i++) g[i] = NAN;
    if (H)
      for (int i = 0; i < 144; i++) H[i] = NAN;
    return NAN;
  }
  double gc[12], Hc[144];
  double c = cb_edge_edge_cross_squared(x, (g || H) ? gc : NULL, H ? Hc : NULL);
  if (!(c < eps_x)) { /* e_x = 1: flat */
    if (g) memset(g, 0, 12 * sizeof(double));
    if (H) memset(H, 0, 144 * sizeof(double));
    return isnan(c) ? NAN : 1.0;
  }
  double r = c / eps_x;
  double e1 = 2 / eps_x * (1 - r);  /* e_x'(c) = 2 (1 - c/eps_x) / eps_x */
  double e2 = -2 / (eps_x * eps_x); /* e_x''(c) */
  if (g)
    for (int i = 0; i < 12; i++) g[i] = e1 * gc[i]; /* grad e_x = e_x' grad c */
  if (H)
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++)
        H[i * 12 + j] = e2 * gc[i] * gc[j] + e1 * Hc[i * 12 + j]; /* e_x'' gc gc^T + e_x' hess c */
  return (2 - r) * r;                                             /* e_x = (2 - c/eps_x) c/eps_x */
}
