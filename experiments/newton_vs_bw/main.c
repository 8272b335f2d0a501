/* newton_vs_bw: Baraff-Witkin's single Newton iteration against full Newton,
 * as error against run time (claims I2, I3). The measurements live in
 * experiments/newton_vs_bw/newton_study*.c, the reference step in lib/instruments/reference.c, the methods in
 * lib/instruments/method.c; this file chooses scenes, sweeps and what runs in --quick.
 *
 * Outputs (results/): newton_vs_bw.csv (one step of every method from states
 * of the reference trajectory: error, times), newton_vs_bw_traj.csv
 * (trajectories against the converged trajectory), newton_vs_bw_dt.csv
 * (converged dt against dt/16), newton_vs_bw_regime.csv (the K = 1 regime
 * map), newton_vs_bw_i2.csv (|grad F| per Newton iteration). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <clothbench/clothbench.h>
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "newton_study.h"

static const char *const ABOUT =
    "Decides I2 (Newton converges quadratically: order from the |grad F| sequence on a stretched\n"
    "hanging cloth) and I3 (Baraff-Witkin's K = 1 is fast but can fail: step error against the\n"
    "converged minimiser and wall time for K = 1, 2, 3, 5, 10 and converged, with and without line\n"
    "search, over CHOLMOD, CG and Chebyshev-Jacobi cut at 32 iterations or run to tolerance; the\n"
    "(dt, k, stretch) regime where K = 1 has one-step error above 1% or diverges).";

typedef struct {
  const char *label;
  const char *sets[4];
} scene_def;

/* the lab scene; the same cloth at 64^2 (same 441 kg and k: 441/4096 kg per
 * vertex); the lab scene 125x stiffer */
static const scene_def SCENES[] = {
    {"lab", {NULL}},
    {"grid64", {"mesh.n=64", "material.vertex_mass=0.107666015625", NULL}},
    {"stiff", {"material.stretch_k=1e6", NULL}},
};

/* The scene, and its config's integrator.dt in *dt. */
static int build(const cb_experiment *e, const char *const *sets, const char *extra, cb_scene **s, double *dt) {
  cb_config c;
  int st = cb_experiment_config(e, "hanging.ini", sets, &c);
  if (st == CB_OK && extra) st = cb_config_set(&c, extra);
  if (st == CB_OK) st = cb_config_validate(&c);
  if (st == CB_OK) st = cb_scene_from_config(&c, s);
  *dt = c.dt;
  return st;
}

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

