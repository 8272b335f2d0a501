/* The nonlinear iterations' kernel (internal to lib/core): what the spring
 * and gravity terms expose, beyond the term interface, so that jacobi-nl,
 * chebyshev-nl and pd can fuse the gradient, the objective and the update
 * into one pass over the vertices (integrator_nljacobi.c, integrator_pd.c)
 * with the terms' own arithmetic, in the terms' own order. It lives in the
 * energy room, below the integrators that call it, because the spring term's
 * own energy() runs it too: the spring parts are in nl_kernel.c (over the
 * term's state, spring_state.h), the gravity accessor in energy_gravity.c. */
#ifndef CB_NL_KERNEL_H
#define CB_NL_KERNEL_H

#include <stdint.h>
#include <string.h>

#include <clothbench/energy.h>

/* A spring term's springs as structure of arrays, and each vertex's springs:
 * inc[off[v] .. off[v+1]) = 2e + side, e increasing (side 0: v = ei[e], 1: v = ej[e]). */
typedef struct {
  int ns, nv;
  const int *ei, *ej;
  const double *rest;
  double k;
  const int *off, *inc;
} cb_spring_layout;

int cb_spring_term_layout(const cb_term *t, cb_spring_layout *out);

/* The per-spring results of one kernel pass (cb_spring_term_forces): f =
 * dE/dx_i of each spring and its energy, four blocks of R (x, y, z, E).
 *
 * Streamed (sorted linear springs, the common case): the blocks are a ring
 * of R springs (a power of two) and inc holds each spring's place in it
 * (e mod R); the forces are computed a chunk of vertices ahead of the
 * gather (cb_spring_gather_upto before the gather of each chunk of
 * CB_SPRING_CHUNK vertices, in order), so the scratch stays in L1/L2
 * instead of going through L3 (32 bytes a spring written and read again:
 * 1.6 MB at 129^2, more than the rest of the iteration's arrays together).
 * cb_spring_term_alloc sizes R from that schedule so that no spring a
 * gather reads has been overwritten. Otherwise (unsorted springs, Choi-Ko)
 * R = ns and every spring's forces are computed at once. */
enum { CB_SPRING_CHUNK = 64 };
typedef struct {
  int ns, R;
  int sorted; /* springs sorted by their first end (ei nondecreasing): the gather can sum E in spring order */
  int split;  /* every vertex lists its springs as second end before those as first end: mid splits them */
  const int *off, *mid, *inc;
  const double *f;
  int done;         /* forces computed for the springs < done */
  const int *need;  /* nv: forces needed for the springs < need[v] before vertex v's gather (nondecreasing) */
  const cb_term *t; /* the term and the x of the pass */
  const double *x;
} cb_spring_gather;

/* One pass over the springs at x (no gradient yet): sets up g; the forces
 * and energies go into the term's scratch, all of them now, or (streamed)
 * chunk by chunk through cb_spring_gather_upto. */
void cb_spring_term_forces(const cb_term *t, const double *x, cb_spring_gather *g);

/* Before the gathers of the vertices [v0, v1) (v0 = 0, CB_SPRING_CHUNK, ...; v1 = min(v0 + CB_SPRING_CHUNK, nv)). */
void cb_spring_gather_compute(cb_spring_gather *g, int need);
static inline void cb_spring_gather_upto(cb_spring_gather *g, int v1) {
  if (g->need[v1 - 1] > g->done) cb_spring_gather_compute(g, g->need[v1 - 1]);
}

/* g += vertex v's share of the spring term's gradient, in spring order:
 * exactly what the term's energy() adds to grad + 3v. If g->sorted, *E also
 * gets the energies of the springs whose first end is v (else it is unchanged): called for v = 0,
 * 1, ..., nv-1 from *E = 0 this sums E_e in spring order, bit for bit the
 * term's energy (its summation order). Each chunk's gathers come after its
 * cb_spring_gather_upto. */
static inline __attribute__((always_inline)) void cb_spring_gather_add(const cb_spring_gather *g, int v, double *gx,
                                                                       double *gy, double *gz, double *E) {
  const double *fx = g->f, *fy = g->f + g->R, *fz = g->f + 2 * (size_t)g->R, *en = g->f + 3 * (size_t)g->R;
  double ax = *gx, ay = *gy, az = *gz, ae = *E;
  if (g->split && g->sorted) { /* the common case (a mesh's edges): -f_e of the springs ending at v, then +f_e, E_e */
    int q = g->off[v], qm = g->mid[v], q1 = g->off[v + 1];
    for (; q < qm; q++) {
      int e = g->inc[q] >> 1;
      ax -= fx[e]; /* + (-f_e) exactly */
      ay -= fy[e];
      az -= fz[e];
    }
    for (; q < q1; q++) {
      int e = g->inc[q] >> 1;
      ax += fx[e];
      ay += fy[e];
      az += fz[e];
      ae += en[e];
    }
  } else {
    for (int q = g->off[v]; q < g->off[v + 1]; q++) {
      int e = g->inc[q] >> 1, side = g->inc[q] & 1;
      double sg = side ? -1.0 : 1.0; /* -f_e exactly */
      ax += sg * fx[e];
      ay += sg * fy[e];
      az += sg * fz[e];
      if (g->sorted) ae += side ? 0.0 : en[e]; /* + 0.0 is exact: a sum from +0 is never -0 */
    }
  }
  *gx = ax;
  *gy = ay;
  *gz = az;
  *E = ae;
}

