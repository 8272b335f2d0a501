/* newton_vs_bw: Baraff-Witkin's single Newton iteration against full Newton,
 * as error against run time (claims I2, I3). The measurements live in
 * experiments/newton_vs_bw/newton_study*.c, the reference step in lib/instruments/reference.c, the methods in
 * lib/instruments/method.c; this file chooses scenes, sweeps and what runs in --quick
 * and --smoke (one small cell of each sweep: the lab scene's steps at one state,
 * short trajectories, one regime cell, one I2 state).
 *
 * Outputs (results/): newton_vs_bw.csv (one step of every method from states
 * of the reference trajectory: error, times), newton_vs_bw_traj.csv
 * (trajectories against the converged trajectory), newton_vs_bw_dt.csv
 * (converged dt against dt/16), newton_vs_bw_regime.csv (the K = 1 regime
 * map), newton_vs_bw_i2.csv (|grad F| per Newton iteration). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/scene.h>
#include <clothbench/status.h>
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "scene_decl.h"
#include "sweep.h"
#include "newton_study.h"

static const char *const ABOUT =
    "Decides I2 (Newton converges quadratically: order from the |grad F| sequence on a stretched\n"
    "hanging cloth) and I3 (Baraff-Witkin's K = 1 is fast but can fail: step error against the\n"
    "converged minimiser and wall time for K = 1, 2, 3, 5, 10 and converged, with and without line\n"
    "search, over CHOLMOD, CG and Chebyshev-Jacobi cut at 32 iterations or run to tolerance; the\n"
    "(dt, k, stretch) regime where K = 1 has one-step error above 1% or diverges).";

/* Scenes. Roles: "steps" = one step of every method from states of the
 * reference trajectory (main table and pareto; one cell per scene);
 * "trajectory" = 2 s trajectories and the time-discretisation error (one cell
 * each); "regime" = the base of the K = 1 regime map, whose cells override dt,
 * k and stretch (one cell per map cell); "i2" = |grad F| per Newton iteration
 * (one cell). grid64 is the lab cloth at 64^2 (same 441 kg and k: 441/4096 kg
 * per vertex); stiff is the lab scene 125x stiffer. */
static const cb_scene_decl SCENES[] = {
    {"lab", "hanging.ini", {NULL}, "steps"},
    {"grid64", "hanging.ini", {"mesh.n=64", "material.vertex_mass=0.107666015625", NULL}, "steps"},
    {"stiff", "hanging.ini", {"material.stretch_k=1e6", NULL}, "steps"},
    {"lab", "hanging.ini", {NULL}, "trajectory"},
    {"lab", "hanging.ini", {NULL}, "regime"},
    {"lab_stretched", "hanging.ini", {"scene.initial_scale=1.5", NULL}, "i2"},
};
enum { NSCENES = sizeof SCENES / sizeof SCENES[0] };
enum { T_STEPS, T_PARETO, T_TRAJ, T_DT, T_REGIME, T_I2 }; /* tables, in the order opened */

/* methods: K in Ks x line search {0,1} x inner solves; cheb32_alpha1 adds the
 * lab's Chebyshev setting (alpha = 1) at K = 1 without line search. */
static int methods(const int *Ks, int nK, const char *const *inner, int ninner, int alpha1, cb_method *out) {
  int n = 0;
  for (int i = 0; i < ninner; i++)
    for (int ls = 0; ls < 2; ls++)
      for (int k = 0; k < nK; k++)
        if (cb_method_make(Ks[k], ls, inner[i], &out[n++])) return -1;
  if (alpha1 && cb_method_make(1, 0, "cheb32_alpha1", &out[n++])) return -1;
  return n;
}

static const int KS[] = {1, 2, 3, 5, 10, 0}, KS_SHORT[] = {1, 2, 0}, KS_SMOKE[] = {1, 0};
static const char *const ALL[] = {"cholmod", "cg32", "cheb32", "cg_tol", "cheb_tol"};
static const char *const NOCHEB[] = {"cholmod", "cg32", "cg_tol"}, *const CHEB[] = {"cheb32", "cheb_tol"};
/* the K = 1 regime map over dt x k x stretch */
static const char *const DTS[] = {"1/240", "1/120", "1/60", "1/30", "1/20", "1/10"};
static const char *const KV[] = {"1e2", "1e3", "1e4", "1e5", "1e6", "1e7"}, *const SV[] = {"1", "1.25", "1.5", "2"};
static const int DI_Q[] = {0, 3, 5}, KI_Q[] = {0, 2, 5}, SI_Q[] = {0, 3}, DI[] = {0, 1, 2, 3, 4, 5},
                 SI[] = {0, 1, 2, 3};
