/* Spring term: one spring per vertex pair (mesh edges for stretching, or the
 * opposite vertices of neighbouring triangles for bending springs).
 *
 *   E   = 1/2 k (l - L)^2,           x_ij = x_i - x_j,  l = |x_ij|,  u = x_ij / l
 *   dE/dx_i = k (l - L) u = -f_i,     dE/dx_j = -dE/dx_i
 *   H_e = k uu^T + k (1 - L/l)(bi - uu^T)
 *   Hessian blocks: [ H_e  -H_e ; -H_e  H_e ]  for (i, j)
 *
 * Source: GAMES103 lecture, "An Ideal Spring" and "Spring Hessian".
 *
 * Definiteness: the element matrix [H_e -H_e; -H_e H_e] has the eigenvalues
 * 2k (along u), 2 k(1 - L/l) (twice, across u) and 0 (three times), so the
 * only one that can be negative is the transverse t = k(1 - L/l) (l < L).
 * The shared projection (projection.h: clamp for `drop`, abs for `mirror`)
 * therefore acts on t alone, and the spring applies it in closed form,
 * t -> cb_projection_eigenvalue(proj, t), instead of an eigendecomposition
 * (tests/test_energy_projection.c checks that the two agree).
 *
 * A spring that reaches zero length has no direction u; its gradient and
 * Hessian become NaN, which the integrators record as `diverged` rather than
 * inventing a direction.
 *
 * Compressed response (cb_spring_term_set_response): with the Choi-Ko policy
 * a compressed spring has instead the energy E(l) of cb_choi_ko_eval
 * (energy_spring_choi_ko.c: linear until it buckles, then the
 * immediate-buckling arc), and then
 *   dE/dx_i = E'(l) u,   H_e = E''(l) uu^T + (E'(l)/l)(bi - uu^T),
 * the same form as above with k -> E'' and k(1 - L/l) -> E'/l. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>

#include "spring_state.h"
#include "nl_kernel.h"

/* The term's energy() runs the nonlinear iterations' kernel (nl_kernel.c: its loops, the streamed
 * schedule and the push kernel live there, beside the term's state in spring_state.h). */
static double spring_energy(const cb_term *t, const double *x, double *grad) {
  const cb_spring_state *s = (const cb_spring_state *)t;
  cb_spring_gather g;
  cb_spring_term_forces(t, x, &g);
  if (s->ring) { /* streamed (sorted): the gradient's chunks, or the energies alone ring by ring */
    double E = 0.0;
    if (!grad) {
      const double *en = s->f + 3 * (size_t)s->ring;
      for (int e0 = 0; e0 < s->ns; e0 += s->ring) {
        int e1 = e0 + s->ring < s->ns ? e0 + s->ring : s->ns;
        cb_spring_gather_compute(&g, e1);
        for (int e = 0; e < e1 - e0; e++) E += en[e];
      }
      return E;
    }
    for (int v0 = 0; v0 < s->nv; v0 += CB_SPRING_CHUNK) {
      int v1 = v0 + CB_SPRING_CHUNK < s->nv ? v0 + CB_SPRING_CHUNK : s->nv;
      cb_spring_gather_upto(&g, v1);
      for (int v = v0; v < v1; v++) cb_spring_gather_add(&g, v, grad + 3 * v, grad + 3 * v + 1, grad + 3 * v + 2, &E);
    }
    return E;
  }
  if (!grad || !g.sorted) {
    double E = cb_spring_gather_energy(&g);
    double none = 0.0;
    if (grad)
      for (int v = 0; v < s->nv; v++)
        cb_spring_gather_add(&g, v, grad + 3 * v, grad + 3 * v + 1, grad + 3 * v + 2, &none);
    return E;
  }
  double E = 0.0; /* sorted springs: E summed in the gather, in spring order */
  for (int v = 0; v < s->nv; v++) cb_spring_gather_add(&g, v, grad + 3 * v, grad + 3 * v + 1, grad + 3 * v + 2, &E);
  return E;
}

static int spring_pattern(const cb_term *t, cb_pattern *p) {
  return cb_stencil_pattern(&((const cb_spring_state *)t)->st, p);
}

static int spring_bind(cb_term *t, const cb_sparse *A) {
  char what[64];
  snprintf(what, sizeof what, "%s spring", t->label);
  return cb_stencil_bind(&((cb_spring_state *)t)->st, A, what);
}

