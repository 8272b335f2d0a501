/* Verdict logic of the J3 (both panels), W1 and P1 checkers
 * (claims/check_nonlinear.c) on small constructed CSVs, through the claims
 * table: a passing and a failing case per claim. */
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
  snprintf(dir, sizeof dir, "/tmp/cbclaims_nl_XXXXXX");
  cr_assert(mkdtemp(dir), "mkdtemp failed");
}

static void teardown(void) {
  const char *names[] = {"nonlinear.csv",          "nonlinear_w1.csv",   "nonlinear_p1.csv",
                         "nonlinear_p1_error.csv", "linear_solvers.csv", "linear_solvers_scenes.csv"};
  char path[256];
  for (int i = 0; i < 6; i++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    remove(path);
  }
  remove(dir);
}

static void put(const char *name, const char *text) { test_put(dir, name, "# experiment: nonlinear\n", text); }

static cb_verdict decide(const char *id, cb_claim_result *res) { return test_decide_claim(id, "nonlinear", dir, res); }

/* ---- J3 ---- */

#define J3_HEAD \
  "panel,rho_given,rho,frames,frames_run,diverged,diverge_frame,median_rel_grad,rho_lin_median,rho_lin_max\n"

/* panel (b) as linear_solvers writes it: true rho 0.96 at alpha = 1 (eig(D^-1 A) in [0.04, 1.96]);
 * diverging overestimates when div is 1 */
static void linear_panel(int div) {
  char path[256];
  snprintf(path, sizeof path, "%s/linear_solvers_scenes.csv", dir);
  FILE *f = fopen(path, "w");
  cr_assert(f);
  fputs("# experiment: "
        "linear_solvers\nscene,grid_n,n_dofs,non_dd_rows,lmin_lanczos,lmax_lanczos,lmin_dense,lmax_dense,spectrum\n"
        "lab,21,1323,21,0.04,1.96,0.04,1.96,dense\n",
        f);
  fclose(f);
  snprintf(path, sizeof path, "%s/linear_solvers.csv", dir);
  f = fopen(path, "w");
  cr_assert(f);
  fputs("# experiment: linear_solvers\nscene,sweep,solver,alpha,rho,iter,rel_residual,wall_ms,status,error\n", f);
  const double rhos[] = {0.95, 0.98, 0.995}, rates[] = {0.8, 2.0, 2.0};
  for (int r = 0; r < 3; r++) {
    double rate = div ? rates[r] : 0.8;
    int n = rate > 1 ? 20 : 70;
    for (int k = 0; k <= n; k++)
      fprintf(f, "lab,rho,chebyshev,1,%g,%d,%.17g,%d,%s,%.17g\n", rhos[r], k, pow(rate, k), k,
              rate > 1 ? "diverged" : "ok", pow(rate, k));
  }
  fclose(f);
}

/* true linearised rho 0.97 in every converging run */
static void lab_panel(int div995, int div_under) {
  char buf[2048] = J3_HEAD;
  const char *rhos[] = {"0.9", "0.95", "0.99", "0.995", "0.9999"};
  const double vals[] = {0.9, 0.95, 0.99, 0.995, 0.9999};
  for (int r = 0; r < 5; r++) {
    int dv = vals[r] == 0.9999 || (vals[r] == 0.995 && div995) || (vals[r] == 0.9 && div_under);
    sprintf(buf + strlen(buf), "lab_iteration,%s,%g,2000,%d,%d,%s,0.01,%s,0.975\n", rhos[r], vals[r], dv ? 40 : 2000,
            dv, dv ? "41" : "", dv ? "0.99" : "0.97"); /* diverge_frame is empty when the run did not diverge */
  }
  put("nonlinear.csv", buf);
}

TestSuite(claims_nonlinear, .init = setup, .fini = teardown);

Test(claims_nonlinear, j3_reproduced_when_both_panels_see_overestimates_diverge) {
  lab_panel(1, 0);
  linear_panel(1);
  cb_claim_result r;
  cr_expect_eq(decide("J3", &r), CB_REPRODUCED, "%s", r.reason);
  cr_expect(strstr(r.reason, "Panel (a), the lab's iteration") && strstr(r.reason, "Panel (b), linear solves"), "%s",
            r.reason);
}

