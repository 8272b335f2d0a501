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
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>

#include "nl_kernel.h"

typedef struct {
  cb_term base;
  int ns;
  int *ends;      /* 2*ns vertex indices (the pairs: the stencil's and cb_spring_term_springs') */
  int *ei, *ej;   /* ns each: the same ends as two arrays (structure of arrays, for the kernel) */
  double *rest;   /* ns rest lengths L, m */
  double k;       /* N/m */
  cb_choi_ko *ck; /* ns: Choi-Ko response of each spring, or NULL (linear springs) */
  cb_stencil st;  /* 2-vertex elements (i, j) = ends, bound to the pattern */
  int nv;         /* vertices of the mesh */
  int *mid;       /* nv: where each vertex's list turns from second ends to first ends (when split) */
  int split;      /* every vertex's list is second ends, then first ends */
  int *off, *inc; /* nv + 1, 2*ns: each vertex's springs, inc[off[v]..off[v+1]) = 2e + side (0: v = ei[e], 1: v =
                   * ej[e]), e increasing: the gather's order is the scatter's */
  int sorted;     /* ei nondecreasing (the mesh's edges are): the gather sums E too */
  double *f;      /* 4*ns scratch of the kernel: dE/dx_i of each spring (x, y, z blocks of R), then its energy */
  int ring;       /* the streamed ring's length R (a power of two, from the schedule), or 0: not streamed */
  int *need;      /* nv: the springs < need[v] must be ready before vertex v's gather (nondecreasing) */
  int *rinc;      /* 2*ns: inc with each spring's place in the ring, 2 (e mod R) + side (streamed) */
  int push;       /* sorted and ei < ej everywhere: the push kernel applies (to linear springs; nl_kernel.h) */
  int *first;     /* nv + 1: vertex v's springs as first end are [first[v], first[v+1]) (sorted) */
  int pushM;      /* the push accumulator's ring of vertices (a power of two > max ej - ei) */
  int pushcap;    /* the most springs in a chunk of CB_SPRING_CHUNK vertices */
  double *acc;    /* 4 pushM (x, y, z and a lane the push kernel ignores), zero between passes */
  double *x4;     /* 4 nv: the positions of a push pass, padded to four doubles (x, y, z, 0) */
  int *i4, *j4;   /* ns each: 4 ei, 4 ej (where the ends start in x4) */
  int *slot;      /* ns: 4 (ej mod pushM), where spring e's -f_e goes in acc */
} spring_term;

/* Energy of spring e at x and its gradient coefficient c: dE/dx_i = c x_ij,
 * x_ij = d (3 numbers, filled). */
static inline double spring_eval(const spring_term *s, int e, const double *x, double d[3], double *c) {
  int i = s->ends[2 * e], j = s->ends[2 * e + 1];
  d[0] = x[3 * i] - x[3 * j];
  d[1] = x[3 * i + 1] - x[3 * j + 1];
  d[2] = x[3 * i + 2] - x[3 * j + 2];
  double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  double stretch = l - s->rest[e];
  *c = s->k * stretch / l; /* dE/dx_i = k (l - L) x_ij / l */
  if (s->ck && stretch < 0) {
    double Eb, dEb, d2Eb;
    cb_choi_ko_eval(&s->ck[e], l, &Eb, &dEb, &d2Eb);
    *c = dEb / l; /* dE/dx_i = E'(l) x_ij / l */
    return Eb;    /* E = E(l) */
  }
  return 0.5 * s->k * stretch * stretch; /* E = k/2 (l - L)^2 */
}

