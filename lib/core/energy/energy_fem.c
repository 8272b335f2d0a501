/* Co-rotational linear triangle FEM (lecture, "Co-rotational FEM"; Müller &
 * Gross 2004), material.stretch = fem.
 *
 * Per triangle t with rest vertices r0, r1, r2, rest area A_t and the rest
 * edge matrix D_m = [r1 - r0, r2 - r0] in the triangle's own 2D frame:
 *   F   = [x1 - x0, x2 - x0] D_m^-1                (3x2 deformation gradient)
 *   R   = polar rotation of F (polar.h, 3x2 with orthonormal columns)
 *   E_t = mu A_t |F - R|_F^2
 * mu (material.stretch_k, N/m = J/m^2) is an energy per unit rest area, so a
 * refined mesh has the same material (no rescaling with the mesh size). On a
 * right isosceles triangle with the right angle at x0 and legs h (D_m = h I,
 * A_t = h^2/2) this is the lecture's
 *   E_t = mu/2 (|x1 - x0 - R(r1 - r0)|^2 + |x2 - x0 - R(r2 - r0)|^2),
 * and in general the same form with the edges mapped through D_m^-1.
 *
 * With F = sum_a x_a b_a^T (b_1, b_2 the rows of D_m^-1, b_0 = -b_1 - b_2):
 *   dE/dx_a = P b_a,   P = 2 mu A_t (F - R)
 * exactly: d|F - R|^2 = 2 <F - R, dF> - 2 <F - R, dR>, and <F - R, dR> = 0
 * because R^T dR is skew (R^T R = I) and R^T F = S is symmetric. So the
 * gradient equals the lecture's frozen-R force.
 *
 * Two Hessians (material.fem_hessian), two term types in this file:
 *   fem_frozen (`frozen`): R held fixed, H_ab = 2 mu A_t (b_a . b_b) I_3, which
 *     is the lecture's [[2I, -I, -I], [-I, I, 0], [-I, 0, I]] x mu on the
 *     triangle above. It does not depend on x: CB_TERM_CONSTANT_HESSIAN (the
 *     system stores it once, as projective dynamics does) and, being a model
 *     of the Hessian rather than the Hessian, CB_TERM_MODEL_HESSIAN. PSD.
 *   fem (`exact`): with the derivative of R. With S = (F^T F)^(1/2) = V Sigma V^T,
 *     R = F S^-1, dR = (dF - R dS) S^-1, where S dS + dS S = dF^T F + F^T dF,
 *     i.e. (V^T dS V)_ij = (V^T (dF^T F + F^T dF) V)_ij / (sigma_i + sigma_j).
 *     The 9x9 element Hessian 2 mu A_t sum (dF - dR) b_a, one column per
 *     direction dx, is indefinite in compression and is projected by the
 *     shared element projection (projection.h) under drop/mirror.
 *
 * Degenerate triangles (never NaN): a triangle collapsed to a segment or a
 * point (sigma_2 <= CB_POLAR_RANK_TOL sigma_1, F = 0) gets polar.h's
 * deterministic R; its energy mu A_t sum (sigma_i - 1)^2 does not depend on
 * that choice, its gradient is one subgradient, and its exact Hessian (dR
 * has 1/sigma_2 terms) falls back to the frozen element matrix whenever
 * sigma_2 <= FEM_DEGENERATE sigma_1. cb_fem_term_degenerate counts such
 * triangles: the status a caller records. Inversion has no meaning for a
 * 3x2 F (a flipped triangle is a rotated one in 3D), so only the rank
 * matters. A zero-area rest triangle is rejected when the term is built. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/polar.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>

#define FEM_DEGENERATE 1e-8 /* sigma_2 / sigma_1 below which the exact Hessian uses the frozen one */

const char *const cb_fem_hessian_names[] = {"exact", "frozen", NULL};

typedef struct {
  cb_term base;
  int nt;
  int *tri;     /* 3*nt vertices */
  double *b;    /* 6*nt: b_0, b_1, b_2 (2 each) per triangle */
  double *area; /* nt rest areas, m^2 */
  double mu;    /* N/m */
  cb_stencil st;
  cb_projection_work *pw; /* 9x9, for the exact Hessian's projection */
} fem_term;

