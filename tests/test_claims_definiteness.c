/* Verdict logic of the H1/H2 checkers on small constructed CSVs. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"
#include "support.h"

#define MAIN_HEAD \
  "scene,policy,step,newton_iter,system,spd,min_eig_n_per_m,min_eig_res_n_per_m,mu_n_per_m,spd_exact," \
  "min_eig_exact_n_per_m,compressed_frac,cg_breakdown,cg_status,cg_iters,rel_grad,grad_norm_n,f_j,energy_j,wall_ms," \
  "status\n"
#define RUNS_HEAD \
  "scene,policy,steps,steps_done,steps_converged,newton_iters,systems,not_spd,indefinite_exact," \
  "cg_breakdowns,mu_max_n_per_m,factorizations,wall_ms,probe_ms,final_f_j,final_energy_j,final_rel_grad,shape_diff_" \
  "none_m," \
  "shape_diff_drop_m,status\n"
#define PAIR_HEAD \
  "dim,policy,buckling_kb_n_m2,ratio,min_eig_h_n_per_m,min_eig_a_n_per_m,predicted_min_eig_a_n_per_m,spd\n"

static void put(const char *dir, const char *name, const char *text) {
  test_put(dir, name, "# provenance: test\n", text);
}

/* A system row: policy, spd (used), min_eig, spd_exact, min_eig_exact, compressed fraction, CG breakdown. */
static void row(char *buf, const char *pol, int spd, double me, int spdx, double mex, double comp, int bd) {
  char r[512];
  snprintf(r, sizeof r, "s1,%s,1,0,1,%d,%g,0,0,%d,%g,%g,%d,%s,3,1,1,0,0,0.1,%s\n", pol, spd, me, spdx, mex, comp, bd,
           bd ? "indefinite" : "ok", spd ? "ok" : "not_spd");
  strcat(buf, r);
}

static const char *good_pair = PAIR_HEAD "1,none,,0.7,16000,16900,16900,1\n2,none,,0.7,-6857,-5957,-5957,0\n3,none,,0."
                                         "7,-6857,-5957,-5957,0\n"
                                         "1,none,,0.99,16000,16900,16900,1\n3,none,,0.99,-161,739,739,1\n";

static cb_verdict decide(const char *id, const char *dir) {
  cb_claim_result *r = calloc(1, sizeof *r); /* 36 KiB: not on the stack */
  cr_assert_not_null(r);
  cb_verdict v = test_decide_claim(id, NULL, dir, r);
  free(r);
  return v;
}

static char *tmpdir(void) {
  static char d[64];
  strcpy(d, "/tmp/cbclaims_XXXXXX");
  cr_assert_not_null(mkdtemp(d));
  return d;
}

/* Every policy's run; the fixes' costs differ: Newton iterations (= factorisations) 10, 13, 11, 6 and
 * wall ms 1, 1.3, 1.5, 0.8 for drop, mirror, shift, choi-ko over 5 steps. */
static void runs_all_finished(const char *dir, const char *broken) {
  char buf[4096] = RUNS_HEAD;
  const char *pols[] = {"none", "drop", "mirror", "shift", "choi-ko"};
  const int iters[] = {1, 10, 13, 11, 6};
  const double wall[] = {0.1, 1, 1.3, 1.5, 0.8};
  for (int p = 0; p < 5; p++) {
    char r[512];
    int done = p == 0 ? 1 : (broken && !strcmp(broken, pols[p])) ? 3 : 5;
    snprintf(r, sizeof r, "s1,%s,5,%d,%d,%d,10,0,0,0,0,%d,%g,1,0,0,0,,,%s\n", pols[p], done, done, iters[p], iters[p],
             wall[p], p == 0 ? "not_spd" : "ok");
    strcat(buf, r);
  }
  put(dir, "definiteness_runs.csv", buf);
}

Test(claims_definiteness, h1_reproduced_on_indefinite_compressed_scene) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  row(buf, "none", 0, -5000, 0, -5000, 0.6, 1);
  row(buf, "drop", 1, 900, 0, -3000, 0.5, 0);
  row(buf, "drop", 1, 900, 1, 800, 0.0, 0); /* nothing compressed: SPD */
  put(dir, "definiteness.csv", buf);
  put(dir, "definiteness_pair.csv", good_pair);
  cr_assert_eq(decide("H1", dir), CB_REPRODUCED);
}

