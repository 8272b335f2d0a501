/* Integrator registry and the shared wrapper: it allocates each type's state
 * and parameters from the type's sizes, the linear solver when the type's
 * flags ask for one, and runs the scene's post-step stage after every step.
 * It knows nothing about any one type: a new one is a file with its
 * cb_integrator_type and one X(id) line in CB_INTEGRATOR_REGISTRY below. */
#include <clothbench/integrator.h>

#include <cblas.h>

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/contact.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

/* The registry. Each plug-in file lib/core/integrator/integrator_<file>.c defines
 * `const cb_integrator_type cb_integrator_<id>` (one file may define
 * several, as integrator_pd.c does pd and pd-chebyshev); its one X(id) line
 * below declares and lists it. The order is that of integrator.method's
 * choices, of the config keys (--help-config) and of the tests' loops. */
#define CB_INTEGRATOR_REGISTRY(X) \
  X(explicit) \
  X(newton) \
  X(jacobi_nl) \
  X(chebyshev_nl) \
  X(pd) \
  X(pd_chebyshev) \
  X(pbd) \
  X(xpbd) \
  X(lbfgs) \
  X(vbd) \
  X(vbd_chebyshev) \
  X(shape_matching) \
  /* one X(id) line per integrator, above this line */
#define CB_INTEGRATOR_DECLARE(id) extern const cb_integrator_type cb_integrator_##id;
#define CB_INTEGRATOR_ENTRY(id) &cb_integrator_##id,
CB_INTEGRATOR_REGISTRY(CB_INTEGRATOR_DECLARE)
const cb_integrator_type *const cb_integrator_types[] = {CB_INTEGRATOR_REGISTRY(CB_INTEGRATOR_ENTRY) NULL};

const char *cb_integrator_name(int i) {
  for (int k = 0; k <= i; k++)
    if (!cb_integrator_types[k]) return NULL;
  return cb_integrator_types[i]->name;
}

const cb_integrator_type *cb_integrator_type_find(const char *name) {
  for (int i = 0; cb_integrator_types[i]; i++)
    if (strcmp(cb_integrator_types[i]->name, name) == 0) return cb_integrator_types[i];
  return NULL;
}

/* A type's parameters start with their cookie: the wrapper checks it without knowing the type's struct. */
_Static_assert(offsetof(cb_newton_params, cookie) == 0, "cookie first");
_Static_assert(offsetof(cb_nljacobi_params, cookie) == 0, "cookie first");
_Static_assert(offsetof(cb_pd_params, cookie) == 0, "cookie first");
_Static_assert(offsetof(cb_xpbd_params, cookie) == 0, "cookie first");
_Static_assert(offsetof(cb_lbfgs_params, cookie) == 0, "cookie first");
_Static_assert(offsetof(cb_vbd_params, cookie) == 0, "cookie first");
_Static_assert(offsetof(cb_shape_matching_params, cookie) == 0, "cookie first");

cb_integrator_params cb_integrator_params_default(void) {
  cb_integrator_params p = {.cookie = CB_PARAMS_COOKIE, .dt = 1.0 / 30, .damping = 1.0, .hook = NULL, .hook_ctx = NULL};
  return p;
}

/* coords = the free vertices' positions in x, in the unknowns' order (3 per free vertex). */
static void fill_coords(cb_integrator *it, const double *x) {
  const cb_scene *s = it->scene;
  for (int k = 0; k < s->model.nfree; k++)
    for (int a = 0; a < 3; a++) it->coords[3 * k + a] = x[3 * s->free_vertex[k] + a];
}