/* The energy sum of the last cb_spring_term_forces, in spring order (when
 * not g->sorted: then never streamed, R = ns). */
static inline double cb_spring_gather_energy(const cb_spring_gather *g) {
  const double *en = g->f + 3 * (size_t)g->R;
  double E = 0.0;
  for (int e = 0; e < g->ns; e++) E += en[e];
  return E;
}

/* The push kernel (jacobi-nl and chebyshev-nl's fused pass): for linear springs sorted by their first end
 * with ei[e] < ej[e] (a mesh's edges), vertex v's springs as first end are the contiguous e in
 * [first[v], first[v+1]), and every spring that ends at v comes before them. So, with the vertices in
 * order, each vertex can take its -f_e from an accumulator that the earlier vertices' springs pushed
 * them into (acc[ej] -= f_e, in spring order, from 0) and then add its own +f_e: the same numbers added
 * in the same order as the gather (cb_spring_gather_add), without its incidence lists. The accumulator
 * is a ring of M vertices (a power of two above the largest ej - ei): 32 M bytes, in L1 on a grid.
 * The forces of a chunk of CB_SPRING_CHUNK vertices' springs are computed at once (vectorised, from x4:
 * cb_spring_push_positions, a chunk ahead) into f by cb_spring_push_forces, four doubles a spring
 * (x, y, z, E), so that the vertex loop moves a spring's force, an accumulator's entry (x, y, z and a
 * lane it ignores) and a vertex's update as 4-vectors (cb_v4d): lane by lane, the same operations as
 * three scalar ones. f, acc and x4 start at a cache line (cb_calloc_aligned). */
typedef struct {
  int nv, ns, M, cap;
  const int *first, *slot; /* slot[e]: where spring e's -f_e goes in acc, 4 (ej[e] mod M) */
  double *f;               /* 4 cap: spring first[v0] + q at 4q */
  double *acc;             /* 4 M, zero between passes */
  double *x4;              /* 4 nv: x padded to four doubles (x, y, z, 0), filled by cb_spring_push_positions */
  const cb_term *t;
} cb_spring_push;

/* The kernel's loops are compiled twice on x86-64 with GCC, for AVX2 (without FMA, so every product and
 * sum rounds as in the SSE2 copy: the same bits) and the default, and the loader picks the one the CPU
 * runs. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CB_KERNEL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define CB_KERNEL_CLONES
#endif

/* Four doubles as one value (GCC's and clang's vector extension): +, - and * act lane by lane with IEEE
 * rounding, as on four doubles; compiled to AVX where the function is built for it, else to SSE2 pairs.
 * Loaded and stored through memcpy (any alignment, no aliasing through a cast). */
typedef double cb_v4d __attribute__((vector_size(4 * sizeof(double))));
typedef uint64_t cb_v4u __attribute__((vector_size(4 * sizeof(uint64_t)))); /* their bits */
static inline __attribute__((always_inline)) void cb_v4d_get(cb_v4d *v, const double *p) { memcpy(v, p, sizeof *v); }
static inline __attribute__((always_inline)) void cb_v4d_put(double *p, const cb_v4d *v) { memcpy(p, v, sizeof *v); }

/* 1 and p filled if the term's springs allow the push kernel, else 0. */
int cb_spring_term_push(const cb_term *t, cb_spring_push *p);
/* p->x4 = x (padded) at the vertices [v0, v1): before the forces of springs that reach them. */
void cb_spring_push_positions(const cb_spring_push *p, const double *x, int v0, int v1);
/* The forces of the springs [e0, e1) at x (from p->x4, which must hold their ends) into p->f at 4 (e - e0)
 * (e1 - e0 <= p->cap), and their energies unless energy is 0 (then lane 3 holds no energy: the springs
 * done four at a time leave c_e * 0 there). */
void cb_spring_push_forces(const cb_spring_push *p, const double *x, int e0, int e1, int energy);

/* The gravity term's acceleration g (E = -sum_i m_i g . x_i). */
int cb_gravity_term_vector(const cb_term *t, double g[3]);

#endif
