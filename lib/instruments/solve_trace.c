/* Traced linear solves (see solve_trace.h). */
#include "solve_trace.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include <clothbench/timer.h>

cb_trace_params cb_trace_params_default(void) {
  cb_trace_params p = {.keep_all = 100, .growth = 1.05, .mark_tol = 1e-6, .mark_err = 0};
  return p;
}

typedef struct {
  cb_trace *t;
  cb_trace_params p;
  int cap, n, marked, marked_err, next_keep;
  const double *xref;
  double xref_norm, t_start, overhead;
  cb_trace_row pending; /* the latest iteration, kept or not */
  int pending_kept;
  int called; /* the monitor ran (iterative solver) */
} tracer;

static double rel_error(const tracer *tr, const double *x) {
  if (!tr->xref) return NAN;
  double e = 0;
  for (int i = 0; i < tr->n; i++) {
    double d = x[i] - tr->xref[i];
    e += d * d;
  }
  return sqrt(e) / tr->xref_norm; /* |x - x*| / |x*| */
}

static void push(tracer *tr, cb_trace_row r) {
  cb_trace *t = tr->t;
  if (t->nrows < tr->cap) t->rows[t->nrows++] = r;
}

static void monitor(void *ctx, int k, double rel, const double *x) {
  double t_in = cb_now_ms();
  tracer *tr = ctx;
  tr->called = 1;
  cb_trace_row r = {k, rel, tr->t->setup_ms + (t_in - tr->t_start - tr->overhead), NAN};
  int keep = k <= tr->p.keep_all || k >= tr->next_keep;
  if (!tr->marked && rel <= tr->p.mark_tol) keep = tr->marked = 1;
  if (tr->xref && tr->p.mark_err > 0 && !tr->marked_err) { /* the error at every iteration until it is under mark_err */
    r.error = rel_error(tr, x);
    if (r.error <= tr->p.mark_err) {
      keep = tr->marked_err = 1;
      tr->t->iter_err = k;
    }
  }
  if (keep) {
    if (isnan(r.error)) r.error = rel_error(tr, x);
    push(tr, r);
    if (k > tr->p.keep_all) tr->next_keep = (int)ceil(k * tr->p.growth);
    if (tr->next_keep <= k) tr->next_keep = k + 1;
  }
  tr->pending = r;
  tr->pending_kept = keep;
  tr->overhead += cb_now_ms() - t_in;
}

int cb_trace_solve(const char *solver, const cb_solver_params *p, const cb_sparse *A, const double *b,
                   const double *xref, const cb_trace_params *tp, double *xout, cb_trace *out) {
  memset(out, 0, sizeof *out);
  out->iter_err = -1;
  int n = A->n;
  tracer tr;
  memset(&tr, 0, sizeof tr);
  tr.t = out;
  tr.p = tp ? *tp : cb_trace_params_default();
  if (tr.p.keep_all < 0 || !(tr.p.growth > 1) || !(tr.p.mark_err >= 0))
    return cb_fail("trace: keep_all must be >= 0, growth > 1 and mark_err >= 0");
  tr.n = n;
  tr.xref = xref;
  tr.next_keep = (int)ceil(tr.p.keep_all * tr.p.growth);
  if (tr.next_keep <= tr.p.keep_all) tr.next_keep = tr.p.keep_all + 1;
  if (xref) {
    for (int i = 0; i < n; i++) tr.xref_norm += xref[i] * xref[i];
    tr.xref_norm = sqrt(tr.xref_norm);
    if (!(tr.xref_norm > 0)) tr.xref_norm = 1; /* x* = 0: absolute error */
  }
  cb_solver_params sp = p ? *p : cb_solver_params_default();
  sp.monitor = monitor;
  sp.monitor_ctx = &tr;
  /* rows: every one up to keep_all, then a geometric sequence, plus the mark and the last */
  int m = sp.max_iters > 0 ? sp.max_iters : 1;
  tr.cap = tr.p.keep_all + 5 +
           (m > tr.p.keep_all ? (int)ceil(log((double)m / (tr.p.keep_all + 1)) / log(tr.p.growth)) + 1 : 0);
  out->rows = cb_malloc((size_t)tr.cap, sizeof *out->rows);
  double *x = cb_calloc((size_t)n, sizeof(double)); /* x = 0 */
  cb_solver *s = NULL;
  int st = (!out->rows || !x) ? CB_ENOMEM : cb_solver_alloc(solver, &sp, n, &s);
  if (st == CB_OK) st = cb_solver_analyze(s, A);
  if (st < 0) goto done;
  out->analyze_ms = s->stats.analyze_ms;
  int fst = cb_solver_factor(s, A);
  out->setup_ms = s->stats.factor_ms;
  out->rho_ms = s->stats.setup_ms;
  out->rho = s->stats.rho;
  if (fst != CB_OK) { /* the set-up failed: one row at x = 0 */
    if (fst < 0 && fst != CB_ENOMEM) fst = CB_LINEAR_FAILED;
    out->status = fst;
    out->wall_ms = out->setup_ms;
    push(&tr, (cb_trace_row){0, 1.0, out->setup_ms, xref ? rel_error(&tr, x) : NAN});
    st = fst == CB_ENOMEM ? CB_ENOMEM : CB_OK;
    goto done;
  }
  tr.t_start = cb_now_ms();
  out->status = cb_solver_solve(s, A, b, x);
  double t_end = cb_now_ms();
  out->iters = s->stats.iters;
  out->wall_ms = out->setup_ms + (t_end - tr.t_start - tr.overhead);
  if (!tr.called) { /* a direct solve: one row */
    push(&tr, (cb_trace_row){s->stats.iters, s->stats.rel_residual, out->wall_ms, rel_error(&tr, x)});
  } else if (!tr.pending_kept) { /* the last iteration, from the final iterate */
    cb_trace_row r = tr.pending;
    r.error = rel_error(&tr, x);
    push(&tr, r);
  }
  if (out->status < 0 && out->status != CB_ENOMEM) out->status = CB_LINEAR_FAILED;
  st = out->status == CB_ENOMEM ? CB_ENOMEM : CB_OK;
done:
  if (xout && x) memcpy(xout, x, (size_t)n * sizeof(double));
  cb_solver_free(s);
  free(x);
  return st;
}

