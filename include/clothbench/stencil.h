/* The blocks of a k-vertex stencil (a spring has 2 vertices, a triangle 3, a
 * hinge 4) bound to the fixed sparsity pattern, once (stencil.c).
 *
 * An element e joins the vertices vert[k e .. k e + k - 1]. Its Hessian is a
 * dense 3k x 3k row-major matrix H_e (block (a, b) couples vertex a with
 * vertex b of the element) and its gradient a 3k vector g_e. Binding looks up
 * the slot of each of the k x k 3x3 blocks in the matrix (-1 when either
 * vertex is pinned, so eliminated rows and columns are skipped); assembly
 * then only adds numbers:
 *   A(fi(v_a), fi(v_b)) += H_e(a, b)     for the free vertices of e
 *   grad(v_a) += g_e(a)                  for every vertex (pinned ones too)
 * Every term that stores slot indices uses this one helper: a general
 * element adds its dense H_e (cb_stencil_add_hessian); one whose blocks are
 * multiples of a single 3x3 matrix may add them block by block
 * (cb_stencil_add_block), as the spring does. */
#ifndef CB_STENCIL_H
#define CB_STENCIL_H

#include "sparse.h"

typedef struct cb_stencil {
  int k;                 /* vertices per element */
  int ne;                /* elements */
  const int *vert;       /* k*ne vertex indices (not owned: the term keeps them) */
  const int *free_index; /* nv: block index of each vertex, -1 if pinned (the model's) */
  int *slot;             /* 2*k*k*ne: (slot, stride) of block (a, b) of element e at 2 ((e k + a) k + b) */
} cb_stencil;

/* Fails on k < 1 or ne < 0. */
int cb_stencil_init(cb_stencil *s, int k, int ne, const int *vert, const int *free_index);
void cb_stencil_free(cb_stencil *s);

/* Declares every block pair of every element (pinned vertices are ignored). */
int cb_stencil_pattern(const cb_stencil *s, cb_pattern *p);

/* Looks up the slots in the finalised matrix; fails, naming the element and
 * label, if a block between two free vertices is missing. */
int cb_stencil_bind(cb_stencil *s, const cb_sparse *A, const char *label);

/* Nonzero if element e has a free vertex (else its Hessian adds nothing). */
static inline int cb_stencil_active(const cb_stencil *s, int e) {
  const int *q = s->slot + 2 * (size_t)e * s->k * s->k;
  for (int a = 0; a < s->k; a++)
    if (q[2 * (a * s->k + a)] >= 0) return 1;
  return 0;
}

/* val += H_e over the free-free blocks of element e (H_e row-major 3k x 3k). */
static inline void cb_stencil_add_hessian(const cb_stencil *s, int e, const double *H, double *val) {
  int k = s->k, n = 3 * k;
  const int *q = s->slot + 2 * (size_t)e * k * k;
  for (int a = 0; a < k; a++)
    for (int b = 0; b < k; b++, q += 2) {
      int slot = q[0], stride = q[1];
      if (slot < 0) continue;
      for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) val[slot + c * stride + r] += H[(3 * a + r) * n + 3 * b + c]; /* entry (r, c) */
    }
}

/* val += scale * B into block (a, b) of element e (B row-major 3x3; nothing
 * if a vertex is pinned): for elements whose blocks are multiples of one 3x3
 * matrix, such as the spring's [H -H; -H H], without forming the 3k x 3k one. */
static inline void cb_stencil_add_block(const cb_stencil *s, int e, int a, int b, const double B[9], double scale,
                                        double *val) {
  const int *q = s->slot + 2 * (((size_t)e * s->k + a) * s->k + b);
  cb_sparse_add_block(val, q[0], q[1], B, scale);
}

/* grad += g_e at the element's vertices (grad is 3*nv; pinned vertices too). */
static inline void cb_stencil_add_gradient(const cb_stencil *s, int e, const double *g, double *grad) {
  const int *v = s->vert + (size_t)e * s->k;
  for (int a = 0; a < s->k; a++)
    for (int c = 0; c < 3; c++) grad[3 * v[a] + c] += g[3 * a + c];
}

#endif