static const int DI_S[] = {3}, KI_S[] = {2}, SI_S[] = {3}; /* smoke: dt 1/30, k 1e4, stretch 2 */

typedef struct {
  const cb_experiment *e;
  int q, smoke;
  double traj_s, dt_err_s, regime_s; /* simulated durations: trajectories, dt error, regime cells */
  int regime_samples, i2_states;
  int steps[NSCENES], nsteps, traj, regime, i2; /* scene indices by role */
  const int *di, *ki, *si;
  int nd, nk, nst;
  double steps_cost[NSCENES], traj_cost[2], i2_cost; /* cost hints (estimated ms) */
} plan;

/* the trajectories' methods */
static int traj_methods(int q, int smoke, cb_method *M) {
  if (smoke) return methods(KS, 1, ALL, 2, 0, M);      /* K = 1 with CHOLMOD and cg32, line search off/on */
  int nm = methods(KS, q ? 3 : 5, ALL, 1, 0, M);       /* K = 1..10 (fixed), CHOLMOD, line search off/on */
  if (!q) nm += methods(KS + 5, 1, ALL, 1, 0, M + nm); /* converged, CHOLMOD (the reference is converged too) */
  nm += methods(KS, 1, ALL + 1, q ? 1 : 2, 0, M + nm); /* K = 1 with cg32 (and cheb32) */
  return nm;
}

/* The methods and start states of a "steps" scene, by label. */
static int step_plan(const plan *p, const char *label, cb_method *M, const int **states, int *ns) {
  static const int ST_LAB[] = {0, 20, 40}, ST_LAB_Q[] = {20}, ST_64[] = {0, 10}, ST_64_Q[] = {5}, ST_SMOKE[] = {1};
  int q = p->q, nm;
  *states = ST_LAB;
  *ns = 3;
  if (p->smoke) { /* smoke: K = 1 and converged with every inner solve, one state */
    nm = methods(KS_SMOKE, 2, ALL, 5, 1, M);
    *states = ST_SMOKE, *ns = 1;
  } else if (!strcmp(label,
                     "grid64")) { /* 64^2: Chebyshev (a Lanczos rho estimate per factorisation) only at K = 1, 2 */
    nm = methods(q ? KS_SHORT : KS, q ? 3 : 6, NOCHEB, q ? 2 : 3, 0, M);
    if (!q) nm += methods(KS, 2, CHEB, 2, 0, M + nm);
    *states = q ? ST_64_Q : ST_64;
    *ns = q ? 1 : 2;
  } else if (q) { /* quick: Chebyshev only at K = 1, 2 */
    int lab = !strcmp(label, "lab");
    nm = methods(KS, 6, NOCHEB, 3, 0, M);
    nm += methods(KS, 2, CHEB, lab ? 2 : 1, lab, M + nm);
    *states = ST_LAB_Q, *ns = 1;
  } else if (!strcmp(label,
                     "stiff")) { /* stiff: Chebyshev up to K = 5 (inexact Newton with it needs ~100 Lanczos runs) */
    nm = methods(KS, 6, NOCHEB, 3, 0, M);
    nm += methods(KS, 4, CHEB, 2, 0, M + nm);
  } else {
    nm = methods(KS, 6, ALL, 5, 1, M);
  }
  /* the converged Newton that I3 compares K = 1 with is the fastest converging variant: these too */
  for (int ls = 0; ls < 2; ls++)
    if (cb_method_make_exact(ls, "cholmod", &M[nm++])) return -1;
  return nm;
}