Test(claims_definiteness, h1_not_reproduced_when_never_indefinite) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  row(buf, "none", 1, 500, 1, 500, 0.3, 0);
  row(buf, "drop", 1, 900, 1, 800, 0.2, 0);
  put(dir, "definiteness.csv", buf);
  put(dir, "definiteness_pair.csv", PAIR_HEAD "1,none,,0.7,16000,16900,16900,1\n3,none,,0.99,-161,739,739,1\n");
  cr_assert_eq(decide("H1", dir), CB_NOT_REPRODUCED);
}

Test(claims_definiteness, h1_partly_when_a_stretched_state_is_indefinite_or_1d_fails) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  row(buf, "none", 0, -5000, 0, -5000, 0.6, 1);
  row(buf, "drop", 1, 900, 0, -10, 0.0, 0); /* indefinite with nothing compressed: contradicts the claim */
  put(dir, "definiteness.csv", buf);
  put(dir, "definiteness_pair.csv", good_pair);
  cr_assert_eq(decide("H1", dir), CB_PARTLY);
  char *dir2 = tmpdir(), buf2[8192] = MAIN_HEAD;
  row(buf2, "none", 0, -5000, 0, -5000, 0.6, 1);
  put(dir2, "definiteness.csv", buf2);
  put(dir2, "definiteness_pair.csv", PAIR_HEAD "1,none,,0.7,16000,-10,16900,0\n3,none,,0.7,-6857,-5957,-5957,0\n");
  cr_assert_eq(decide("H1", dir2), CB_PARTLY);
}

static void fixes_rows(char *buf, const char *bad, int bad_spd, int bad_cg) {
  row(buf, "none", 0, -5000, 0, -5000, 0.6, 1);
  const char *pols[] = {"drop", "mirror", "shift", "choi-ko"};
  for (int p = 0; p < 4; p++) {
    int b = bad && !strcmp(bad, pols[p]);
    row(buf, pols[p], b && bad_spd ? 0 : 1, 900, 0, -3000, 0.5, b && bad_cg);
  }
}

Test(claims_definiteness, h2_reproduced_when_every_fix_is_spd) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, NULL, 0, 0);
  put(dir, "definiteness.csv", buf);
  runs_all_finished(dir, NULL);
  cr_assert_eq(decide("H2", dir), CB_REPRODUCED);
}

/* The ranking, by wall time per step against drop: choi-ko 0.8x, drop, mirror 1.3x, shift 1.5x. */
Test(claims_definiteness, h2_ranks_the_fixes_by_their_cost_against_drop) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, NULL, 0, 0);
  put(dir, "definiteness.csv", buf);
  runs_all_finished(dir, NULL);
  cb_claim_result *r = calloc(1, sizeof *r);
  for (int i = 0; i < cb_nclaims; i++)
    if (!strcmp(cb_claims[i].id, "H2")) cb_claim_decide(&cb_claims[i], dir, r);
  cr_expect_eq(r->verdict, CB_REPRODUCED, "%s", r->reason);
  cr_expect(strstr(r->reason, "1. choi-ko 0.80x, 0.60x the Newton iterations; 2. drop (1x, the baseline); "
                              "3. mirror 1.30x, 1.30x the Newton iterations; 4. shift 1.50x, 1.10x the Newton "
                              "iterations."),
            "%s", r->reason);
  cr_expect(strstr(r->numbers, "| 4 | shift | 1 | 1.10 | 1.10 | 1.50x | yes | nan |"), "%s", r->numbers);
  free(r);
}

