/* definiteness (claims H1, H2): how often Newton's matrix A = M/dt^2 + H is
 * indefinite on scenes that compress springs, and what each fix of
 * integrator.definiteness (drop, mirror, shift, choi-ko) costs.
 * Physics and witnesses live in lib/ (definiteness.c, spd_probe.c,
 * newton_trace.c); this program sweeps scenes x policies and writes CSV. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/definiteness.h>
#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include "csv.h"
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "scene_decl.h"
#include "sweep.h"
#include "newton_trace.h"
#include "stats.h"

enum { NPOL = 5 };
static const char *const policies[NPOL] = {"none", "drop", "mirror", "shift", "choi-ko"};

/* Scenes. Roles: "trajectory" = Newton steps from the scene's start under every
 * policy (tables main, steps, runs; one cell per scene); "static" = the
 * spring pair held still at a list of compressions (table pair; one cell per
 * policy variant of pair_variants). steps[0] full, steps[1] --quick. */
typedef struct {
  cb_scene_decl scene;
  int steps[2];
} scene_plan;
#define PAIR "mesh.type=chain", "mesh.n=3", "mesh.size=2", "mesh.plane=xy", "scene.pins=0 2"
static const scene_plan scenes[] = {
    {{"hanging", "hanging.ini", {NULL}, "trajectory"}, {20, 3}}, /* the lab cloth falling from two corners */
    {{"scaled", "hanging.ini", {"scene.initial_scale=0.7", NULL}, "trajectory"},
     {20, 3}}, /* starts at 0.7x its rest shape (pins too) */
    {{"driven",
      "hanging.ini", /* left and right edges of the 21x21 grid (vertex (i, j) is j*21 + i) pushed together: buckling */
      {"scene.pins=0 21 42 63 84 105 126 147 168 189 210 231 252 273 294 315 336 357 378 399 420 "
       "20 41 62 83 104 125 146 167 188 209 230 251 272 293 314 335 356 377 398 419 440",
       "scene.pin_squeeze=2 0 0", NULL},
      "trajectory"},
     {30, 3}},
    {{"pair", "hanging.ini", {PAIR, "scene.initial_scale=0.7", NULL}, "trajectory"},
     {30, 10}},                                                       /* two springs compressed to 0.7 L between pins */
    {{"pair_static", "hanging.ini", {PAIR, NULL}, "static"}, {0, 0}}, /* the same pair, positions set by hand */
};
enum { NSCENES = sizeof scenes / sizeof scenes[0] };
/* the static pair's policy variants: policy and (choi-ko) buckling stiffness */
static const char *const pair_pols[] = {"none", "drop", "mirror", "choi-ko", "choi-ko", "choi-ko", "choi-ko"};
static const char *const pair_kbs[] = {"0.01", "0.01", "0.01", "0.01", "0.1", "1", "10"};
enum { NPAIR = sizeof pair_pols / sizeof pair_pols[0] };
enum { T_IT, T_STEPS, T_RUNS, T_PAIR }; /* tables, in the order opened */

/* eigenvalues of A = M/dt^2 + H and the shift mu (A + mu I) are in A's units, N/m; |grad F| in N */
#define IT_HEAD \
  "scene,policy,step,newton_iter,system,spd,min_eig_n_per_m,min_eig_res_n_per_m,mu_n_per_m,spd_exact," \
  "min_eig_exact_n_per_m,compressed_frac,cg_breakdown,cg_status,cg_iters,rel_grad,grad_norm_n,f_j,energy_j,wall_ms," \
  "status"
#define RUN_HEAD \
  "scene,policy,steps,steps_done,steps_converged,newton_iters,systems,not_spd,indefinite_exact," \
  "cg_breakdowns,mu_max_n_per_m,factorizations,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,probe_ms," \
  "final_f_j," \
  "final_energy_j,final_rel_grad," \
  "shape_diff_none_m,shape_diff_drop_m,status"

