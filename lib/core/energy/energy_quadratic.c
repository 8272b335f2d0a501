/* Quadratic bending (Bergou, Wardetzky, Harmon, Zorin & Grinspun 2006, "A
 * Quadratic Bending Model for Inextensible Surfaces", SCA), exactly as the
 * lecture gives it ("A Quadratic Bending Model"): per hinge, with x0, x1 the
 * shared edge and x2, x3 the wings of triangles A (area A_0) and B (A_1),
 *
 *   q = [ (cot t1 + cot t3) I, (cot t0 + cot t2) I, -(cot t0 + cot t1) I, -(cot t2 + cot t3) I ]
 *   Q = 3 / (A_0 + A_1) q q^T,      E = k_b/2 x^T Q x = k_b 3 |q^T x|^2 / (2 (A_0 + A_1)),
 *
 * t0, t1 the angles at x0, x1 in triangle A, t2, t3 those at x0, x1 in B,
 * all measured once on the rest mesh. k_b = material.bend_k in N m (J): q is
 * dimensionless and Q has units 1/m^2. The scaling is the lecture's, with no
 * extra factor: 3/(A_0+A_1) and 1/2.
 *
 * q^T x vanishes on a flat hinge whose shape has the rest cotangents, and
 * under translations (the entries of q sum to 0) and rotations of it. The
 * rest configuration should be planar, as the lecture warns. A non-planar
 * rest hinge is accepted with its rest curvature subtracted:
 *   E = k_b/2 (x - x_bar)^T Q (x - x_bar),
 * zero at rest; that energy is not invariant under rotations of a curved
 * rest shape (why the lecture calls the model unsuitable there). For a planar
 * rest mesh q^T x_bar = 0 and this is the lecture's E = k_b/2 x^T Q x.
 *
 * The Hessian k_b Q is constant and PSD (CB_TERM_CONSTANT_HESSIAN): the
 * system assembles it once per scene. Blocks: H_ab = k_b 3/(A_0+A_1) q_a q_b I. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>

extern const cb_term_type cb_term_quadratic_type;

typedef struct {
  cb_term base;
  int nh;
  int *vert;   /* 4*nh: x0, x1 (edge), x2 (wing A), x3 (wing B) */
  double *q;   /* 4*nh cotangent weights */
  double *w;   /* nh: k_b 3 / (A_0 + A_1), J/m^2 */
  double *qx0; /* 3*nh: q^T x_bar (0 for a planar rest hinge) */
  cb_stencil st;
} quad_term;

/* cot of the angle at vertex o between o->p and o->r. */
static double cot_at(const double *o, const double *p, const double *r) {
  double u[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]}, v[3] = {r[0] - o[0], r[1] - o[1], r[2] - o[2]};
  double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  return (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

static double tri_area(const double *a, const double *b, const double *c) {
  double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* q^T x at hinge e (3 numbers), less its rest value. */
static void qx(const quad_term *s, int e, const double *x, double *o) {
  const int *v = s->vert + 4 * e;
  const double *q = s->q + 4 * e;
  for (int c = 0; c < 3; c++)
    o[c] = q[0] * x[3 * v[0] + c] + q[1] * x[3 * v[1] + c] + q[2] * x[3 * v[2] + c] + q[3] * x[3 * v[3] + c] -
           s->qx0[3 * e + c];
}

static double quad_energy(const cb_term *t, const double *x, double *grad) {
  const quad_term *s = (const quad_term *)t;
  double E = 0;
  for (int e = 0; e < s->nh; e++) {
    double r[3];
    qx(s, e, x, r);
    E += 0.5 * s->w[e] * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (grad) {
      double g[12];
      for (int a = 0; a < 4; a++)
        for (int c = 0; c < 3; c++) g[3 * a + c] = s->w[e] * s->q[4 * e + a] * r[c];
      cb_stencil_add_gradient(&s->st, e, g, grad);
    }
  }
  return E;
}

static int quad_pattern(const cb_term *t, cb_pattern *p) { return cb_stencil_pattern(&((const quad_term *)t)->st, p); }

static int quad_bind(cb_term *t, const cb_sparse *A) {
  char what[64];
  snprintf(what, sizeof what, "%s quadratic hinge", t->label);
  return cb_stencil_bind(&((quad_term *)t)->st, A, what);
}

static void quad_hessian(const cb_term *t, const double *x, cb_projection proj, double *val) {
  (void)x;
  (void)proj; /* constant and PSD: assembled once, never projected */
  const quad_term *s = (const quad_term *)t;
  static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int e = 0; e < s->nh; e++) {
    if (!cb_stencil_active(&s->st, e)) continue;
    const double *q = s->q + 4 * e;
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++) cb_stencil_add_block(&s->st, e, a, b, I, s->w[e] * q[a] * q[b], val);
  }
}

