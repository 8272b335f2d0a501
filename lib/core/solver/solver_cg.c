/* Conjugate gradients, plain (`cg`) and preconditioned with the inverses of
 * the 3x3 diagonal blocks (`pcg`, block Jacobi: one block per vertex).
 *
 *   r = b - A x;  z = P^-1 r;  p = z
 *   repeat:  q = A p;  if p.q <= 0: breakdown (A is not positive definite)
 *            a = (r.z)/(p.q);  x += a p;  r -= a q
 *            stop if |r|/|b| <= tol
 *            z = P^-1 r;  beta = (r.z)_new/(r.z)_old;  p = z + beta p
 *
 * A breakdown p^T A p <= 0 is reported as CB_INDEFINITE, except p^T A p = 0
 * once |r| <= eps |b|: the recursion went below round-off (solver.tol below
 * what double precision reaches) and p underflowed, which says nothing of A;
 * that stops as CB_NOT_CONVERGED, with the reason. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "solver_iterative.h"
#include "vec.h"

typedef struct {
  int precond;
  double *binv; /* 9 per block: inverse of the diagonal block (pcg) */
  double *r, *z, *p, *q;
  cb_sparse_sym S; /* upper blocks of A, refreshed by factor (the products read it) */
} cg_work;

static void cgw_free(cb_solver *s) {
  cg_work *w = s->work;
  if (!w) return;
  free(w->binv);
  free(w->r);
  free(w->z);
  free(w->p);
  free(w->q);
  cb_sparse_sym_free(&w->S);
  free(w);
  s->work = NULL;
}

static int cgw_alloc(cb_solver *s, int n, int precond) {
  cg_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  s->work = w;
  w->precond = precond;
  w->r = cb_malloc((size_t)n, sizeof(double));
  w->z = precond ? cb_malloc((size_t)n, sizeof(double)) : NULL;
  w->p = cb_malloc((size_t)n, sizeof(double));
  w->q = cb_malloc((size_t)n, sizeof(double));
  w->binv = precond ? cb_malloc((size_t)3 * n, sizeof(double)) : NULL;
  if (!w->r || !w->p || !w->q || (precond && (!w->z || !w->binv))) {
    cgw_free(s);
    return CB_ENOMEM;
  }
  return CB_OK;
}

static int cg_alloc(cb_solver *s, int n) { return cgw_alloc(s, n, 0); }
static int pcg_alloc(cb_solver *s, int n) { return cgw_alloc(s, n, 1); }

static int cg_analyze(cb_solver *s, const cb_sparse *A) {
  cg_work *w = s->work;
  cb_sparse_sym_free(&w->S);
  return cb_sparse_sym_alloc(&w->S, A);
}

/* Inverse of a symmetric positive definite 3x3 block by its Cholesky factor. */
static int inverse3_spd(const double a[9], double out[9]) {
  double l00 = a[0];
  if (!(l00 > 0)) return -1;
  l00 = sqrt(l00);
  double l10 = a[3] / l00, l20 = a[6] / l00;
  double d1 = a[4] - l10 * l10;
  if (!(d1 > 0)) return -1;
  double l11 = sqrt(d1), l21 = (a[7] - l20 * l10) / l11;
  double d2 = a[8] - l20 * l20 - l21 * l21;
  if (!(d2 > 0)) return -1;
  double l22 = sqrt(d2);
  /* L^-1 (lower triangular), then A^-1 = L^-T L^-1 */
  double m00 = 1 / l00, m11 = 1 / l11, m22 = 1 / l22;
  double m10 = -l10 * m00 / l11, m21 = -l21 * m11 / l22, m20 = -(l20 * m00 + l21 * m10) / l22;
  double M[9] = {m00, 0, 0, m10, m11, 0, m20, m21, m22};
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      double v = 0;
      for (int k = 0; k < 3; k++) v += M[3 * k + r] * M[3 * k + c]; /* (L^-T L^-1)_rc = sum_k M_kr M_kc */
      out[3 * r + c] = v;
    }
  return 0;
}

