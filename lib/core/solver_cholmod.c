/* CHOLMOD sparse Cholesky (SuiteSparse).
 *
 * analyze: cholmod_analyze on the fixed pattern (fill-reducing ordering and
 *          symbolic factorisation), once per run.
 * factor:  cholmod_factorize, once per Newton iteration. The factor is kept in
 *          LL' form (Common->final_ll) and a non-positive pivot is reported as
 *          CB_NOT_SPD with the failing column in L->minor, never a crash.
 * solve:   cholmod_solve2 into workspaces allocated on the first solve, so
 *          later solves do not allocate.
 * Our matrix stores both triangles; with stype = +1 CHOLMOD reads the upper
 * one, straight from our arrays without a copy. */
#include <cholmod.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/solver.h>
#include <clothbench/status.h>

typedef struct {
  cholmod_common c;
  cholmod_factor *L;
  cholmod_dense *X, *Y, *E;
  double *work; /* residual */
} cholmod_work;

static cholmod_sparse wrap(const cb_sparse *A) {
  cholmod_sparse s;
  memset(&s, 0, sizeof s);
  s.nrow = s.ncol = (size_t)A->n;
  s.nzmax = (size_t)A->nnz;
  s.p = A->colp;
  s.i = A->rowi;
  s.x = A->val;
  s.stype = 1; /* symmetric, upper triangle used */
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

static int ch_alloc(cb_solver *s, int n) {
  cholmod_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  w->work = cb_malloc((size_t)n, sizeof(double));
  if (!w->work) { free(w); return CB_ENOMEM; }
  cholmod_start(&w->c);
  w->c.print = 0;            /* statuses are ours to report */
  w->c.error_handler = NULL;
  w->c.final_ll = 1;         /* LL': a non-positive pivot is a failure */
  s->work = w;
  return CB_OK;
}

static int ch_analyze(cb_solver *s, const cb_sparse *A) {
  cholmod_work *w = s->work;
  cholmod_sparse As = wrap(A);
  if (w->L) cholmod_free_factor(&w->L, &w->c);
  w->L = cholmod_analyze(&As, &w->c);
  if (!w->L) return cb_fail_status(CB_ENOMEM, "cholmod_analyze failed (status %d)", w->c.status);
  return CB_OK;
}

static int ch_factor(cb_solver *s, const cb_sparse *A) {
  cholmod_work *w = s->work;
  if (!w->L) return cb_fail("cholmod: factor before analyze");
  cholmod_sparse As = wrap(A);
  w->c.status = CHOLMOD_OK;
  cholmod_factorize(&As, w->L, &w->c);
  s->stats.factor_nnz = w->c.lnz;
  if (w->c.status == CHOLMOD_NOT_POSDEF || w->L->minor < w->L->n)
    return cb_fail_status(CB_NOT_SPD, "cholmod: matrix not positive definite (column %zu)", (size_t)w->L->minor);
  if (w->c.status < CHOLMOD_OK) return cb_fail_status(CB_ENOMEM, "cholmod_factorize failed (status %d)", w->c.status);
  return CB_OK;
}

static int ch_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  cholmod_work *w = s->work;
  if (!w->L || w->L->minor < w->L->n) return cb_fail_status(CB_NOT_SPD, "cholmod: no valid factor");
  cholmod_dense B;
  memset(&B, 0, sizeof B);
  B.nrow = B.d = (size_t)A->n;
  B.ncol = 1;
  B.nzmax = (size_t)A->n;
  B.x = (void *)b;
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, w->L, &B, NULL, &w->X, NULL, &w->Y, &w->E, &w->c))
    return cb_fail_status(CB_ENOMEM, "cholmod_solve2 failed (status %d)", w->c.status);
  memcpy(x, w->X->x, (size_t)A->n * sizeof(double));
  s->stats.iters = 1;
  s->stats.rel_residual = cb_relative_residual(A, b, x, w->work);
  if (s->stats.history && s->params.history_cap > 0) {
    s->stats.history[0] = s->stats.rel_residual;
    s->stats.history_len = 1;
  }
  return CB_OK;
}

static void ch_free(cb_solver *s) {
  cholmod_work *w = s->work;
  if (!w) return;
  cholmod_free_factor(&w->L, &w->c);
  cholmod_free_dense(&w->X, &w->c);
  cholmod_free_dense(&w->Y, &w->c);
  cholmod_free_dense(&w->E, &w->c);
  cholmod_finish(&w->c);
  free(w->work);
  free(w);
}

const cb_solver_type cb_solver_cholmod = {"cholmod", CB_SOLVER_DIRECT, ch_alloc, ch_analyze, ch_factor, ch_solve, ch_free};
