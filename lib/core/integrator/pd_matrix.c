/* The projective-dynamics matrix (pd_matrix.h has the formula). */
#include "pd_matrix.h"

#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

const char *const cb_pd_matrix_names[] = {"auto", "block", NULL};

const char *cb_global_path_name(int path) {
  static const char *const names[] = {"none", "scalar", "block"};
  return path >= 0 && path < 3 ? names[path] : NULL;
}

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

int cb_pd_matrix_is_kronecker(const cb_sparse *A, const double *val, int *bad) {
  if (bad) *bad = -1;
  for (int bj = 0; bj < A->nblk; bj++)
    for (int k = A->bcolp[bj]; k < A->bcolp[bj + 1]; k++) {
      int slot, stride;
      cb_sparse_block_slot(A, A->brow[k], bj, &slot, &stride);
      const double *b = val + slot; /* entry (r, c) at b[c stride + r] */
      double d = b[0];
      for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
          if (b[c * stride + r] != (r == c ? d : 0.0)) { /* block = d I_3 */
            if (bad) *bad = bj;
            return 0;
          }
    }
  return 1;
}

/* The scalar matrix's index of entry (i, j), or -1: a binary search in column j. */
static int scalar_slot(const cb_sparse *P, int i, int j) {
  int lo = P->colp[j], hi = P->colp[j + 1] - 1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2;
    if (P->rowi[mid] < i) lo = mid + 1;
    else if (P->rowi[mid] > i) hi = mid - 1;
    else return mid;
  }
  return -1;
}

static void scalar_add(cb_sparse *P, int i, int j, double v) {
  int q = scalar_slot(P, i, j);
  if (q >= 0) P->val[q] += v;
}

int cb_pd_matrix_build_scalar(const cb_scene *s, double dt, int with_constant, cb_sparse *P) {
  memset(P, 0, sizeof *P);
  const cb_sparse *A = &s->sys.A;
  if (s->model.nfree == 0) { /* an empty matrix */
    P->colp = cb_calloc(1, sizeof(int));
    P->rowi = cb_calloc(1, sizeof(int));
    P->val = cb_calloc(1, sizeof(double));
    return P->colp && P->rowi && P->val ? CB_OK : CB_ENOMEM;
  }
  const double *hc = with_constant ? s->sys.hconst : NULL;
  if (hc && !cb_pd_matrix_is_kronecker(A, hc, NULL)) return CB_PD_NOT_KRONECKER;
  const int *fi = s->free_index;
  int nf = s->model.nfree;
  /* The pattern: the diagonal, every spring's pair of free ends, every nonzero constant-Hessian block. Built as a
   * block pattern (which sorts and merges the pairs); its block CSC (bcolp, brow) is the scalar CSC. */
  cb_pattern pat;
  int st = cb_pattern_init(&pat, nf);
  for (int t = 0; st == CB_OK && t < s->sys.nterms; t++) {
    int ns;
    const int *ends;
    const double *rest;
    double k;
    if (s->sys.terms[t]->type != cb_term_spring) continue;
    cb_spring_term_springs(s->sys.terms[t], &ns, &ends, &rest, &k);
    for (int e = 0; st == CB_OK && e < ns; e++) st = cb_pattern_add(&pat, fi[ends[2 * e]], fi[ends[2 * e + 1]]);
  }
  if (hc)
    for (int bj = 0; st == CB_OK && bj < A->nblk; bj++)
      for (int k = A->bcolp[bj]; st == CB_OK && k < A->bcolp[bj + 1]; k++) {
        int slot, stride;
        cb_sparse_block_slot(A, A->brow[k], bj, &slot, &stride);
        if (hc[slot] != 0.0) st = cb_pattern_add(&pat, A->brow[k], bj);
      }
  cb_sparse B;
  memset(&B, 0, sizeof B);
  if (st == CB_OK) st = cb_sparse_from_pattern(&pat, &B);
  cb_pattern_free(&pat);
  if (st) {
    cb_sparse_free(&B);
    return st;
  }
  /* the block CSC becomes the scalar one: colp = bcolp, rowi = brow */
  P->n = nf;
  P->nnz = B.bcolp[nf];
  P->colp = B.bcolp;
  P->rowi = B.brow;
  B.bcolp = NULL;
  B.brow = NULL;
  cb_sparse_free(&B);
  P->val = cb_calloc((size_t)P->nnz + 1, sizeof(double));
  if (!P->val) {
    cb_sparse_free(P);
    return CB_ENOMEM;
  }
  /* values in the block path's order of additions, so each entry is the same sum: H_const, M/dt^2, springs */
  if (hc)
    for (int bj = 0; bj < A->nblk; bj++)
      for (int k = A->bcolp[bj]; k < A->bcolp[bj + 1]; k++) {
        int slot, stride;
        cb_sparse_block_slot(A, A->brow[k], bj, &slot, &stride);
        if (hc[slot] != 0.0) scalar_add(P, A->brow[k], bj, hc[slot]); /* P_ij = H_const(3i, 3j) */
      }
  for (int b = 0; b < nf; b++) scalar_add(P, b, b, s->mass[s->free_vertex[b]] / (dt * dt)); /* M/dt^2 */
  for (int t = 0; t < s->sys.nterms; t++) {
    int ns;
    const int *ends;
    const double *rest;
    double k;
    if (s->sys.terms[t]->type != cb_term_spring) continue;
    cb_spring_term_springs(s->sys.terms[t], &ns, &ends, &rest, &k);
    for (int e = 0; e < ns; e++) { /* k A_e A_e^T: +k on (i,i), (j,j); -k on (i,j), (j,i) */
      int bi = fi[ends[2 * e]], bj = fi[ends[2 * e + 1]];
      if (bi >= 0) scalar_add(P, bi, bi, k);
      if (bj >= 0) scalar_add(P, bj, bj, k);
      if (bi >= 0 && bj >= 0) {
        scalar_add(P, bi, bj, -k);
        scalar_add(P, bj, bi, -k);
      }
    }
  }
  return CB_OK;
}