/* F = sum_a x_a b_a^T (3x2 row-major) of triangle e. */
static void deformation(const fem_term *f, int e, const double *x, double F[6]) {
  const int *v = f->tri + 3 * e;
  const double *b = f->b + 6 * e;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 2; c++)
      F[2 * r + c] = x[3 * v[0] + r] * b[c] + x[3 * v[1] + r] * b[2 + c] + x[3 * v[2] + r] * b[4 + c];
}

/* Energy mu A |F - R|^2 of triangle e at x and its gradient g (9: P b_a per vertex). */
static inline double fem_elem(const fem_term *f, int e, const double *x, double g[9]) {
  double F[6], R[6], D[6];
  deformation(f, e, x, F);
  cb_polar32(F, R, NULL);
  double s = 0;
  for (int i = 0; i < 6; i++) {
    D[i] = F[i] - R[i];
    s += D[i] * D[i];
  }
  double c = f->mu * f->area[e];
  if (g) {
    const double *b = f->b + 6 * e;
    for (int a = 0; a < 3; a++)
      for (int r = 0; r < 3; r++)
        g[3 * a + r] = 2 * c * (D[2 * r] * b[2 * a] + D[2 * r + 1] * b[2 * a + 1]); /* P b_a */
  }
  return c * s; /* mu A |F - R|^2 */
}

static double fem_energy(const cb_term *t, const double *x, double *grad) {
  const fem_term *f = (const fem_term *)t;
  double E = 0;
  for (int e = 0; e < f->nt; e++) {
    double g[9];
    E += fem_elem(f, e, x, grad ? g : NULL);
    if (grad) cb_stencil_add_gradient(&f->st, e, g, grad);
  }
  return E;
}

static int fem_pattern(const cb_term *t, cb_pattern *p) { return cb_stencil_pattern(&((const fem_term *)t)->st, p); }

static int fem_bind(cb_term *t, const cb_sparse *A) {
  char what[64];
  snprintf(what, sizeof what, "%s triangle", t->label);
  return cb_stencil_bind(&((fem_term *)t)->st, A, what);
}

/* The frozen element: H_ab = 2 mu A (b_a . b_b) I_3. */
static void frozen_element(const fem_term *f, int e, double H[81]) {
  const double *b = f->b + 6 * e;
  double c = 2 * f->mu * f->area[e];
  memset(H, 0, 81 * sizeof(double));
  for (int a = 0; a < 3; a++)
    for (int q = 0; q < 3; q++) {
      double w = c * (b[2 * a] * b[2 * q] + b[2 * a + 1] * b[2 * q + 1]);
      for (int r = 0; r < 3; r++) H[(3 * a + r) * 9 + 3 * q + r] = w;
    }
}