/* I3 (b, c): one step of every method from the scene's states, and its error / run-time summary */
static int steps_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = &SCENES[p->steps[i]];
  static cb_method M[200];
  static cb_study_point P[200 * 4];
  const int *states;
  int ns, nm = step_plan(p, d->label, M, &states, &ns);
  if (nm < 0) return CB_EINVAL;
  cb_scene *s = NULL;
  cb_config cfg;
  int st = cb_scene_decl_build(p->e, d, NULL, &cfg, &s);
  if (st == CB_OK) st = cb_study_steps(s, d->label, cfg.dt, states, ns, M, nm, p->q, out[T_STEPS], P);
  if (st == CB_OK) st = cb_study_pareto(out[T_PARETO], d->label, M, nm, P, ns);
  cb_scene_free(s);
  return st;
}

/* trajectories of 2 s (cell 0) and the time-discretisation error (cell 1), lab scene */
static int traj_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = &SCENES[p->traj];
  cb_scene *s = NULL;
  cb_config cfg;
  int st = cb_scene_decl_build(p->e, d, NULL, &cfg, &s);
  if (st) return st;
  double dt = cfg.dt;
  if (i == 0) {
    static cb_method M[200];
    int nm = traj_methods(p->q, p->smoke, M);
    st = cb_study_trajectories(s, d->label, dt, (int)lround(p->traj_s / dt), M, nm, out[T_TRAJ]);
  } else {
    st = cb_study_dt_error(s, d->label, dt, 16, (int)lround(p->dt_err_s / dt), out[T_DT]);
  }
  cb_scene_free(s);
  return st;
}

/* I3 (a): one (dt, k, stretch) cell of the K = 1 regime map; dt varies fastest */
static int regime_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  int d = (int)(i % p->nd), c = (int)(i / p->nd % p->nk), a = (int)(i / ((long)p->nd * p->nk));
  char s1[64], s2[64], s3[64];
  snprintf(s1, sizeof s1, "integrator.dt=%s", DTS[p->di[d]]);
  snprintf(s2, sizeof s2, "material.stretch_k=%s", KV[p->ki[c]]);
  snprintf(s3, sizeof s3, "scene.initial_scale=%s", SV[p->si[a]]);
  const char *sets[] = {s1, s2, s3, NULL};
  cb_scene *s = NULL;
  const cb_scene_decl *sd = &SCENES[p->regime];
  cb_config cfg;
  int st = cb_scene_decl_build(p->e, sd, sets, &cfg, &s);
  if (st == CB_OK)
    st = cb_study_regime_cell(s, sd->label, cfg.dt, p->regime_s, p->regime_samples, 0.01, p->di[d], p->ki[c], p->si[a],
                              out[T_REGIME]);
  cb_scene_free(s);
  return st;
}

/* I2: |grad F| per Newton iteration on the stretched hanging cloth */
static int i2_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = &SCENES[p->i2];
  cb_scene *s = NULL;
  (void)i;
  cb_config cfg;
  int st = cb_scene_decl_build(p->e, d, NULL, &cfg, &s);
  if (st == CB_OK) st = cb_study_order(s, d->label, cfg.dt, p->i2_states, out[T_I2]);
  cb_scene_free(s);
  return st;
}

/* Cost hints: estimated ms, from a quick run's cost per unit of work scaled
 * by vertices / 441: 40 ms per (method, state) step (Newton up to converged),
 * 5 ms per trajectory step, 10 ms per converged reference step, 2 ms per
 * Baraff-Witkin step of the regime map, 300 ms per I2 state (five converged
 * Newton runs logged to 1e-14). */
static double steps_cost(long i, void *ctx) { return ((const plan *)ctx)->steps_cost[i]; }
static double traj_cost(long i, void *ctx) { return ((const plan *)ctx)->traj_cost[i]; }
static double i2_cost(long i, void *ctx) {
  (void)i;
  return ((const plan *)ctx)->i2_cost;
}
static double regime_cost(long i, void *ctx) {
  const plan *p = ctx;
  double dt = 1;
  cb_parse_double(DTS[p->di[i % p->nd]], &dt);
  return 2.0 * lround(p->regime_s / dt);
}