int cb_integrator_alloc(const char *method, cb_scene *scene, const cb_integrator_params *p, const void *type_params,
                        const char *solver, const cb_solver_params *sp, cb_integrator **out) {
  *out = NULL;
  const cb_integrator_type *t = cb_integrator_type_find(method);
  if (!t) return cb_fail("unknown integrator '%s'", method);
  int ck = cb_params_check(p->cookie, "integrator", "cb_integrator_params_default");
  if (ck == CB_OK && type_params && t->params_size) /* a type's parameters start with their cookie */
    ck = cb_params_check(*(const int *)type_params, t->name, "its type's cb_<type>_params_default");
  if (ck) return ck;
  if (!(p->dt > 0)) return cb_fail("integrator: dt must be > 0, got %g", p->dt);
  double mmax = 0;
  for (int i = 0; i < scene->mesh.nv; i++) mmax = fmax(mmax, scene->mass[i]);
  if (!isfinite(mmax / (p->dt * p->dt))) /* every implicit method's inertia term; 1/dt^2 alone may overflow */
    return cb_fail("integrator.dt = %g s is too small for double precision: the inertia term M/dt^2 of the heaviest "
                   "vertex (%g kg) is not a finite double; dt must be at least %.3g s",
                   p->dt, mmax, 2 * sqrt(mmax) / sqrt(DBL_MAX));
  if (!(p->damping >= 0 && p->damping <= 1))
    return cb_fail("integrator: damping must be in [0, 1], got %g", p->damping);
  if ((t->flags & CB_INTEGRATOR_LINEAR_SOLVER) && !solver) return cb_fail("%s: needs a linear solver", t->name);
  cb_integrator *it = cb_calloc(1, sizeof *it);
  if (!it) return CB_ENOMEM;
  it->type = t;
  it->scene = scene;
  it->sys = &scene->sys;
  it->params = *p;
  int st = CB_OK;
  if (t->params_size) { /* the type's parameters: the caller's, or the type's defaults */
    it->type_params = cb_malloc(1, t->params_size);
    if (!it->type_params) st = CB_ENOMEM;
    else if (type_params || t->params_default)
      memcpy(it->type_params, type_params ? type_params : t->params_default, t->params_size);
    else memset(it->type_params, 0, t->params_size);
  }
  if (st == CB_OK && t->size && !(it->state = cb_calloc(1, t->size))) st = CB_ENOMEM;
  if (st == CB_OK && !(it->x_start = cb_malloc((size_t)3 * (scene->mesh.nv > 0 ? scene->mesh.nv : 1), sizeof(double))))
    st = CB_ENOMEM;
  if (st == CB_OK && (t->flags & CB_INTEGRATOR_LINEAR_SOLVER)) {
    st = cb_solver_alloc(solver, sp, it->sys->A.n, &it->solver);
    if (st == CB_OK && (it->solver->type->flags & CB_SOLVER_USES_COORDS)) {
      if (!(it->coords = cb_malloc((size_t)it->sys->A.n, sizeof *it->coords))) st = CB_ENOMEM;
      else {
        fill_coords(it, scene->x0);
        it->solver->coords = it->coords;
      }
    }
    if (st == CB_OK) st = cb_solver_analyze(it->solver, &it->sys->A);
  }
  for (int k = 0; st == CB_OK && !(t->flags & CB_INTEGRATOR_STEP_FILTER) && k < it->sys->nterms; k++)
    if (it->sys->terms[k]->type->max_step &&
        !((t->flags & CB_INTEGRATOR_VERTEX_BOUNDS) && it->sys->terms[k]->type->vertex_bound))
      st = cb_fail("integrator.method: %s: the scene's term '%s' (%s) bounds every step by CCD (the line-search "
                   "filter, system.h), which %s does not call; newton and lbfgs do, and vbd keeps its vertex bounds "
                   "(docs/contact.md)",
                   t->name, it->sys->terms[k]->label, it->sys->terms[k]->type->name, t->name);
  int inited = 0;
  if (st == CB_OK) {
    inited = 1;
    st = t->init(it);
  }
  if (st) {
    if (inited) t->free(it); /* releases what init allocated before it failed */
    cb_solver_free(it->solver);
    free(it->coords);
    free(it->state);
    free(it->type_params);
    free(it->x_start);
    free(it);
    return st;
  }
  *out = it;
  return CB_OK;
}