/* The exact element (see the top); returns 0, or 1 if degenerate (H frozen). */
static int exact_element(const fem_term *f, int e, const double *x, double H[81]) {
  double F[6], R[6], sg[2];
  deformation(f, e, x, F);
  cb_polar32(F, R, sg);
  if (!(sg[1] > FEM_DEGENERATE * sg[0])) {
    frozen_element(f, e, H);
    return 1;
  }
  /* V from the eigenvectors of F^T F (2x2 symmetric), consistent with sigma */
  double a = F[0] * F[0] + F[2] * F[2] + F[4] * F[4], c = F[1] * F[1] + F[3] * F[3] + F[5] * F[5],
         bb = F[0] * F[1] + F[2] * F[3] + F[4] * F[5];
  double th = 0.5 * atan2(2 * bb, a - c), cs = cos(th), sn = sin(th);
  double V[4] = {cs, -sn, sn, cs}; /* columns: eigenvectors of F^T F */
  double l0 = a * cs * cs + 2 * bb * cs * sn + c * sn * sn, l1 = a * sn * sn - 2 * bb * cs * sn + c * cs * cs;
  double s0 = sqrt(fmax(l0, 0)), s1 = sqrt(fmax(l1, 0));
  if (!(s0 > 0 && s1 > 0)) {
    frozen_element(f, e, H);
    return 1;
  }
  double Si[4]; /* S^-1 = V diag(1/s) V^T */
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) Si[2 * i + j] = V[2 * i] * V[2 * j] / s0 + V[2 * i + 1] * V[2 * j + 1] / s1;
  double sv[2] = {s0, s1};
  const double *b = f->b + 6 * e;
  double coef = 2 * f->mu * f->area[e];
  for (int q = 0; q < 3; q++)
    for (int rr = 0; rr < 3; rr++) { /* direction dx = unit at vertex q, coordinate rr: dF = e_rr b_q^T */
      double dF[6] = {0, 0, 0, 0, 0, 0};
      dF[2 * rr] = b[2 * q];
      dF[2 * rr + 1] = b[2 * q + 1];
      double C[4]; /* dF^T F + F^T dF */
      for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) C[2 * i + j] = dF[2 * rr + i] * F[2 * rr + j] + F[2 * rr + i] * dF[2 * rr + j];
      double dSh[4], dS[4]; /* dS in the V basis, then in the standard one */
      for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
          double s = 0;
          for (int k = 0; k < 2; k++)
            for (int l = 0; l < 2; l++) s += V[2 * k + i] * C[2 * k + l] * V[2 * l + j];
          dSh[2 * i + j] = s / (sv[i] + sv[j]);
        }
      for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
          double s = 0;
          for (int k = 0; k < 2; k++)
            for (int l = 0; l < 2; l++) s += V[2 * i + k] * dSh[2 * k + l] * V[2 * j + l];
          dS[2 * i + j] = s;
        }
      double M[6], dR[6]; /* M = dF - R dS; dR = M S^-1 */
      for (int r = 0; r < 3; r++)
        for (int j = 0; j < 2; j++) M[2 * r + j] = dF[2 * r + j] - (R[2 * r] * dS[j] + R[2 * r + 1] * dS[2 + j]);
      for (int r = 0; r < 3; r++)
        for (int j = 0; j < 2; j++) dR[2 * r + j] = M[2 * r] * Si[j] + M[2 * r + 1] * Si[2 + j];
      int col = 3 * q + rr;
      for (int p = 0; p < 3; p++)
        for (int r = 0; r < 3; r++) {
          double d0 = dF[2 * r] - dR[2 * r], d1 = dF[2 * r + 1] - dR[2 * r + 1];
          H[(3 * p + r) * 9 + col] = coef * (d0 * b[2 * p] + d1 * b[2 * p + 1]);
        }
    }
  for (int i = 0; i < 9; i++) /* symmetric up to round-off: symmetrise */
    for (int j = 0; j < i; j++) {
      double s = 0.5 * (H[9 * i + j] + H[9 * j + i]);
      H[9 * i + j] = H[9 * j + i] = s;
    }
  return 0;
}

static void fem_hessian_exact(const cb_term *t, const double *x, cb_projection proj, double *val) {
  const fem_term *f = (const fem_term *)t;
  double H[81];
  for (int e = 0; e < f->nt; e++) {
    if (!cb_stencil_active(&f->st, e)) continue;
    if (exact_element(f, e, x, H) == 0 && proj != CB_PROJ_NONE) cb_projection_apply(proj, 9, H, f->pw);
    cb_stencil_add_hessian(&f->st, e, H, val);
  }
}

static void fem_hessian_frozen(const cb_term *t, const double *x, cb_projection proj, double *val) {
  (void)x;
  (void)proj; /* constant and PSD */
  const fem_term *f = (const fem_term *)t;
  double H[81];
  for (int e = 0; e < f->nt; e++) {
    if (!cb_stencil_active(&f->st, e)) continue;
    frozen_element(f, e, H);
    cb_stencil_add_hessian(&f->st, e, H, val);
  }
}

static const cb_stencil *fem_stencil(const cb_term *t) { return &((const fem_term *)t)->st; }

