/* One step of a method from a fixed start state against the converged step: step_bench.h. */
#include "step_bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bind.h"
#include "reference.h"
#include <clothbench/run.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

void cb_step_state_free(cb_step_state *S) {
  cb_objective_free(&S->obj);
  cb_scene_free(S->s);
  free(S->x0);
  free(S->v0);
  free(S->xm);
  free(S->vm);
  free(S->xstar);
  free(S->x);
  free(S->v);
  memset(S, 0, sizeof *S);
}

int cb_step_state_init(cb_step_state *S, const char *label, const cb_config *c, cb_scene *s, int frames) {
  memset(S, 0, sizeof *S);
  S->label = label;
  S->s = s;
  S->c = *c;
  cb_integrator *it = NULL;
  cb_run run;
  memset(&run, 0, sizeof run);
  int st = cb_integrator_from_config(&S->c, S->s, NULL, &it);
  if (st == CB_OK) st = cb_run_init(&run, S->s, it);
  if (st == CB_OK) {
    S->n3 = 3 * S->s->mesh.nv;
    size_t b = (size_t)S->n3 * sizeof(double);
    S->x0 = malloc(b);
    S->v0 = malloc(b);
    S->xstar = malloc(b);
    S->x = malloc(b);
    S->v = malloc(b);
    if (frames > 0) {
      S->xm = malloc(b);
      S->vm = malloc(b);
    }
    if (!S->x0 || !S->v0 || !S->xstar || !S->x || !S->v || (frames > 0 && (!S->xm || !S->vm)))
      st = cb_fail_status(CB_ENOMEM, "out of memory");
  }
  for (int f = 0; st == CB_OK && f < frames; f++) {
    if (f == frames - 1) { /* the frame before the start state: the warm-up step's start */
      memcpy(S->xm, run.x, (size_t)S->n3 * sizeof(double));
      memcpy(S->vm, run.v, (size_t)S->n3 * sizeof(double));
    }
    int sst = cb_run_step(&run);
    if (cb_status_is_fatal(sst))
      st = cb_fail_status(sst, "scene %s: start state, frame %d: %s", label, f + 1, cb_error_message());
  }
  if (st == CB_OK) {
    size_t b = (size_t)S->n3 * sizeof(double);
    {
      memcpy(S->x0, run.x, b);
      memcpy(S->v0, run.v, b);
    }
  }
  cb_run_free(&run);
  cb_integrator_free(it);
  if (st == CB_OK) {
    cb_reference_params rp = cb_reference_params_default();
    rp.dt = S->c.dt;
    cb_reference *ref = NULL;
    cb_reference_stats rs;
    st = cb_reference_alloc(S->s, &rp, &ref);
    if (st == CB_OK) {
      int rst = cb_reference_step(ref, S->x0, S->v0, S->xstar, &rs);
      if (rst > CB_NOT_CONVERGED || rst < 0)
        st = cb_fail_status(rst, "scene %s: reference step after %d frames: %s", label, frames, cb_status_name(rst));
    }
    cb_reference_free(ref);
  }
  if (st == CB_OK) st = cb_objective_init(&S->obj, S->s);
  if (st == CB_OK) {
    cb_objective_begin(&S->obj, S->x0, S->v0, S->c.dt);
    S->Fhat = cb_objective_eval(&S->obj, S->obj.xhat, NULL, NULL);
    S->Fstar = cb_objective_eval(&S->obj, S->xstar, NULL, NULL);
  }
  if (st) cb_step_state_free(S);
  return st;
}

int cb_step_classify(int status, double rel_grad_hat) {
  if (cb_status_is_fatal(status)) return status;
  if (!(rel_grad_hat <= CB_STEP_GROWTH_BOUND)) return CB_DIVERGED; /* NaN fails the test too */
  return status;
}

double cb_step_obj_error(cb_step_state *S, const double *x) {
  double den = S->Fhat - S->Fstar;
  return den != 0 ? (cb_objective_eval(&S->obj, x, NULL, NULL) - S->Fstar) / den : NAN;
}

int cb_step_config(const cb_step_state *S, const char *const *sets, cb_config *out) {
  enum { MAXSETS = 16 };
  *out = S->c;
  int st = CB_OK, n = 0;
  for (; st == CB_OK && sets && sets[n] && n < MAXSETS; n++) st = cb_config_set(out, sets[n]);
  if (st == CB_OK && sets && sets[n]) st = cb_fail("more than %d sets", MAXSETS);
  if (st == CB_OK) st = cb_config_set(out, "integrator.damping=1");
  if (st == CB_OK) st = cb_config_validate(out);
  if (st) {
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", cb_error_message());
    return cb_fail_status(st, "scene %s: %s", S->label, msg);
  }
  return CB_OK;
}