/* The kernel, in three loops (the gradient, the objective and its terms in
 * one pass over the springs; no scatter):
 *   1. forces: for every spring, independently, x_ij = x_i - x_j, l = |x_ij|,
 *      c = k (l - L)/l, f_e = c x_ij and E_e = k/2 (l - L)^2 into
 *      structure-of-arrays scratch: no loop-carried dependence, so the
 *      compiler vectorises it (sqrt and divide included: one divide per
 *      spring, 1/l, is the only one; -fno-math-errno, Makefile KERNEL_CFLAGS);
 *      compressed Choi-Ko springs are then redone one by one;
 *   2. E = sum of E_e, in spring order;
 *   3. gradient: each vertex, in mesh order, gathers its springs' +-f_e in
 *      spring order (off/inc), starting from grad's value.
 * For sorted linear springs (a mesh's edges) loops 1 and 3 interleave: loop
 * 1 runs a chunk of vertices ahead of loop 3 into a ring of R springs
 * (nl_kernel.h, spring_schedule), and loop 2 is folded into loop 3, so the
 * scratch stays in L1/L2 (measured at 129^2 on a Xeon with 2 MB of L2: the
 * frame 7-10% faster, bench_nonlinear's ratio 1.41x -> 1.51x in CPU time;
 * compiling loop 1 for AVX2 or AVX-512 did not change the time there; on an
 * AMD EPYC (Zen 3) the AVX2 copy below runs 23% fewer instructions in loop 1
 * and the frame about 3% faster). The update passes of jacobi-nl and
 * chebyshev-nl need no F, so their loop 1 skips the energies (energy = 0).
 * The push kernel (nl_kernel.h) has its own loop 1, spring_push_body: four
 * springs at a time as 4-vectors, from positions padded to four doubles
 * (x4, 64-byte aligned like f and acc, so that no 4-vector straddles two
 * cache lines), into four doubles a spring; measured at 129^2 on an AMD EPYC
 * (Zen 5) against the compiler's vectorisation of spring_forces_body, whose
 * twelve scalar loads and inserts a spring dominated: the frame about 1.6x
 * faster with the 4-vector vertex loop of integrator_nljacobi.c.
 * The order of every sum is unchanged.
 * Loop 3 adds to each grad entry the same numbers in the same order as the
 * scatter grad_i += f_e, grad_j += -f_e over e did, and loops 1-2 evaluate
 * the same expressions, so energy and gradient are bit for bit those of the
 * one-spring-at-a-time kernel (spring_eval). The scratch makes a term
 * non-reentrant: one thread evaluates a term at a time (as everywhere here). */
/* Loop 1 is compiled twice on x86-64 with GCC (CB_KERNEL_CLONES, nl_kernel.h). */
/* Loop 1 for the springs [e0, e1), spring e's results at q = e - base (the caller keeps q inside the
 * scratch): lane a (x, y, z, E) at out[q * qs + a * ls]. The gather's layout is blocks of R (qs = 1, ls = R);
 * the push kernel's is four doubles a spring (qs = 4, ls = 1), where it does the springs that
 * spring_push_body leaves over, and energy 0 writes 0 as E. */
static inline __attribute__((always_inline)) void spring_forces_body(const spring_term *s, const double *restrict x,
                                                                     int e0, int e1, int base, double *restrict out,
                                                                     size_t qs, size_t ls, int energy) {
  const int *restrict ei = s->ei, *restrict ej = s->ej;
  const double *restrict rest = s->rest, k = s->k;
  for (int e = e0; e < e1; e++) {
    int i = ei[e], j = ej[e];
    double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
    double l = sqrt(dx * dx + dy * dy + dz * dz);
    double stretch = l - rest[e];
    double c = k * stretch / l; /* dE/dx_i = k (l - L) x_ij / l */
    double *o = out + (size_t)(e - base) * qs;
    o[0] = c * dx;
    o[ls] = c * dy;
    o[2 * ls] = c * dz;
    o[3 * ls] = energy ? 0.5 * k * stretch * stretch : 0.0; /* E = k/2 (l - L)^2 */
  }
}
CB_KERNEL_CLONES static void spring_forces_range(const spring_term *s, const double *restrict x, int e0, int e1,
                                                 int base, int R) {
  spring_forces_body(s, x, e0, e1, base, s->f, 1, (size_t)R, 1);
}
/* The push kernel's loop 1: four springs at a time as 4-vectors. Each end's position is one vector (x, y, z,
 * 0), their differences are transposed into dx, dy, dz of the four springs, and l, c and E are computed
 * lane by lane with the expressions of spring_forces_body; then spring s's force is c_s (dx, dy, dz, 0) of
 * its own difference, one vector store. The lane by lane operations round as the scalar ones: the same bits
 * (bench_nonlinear checks them against the old kernel). The springs left over go through spring_forces_body. */
