/* Verdict logic of claims/check_contact.c (C1, C2) on small constructed CSVs: one fixture per verdict. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"
#include "support.h"

static const char *header = "# test\nscene,vertices,response,integrator,dt_s,speed_m_per_s,frame,t_s,self_"
                            "intersections,obstacle_intersections,intersections,min_separation_m,contacts,newton_"
                            "iters,wall_ms,status\n";

static cb_claim_result res;

/* One cell: frames 0..n-1 of (scene, response) with the given per-frame intersection counts (self, obstacle);
 * the last frame's status is last_status. */
static size_t cell(char *buf, size_t cap, const char *scene, const char *resp, int n, const int *self, const int *obst,
                   const char *last_status) {
  size_t u = 0;
  for (int k = 0; k < n; k++) {
    int w = snprintf(buf + u, cap - u, "%s,64,%s,newton,0.033,0,%d,%g,%d,%d,%d,0.004,%d,5,1.0,%s\n", scene, resp, k,
                     k * 0.033, self[k], obst[k], self[k] + obst[k], 10 + k, k == n - 1 ? last_status : "ok");
    cr_assert(w > 0 && (size_t)w < cap - u, "fixture buffer too small");
    u += (size_t)w;
  }
  return u;
}

static const int Z[4] = {0, 0, 0, 0}, HIT[4] = {0, 0, 3, 1};

/* Both scenes, ipc with intersections ipc_self/ipc_obst, penalty with pen_self/pen_obst. */
static cb_verdict decide(const int *ipc_self, const int *ipc_obst, const int *pen_self, const int *pen_obst,
                         const char *ipc_last) {
  static char rows[8192];
  size_t u = 0;
  const char *scenes[] = {"sheet_on_table", "rotating_sphere"};
  for (int s = 0; s < 2; s++) {
    u += cell(rows + u, sizeof rows - u, scenes[s], "penalty", 4, pen_self, pen_obst, "ok");
    u += cell(rows + u, sizeof rows - u, scenes[s], "ipc", 4, s ? Z : ipc_self, s ? Z : ipc_obst, ipc_last);
  }
  return test_decide_rows(cb_check_C1, header, rows, &res);
}

Test(claims_contact, C1_reproduced_when_ipc_is_clean_and_the_penalty_intersects) {
  cr_expect_eq(decide(Z, Z, HIT, Z, "ok"), CB_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "ipc has 0 intersecting pairs at all 8 frames"), "%s", res.reason);
  cr_expect(strstr(res.numbers, "| sheet_on_table | penalty | 1 | 0 | 4 | 2 | 3 (3 / 0) |"), "%s", res.numbers);
  /* an intersection with the obstacle counts as well as a self-intersection */
  cr_expect_eq(decide(Z, Z, Z, HIT, "max_iters"), CB_REPRODUCED, "%s", res.reason);
}

Test(claims_contact, C1_not_reproduced_when_ipc_intersects_once) {
  const int one[4] = {0, 0, 0, 1};
  cr_expect_eq(decide(Z, one, HIT, Z, "ok"), CB_NOT_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "1 of its 8 frames"), "%s", res.reason);
  cr_expect_eq(decide(one, Z, HIT, Z, "ok"), CB_NOT_REPRODUCED, "%s", res.reason);
}

Test(claims_contact, C1_partly_when_the_penalty_never_intersects) {
  cr_expect_eq(decide(Z, Z, Z, Z, "ok"), CB_PARTLY, "%s", res.reason);
  cr_expect(strstr(res.reason, "the contrast is not shown"), "%s", res.reason);
}