static void put_row(FILE *f, const char *sc, const char *pol, int step, const cb_newton_trace_row *r, int exact_run) {
  cb_csv_printf(f, "%s,%s,%d,%d,%d,", sc, pol, step, r->iter, r->system);
  if (r->system) {
    const cb_spd_probe_result *u = &r->used, *x = exact_run ? &r->used : &r->exact;
    int spd_x = exact_run ? r->status != CB_NOT_SPD : x->cholmod_status == CB_OK;
    cb_csv_printf(f, "%d,%.17g,%.17g,%.17g,%d,%.17g,", r->status != CB_NOT_SPD, u->min_eig, u->min_eig_res, r->mu,
                  spd_x, x->min_eig);
  } else {
    fputs(",,,,,,", f);
  }
  cb_csv_printf(f, "%.17g,", r->compressed_frac);
  if (r->system)
    cb_csv_printf(f, "%d,%s,%d,", r->used.cg_status == CB_INDEFINITE, cb_status_name(r->used.cg_status),
                  r->used.cg_iters);
  else fputs(",,,", f);
  cb_csv_printf(f, "%.17g,%.17g,%.17g,%.17g,%.6f,%s\n", r->rel_grad, r->grad_norm, r->F, r->energy, r->wall_ms,
                cb_status_name(r->status));
}

/* max_i |x_i - y_i| over vertices (Euclidean), or "" when y is missing */
static void put_diff(FILE *f, const double *x, const double *y, int nv) {
  if (!x || !y) {
    fputs(",", f);
    return;
  }
  double m = 0;
  for (int i = 0; i < nv; i++)
    m = fmax(m, hypot(hypot(x[3 * i] - y[3 * i], x[3 * i + 1] - y[3 * i + 1]), x[3 * i + 2] - y[3 * i + 2]));
  cb_csv_printf(f, "%.17g,", m);
}

typedef struct {
  int steps_done, converged, iters, systems, not_spd, indef_x, cg_bd, fact, status;
  double mu, probe, F, energy, rel_grad, *x;
} tally;

static int run_policy(const cb_experiment *e, const scene_plan *sd, int p, FILE *it, FILE *stp, tally *t, int *nv) {
  char pol[64];
  snprintf(pol, sizeof pol, "integrator.definiteness=%s", policies[p]);
  /* |grad F(x0)| can be tiny at rest: stop at round-off */
  const char *sets[] = {"integrator.tol_dx=1e-9", pol, NULL},
             *refsets[] = {sets[0], "integrator.definiteness=none", NULL};
  const char *label = sd->scene.label;
  int steps = sd->steps[e->quick];
  cb_scene *s = NULL, *ref = NULL; /* ref: linear springs, for the exact (none) matrix at our iterates */
  cb_integrator *integ = NULL;
  cb_newton_trace tr = {0};
  cb_run run = {0};
  cb_integrator_params ip;
  cb_config cfg;
  cb_newton_params np;
  int st = cb_scene_decl_build(e, &sd->scene, sets, &cfg, &s);
  if (st == CB_OK && p > 0) st = cb_scene_decl_build(e, &sd->scene, refsets, NULL, &ref);
  if (st == CB_OK) st = cb_integrator_params_from_config(&cfg, &ip);
  if (st == CB_OK) st = cb_newton_params_from_config(&cfg, &np);
  if (st == CB_OK)
    st = cb_newton_trace_init(&tr, s, ref ? &ref->sys : NULL, ip.dt, np.max_iters + 1, CB_PROBE_EIG | CB_PROBE_CG,
                              CB_PROBE_CHOLMOD | CB_PROBE_EIG, NULL);
  ip.hook = cb_newton_trace_hook;
  ip.hook_ctx = &tr;
  if (st == CB_OK) st = cb_integrator_from_config(&cfg, s, &ip, &integ);
  if (st == CB_OK) st = cb_run_init(&run, s, integ);
  for (int k = 0; st == CB_OK && k < steps; k++) {
    cb_newton_trace_begin_step(&tr);
    t->status = cb_run_step(&run);
    cb_newton_trace_end_step(&tr, t->status);
    if ((st = tr.error)) break;
    const cb_step_stats *ss = &run.last;
    /* no iterate was seen (the step failed before any hook): its energy and compression were not measured */
    cb_newton_trace_row none_seen = {.energy = cb_csv_na(), .compressed_frac = cb_csv_na()};
    const cb_newton_trace_row *fin = tr.nrows ? &tr.rows[tr.nrows - 1] : &none_seen;
    double wall = ss->wall_ms - tr.probe_ms; /* the integrator's time, probes excluded */
    for (int r = 0; r < tr.nrows; r++) {
      const cb_newton_trace_row *w = &tr.rows[r];
      put_row(it, label, policies[p], run.step, w, p == 0);
      t->systems += w->system;
      t->not_spd += w->system && w->status == CB_NOT_SPD;
      t->indef_x += w->system && (p == 0 ? w->status == CB_NOT_SPD || w->used.min_eig < 0
                                         : w->exact.cholmod_status == CB_NOT_SPD || w->exact.min_eig < 0);
      t->cg_bd += w->system && w->used.cg_status == CB_INDEFINITE;
    }
    cb_csv_printf(stp, "%s,%s,%d,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.6f,%s\n", label, policies[p],
                  run.step, run.t, ss->newton_iters, ss->factorizations, ss->F, fin->energy, run.kinetic, ss->rel_grad,
                  fin->compressed_frac, ss->shift_mu, wall, cb_status_name(t->status));
    t->steps_done++;
    t->converged += t->status == CB_OK;
    t->iters += ss->newton_iters;
    t->fact += ss->factorizations;
    t->mu = fmax(t->mu, ss->shift_mu);
    t->probe += tr.probe_ms;
    t->F = ss->F;
    t->energy = fin->energy;
    t->rel_grad = ss->rel_grad;
    if (cb_status_is_fatal(t->status)) break;
  }
  if (st == CB_OK) {
    *nv = s->mesh.nv;
    char obj[1024], suffix[128];
    snprintf(suffix, sizeof suffix, "%s_%s.obj", label, policies[p]);
    cb_experiment_side_path(e, suffix, obj, sizeof obj);
    st = cb_mesh_write_obj(&s->mesh, run.x, obj); /* the final (or failing) state */
    if (t->steps_done == steps && !cb_status_is_fatal(t->status) && (t->x = malloc((size_t)3 * *nv * sizeof(double))))
      memcpy(t->x, run.x, (size_t)3 * *nv * sizeof(double)); /* a finished run is a reference */
  }
  cb_run_free(&run);
  cb_integrator_free(integ);
  cb_newton_trace_free(&tr);
  cb_scene_free(s);
  cb_scene_free(ref);
  return st;
}