Test(claims_nonlinear, j3_partly_when_only_the_lab_iteration_diverges) {
  lab_panel(1, 0);
  linear_panel(0);
  cb_claim_result r;
  cr_expect_eq(decide("J3", &r), CB_PARTLY, "%s", r.reason);
}

Test(claims_nonlinear, j3_not_reproduced_when_an_underestimate_diverges_and_linear_never_does) {
  lab_panel(0, 1);
  linear_panel(0);
  cb_claim_result r;
  cr_expect_eq(decide("J3", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

/* ---- W1 ---- */

#define W1_HEAD \
  "scene,n,method,pair,rho,max_iters,tol,iters_to_tol,wall_to_tol_ms,setup_ms,alloc_ms,final_rel_grad,status\n"

/* pd_plain_iters < 0: plain pd was cut off at its largest cap (iters_to_tol and wall_to_tol_ms empty) */
static void w1(int cheb_iters, int pd_plain_iters) {
  char buf[2048] = W1_HEAD, pd[64] = ",";
  if (pd_plain_iters >= 0) snprintf(pd, sizeof pd, "%d,300", pd_plain_iters);
  sprintf(
      buf + strlen(buf),
      "lab,21,jacobi-nl,jacobi,0,20000,0.0001,3000,30,0,0,1e-9,ok\n"
      "lab,21,chebyshev-nl auto,jacobi,0.998,20000,0.0001,%d,3,1,0,1e-12,ok\n" /* plain's rate 1e-4^(1/3000) = 0.9969 */
      "lab,21,pd,pd,0,1000,0.0001,%s,0,5,1e-5,ok\n"
      "lab,21,pd-chebyshev auto,pd,0.95,1000,0.0001,50,50,8,5,1e-10,ok\n",
      cheb_iters, pd);
  put("nonlinear_w1.csv", buf);
  put("nonlinear.csv", J3_HEAD);
}

Test(claims_nonlinear, w1_reproduced_at_an_order_of_magnitude_a_cut_off_pair_undecided) {
  w1(250, -1); /* 12x; pd plain cut off: undecided, neither for nor against */
  cb_claim_result r;
  cr_expect_eq(decide("W1", &r), CB_REPRODUCED, "%s", r.reason);
  cr_expect(strstr(r.reason, "in 1 of 1 decided") && strstr(r.reason, "1 more undecided"), "%s", r.reason);
  cr_expect(strstr(r.numbers, "| cut off at 1000 | 50 | undecided (cut off) |"), "%s", r.numbers);
}

Test(claims_nonlinear, w1_partly_and_a_low_rho_shown_against_plains_rate) {
  w1(250, 200); /* 12x and 4x; pd-chebyshev's 0.95 below plain pd's 1e-4^(1/200) = 0.9550 */
  cb_claim_result r;
  cr_expect_eq(decide("W1", &r), CB_PARTLY, "%s", r.reason);
  cr_expect(strstr(r.numbers, "pd-chebyshev auto (0.9500; 0.9550)"), "%s", r.numbers);
  cr_expect(strstr(r.reason, "in 1 of 2 pairs"), "%s", r.reason);
}

Test(claims_nonlinear, w1_not_reproduced_below_ten) {
  w1(1000, 200); /* 3x and 4x */
  cb_claim_result r;
  cr_expect_eq(decide("W1", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

#define W1_HEAD_SPREAD \
  "scene,n,method,pair,rho,max_iters,tol,iters_to_tol,wall_to_tol_ms,wall_to_tol_min_ms,wall_to_tol_max_ms," \
  "wall_to_tol_each_ms,wall_repeats,setup_ms,alloc_ms,final_rel_grad,status\n"

/* Repeats: jacobi-nl 30, 33, 27 ms and chebyshev-nl 3, 3.3, 2.7 ms (interleaved): paired speed-ups 10, 10, 10
 * (bounds from the min and max would give 8.2-12.2); pd never reached the tolerance (nan, no repeats). */
Test(claims_nonlinear, w1_quotes_wall_times_with_their_spread) {
  char buf[2048] = W1_HEAD_SPREAD;
  strcat(buf, "lab,21,jacobi-nl,jacobi,0,20000,0.0001,3000,30,27,33,30;33;27,3,0,0,1e-9,ok\n"
              "lab,21,chebyshev-nl auto,jacobi,0.97,20000,0.0001,250,3,2.7,3.3,3;3.3;2.7,3,1,0,1e-12,ok\n"
              "lab,21,pd,pd,,1000,0.0001,,,,,,,,5,1e-5,ok\n"
              "lab,21,pd-chebyshev auto,pd,0.95,1000,0.0001,50,50,49,52,50;52;49,3,8,5,1e-10,ok\n");
  put("nonlinear_w1.csv", buf);
  put("nonlinear.csv", J3_HEAD);
  cb_claim_result r;
  cr_expect_eq(decide("W1", &r), CB_REPRODUCED, "%s", r.reason);
  cr_expect(strstr(r.numbers, "| 30 (27-33) | 3 (2.7-3.3) | 10.0x (10.0-10.0x) |"), "%s", r.numbers);
  cr_expect(strstr(r.numbers, "| - | 50 (49-52) | - |"), "%s", r.numbers);
  cr_expect(strstr(r.numbers, "median of 3 repeats"), "%s", r.numbers);
  cr_expect(strstr(r.reason, "10.0x (10.0-10.0x over 3 paired repeats) (lab chebyshev-nl auto)"), "%s", r.reason);
}

/* ---- P1 ---- */

#define P1_HEAD "scene,n,k_n_per_m,method,frame,iters,wall_ms,alloc_ms,step_error,rel_grad,fallback,status\n"
#define P1E_HEAD "scene,n,k_n_per_m,method,frame,tol,max_iters,iters_to_tol,wall_to_tol_ms,step_error,fallback,status\n"

/* Two frames: pd10 pd_ms at error pd_err; newton_exact 1000 ms (status exact_status), newton_drop 2000 ms, both
 * converged; Baraff-Witkin 40 ms at error bw_err. To step error 1e-2: pd in pd_to ms (12 iterations), newton_exact
 * in newton_to ms (2 iterations); to 1e-3: pd cut off at its cap, newton_exact 3 iterations. */
static void p1(double pd_ms, double pd_err, double bw_err, double pd_to, double newton_to, const char *exact_status) {
  char buf[4096] = P1_HEAD, eb[4096] = P1E_HEAD;
  for (int f = 5; f <= 10; f += 5) {
    sprintf(buf + strlen(buf),
            "grid81,81,8000,pd10,%d,10,%g,40,%g,0.05,0,ok\n"
            "grid81,81,8000,newton_exact,%d,5,1000,6,1e-9,1e-9,0,%s\n"
            "grid81,81,8000,newton_drop,%d,20,2000,6,1e-9,1e-9,0,ok\n"
            "grid81,81,8000,baraff_witkin,%d,1,40,6,%g,0.1,0,max_iters\n",
            f, pd_ms, pd_err, f, f == 10 ? exact_status : "ok", f, f, bw_err);
    sprintf(eb + strlen(eb),
            "grid81,81,8000,pd,%d,0.01,400,12,%g,0.009,,ok\n"
            "grid81,81,8000,pd,%d,0.001,400,,,,,cut_off\n"
            "grid81,81,8000,newton_exact,%d,0.01,50,2,%g,0.004,0,max_iters\n"
            "grid81,81,8000,newton_exact,%d,0.001,50,3,%g,0.0001,0,max_iters\n",
            f, pd_to, f, f, newton_to, f, 1.5 * newton_to);
  }
  put("nonlinear_p1.csv", buf);
  put("nonlinear_p1_error.csv", eb);
  put("nonlinear.csv", J3_HEAD);
}

Test(claims_nonlinear, p1_reproduced_when_pd_is_fast_close_and_first_to_the_same_error) {
  p1(20, 0.01, 0.05, 25, 400,
     "ok"); /* 50x per frame over newton_exact; at 1e-2 400/25 = 16x (BW's 5% does not get there) */
  cb_claim_result r;
  cr_expect_eq(decide("P1", &r), CB_REPRODUCED, "%s", r.reason);
  cr_expect(strstr(r.reason, "50x") && strstr(r.reason, "over newton_exact"), "%s", r.reason);
  cr_expect(strstr(r.reason, "grid81 16.00x"), "%s", r.reason);
  cr_expect(strstr(r.numbers, "| grid81 | step_error 0.001 | not reached within the cap on 2 of 2 frames | 600 ms "
                              "(newton_exact) | - | Newton (pd never) |"),
            "%s", r.numbers);
}

Test(claims_nonlinear, p1_partly_when_baraff_witkin_reaches_the_same_error_as_fast) {
  p1(20, 0.01, 0.001, 25, 400, "ok"); /* BW's one iteration reaches 1e-2 in 40 ms: 40/25 = 1.6x */
  cb_claim_result r;
  cr_expect_eq(decide("P1", &r), CB_PARTLY, "%s", r.reason);
  cr_expect(strstr(r.numbers, "| grid81 | step_error 0.01 | 25 ms | 40 ms (baraff_witkin) | 1.60x | pd |"), "%s",
            r.numbers);
}

Test(claims_nonlinear, p1_baseline_is_the_fastest_newton_that_converged) {
  p1(20, 0.01, 0.05, 25, 400, "max_iters"); /* newton_exact cut on a frame: the baseline is newton_drop, 100x */
  cb_claim_result r;
  decide("P1", &r);
  cr_expect(strstr(r.reason, "100x") && strstr(r.reason, "over newton_drop"), "%s", r.reason);
  cr_expect(strstr(r.numbers, "| grid81 | 6561 | newton_exact | 2 | 1000 | 1e-09 | - | 1e-09 | 1 of 2 |"), "%s",
            r.numbers);
}

Test(claims_nonlinear, p1_not_reproduced_when_pd_is_not_ten_times_faster) {
  p1(200, 0.01, 0.05, 25, 400, "ok"); /* 5x per frame */
  cb_claim_result r;
  cr_expect_eq(decide("P1", &r), CB_NOT_REPRODUCED, "%s", r.reason);
}

#define P1_HEAD_SPREAD \
  "scene,n,k,method,frame,iters,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,alloc_ms,step_error," \
  "rel_grad,status\n"

/* Two frames, three interleaved repeats: pd10 20, 19, 21 ms and 20, 21, 19 ms (per repeat the median over the
 * frames: 20, 20, 20); Newton 1000, 1100, 900 ms at both: paired ratios 50, 55, 45 (bounds: 42.9-57.9). */
Test(claims_nonlinear, p1_quotes_times_and_the_ratio_with_their_spread) {
  char buf[2048] = P1_HEAD_SPREAD;
  strcat(buf, "grid81,81,8000,pd10,5,10,20,19,21,20;19;21,3,40,0.01,0.05,ok\n"
              "grid81,81,8000,newton_exact,5,5,1000,900,1100,1000;1100;900,3,6,1e-9,1e-9,ok\n"
              "grid81,81,8000,baraff_witkin,5,1,40,39,41,40;41;39,3,6,0.001,0.1,max_iters\n"
              "grid81,81,8000,pd10,10,10,20,19,21,20;21;19,3,40,0.01,0.05,ok\n"
              "grid81,81,8000,newton_exact,10,5,1000,900,1100,1000;1100;900,3,6,1e-9,1e-9,ok\n"
              "grid81,81,8000,baraff_witkin,10,1,40,39,41,40;39;41,3,6,0.001,0.1,max_iters\n");
  put("nonlinear_p1.csv", buf);
  put("nonlinear.csv", J3_HEAD);
  cb_claim_result r;
  cr_expect_eq(decide("P1", &r), CB_PARTLY, "%s", r.reason); /* no time-to-error table: not >= 10x at equal error */
  cr_expect(strstr(r.numbers, "| grid81 | 6561 | pd10 | 2 | 20 (20-20) | 0.01 |"), "%s", r.numbers);
  cr_expect(strstr(r.numbers, "| grid81 | 6561 | newton_exact | 2 | 1000 (900-1100) |"), "%s", r.numbers);
  cr_expect(strstr(r.reason, "grid81: 50x (45-55x over 3 paired repeats) over newton_exact"), "%s", r.reason);
  cr_expect(strstr(r.reason, "Baraff-Witkin 0.001 in 40 (40-40) ms"), "%s", r.reason);
}

/* Issue 31's CSVs (measure, obj_error, global_matrix, lbfgs10): pd10's per-frame speed-up over newton_exact
 * has paired repeats 10.5x, 20x and 5x (it straddles 10x), the rest passes (error 1%, 16x at step error 1e-2):
 * counted as fast it is reproduced, as slow not: undecided. With repeats 20x, 25x, 16.7x it is reproduced. The
 * papers' set-ups are labelled rows, and the objective error and |grad F| rows are reported. */
static void p1_spread(const char *pd_each, double pd_med) {
  char buf[4096] = "scene,n,k_n_per_m,method,frame,iters,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,"
                   "alloc_ms,step_error,obj_error,rel_grad,fallback,global_matrix,status\n";
  char eb[4096] = "scene,n,k_n_per_m,method,frame,measure,tol,max_iters,iters_to_tol,wall_to_tol_ms,wall_to_tol_min_ms,"
                  "wall_to_tol_max_ms,wall_to_tol_each_ms,wall_repeats,step_error,obj_error,rel_grad,fallback,"
                  "global_matrix,status\n";
  sprintf(buf + strlen(buf),
          "grid81,81,8000,pd10,5,10,%g,,,%s,3,40,0.01,0.002,0.05,0,scalar,ok\n"
          "grid81,81,8000,lbfgs10,5,10,30,,,30;30;30,3,40,0.004,0.0005,0.02,0,scalar,max_iters\n"
          "grid81,81,8000,newton_exact,5,5,1000,,,1050;1000;1000,3,6,1e-9,1e-12,1e-9,0,none,ok\n"
          "grid81,81,8000,newton_drop,5,20,2000,,,2000;2000;2000,3,6,1e-9,1e-12,1e-9,0,none,ok\n"
          "grid81,81,8000,baraff_witkin,5,1,40,,,40;40;40,3,6,0.05,0.02,0.1,0,none,max_iters\n",
          pd_med, pd_each);
  static const char *const meas[3] = {"step_error", "obj_error", "rel_grad"};
  static const double tols[3][2] = {{1e-2, 1e-3}, {1e-2, 1e-3}, {1e-3, 1e-5}};
  for (int me = 0; me < 3; me++)
    for (int q = 0; q < 2; q++) {
      if (q == 0)
        sprintf(eb + strlen(eb), "grid81,81,8000,pd,5,%s,%g,400,12,25,,,25;25;25,3,0.009,0.001,0.04,0,scalar,ok\n",
                meas[me], tols[me][q]);
      else sprintf(eb + strlen(eb), "grid81,81,8000,pd,5,%s,%g,400,,,,,,,,,,,none,cut_off\n", meas[me], tols[me][q]);
      sprintf(eb + strlen(eb),
              "grid81,81,8000,newton_exact,5,%s,%g,50,2,400,,,400;400;400,3,0.004,1e-5,1e-4,0,none,max_iters\n",
              meas[me], tols[me][q]);
    }
  put("nonlinear_p1.csv", buf);
  put("nonlinear_p1_error.csv", eb);
  put("nonlinear.csv", J3_HEAD);
}

Test(claims_nonlinear, p1_undecided_when_the_per_frame_speed_up_straddles_ten) {
  p1_spread("100;50;200", 100); /* Newton / pd per repeat: 10.5, 20, 5 */
  cb_claim_result r;
  cr_expect_eq(decide("P1", &r), CB_UNDECIDED, "%s", r.reason);
  cr_expect(strstr(r.reason, "Undecided within the spread"), "%s", r.reason);
  p1_spread("50;40;60", 50); /* 21, 25, 16.7: above 10 in every pair */
  cr_expect_eq(decide("P1", &r), CB_REPRODUCED, "%s", r.reason);
  cr_expect(strstr(r.numbers, "Liu 2017: lbfgs 10 iterations vs Baraff-Witkin"), "the papers' set-ups: %s", r.numbers);
  cr_expect(strstr(r.numbers, "Liu 2013: pd 10 iterations vs newton_exact converged"), "%s", r.numbers);
  cr_expect(strstr(r.numbers, "| grid81 | obj_error 0.01 | 25 ms (25-25 ms) | 400 ms (400-400 ms) (newton_exact) | "
                              "16.00x"),
            "%s", r.numbers);
  cr_expect(strstr(r.numbers, "| grid81 | rel_grad 1e-05 | not reached within the cap on 1 of 1 frames |"), "%s",
            r.numbers);
  cr_expect(strstr(r.numbers, "| grid81 | 6561 | lbfgs10 | 1 | 30 (30-30) | 0.004 | 0.0005 | 0.02 | - |"), "%s",
            r.numbers);
}