/* H_e = k uu^T + tr (I - uu^T) of spring e at x, tr projected by proj. */
static inline void spring_block(const cb_spring_state *s, int e, const double *x, cb_projection proj, double H[9]) {
  int i = s->ends[2 * e], j = s->ends[2 * e + 1];
  double d[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
  double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], l = sqrt(l2);
  double along = s->k, tr = s->k * (1.0 - s->rest[e] / l); /* k, k(1 - L/l) */
  if (s->ck && l < s->rest[e]) {
    double Eb, dEb, d2Eb;
    cb_choi_ko_eval(&s->ck[e], l, &Eb, &dEb, &d2Eb);
    along = d2Eb; /* E''(l) */
    tr = dEb / l; /* E'(l) / l */
  }
  tr = cb_projection_eigenvalue(proj, tr); /* the element's only possibly negative eigenvalue (2 tr) */
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      double uu = d[a] * d[b] / l2;                     /* (uu^T)_ab */
      H[3 * a + b] = along * uu + tr * ((a == b) - uu); /* H_e = k uu^T + tr (I - uu^T) */
    }
}

static void spring_hessian(const cb_term *t, const double *x, cb_projection proj, double *val) {
  const cb_spring_state *s = (const cb_spring_state *)t;
  for (int e = 0; e < s->ns; e++) {
    if (!cb_stencil_active(&s->st, e)) continue; /* both ends pinned */
    double H[9];
    spring_block(s, e, x, proj, H);
    /* element matrix [H_e -H_e; -H_e H_e], block by block */
    cb_stencil_add_block(&s->st, e, 0, 0, H, 1.0, val);
    cb_stencil_add_block(&s->st, e, 0, 1, H, -1.0, val);
    cb_stencil_add_block(&s->st, e, 1, 0, H, -1.0, val);
    cb_stencil_add_block(&s->st, e, 1, 1, H, 1.0, val);
  }
}

static const cb_stencil *spring_stencil(const cb_term *t) { return &((const cb_spring_state *)t)->st; }

static double spring_element(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  const cb_spring_state *s = (const cb_spring_state *)t;
  double d[3], c, B[9];
  double E = cb_spring_eval(s, e, x, d, &c);
  spring_block(s, e, x, proj, B);
  for (int a = 0; a < 3; a++) {
    g[a] = c * d[a];
    g[3 + a] = -(c * d[a]);
    for (int b = 0; b < 3; b++) { /* [H_e -H_e; -H_e H_e] */
      H[6 * a + b] = H[6 * (3 + a) + 3 + b] = B[3 * a + b];
      H[6 * a + 3 + b] = H[6 * (3 + a) + b] = -B[3 * a + b];
    }
  }
  return E;
}

/* Its vertex a's part (cb_term_type.element_vertex, for VBD): the energy, the gradient block
 * dE/dx_i = c x_ij (a = 0) or dE/dx_j = -c x_ij (a = 1), and the diagonal block of the element matrix
 * [H_e -H_e; -H_e H_e], which is +H_e for either end: one 3x3 block, not the 6x6 (g, H may be NULL:
 * then they are not computed). The same numbers as spring_element with CB_PROJ_NONE. */
static double spring_element_vertex(const cb_term *t, int e, int a, const double *x, double *g, double *H) {
  const cb_spring_state *s = (const cb_spring_state *)t;
  double d[3], c;
  double E = cb_spring_eval(s, e, x, d, &c);
  if (g)
    for (int q = 0; q < 3; q++) g[q] = a ? -(c * d[q]) : c * d[q];
  if (H) spring_block(s, e, x, CB_PROJ_NONE, H);
  return E;
}

static void spring_free(cb_term *t) {
  cb_spring_state *s = (cb_spring_state *)t;
  free(s->ends);
  free(s->ei);
  free(s->ej);
  free(s->off);
  free(s->inc);
  free(s->mid);
  free(s->f);
  free(s->need);
  free(s->rinc);
  free(s->first);
  free(s->acc);
  free(s->x4);
  free(s->i4);
  free(s->j4);
  free(s->slot);
  free(s->rest);
  cb_stencil_free(&s->st);
  free(s->ck);
  free(s);
}

static int spring_example(const cb_model *m, int i, cb_term **out);
static int spring_indefinite(const cb_term *t, const double *x, int *nsprings);

extern const cb_term_type cb_term_spring_type; /* registered in energy.c */
const cb_term_type cb_term_spring_type = {.name = "spring",
                                          .energy = spring_energy,
                                          .pattern = spring_pattern,
                                          .bind = spring_bind,
                                          .hessian = spring_hessian,
                                          .free = spring_free,
                                          .stencil = spring_stencil,
                                          .element = spring_element,
                                          .element_vertex = spring_element_vertex,
                                          .nexamples = 3,
                                          .example = spring_example,
                                          .indefinite = spring_indefinite};
