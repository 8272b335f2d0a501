/* Timing-based numbers with their spread (claims/spread.c): read from CSV
 * columns, ratios and differences from paired repeats or as bounds, medians
 * over rows, and their text. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "claims.h"
#include "support.h"

static cb_table table(const char *text) {
  cb_table t;
  cr_assert_eq(cb_table_read(test_tmpfile(".csv", text), &t), 0);
  return t;
}

Test(claims_spread, columns_are_derived_from_the_median_column) {
  cb_table t = table("# t\na,wall_ms_per_s,wall_min_ms_per_s,wall_max_ms_per_s,wall_each_ms_per_s,wall_repeats,x_ms\n"
                     "1,2,1,4,4;2;1,3,7\n");
  cb_claim_timing w = cb_claim_timing_at(&t, 0, "wall_ms_per_s"), x = cb_claim_timing_at(&t, 0, "x_ms");
  cr_expect(w.med == 2 && w.min == 1 && w.max == 4 && w.n == 3 && w.each.n == 3 && !w.bounds);
  cr_expect(x.med == 7 && isnan(x.min) && x.n == 0, "no spread columns: none shown");
  char b[128];
  cr_expect_str_eq(cb_claim_spread(b, sizeof b, "%.3g", &w, " ms"), "2 ms (1-4 ms)");
  cr_expect_str_eq(cb_claim_spread_long(b, sizeof b, "%.3g", &w, ""), "2 (1-4 over 3 repeats)");
  cr_expect_str_eq(cb_claim_spread(b, sizeof b, "%.3g", &x, ""), "7");
  cb_table_free(&t);
}

Test(claims_spread, min_max_without_a_list_gives_the_count_column) {
  cb_table t = table("# t\nwall_ms,wall_min_ms,wall_max_ms,wall_repeats\n2,1,3,5\n");
  cb_claim_timing w = cb_claim_timing_at(&t, 0, "wall_ms");
  cr_expect(w.min == 1 && w.max == 3 && w.n == 5 && w.each.n == 0);
  cb_table_free(&t);
}

static cb_claim_timing timing(const double *v, int n, int list) {
  cb_claim_timing t = cb_claim_timing_value(0);
  cb_timing e = {0};
  for (int i = 0; i < n; i++) cb_timing_add(&e, v[i]);
  t.med = cb_timing_median(&e);
  t.min = cb_timing_min(&e);
  t.max = cb_timing_max(&e);
  t.n = n;
  if (list) t.each = e;
  return t;
}

Test(claims_spread, ratio_paired_or_bounds) {
  const double a[] = {10, 11, 12}, b[] = {1, 1.1, 1.2};
  cb_claim_timing A = timing(a, 3, 1), B = timing(b, 3, 1);
  cb_claim_timing r = cb_claim_timing_ratio(&A, &B);
  cr_expect(fabs(r.med - 10) < 1e-12 && fabs(r.min - 10) < 1e-12 && fabs(r.max - 10) < 1e-12 && r.paired && !r.bounds);
  char s[128];
  cr_expect_str_eq(cb_claim_spread_long(s, sizeof s, "%.3g", &r, "x"), "10x (10-10x over 3 paired repeats)");
  A = timing(a, 3, 0); /* no list: conservative bounds min/max .. max/min */
  r = cb_claim_timing_ratio(&A, &B);
  cr_expect(r.bounds && !r.paired && fabs(r.min - 10 / 1.2) < 1e-12 && fabs(r.max - 12) < 1e-12);
  cr_expect_str_eq(cb_claim_spread_long(s, sizeof s, "%.3g", &r, "x"), "10x (8.33-12x, bounds from the min and max of "
                                                                       "3 repeats)");
  cb_claim_timing two = cb_claim_timing_value(2); /* a constant divides exactly */
  r = cb_claim_timing_ratio(&A, &two);
  cr_expect(!r.bounds && r.min == 5 && r.max == 6);
  cb_claim_timing d = cb_claim_timing_diff(&B, &B);
  cr_expect(d.paired && d.min == 0 && d.max == 0);
}

