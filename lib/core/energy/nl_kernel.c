/* The nonlinear iterations' spring kernel (nl_kernel.h): the passes over a
 * spring term's springs that jacobi-nl, chebyshev-nl and pd fuse into their
 * vertex loops (integrator_nljacobi.c, integrator_pd.c), and that the spring
 * term's own energy() runs too (energy_spring.c). It reads the term's arrays
 * and the math of one spring from spring_state.h, and knows nothing else of
 * the term (the entry points that check a term's type are energy_spring.c's),
 * so the term depends on the kernel and not the other way round. Every pass
 * adds the same numbers in the same order. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>

#include "nl_kernel.h"
#include "spring_state.h"

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
 * (nl_kernel.h, cb_spring_schedule), and loop 2 is folded into loop 3, so the
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
 * one-spring-at-a-time kernel (cb_spring_eval). The scratch makes a term
 * non-reentrant: one thread evaluates a term at a time (as everywhere here). */
/* Loop 1 is compiled twice on x86-64 with GCC (CB_KERNEL_CLONES, nl_kernel.h). */
/* Loop 1 for the springs [e0, e1), spring e's results at q = e - base (the caller keeps q inside the
 * scratch): lane a (x, y, z, E) at out[q * qs + a * ls]. The gather's layout is blocks of R (qs = 1, ls = R);
 * the push kernel's is four doubles a spring (qs = 4, ls = 1), where it does the springs that
 * spring_push_body leaves over, and energy 0 writes 0 as E. */
static inline __attribute__((always_inline)) void spring_forces_body(const cb_spring_state *s, const double *restrict x,
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
CB_KERNEL_CLONES static void spring_forces_range(const cb_spring_state *s, const double *restrict x, int e0, int e1,
                                                 int base, int R) {
  spring_forces_body(s, x, e0, e1, base, s->f, 1, (size_t)R, 1);
}
/* The push kernel's loop 1: four springs at a time as 4-vectors. Each end's position is one vector (x, y, z,
 * 0), their differences are transposed into dx, dy, dz of the four springs, and l, c and E are computed
 * lane by lane with the expressions of spring_forces_body; then spring s's force is c_s (dx, dy, dz, 0) of
 * its own difference, one vector store. The lane by lane operations round as the scalar ones: the same bits
 * (bench_nonlinear checks them against the old kernel). The springs left over go through spring_forces_body. */
static inline __attribute__((always_inline)) void spring_push_body(const cb_spring_state *s, const double *restrict x,
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
CB_KERNEL_CLONES static void spring_push_range(const cb_spring_state *s, const double *restrict x, int e0, int e1) {
  spring_push_body(s, x, e0, e1, 1);
}
CB_KERNEL_CLONES static void spring_push_range_noenergy(const cb_spring_state *s, const double *restrict x, int e0,
                                                        int e1) {
  spring_push_body(s, x, e0, e1, 0);
}

/* Every spring's forces at once (not streamed). */
static void spring_forces(const cb_spring_state *s, const double *restrict x) {
  const int ns = s->ns;
  spring_forces_range(s, x, 0, ns, 0, ns);
  if (!s->ck) return;
  double *restrict fx = s->f, *restrict fy = s->f + ns, *restrict fz = s->f + 2 * (size_t)ns,
                   *restrict en = s->f + 3 * (size_t)ns;
  for (int e = 0; e < ns; e++) { /* compressed Choi-Ko springs: cb_spring_eval's other branch */
    double d[3], c;
    double E = cb_spring_eval(s, e, x, d, &c);
    fx[e] = c * d[0];
    fy[e] = c * d[1];
    fz[e] = c * d[2];
    en[e] = E;
  }
}

/* Streamed: the springs [done, need) into the ring, at e mod R. */
void cb_spring_gather_compute(cb_spring_gather *g, int need) {
  const cb_spring_state *s = (const cb_spring_state *)g->t;
  const int R = g->R;
  for (int e0 = g->done; e0 < need;) {
    int base = e0 & ~(R - 1), e1 = base + R < need ? base + R : need; /* up to the ring's end */
    spring_forces_range(s, g->x, e0, e1, base, R);
    e0 = e1;
  }
  g->done = need;
}

void cb_spring_term_forces(const cb_term *t, const double *x, cb_spring_gather *g) {
  const cb_spring_state *s = (const cb_spring_state *)t;
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


/* The streamed schedule (nl_kernel.h), played once: need[v] (the last spring of vertices <= v, + 1), and the
 * ring: before chunk [v0, v1) gathers, the springs < need[v1 - 1] are computed, and it must still hold the
 * first spring (lo) of each vertex of the chunk. Streamed when sorted and linear and the ring is shorter
 * than ns. */
void cb_spring_schedule(cb_spring_state *s) {
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
int cb_spring_push_setup(cb_spring_state *s) {
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
  if (energy) spring_push_range((const cb_spring_state *)p->t, x, e0, e1);
  else spring_push_range_noenergy((const cb_spring_state *)p->t, x, e0, e1);
}