const cb_term_type *const cb_term_spring = &cb_term_spring_type;


int cb_spring_term_alloc(const cb_model *m, const char *label, int ns, const int *ends, double k, cb_term **out) {
  *out = NULL;
  if (!(k >= 0) || !isfinite(k)) return cb_fail("%s springs: stiffness must be >= 0, got %g", label, k);
  cb_spring_state *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->base.type = &cb_term_spring_type;
  s->base.model = m;
  snprintf(s->base.label, sizeof s->base.label, "%s", label);
  s->ns = ns;
  s->k = k;
  s->nv = m->mesh->nv;
  s->ends = cb_malloc((size_t)2 * ns, sizeof(int));
  s->ei = cb_malloc((size_t)ns + 1, sizeof(int));
  s->ej = cb_malloc((size_t)ns + 1, sizeof(int));
  s->inc = cb_malloc((size_t)2 * ns + 1, sizeof(int));
  s->off = cb_calloc((size_t)s->nv + 1, sizeof(int));
  s->mid = cb_malloc((size_t)s->nv + 1, sizeof(int));
  s->f = cb_calloc_aligned((size_t)4 * ns + 1, sizeof(double)); /* aligned: the push kernel's 4-vectors */
  s->rest = cb_malloc((size_t)ns + 1, sizeof(double));
  s->need = cb_malloc((size_t)s->nv + 1, sizeof(int));
  s->rinc = cb_malloc((size_t)2 * ns + 1, sizeof(int));
  if (!s->ends || !s->ei || !s->ej || !s->inc || !s->off || !s->mid || !s->f || !s->rest || !s->need || !s->rinc ||
      cb_stencil_init(&s->st, 2, ns, s->ends, m->free_index)) {
    spring_free(&s->base);
    return CB_ENOMEM;
  }
  const double *x = m->mesh->x;
  for (int e = 0; e < ns; e++) {
    int i = ends[2 * e], j = ends[2 * e + 1];
    if (i < 0 || j < 0 || i >= m->mesh->nv || j >= m->mesh->nv || i == j) {
      spring_free(&s->base);
      return cb_fail("%s spring %d joins invalid vertices (%d, %d)", label, e, i, j);
    }
    s->ends[2 * e] = i;
    s->ends[2 * e + 1] = j;
    double d[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
    s->rest[e] = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(s->rest[e] > 0)) {
      spring_free(&s->base);
      return cb_fail("%s spring %d between vertices %d and %d has zero rest length (coincident vertices)", label, e, i,
                     j);
    }
    s->ei[e] = i;
    s->ej[e] = j;
  }
  /* each vertex's springs, e increasing (a counting sort): the gather's order */
  for (int e = 0; e < ns; e++) {
    s->off[s->ei[e] + 1]++;
    s->off[s->ej[e] + 1]++;
  }
  for (int v = 0; v < s->nv; v++) s->off[v + 1] += s->off[v];
  int *fill = cb_malloc((size_t)s->nv + 1, sizeof(int));
  if (!fill) {
    spring_free(&s->base);
    return CB_ENOMEM;
  }
  memcpy(fill, s->off, (size_t)s->nv * sizeof(int));
  for (int e = 0; e < ns; e++) {
    s->inc[fill[s->ei[e]]++] = 2 * e;
    s->inc[fill[s->ej[e]]++] = 2 * e + 1;
  }
  free(fill);
  s->sorted = 1;
  for (int e = 1; e < ns; e++) s->sorted &= s->ei[e] >= s->ei[e - 1];
  s->split = 1;
  for (int v = 0; v < s->nv; v++) {
    int q = s->off[v];
    while (q < s->off[v + 1] && (s->inc[q] & 1)) q++;
    s->mid[v] = q;
    for (; q < s->off[v + 1]; q++) s->split &= !(s->inc[q] & 1);
  }
  cb_spring_schedule(s);
  if (cb_spring_push_setup(s)) {
    spring_free(&s->base);
    return CB_ENOMEM;
  }
  *out = &s->base;
  return CB_OK;
}