Test(claims_contact, C1_partly_when_an_ipc_cell_stopped_early) {
  cr_expect_eq(decide(Z, Z, HIT, Z, "diverged"), CB_PARTLY, "%s", res.reason);
  cr_expect(strstr(res.reason, "2 ipc cells stopped early"), "%s", res.reason);
  /* a one-row cell (the scene refused its start) is a failed cell too */
  static char rows[4096];
  size_t u = cell(rows, sizeof rows, "sheet_on_table", "penalty", 4, HIT, Z, "ok");
  u += cell(rows + u, sizeof rows - u, "sheet_on_table", "ipc", 4, Z, Z, "ok");
  snprintf(rows + u, sizeof rows - u, "sheet_on_table,,ipc,,0.066,12,,,,,,,,,,invalid\n");
  cr_expect_eq(test_decide_rows(cb_check_C1, header, rows, &res), CB_PARTLY, "%s", res.reason);
  cr_expect(strstr(res.numbers, "| sheet_on_table | ipc | 2 | 1 | 4 | 0 |"), "%s", res.numbers);
}

Test(claims_contact, C1_not_run_without_ipc_or_penalty_frames_or_columns) {
  static char rows[4096];
  cell(rows, sizeof rows, "sheet_on_table", "penalty", 4, HIT, Z, "ok");
  cr_expect_eq(test_decide_rows(cb_check_C1, header, rows, &res), CB_NOT_RUN, "%s", res.reason);
  cr_expect(strstr(res.reason, "no checked frame of ipc"), "%s", res.reason);
  cr_expect_eq(test_decide_rows(cb_check_C1, "# test\nscene,response,frame,status\n", "a,ipc,0,ok\n", &res), CB_NOT_RUN,
               "%s", res.reason);
}

/* ---- C2: the stick-slip threshold (contact_c2.csv) ---------------------------------------------------------- */

/* A contact_c2.csv in a fresh folder with one threshold row per angle, mu* = q[k] tan theta[k] (NaN: not
 * bracketed), the slide rows of f = 0.5 and 1.5, and VBD's refused row; then C2's verdict. */
static cb_verdict decide_c2(int n, const double *theta, const double *q) {
  static char dir[] = "/tmp/cbc2XXXXXX";
  strcpy(dir, "/tmp/cbc2XXXXXX");
  cr_assert_not_null(mkdtemp(dir));
  char path[256], main_csv[256];
  snprintf(path, sizeof path, "%s/contact_c2.csv", dir);
  snprintf(main_csv, sizeof main_csv, "%s/contact.csv", dir);
  FILE *f = fopen(path, "w");
  cr_assert_not_null(f);
  fputs("# test\nkind,integrator,theta_deg,tan_theta,mu,mu_over_tan,slide_m,closed_form_m,drift_m,steps,not_"
        "converged,mu_star,mu_lo,mu_hi,creep_m,runs,wall_ms,note,status\n",
        f);
  for (int k = 0; k < n; k++) {
    double tn = tan(theta[k] * 3.14159265358979323846 / 180);
    fprintf(f, "slide,newton,%g,%.17g,%.17g,0.5,0.08,0.08,0,100,0,,,,,1,10,,ok\n", theta[k], tn, 0.5 * tn);
    fprintf(f, "slide,newton,%g,%.17g,%.17g,1.5,0.0004,0,0,100,0,,,,,1,10,,ok\n", theta[k], tn, 1.5 * tn);
    fprintf(f, "threshold,newton,%g,%.17g,,%.17g,0.02,,,,,%.17g,,,0.0003,8,80,,%s\n", theta[k], tn, q[k], q[k] * tn,
            isnan(q[k]) ? "not_bracketed" : "ok");
    fprintf(f, "slide,vbd,%g,%.17g,%.17g,0.5,,,,,,,,,,1,,no friction,refused\n", theta[k], tn, 0.5 * tn);
  }
  cr_assert_eq(fclose(f), 0);
  f = fopen(main_csv, "w");
  cr_assert_not_null(f);
  fputs(header, f);
  cr_assert_eq(fclose(f), 0);
  cb_verdict v = test_decide_check(cb_check_C2, main_csv, dir, &res);
  unlink(path);
  unlink(main_csv);
  rmdir(dir);
  return v;
}