int cb_trace_timed_solve(const char *solver, const cb_solver_params *p, const cb_sparse *A, const double *b,
                         const double *xref, cb_timed_solve *out) {
  memset(out, 0, sizeof *out);
  out->error = NAN;
  int n = A->n;
  cb_solver_params sp = p ? *p : cb_solver_params_default();
  sp.monitor = NULL;
  sp.monitor_ctx = NULL;
  double *x = cb_calloc((size_t)n, sizeof(double)); /* x = 0 */
  cb_solver *s = NULL;
  int st = !x ? CB_ENOMEM : cb_solver_alloc(solver, &sp, n, &s);
  if (st == CB_OK) {
    double t0 = cb_now_ms();
    st = cb_solver_analyze(s, A);
    double t1 = cb_now_ms();
    int fst = st == CB_OK ? cb_solver_factor(s, A) : st;
    double t2 = cb_now_ms();
    out->status = fst == CB_OK ? cb_solver_solve(s, A, b, x) : fst;
    double t3 = cb_now_ms();
    out->analyze_ms = t1 - t0;
    out->factor_ms = t2 - t1;
    out->solve_ms = fst == CB_OK ? t3 - t2 : 0;
    out->total_ms = out->analyze_ms + out->factor_ms + out->solve_ms;
    out->iters = s->stats.iters;
    out->factor_nnz = s->stats.factor_nnz;
    if (out->status < 0 && out->status != CB_ENOMEM) out->status = CB_LINEAR_FAILED;
    st = out->status == CB_ENOMEM ? CB_ENOMEM : CB_OK;
  }
  if (st == CB_OK && xref) {
    double e = 0, nx = 0;
    for (int i = 0; i < n; i++) {
      e += (x[i] - xref[i]) * (x[i] - xref[i]);
      nx += xref[i] * xref[i];
    }
    out->error = sqrt(e) / (nx > 0 ? sqrt(nx) : 1);
  }
  cb_solver_free(s);
  free(x);
  return st;
}

void cb_trace_free(cb_trace *t) {
  if (!t) return;
  free(t->rows);
  t->rows = NULL;
  t->nrows = 0;
}

const cb_trace_row *cb_trace_at(const cb_trace *t, int k) {
  const cb_trace_row *best = NULL;
  for (int i = 0; i < t->nrows; i++)
    if (t->rows[i].iter <= k) best = &t->rows[i];
  return best;
}

int cb_trace_reference(const cb_sparse *A, const double *b, double *xref) {
  int n = A->n;
  double *r = cb_malloc((size_t)n, sizeof(double)), *dx = cb_malloc((size_t)n, sizeof(double));
  cb_solver *s = NULL;
  int st = (!r || !dx) ? CB_ENOMEM : cb_solver_alloc("cholmod", NULL, n, &s);
  if (st == CB_OK) st = cb_solver_analyze(s, A);
  if (st == CB_OK) st = cb_solver_factor(s, A);
  if (st == CB_OK) st = cb_solver_solve(s, A, b, xref); /* x = A^-1 b */
  if (st == CB_OK) {
    cb_sparse_residual(A, b, xref, r);                           /* r = b - A x */
    st = cb_solver_solve(s, A, r, dx);                           /* dx = A^-1 r */
    for (int i = 0; st == CB_OK && i < n; i++) xref[i] += dx[i]; /* x* = x + dx */
  }
  cb_solver_free(s);
  free(r);
  free(dx);
  return st;
}

double cb_trace_rate_window(const cb_trace_row *rows, int nrows, double f0, double f1) {
  if (nrows < 2) return NAN;
  double n = rows[nrows - 1].iter;
  const cb_trace_row *from = NULL, *to = NULL;
  for (int i = 0; i < nrows; i++) {
    if (rows[i].iter <= f0 * n) from = &rows[i];
    if (rows[i].iter <= f1 * n) to = &rows[i];
  }
  if (!from || !to || to->iter <= from->iter || !(from->rel_residual > 0)) return NAN;
  return pow(to->rel_residual / from->rel_residual, 1.0 / (to->iter - from->iter)); /* (r_m / r_j)^(1/(m-j)) */
}

double cb_trace_rate(const cb_trace_row *rows, int nrows, double tail) {
  return cb_trace_rate_window(rows, nrows, 1.0 - tail, 1.0);
}