/* wall_ms with its spread over three repeats: 10, 12, 11 ms over 5 steps: 2.2 (2.0-2.4) ms per step */
Test(claims_definiteness, h2_quotes_the_time_per_step_with_its_spread) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, NULL, 0, 0);
  put(dir, "definiteness.csv", buf);
  char runs[4096] = "scene,policy,steps,steps_done,steps_converged,newton_iters,systems,not_spd,indefinite_exact,cg_"
                    "breakdowns,"
                    "mu_max_n_per_m,factorizations,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,probe_ms,"
                    "final_f_j,"
                    "final_energy_j,final_rel_grad,shape_diff_none_m,shape_diff_drop_m,status\n";
  const char *pols[] = {"none", "drop", "mirror", "shift", "choi-ko"};
  for (int p = 0; p < 5; p++) {
    char r[512];
    snprintf(r, sizeof r, "s1,%s,5,%d,%d,10,10,0,0,0,0,10,11,10,12,10;12;11,3,1,0,0,0,,,%s\n", pols[p], p ? 5 : 1,
             p ? 5 : 1, p == 0 ? "not_spd" : "ok");
    strcat(runs, r);
  }
  put(dir, "definiteness_runs.csv", runs);
  cb_claim_result r;
  for (int i = 0; i < cb_nclaims; i++)
    if (!strcmp(cb_claims[i].id, "H2")) cb_claim_decide(&cb_claims[i], dir, &r);
  /* every fix costs what drop costs, repeat by repeat: "at different costs" fails */
  cr_expect_eq(r.verdict, CB_PARTLY, "%s", r.reason);
  cr_expect(strstr(r.reason, "\"at different costs\" is not reproduced") && strstr(r.reason, "mirror 1.00x "
                                                                                             "(1.00-1.00x)"),
            "%s", r.reason);
  cr_expect(strstr(r.numbers, "| s1 | drop | 0 / 1 | 0 | 5 (5) / 5 | 2.00 | 2.00 | 2.2 (2.0-2.4) |"), "%s", r.numbers);
  cr_expect(strstr(r.numbers, "median of 3 repeats of the run without the probes"), "%s", r.numbers);
}

Test(claims_definiteness, h2_not_reproduced_when_drop_fails) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, "drop", 1, 0);
  put(dir, "definiteness.csv", buf);
  runs_all_finished(dir, NULL);
  cr_assert_eq(decide("H2", dir), CB_NOT_REPRODUCED);
  char *dir2 = tmpdir(), buf2[8192] = MAIN_HEAD;
  fixes_rows(buf2, "drop", 0, 1); /* a CG breakdown on drop's matrix */
  put(dir2, "definiteness.csv", buf2);
  runs_all_finished(dir2, NULL);
  cr_assert_eq(decide("H2", dir2), CB_NOT_REPRODUCED);
}

Test(claims_definiteness, h2_partly_when_another_fix_fails) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, "choi-ko", 0, 1);
  put(dir, "definiteness.csv", buf);
  runs_all_finished(dir, NULL);
  cr_assert_eq(decide("H2", dir), CB_PARTLY);
  char *dir2 = tmpdir(), buf2[8192] = MAIN_HEAD;
  fixes_rows(buf2, NULL, 0, 0);
  put(dir2, "definiteness.csv", buf2);
  runs_all_finished(dir2, "mirror"); /* mirror's run did not finish */
  cr_assert_eq(decide("H2", dir2), CB_PARTLY);
}

/* A policy the checker has never seen ("newfix", on a scene "zeta") is one
 * more fix: H2 stays reproduced while it works everywhere, and becomes partly
 * when its run does not finish; the table and the reason name it. */
Test(claims_definiteness, h2_takes_policy_and_scene_names_from_the_csv) {
  for (int broken = 0; broken < 2; broken++) {
    char *dir = tmpdir(), buf[8192] = MAIN_HEAD, runs[4096] = RUNS_HEAD;
    const char *pols[] = {"none", "drop", "newfix"};
    for (int p = 0; p < 3; p++) {
      char r[512];
      snprintf(r, sizeof r, "zeta,%s,1,0,1,%d,900,0,0,1,900,0.5,0,ok,3,1,1,0,0,0.1,%s\n", pols[p], p > 0,
               p ? "ok" : "not_spd");
      strcat(buf, r);
      int done = p == 0 ? 1 : broken && p == 2 ? 3 : 5;
      snprintf(r, sizeof r, "zeta,%s,5,%d,%d,%d,10,0,0,0,0,10,1,1,0,0,0,,,%s\n", pols[p], done, done, p == 2 ? 12 : 10,
               p == 0 ? "not_spd" : "ok");
      strcat(runs, r);
    }
    put(dir, "definiteness.csv", buf);
    put(dir, "definiteness_runs.csv", runs);
    cb_claim_result *r = calloc(1, sizeof *r);
    for (int i = 0; i < cb_nclaims; i++)
      if (!strcmp(cb_claims[i].id, "H2")) cb_claim_decide(&cb_claims[i], dir, r);
    cr_expect_eq(r->verdict, broken ? CB_PARTLY : CB_REPRODUCED, "%s", r->reason);
    cr_expect(strstr(r->numbers, "| zeta | newfix | 0 / 1 |"), "%s", r->numbers);
    cr_expect(strstr(r->reason, broken ? "but newfix did not" : "the 1 other fixes (newfix)"), "%s", r->reason);
    free(r);
  }
}

