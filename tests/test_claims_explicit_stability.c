/* Verdict logic of claims/check_explicit_stability.c on small constructed
 * CSVs (main table plus the boundary and timing side tables) in a temp dir. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"
#include "support.h"


static const char *main_hdr = "# "
                              "test\nkind,case,scene,k_n_per_m,dt_s,method,status,max_energy_ratio,steps,dt_crit_pred_"
                              "s,dt_crit_meas_s,"
                              "not_converged_steps,t_mark_s,energy_loss_w,kinetic0_j,window_s,t_end_s\n";
static const char *bound_hdr = "# "
                               "test\nscene,k_n_per_m,dt_crit_pred_s,dt_crit_meas_s,bisect_status,dt_crit_pred_rest_s,"
                               "lambda_dense_per_s2,lambda_lanczos_per_s2\n";
static const char *time_hdr = "# test\nscene,family,n_vertices,k_n_per_m,method,wall_ms_per_s,wall_min_ms_per_s,"
                              "wall_max_ms_per_s,wall_each_ms_per_s,wall_repeats,steps,status,dt_crit_pred_s,step_"
                              "error_max,"
                              "not_converged_steps,iters_per_step\n";

static char dir[64];
static char main_rows[65536], bound_rows[8192], time_rows[16384];

static cb_claim_result last; /* the result of the last decide() */

static cb_verdict decide(cb_claim_check check) {
  snprintf(dir, sizeof dir, "/tmp/cbclaimsXXXXXX");
  cr_assert(mkdtemp(dir));
  test_put(dir, "explicit_stability.csv", main_hdr, main_rows);
  test_put(dir, "explicit_stability_boundary.csv", bound_hdr, bound_rows);
  test_put(dir, "explicit_stability_timing.csv", time_hdr, time_rows);
  char path[256];
  snprintf(path, sizeof path, "%s/explicit_stability.csv", dir);
  cb_claim_result r;
  test_decide_check(check, path, dir, &r);
  last = r;
  const char *names[] = {"explicit_stability.csv", "explicit_stability_boundary.csv", "explicit_stability_timing.csv"};
  for (int i = 0; i < 3; i++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    unlink(path);
  }
  rmdir(dir);
  cr_assert_neq(r.reason[0], '\0');
  return r.verdict;
}

/* A spring-like scene: dt_pred = 2 sqrt(m/k) with m = 0.01, measured = ratio x pred;
 * an explicit map around it, and Newton cells losing energy ~ dt. */
static double damp_exp = 1;    /* energy lost per second ~ dt^damp_exp */
static double newton_time = 1; /* simulated time of a Newton cell, s (the explicit cells': 1 s, 0.5 s where diverged) */
static void build(double ratio, double slope, int newton_diverges) {
  main_rows[0] = bound_rows[0] = '\0';
  const char *sc[] = {"spring", "cloth"};
  for (int s = 0; s < 2; s++)
    for (int i = 0; i < 4; i++) {
      double k = pow(10.0, 1 + 2 * i), pred = 2 * sqrt(0.01 / k);
      double meas = ratio * pred * pow(k / 10.0, -slope - 0.5); /* slope of log meas against log k */
      size_t n = strlen(bound_rows);
      snprintf(bound_rows + n, sizeof bound_rows - n, "%s,%.17g,%.17g,%.17g,ok,%.17g,%s\n", sc[s], k, pred, meas, pred,
               s == 0 ? "400,400.0000001" : "nan,nan");
      for (int j = 0; j < 9; j++) {
        double dt = pred * pow(10.0, (j - 4) / 4.0); /* 0.1 .. 10 x pred */
        const char *st = dt <= meas ? "stable" : "diverged";
        n = strlen(main_rows);
        snprintf(main_rows + n, sizeof main_rows - n,
                 "sweep,map,%s,%.17g,%.17g,explicit,%s,0,100,%.17g,%.17g,0,0.1,0,1,0,%g\n", sc[s], k, dt, st, pred,
                 meas, dt <= meas ? 1.0 : 0.5);
        double loss = 5 * pow(dt, damp_exp); /* J per s, kinetic0 = 1 J */
        const char *nst = newton_diverges && s == 1 && i == 3 && j == 8 ? "diverged" : "stable";
        n = strlen(main_rows);
        snprintf(main_rows + n, sizeof main_rows - n,
                 "sweep,map,%s,%.17g,%.17g,newton,%s,0,100,%.17g,%.17g,0,0.1,%.17g,1,0.1,%g\n", sc[s], k, dt, nst, pred,
                 meas, loss, newton_time);
      }
    }
}

