/* The spring term's state (internal to lib/core/energy): shared by the term
 * (energy_spring.c: its energy, Hessian, elements, allocation) and the
 * nonlinear iterations' kernel over it (nl_kernel.c: the streamed schedule,
 * the gather and push passes), so that the kernel can live in a module of its
 * own and still read the springs in the term's own arrays. */
#ifndef CB_SPRING_STATE_H
#define CB_SPRING_STATE_H

#include <math.h>

#include <clothbench/energy.h>
#include <clothbench/stencil.h>

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
} cb_spring_state;

/* Energy of spring e at x and its gradient coefficient c: dE/dx_i = c x_ij,
 * x_ij = d (3 numbers, filled). */
static inline double cb_spring_eval(const cb_spring_state *s, int e, const double *x, double d[3], double *c) {
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

/* The kernel's set-up at allocation (nl_kernel.c): the streamed schedule (need, ring, rinc; again after
 * the response changes) and the push kernel's layout (first, acc, x4, i4, j4, slot: CB_ENOMEM if short). */
void cb_spring_schedule(cb_spring_state *s);
int cb_spring_push_setup(cb_spring_state *s);

#endif