/* The run of policy p on sd again, without the trace (no probes, no hook): the integrator's time over
 * the same steps, stopping where the traced run stopped (a fatal status). */
static int timed_run(const cb_experiment *e, const scene_plan *sd, int p, double *ms) {
  char pol[64];
  snprintf(pol, sizeof pol, "integrator.definiteness=%s", policies[p]);
  const char *sets[] = {"integrator.tol_dx=1e-9", pol, NULL};
  cb_scene *s = NULL;
  cb_integrator *integ = NULL;
  cb_run run = {0};
  cb_config cfg;
  int st = cb_scene_decl_build(e, &sd->scene, sets, &cfg, &s);
  if (st == CB_OK) st = cb_integrator_from_config(&cfg, s, NULL, &integ);
  if (st == CB_OK) st = cb_run_init(&run, s, integ);
  *ms = 0;
  for (int k = 0; st == CB_OK && k < sd->steps[e->quick]; k++) {
    int ss = cb_run_step(&run);
    *ms += run.last.wall_ms;
    if (cb_status_is_fatal(ss)) break;
  }
  cb_run_free(&run);
  cb_integrator_free(integ);
  cb_scene_free(s);
  return st;
}

/* The spring pair held still: two springs (L = 1) compressed to l = ratio L
 * between pinned ends, the middle vertex free; H and A restricted to 1, 2 or
 * 3 dimensions. Prediction: A's eigenvalues are m/dt^2 + 2 (along) and
 * m/dt^2 + 2 (transverse, twice), the spring's eigenvalues doubled. */
