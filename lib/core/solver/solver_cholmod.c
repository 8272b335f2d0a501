/* CHOLMOD sparse Cholesky (SuiteSparse).
 *
 * analyze: cholmod_analyze on the fixed pattern (fill-reducing ordering and
 *          symbolic factorisation), once per run.
 * factor:  cholmod_factorize, once per Newton iteration. The factor is kept in
 *          LL' form (Common->final_ll) and a non-positive pivot is reported as
 *          CB_NOT_SPD with the failing column in L->minor, never a crash.
 * solve:   cholmod_solve2 into workspaces allocated on the first solve, so
 *          later solves do not allocate; solve_n takes several right-hand
 *          sides as one dense n x nrhs block (pd and lbfgs solve x, y and z
 *          with the n x n matrix P at once). With solver.residual = 1 (the
 *          default) each solve also computes |b - Ax|/|b|, one product with A.
 * Our matrix stores both triangles. With solver.storage = full CHOLMOD
 * reads it straight from our arrays (stype = +1: the upper triangle is used,
 * the lower skipped); with `upper` it gets a copy of the upper triangle
 * (pattern built at analyse, values copied at every factorisation), which
 * analyses and factorises faster (bench/bench_core.c measures both).
 * solver.ordering and solver.nrelax set Common->method and Common->nrelax.
 * solver.denormals = flush (the default) runs factorize and solve with x86's
 * flush-to-zero and denormals-are-zero bits set on this thread: the fill of a
 * large factor decays into subnormal numbers (|x| < 2.2e-308; thousands in L at
 * 256^2), and each one costs the BLAS kernels a microcode assist. Flushing
 * them moves the factor by less than 1e-300 per entry. */
#include <cholmod.h>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/solver.h>
#include <clothbench/status.h>

/* The thread's floating-point control word, with FTZ and DAZ set if flush;
 * pass what it returns to denormals_restore. */
static unsigned denormals_begin(int flush) {
#if defined(__SSE2__)
  unsigned old = _mm_getcsr();
  if (flush) _mm_setcsr(old | 0x8040u); /* FTZ (bit 15) | DAZ (bit 6) */
  return old;
#else
  (void)flush;
  return 0;
#endif
}

static void denormals_restore(unsigned old) {
#if defined(__SSE2__)
  _mm_setcsr((_mm_getcsr() & ~0x8040u) | (old & 0x8040u)); /* the two modes back; exception flags kept */
#else
  (void)old;
#endif
}

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

typedef struct {
  cholmod_common c;
  cholmod_factor *L;
  cholmod_dense *X, *Y, *E;
  double *work; /* residual */
  /* storage = upper: CSC of the upper triangle, and for each of its entries
   * the index of the same entry in the full matrix */
  int *up, *ui, *usrc;
  double *ux;
} cholmod_work;

/* What CHOLMOD reads: the full arrays, or the upper copy with fresh values. */
static cholmod_sparse wrap_for(cholmod_work *w, const cb_sparse *A, int upper) {
  cholmod_sparse s = wrap(A);
  if (upper && w->up) {
    int nz = w->up[A->n];
    for (int q = 0; q < nz; q++) w->ux[q] = A->val[w->usrc[q]]; /* U(i,j) = A(i,j), i <= j */
    s.p = w->up;
    s.i = w->ui;
    s.x = w->ux;
    s.nzmax = (size_t)nz;
  }
  return s;
}

static int build_upper(cholmod_work *w, const cb_sparse *A) {
  free(w->up);
  free(w->ui);
  free(w->usrc);
  free(w->ux);
  int nz = 0;
  for (int j = 0; j < A->n; j++)
    for (int q = A->colp[j]; q < A->colp[j + 1]; q++) nz += A->rowi[q] <= j;
  w->up = cb_malloc((size_t)A->n + 1, sizeof(int));
  w->ui = cb_malloc((size_t)nz + 1, sizeof(int));
  w->usrc = cb_malloc((size_t)nz + 1, sizeof(int));
  w->ux = cb_malloc((size_t)nz + 1, sizeof(double));
  if (!w->up || !w->ui || !w->usrc || !w->ux) return CB_ENOMEM;
  nz = 0;
  for (int j = 0; j < A->n; j++) {
    w->up[j] = nz;
    for (int q = A->colp[j]; q < A->colp[j + 1]; q++)
      if (A->rowi[q] <= j) {
        w->ui[nz] = A->rowi[q];
        w->usrc[nz++] = q;
      }
  }
  w->up[A->n] = nz;
  return CB_OK;
}