Test(claims_contact, C2_reproduced_when_every_threshold_is_near_tan_theta) {
  const double th[] = {10, 20, 30}, q[] = {0.99, 1.05, 0.92};
  cr_expect_eq(decide_c2(3, th, q), CB_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "at 3 of 3 angles (worst |mu*/tan theta - 1| = 0.080)"), "%s", res.reason);
  cr_expect(strstr(res.reason, "VBD: refused"), "%s", res.reason);
  cr_expect(strstr(res.numbers, "| 20 deg | 0.3640 | 0.3822 | 1.050 |"), "%s", res.numbers);
}

Test(claims_contact, C2_not_reproduced_when_no_threshold_is_near) {
  const double th[] = {10, 20, 30}, q[] = {1.3, 0.7, 1.15};
  cr_expect_eq(decide_c2(3, th, q), CB_NOT_REPRODUCED, "%s", res.reason);
  const double q2[] = {NAN, NAN, NAN};
  cr_expect_eq(decide_c2(3, th, q2), CB_NOT_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "at 3 the threshold was not bracketed"), "%s", res.reason);
}

Test(claims_contact, C2_partly_when_some_angles_miss_or_one_angle_alone) {
  const double th[] = {10, 20, 30}, q[] = {0.99, 1.25, 1.0};
  cr_expect_eq(decide_c2(3, th, q), CB_PARTLY, "%s", res.reason);
  const double one[] = {1.0};
  cr_expect_eq(decide_c2(1, th, one), CB_PARTLY, "%s", res.reason);
}

/* ---- C3: error against time, VBD against IPC's Newton (contact_c3.csv) -------------------------------------- */

static const char *c3_header = "# test\nscene,vertices,method,integrator,iters,dt_s,frame,step_error,wall_ms,wall_min_"
                               "ms,wall_max_ms,wall_each_ms,wall_repeats,intersections,ref_step_m,note,status\n";

/* A method's ladder 1, 2, 4, ... on a scene: step errors err[k], median wall times ms[k] with three repeats
 * 0.9 ms, ms, 1.1 ms (so every paired ratio of two such rows is the ratio of their medians), intersection counts
 * nint[k] (NULL: all 0). */
static size_t c3_ladder(char *buf, size_t cap, const char *scene, const char *method, int n, const double *err,
                        const double *ms, const int *nint) {
  size_t u = 0;
  for (int k = 0; k < n; k++) {
    double a = 0.9 * ms[k], b = ms[k], c = 1.1 * ms[k];
    int w = snprintf(buf + u, cap - u, "%s,144,%s,%s,%d,0.0333,6,%.17g,%.17g,%.17g,%.17g,%.17g;%.17g;%.17g,3,%d,,,%s\n",
                     scene, method, method, 1 << k, err[k], b, a, c, a, b, c, nint ? nint[k] : 0,
                     strcmp(method, "vbd") ? "max_iters" : "ok");
    cr_assert(w > 0 && (size_t)w < cap - u, "fixture buffer too small");
    u += (size_t)w;
  }
  return u;
}

/* contact_c3.csv with `text` in a fresh folder (and an empty contact.csv beside it); then C3's verdict. */
static cb_verdict decide_c3_text(const char *head, const char *text) {
  static char dir[] = "/tmp/cbc3XXXXXX";
  strcpy(dir, "/tmp/cbc3XXXXXX");
  cr_assert_not_null(mkdtemp(dir));
  char path[256], main_csv[256];
  snprintf(path, sizeof path, "%s/contact_c3.csv", dir);
  snprintf(main_csv, sizeof main_csv, "%s/contact.csv", dir);
  FILE *f = fopen(path, "w");
  cr_assert_not_null(f);
  fputs(head, f);
  fputs(text, f);
  cr_assert_eq(fclose(f), 0);
  f = fopen(main_csv, "w");
  cr_assert_not_null(f);
  fputs(header, f);
  cr_assert_eq(fclose(f), 0);
  cb_verdict v = test_decide_check(cb_check_C3, main_csv, dir, &res);
  unlink(path);
  unlink(main_csv);
  rmdir(dir);
  return v;
}

