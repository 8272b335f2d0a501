#include <clothbench/eigen.h>

#include <gsl/gsl_cblas.h> /* cblas_* prototypes; OpenBLAS provides them at link time */
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_sort_vector.h>
#include <gsl/gsl_vector.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "rng.h"

cb_lanczos_params cb_lanczos_params_default(void) {
  cb_lanczos_params p = {.max_steps = 300, .tol = 1e-8, .seed = 1, .reorth = 1, .done = NULL, .done_ctx = NULL};
  return p;
}

void cb_scaled_op_apply(void *ctx, const double *x, double *y) {
  cb_scaled_op *o = ctx;
  int n = o->A->n;
  if (!o->d) {
    cb_sparse_matvec(o->A, x, y);
    return;
  }
  for (int i = 0; i < n; i++) o->work[i] = o->d[i] * x[i];
  cb_sparse_matvec(o->A, o->work, y);
  for (int i = 0; i < n; i++) y[i] *= o->d[i]; /* y = D A D x */
}

/* LAPACK (OpenBLAS provides it): selected eigenpairs of a symmetric
 * tridiagonal matrix by the MRRR algorithm. */
extern void dstevr_(const char *jobz, const char *range, const int *n, double *d, double *e, const double *vl,
                    const double *vu, const int *il, const int *iu, const double *abstol, int *m, double *w, double *z,
                    const int *ldz, int *isuppz, double *work, const int *lwork, int *iwork, const int *liwork,
                    int *info, size_t jobz_len, size_t range_len);

/* The extreme eigenpairs of the k x k Lanczos tridiagonal T (alpha, beta):
 * O(k) each with dstevr, where a dense eigendecomposition would be O(k^3).
 * work: 24k doubles, iwork: 10k ints (dstevr wants 20k and 10k). */
static int ritz(int k, const double *alpha, const double *beta, double beta_k, double *work, int *iwork,
                cb_eig_result *r) {
  double *d = work, *e = work + k, *z = work + 2 * k, *wv = work + 3 * k, *lw = work + 4 * k;
  int lwork = 20 * k, liwork = 10 * k, m, info, isuppz[2];
  double zero = 0;
  for (int which = 0; which < 2; which++) {
    int il = which ? k : 1; /* 1: smallest, k: largest */
    memcpy(d, alpha, (size_t)k * sizeof(double));
    if (k > 1) memcpy(e, beta, (size_t)(k - 1) * sizeof(double));
    e[k - 1] = 0;
    dstevr_("V", "I", &k, d, e, &zero, &zero, &il, &il, &zero, &m, wv, z, &k, isuppz, lw, &lwork, iwork, &liwork, &info,
            1, 1); /* W (wv) has n entries: LAPACK may use all of them */
    if (info != 0 || m != 1) return cb_fail("lanczos: tridiagonal eigensolve failed (dstevr info %d)", info);
    /* the Ritz pair (theta, Q s) has residual |beta_k| |s_k| (last component of s) */
    if (which) {
      r->lmax = wv[0];
      r->res_max = fabs(beta_k * z[k - 1]);
    } else {
      r->lmin = wv[0];
      r->res_min = fabs(beta_k * z[k - 1]);
    }
  }
  return CB_OK;
}

void cb_lanczos_workspace_free(cb_lanczos_workspace *ws) {
  if (!ws) return;
  free(ws->Q);
  free(ws->w);
  free(ws->alpha);
  free(ws->beta);
  free(ws->tw);
  free(ws->tiw);
  memset(ws, 0, sizeof *ws);
}

int cb_lanczos_workspace_alloc(cb_lanczos_workspace *ws, int n, const cb_lanczos_params *pp) {
  cb_lanczos_params p = pp ? *pp : cb_lanczos_params_default();
  memset(ws, 0, sizeof *ws);
  int m = p.max_steps < n ? p.max_steps : n;
  if (m < 1) return cb_fail("lanczos: empty operator");
  ws->n = n;
  ws->m = m;
  ws->reorth = p.reorth && (double)n * (m + 1) * sizeof(double) <= 1073741824.0;
  ws->Q = cb_malloc((size_t)(ws->reorth ? m + 1 : 3) * (size_t)n, sizeof(double));
  ws->w = cb_malloc((size_t)n, sizeof(double));
  ws->alpha = cb_calloc((size_t)m + 1, sizeof(double));
  ws->beta = cb_calloc((size_t)m + 1, sizeof(double));
  ws->tw = cb_malloc((size_t)24 * m + 2, sizeof(double));
  ws->tiw = cb_malloc((size_t)10 * m + 2, sizeof(int));
  if (!ws->Q || !ws->w || !ws->alpha || !ws->beta || !ws->tw || !ws->tiw) {
    cb_lanczos_workspace_free(ws);
    return cb_fail_status(CB_ENOMEM, "lanczos: out of memory");
  }
  return CB_OK;
}

int cb_lanczos(int n, cb_linop op, void *ctx, const cb_lanczos_params *p, cb_eig_result *out) {
  cb_lanczos_workspace ws;
  memset(out, 0, sizeof *out);
  int st = cb_lanczos_workspace_alloc(&ws, n, p);
  if (st == CB_OK) st = cb_lanczos_ws(op, ctx, p, &ws, out);
  cb_lanczos_workspace_free(&ws);
  return st;
}