Test(claims_definiteness, missing_side_csv_is_not_run) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, NULL, 0, 0);
  put(dir, "definiteness.csv", buf);
  cr_assert_eq(decide("H1", dir), CB_NOT_RUN);
  cr_assert_eq(decide("H2", dir), CB_NOT_RUN);
}

/* Every fix at drop's Newton iterations; drop's wall times 10, 10, 10 ms over three interleaved repeats,
 * mirror's mw[0..3), the others' drop's. Mirror at 9.8, 10.6, 10.2 ms: paired ratios 0.98-1.06 straddle the
 * 5% band's edge (1.05): undecided whether "at different costs" holds (reproduced if mirror differs,
 * partly if not); at 11, 11.5, 12 ms it lies beyond the band: reproduced; at 9.9, 10, 10.1 inside: partly. */
static cb_verdict h2_spread(const double *mw, cb_claim_result *r) {
  char *dir = tmpdir(), buf[8192] = MAIN_HEAD;
  fixes_rows(buf, NULL, 0, 0);
  put(dir, "definiteness.csv", buf);
  char runs[4096] = "scene,policy,steps,steps_done,steps_converged,newton_iters,systems,not_spd,indefinite_exact,cg_"
                    "breakdowns,mu_max_n_per_m,factorizations,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_"
                    "repeats,probe_ms,final_f_j,final_energy_j,final_rel_grad,shape_diff_none_m,shape_diff_drop_m,"
                    "status\n";
  const char *pols[] = {"none", "drop", "mirror", "shift", "choi-ko"};
  for (int p = 0; p < 5; p++) {
    double e[3] = {10, 10, 10};
    if (p == 2) e[0] = mw[0], e[1] = mw[1], e[2] = mw[2];
    double lo = e[0] < e[1] ? (e[0] < e[2] ? e[0] : e[2]) : (e[1] < e[2] ? e[1] : e[2]);
    double hi = e[0] > e[1] ? (e[0] > e[2] ? e[0] : e[2]) : (e[1] > e[2] ? e[1] : e[2]);
    char row_[512];
    snprintf(row_, sizeof row_, "s1,%s,5,%d,%d,10,10,0,0,0,0,10,%g,%g,%g,%g;%g;%g,3,1,0,0,0,,,%s\n", pols[p], p ? 5 : 1,
             p ? 5 : 1, e[0] + e[1] + e[2] - lo - hi, lo, hi, e[0], e[1], e[2], p == 0 ? "not_spd" : "ok");
    strcat(runs, row_);
  }
  put(dir, "definiteness_runs.csv", runs);
  for (int i = 0; i < cb_nclaims; i++)
    if (!strcmp(cb_claims[i].id, "H2")) cb_claim_decide(&cb_claims[i], dir, r);
  return r->verdict;
}

Test(claims_definiteness, h2_a_cost_ratio_across_the_5_percent_edge_is_undecided) {
  cb_claim_result *r = calloc(1, sizeof *r);
  cr_assert_not_null(r);
  const double straddle[3] = {9.8, 10.6, 10.2}, beyond[3] = {11, 11.5, 12}, inside[3] = {9.9, 10, 10.1};
  cr_expect_eq(h2_spread(straddle, r), CB_UNDECIDED, "%s", r->reason);
  cr_expect(strstr(r->reason, "mirror 1.02x (0.98-1.06x), 1.00x the Newton iterations (undecided within the spread)"),
            "%s", r->reason);
  cr_expect(strstr(r->reason, "mirror's wall time / drop's 1.020x (0.980-1.060x over 3 paired repeats) straddles "
                              "1.050x"),
            "%s", r->reason);
  cr_expect(strstr(r->numbers, "| undecided |"), "%s", r->numbers);
  cr_expect_eq(h2_spread(beyond, r), CB_REPRODUCED, "%s", r->reason);
  cr_expect_eq(h2_spread(inside, r), CB_PARTLY, "%s", r->reason);
  free(r);
}