static int ch_alloc(cb_solver *s, int n) {
  cholmod_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  w->work = cb_malloc((size_t)n, sizeof(double));
  if (!w->work) {
    free(w);
    return CB_ENOMEM;
  }
  cholmod_start(&w->c);
  const cb_solver_params *p = &s->params;
  for (int k = 0; k < 3; k++)
    if (p->nrelax[k] < 0 || (k && p->nrelax[k] < p->nrelax[k - 1])) {
      cholmod_finish(&w->c);
      free(w->work);
      free(w);
      return cb_fail("cholmod: solver.nrelax must be 3 non-decreasing counts >= 0, got %d %d %d", p->nrelax[0],
                     p->nrelax[1], p->nrelax[2]);
    }
  for (int k = 0; k < 3; k++) w->c.nrelax[k] = (size_t)p->nrelax[k];
  if (p->ordering != CB_ORDER_DEFAULT) { /* one method, no search over several */
    static const int method[] = {0, CHOLMOD_AMD, CHOLMOD_METIS, CHOLMOD_NESDIS};
    w->c.nmethods = 1;
    w->c.method[0].ordering = method[p->ordering];
    w->c.postorder = 1;
  }
  w->c.print = 0; /* statuses are ours to report */
  w->c.error_handler = NULL;
  w->c.final_ll = 1; /* LL': a non-positive pivot is a failure */
  s->work = w;
  return CB_OK;
}

static int ch_analyze(cb_solver *s, const cb_sparse *A) {
  cholmod_work *w = s->work;
  if (s->params.upper) {
    int st = build_upper(w, A);
    if (st) return st;
  }
  cholmod_sparse As = wrap_for(w, A, s->params.upper);
  if (w->L) cholmod_free_factor(&w->L, &w->c);
  w->L = cholmod_analyze(&As, &w->c);
  if (!w->L) return cb_fail_status(CB_ENOMEM, "cholmod_analyze failed (status %d)", w->c.status);
  return CB_OK;
}

static int ch_factor(cb_solver *s, const cb_sparse *A) {
  cholmod_work *w = s->work;
  if (!w->L) return cb_fail("cholmod: factor before analyze");
  cholmod_sparse As = wrap_for(w, A, s->params.upper);
  w->c.status = CHOLMOD_OK;
  unsigned csr = denormals_begin(s->params.flush_denormals);
  cholmod_factorize(&As, w->L, &w->c);
  denormals_restore(csr);
  s->stats.factor_nnz = w->c.lnz;
  s->stats.factor_flops = w->c.fl; /* set by the analysis for this pattern */
  if (w->c.status == CHOLMOD_NOT_POSDEF || w->L->minor < w->L->n)
    return cb_fail_status(CB_NOT_SPD, "cholmod: matrix not positive definite (column %zu)", (size_t)w->L->minor);
  if (w->c.status < CHOLMOD_OK) return cb_fail_status(CB_ENOMEM, "cholmod_factorize failed (status %d)", w->c.status);
  return CB_OK;
}

/* A X = B for nrhs columns in one cholmod_solve2 (one pass over L per triangular solve, the columns together). */
static int solve_cols(cb_solver *s, const cb_sparse *A, int nrhs, const double *b, double *x) {
  cholmod_work *w = s->work;
  if (!w->L || w->L->minor < w->L->n) return cb_fail_status(CB_NOT_SPD, "cholmod: no valid factor");
  cholmod_dense B;
  memset(&B, 0, sizeof B);
  B.nrow = B.d = (size_t)A->n;
  B.ncol = (size_t)nrhs;
  B.nzmax = (size_t)A->n * (size_t)nrhs;
  B.x = (void *)b;
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  unsigned csr = denormals_begin(s->params.flush_denormals);
  int solved = cholmod_solve2(CHOLMOD_A, w->L, &B, NULL, &w->X, NULL, &w->Y, &w->E, &w->c);
  denormals_restore(csr);
  if (!solved) return cb_fail_status(CB_ENOMEM, "cholmod_solve2 failed (status %d)", w->c.status);
  memcpy(x, w->X->x, (size_t)A->n * (size_t)nrhs * sizeof(double));
  s->stats.iters = 1;
  s->stats.rel_residual = NAN; /* solver.residual = 0: not computed */
  if (s->params.residual) {    /* the largest column's |b - A x|/|b| (a product with A per column) */
    double r = 0.0;
    for (int c = 0; c < nrhs; c++) {
      double rc = cb_relative_residual(A, b + (size_t)c * A->n, x + (size_t)c * A->n, w->work);
      if (!(rc <= r)) r = rc;
    }
    s->stats.rel_residual = r;
  }
  if (s->stats.history && s->params.history_cap > 0) {
    s->stats.history[0] = s->stats.rel_residual;
    s->stats.history_len = 1;
  }
  return CB_OK;
}

static int ch_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) { return solve_cols(s, A, 1, b, x); }

static int ch_solve_n(cb_solver *s, const cb_sparse *A, int nrhs, const double *b, double *x) {
  return solve_cols(s, A, nrhs, b, x);
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
  free(w->up);
  free(w->ui);
  free(w->usrc);
  free(w->ux);
  free(w);
}

const cb_solver_type cb_solver_cholmod = {
    .name = "cholmod",
    .flags = CB_SOLVER_DIRECT,
    .alloc = ch_alloc,
    .analyze = ch_analyze,
    .factor = ch_factor,
    .solve = ch_solve,
    .solve_n = ch_solve_n,
    .free = ch_free,
};