Test(claims_explicit_stability, E1_reproduced_when_the_boundary_matches) {
  build(0.99, -0.5, 0);
  cr_assert_eq(decide(cb_check_E1), CB_REPRODUCED);
}

Test(claims_explicit_stability, E1_fails_when_the_boundary_is_far_off) {
  build(0.5, -0.5, 0); /* measured at half the prediction: every ratio outside 15% */
  cr_assert_eq(decide(cb_check_E1), CB_NOT_REPRODUCED);
  build(0.99, -0.3, 0); /* ratios drift with k: slope -0.3 */
  cr_assert_neq(decide(cb_check_E1), CB_REPRODUCED);
}

/* A row's repeats: its median v times 0.9, 1, 1.1 (explicit, Baraff-Witkin) or 1, 1, 1.2 (Newton), in
 * that order: "median,min,max,each,3". */
static void reps(char *buf, size_t n, double v, int newton) {
  double a = newton ? 1.0 : 0.9, b = 1.0, c = newton ? 1.2 : 1.1;
  snprintf(buf, n, "%.17g,%.17g,%.17g,%.17g;%.17g;%.17g,3", v, a * v, c * v, a * v, b * v, c * v);
}

/* One (scene, k): explicit at wall ex ms and omega_max = omega (dt_pred = 2/omega), converged Newton at nt ms
 * (step error 1e-8), Baraff-Witkin (drop) at nt/10 ms with step error bw_err and Baraff-Witkin (shift) at
 * nt/4 ms with step error bw_err/10. */
static void trow3(const char *scene, const char *family, int nv, double k, double ex, double omega, double nt,
                  double bw_err) {
  char e[256], t[256], w[256], w2[256];
  reps(e, sizeof e, ex, 0);
  reps(t, sizeof t, nt, 1);
  reps(w, sizeof w, nt / 10, 0);
  reps(w2, sizeof w2, nt / 4, 0);
  size_t n = strlen(time_rows);
  snprintf(time_rows + n, sizeof time_rows - n,
           "%s,%s,%d,%.17g,explicit,%s,%.0f,stable,%.17g,,,\n%s,%s,%d,%.17g,newton,%s,30,stable,%.17g,1e-8,0,\n"
           "%s,%s,%d,%.17g,newton_bw,%s,30,stable,%.17g,%.17g,,1\n%s,%s,%d,%.17g,newton_bw_shift,%s,30,stable,%.17g,%."
           "17g,,1\n",
           scene, family, nv, k, e, omega * 0.5, 2 / omega, scene, family, nv, k, t, 2 / omega, scene, family, nv, k, w,
           2 / omega, bw_err, scene, family, nv, k, w2, 2 / omega, bw_err / 10);
}

/* Stretch family: cloth21 at k = 10, 1e3, 1e4, 1e5, 1e7 with omega = sqrt(k), explicit 0.5 k^kexp ms,
 * and 41^2, 81^2 at k = 1e4 with omega ~ n^0.5 and explicit ~ n^sexp; bending family: 11^2, 21^2, 41^2 at
 * k = 1e4 with omega ~ n (3 x the stretch one at 121) and explicit ~ n^bexp. Implicit: nt ms on 21^2 (and
 * smaller), growing like n^1.2 above it. So the predicted exponents are 1.5 (stretch) and 2 (bending). */
static void timing(double kexp, double sexp, double bexp, double nt, double bw_err) {
  time_rows[0] = '\0';
  const double ks[] = {10, 1e3, 1e4, 1e5, 1e7};
  for (int i = 0; i < 5; i++) trow3("cloth21", "stretch", 441, ks[i], 0.5 * pow(ks[i], kexp), sqrt(ks[i]), nt, bw_err);
  const int nv[] = {1681, 6561};
  for (int r = 0; r < 2; r++) {
    double f = nv[r] / 441.0;
    trow3(r ? "cloth81" : "cloth41", "stretch", nv[r], 1e4, 0.5 * pow(1e4, kexp) * pow(f, sexp), 100 * sqrt(f),
          nt * pow(f, 1.2), bw_err);
  }
  const int nb[] = {121, 441, 1681};
  for (int r = 0; r < 3; r++) {
    double f = nb[r] / 121.0;
    trow3(r == 0   ? "bend11"
          : r == 1 ? "bend21"
                   : "bend41",
          "bending", nb[r], 1e4, 150 * pow(f, bexp), 300 * f, nt * pow(nb[r] > 441 ? nb[r] / 441.0 : 1, 1.2), bw_err);
  }
}

