/* Solver registry and the shared wrapper: timing and statistics. */
#include <clothbench/solver.h>

#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include <clothbench/timer.h>

/* The registry. Each plug-in file lib/core/solver/solver_<name>.c defines
 * `const cb_solver_type cb_solver_<name>`; its one X(name) line below declares
 * and lists it. The order is that of solver.method's choices, of the tests'
 * loops and of the experiments' rows. */
#define CB_SOLVER_REGISTRY(X) \
  X(cholmod) \
  X(jacobi) \
  X(chebyshev) \
  X(cg) \
  X(pcg) \
  X(sgs) \
  X(nesterov) \
  X(petsc_generic) \
  X(petsc_gamg) \
  X(petsc_hypre) \
  X(petsc_ml) \
  X(petsc_icc) \
  /* one X(name) line per solver, above this line */
#define CB_SOLVER_DECLARE(name) extern const cb_solver_type cb_solver_##name;
#define CB_SOLVER_ENTRY(name) &cb_solver_##name,
CB_SOLVER_REGISTRY(CB_SOLVER_DECLARE)
const cb_solver_type *const cb_solver_types[] = {CB_SOLVER_REGISTRY(CB_SOLVER_ENTRY) NULL};

const char *cb_solver_name(int i) {
  for (int k = 0; k <= i; k++)
    if (!cb_solver_types[k]) return NULL;
  return cb_solver_types[i]->name;
}

const char *cb_order_name(int ordering) {
  static const char *const names[] = {"default", "amd", "metis", "nesdis"};
  return ordering >= 0 && ordering < 4 ? names[ordering] : NULL;
}

cb_solver_params cb_solver_params_default(void) {
  cb_solver_params p = {.cookie = CB_PARAMS_COOKIE,
                        .tol = 1e-8,
                        .max_iters = 1000,
                        .alpha = CB_AUTO,
                        .rho = CB_AUTO,
                        .history_cap = 0,
                        .ordering = CB_ORDER_NESDIS,
                        .nrelax = {16, 64, 128},
                        .upper = 1,
                        .flush_denormals = 1,
                        .rho_reuse = 1,
                        .residual = 1,
                        .petsc_options = "",
                        .pc_reuse = CB_PC_REUSE_AUTO,
                        .pc_reuse_steps = 1,
                        .rigid_modes = 0,
                        .monitor = NULL,
                        .monitor_ctx = NULL};
  return p;
}

const cb_solver_type *cb_solver_type_find(const char *name) {
  for (int i = 0; cb_solver_types[i]; i++)
    if (strcmp(cb_solver_types[i]->name, name) == 0) return cb_solver_types[i];
  return NULL;
}

int cb_solver_alloc(const char *name, const cb_solver_params *p, int n, cb_solver **out) {
  *out = NULL;
  const cb_solver_type *t = cb_solver_type_find(name);
  if (!t) return cb_fail("unknown linear solver '%s'", name);
  if (p) {
    int st = cb_params_check(p->cookie, "solver", "cb_solver_params_default");
    if (st) return st;
  }
  cb_solver *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->type = t;
  s->params = p ? *p : cb_solver_params_default();
  s->n = n;
  if (s->params.history_cap > 0) {
    s->stats.history = cb_calloc((size_t)s->params.history_cap, sizeof(double));
    if (!s->stats.history) {
      free(s);
      return CB_ENOMEM;
    }
  }
  int st = t->alloc(s, n);
  if (st) {
    free(s->stats.history);
    free(s);
    return st;
  }
  *out = s;
  return CB_OK;
}

int cb_solver_analyze(cb_solver *s, const cb_sparse *A) {
  double t0 = cb_now_ms();
  int st = s->type->analyze ? s->type->analyze(s, A) : CB_OK;
  s->stats.analyze_ms = cb_now_ms() - t0;
  return st;
}

int cb_solver_factor(cb_solver *s, const cb_sparse *A) {
  s->stats.setup_ms = 0;
  double t0 = cb_now_ms();
  int st = s->type->factor(s, A);
  s->stats.factor_ms = cb_now_ms() - t0;
  s->stats.status = st;
  return st;
}

int cb_solver_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  s->stats.history_len = 0;
  s->stats.iters = 0;
  double t0 = cb_now_ms();
  int st = s->type->solve(s, A, b, x);
  s->stats.solve_ms = cb_now_ms() - t0;
  s->stats.status = st;
  return st;
}

int cb_solver_solve_n(cb_solver *s, const cb_sparse *A, int nrhs, const double *b, double *x) {
  s->stats.history_len = 0;
  s->stats.iters = 0;
  double t0 = cb_now_ms();
  int st = CB_OK;
  if (s->type->solve_n) st = s->type->solve_n(s, A, nrhs, b, x);
  else {
    int iters = 0;
    for (int c = 0; c < nrhs && (st == CB_OK || st == CB_NOT_CONVERGED); c++) {
      int sc = s->type->solve(s, A, b + (size_t)c * A->n, x + (size_t)c * A->n);
      iters += s->stats.iters;
      if (sc != CB_OK) st = sc; /* the worst column's status: an error stops, not converged carries on */
    }
    s->stats.iters = iters;
  }
  s->stats.solve_ms = cb_now_ms() - t0;
  s->stats.status = st;
  return st;
}

void cb_solver_forget(cb_solver *s) {
  if (s && s->type->forget) s->type->forget(s);
}

void cb_solver_free(cb_solver *s) {
  if (!s) return;
  s->type->free(s);
  free(s->stats.history);
  free(s);
}

double cb_relative_residual(const cb_sparse *A, const double *b, const double *x, double *work) {
  cb_sparse_matvec(A, x, work);
  cblas_daxpy(A->n, -1.0, b, 1, work, 1); /* work = A x - b */
  double bn = cblas_dnrm2(A->n, b, 1), rn = cblas_dnrm2(A->n, work, 1);
  return bn > 0 ? rn / bn : rn;
}
