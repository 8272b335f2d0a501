/* Verdict logic of the I2 and I3 checkers (claims/check_newton_vs_bw.c) on
 * small constructed CSVs in a temporary folder, through the claims table. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"
#include "support.h"

static char dir[64];

static void setup(void) {
  snprintf(dir, sizeof dir, "/tmp/cbclaims_XXXXXX");
  cr_assert(mkdtemp(dir), "mkdtemp failed");
}

static void teardown(void) {
  const char *names[] = {"newton_vs_bw.csv", "newton_vs_bw_i2.csv", "newton_vs_bw_regime.csv"};
  char path[256];
  for (int i = 0; i < 3; i++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    remove(path);
  }
  remove(dir);
}

static void put(const char *name, const char *text) { test_put(dir, name, "# experiment: newton_vs_bw\n", text); }

static cb_verdict decide(const char *id, cb_claim_result *res) {
  return test_decide_claim(id, "newton_vs_bw", dir, res);
}

/* ---- I2 ---- */

#define I2_HEAD "definiteness,line_search,step,iter,grad_norm_n,alpha,hessian,step_status\n"

/* one run: g_k given, all updates with the given Hessian */
static void run(char *buf, const char *def, int ls, int step, const double *g, int n, const char *hess,
                const char *status) {
  for (int i = 0; i < n; i++)
    sprintf(buf + strlen(buf), "%s,%d,%d,%d,%.17g,%g,%s,%s\n", def, ls, step, i, g[i], i == 2 ? 0.5 : 1.0,
            i ? hess : "-", status);
}

static void i2_file(const double *g, int n, const char *hess) {
  static char buf[65536];
  strcpy(buf, I2_HEAD);
  const double lin[] = {1e3, 1e2, 10, 1, 0.1, 0.01};
  for (int s = 0; s < 6; s++) {
    run(buf, "exact_or_shift", 1, s, g, n, hess, "ok");
    run(buf, "drop", 1, s, lin, 6, "drop", "max_iters");
  }
  put("newton_vs_bw_i2.csv", buf);
  put("newton_vs_bw.csv", "scene,method\nlab,newton_k1\n");
}

Test(claims_newton_vs_bw, i2_quadratic_is_reproduced, .init = setup, .fini = teardown) {
  const double g[] = {1e4, 1e3, 1e2, 1, 1e-4, 1e-12}; /* p = 2 on (1e2, 1, 1e-4) */
  i2_file(g, 6, "exact");
  cb_claim_result r;
  cr_assert_eq(decide("I2", &r), CB_REPRODUCED, "%s", r.reason);
  cr_assert(strstr(r.numbers, "| exact_or_shift | yes | 6 | 6 | 6 | 6 | 2 |"), "%s", r.numbers);
  cr_assert(strstr(r.reason, "drop fix"), "%s", r.reason);
}