static double fem_element_exact(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  const fem_term *f = (const fem_term *)t;
  if (exact_element(f, e, x, H) == 0 && proj != CB_PROJ_NONE) cb_projection_apply(proj, 9, H, f->pw);
  return fem_elem(f, e, x, g);
}

static double fem_element_frozen(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  (void)proj; /* constant and PSD */
  const fem_term *f = (const fem_term *)t;
  frozen_element(f, e, H);
  return fem_elem(f, e, x, g);
}

/* Its vertex a's part (cb_term_type.element_vertex): the blocks of the
 * element's gradient and Hessian (the Hessian only when asked: the line
 * search of vertex block descent wants the energy alone). */
static double fem_element_vertex(const cb_term *t, int e, int a, const double *x, double *g, double *H, int exact) {
  const fem_term *f = (const fem_term *)t;
  double ge[9], He[81];
  if (H) {
    if (exact) exact_element(f, e, x, He);
    else frozen_element(f, e, He);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) H[3 * i + j] = He[9 * (3 * a + i) + 3 * a + j];
  }
  double E = fem_elem(f, e, x, g ? ge : NULL);
  if (g) memcpy(g, ge + 3 * a, 3 * sizeof(double));
  return E;
}
static double fem_vertex_exact(const cb_term *t, int e, int a, const double *x, double *g, double *H) {
  return fem_element_vertex(t, e, a, x, g, H, 1);
}
static double fem_vertex_frozen(const cb_term *t, int e, int a, const double *x, double *g, double *H) {
  return fem_element_vertex(t, e, a, x, g, H, 0);
}

static void fem_free(cb_term *t) {
  fem_term *f = (fem_term *)t;
  free(f->tri);
  free(f->b);
  free(f->area);
  cb_stencil_free(&f->st);
  cb_projection_work_free(f->pw);
  free(f);
}

static int fem_example(const cb_model *m, int i, cb_term **out);
static int fem_frozen_example(const cb_model *m, int i, cb_term **out);

const cb_term_type cb_term_fem_type = {.name = "fem",
                                       .energy = fem_energy,
                                       .pattern = fem_pattern,
                                       .bind = fem_bind,
                                       .hessian = fem_hessian_exact,
                                       .free = fem_free,
                                       .stencil = fem_stencil,
                                       .element = fem_element_exact,
                                       .element_vertex = fem_vertex_exact,
                                       .nexamples = 1,
                                       .example = fem_example};
const cb_term_type cb_term_fem_frozen_type = {.name = "fem_frozen",
                                              .flags = CB_TERM_CONSTANT_HESSIAN | CB_TERM_MODEL_HESSIAN,
                                              .energy = fem_energy,
                                              .pattern = fem_pattern,
                                              .bind = fem_bind,
                                              .hessian = fem_hessian_frozen,
                                              .free = fem_free,
                                              .stencil = fem_stencil,
                                              .element = fem_element_frozen,
                                              .element_vertex = fem_vertex_frozen,
                                              .nexamples = 1,
                                              .example = fem_frozen_example};