/* Newton: 1e-2 first reached at 8 iterations (40 ms), 1e-3 too (7e-4); L-BFGS reaches 1e-2 only (at 30 ms). */
static const double NEWTON_ERR[] = {0.3, 0.1, 0.02, 7e-4, 2e-6}, NEWTON_MS[] = {5, 10, 20, 40, 80};
static const double LBFGS_ERR[] = {0.5, 0.2, 0.05, 9e-3}, LBFGS_MS[] = {4, 8, 15, 30};

/* Both claim scenes, Newton and L-BFGS as above, VBD with errors verr and times vms (4 rungs) and intersection
 * counts vint (NULL: none) on the rotating sphere. */
static cb_verdict decide_c3(const double *verr, const double *vms, const int *vint) {
  static char rows[16384];
  size_t u = 0;
  const char *scenes[] = {"sheet_on_table", "rotating_sphere"};
  for (int s = 0; s < 2; s++) {
    u += snprintf(rows + u, sizeof rows - u, "%s,144,reference,newton,27,0.0333,6,0,60,,,,,0,0.05,,ok\n", scenes[s]);
    u += c3_ladder(rows + u, sizeof rows - u, scenes[s], "newton", 5, NEWTON_ERR, NEWTON_MS, NULL);
    u += c3_ladder(rows + u, sizeof rows - u, scenes[s], "lbfgs", 4, LBFGS_ERR, LBFGS_MS, NULL);
    u += c3_ladder(rows + u, sizeof rows - u, scenes[s], "vbd", 4, verr, vms, s ? vint : NULL);
  }
  return decide_c3_text(c3_header, rows);
}

Test(claims_contact, C3_reproduced_when_vbd_reaches_both_errors_first_without_intersections) {
  const double err[] = {0.5, 0.05, 5e-3, 5e-4}, ms[] = {1, 2, 4, 8};
  cr_expect_eq(decide_c3(err, ms, NULL), CB_REPRODUCED, "%s", res.reason);
  /* 1e-2: VBD's fastest qualifying row is 4 sweeps (4 ms) against Newton's 8 iterations (40 ms): 0.1x */
  cr_expect(strstr(res.reason, "rotating_sphere 1e-02 (0.1x"), "%s", res.reason);
  /* 1e-3: 8 ms against 40 ms; L-BFGS never reaches 1e-3 */
  cr_expect(strstr(res.numbers, "| rotating_sphere | 1e-03 | 8 it.: 40 ms (36-44 ms) | not reached (least 0.009, 8 "
                                "it.) | 8 it.: 8 ms"),
            "%s", res.numbers);
  /* L-BFGS at 1e-2: 8 it. at 30 ms, VBD / L-BFGS = 4 / 30 */
  cr_expect(strstr(res.numbers, "| 0.133x"), "%s", res.numbers);
  cr_expect(strstr(res.numbers, "| rotating_sphere | vbd | 4 | 0 | 0 | 0 |"), "%s", res.numbers);
}

Test(claims_contact, C3_not_reproduced_when_vbd_is_slower) {
  const double err[] = {0.5, 0.05, 5e-3, 5e-4}, ms[] = {100, 200, 400, 800};
  cr_expect_eq(decide_c3(err, ms, NULL), CB_NOT_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "VBD / Newton 10x"), "%s", res.reason); /* 400 ms against 40 ms at 1e-2 */
}