Test(claims_newton_vs_bw, i2_linear_is_not_reproduced, .init = setup, .fini = teardown) {
  const double g[] = {1e4, 1e3, 1e2, 10, 1, 0.1};
  i2_file(g, 6, "exact");
  cb_claim_result r;
  cr_assert_eq(decide("I2", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

Test(claims_newton_vs_bw, i2_counts_only_exact_hessian_updates, .init = setup, .fini = teardown) {
  const double g[] = {1e4, 1e3, 1e2, 1, 1e-4, 1e-12}; /* quadratic, but made with the shifted Hessian */
  i2_file(g, 6, "shifted");
  cb_claim_result r;
  cr_assert_eq(decide("I2", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

Test(claims_newton_vs_bw, i2_missing_side_csv_is_not_run, .init = setup, .fini = teardown) {
  put("newton_vs_bw.csv", "scene,method\nlab,newton_k1\n");
  cb_claim_result r;
  cr_assert_eq(decide("I2", &r), CB_NOT_RUN, "%s", r.reason);
}

/* ---- I3 ---- */

#define MAIN_HEAD "scene,step,method,inner_solver,line_search,step_error,wall_ms,status\n"
#define MAIN_HEAD_SPREAD \
  "scene,step,method,inner_solver,line_search,step_error,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats," \
  "status\n"
#define REG_HEAD "dt_s,k_n_per_m,stretch,first_diverged_step,step_error_max,ref_status,k1_fails\n"

/* the timing fields of a row: "wall_ms" alone, or with its spread over three repeats, scaled by f */
static const char *wall(char *buf, int spread, double med, const double *each) {
  if (!spread) sprintf(buf, "%g", med);
  else
    sprintf(buf, "%g,%g,%g,%g;%g;%g,3", med, fmin(each[0], fmin(each[1], each[2])),
            fmax(each[0], fmax(each[1], each[2])), each[0], each[1], each[2]);
  return buf;
}

/* an extra converged variant: its method, inner solve, line search, step error and median ms (NULL: none) */
typedef struct {
  const char *method, *inner;
  int ls;
  double err, ms;
} i3_extra;

static void i3_scenes_extra(double conv_ms, int regime_fail, const char *const *scenes, int nscenes, int spread,
                            const i3_extra *x) {
  static char buf[16384];
  strcpy(buf, spread ? MAIN_HEAD_SPREAD : MAIN_HEAD);
  /* K = 1 repeats: state 0 at 0.9, 1, 1.2 ms, state 1 at 1.1, 1, 1 ms (per repeat the median over the two
   * states: 1, 1, 1.1); converged: conv x (1, 1, 1.1) at both states */
  const double k1[2][3] = {{0.9, 1.0, 1.2}, {1.1, 1.0, 1.0}}, cv[3] = {conv_ms, conv_ms, 1.1 * conv_ms};
  const double cg[3] = {0.5, 0.5, 0.5}, ch[3] = {3, 3, 3};
  char w[128];
  for (int s = 0; s < nscenes; s++)
    for (int st = 0; st < 2; st++) {
      sprintf(buf + strlen(buf), "%s,%d,newton_k1,cholmod,0,%g,%s,max_iters\n", scenes[s], st, 1e-3 * (st + 1),
              wall(w, spread, 1.0, k1[st]));
      sprintf(buf + strlen(buf), "%s,%d,newton_converged,cholmod,0,1e-10,%s,ok\n", scenes[s], st,
              wall(w, spread, conv_ms, cv));
      sprintf(buf + strlen(buf), "%s,%d,newton_k1,cg32,0,2e-3,%s,max_iters\n", scenes[s], st, wall(w, spread, 0.5, cg));
      sprintf(buf + strlen(buf), "%s,%d,newton_k1,cheb32_alpha1,0,0.06,%s,linear_failed\n", scenes[s], st,
              wall(w, spread, 3.0, ch));
      if (x) {
        const double xe[3] = {x->ms, x->ms, x->ms};
        sprintf(buf + strlen(buf), "%s,%d,%s,%s,%d,%g,%s,ok\n", scenes[s], st, x->method, x->inner, x->ls, x->err,
                wall(w, spread, x->ms, xe));
      }
    }
  put("newton_vs_bw.csv", buf);
  char reg[1024];
  /* first_diverged_step is empty when the trajectory did not diverge */
  snprintf(reg, sizeof reg, REG_HEAD "0.1,100,1,,1e-4,ok,0\n0.1,1e7,2,%s,%g,ok,%d\n", regime_fail ? "2" : "",
           regime_fail ? 0.2 : 1e-3, regime_fail);
  put("newton_vs_bw_regime.csv", reg);
}

static void i3_scenes(double conv_ms, int regime_fail, const char *const *scenes, int nscenes) {
  i3_scenes_extra(conv_ms, regime_fail, scenes, nscenes, 0, NULL);
}

static void i3_files(double conv_ms, int regime_fail) {
  const char *scenes[] = {"lab", "grid64", "stiff"};
  i3_scenes_extra(conv_ms, regime_fail, scenes, 3, 1, NULL);
}

Test(claims_newton_vs_bw, i3_fast_and_failing_is_reproduced, .init = setup, .fini = teardown) {
  i3_files(10.0, 1);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_REPRODUCED, "%s", r.reason);
  /* the cheapest at 1e-2 is CG cut at 32 (0.5 ms, max error 2e-3); the failed Chebyshev never counts */
  cr_assert(strstr(r.numbers, "newton_k1 cg32 (0.5 (0.5-0.5) ms"), "%s", r.numbers);
  /* per repeat: K = 1 at 1, 1, 1.1 ms, converged at 10, 10, 11 ms: paired speed-ups 10, 10, 10 (bounds: 9.1-11) */
  cr_assert(strstr(r.numbers, "| lab | 1 (1-1.1) | newton_converged cholmod: 10 (10-11) | 10.0 (10.0-10.0) |"), "%s",
            r.numbers);
  cr_assert(strstr(r.numbers, "medians of 3 repeats"), "%s", r.numbers);
  cr_assert(strstr(r.reason, "lab 10.0x (10.0-10.0x over 3 paired repeats) against newton_converged cholmod"), "%s",
            r.reason);
  cr_assert(strstr(r.numbers, "1/10:D"), "%s", r.numbers);
}

Test(claims_newton_vs_bw, i3_without_spread_columns_quotes_the_medians, .init = setup, .fini = teardown) {
  const char *scenes[] = {"lab"};
  i3_scenes(10.0, 1, scenes, 1);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_REPRODUCED, "%s", r.reason);
  cr_assert(strstr(r.numbers, "| lab | 1 | newton_converged cholmod: 10 | 10.0 |"), "%s", r.numbers);
  cr_assert(strstr(r.reason, "lab 10.0x against newton_converged cholmod."), "%s", r.reason);
}

/* The baseline is the fastest converged variant: an exact-Hessian Newton with line search at 4 ms beats
 * drop's 10 ms, and the speed-up is 4x against it, named. */
Test(claims_newton_vs_bw, i3_baseline_is_the_fastest_converged_newton, .init = setup, .fini = teardown) {
  const char *scenes[] = {"lab"};
  const i3_extra x = {"newton_converged_exact", "cholmod", 1, 1e-9, 4.0};
  i3_scenes_extra(10.0, 1, scenes, 1, 0, &x);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_REPRODUCED, "%s", r.reason);
  cr_assert(strstr(r.numbers, "| lab | 1 | newton_converged_exact cholmod +LS: 4 | 4.0 |"), "%s", r.numbers);
  cr_assert(strstr(r.reason, "lab 4.0x against newton_converged_exact cholmod +LS."), "%s", r.reason);
}

/* The same data that is "reproduced" against drop alone is not, once a converged variant only 1.5x slower than
 * K = 1 exists: against the fastest baseline K = 1 is not 2x faster (and it fails: partly). */
Test(claims_newton_vs_bw, i3_fast_only_against_a_slow_baseline_is_partly, .init = setup, .fini = teardown) {
  const char *scenes[] = {"lab"};
  const i3_extra x = {"newton_converged_exact", "cholmod", 1, 1e-9, 1.5};
  i3_scenes_extra(10.0, 1, scenes, 1, 0, &x);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_PARTLY, "%s", r.reason);
  cr_assert(strstr(r.reason, "not at least 2x faster"), "%s", r.reason);
  i3_scenes_extra(10.0, 0, scenes, 1, 0, &x); /* and without a failing regime cell: not reproduced */
  cr_assert_eq(decide("I3", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

/* A faster "converged" run whose step error is 1e-3 did not converge: it is not the baseline. */
Test(claims_newton_vs_bw, i3_inaccurate_converged_run_is_not_the_baseline, .init = setup, .fini = teardown) {
  const char *scenes[] = {"lab"};
  const i3_extra x = {"newton_converged", "cg_tol", 0, 1e-3, 1.5};
  i3_scenes_extra(10.0, 1, scenes, 1, 0, &x);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_REPRODUCED, "%s", r.reason);
  cr_assert(strstr(r.reason, "lab 10.0x against newton_converged cholmod."), "%s", r.reason);
}

Test(claims_newton_vs_bw, i3_fast_but_never_failing_is_partly, .init = setup, .fini = teardown) {
  i3_files(10.0, 0);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_PARTLY, "%s", r.reason);
}

Test(claims_newton_vs_bw, i3_neither_is_not_reproduced, .init = setup, .fini = teardown) {
  i3_files(1.5, 0); /* converged only 1.5x slower, and K = 1 never fails */
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

/* Scene names the checker has never seen: every scene of the CSV is decided,
 * in its order, and one slow scene among them makes "K = 1 is fast" fail. */
Test(claims_newton_vs_bw, i3_takes_scene_names_from_the_csv, .init = setup, .fini = teardown) {
  const char *scenes[] = {"zeta", "omega", "lab", "grid64"};
  i3_scenes(10.0, 1, scenes, 4);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_REPRODUCED, "%s", r.reason);
  cr_assert(strstr(r.numbers, "| zeta | 1 | newton_converged cholmod: 10 | 10.0 |") && strstr(r.numbers, "| omega | 1 "
                                                                                                         "| "
                                                                                                         "newton_"
                                                                                                         "converged "
                                                                                                         "cholmod: 10 "
                                                                                                         "|"),
            "%s", r.numbers);
  cr_assert(strstr(r.numbers, "| zeta |") < strstr(r.numbers, "| omega |"), "scenes out of the CSV's order: %s",
            r.numbers);
  cr_assert(strstr(r.reason, "on all 4 scenes"), "%s", r.reason);
}

/* One scene, K = 1 at 1 ms in every repeat and converged Newton at conv[0..3) ms (paired repeats): the
 * speed-up's spread is conv itself. */
static void i3_spread(const double *conv, int regime_fail) {
  static char buf[4096];
  const double one[3] = {1, 1, 1};
  char w[128];
  strcpy(buf, MAIN_HEAD_SPREAD);
  double s[3] = {conv[0], conv[1], conv[2]};
  for (int i = 1; i < 3; i++) /* the median of the three */
    for (int j = i; j > 0 && s[j] < s[j - 1]; j--) {
      double t = s[j];
      s[j] = s[j - 1];
      s[j - 1] = t;
    }
  for (int st = 0; st < 2; st++) {
    sprintf(buf + strlen(buf), "lab,%d,newton_k1,cholmod,0,1e-3,%s,max_iters\n", st, wall(w, 1, 1.0, one));
    sprintf(buf + strlen(buf), "lab,%d,newton_converged,cholmod,0,1e-10,%s,ok\n", st, wall(w, 1, s[1], conv));
  }
  put("newton_vs_bw.csv", buf);
  char reg[1024];
  snprintf(reg, sizeof reg, REG_HEAD "0.1,1e7,2,%s,%g,ok,%d\n", regime_fail ? "2" : "", regime_fail ? 0.2 : 1e-3,
           regime_fail);
  put("newton_vs_bw_regime.csv", reg);
}

/* Speed-ups 1.5, 2.25, 2.5 over three paired repeats straddle 2x: undecided, whether K = 1 fails somewhere
 * (reproduced or partly) or not (partly or not reproduced). Margin +0.25x; half-width 0.75 on the
 * threshold's side: 3 (0.75/0.25)^2 = 27, so 28 repeats. */
Test(claims_newton_vs_bw, i3_speedup_straddling_2x_is_undecided, .init = setup, .fini = teardown) {
  const double conv[3] = {1.5, 2.25, 2.5};
  i3_spread(conv, 1);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_UNDECIDED, "%s", r.reason);
  cr_expect(strstr(r.reason, "reproduced with every speed-up at least 2x, partly reproduced without"), "%s", r.reason);
  cr_expect(strstr(r.reason, "on lab the speed-up 2.25x (1.50-2.50x over 3 paired repeats) straddles 2.00x: margin "
                             "+0.25x (median above by 12%)"),
            "%s", r.reason);
  cr_expect(strstr(r.reason, "about 28 repeats would decide it"), "%s", r.reason);
  i3_spread(conv, 0);
  cr_expect_eq(decide("I3", &r), CB_UNDECIDED, "%s", r.reason);
  /* the same median, 2.25x, with a spread that clears 2x is decided */
  const double tight[3] = {2.1, 2.25, 2.5};
  i3_spread(tight, 1);
  cr_expect_eq(decide("I3", &r), CB_REPRODUCED, "%s", r.reason);
}

/* A spread wholly below 2x, and no failing cell: not reproduced (the spread decides it, below). */
Test(claims_newton_vs_bw, i3_speedup_below_2x_over_its_spread_is_not_reproduced, .init = setup, .fini = teardown) {
  const double conv[3] = {1.2, 1.5, 1.9};
  i3_spread(conv, 0);
  cb_claim_result r;
  cr_assert_eq(decide("I3", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}