static inline __attribute__((always_inline)) void spring_push_body(const spring_term *s, const double *restrict x,
                                                                   int e0, int e1, int energy) {
  const double *restrict x4 = s->x4;
  const int *restrict i4 = s->i4, *restrict j4 = s->j4;
  const double *restrict rest = s->rest, k = s->k;
  double *restrict out = s->f;
  int e = e0;
  for (; e + 4 <= e1; e += 4) {
    cb_v4d d[4], L, l, c;
#pragma GCC unroll 4
    for (int a = 0; a < 4; a++) {
      cb_v4d pi, pj;
      cb_v4d_get(&pi, x4 + i4[e + a]);
      cb_v4d_get(&pj, x4 + j4[e + a]);
      d[a] = pi - pj; /* x_ij of spring e + a */
    }
    cb_v4d t0 = __builtin_shufflevector(d[0], d[1], 0, 4, 2, 6), t1 = __builtin_shufflevector(d[0], d[1], 1, 5, 3, 7);
    cb_v4d t2 = __builtin_shufflevector(d[2], d[3], 0, 4, 2, 6), t3 = __builtin_shufflevector(d[2], d[3], 1, 5, 3, 7);
    cb_v4d dx = __builtin_shufflevector(t0, t2, 0, 1, 4, 5), dy = __builtin_shufflevector(t1, t3, 0, 1, 4, 5),
           dz = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    cb_v4d l2 = dx * dx + dy * dy + dz * dz;
#pragma GCC unroll 4
    for (int a = 0; a < 4; a++) l[a] = sqrt(l2[a]);
    memcpy(&L, rest + e, sizeof L);
    cb_v4d stretch = l - L;
    c = k * stretch / l; /* dE/dx_i = k (l - L) x_ij / l */
#pragma GCC unroll 4
    for (int a = 0; a < 4; a++) {
      cb_v4d f = c[a] * d[a];
      cb_v4d_put(out + 4 * (size_t)(e + a - e0), &f);
    }
    if (energy) {
      cb_v4d E = 0.5 * k * stretch * stretch; /* E = k/2 (l - L)^2 */
#pragma GCC unroll 4
      for (int a = 0; a < 4; a++) out[4 * (size_t)(e + a - e0) + 3] = E[a];
    }
  }
  spring_forces_body(s, x, e, e1, e0, out, 4, 1, energy);
}
CB_KERNEL_CLONES static void spring_push_range(const spring_term *s, const double *restrict x, int e0, int e1) {
  spring_push_body(s, x, e0, e1, 1);
}
CB_KERNEL_CLONES static void spring_push_range_noenergy(const spring_term *s, const double *restrict x, int e0,
                                                        int e1) {
  spring_push_body(s, x, e0, e1, 0);
}

/* Every spring's forces at once (not streamed). */
static void spring_forces(const spring_term *s, const double *restrict x) {
  const int ns = s->ns;
  spring_forces_range(s, x, 0, ns, 0, ns);
  if (!s->ck) return;
  double *restrict fx = s->f, *restrict fy = s->f + ns, *restrict fz = s->f + 2 * (size_t)ns,
                   *restrict en = s->f + 3 * (size_t)ns;
  for (int e = 0; e < ns; e++) { /* compressed Choi-Ko springs: spring_eval's other branch */
    double d[3], c;
    double E = spring_eval(s, e, x, d, &c);
    fx[e] = c * d[0];
    fy[e] = c * d[1];
    fz[e] = c * d[2];
    en[e] = E;
  }
}

/* Streamed: the springs [done, need) into the ring, at e mod R. */
void cb_spring_gather_compute(cb_spring_gather *g, int need) {
  const spring_term *s = (const spring_term *)g->t;
  const int R = g->R;
  for (int e0 = g->done; e0 < need;) {
    int base = e0 & ~(R - 1), e1 = base + R < need ? base + R : need; /* up to the ring's end */
    spring_forces_range(s, g->x, e0, e1, base, R);
    e0 = e1;
  }
  g->done = need;
}

static double spring_energy(const cb_term *t, const double *x, double *grad) {
  const spring_term *s = (const spring_term *)t;
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
  return cb_stencil_pattern(&((const spring_term *)t)->st, p);
}