int cb_lanczos_ws(cb_linop op, void *ctx, const cb_lanczos_params *pp, cb_lanczos_workspace *ws, cb_eig_result *out) {
  cb_lanczos_params p = pp ? *pp : cb_lanczos_params_default();
  memset(out, 0, sizeof *out);
  double t0 = cb_now_ms();
  int n = ws->n, m = p.max_steps < ws->m ? p.max_steps : ws->m, reorth = ws->reorth, st = CB_OK;
  if (m < 1) return cb_fail("lanczos: empty operator");
  double *Q = ws->Q, *w = ws->w, *alpha = ws->alpha, *beta = ws->beta, *tw = ws->tw;
  int *tiw = ws->tiw;
  {
    /* deterministic pseudo-random start vector (64-bit LCG) */
    cb_rng rng = cb_rng_seed((uint64_t)(p.seed + 1));
    for (int i = 0; i < n; i++) Q[i] = cb_rng_uniform(&rng) - 0.5;
    double nq = cblas_dnrm2(n, Q, 1);
    cblas_dscal(n, 1.0 / nq, Q, 1);
  }
  int k = 0;
  out->status = CB_NOT_CONVERGED;
  for (; st == CB_OK && k < m; k++) {
    double *q = reorth ? Q + (size_t)k * n : Q + (size_t)(k % 3) * n;
    double *qprev = k == 0 ? NULL : reorth ? Q + (size_t)(k - 1) * n : Q + (size_t)((k + 2) % 3) * n;
    op(ctx, q, w);                                           /* w = Op q_k */
    if (qprev) cblas_daxpy(n, -beta[k - 1], qprev, 1, w, 1); /* w -= beta_{k-1} q_{k-1} */
    alpha[k] = cblas_ddot(n, q, 1, w, 1);                    /* alpha_k = q_k . w */
    cblas_daxpy(n, -alpha[k], q, 1, w, 1);                   /* w -= alpha_k q_k */
    if (reorth)                                              /* full reorthogonalisation, twice is enough */
      for (int pass = 0; pass < 2; pass++)
        for (int j = 0; j <= k; j++) {
          double c = cblas_ddot(n, Q + (size_t)j * n, 1, w, 1);
          cblas_daxpy(n, -c, Q + (size_t)j * n, 1, w, 1);
        }
    beta[k] = cblas_dnrm2(n, w, 1);
    if (!isfinite(alpha[k]) || !isfinite(beta[k])) {
      st = cb_fail_status(CB_DIVERGED, "lanczos: NaN in operator");
      break;
    }
    int invariant = beta[k] <= 1e-14 * fabs(alpha[k]); /* Krylov space is invariant: Ritz values exact */
    int last = k + 1 == m || invariant;
    if (last || (k + 1) % 5 == 0) {
      st = ritz(k + 1, alpha, beta, beta[k], tw, tiw, out);
      if (st) break;
      double scale = fmax(fabs(out->lmin), fabs(out->lmax));
      int converged =
          invariant || k + 1 == n ||
          (p.done ? p.done(p.done_ctx, out) : out->res_min <= p.tol * scale && out->res_max <= p.tol * scale);
      if (converged || last) {
        out->status = converged ? CB_OK : CB_NOT_CONVERGED;
        k++;
        break;
      }
    }
    double *qnext = reorth ? Q + (size_t)(k + 1) * n : Q + (size_t)((k + 1) % 3) * n;
    for (int i = 0; i < n; i++) qnext[i] = w[i] / beta[k]; /* q_{k+1} = w / beta_k */
  }
  out->steps = k;
  out->ms = cb_now_ms() - t0;
  return st;
}

double cb_eigen_prescale(double *a, size_t n, size_t tda) {
  double amax = 0;
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) {
      double v = fabs(a[i * tda + j]);
      if (!isfinite(v)) return 1.0; /* NaN or Inf: left for the caller's checks to see */
      if (v > amax) amax = v;
    }
  if (amax == 0) return 1.0;
  int e;
  frexp(amax, &e); /* amax = f 2^e, f in [0.5, 1) */
  double tiny = DBL_EPSILON * DBL_EPSILON;
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) {
      double v = ldexp(a[i * tda + j], -e); /* exact unless it underflows, and then it is flushed */
      a[i * tda + j] = fabs(v) < tiny ? 0.0 : v;
    }
  return ldexp(1.0, e);
}

int cb_dense_eigenvalues(const cb_sparse *A, const double *d, double *eval) {
  size_t n = (size_t)A->n;
  gsl_matrix *D = gsl_matrix_calloc(n, n);
  gsl_vector *ev = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc(n);
  if (!D || !ev || !ws) {
    gsl_matrix_free(D);
    gsl_vector_free(ev);
    if (ws) gsl_eigen_symm_free(ws);
    return cb_fail_status(CB_ENOMEM, "dense eigenvalues: out of memory for n = %zu", n);
  }
  cb_sparse_to_dense(A, d, NULL, D->data, D->tda);
  double scale = cb_eigen_prescale(D->data, n, D->tda);
  int st = gsl_eigen_symm(D, ev, ws) ? cb_fail("gsl_eigen_symm failed") : CB_OK;
  if (st == CB_OK) {
    gsl_sort_vector(ev);
    for (size_t i = 0; i < n; i++) eval[i] = scale * gsl_vector_get(ev, i);
  }
  gsl_matrix_free(D);
  gsl_vector_free(ev);
  gsl_eigen_symm_free(ws);
  return st;
}