Test(claims_spread, median_over_rows) {
  const double s0[] = {1, 2, 3}, s1[] = {3, 2, 1}, s2[] = {2, 9, 2};
  cb_claim_timing v[3] = {timing(s0, 3, 1), timing(s1, 3, 1), timing(s2, 3, 1)};
  cb_claim_timing m = cb_claim_timing_median(v, 3);
  cr_expect(m.med == 2 && m.min == 2 && m.max == 2 && m.n == 3, "%g %g %g", m.med, m.min, m.max);
  v[2] = timing(s2, 3, 0); /* one row without its list: the median of the mins and of the maxes */
  m = cb_claim_timing_median(v, 3);
  cr_expect(m.bounds && m.min == 1 && m.max == 3, "%g %g", m.min, m.max);
  cb_claim_repeats r = {0};
  cb_claim_repeats_add(&r, &v[0]);
  v[1].n = 5;
  cb_claim_repeats_add(&r, &v[1]);
  char b[64];
  cr_expect_str_eq(cb_claim_repeats_text(b, sizeof b, &r), "3-5 repeats");
}

/* Where a timing stands against a threshold, and how many repeats would decide it: a spread 1.5-2.5 with
 * median 2.25 over 3 repeats straddles 2 (margin 0.25, half-width 0.75 below): 3 (0.75/0.25)^2 = 27, so 28. */
Test(claims_spread, side_range_and_repeats_to_decide) {
  const double e[] = {1.5, 2.25, 2.5};
  cb_claim_timing t = timing(e, 3, 1);
  cr_expect_eq(cb_claim_timing_side(&t, 2), 0);
  cr_expect_eq(cb_claim_timing_side(&t, 1.4), 1);
  cr_expect_eq(cb_claim_timing_side(&t, 3), -1);
  cr_expect_eq(cb_claim_timing_repeats_to_decide(&t, 2), 28);
  cr_expect_eq(cb_claim_timing_repeats_to_decide(&t, 1.4), 0, "decided already");
  cb_claim_timing on = timing((const double[]){1, 2, 3}, 3, 1);
  cr_expect_eq(cb_claim_timing_repeats_to_decide(&on, 2), -1, "the median on the threshold");
  cb_claim_timing v = cb_claim_timing_value(2); /* no spread: the claim's own comparison decides */
  cr_expect_eq(cb_claim_timing_side_ge(&v, 2, 1), 1);
  cr_expect_eq(cb_claim_timing_side_ge(&v, 2, 0), -1);
  cr_expect_eq(cb_claim_timing_side_ge(&t, 2, 1), 0);
  char b[1024];
  cb_claim_undecided_text(b, sizeof b, "the ratio", "%.2f", &t, "x", 2);
  cr_expect(strstr(b, "the ratio 2.25x (1.50-2.50x over 3 repeats) straddles 2.00x: margin +0.25x (median above by "
                      "12%), while the spread reaches 1.50x on the other side; about 28 repeats would decide it"),
            "%s", b);
  cb_claim_margin_text(b, sizeof b, "%.2f", &t, "x", 1.25);
  cr_expect_str_eq(b, "margin +0.25x: the spread's low end 1.50x lies above 1.25x (by 20%)");
  cr_expect_eq(cb_claim_verdict_either(CB_PARTLY, CB_PARTLY), CB_PARTLY);
  cr_expect_eq(cb_claim_verdict_either(CB_PARTLY, CB_REPRODUCED), CB_UNDECIDED);
  cb_claim_verdict_median_only = 1; /* the rule before issue 31: the median alone */
  cr_expect_eq(cb_claim_timing_side(&t, 2), 1);
  cb_claim_verdict_median_only = 0;
  char name[64];
  cb_claim_spread_column("wall_ms_per_s", "min", name, sizeof name);
  cr_expect_str_eq(name, "wall_min_ms_per_s");
  cb_claim_spread_column("rms_m", "min", name, sizeof name);
  cr_expect_str_eq(name, "");
}