static int spring_bind(cb_term *t, const cb_sparse *A) {
  char what[64];
  snprintf(what, sizeof what, "%s spring", t->label);
  return cb_stencil_bind(&((spring_term *)t)->st, A, what);
}

/* H_e = k uu^T + tr (I - uu^T) of spring e at x, tr projected by proj. */
static inline void spring_block(const spring_term *s, int e, const double *x, cb_projection proj, double H[9]) {
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
  const spring_term *s = (const spring_term *)t;
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

static const cb_stencil *spring_stencil(const cb_term *t) { return &((const spring_term *)t)->st; }

static double spring_element(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H) {
  const spring_term *s = (const spring_term *)t;
  double d[3], c, B[9];
  double E = spring_eval(s, e, x, d, &c);
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
  const spring_term *s = (const spring_term *)t;
  double d[3], c;
  double E = spring_eval(s, e, x, d, &c);
  if (g)
    for (int q = 0; q < 3; q++) g[q] = a ? -(c * d[q]) : c * d[q];
  if (H) spring_block(s, e, x, CB_PROJ_NONE, H);
  return E;
}

static void spring_free(cb_term *t) {
  spring_term *s = (spring_term *)t;
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

void cb_spring_term_forces(const cb_term *t, const double *x, cb_spring_gather *g) {
  const spring_term *s = (const spring_term *)t;
  g->ns = s->ns;
  g->sorted = s->sorted;
  g->split = s->split;
  g->mid = s->mid;
  g->off = s->off;
  g->f = s->f;
  g->need = s->need;
  g->t = t;
  g->x = x;
  if (s->ring) { /* streamed: nothing computed yet */
    g->R = s->ring;
    g->inc = s->rinc;
    g->done = 0;
  } else {
    g->R = s->ns;
    g->inc = s->inc;
    spring_forces(s, x);
    g->done = s->ns;
  }
}

int cb_spring_term_layout(const cb_term *t, cb_spring_layout *out) {
  if (!t || t->type != &cb_term_spring_type) return cb_fail("term '%s' is not a spring term", t ? t->label : "(null)");
  const spring_term *s = (const spring_term *)t;
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

/* The streamed schedule (nl_kernel.h), played once: need[v] (the last spring of vertices <= v, + 1), and the
 * ring: before chunk [v0, v1) gathers, the springs < need[v1 - 1] are computed, and it must still hold the
 * first spring (lo) of each vertex of the chunk. Streamed when sorted and linear and the ring is shorter
 * than ns. */
static void spring_schedule(spring_term *s) {
  int ns = s->ns, nv = s->nv, hi = 0, window = 1;
  for (int v = 0; v < nv; v++) {
    int q0 = s->off[v], q1 = s->off[v + 1];
    if (q1 > q0 && (s->inc[q1 - 1] >> 1) + 1 > hi) hi = (s->inc[q1 - 1] >> 1) + 1; /* inc is in increasing e */
    s->need[v] = hi;
  }
  for (int v0 = 0; v0 < nv; v0 += CB_SPRING_CHUNK) {
    int v1 = v0 + CB_SPRING_CHUNK < nv ? v0 + CB_SPRING_CHUNK : nv, done = s->need[v1 - 1];
    for (int v = v0; v < v1; v++)
      if (s->off[v + 1] > s->off[v] && done - (s->inc[s->off[v]] >> 1) > window)
        window = done - (s->inc[s->off[v]] >> 1);
  }
  int R = 1;
  while (R < window && R < ns) R *= 2;
  s->ring = s->sorted && !s->ck && R < ns ? R : 0;
  for (int q = 0; q < 2 * ns; q++)
    s->rinc[q] = s->ring ? (((s->inc[q] >> 1) & (R - 1)) << 1) | (s->inc[q] & 1) : s->inc[q];
}

/* The push kernel's layout (nl_kernel.h): first, the accumulator's ring and the chunks' largest spring count. */
static int spring_push_setup(spring_term *s) {
  s->push = s->sorted;
  int maxd = 0;
  for (int e = 0; e < s->ns && s->push; e++) {
    s->push &= s->ei[e] < s->ej[e];
    if (s->ej[e] - s->ei[e] > maxd) maxd = s->ej[e] - s->ei[e];
  }
  s->push &= s->nv <= INT_MAX / 4; /* its offsets 4 v in int */
  if (!s->push) return CB_OK;
  s->first = cb_malloc((size_t)s->nv + 1, sizeof(int));
  if (!s->first) return CB_ENOMEM;
  for (int v = 0, e = 0; v <= s->nv; v++) { /* the first spring whose first end is >= v */
    while (e < s->ns && s->ei[e] < v) e++;
    s->first[v] = e;
  }
  int M = 1;
  while (M <= maxd) M *= 2;
  s->pushM = M;
  s->acc = cb_calloc_aligned((size_t)4 * M, sizeof(double));
  s->x4 = cb_calloc_aligned((size_t)4 * s->nv, sizeof(double));
  s->i4 = cb_malloc((size_t)s->ns, sizeof(int));
  s->j4 = cb_malloc((size_t)s->ns, sizeof(int));
  s->slot = cb_malloc((size_t)s->ns, sizeof(int));
  if (!s->acc || !s->x4 || !s->i4 || !s->j4 || !s->slot) return CB_ENOMEM;
  for (int e = 0; e < s->ns; e++) {
    s->i4[e] = 4 * s->ei[e];
    s->j4[e] = 4 * s->ej[e];
    s->slot[e] = 4 * (s->ej[e] & (M - 1));
  }
  s->pushcap = 0;
  for (int v0 = 0; v0 < s->nv; v0 += CB_SPRING_CHUNK) {
    int v1 = v0 + CB_SPRING_CHUNK < s->nv ? v0 + CB_SPRING_CHUNK : s->nv;
    if (s->first[v1] - s->first[v0] > s->pushcap) s->pushcap = s->first[v1] - s->first[v0];
  }
  return CB_OK;
}

int cb_spring_term_push(const cb_term *t, cb_spring_push *p) {
  if (!t || t->type != &cb_term_spring_type) return 0;
  const spring_term *s = (const spring_term *)t;
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

CB_KERNEL_CLONES void cb_spring_push_positions(const cb_spring_push *p, const double *restrict x, int v0, int v1) {
  double *restrict x4 = p->x4;
  int vl = v1 < p->nv ? v1 : p->nv - 1; /* four doubles from x + 3v stay inside x below the last vertex */
  for (int v = v0; v < vl; v++) {       /* (x, y, z, the next vertex's x) with its fourth lane made 0 */
    cb_v4d t;
    cb_v4d_get(&t, x + 3 * (size_t)v);
    t[3] = 0.0;
    cb_v4d_put(x4 + 4 * (size_t)v, &t);
  }
  for (int v = vl > v0 ? vl : v0; v < v1; v++) {
    x4[4 * (size_t)v] = x[3 * (size_t)v];
    x4[4 * (size_t)v + 1] = x[3 * (size_t)v + 1];
    x4[4 * (size_t)v + 2] = x[3 * (size_t)v + 2];
  }
}

void cb_spring_push_forces(const cb_spring_push *p, const double *x, int e0, int e1, int energy) {
  if (energy) spring_push_range((const spring_term *)p->t, x, e0, e1);
  else spring_push_range_noenergy((const spring_term *)p->t, x, e0, e1);
}

int cb_spring_term_alloc(const cb_model *m, const char *label, int ns, const int *ends, double k, cb_term **out) {
  *out = NULL;
  if (!(k >= 0) || !isfinite(k)) return cb_fail("%s springs: stiffness must be >= 0, got %g", label, k);
  spring_term *s = cb_calloc(1, sizeof *s);
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
  spring_schedule(s);
  if (spring_push_setup(s)) {
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
  spring_term *s = (spring_term *)t;
  free(s->ck);
  s->ck = NULL;
  spring_schedule(s); /* linear springs: streamed if sorted */
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
  const spring_term *s = (const spring_term *)t;
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
  return t && t->type == &cb_term_spring_type && ((const spring_term *)t)->ck;
}

int cb_spring_term_springs(const cb_term *t, int *ns, const int **ends, const double **rest, double *k) {
  if (!t || t->type != &cb_term_spring_type) return cb_fail("term '%s' is not a spring term", t ? t->label : "(null)");
  const spring_term *s = (const spring_term *)t;
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