int cb_step_once(cb_step_state *S, const cb_config *c, cb_newton_hook hook, void *ctx, cb_step_result *r,
                 double *wall) {
  cb_integrator_params ip;
  cb_integrator_params_from_config(c, &ip);
  ip.hook = hook;
  ip.hook_ctx = ctx;
  cb_integrator *it = NULL;
  double t0 = cb_now_ms();
  int st = cb_integrator_from_config(c, S->s, &ip, &it);
  if (st) return st;
  r->alloc_ms = cb_now_ms() - t0; /* pd, lbfgs: their one factorisation */
  double warm_setup = 0.0;
  if ((it->type->flags & CB_INTEGRATOR_HISTORY) && S->xm) { /* the untimed, unobserved warm-up step */
    cb_step_stats ws;
    memcpy(S->x, S->xm, (size_t)S->n3 * sizeof(double));
    memcpy(S->v, S->vm, (size_t)S->n3 * sizeof(double));
    it->params.hook = NULL;
    cb_integrator_step(it, S->x, S->v, &ws); /* its status is not the timed step's (which records its own) */
    it->params.hook = hook;
    warm_setup = ws.factor_ms; /* a once-per-run rho estimate happens here */
  }
  memcpy(S->x, S->x0, (size_t)S->n3 * sizeof(double));
  memcpy(S->v, S->v0, (size_t)S->n3 * sizeof(double));
  cb_step_stats ss;
  r->status = cb_integrator_step(it, S->x, S->v, &ss);
  /* the fixed-iteration methods' factor_ms is the auto rho's estimate, once per run, not a step's cost
     (pd factorises in alloc, alloc_ms); Newton's is its factorisations, which are */
  int once = strcmp(it->type->name, "newton") != 0;
  *wall = ss.wall_ms - (once ? ss.factor_ms : 0.0);
  r->setup_ms = ss.factor_ms + warm_setup;
  r->rel_grad = ss.rel_grad_hat;
  r->status = cb_step_classify(r->status, ss.rel_grad_hat);
  r->iters = ss.newton_iters;
  r->rho = ss.rho;
  r->error = cb_step_error(S->s, S->x, S->xstar, S->x0);
  r->obj_error = cb_step_obj_error(S, S->x);
  r->global_path = ss.global_path;
  cb_integrator_free(it);
  return CB_OK;
}

int cb_step_fallback(cb_step_state *S, const cb_config *c, const cb_config *fb, cb_newton_hook hook, void *ctx,
                     cb_step_result *r, double *wall) {
  int st = cb_step_once(S, c, hook, ctx, r, wall);
  r->fallback = 0;
  if (st || !fb || r->status != CB_NOT_SPD) return st;
  double w2;
  st = cb_step_once(S, fb, hook, ctx, r, &w2);
  r->fallback = 1;
  *wall += w2;
  return st;
}

int cb_step_repeat(cb_step_state *S, const char *const *sets, cb_newton_hook hook, void *ctx, cb_step_result *r) {
  static cb_config c; /* large (the pins and overrides): not on the stack */
  int st = cb_step_config(S, sets, &c);
  if (st) return st;
  double walls[5], w;
  int reps = 0;
  memset(r, 0, sizeof *r);
  do {
    if ((st = cb_step_once(S, &c, hook, ctx, r, &w))) return st;
    walls[reps++] = w;
    cb_timing_add(&r->wall, w);
    if (hook) break;
  } while (reps < 5 && cb_median(walls, reps) * reps < 30.0);
  r->wall_ms = cb_median(walls, reps);
  return CB_OK;
}

int cb_step_time_group(int quick, cb_step_state *S, const char *const *const *sets, const char *const *const *fallback,
                       int n, cb_step_result *r) {
  return cb_step_time_group_ex(quick, INFINITY, S, sets, fallback, n, r, NULL);
}

int cb_step_time_group_ex(int quick, double once_ms, cb_step_state *S, const char *const *const *sets,
                          const char *const *const *fallback, int n, cb_step_result *r, double *const *xend) {
  static cb_config c[CB_STEP_GROUP_MAX], cf[CB_STEP_GROUP_MAX];
  if (n > CB_STEP_GROUP_MAX) return cb_fail("step group: more than %d steps in one group", CB_STEP_GROUP_MAX);
  for (int i = 0; i < n; i++) {
    int st = cb_step_config(S, sets[i], &c[i]);
    if (st == CB_OK && fallback && fallback[i]) st = cb_step_config(S, fallback[i], &cf[i]);
    if (st) return st;
    memset(&r[i], 0, sizeof r[i]);
  }
  double spent = 0;
  for (int round = 0; cb_timing_more(quick, round, spent); round++)
    for (int i = 0; i < n; i++) {
      if (round > 0 && isfinite(once_ms) && !(r[i].wall.ms[0] < once_ms))
        continue; /* a long step: its one time is its median */
      cb_step_result x;
      double w;
      const cb_config *fb = fallback && fallback[i] ? &cf[i] : NULL;
      int st = cb_step_fallback(S, &c[i], fb, NULL, NULL, &x, &w);
      if (st == CB_OK && cb_timing_warm(w))
        st = cb_step_fallback(S, &c[i], fb, NULL, NULL, &x, &w); /* that was the warm-up */
      if (st) return st;
      if (round == 0) {
        cb_timing keep = r[i].wall;
        r[i] = x;
        r[i].wall = keep;
        if (xend && xend[i]) memcpy(xend[i], S->x, (size_t)S->n3 * sizeof(double));
      }
      cb_timing_add(&r[i].wall, w);
      spent += w;
    }
  for (int i = 0; i < n; i++) r[i].wall_ms = cb_timing_median(&r[i].wall);
  return CB_OK;
}