Test(claims_contact, C3_not_reproduced_when_a_vbd_row_intersects) {
  const double err[] = {0.5, 0.05, 5e-3, 5e-4}, ms[] = {1, 2, 4, 8};
  const int hit[] = {0, 0, 2, 0};
  cr_expect_eq(decide_c3(err, ms, hit), CB_NOT_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "VBD intersects: 1 of its rows"), "%s", res.reason);
  cr_expect(strstr(res.numbers, "| rotating_sphere | vbd | 4 | 1 | 2 | 0 |"), "%s", res.numbers);
}

Test(claims_contact, C3_partly_when_vbd_never_reaches_1e_3) {
  const double err[] = {0.5, 0.05, 5e-3, 2e-3}, ms[] = {1, 2, 4, 8};
  cr_expect_eq(decide_c3(err, ms, NULL), CB_PARTLY, "%s", res.reason);
  cr_expect(strstr(res.reason, "sheet_on_table 1e-03: VBD does not reach it within 4 rows (not reached (least 0.002, 8 "
                               "it.);"),
            "%s", res.reason);
  cr_expect(strstr(res.reason, "faster than Newton at: sheet_on_table 1e-02"), "%s", res.reason);
  cr_expect(strstr(res.numbers, "| sheet_on_table | 1e-03 | 8 it.: 40 ms (36-44 ms) | not reached (least 0.009, 8 it.) "
                                "| "
                                "not reached (least 0.002, 8 it.) | - | - |"),
            "%s", res.numbers);
  /* a VBD row that diverged (NaN error, not counted) reaches nothing and is listed as not counted */
  const double err2[] = {0.5, NAN, NAN, NAN};
  cr_expect_eq(decide_c3(err2, ms, NULL), CB_NOT_REPRODUCED, "%s", res.reason);
}

Test(claims_contact, C3_undecided_when_the_spread_straddles_one) {
  static char rows[8192];
  size_t u = 0;
  const char *scenes[] = {"sheet_on_table", "rotating_sphere"};
  const double err[] = {5e-4};
  for (int s = 0; s < 2; s++) {
    u += c3_ladder(rows + u, sizeof rows - u, scenes[s], "newton", 5, NEWTON_ERR, NEWTON_MS, NULL);
    /* VBD's repeats 30, 45, 60 ms against Newton's 36, 40, 44: paired ratios 0.83, 1.125, 1.36 */
    u += snprintf(rows + u, sizeof rows - u, "%s,144,vbd,vbd,1,0.0333,6,%g,45,30,60,30;45;60,3,0,,,ok\n", scenes[s],
                  err[0]);
  }
  cr_expect_eq(decide_c3_text(c3_header, rows), CB_UNDECIDED, "%s", res.reason);
  cr_expect(strstr(res.reason, "Undecided within the spread"), "%s", res.reason);
}

Test(claims_contact, C3_not_run_on_a_malformed_table) {
  /* a column missing: the checker names it */
  cr_expect_eq(decide_c3_text("# test\nscene,method,iters,step_error,wall_ms,status\n", "a,vbd,1,0.1,3,ok\n"),
               CB_NOT_RUN, "%s", res.reason);
  cr_expect(strstr(res.reason, "intersections"), "%s", res.reason);
  /* fields that are not numbers, no Newton row: not run, no crash */
  cr_expect_eq(decide_c3_text(c3_header, "rotating_sphere,144,vbd,vbd,x,y,z,abc,,,,;;,q,?,,,ok\n"), CB_NOT_RUN, "%s",
               res.reason);
  cr_expect(strstr(res.reason, "no Newton row"), "%s", res.reason);
  /* a short row: the table is refused as unreadable */
  cr_expect_eq(decide_c3_text(c3_header, "rotating_sphere,vbd\n"), CB_NOT_RUN, "%s", res.reason);
  cr_expect(strstr(res.reason, "unreadable"), "%s", res.reason);
  /* an empty table */
  cr_expect_eq(decide_c3_text(c3_header, ""), CB_NOT_RUN, "%s", res.reason);
}