/* The scene's contact terms' phase timers (cb_contact_stats: running totals), ms: broad phase, CCD, barrier. */
static void contact_timers(const cb_system *sys, double *t) {
  t[0] = t[1] = t[2] = 0;
  for (int k = 0; k < sys->nterms; k++) {
    const cb_contact_stats *cs = cb_contact_term_stats(sys->terms[k]);
    if (!cs) continue;
    t[0] += cs->broad_ms;
    t[1] += cs->ccd_ms;
    t[2] += cs->barrier_ms;
  }
}

int cb_integrator_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  memset(st, 0, sizeof *st);
  double c0[3], c1[3];
  contact_timers(&it->scene->sys, c0); /* before t0: the step's phases stay inside its wall time */
  double t0 = cb_now_ms();
  if (it->params.damping != 1.0) { /* v <- damping v, before the step's predictor (the lab's place); pins keep theirs */
    const cb_scene *s = it->scene;
    for (int k = 0; k < s->model.nfree; k++)
      for (int a = 0; a < 3; a++) v[3 * s->free_vertex[k] + a] *= it->params.damping;
  }
  if (it->solver) { /* the step's number and its starting positions, for a solver that reuses set-ups across steps or
                      builds from the geometry (solver.pc_reuse, solver.rigid_modes) */
    it->solver->step++;
    if (it->coords) fill_coords(it, x);
  }
  /* the step's start, for the responses that sweep x_start -> x (contact.method = bridson) */
  memcpy(it->x_start, x, (size_t)3 * it->scene->mesh.nv * sizeof(double));
  /* the terms that freeze quantities for the step (IPC's lagged friction) do so at its start state */
  int r = cb_system_begin_step(&it->scene->sys, x, it->params.dt);
  if (r == CB_OK) {
    r = it->type->step(it, x, v, st);
    int post = cb_scene_post_step(it->scene, it->x_start, x, v, it->params.dt); /* the scene's post-step responses */
    if (r == CB_OK && post) r = post;
  }
  st->wall_ms = cb_now_ms() - t0;
  contact_timers(&it->scene->sys, c1);
  st->contact_broad_ms = c1[0] - c0[0];
  st->contact_ccd_ms = c1[1] - c0[1];
  st->contact_barrier_ms = c1[2] - c0[2];
  st->status = r;
  return r;
}

int cb_integrator_measure(const cb_integrator *it, cb_objective *o, const double *x, double *gF, int iter, double *g0,
                          double g_hat, cb_newton_hook hook, cb_step_stats *st) {
  double t0 = cb_now_ms();
  double F = cb_objective_eval(o, x, gF, NULL);
  double gn = cblas_dnrm2(3 * it->scene->model.nfree, gF, 1);
  st->assemble_ms += cb_now_ms() - t0;
  if (iter == 0) *g0 = gn;
  st->F = F;
  st->grad_norm = gn;
  st->rel_grad = *g0 > 0 ? gn / *g0 : 0.0;
  st->rel_grad_hat = g_hat < 0 ? st->rel_grad : g_hat > 0 ? gn / g_hat : 0.0;
  st->newton_iters = iter;
  if (!isfinite(F) || !isfinite(gn)) return CB_DIVERGED;
  if (hook) {
    cb_newton_event ev;
    memset(&ev, 0, sizeof ev);
    ev.alpha = 1.0;
    ev.iter = iter;
    ev.F = F;
    ev.grad_norm = gn;
    ev.rel_grad = st->rel_grad;
    ev.x = x;
    hook(it->params.hook_ctx, CB_NEWTON_GRADIENT, &ev);
  }
  return CB_OK;
}

void cb_integrator_free(cb_integrator *it) {
  if (!it) return;
  it->type->free(it);
  cb_solver_free(it->solver);
  free(it->coords);
  free(it->state);
  free(it->type_params);
  free(it->x_start);
  free(it);
}
