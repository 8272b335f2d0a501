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