int cb_spring_term_set_response(cb_term *t, cb_definiteness def, double kb) {
  if (!t || t->type != &cb_term_spring_type) return cb_fail("set_response: not a spring term");
  if (def == CB_DEF_CHOI_KO && !(kb > 0 && isfinite(kb)))
    return cb_fail("%s springs: Choi-Ko bending stiffness must be > 0, got %g", t->label, kb);
  cb_spring_state *s = (cb_spring_state *)t;
  free(s->ck);
  s->ck = NULL;
  cb_spring_schedule(s); /* linear springs: streamed if sorted */
  if (def != CB_DEF_CHOI_KO) return CB_OK;
  s->ck = cb_malloc((size_t)(s->ns > 0 ? s->ns : 1), sizeof *s->ck);
  if (!s->ck) return CB_ENOMEM;
  for (int e = 0; e < s->ns; e++) {
    int st = cb_choi_ko_init(&s->ck[e], s->k, s->rest[e], kb);
    if (st) {
      char msg[512];
      snprintf(msg, sizeof msg, "%s", cb_error_message());
      free(s->ck);
      s->ck = NULL;
      return cb_fail("%s spring %d: %s", t->label, e, msg);
    }
  }
  s->ring = 0; /* Choi-Ko springs are all computed at once */
  return CB_OK;
}

/* The springs with l < L at x: the only ones whose transverse eigenvalue
 * k (1 - L/l) is negative. */
static int spring_indefinite(const cb_term *t, const double *x, int *nsprings) {
  *nsprings = 0;
  if (!t || t->type != &cb_term_spring_type) return 0;
  const cb_spring_state *s = (const cb_spring_state *)t;
  int c = 0;
  for (int e = 0; e < s->ns; e++) {
    int i = s->ends[2 * e], j = s->ends[2 * e + 1];
    double d[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
    c += d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < s->rest[e] * s->rest[e]; /* l < L */
  }
  *nsprings = s->ns;
  return c;
}

int cb_spring_term_is_choi_ko(const cb_term *t) {
  return t && t->type == &cb_term_spring_type && ((const cb_spring_state *)t)->ck;
}

int cb_spring_term_springs(const cb_term *t, int *ns, const int **ends, const double **rest, double *k) {
  if (!t || t->type != &cb_term_spring_type) return cb_fail("term '%s' is not a spring term", t ? t->label : "(null)");
  const cb_spring_state *s = (const cb_spring_state *)t;
  *ns = s->ns;
  *ends = s->ends;
  *rest = s->rest;
  *k = s->k;
  return CB_OK;
}

/* Examples: 0 stretch springs on every edge, 1 bending springs across every
 * pair of neighbouring triangles, 2 stretch springs with the Choi-Ko response
 * (k_b = 1e-4 N m^2: k > 12 pi^2 k_b / L^3 for every rest length L > 1 cm). */
static int spring_example(const cb_model *m, int i, cb_term **out) {
  if (i == 1) return cb_spring_term_alloc(m, "bend", m->topo->np, m->topo->pair_opp, 37.0, out);
  int st = cb_spring_term_alloc(m, "stretch", m->topo->ne, m->topo->edge, 8000.0, out);
  if (st == CB_OK && i == 2) st = cb_spring_term_set_response(*out, CB_DEF_CHOI_KO, 1e-4);
  if (st && *out) {
    cb_term_free(*out);
    *out = NULL;
  }
  return st;
}

/* The kernel's entry points that take a term (nl_kernel.h): they check the type here, so that
 * nl_kernel.c needs nothing of this file. */
int cb_spring_term_layout(const cb_term *t, cb_spring_layout *out) {
  if (!t || t->type != &cb_term_spring_type) return cb_fail("term '%s' is not a spring term", t ? t->label : "(null)");
  const cb_spring_state *s = (const cb_spring_state *)t;
  out->ns = s->ns;
  out->nv = s->nv;
  out->ei = s->ei;
  out->ej = s->ej;
  out->rest = s->rest;
  out->k = s->k;
  out->off = s->off;
  out->inc = s->inc;
  return CB_OK;
}

int cb_spring_term_push(const cb_term *t, cb_spring_push *p) {
  if (!t || t->type != &cb_term_spring_type) return 0;
  const cb_spring_state *s = (const cb_spring_state *)t;
  if (!s->push || s->ck || s->ns == 0) return 0;
  p->nv = s->nv;
  p->ns = s->ns;
  p->M = s->pushM;
  p->cap = s->pushcap;
  p->first = s->first;
  p->slot = s->slot;
  p->f = s->f; /* the term's scratch (4 ns >= 4 cap) */
  p->acc = s->acc;
  p->x4 = s->x4;
  p->t = t;
  return 1;
}
