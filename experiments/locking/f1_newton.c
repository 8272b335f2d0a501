/* locking, F1 (results/locking_newton.csv, locking_newton_steps.csv): one
 * implicit Euler step of the lab cloth per model, timed, |grad F| traced. */
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "csv.h"
#include "bind.h"
#include "stats.h"

#include "locking.h"

/* ---- F1: one implicit Euler step of the lab cloth, timed ------------------------------ */

typedef struct {
  FILE *f;
  const char *model;
  int rep;
  double t0;
} trace_ctx;
static void trace_hook(void *ctx, int event, const cb_newton_event *ev) {
  trace_ctx *c = ctx;
  if (event != CB_NEWTON_GRADIENT) return;
  cb_csv_printf(c->f, "%s,%d,%d,%.17g,%.17g,%.17g,%.4f\n", c->model, c->rep, ev->iter, ev->F, ev->grad_norm,
                ev->rel_grad, cb_now_ms() - c->t0);
}

/* One model's timed step: its scene and integrator, and the state after the warm-up steps. */
typedef struct {
  cb_scene *s;
  cb_integrator *it;
  double *x, *v, *xs, *vs;
  size_t n3;
} f1_model;

static void f1_model_free(f1_model *m) {
  free(m->x);
  free(m->v);
  free(m->xs);
  free(m->vs);
  cb_integrator_free(m->it);
  cb_scene_free(m->s);
  memset(m, 0, sizeof *m);
}

/* The "step" scene sm on the n^2 lab cloth: five steps to swing down (drop), then its own policy
 * for the timed step, to a tight tolerance. */
static int f1_model_init(const scene_plan *sm, int n, f1_model *m) {
  memset(m, 0, sizeof *m);
  char sn[32], sm_mass[64], sd[48];
  snprintf(sn, sizeof sn, "mesh.n=%d", n);
  snprintf(sm_mass, sizeof sm_mass, "material.vertex_mass=%.17g", 441.0 / ((double)n * n)); /* the lab's 441 kg */
  snprintf(sd, sizeof sd, "integrator.definiteness=%s", sm->definiteness);
  const char *sets[] = {sn, sm_mass, NULL};
  cb_config c;
  int bs = cb_scene_decl_build(&E, &sm->scene, sets, &c, &m->s);
  if (bs) return bs;
  cb_integrator_params ip;
  cb_integrator_params_from_config(&c, &ip);
  if ((bs = cb_integrator_from_config(&c, m->s, &ip, &m->it))) return bs;
  m->n3 = 3 * (size_t)m->s->mesh.nv;
  m->x = malloc(m->n3 * sizeof(double));
  m->v = calloc(m->n3, sizeof(double));
  m->xs = malloc(m->n3 * sizeof(double));
  m->vs = malloc(m->n3 * sizeof(double));
  if (!m->x || !m->v || !m->xs || !m->vs) return cb_fail_status(CB_ENOMEM, "out of memory");
  memcpy(m->x, m->s->x0, m->n3 * sizeof(double));
  cb_step_stats st;
  for (int k = 0; k < 5; k++) {
    memset(&st, 0, sizeof st);
    cb_integrator_step(m->it, m->x, m->v, &st);
  } /* swing down */
  cb_newton_params *np = m->it->type_params;
  cb_config cd = c; /* the method's policy for the timed step (the warm-up used drop) */
  if ((bs = cb_config_set(&cd, sd)) || (bs = cb_newton_params_from_config(&cd, np))) return bs;
  np->tol = 1e-12;
  np->tol_dx = 1e-12;
  np->max_iters = 300;
  return CB_OK;
}

/* One timed step of m from its state (traced into f with rep when f is not NULL); *ms its wall time. */
static int f1_model_step(f1_model *m, FILE *f, const char *model, int rep, cb_step_stats *st, double *ms) {
  memcpy(m->xs, m->x, m->n3 * sizeof(double));
  memcpy(m->vs, m->v, m->n3 * sizeof(double));
  trace_ctx tc = {f, model, rep, cb_now_ms()};
  m->it->params.hook = f ? trace_hook : NULL;
  m->it->params.hook_ctx = &tc;
  memset(st, 0, sizeof *st);
  int rc = cb_integrator_step(m->it, m->xs, m->vs, st);
  *ms = cb_now_ms() - tc.t0;
  m->it->params.hook = NULL;
  return rc;
}

/* The one cell of F1's timed step: every "step" scene (model, Hessian, definiteness of the timed
 * step) timed in interleaved rounds (stats.h: 3 with --quick, 2-5 in a full run by their cost; a
 * step under 25 ms timed right after an untimed one of its own); a row per model and round, rep
 * the round; the step's |grad F| per iteration traced at every round. */
int lk_f1_newton_cell(long i, void *ctx, FILE *const *out) {
  (void)i;
  int quick = *(const int *)ctx, n = E.smoke ? 8 : quick ? 32 : 64, st = CB_OK;
  FILE *f = out[T_NEWTON], *fs = out[T_STEPS];
  static f1_model M[NSCENES];
  for (int k = 0; k < nsteps; k++) memset(&M[k], 0, sizeof M[k]);
  for (int k = 0; st == CB_OK && k < nsteps; k++) st = f1_model_init(&SCENES[step_idx[k]], n, &M[k]);
  double spent = 0;
  for (int round = 0; st == CB_OK && cb_timing_more(quick, round, spent); round++)
    for (int k = 0; k < nsteps; k++) {
      const char *model = SCENES[step_idx[k]].scene.label;
      cb_step_stats ss;
      double ms;
      char *buf = NULL;
      size_t len = 0;
      FILE *tf = open_memstream(&buf, &len); /* the trace, kept if this run is the repeat */
      if (!tf) {
        st = cb_fail_status(CB_ENOMEM, "out of memory");
        break;
      }
      int rc = f1_model_step(&M[k], tf, model, round, &ss, &ms);
      if (cb_timing_warm(ms)) { /* that was the warm-up: the repeat is the next run */
        fclose(tf);
        free(buf);
        buf = NULL;
        if (!(tf = open_memstream(&buf, &len))) {
          st = cb_fail_status(CB_ENOMEM, "out of memory");
          break;
        }
        rc = f1_model_step(&M[k], tf, model, round, &ss, &ms);
      }
      fclose(tf);
      fwrite(buf, 1, len, f);
      free(buf);
      spent += ms;
      cb_csv_printf(fs, "%s,%d,%d,%d,%d,%.17g,%.4f,%.4f,%.4f,%.4f,%s\n", model, n, round, ss.newton_iters,
                    ss.factorizations, ss.rel_grad, ss.assemble_ms, ss.factor_ms, ss.solve_ms, ms, cb_status_name(rc));
    }
  for (int k = 0; k < nsteps; k++) f1_model_free(&M[k]);
  return st;
}