/* the columns of the methods a row did not time: Newton with 2-5 iterations, chebyshev-nl, pd */
#define NT " | not timed / not timed / not timed / not timed | not timed | not timed"

/* One more implicit row for (scene, k): method at median v ms, its three paired repeats a v, v, c v (in the
 * rounds' order), step error err, iters a step. */
static void extra(const char *scene, const char *family, int nv, double k, const char *method, double v, double a,
                  double c, double err, int iters) {
  size_t n = strlen(time_rows);
  snprintf(time_rows + n, sizeof time_rows - n,
           "%s,%s,%d,%.17g,%s,%.17g,%.17g,%.17g,%.17g;%.17g;%.17g,3,30,stable,1,%.17g,,%d\n", scene, family, nv, k,
           method, v, fmin(a, c) * v, fmax(a, c) * v, a * v, v, c * v, err, iters);
}

Test(claims_explicit_stability, E2_reproduced_when_explicit_is_slow_and_follows_omega_max) {
  timing(0.5, 1.5, 2.0, 100, 1e-3); /* explicit 1.6 ms .. 1.6 s against k; Baraff-Witkin 10 ms */
  cr_assert_eq(decide(cb_check_E2), CB_REPRODUCED, "%s", last.reason);
  /* the baseline is named, with its step error */
  cr_expect(strstr(last.numbers, "| cloth21 | stretch | 1e+07 | 441 | 1581 (1423-1739) | 1581 | 100 (100-120); 1e-08 | "
                                 "10 (9-11); 0.001 | 25 (22.5-27.5); 0.0001" NT " | Baraff-Witkin (drop) | 158 "
                                 "(158-158 "
                                 "over 3 paired repeats) |"),
            "%s", last.numbers);
  cr_expect(strstr(last.numbers, "Baraff-Witkin (one Newton iteration, the lecture's drop fix, CHOLMOD)"), "%s",
            last.numbers);
  cr_expect(strstr(last.numbers, "stretch family, k = 1e+04: explicit ~ n^1.500 (1.500 / 1.500 fitted to the fastest / "
                                 "slowest repeats), b_pred = 1.500 (omega_max ~ n^0.500)"),
            "%s", last.numbers);
  cr_expect(strstr(last.numbers, "bending family, k = 1e+04: explicit ~ n^2.000"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "explicit ~ k^0.500 (0.500 / 0.500 fitted to the fastest / slowest repeats) over 5 "
                                 "stiffnesses, predicted 0.500; explicit is slower from k = 1e+03"),
            "%s", last.numbers);
  cr_expect(strstr(last.reason, "Times are medians of 3 repeats."), "%s", last.reason);
}

Test(claims_explicit_stability, E2_partly_when_the_exponent_is_not_the_predicted_one) {
  timing(0.5, 2.0, 2.0, 100, 1e-3); /* the stretch family at n^2 (the old target) where omega_max predicts n^1.5 */
  cr_assert_eq(decide(cb_check_E2), CB_PARTLY, "%s", last.reason);
  cr_expect(strstr(last.reason, "worst: stretch family at k = 1e+04: b = 2.000 against b_pred = 1.500"), "%s",
            last.reason);
  timing(0.5, 1.5, 1.5, 100, 1e-3); /* the bending family's cost grows slower than its omega_max predicts */
  cr_assert_eq(decide(cb_check_E2), CB_PARTLY, "%s", last.reason);
}

Test(claims_explicit_stability, E2_not_reproduced_when_explicit_is_never_slower) {
  timing(0.5, 1.5, 2.0, 1e7, 1e-3); /* the implicit methods cost 1e6 ms and more: explicit is faster at every (k, n) */
  cr_assert_eq(decide(cb_check_E2), CB_NOT_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.reason, "slower than the fastest implicit method at 1/30 s within 1% step error in 0 of 10"),
            "%s", last.reason);
}

