/* Verdict logic of claims/check_bending.c (B1, B2, B3) on small constructed CSVs. */
#define _DEFAULT_SOURCE
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"

void cb_check_B1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_B2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_B3(const cb_table *t, const char *results_dir, cb_claim_result *out);

static const char *header_plain = "# test\npart,model,mesh,n,angle_deg,stretch,radius_m,force_n,force_total_n,energy_j,energy_ref_j,ratio,"
                            "steps,newton_iters,assemble_ms,factor_ms,solve_ms,wall_ms,kinetic_j,rms_m,contacts,"
                            "indefinite,hinges,status\n";

static const char *header_spread = "# test\npart,model,mesh,n,angle_deg,stretch,radius_m,force_n,force_total_n,energy_j,energy_ref_j,ratio,"
                                   "steps,newton_iters,assemble_ms,factor_ms,solve_ms,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,"
                                   "wall_repeats,step_min_ms,step_max_ms,assemble_min_ms,assemble_max_ms,assemble_each_ms,"
                                   "factor_min_ms,factor_max_ms,factor_each_ms,solve_min_ms,solve_max_ms,solve_each_ms,kinetic_j,"
                                   "rms_m,contacts,indefinite,hinges,status\n";
static const char *header;

static cb_claim_result res;

static cb_verdict decide(const char *rows, void (*check)(const cb_table *, const char *, cb_claim_result *)) {
  char path[] = "/tmp/cbclaimXXXXXX";
  int fd = mkstemp(path);
  cr_assert(fd >= 0);
  FILE *f = fdopen(fd, "w");
  fputs(header ? header : header_plain, f);
  fputs(rows, f);
  fclose(f);
  cb_table t;
  cr_assert_eq(cb_table_read(path, &t), 0);
  memset(&res, 0, sizeof res);
  check(&t, "/tmp", &res);
  cb_table_free(&t);
  unlink(path);
  return res.verdict;
}

/* b1 rows F = c theta^p for the spring (p_spring) and two hinges (p_hinge) */
static void b1_rows(char *buf, size_t n, double p_spring, double p_hinge) {
  size_t u = 0;
  const double angles[] = {1, 2, 3, 5, 8, 10, 30, 60};
  for (int k = 0; k < 8; k++) {
    double a = angles[k];
    u += (size_t)snprintf(buf + u, n - u, "b1,spring,hinge,,%g,,,%.17g,,,,,,,,,,,,,,,,ok\n", a, 1e-6 * pow(a, p_spring));
    u += (size_t)snprintf(buf + u, n - u, "b1,dihedral,hinge,,%g,,,%.17g,,,,,,,,,,,,,,,,ok\n", a, 0.08 * pow(a, p_hinge));
    u += (size_t)snprintf(buf + u, n - u, "b1,quadratic,hinge,,%g,,,%.17g,,,,,,,,,,,,,,,,ok\n", a, 0.08 * pow(a, 1.0));
  }
}

Test(claims_bending, B1_reproduced_for_cubic_spring_and_linear_hinges) {
  char rows[8192];
  b1_rows(rows, sizeof rows, 3.0, 1.0);
  cr_assert_eq(decide(rows, cb_check_B1), CB_REPRODUCED, "%s", res.reason);
}

Test(claims_bending, B1_not_reproduced_for_a_quadratic_spring_or_a_superlinear_hinge) {
  char rows[8192];
  b1_rows(rows, sizeof rows, 2.0, 1.0);
  cr_expect_eq(decide(rows, cb_check_B1), CB_NOT_REPRODUCED, "%s", res.reason);
  b1_rows(rows, sizeof rows, 3.0, 1.3);
  cr_expect_eq(decide(rows, cb_check_B1), CB_NOT_REPRODUCED, "%s", res.reason);
}

static void b2_rows(char *buf, size_t n, double qwall, double dwall, const char *dstatus) {
  snprintf(buf, n,
           "b2,quadratic,grid,8,,,,,,,,,30,300,1,%g,0.5,%g,0.001,,10,0,0,ok\n"
           "b2,dihedral,grid,8,,,,,,,,,30,330,20,%g,0.5,%g,0.001,,10,100,150,ok\n"
           "b2_rms,quadratic-dihedral,grid,8,,,,,,,,,30,,,,,,,0.01,,,,ok\n"
           "b2,quadratic,grid,16,,,,,,,,,30,300,1,%g,0.5,%g,0.001,,10,0,0,ok\n"
           "b2,dihedral,grid,16,,,,,,,,,30,330,20,%g,0.5,%g,0.001,,10,100,150,%s\n"
           "b2_rms,quadratic-dihedral,grid,16,,,,,,,,,30,,,,,,,0.01,,,,ok\n",
           qwall - 1.5, qwall, dwall - 20.5, dwall, qwall - 1.5, qwall, dwall - 20.5, dwall, dstatus);
}