int cb_fem_term_alloc(const cb_model *m, const char *label, double mu, cb_fem_hessian h, cb_term **out) {
  *out = NULL;
  if (!(mu >= 0) || !isfinite(mu)) return cb_fail("%s FEM: stiffness must be >= 0, got %g", label, mu);
  if (h != CB_FEM_EXACT && h != CB_FEM_FROZEN) return cb_fail("%s FEM: unknown Hessian %d", label, (int)h);
  const cb_mesh *mesh = m->mesh;
  fem_term *f = cb_calloc(1, sizeof *f);
  if (!f) return CB_ENOMEM;
  f->base.type = h == CB_FEM_FROZEN ? &cb_term_fem_frozen_type : &cb_term_fem_type;
  f->base.model = m;
  snprintf(f->base.label, sizeof f->base.label, "%s", label);
  f->nt = mesh->nt;
  f->mu = mu;
  size_t nt = (size_t)(mesh->nt > 0 ? mesh->nt : 1);
  f->tri = cb_malloc(3 * nt, sizeof(int));
  f->b = cb_malloc(6 * nt, sizeof(double));
  f->area = cb_malloc(nt, sizeof(double));
  if (!f->tri || !f->b || !f->area || cb_stencil_init(&f->st, 3, f->nt, f->tri, m->free_index) ||
      cb_projection_work_alloc(9, &f->pw)) {
    fem_free(&f->base);
    return CB_ENOMEM;
  }
  for (int e = 0; e < f->nt; e++) {
    const int *v = mesh->tri + 3 * e;
    memcpy(f->tri + 3 * e, v, 3 * sizeof(int));
    const double *r0 = mesh->x + 3 * v[0], *r1 = mesh->x + 3 * v[1], *r2 = mesh->x + 3 * v[2];
    double d1[3], d2[3], n[3];
    for (int a = 0; a < 3; a++) {
      d1[a] = r1[a] - r0[a];
      d2[a] = r2[a] - r0[a];
    }
    n[0] = d1[1] * d2[2] - d1[2] * d2[1];
    n[1] = d1[2] * d2[0] - d1[0] * d2[2];
    n[2] = d1[0] * d2[1] - d1[1] * d2[0];
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), l1 = sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
    if (!(nn > 0) || !(l1 > 0)) {
      fem_free(&f->base);
      return cb_fail("%s FEM: triangle %d (vertices %d %d %d) has zero rest area", label, e, v[0], v[1], v[2]);
    }
    /* the triangle's 2D frame: e1 along d1, e2 = n x e1 / |n| */
    double e1[3] = {d1[0] / l1, d1[1] / l1, d1[2] / l1}, e2[3];
    e2[0] = (n[1] * e1[2] - n[2] * e1[1]) / nn;
    e2[1] = (n[2] * e1[0] - n[0] * e1[2]) / nn;
    e2[2] = (n[0] * e1[1] - n[1] * e1[0]) / nn;
    double D00 = l1, D01 = e1[0] * d2[0] + e1[1] * d2[1] + e1[2] * d2[2],
           D11 = e2[0] * d2[0] + e2[1] * d2[1] + e2[2] * d2[2];
    /* D_m = [[D00, D01], [0, D11]]; its inverse's rows are b_1, b_2 */
    double *b = f->b + 6 * e;
    b[2] = 1 / D00;
    b[3] = -D01 / (D00 * D11);
    b[4] = 0;
    b[5] = 1 / D11;
    b[0] = -b[2] - b[4];
    b[1] = -b[3] - b[5];
    f->area[e] = 0.5 * nn;
  }
  *out = &f->base;
  return CB_OK;
}

int cb_fem_term_degenerate(const cb_term *t, const double *x, int *ntri) {
  *ntri = 0;
  if (!t || (t->type != &cb_term_fem_type && t->type != &cb_term_fem_frozen_type)) return 0;
  const fem_term *f = (const fem_term *)t;
  int c = 0;
  for (int e = 0; e < f->nt; e++) {
    double F[6], R[6], sg[2];
    deformation(f, e, x, F);
    cb_polar32(F, R, sg);
    c += !(sg[1] > FEM_DEGENERATE * sg[0]);
  }
  *ntri = f->nt;
  return c;
}

double cb_fem_term_max_strain(const cb_term *t, const double *x) {
  if (!t || (t->type != &cb_term_fem_type && t->type != &cb_term_fem_frozen_type)) return NAN;
  const fem_term *f = (const fem_term *)t;
  double m = 0;
  for (int e = 0; e < f->nt; e++) {
    double F[6], R[6], sg[2];
    deformation(f, e, x, F);
    cb_polar32(F, R, sg);
    m = fmax(m, fmax(fabs(sg[0] - 1), fabs(sg[1] - 1)));
  }
  return m;
}

/* Examples: mu = 500 N/m on every triangle, exact and frozen. */
static int fem_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  return cb_fem_term_alloc(m, "stretch", 500.0, CB_FEM_EXACT, out);
}
static int fem_frozen_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  return cb_fem_term_alloc(m, "stretch", 500.0, CB_FEM_FROZEN, out);
}
