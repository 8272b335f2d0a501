/* Newton step methods and their one-step measurement (see method.h). */
#include "method.h"
#include "vec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

int cb_method_make(int K, int line_search, const char *inner, cb_method *m) {
  memset(m, 0, sizeof *m);
  if (K < 0) return cb_fail("method: K must be >= 0 (0 = converged), got %d", K);
  m->K = K;
  m->definiteness = CB_DEF_DROP;
  m->line_search = line_search ? 1 : 0;
  if (K == 0) snprintf(m->name, sizeof m->name, "newton_converged");
  else snprintf(m->name, sizeof m->name, "newton_k%d", K);
  snprintf(m->inner, sizeof m->inner, "%s", inner);
  m->sp = cb_solver_params_default();
  if (!strcmp(inner, "cholmod")) {
    snprintf(m->solver, sizeof m->solver, "cholmod");
  } else if (!strcmp(inner, "cg32") || !strcmp(inner, "cg_tol")) {
    snprintf(m->solver, sizeof m->solver, "cg");
  } else if (!strcmp(inner, "cheb32") || !strcmp(inner, "cheb_tol") || !strcmp(inner, "cheb32_alpha1")) {
    snprintf(m->solver, sizeof m->solver, "chebyshev");
    m->sp.alpha = strcmp(inner, "cheb32_alpha1") ? CB_METHOD_CHEB_ALPHA : 1.0;
    m->sp.rho = CB_AUTO; /* auto: Lanczos, amortised over factorisations (solver_jacobi.c) */
  } else {
    return cb_fail("method: unknown inner solve '%s'", inner);
  }
  if (strstr(inner, "32")) { /* cut at 32 iterations: the tolerance never stops it */
    m->sp.max_iters = 32;
    m->sp.tol = 1e-300;
  } else if (strstr(inner, "_tol")) {
    m->sp.max_iters = 10000;
    m->sp.tol = 1e-8;
  }
  return CB_OK;
}

int cb_method_make_exact(int line_search, const char *inner, cb_method *m) {
  int st = cb_method_make(0, line_search, inner, m);
  if (st) return st;
  m->definiteness = CB_DEF_SHIFT;
  snprintf(m->name, sizeof m->name, "newton_converged_exact");
  return CB_OK;
}

int cb_method_integrator(const cb_method *m, cb_scene *s, double dt, cb_newton_hook hook, void *hook_ctx,
                         cb_integrator **out) {
  cb_integrator_params p = cb_integrator_params_default();
  p.dt = dt;
  p.hook = hook;
  p.hook_ctx = hook_ctx;
  cb_newton_params np = cb_newton_params_default();
  np.max_iters = m->K > 0 ? m->K : CB_METHOD_CONVERGED_ITERS;
  np.tol = m->K > 0 ? 0.0 : CB_METHOD_CONVERGED_TOL;
  np.tol_dx = 0;
  np.init_predict = 1;
  np.line_search = m->line_search;
  np.definiteness = (cb_definiteness)m->definiteness;
  return cb_integrator_alloc("newton", s, &p, &np, m->solver, &m->sp, out);
}

int cb_method_work_alloc(const cb_scene *s, cb_method_work *w) {
  memset(w, 0, sizeof *w);
  w->x = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
  w->v = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
  if (!w->x || !w->v) {
    cb_method_work_free(w);
    return CB_ENOMEM;
  }
  return CB_OK;
}

void cb_method_work_free(cb_method_work *w) {
  free(w->x);
  free(w->v);
  w->x = w->v = NULL;
}

void cb_method_hook(void *work, int event, const cb_newton_event *ev) {
  cb_method_work *w = work;
  if (event == CB_NEWTON_SOLVED && ev->solver) w->setup_ms += ev->solver->stats.setup_ms;
  if (event == CB_NEWTON_GRADIENT && ev->iter > 0 && ev->alpha < 1.0) w->ls_reduced++;
}

int cb_method_step(cb_integrator *it, cb_method_work *w, cb_reference *ref, const double *x0, const double *v0,
                   const double *xstar, double Fstar, cb_step_result *out) {
  const cb_scene *s = it->scene;
  int n3 = 3 * s->mesh.nv;
  memset(out, 0, sizeof *out);
  memcpy(w->x, x0, (size_t)n3 * sizeof(double));
  memcpy(w->v, v0, (size_t)n3 * sizeof(double));
  w->setup_ms = 0;
  w->ls_reduced = 0;
  /* a measured step must not depend on the steps the integrator made before it: the timing
   * rounds repeat it a number of times that depends on the clock, and a Chebyshev inner solve
   * reuses its spectral bounds over up to 30 factorisations (solver_jacobi.c) */
  cb_solver_forget(it->solver);
  int st = cb_integrator_step(it, w->x, w->v, &out->st);
  out->setup_ms = w->setup_ms;
  out->ls_reduced = w->ls_reduced;
  if (cb_vec_all_finite(n3, w->x)) {
    out->step_error = cb_step_error(s, w->x, xstar, x0);
    out->f_minus_fstar = cb_reference_objective(ref, x0, v0, w->x, NULL) - Fstar;
  } else {
    out->step_error = out->f_minus_fstar = NAN;
    if (st == CB_OK || st == CB_NOT_CONVERGED) st = out->st.status = CB_DIVERGED;
  }
  return st;
}