Test(claims_explicit_stability, E2_an_inaccurate_baraff_witkin_does_not_count) {
  timing(0.5, 1.5, 2.0, 100, 0.05); /* Baraff-Witkin (drop) 5% off: the shift variant (25 ms, 0.5%) is the baseline */
  decide(cb_check_E2);
  cr_expect(strstr(last.numbers, "| 10 (9-11); 0.05 | 25 (22.5-27.5); 0.005" NT " | Baraff-Witkin (shift) | 63.2 "
                                 "(63.2-63.2 over 3 paired repeats) |"),
            "%s", last.numbers);
  timing(0.5, 1.5, 2.0, 100, 0.5); /* both 5% and more off: converged Newton (100 ms) */
  decide(cb_check_E2);
  cr_expect(strstr(last.numbers, "; 0.05" NT " | converged Newton | 15.8 (14.2-15.8 over 3 paired repeats) |"), "%s",
            last.numbers);
  timing(0.0, 1.5, 2.0, 1e3, 0.05); /* explicit at 0.5 ms on the whole k sweep beats the 250 ms baseline */
  decide(cb_check_E2);
  cr_expect(strstr(last.reason, "but not at the stiffest k"), "%s", last.reason);
  cr_expect_neq(last.verdict, CB_REPRODUCED);
}

Test(claims_explicit_stability, E2_labels_newton_rows_that_did_not_converge_and_unstable_explicit) {
  timing(0.5, 1.5, 2.0, 100, 1e-3);
  char *p = strstr(time_rows, "cloth21,stretch,441,10000,newton,");
  cr_assert(p);
  p = strchr(p, '\n');
  cr_assert(p && p[-2] == '0'); /* not_converged_steps, before the empty iters_per_step */
  p[-2] = '5';                  /* 5 steps at max_iters */
  p = strstr(time_rows, "bend41,bending,1681,10000,explicit,");
  cr_assert(p);
  memcpy(strstr(p, "stable"), "diverg", 6); /* explicit not stable at the finest bending mesh */
  decide(cb_check_E2);
  cr_expect(strstr(last.numbers, "; 1e-08, **not converged** |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "(**not stable**)"), "%s", last.numbers);
  cr_expect(strstr(last.reason, "1 timed runs were not stable"), "%s", last.reason);
  cr_expect_neq(last.verdict, CB_REPRODUCED);
  cr_expect(!strstr(last.numbers, "nan"), "no nan cells: %s", last.numbers);
}

Test(claims_explicit_stability, I1_reproduced_when_newton_never_diverges_and_damps_more_with_dt) {
  build(0.99, -0.5, 0);
  cr_assert_eq(decide(cb_check_I1), CB_REPRODUCED);
}

Test(claims_explicit_stability, I1_fails_when_a_newton_cell_diverges) {
  build(0.99, -0.5, 1);
  cr_assert_eq(decide(cb_check_I1), CB_NOT_REPRODUCED);
  damp_exp = 0; /* stable, but the damping does not grow with dt */
  build(0.99, -0.5, 0);
  cr_assert_eq(decide(cb_check_I1), CB_PARTLY);
  damp_exp = 1;
}

Test(claims_explicit_stability, I1_partly_when_newton_runs_shorter_than_explicit) {
  newton_time = 0.1; /* stable and damping, but over a tenth of the explicit cells' time */
  build(0.99, -0.5, 0);
  cr_assert_eq(decide(cb_check_I1), CB_PARTLY, "%s", last.reason);
  cr_expect(strstr(last.reason, "0 of 72 Newton cells ran the simulated time of the explicit cell"), "%s", last.reason);
  newton_time = 1;
  build(0.99, -0.5, 0);
  decide(cb_check_I1);
  cr_expect(strstr(last.reason, "72 of 72 Newton cells ran the simulated time of the explicit cell"), "%s",
            last.reason);
}

Test(claims_explicit_stability, E1_says_at_which_state_it_is_judged) {
  static const char *hdr_eq = "# test\nscene,k_n_per_m,dt_crit_pred_s,dt_crit_meas_s,bisect_status,dt_crit_pred_rest_s,"
                              "lambda_dense_per_s2,lambda_lanczos_per_s2,equilibrium_status\n";
  build(0.99, -0.5, 0);
  char rows[8192] = "";
  for (char *line = strtok(bound_rows, "\n"); line;
       line = strtok(NULL, "\n")) /* every row started at its equilibrium */
    snprintf(rows + strlen(rows), sizeof rows - strlen(rows), "%s,ok\n", line);
  snprintf(bound_rows, sizeof bound_rows, "%s", rows);
  const char *saved = bound_hdr;
  bound_hdr = hdr_eq;
  decide(cb_check_E1);
  bound_hdr = saved;
  cr_expect(strstr(last.reason, "Judged at the state every run starts from, the static hanging equilibrium"), "%s",
            last.reason);
  cr_expect(strstr(last.reason, "At the flat rest shape instead, 8 of 8 lie within 15%"), "%s", last.reason);
  build(0.99, -0.5, 0); /* no equilibrium recorded: it says so */
  decide(cb_check_E1);
  cr_expect(strstr(last.reason, "the static hanging equilibrium in 0 of 8 rows"), "%s", last.reason);
}

/* The new implicit methods (issue 31 §6) enter the baseline by the same rule: an accurate pd faster than
 * explicit turns "never slower" into reproduced; an inaccurate chebyshev-nl, however fast, does not count. */
Test(claims_explicit_stability, E2_new_implicit_methods_count_only_when_accurate) {
  timing(0.5, 1.5, 2.0, 1e7, 1e-3); /* Newton and Baraff-Witkin at 1e6 ms and more: explicit faster everywhere */
  const char *sc[] = {"cloth21", "cloth21", "cloth21", "cloth21", "cloth21",
                      "cloth41", "cloth81", "bend11",  "bend21",  "bend41"};
  const char *fam[] = {"stretch", "stretch", "stretch", "stretch", "stretch",
                       "stretch", "stretch", "bending", "bending", "bending"};
  const int nv[] = {441, 441, 441, 441, 441, 1681, 6561, 121, 441, 1681};
  const double ks[] = {10, 1e3, 1e4, 1e5, 1e7, 1e4, 1e4, 1e4, 1e4, 1e4};
  for (int i = 0; i < 10; i++) extra(sc[i], fam[i], nv[i], ks[i], "chebyshev_nl", 0.01, 0.9, 1.1, 0.05, 512);
  cr_assert_eq(decide(cb_check_E2), CB_NOT_REPRODUCED, "%s", last.reason); /* 5% off: out of the baseline */
  cr_expect(strstr(last.numbers, "| 512 it.: 0.01 (0.009-0.011); 0.05 |"), "%s", last.numbers);
  for (int i = 0; i < 10; i++) extra(sc[i], fam[i], nv[i], ks[i], "pd", 0.01, 0.9, 1.1, 1e-3, 32);
  cr_assert_eq(decide(cb_check_E2), CB_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.numbers, "| 32 it.: 0.01 (0.009-0.011); 0.001 | pd |"), "%s", last.numbers);
  /* Newton with 2 iterations, accurate and the fastest: it is the baseline */
  timing(0.5, 1.5, 2.0, 1e7, 1e-3);
  for (int i = 0; i < 10; i++) extra(sc[i], fam[i], nv[i], ks[i], "newton_2", 0.02, 0.9, 1.1, 2e-3, 2);
  cr_assert_eq(decide(cb_check_E2), CB_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.numbers, "| 0.02 (0.018-0.022); 0.002 / not timed / not timed / not timed | not timed | not "
                                 "timed | Newton, 2 iterations |"),
            "%s", last.numbers);
}