static int pair_cell(const cb_experiment *e, const cb_scene_decl *sd, int p, FILE *f) {
  static const double ratios[] = {1.05, 1.0, 0.99, 0.97, 0.95, 0.94, 0.9, 0.8, 0.7, 0.5, 0.3, 0.1};
  const char *const *pols = pair_pols, *const *kbs = pair_kbs;
  char pol[64], kb[64];
  snprintf(pol, sizeof pol, "integrator.definiteness=%s", pols[p]);
  snprintf(kb, sizeof kb, "material.buckling_kb=%s", kbs[p]);
  const char *sets[] = {pol, kb, NULL};
  cb_scene *s = NULL;
  cb_definiteness def = CB_DEF_NONE;
  cb_config cfg;
  int st = cb_scene_decl_build(e, sd, sets, &cfg, &s);
  if (st == CB_OK) st = cb_definiteness_from_name(pols[p], &def);
  for (size_t r = 0; st == CB_OK && r < sizeof ratios / sizeof ratios[0]; r++) {
    double q = ratios[r], x[9] = {-q, 0, 0, 0, 0, 0, q, 0, 0}, m = s->mass[1], s2 = 1.0 / (cfg.dt * cfg.dt);
    double k = cfg.stretch_k, along = k, tr = k * (1 - 1 / q), Eb, dEb, d2Eb; /* one spring: k, k(1 - L/l) */
    cb_choi_ko ck;
    if (def == CB_DEF_CHOI_KO && (st = cb_choi_ko_init(&ck, k, 1.0, cfg.buckling_kb)) == CB_OK) {
      cb_choi_ko_eval(&ck, q, &Eb, &dEb, &d2Eb);
      along = d2Eb; /* E''(l) */
      tr = dEb / q; /* E'(l)/l */
    }
    tr = cb_definiteness_transverse(def, tr);
    for (int dim = 1; dim <= 3 && st == CB_OK; dim++) {
      int keep[3] = {1, dim >= 2, dim >= 3}, ok_h, ok_a;
      double lh, la;
      cb_system_assemble(&s->sys, x, 0.0, def, 0.0); /* H */
      st = cb_dense_restricted_spd(&s->sys.A, keep, &lh, &ok_h);
      cb_system_assemble(&s->sys, x, s2, def, 0.0); /* A = M/dt^2 + H */
      if (st == CB_OK) st = cb_dense_restricted_spd(&s->sys.A, keep, &la, &ok_a);
      double pred = m * s2 + 2 * (dim == 1 ? along : fmin(along, tr));
      if (st == CB_OK)
        cb_csv_printf(f, "%d,%s,%s,%.17g,%.17g,%.17g,%.17g,%d\n", dim, pols[p], def == CB_DEF_CHOI_KO ? kbs[p] : "", q,
                      lh, la, pred, ok_a);
    }
  }
  cb_scene_free(s);
  return st;
}

typedef struct {
  const cb_experiment *e;
  int traj[NSCENES], ntraj, stat[NSCENES], nstat; /* scene indices by role */
  double cost[NSCENES];                           /* of the trajectory cells */
} plan;

/* One trajectory scene under every policy: its iterate and step rows, then
 * one runs row per policy with the shape differences against none and drop. */
static int traj_cell(long i, void *ctx, FILE *const *out) {
  const plan *pl = ctx;
  const scene_plan *sd = &scenes[pl->traj[i]];
  tally t[NPOL];
  memset(t, 0, sizeof t);
  int nv = 0, st = CB_OK;
  for (int p = 0; p < NPOL && st == CB_OK; p++) st = run_policy(pl->e, sd, p, out[T_IT], out[T_STEPS], &t[p], &nv);
  /* the runs' wall time (what the fixes cost, H2): the policies' runs again without the trace, in
   * interleaved rounds (stats.h: 3 with --quick, 2-5 in a full run by their cost; a run under 25 ms
   * timed right after an untimed one of its own) */
  cb_timing wall[NPOL];
  memset(wall, 0, sizeof wall);
  double spent = 0;
  for (int round = 0; st == CB_OK && cb_timing_more(pl->e->quick, round, spent); round++)
    for (int p = 0; p < NPOL && st == CB_OK; p++) {
      double ms;
      st = timed_run(pl->e, sd, p, &ms);
      if (st == CB_OK && cb_timing_warm(ms)) st = timed_run(pl->e, sd, p, &ms);
      cb_timing_add(&wall[p], ms);
      spent += ms;
    }
  for (int p = 0; p < NPOL && st == CB_OK; p++) {
    const tally *a = &t[p];
    FILE *f = out[T_RUNS];
    cb_csv_printf(f, "%s,%s,%d,%d,%d,%d,%d,%d,%d,%d,%.17g,%d,", sd->scene.label, policies[p], sd->steps[pl->e->quick],
                  a->steps_done, a->converged, a->iters, a->systems, a->not_spd, a->indef_x, a->cg_bd, a->mu, a->fact);
    cb_timing_csv(f, &wall[p], 1.0);
    fputc(',', f);
    cb_timing_csv_each(f, &wall[p], 1.0);
    cb_csv_printf(f, ",%d,%.6f,%.17g,%.17g,%.17g,", wall[p].n, a->probe, a->F, a->energy, a->rel_grad);
    put_diff(f, a->x, t[0].x, nv);
    put_diff(f, a->x, t[1].x, nv);
    cb_csv_printf(f, "%s\n", cb_status_name(a->status));
  }
  for (int p = 0; p < NPOL; p++) free(t[p].x);
  return st;
}

