/* The projective-dynamics matrix (pd_matrix.h has the formula). */
#include "pd_matrix.h"

#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>

static int copy_pattern(const cb_sparse *A, cb_sparse *P) {
  memset(P, 0, sizeof *P);
  P->n = A->n;
  P->nnz = A->nnz;
  P->nblk = A->nblk;
  P->colp = cb_malloc((size_t)A->n + 1, sizeof(int));
  P->rowi = cb_malloc((size_t)A->nnz + 1, sizeof(int));
  P->val = cb_calloc((size_t)A->nnz + 1, sizeof(double));
  P->bcolp = cb_malloc((size_t)A->nblk + 1, sizeof(int));
  P->brow = cb_malloc((size_t)A->bcolp[A->nblk] + 1, sizeof(int));
  if (!P->colp || !P->rowi || !P->val || !P->bcolp || !P->brow) return CB_ENOMEM;
  memcpy(P->colp, A->colp, ((size_t)A->n + 1) * sizeof(int));
  memcpy(P->rowi, A->rowi, (size_t)A->nnz * sizeof(int));
  memcpy(P->bcolp, A->bcolp, ((size_t)A->nblk + 1) * sizeof(int));
  memcpy(P->brow, A->brow, (size_t)A->bcolp[A->nblk] * sizeof(int));
  return CB_OK;
}

/* Adds s I_3 to block (bi, bj) if it is in the pattern. */
static void add_identity(cb_sparse *P, int bi, int bj, double s) {
  static const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  int slot, stride;
  if (cb_sparse_block_slot(P, bi, bj, &slot, &stride) >= 0) cb_sparse_add_block(P->val, slot, stride, I3, s);
}

int cb_pd_matrix_build(const cb_scene *s, double dt, int with_constant, cb_sparse *P) {
  int st = copy_pattern(&s->sys.A, P);
  if (st) return st;
  if (with_constant && s->sys.hconst) memcpy(P->val, s->sys.hconst, (size_t)P->nnz * sizeof(double));
  const int *fi = s->free_index;
  for (int b = 0; b < s->model.nfree; b++) add_identity(P, b, b, s->mass[s->free_vertex[b]] / (dt * dt)); /* M/dt^2 */
  for (int t = 0; t < s->sys.nterms; t++) {
    int ns;
    const int *ends;
    const double *rest;
    double k;
    if (s->sys.terms[t]->type != cb_term_spring) continue;
    cb_spring_term_springs(s->sys.terms[t], &ns, &ends, &rest, &k);
    for (int e = 0; e < ns; e++) { /* k A_e A_e^T (x) I_3: +k on (i,i), (j,j); -k on (i,j), (j,i) */
      int bi = fi[ends[2 * e]], bj = fi[ends[2 * e + 1]];
      if (bi >= 0) add_identity(P, bi, bi, k);
      if (bj >= 0) add_identity(P, bj, bj, k);
      if (bi >= 0 && bj >= 0) {
        add_identity(P, bi, bj, -k);
        add_identity(P, bj, bi, -k);
      }
    }
  }
  return CB_OK;
}