Test(claims_bending, B2_reproduced_between_1_5_and_3_and_above) {
  char rows[4096];
  b2_rows(rows, sizeof rows, 10, 25, "ok");
  cr_expect_eq(decide(rows, cb_check_B2), CB_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "Reproduced") != NULL, "%s", res.reason);
  b2_rows(rows, sizeof rows, 10, 80, "ok");
  cr_expect_eq(decide(rows, cb_check_B2), CB_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "Exceeded") != NULL, "%s", res.reason);
}

Test(claims_bending, B2_not_reproduced_below_1_5_or_when_a_run_failed) {
  char rows[4096];
  b2_rows(rows, sizeof rows, 30, 25, "ok");
  cr_expect_eq(decide(rows, cb_check_B2), CB_NOT_REPRODUCED, "%s", res.reason);
  b2_rows(rows, sizeof rows, 20, 25, "ok");
  cr_expect_eq(decide(rows, cb_check_B2), CB_PARTLY, "%s", res.reason);
  b2_rows(rows, sizeof rows, 10, 25, "diverged");
  cr_expect_eq(decide(rows, cb_check_B2), CB_NOT_REPRODUCED, "%s", res.reason);
}

/* Three repeats per model, interleaved: quadratic steps of 10, 9, 11 ms (assembly 1 ms), dihedral
 * 25, 24, 27.5 ms (assembly 20, 20, 22 ms): paired ratios 2.5, 2.67, 2.5 (bounds would be 2.18-3.06). */
Test(claims_bending, B2_quotes_times_and_the_ratio_with_their_spread) {
  header = header_spread;
  char rows[4096];
  snprintf(rows, sizeof rows,
           "b2,quadratic,grid,16,,,,,,,,,30,300,1,8,0.5,10,9,11,10;9;11,3,0.9,23,1,1,1;1;1,8,8,8;8;8,0.5,0.5,0.5;0.5;0.5,0.001,,10,0,0,ok\n"
           "b2,dihedral,grid,16,,,,,,,,,30,330,20,4,0.5,25,24,27.5,25;24;27.5,3,2.5,60,20,22,20;20;22,4,4,4;4;4,0.5,0.5,0.5;0.5;0.5,0.001,,10,100,150,ok\n"
           "b2_rms,quadratic-dihedral,grid,16,,,,,,,,,30,,,,,,,,,,,,,,,,,,,,,,0.01,,,,ok\n");
  cr_expect_eq(decide(rows, cb_check_B2), CB_REPRODUCED, "%s", res.reason);
  header = NULL;
  cr_expect(strstr(res.numbers, "| 1.00 (1.00-1.00) | 8.00 (8.00-8.00) | 0.50 (0.50-0.50) | 10.00 (9.00-11.00) | 0.9-23.0 |"), "%s", res.numbers);
  cr_expect(strstr(res.numbers, "**2.50x (2.50-2.67x)**"), "%s", res.numbers);
  cr_expect(strstr(res.numbers, "median over 3 repeats") && strstr(res.numbers, "paired repeats"), "%s", res.numbers);
  cr_expect(strstr(res.reason, "2.50x (2.50-2.67x over 3 paired repeats) faster"), "%s", res.reason);
}

static void b3_rows(char *buf, size_t n, double r0, double slope) {
  size_t u = 0;
  for (int m = 0; m < 2; m++)
    for (int k = 0; k <= 10; k++) {
      double s = 0.03 * k;
      u += (size_t)snprintf(buf + u, n - u, "b3,quadratic,%s,,20,%g,,,,%g,1,%g,,,,,,,,,,,,ok\n", m ? "across" : "uniform", s,
                            r0 + slope * s, r0 + slope * s);
    }
}

Test(claims_bending, B3_reproduced_when_agreeing_unstretched_and_parting_within_30_percent) {
  char rows[8192];
  b3_rows(rows, sizeof rows, 0.99, 2.0); /* 10% at s = 5.5% */
  cr_expect_eq(decide(rows, cb_check_B3), CB_REPRODUCED, "%s", res.reason);
  cr_expect(strstr(res.reason, "5.5%") != NULL, "%s", res.reason);
}

Test(claims_bending, B3_not_reproduced_when_never_parting_or_already_apart) {
  char rows[8192];
  b3_rows(rows, sizeof rows, 1.0, 0.1); /* 3% at 30% */
  cr_expect_eq(decide(rows, cb_check_B3), CB_NOT_REPRODUCED, "%s", res.reason);
  b3_rows(rows, sizeof rows, 1.5, 1.0); /* apart from the start */
  cr_expect_eq(decide(rows, cb_check_B3), CB_NOT_REPRODUCED, "%s", res.reason);
}