static double traj_cost(long i, void *ctx) { return ((const plan *)ctx)->cost[i]; }

static int static_cell(long i, void *ctx, FILE *const *out) {
  const plan *pl = ctx;
  return pair_cell(pl->e, &scenes[pl->stat[i / NPAIR]].scene, (int)(i % NPAIR), out[T_PAIR]);
}

int main(int argc, char **argv) {
  cb_experiment e;
  int st = cb_experiment_begin(&e, "definiteness",
                               "Claims H1, H2: how often A = M/dt^2 + H is indefinite on scenes that compress springs "
                               "(hanging, scaled, driven, pair; and a static spring pair in 1D/2D/3D), and what the "
                               "fixes drop, mirror, shift and choi-ko cost (Newton iterations, time, shape).",
                               argc, argv);
  if (st) return st > 0 ? 0 : 1;
  /* H2's wall times are measured in the trajectory cells, which run alone; the static spring pairs time
   * nothing and may run beside other untimed work */
  cb_experiment_timed_cells(&e, (const char *const[]){"static pair", NULL});
  plan pl = {.e = &e};
  for (int i = 0; i < NSCENES; i++) { /* smoke: the smallest scene of each role (the spring pair) */
    if (e.smoke && strcmp(scenes[i].scene.label, "pair") && strcmp(scenes[i].scene.label, "pair_static")) continue;
    if (cb_scene_decl_is(&scenes[i].scene, "trajectory")) pl.traj[pl.ntraj++] = i;
    if (cb_scene_decl_is(&scenes[i].scene, "static")) pl.stat[pl.nstat++] = i;
  }
  for (int i = 0; i < pl.ntraj; i++) { /* cost hint: policies x steps x vertices (Newton iterations vary 10x) */
    cb_config cfg;
    const scene_plan *sp = &scenes[pl.traj[i]];
    if ((st = cb_scene_decl_config(&e, &sp->scene, NULL, &cfg))) return cb_experiment_end(&e, st), 1;
    pl.cost[i] = (double)NPOL * sp->steps[e.quick] * (double)cb_scene_decl_vertices(&cfg);
  }
  const char *extra = "# one row per Newton iterate x^(k); system = 1 if A(x^(k)) was assembled and solved there\n";
  if (cb_experiment_table(&e, NULL, extra, IT_HEAD) != T_IT ||
      cb_experiment_table(&e, "steps", NULL,
                          "scene,policy,step,t_s,newton_iters,factorizations,"
                          "f_j,energy_j,kinetic_j,rel_grad,compressed_frac,mu_max_n_per_m,wall_ms,status") != T_STEPS ||
      cb_experiment_table(&e, "runs", NULL, RUN_HEAD) != T_RUNS ||
      cb_experiment_table(&e, "pair", NULL,
                          "dim,policy,buckling_kb_n_m2,ratio,min_eig_h_n_per_m,min_eig_a_n_per_m,"
                          "predicted_min_eig_a_n_per_m,spd") != T_PAIR)
    return cb_experiment_end(&e, CB_EIO), 2;
  const cb_sweep sweeps[] = {{"trajectory", pl.ntraj, traj_cell, traj_cost, &pl, NULL},
                             {"static pair", (long)pl.nstat * (e.smoke ? 1 : NPAIR), static_cell, NULL, &pl, NULL}};
  st = cb_sweep_run(&e, sweeps, 2);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