int cb_pd_global_init(cb_pd_global *g, cb_integrator *it, int with_constant, int matrix) {
  const cb_scene *s = it->scene;
  double dt = it->params.dt;
  memset(g, 0, sizeof *g);
  g->nf = s->model.nfree;
  it->solver->params.residual = 0; /* nothing reads it (cb_pd_global_init in pd_matrix.h) */
  g->path = CB_GLOBAL_BLOCK;
  if (matrix == CB_PD_MATRIX_AUTO && it->solver->type->solve_n && (it->solver->type->flags & CB_SOLVER_DIRECT)) {
    int st = cb_pd_matrix_build_scalar(s, dt, with_constant, &g->P);
    if (st < 0) return st;
    if (st == CB_OK) g->path = CB_GLOBAL_SCALAR; /* else CB_PD_NOT_KRONECKER: the block path */
  }
  if (g->path == CB_GLOBAL_BLOCK) {
    int st = cb_pd_matrix_build(s, dt, with_constant, &g->P);
    if (st) return st;
    if (g->nf == 0) return CB_OK;
    return cb_solver_factor(it->solver, &g->P); /* once per scene, on the integrator's solver (analysed on the
                                                   system's pattern, which P copies) */
  }
  cb_solver_params sp = it->solver->params;
  sp.residual = 0;
  int st = cb_solver_alloc(it->solver->type->name, &sp, g->nf, &g->s);
  if (st) return st;
  g->B = cb_malloc((size_t)3 * g->nf + 1, sizeof(double));
  g->X = cb_malloc((size_t)3 * g->nf + 1, sizeof(double));
  if (!g->B || !g->X) return CB_ENOMEM;
  if (g->nf == 0) return CB_OK;
  st = cb_solver_analyze(g->s, &g->P);
  return st ? st : cb_solver_factor(g->s, &g->P); /* once per scene */
}

int cb_pd_global_solve(cb_pd_global *g, cb_integrator *it, const double *b, double *x, cb_step_stats *st) {
  int ls, nf = g->nf;
  cb_solver *sv = g->s ? g->s : it->solver;
  if (g->path == CB_GLOBAL_BLOCK) ls = cb_solver_solve(sv, &g->P, b, x);
  else {
    double t0 = cb_now_ms();
    for (int i = 0; i < nf; i++) /* interleaved to 3 columns: B(i, a) = b(3i + a) */
      for (int a = 0; a < 3; a++) g->B[(size_t)a * nf + i] = b[3 * i + a];
    ls = cb_solver_solve_n(sv, &g->P, 3, g->B, g->X); /* P [X Y Z] = [Bx By Bz] */
    for (int i = 0; i < nf; i++)
      for (int a = 0; a < 3; a++) x[3 * i + a] = g->X[(size_t)a * nf + i];
    st->solve_ms += cb_now_ms() - t0 - sv->stats.solve_ms; /* the two copies; the solve's own time added below */
  }
  st->solve_ms += sv->stats.solve_ms;
  st->linear_iters += sv->stats.iters;
  st->linear_status = ls;
  st->global_path = g->path;
  st->global_factor_nnz = sv->stats.factor_nnz;
  return ls;
}

void cb_pd_global_free(cb_pd_global *g) {
  cb_sparse_free(&g->P);
  cb_solver_free(g->s);
  free(g->B);
  free(g->X);
  memset(g, 0, sizeof *g);
}
