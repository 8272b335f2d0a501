/* make compare's rule (claims/compare.c): two runs' verdicts of one claim
 * agree, differ within the spreads of a timing they were decided on, differ
 * outside them, or cannot be compared; and cb_claim_timing_side records the
 * deciding numbers it is asked about. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "claims.h"
#include "report.h"

static cb_claim_result result(cb_verdict v, double med, double min, double max, double thr) {
  cb_claim_result r = {.verdict = v, .ndeciding = 1};
  r.deciding[0] = (cb_claim_deciding){.med = med, .min = min, .max = max, .thr = thr};
  r.deciding[0].side = min > thr ? 1 : max < thr ? -1 : 0;
  if (isnan(min)) r.deciding[0].side = med > thr ? 1 : -1;
  return r;
}

Test(compare, the_same_verdict_is_the_same) {
  cb_claim_result a = result(CB_REPRODUCED, 2.5, 2.2, 2.8, 2), b = result(CB_REPRODUCED, 3, 2.9, 3.1, 2);
  cr_expect_eq(cb_report_compare_claim(&a, &b), CB_COMPARE_SAME);
}

Test(compare, a_flip_whose_spreads_overlap_is_within_them) {
  /* this run 2.1x (1.9-2.3x) is above 2x; the reference's 1.8x (1.6-2.05x) is below: the spreads overlap */
  cb_claim_result a = result(CB_REPRODUCED, 2.1, 2.05, 2.3, 2), b = result(CB_PARTLY, 1.8, 1.6, 1.95, 2);
  b.deciding[0].max = 2.06;
  cr_expect_eq(cb_report_compare_claim(&a, &b), CB_COMPARE_WITHIN);
}

Test(compare, a_flip_whose_spreads_are_apart_differs) {
  cb_claim_result a = result(CB_REPRODUCED, 2.5, 2.3, 2.7, 2), b = result(CB_PARTLY, 1.5, 1.4, 1.6, 2);
  cr_expect_eq(cb_report_compare_claim(&a, &b), CB_COMPARE_DIFFERS);
}

Test(compare, a_flip_without_a_deciding_timing_differs) {
  cb_claim_result a = {.verdict = CB_REPRODUCED}, b = {.verdict = CB_NOT_REPRODUCED};
  cr_expect_eq(cb_report_compare_claim(&a, &b), CB_COMPARE_DIFFERS);
}

Test(compare, timings_against_other_thresholds_are_not_paired) {
  cb_claim_result a = result(CB_REPRODUCED, 2.1, 2.05, 2.3, 2), b = result(CB_PARTLY, 1.8, 1.6, 2.06, 3);
  cr_expect_eq(cb_report_compare_claim(&a, &b), CB_COMPARE_DIFFERS);
}

Test(compare, undecided_or_not_run_is_not_compared) {
  cb_claim_result a = {.verdict = CB_UNDECIDED}, b = {.verdict = CB_NOT_REPRODUCED}, c = {.verdict = CB_NOT_RUN};
  cr_expect_eq(cb_report_compare_claim(&a, &b), CB_COMPARE_NOT_COMPARED);
  cr_expect_eq(cb_report_compare_claim(&b, &c), CB_COMPARE_NOT_COMPARED);
}

/* a checker that holds two timings against 2x, run by cb_claim_decide's recorder */
static void check_two(const cb_table *csv, const char *dir, cb_claim_result *out) {
  (void)csv;
  (void)dir;
  cb_claim_timing t1 = {.med = 2.5, .min = 2.1, .max = 2.9, .n = 3};
  cb_claim_timing t2 = {.med = 2.1, .min = 1.9, .max = 2.4, .n = 3};
  cr_expect_eq(cb_claim_timing_side(&t1, 2), 1);
  cr_expect_eq(cb_claim_timing_side(&t2, 2), 0, "1.9-2.4 straddles 2");
  out->verdict = CB_UNDECIDED;
}

Test(compare, timing_side_records_the_deciding_numbers_of_the_claim_being_decided) {
  cb_claim c = {.id = "Z9", .experiment = "z", .check = check_two};
  char dir[] = "/tmp/cbcompareXXXXXX";
  cr_assert_not_null(mkdtemp(dir));
  char path[64];
  snprintf(path, sizeof path, "%s/z.csv", dir);
  FILE *f = fopen(path, "w");
  cr_assert_not_null(f);
  fputs("# t\na\n1\n", f);
  fclose(f);
  cb_claim_result r;
  cb_claim_decide(&c, dir, &r);
  cr_assert_eq(r.ndeciding, 2);
  cr_expect(r.deciding[0].med == 2.5 && r.deciding[0].min == 2.1 && r.deciding[0].max == 2.9 &&
            r.deciding[0].thr == 2 && r.deciding[0].side == 1);
  cr_expect(r.deciding[1].side == 0);
  /* outside a claim's decision nothing is recorded (and nothing crashes) */
  cb_claim_timing t = {.med = 1};
  cr_expect_eq(cb_claim_timing_side(&t, 2), -1);
  cr_expect_eq(r.ndeciding, 2);
  remove(path);
  rmdir(dir);
}
