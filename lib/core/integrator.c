/* Integrator registry and shared plumbing. */
#include <clothbench/integrator.h>

#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include <clothbench/timer.h>

const cb_integrator_type *const cb_integrator_types[] = {&cb_integrator_explicit, &cb_integrator_newton, NULL};

const char *cb_integrator_name(int i) {
  for (int k = 0; k <= i; k++)
    if (!cb_integrator_types[k]) return NULL;
  return cb_integrator_types[i]->name;
}

cb_integrator_params cb_integrator_params_default(void) {
  cb_integrator_params p = {.dt = 1.0 / 30, .max_iters = 50, .tol = 1e-8, .tol_dx = 0, .init_predict = 1,
                            .line_search = 0, .definiteness = CB_DEF_DROP, .hook = NULL, .hook_ctx = NULL};
  return p;
}

int cb_integrator_params_from_config(const cb_config *c, cb_integrator_params *p) {
  *p = cb_integrator_params_default();
  p->dt = c->dt;
  p->max_iters = c->max_iters;
  p->tol = c->tol;
  p->tol_dx = c->tol_dx;
  p->init_predict = strcmp(c->init, "x0") != 0;
  p->line_search = c->line_search;
  return cb_definiteness_from_name(c->definiteness, &p->definiteness);
}

int cb_integrator_alloc(const char *method, cb_scene *scene, const cb_integrator_params *p, const char *solver,
                        const cb_solver_params *sp, cb_integrator **out) {
  *out = NULL;
  const cb_integrator_type *t = NULL;
  for (int i = 0; cb_integrator_types[i]; i++)
    if (strcmp(cb_integrator_types[i]->name, method) == 0) t = cb_integrator_types[i];
  if (!t) return cb_fail("unknown integrator '%s'", method);
  if (!(p->dt > 0)) return cb_fail("integrator: dt must be > 0, got %g", p->dt);
  /* Choi-Ko changes the springs' energy, which is fixed when the scene is built */
  int choi_ko = 0, springs = 0;
  for (int k = 0; k < scene->sys.nterms; k++) {
    springs += scene->sys.terms[k]->type == cb_term_spring;
    choi_ko |= cb_spring_term_is_choi_ko(scene->sys.terms[k]);
  }
  if (springs && choi_ko != (p->definiteness == CB_DEF_CHOI_KO))
    return cb_fail("integrator: definiteness '%s' does not match the scene, whose springs were built %s the Choi-Ko "
                   "response (set integrator.definiteness before building the scene)",
                   cb_definiteness_names[p->definiteness], choi_ko ? "with" : "without");
  cb_integrator *it = cb_calloc(1, sizeof *it);
  if (!it) return CB_ENOMEM;
  it->type = t;
  it->scene = scene;
  it->sys = &scene->sys;
  it->params = *p;
  int st = CB_OK;
  if (solver && t != &cb_integrator_explicit) {
    st = cb_solver_alloc(solver, sp, it->sys->A.n, &it->solver);
    if (st == CB_OK) st = cb_solver_analyze(it->solver, &it->sys->A);
  }
  if (st == CB_OK) st = t->alloc(it); /* cleans up after itself on failure */
  if (st) {
    cb_solver_free(it->solver);
    free(it);
    return st;
  }
  *out = it;
  return CB_OK;
}

int cb_integrator_from_config(cb_scene *scene, cb_integrator **out) {
  cb_integrator_params p;
  int st = cb_integrator_params_from_config(&scene->cfg, &p);
  if (st) return st;
  cb_solver_params sp = cb_solver_params_from_config(&scene->cfg);
  return cb_integrator_alloc(scene->cfg.method, scene, &p, scene->cfg.solver, &sp, out);
}

int cb_integrator_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  memset(st, 0, sizeof *st);
  double t0 = cb_now_ms();
  int r = it->type->step(it, x, v, st);
  st->wall_ms = cb_now_ms() - t0;
  st->status = r;
  return r;
}

void cb_integrator_free(cb_integrator *it) {
  if (!it) return;
  it->type->free(it);
  cb_solver_free(it->solver);
  free(it);
}
