/* Symmetric block Gauss-Seidel (`sgs`) with one 3x3 block per vertex: a
 * forward sweep over the block rows, then a backward sweep, each block solved
 * exactly with its diagonal block (Saad, "Iterative Methods for Sparse Linear
 * Systems", 2nd ed., 2003, ch. 4.1: block SSOR with omega = 1). With
 * A = L + B + L^T (B the block diagonal, L the strictly lower block triangle):
 *
 *   forward:   for i = 0 .. nblk-1:   x_i <- B_ii^-1 (b_i - sum_{j != i} A_ij x_j)
 *   backward:  for i = nblk-1 .. 0:   x_i <- B_ii^-1 (b_i - sum_{j != i} A_ij x_j)
 *   (x_j: the newest value, so the forward sweep solves (B + L) x' = b - L^T x)
 *   r <- b - A x;  stop if |r| / |b| <= tol (solver_iterative.h)
 *
 * For SPD A each sweep converges (block Gauss-Seidel, the Ostrowski-Reich
 * theorem), so SGS needs neither a weight nor a spectral estimate; its
 * preconditioner M = (B + L) B^-1 (B + L^T) is symmetric, which makes it the
 * usual smoother and CG preconditioner.
 *
 * factor() Cholesky-factors every diagonal block, B_ii = L_i L_i^T; a block
 * that is not positive definite is CB_NOT_SPD (A is then not SPD). solve()
 * walks block column i of the symmetric CSC storage as block row i. One
 * iteration costs about three matrix-vector products (two sweeps and the
 * residual of the stopping test). */
#include <math.h>
#include <stdlib.h>

#include "solver_iterative.h"

typedef struct {
  double *chol; /* 6 per block: L_i row by row, with reciprocal diagonal: 1/l00 l10 1/l11 l20 l21 1/l22 */
  double *r;    /* residual b - A x */
} sgs_work;

static void sgs_free(cb_solver *s) {
  sgs_work *w = s->work;
  if (!w) return;
  free(w->chol);
  free(w->r);
  free(w);
  s->work = NULL;
}

static int sgs_alloc(cb_solver *s, int n) {
  sgs_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  s->work = w;
  w->chol = cb_malloc((size_t)(n / 3) * 6 + 1, sizeof(double));
  w->r = cb_malloc((size_t)n, sizeof(double));
  if (!w->chol || !w->r) {
    sgs_free(s);
    return CB_ENOMEM;
  }
  return CB_OK;
}

/* B = L L^T for a symmetric 3x3 block (entry (r, c) at a[3r + c]); L row by
 * row into l, its diagonal as reciprocals (the sweeps multiply instead of
 * divide: the block solves are a dependency chain). Returns -1 if B is not
 * positive definite. */
static int cholesky3(const double a[9], double l[6]) {
  double d0 = a[0];
  if (!(d0 > 0)) return -1;
  double l00 = sqrt(d0);        /* l00 = sqrt(a00) */
  double l10 = a[3] / l00;      /* l10 = a10 / l00 */
  double d1 = a[4] - l10 * l10; /* a11 - l10^2 */
  if (!(d1 > 0)) return -1;
  double l11 = sqrt(d1);
  double l20 = a[6] / l00;               /* l20 = a20 / l00 */
  double l21 = (a[7] - l20 * l10) / l11; /* l21 = (a21 - l20 l10) / l11 */
  double d2 = a[8] - l20 * l20 - l21 * l21;
  if (!(d2 > 0)) return -1;
  double l22 = sqrt(d2);
  l[0] = 1 / l00;
  l[1] = l10;
  l[2] = 1 / l11;
  l[3] = l20;
  l[4] = l21;
  l[5] = 1 / l22;
  return 0;
}

static int sgs_factor(cb_solver *s, const cb_sparse *A) {
  sgs_work *w = s->work;
  for (int b = 0; b < A->nblk; b++) {
    int slot, stride;
    if (cb_sparse_block_slot(A, b, b, &slot, &stride) < 0) return cb_fail("sgs: diagonal block %d missing", b);
    double blk[9];
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) blk[3 * r + c] = A->val[slot + c * stride + r];
    if (cholesky3(blk, w->chol + 6 * b))
      return cb_fail_status(CB_NOT_SPD, "sgs: diagonal block %d is not positive definite", b);
  }
  return CB_OK;
}

/* x_i <- B_ii^-1 (b_i - sum_{j != i} A_ij x_j), with the newest x_j. Block
 * column i is block row i (A is symmetric): entry (c, r) of block (j, i),
 * val[slot + c*stride + r] (c the column of block i), is A(3i+c, 3j+r). */
static inline void relax_block(const cb_sparse *A, const double *chol, int i, const double *b, double *x) {
  int k0 = A->bcolp[i], nb = A->bcolp[i + 1] - k0, base = A->colp[3 * i], stride = 3 * nb;
  double s0 = b[3 * i], s1 = b[3 * i + 1], s2 = b[3 * i + 2];
  for (int k = 0; k < nb; k++) {
    int j = A->brow[k0 + k];
    if (j == i) continue;
    const double *v = A->val + base + 3 * k, *xj = x + 3 * j;
    s0 -= v[0] * xj[0] + v[1] * xj[1] + v[2] * xj[2]; /* s_c -= sum_r A(3i+c, 3j+r) x_j[r] */
    s1 -= v[stride] * xj[0] + v[stride + 1] * xj[1] + v[stride + 2] * xj[2];
    s2 -= v[2 * stride] * xj[0] + v[2 * stride + 1] * xj[1] + v[2 * stride + 2] * xj[2];
  }
  const double *l = chol + 6 * i;
  double y0 = s0 * l[0]; /* L y = s (l[0], l[2], l[5]: 1 / diagonal) */
  double y1 = (s1 - l[1] * y0) * l[2];
  double y2 = (s2 - l[3] * y0 - l[4] * y1) * l[5];
  double *xi = x + 3 * i;
  double x2 = y2 * l[5]; /* L^T x_i = y */
  double x1 = (y1 - l[4] * x2) * l[2];
  xi[0] = (y0 - l[1] * x1 - l[3] * x2) * l[0];
  xi[1] = x1;
  xi[2] = x2;
}

static int sgs_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  sgs_work *w = s->work;
  int n = A->n, status = CB_NOT_CONVERGED;
  double bnorm = 0;
  for (int i = 0; i < n; i++) bnorm += b[i] * b[i];
  bnorm = sqrt(bnorm);
  double r0 = cb_sparse_residual(A, b, x, w->r);
  if (cb_iter_stop(s, 0, r0, r0, bnorm, x, &status)) return status;
  status = CB_NOT_CONVERGED;
  for (int k = 0; k < s->params.max_iters; k++) {
    for (int i = 0; i < A->nblk; i++) relax_block(A, w->chol, i, b, x);      /* forward sweep */
    for (int i = A->nblk - 1; i >= 0; i--) relax_block(A, w->chol, i, b, x); /* backward sweep */
    double rn = cb_sparse_residual(A, b, x, w->r);                           /* r = b - A x */
    if (cb_iter_stop(s, k + 1, rn, r0, bnorm, x, &status)) return status;
    status = CB_NOT_CONVERGED;
  }
  return status;
}

const cb_solver_type cb_solver_sgs = {
    .name = "sgs",
    .flags = 0,
    .alloc = sgs_alloc,
    .factor = sgs_factor,
    .solve = sgs_solve,
    .free = sgs_free,
};