/* A timing verdict whose paired spread straddles 1 is undecided (issue 31 §7's rule, cb_claim_timing_side):
 * explicit faster everywhere except one row where an accurate pd ties it, repeat by repeat 0.75x to 1.38x. */
Test(claims_explicit_stability, E2_undecided_when_the_deciding_ratio_straddles_one) {
  timing(0.5, 1.5, 2.0, 1e7, 1e-3);
  double ex = 0.5 * pow(1e7, 0.5); /* explicit's median at k = 1e7; its repeats 0.9, 1, 1.1 x */
  extra("cloth21", "stretch", 441, 1e7, "pd", ex, 1.2, 0.8, 1e-3, 10);
  cr_assert_eq(decide(cb_check_E2), CB_UNDECIDED, "%s", last.reason);
  cr_expect(strstr(last.reason, "in 0 of 10 timed rows, faster in 9, undecided within the spread in 1"), "%s",
            last.reason);
  cr_expect(strstr(last.numbers, "over 3 paired repeats), undecided |"), "%s", last.numbers);
  /* the same tie outside the spread (explicit's repeats slower in every round): reproduced is not claimed, the
   * row counts as slower */
  timing(0.5, 1.5, 2.0, 1e7, 1e-3);
  extra("cloth21", "stretch", 441, 1e7, "pd", ex / 2, 1, 1, 1e-3, 10);
  cr_assert_neq(decide(cb_check_E2), CB_UNDECIDED, "%s", last.reason);
  cr_expect(strstr(last.reason, "in 1 of 10 timed rows, faster in 9, undecided within the spread in 0"), "%s",
            last.reason);
}