static int fail(const char *what) {
  fprintf(stderr, "newton_vs_bw: %s: %s\n", what, cb_error_message());
  return 1;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "newton_vs_bw", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  int q = e.quick;
  const int KS[] = {1, 2, 3, 5, 10, 0}, KS_SHORT[] = {1, 2, 0};
  const char *ALL[] = {"cholmod", "cg32", "cheb32", "cg_tol", "cheb_tol"};
  const char *NOCHEB[] = {"cholmod", "cg32", "cg_tol"}, *CHEB[] = {"cheb32", "cheb_tol"};
  /* start states (steps of the reference trajectory) per scene */
  const int ST_LAB[] = {0, 20, 40}, ST_LAB_Q[] = {20}, ST_64[] = {0, 10}, ST_64_Q[] = {5};
  cb_method M[200];
  static cb_study_point P[200 * 4];
  int st = 0;
  char path[4096];
  cb_outfile csv, par, traj, dtf, reg, i2;
  const char *units = "# units: dt s; k N/m; stretch = scene.initial_scale; *_ms wall milliseconds; step_error = "
                      "|x - x*|_M / |x* - x0|_M; f_minus_fstar_j J\n";
  if (cb_experiment_csv(&e, &csv, NULL, units, cb_study_steps_header)) return fail("main CSV");
  cb_experiment_side_path(&e, "pareto.csv", path, sizeof path);
  if (cb_experiment_csv(&e, &par, path, units, cb_study_pareto_header)) return fail(path);

  /* I3 (b, c): one step of every method, three scenes */
  for (int sc = 0; sc < 3 && !st; sc++) {
    cb_scene *s = NULL;
    double s_dt = 0;
    if (build(&e, SCENES[sc].sets, NULL, &s, &s_dt)) return fail(SCENES[sc].label);
    int nm = 0;
    const int *states = ST_LAB;
    int ns = 3;
    if (sc == 1) { /* 64^2: Chebyshev (a Lanczos rho estimate per factorisation) only at K = 1, 2 */
      nm = methods(q ? KS_SHORT : KS, q ? 3 : 6, NOCHEB, q ? 2 : 3, 0, M);
      if (!q) nm += methods(KS, 2, CHEB, 2, 0, M + nm);
      states = q ? ST_64_Q : ST_64;
      ns = q ? 1 : 2;
    } else if (q) { /* quick: Chebyshev only at K = 1, 2 */
      nm = methods(KS, 6, NOCHEB, 3, 0, M);
      nm += methods(KS, 2, CHEB, sc == 0 ? 2 : 1, sc == 0, M + nm);
      states = ST_LAB_Q, ns = 1;
    } else if (sc == 2) { /* stiff: Chebyshev up to K = 5 (inexact Newton with it needs ~100 Lanczos runs) */
      nm = methods(KS, 6, NOCHEB, 3, 0, M);
      nm += methods(KS, 4, CHEB, 2, 0, M + nm);
    } else {
      nm = methods(KS, 6, ALL, 5, 1, M);
    }
    cb_progress_start(&e.progress, SCENES[sc].label, (long)nm * ns);
    st = cb_study_steps(s, SCENES[sc].label, s_dt, states, ns, M, nm, csv.f, &e.progress, P);
    cb_progress_end(&e.progress);
    if (!st) st = cb_study_pareto(par.f, SCENES[sc].label, M, nm, P, ns);
    cb_scene_free(s);
    if (st) return fail("steps");
  }

  /* trajectories of 2 s and the time-discretisation error, lab scene */
  cb_scene *lab = NULL;
  double dt = 0;
  if (build(&e, SCENES[0].sets, NULL, &lab, &dt)) return fail("lab");
  int nm = methods(KS, q ? 3 : 5, ALL, 1, 0, M); /* K = 1..10 (fixed), CHOLMOD, line search off/on */
  if (!q) nm += methods(KS + 5, 1, ALL, 1, 0, M + nm); /* converged, CHOLMOD (the reference is converged too) */
  nm += methods(KS, 1, ALL + 1, q ? 1 : 2, 0, M + nm); /* K = 1 with cg32 (and cheb32) */
  cb_experiment_side_path(&e, "traj.csv", path, sizeof path);
  if (cb_experiment_csv(&e, &traj, path, units, cb_study_traj_header)) return fail(path);
  cb_progress_start(&e.progress, "trajectories", nm + 1);
  st = cb_study_trajectories(lab, "lab", dt, (int)lround(2.0 / dt), M, nm, traj.f, &e.progress);
  cb_progress_end(&e.progress);
  if (st) return fail("trajectories");
  cb_experiment_side_path(&e, "dt.csv", path, sizeof path);
  if (cb_experiment_csv(&e, &dtf, path, units, cb_study_dt_header)) return fail(path);
  st = cb_study_dt_error(lab, "lab", dt, 16, (int)lround((q ? 0.5 : 2.0) / dt), dtf.f);
  cb_scene_free(lab);
  if (st) return fail("dt error");

  /* I3 (a): the K = 1 regime map over dt x k x stretch */
  const char *DTS[] = {"1/240", "1/120", "1/60", "1/30", "1/20", "1/10"}, *KV[] = {"1e2", "1e3", "1e4", "1e5", "1e6", "1e7"};
  const char *SV[] = {"1", "1.25", "1.5", "2"};
  const int DI_Q[] = {0, 3, 5}, KI_Q[] = {0, 2, 5}, SI_Q[] = {0, 3}, DI[] = {0, 1, 2, 3, 4, 5}, SI[] = {0, 1, 2, 3};
  const int *di = q ? DI_Q : DI, *ki = q ? KI_Q : DI, *si = q ? SI_Q : SI;
  int nd = q ? 3 : 6, nk = q ? 3 : 6, nst = q ? 2 : 4;
  cb_experiment_side_path(&e, "regime.csv", path, sizeof path);
  if (cb_experiment_csv(&e, &reg, path, units, cb_study_regime_header)) return fail(path);
  cb_progress_start(&e.progress, "regime", (long)nd * nk * nst);
  for (int a = 0; a < nst && !st; a++)
    for (int c = 0; c < nk && !st; c++)
      for (int d = 0; d < nd && !st; d++) {
        char s1[64], s2[64], s3[64];
        snprintf(s1, sizeof s1, "integrator.dt=%s", DTS[di[d]]);
        snprintf(s2, sizeof s2, "material.stretch_k=%s", KV[ki[c]]);
        snprintf(s3, sizeof s3, "scene.initial_scale=%s", SV[si[a]]);
        const char *sets[] = {s1, s2, s3, NULL};
        cb_scene *s = NULL;
        double s_dt = 0;
        if (build(&e, sets, NULL, &s, &s_dt)) return fail("regime scene");
        st = cb_study_regime_cell(s, "lab", s_dt, q ? 1.0 : 2.0, q ? 2 : 4, 0.01, di[d], ki[c], si[a], reg.f);
        cb_scene_free(s);
        cb_progress_update(&e.progress, e.progress.done + 1);
      }
  cb_progress_end(&e.progress);
  if (st) return fail("regime");

  /* I2: |grad F| per Newton iteration on the stretched hanging cloth */
  cb_scene *str = NULL;
  double str_dt = 0;
  if (build(&e, SCENES[0].sets, "scene.initial_scale=1.5", &str, &str_dt)) return fail("stretched scene");
  cb_experiment_side_path(&e, "i2.csv", path, sizeof path);
  if (cb_experiment_csv(&e, &i2, path, units, cb_study_order_header)) return fail(path);
  int n2 = q ? 5 : 30;
  cb_progress_start(&e.progress, "I2", n2);
  st = cb_study_order(str, "lab_stretched", str_dt, n2, i2.f, &e.progress);
  cb_progress_end(&e.progress);
  cb_scene_free(str);
  if (st) return fail("I2");

  cb_outfile *outs[] = {&par, &traj, &dtf, &reg, &i2, &csv};
  for (int i = 0; i < 6; i++)
    if (cb_outfile_commit(outs[i])) return fail("writing results");
  return 0;
}