static int cg_factor(cb_solver *s, const cb_sparse *A) {
  cg_work *w = s->work;
  if (!w->S.bcolp) { /* analyze was skipped: build the pattern now */
    int st = cb_sparse_sym_alloc(&w->S, A);
    if (st) return st;
  }
  cb_sparse_sym_fill(&w->S, A);
  if (!w->precond) return CB_OK;
  for (int b = 0; b < A->nblk; b++) {
    int slot, stride;
    if (cb_sparse_block_slot(A, b, b, &slot, &stride) < 0) return cb_fail("pcg: diagonal block %d missing", b);
    double blk[9];
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) blk[3 * r + c] = A->val[slot + c * stride + r];
    if (inverse3_spd(blk, w->binv + 9 * b))
      return cb_fail_status(CB_NOT_SPD, "pcg: diagonal block %d is not positive definite", b);
  }
  return CB_OK;
}

static void apply_precond(const cg_work *w, int nblk, const double *r, double *z) {
  for (int b = 0; b < nblk; b++) {
    const double *m = w->binv + 9 * b, *rb = r + 3 * b;
    double *zb = z + 3 * b;
    zb[0] = m[0] * rb[0] + m[1] * rb[1] + m[2] * rb[2]; /* z_b = B_b^-1 r_b */
    zb[1] = m[3] * rb[0] + m[4] * rb[1] + m[5] * rb[2];
    zb[2] = m[6] * rb[0] + m[7] * rb[1] + m[8] * rb[2];
  }
}

static int cg_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  cg_work *w = s->work;
  int n = A->n, status = CB_NOT_CONVERGED;
  double bnorm = sqrt(cb_vec_dot(n, b, b));
  double r0 = cb_sparse_sym_residual(&w->S, b, x, w->r);
  if (cb_iter_stop(s, 0, r0, r0, bnorm, x, &status)) return status;
  status = CB_NOT_CONVERGED;
  double *z = w->precond ? w->z : w->r;
  if (w->precond) apply_precond(w, A->nblk, w->r, z);
  memcpy(w->p, z, (size_t)n * sizeof(double));
  double rz = cb_vec_dot(n, w->r, z), rnorm = r0;
  for (int k = 0; k < s->params.max_iters; k++) {
    cb_sparse_sym_matvec(&w->S, w->p, w->q); /* q = A p */
    double pq = cb_vec_dot(n, w->p, w->q);
    if (!(pq > 0)) {
      s->stats.iters = k;
      if (!isfinite(pq)) return cb_fail_status(CB_DIVERGED, "%s: NaN at iteration %d", s->type->name, k + 1);
      if (pq == 0 && rnorm <= DBL_EPSILON * (bnorm > 0 ? bnorm : 1)) /* p underflowed with r: round-off, not A */
        return cb_fail_status(CB_NOT_CONVERGED,
                              "%s: not converged: stopped at round-off at iteration %d, |r|/|b| = %.3g (the recursive "
                              "residual fell below double precision, p^T A p underflowed to 0); solver.tol = %g is "
                              "below what double precision reaches",
                              s->type->name, k + 1, bnorm > 0 ? rnorm / bnorm : rnorm, s->params.tol);
      return cb_fail_status(CB_INDEFINITE,
                            "%s: breakdown p^T A p = %g <= 0 at iteration %d (A is not positive definite)",
                            s->type->name, pq, k + 1);
    }
    double a = rz / pq, rr = 0;
    for (int i = 0; i < n; i++) {
      x[i] += a * w->p[i];    /* x += a p */
      w->r[i] -= a * w->q[i]; /* r -= a A p */
      rr += w->r[i] * w->r[i];
    }
    rnorm = sqrt(rr);
    if (cb_iter_stop(s, k + 1, rnorm, r0, bnorm, x, &status)) return status;
    status = CB_NOT_CONVERGED;
    if (w->precond) apply_precond(w, A->nblk, w->r, z);
    double rz_new = w->precond ? cb_vec_dot(n, w->r, z) : rr;
    double beta = rz_new / rz;
    rz = rz_new;
    for (int i = 0; i < n; i++) w->p[i] = z[i] + beta * w->p[i]; /* p = z + beta p */
  }
  return status;
}

const cb_solver_type cb_solver_cg = {
    .name = "cg",
    .flags = 0,
    .alloc = cg_alloc,
    .analyze = cg_analyze,
    .factor = cg_factor,
    .solve = cg_solve,
    .free = cgw_free,
};
const cb_solver_type cb_solver_pcg = {
    .name = "pcg",
    .flags = 0,
    .alloc = pcg_alloc,
    .analyze = cg_analyze,
    .factor = cg_factor,
    .solve = cg_solve,
    .free = cgw_free,
};