static int cost_hints(plan *p) {
  static cb_method M[200];
  const int *states;
  cb_scene_size z;
  int ns, st = CB_OK;
  for (int i = 0; st == CB_OK && i < p->nsteps; i++) {
    const cb_scene_decl *d = &SCENES[p->steps[i]];
    st = cb_sweep_scene_size(p->e, d, &z);
    p->steps_cost[i] = 40.0 * step_plan(p, d->label, M, &states, &ns) * ns * z.rel;
  }
  if (st == CB_OK && p->traj >= 0 && (st = cb_sweep_scene_size(p->e, &SCENES[p->traj], &z)) == CB_OK) {
    p->traj_cost[0] = 5.0 * (traj_methods(p->q, p->smoke, M) + 1) * lround(p->traj_s / z.dt) * z.rel;
    p->traj_cost[1] = 10.0 * 17 * lround(p->dt_err_s / z.dt) * z.rel;
  }
  if (st == CB_OK && p->i2 >= 0 && (st = cb_sweep_scene_size(p->e, &SCENES[p->i2], &z)) == CB_OK)
    p->i2_cost = 300.0 * p->i2_states * z.rel;
  return st;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "newton_vs_bw", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  /* the steps' wall times (I3, the Pareto fronts) run alone; the trajectories, the regime map and I2 compare no
   * wall time (their wall_ms columns are recorded, decide nothing) and run beside other untimed work */
  cb_experiment_timed_cells(&e, (const char *const[]){"trajectories", "regime", "I2", NULL});
  int q = e.quick, sm = e.smoke;
  plan p = {.e = &e,
            .q = q,
            .smoke = sm,
            .traj = -1,
            .regime = -1,
            .i2 = -1,
            .di = sm  ? DI_S
                  : q ? DI_Q
                      : DI,
            .ki = sm  ? KI_S
                  : q ? KI_Q
                      : DI,
            .si = sm  ? SI_S
                  : q ? SI_Q
                      : SI,
            .nd = sm  ? 1
                  : q ? 3
                      : 6,
            .nk = sm  ? 1
                  : q ? 3
                      : 6,
            .nst = sm  ? 1
                   : q ? 2
                       : 4,
            .traj_s = sm ? 0.2 : 2.0,
            .dt_err_s = sm  ? 0.1
                        : q ? 0.5
                            : 2.0,
            .regime_s = sm  ? 0.2
                        : q ? 1.0
                            : 2.0,
            .regime_samples = sm  ? 1
                              : q ? 2
                                  : 4,
            .i2_states = sm  ? 1
                         : q ? 5
                             : 30};
  for (int i = 0; i < NSCENES; i++) {
    const cb_scene_decl *d = &SCENES[i];
    if (cb_scene_decl_is(d, "steps")) {
      if (!sm || p.nsteps == 0) p.steps[p.nsteps++] = i; /* smoke: the first scene (lab) alone */
    } else if (cb_scene_decl_is(d, "trajectory")) p.traj = i;
    else if (cb_scene_decl_is(d, "regime")) p.regime = i;
    else if (cb_scene_decl_is(d, "i2")) p.i2 = i;
  }
  if ((b = cost_hints(&p))) return cb_experiment_end(&e, b), 1;
  const char *units = "# units: the column suffixes (README.md, CSV convention); stretch = scene.initial_scale; "
                      "step_error = |x - x*|_M / |x* - x0|_M\n";
  if (cb_experiment_table(&e, NULL, units, cb_study_steps_header) != T_STEPS ||
      cb_experiment_table(&e, "pareto", units, cb_study_pareto_header) != T_PARETO ||
      cb_experiment_table(&e, "traj", units, cb_study_traj_header) != T_TRAJ ||
      cb_experiment_table(&e, "dt", units, cb_study_dt_header) != T_DT ||
      cb_experiment_table(&e, "regime", units, cb_study_regime_header) != T_REGIME ||
      cb_experiment_table(&e, "i2", units, cb_study_order_header) != T_I2)
    return cb_experiment_end(&e, CB_EIO), 2;
  const cb_sweep sweeps[] = {
      {"steps", p.nsteps, steps_cell, steps_cost, &p, NULL},
      {"trajectories", p.traj >= 0 ? 2 : 0, traj_cell, traj_cost, &p, NULL},
      {"regime", p.regime >= 0 ? (long)p.nd * p.nk * p.nst : 0, regime_cell, regime_cost, &p, NULL},
      {"I2", p.i2 >= 0, i2_cell, i2_cost, &p, NULL},
  };
  int st = cb_sweep_run(&e, sweeps, 4);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