static const cb_stencil *quad_stencil(const cb_term *t) { return &((const quad_term *)t)->st; }

/* E_e = w/2 |q^T x - q^T x_bar|^2, g_a = w q_a r, H_ab = w q_a q_b I_3. */
static double quad_element(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  (void)proj; /* constant and PSD */
  const quad_term *s = (const quad_term *)t;
  const double *q = s->q + 4 * e;
  double r[3];
  qx(s, e, x, r);
  memset(H, 0, 144 * sizeof(double));
  for (int a = 0; a < 4; a++)
    for (int c = 0; c < 3; c++) {
      g[3 * a + c] = s->w[e] * q[a] * r[c];
      for (int b = 0; b < 4; b++) H[(3 * a + c) * 12 + 3 * b + c] = s->w[e] * q[a] * q[b];
    }
  return 0.5 * s->w[e] * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

/* Its vertex a's part (cb_term_type.element_vertex): g = w q_a r, H = w q_a q_a I_3. */
static double quad_element_vertex(const cb_term *t, int e, int a, const double *x, double *g, double *H) {
  const quad_term *s = (const quad_term *)t;
  const double *q = s->q + 4 * e;
  double r[3];
  qx(s, e, x, r);
  if (H) memset(H, 0, 9 * sizeof(double));
  for (int c = 0; c < 3; c++) {
    if (g) g[c] = s->w[e] * q[a] * r[c];
    if (H) H[4 * c] = s->w[e] * q[a] * q[a];
  }
  return 0.5 * s->w[e] * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

static void quad_free(cb_term *t) {
  quad_term *s = (quad_term *)t;
  free(s->vert);
  free(s->q);
  free(s->w);
  free(s->qx0);
  cb_stencil_free(&s->st);
  free(s);
}

int cb_quadratic_bend_term_alloc(const cb_model *m, const char *label, double k, cb_term **out) {
  *out = NULL;
  if (!(k >= 0) || !isfinite(k)) return cb_fail("%s quadratic hinges: stiffness must be >= 0, got %g", label, k);
  quad_term *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->base.type = &cb_term_quadratic_type;
  s->base.model = m;
  snprintf(s->base.label, sizeof s->base.label, "%s", label);
  int nh = m->topo->np, n1 = nh > 0 ? nh : 1;
  s->nh = nh;
  s->vert = cb_malloc((size_t)4 * n1, sizeof(int));
  s->q = cb_malloc((size_t)4 * n1, sizeof(double));
  s->w = cb_malloc((size_t)n1, sizeof(double));
  s->qx0 = cb_calloc((size_t)3 * n1, sizeof(double));
  if (!s->vert || !s->q || !s->w || !s->qx0 || cb_stencil_init(&s->st, 4, nh, s->vert, m->free_index)) {
    quad_free(&s->base);
    return CB_ENOMEM;
  }
  cb_hinge_vertices(m->topo, s->vert);
  const double *X = m->mesh->x;
  for (int e = 0; e < nh; e++) {
    const int *v = s->vert + 4 * e;
    const double *x0 = X + 3 * v[0], *x1 = X + 3 * v[1], *x2 = X + 3 * v[2], *x3 = X + 3 * v[3];
    double A0 = tri_area(x0, x1, x2), A1 = tri_area(x0, x1, x3);
    double t0 = cot_at(x0, x1, x2), t1 = cot_at(x1, x0, x2), t2 = cot_at(x0, x1, x3), t3 = cot_at(x1, x0, x3);
    if (!(A0 > 0) || !(A1 > 0) || !isfinite(t0 + t1 + t2 + t3)) {
      quad_free(&s->base);
      return cb_fail("%s quadratic hinge %d on edge (%d, %d): degenerate rest triangle", label, e, v[0], v[1]);
    }
    double *q = s->q + 4 * e;
    q[0] = t1 + t3;
    q[1] = t0 + t2;
    q[2] = -(t0 + t1);
    q[3] = -(t2 + t3);
    s->w[e] = k * 3.0 / (A0 + A1);
  }
  for (int e = 0; e < nh; e++) qx(s, e, X, s->qx0 + 3 * e); /* qx0 is still 0: q^T x_bar */
  *out = &s->base;
  return CB_OK;
}

/* Examples: every pair, k_b = 0.37 N m. */
static int quad_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  return cb_quadratic_bend_term_alloc(m, "bend", 0.37, out);
}

const cb_term_type cb_term_quadratic_type = {.name = "quadratic",
                                             .flags = CB_TERM_CONSTANT_HESSIAN,
                                             .energy = quad_energy,
                                             .pattern = quad_pattern,
                                             .bind = quad_bind,
                                             .hessian = quad_hessian,
                                             .free = quad_free,
                                             .stencil = quad_stencil,
                                             .element = quad_element,
                                             .element_vertex = quad_element_vertex,
                                             .nexamples = 1,
                                             .example = quad_example};
