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

void cb_check_E1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_E2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_I1(const cb_table *t, const char *results_dir, cb_claim_result *out);

static const char *main_hdr = "# test\nkind,case,scene,k_n_per_m,dt_s,method,status,max_energy_ratio,steps,dt_crit_pred_s,dt_crit_meas_s,"
                              "not_converged_steps,t_mark_s,energy_loss_w,kinetic0_j,window_s\n";
static const char *bound_hdr = "# test\nscene,k_n_per_m,dt_crit_pred_s,dt_crit_meas_s,bisect_status,dt_crit_pred_rest_s,"
                               "lambda_dense_per_s2,lambda_lanczos_per_s2\n";
static const char *time_hdr = "# test\nscene,n_vertices,k_n_per_m,method,wall_ms_per_s,wall_min_ms_per_s,wall_max_ms_per_s,"
                              "wall_each_ms_per_s,wall_repeats,steps,status\n";

static char dir[64];
static char main_rows[65536], bound_rows[8192], time_rows[8192];

static void put(const char *name, const char *hdr, const char *rows) {
  char path[256];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  cr_assert(f);
  fputs(hdr, f);
  fputs(rows, f);
  fclose(f);
}

static cb_claim_result last; /* the result of the last decide() */

static cb_verdict decide(void (*check)(const cb_table *, const char *, cb_claim_result *)) {
  snprintf(dir, sizeof dir, "/tmp/cbclaimsXXXXXX");
  cr_assert(mkdtemp(dir));
  put("explicit_stability.csv", main_hdr, main_rows);
  put("explicit_stability_boundary.csv", bound_hdr, bound_rows);
  put("explicit_stability_timing.csv", time_hdr, time_rows);
  char path[256];
  snprintf(path, sizeof path, "%s/explicit_stability.csv", dir);
  cb_table t;
  cr_assert_eq(cb_table_read(path, &t), 0);
  cb_claim_result r;
  memset(&r, 0, sizeof r);
  check(&t, dir, &r);
  last = r;
  cb_table_free(&t);
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
static double damp_exp = 1; /* energy lost per second ~ dt^damp_exp */
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
        snprintf(main_rows + n, sizeof main_rows - n, "sweep,map,%s,%.17g,%.17g,explicit,%s,0,100,%.17g,%.17g,0,0.1,0,1,0\n",
                 sc[s], k, dt, st, pred, meas);
        double loss = 5 * pow(dt, damp_exp); /* J per s, kinetic0 = 1 J */
        const char *nst = newton_diverges && s == 1 && i == 3 && j == 8 ? "diverged" : "stable";
        n = strlen(main_rows);
        snprintf(main_rows + n, sizeof main_rows - n, "sweep,map,%s,%.17g,%.17g,newton,%s,0,10,%.17g,%.17g,0,0.1,%.17g,1,0.1\n",
                 sc[s], k, dt, nst, pred, meas, loss);
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

static void timing(double kexp, double nexp, double newton_ms) {
  time_rows[0] = '\0';
  char e[256], nt[256], bw[256];
  for (int i = 0; i < 4; i++) {
    double k = pow(10.0, 1 + 2 * i), ex = 0.5 * pow(k, kexp);
    reps(e, sizeof e, ex, 0);
    reps(nt, sizeof nt, newton_ms, 1);
    reps(bw, sizeof bw, newton_ms / 10, 0);
    size_t n = strlen(time_rows);
    snprintf(time_rows + n, sizeof time_rows - n, "cloth21,441,%.17g,explicit,%s,%.0f,stable\n"
             "cloth21,441,%.17g,newton,%s,30,stable\ncloth21,441,%.17g,newton_bw,%s,30,stable\n",
             k, e, 100 * sqrt(k), k, nt, k, bw);
  }
  const int nv[] = {441, 1681, 6561};
  for (int r = 0; r < 3; r++) {
    size_t n = strlen(time_rows);
    double w = 0.5 * pow(1e3, kexp) * pow(nv[r] / 441.0, nexp);
    reps(e, sizeof e, w, 0);
    snprintf(time_rows + n, sizeof time_rows - n, "cloth%d,%d,1000,explicit,%s,%.0f,stable\n", r, nv[r], e,
             100 * pow(nv[r] / 441.0, 0.5));
  }
}

Test(claims_explicit_stability, E2_reproduced_when_explicit_is_slow_and_quadratic) {
  timing(0.5, 2.0, 100); /* explicit 0.5 ms .. 1.6 s; Newton 100 ms */
  cr_assert_eq(decide(cb_check_E2), CB_REPRODUCED);
}

Test(claims_explicit_stability, E2_quotes_every_time_with_its_spread) {
  timing(0.5, 2.0, 100);
  decide(cb_check_E2);
  /* k = 1e7: explicit 0.5 sqrt(1e7) = 1581 ms, repeats 0.9, 1, 1.1 x; Newton 100 ms, 1, 1, 1.2 x */
  cr_expect(strstr(last.numbers, "| cloth21 | 1e+07 | 1581 (1423-1739) | 316228 | 100 (100-120) (convergence not recorded) | 10 (9-11) |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "median of 3 repeats"), "%s", last.numbers);
  /* explicit/Newton = 15.8; paired repeats 0.9/1, 1/1, 1.1/1.2 give 14.2 .. 15.8 (bounds would be 11.9 .. 17.4) */
  cr_expect(strstr(last.numbers, "explicit/Newton = 15.8 (14.2-15.8 over 3 paired repeats)"), "%s", last.numbers);
  /* every series scaled alike by the repeats: the fits to the fastest and slowest agree with the median's */
  cr_expect(strstr(last.numbers, "explicit ~ k^0.500 (0.500 / 0.500 fitted to the fastest / slowest repeats)"), "%s", last.numbers);
  cr_expect(strstr(last.reason, "last exponent 2.000 (2.000 / 2.000 fitted"), "%s", last.reason);
  cr_expect(strstr(last.reason, "Times are medians of 3 repeats."), "%s", last.reason);
}

Test(claims_explicit_stability, E2_partly_or_not_reproduced) {
  timing(0.5, 1.5, 1e5); /* cost grows with k but stays below Newton's, and n^1.5 */
  cr_assert_eq(decide(cb_check_E2), CB_PARTLY);
  timing(0.0, 2.0, 1); /* cost independent of k: small dt is not what makes it slow */
  cr_assert_eq(decide(cb_check_E2), CB_NOT_REPRODUCED);
}

Test(claims_explicit_stability, E2_labels_newton_rows_that_did_not_converge) {
  static const char *hdr_nc = "# test\nscene,n_vertices,k_n_per_m,method,wall_ms_per_s,steps,status,not_converged_steps\n";
  const char *saved = time_hdr;
  time_hdr = hdr_nc;
  /* k = 10: Newton converged; k = 1e4: 5 of 30 steps stopped at max_iters; 41^2: Newton not timed */
  snprintf(time_rows, sizeof time_rows,
           "cloth21,441,10,explicit,0.05,6,stable,0\ncloth21,441,10,newton,150,30,stable,0\ncloth21,441,10,newton_bw,30,30,stable,0\n"
           "cloth21,441,10000,explicit,1.3,147,stable,0\ncloth21,441,10000,newton,570,30,stable,5\n"
           "cloth21,441,1e7,explicit,42,4630,stable,0\ncloth21,441,1e7,newton,520,30,stable,0\n"
           "cloth41,1681,10000,explicit,10,287,stable,0\ncloth41,1681,10000,newton_bw,200,30,stable,0\n");
  decide(cb_check_E2);
  time_hdr = saved;
  cr_expect(strstr(last.numbers, "| 570 (**not converged**: 5 of 30 steps at max_iters) |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "| 150 | 30 |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "| cloth41 | 1e+04 | 10 | 287 | not timed | 200 |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "timed on 3 (scene, k) rows; 1 of them had steps that stopped at max_iters"), "%s", last.numbers);
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
