/* Repeated timings (lib/instruments/stats.c): the number of rounds, the
 * median and spread, the CSV list of repeats, the per-repeat median. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "stats.h"

Test(stats, median_min_max_leave_the_order_alone) {
  cb_timing t = {0};
  const double v[] = {3, 1, 2, 5};
  for (int i = 0; i < 4; i++) cb_timing_add(&t, v[i]);
  cr_expect_eq(cb_timing_median(&t), 2.5);
  cr_expect_eq(cb_timing_min(&t), 1);
  cr_expect_eq(cb_timing_max(&t), 5);
  cr_expect(t.ms[0] == 3 && t.ms[3] == 5, "reordered");
  cb_timing e = {0};
  cr_expect(isnan(cb_timing_median(&e)) && isnan(cb_timing_min(&e)) && isnan(cb_timing_max(&e)));
  for (int i = 0; i < 20; i++) cb_timing_add(&e, i);
  cr_expect_eq(e.n, CB_TIMING_MAX);
}

/* quick: 3 rounds; full: 5 while cheap, 3 past the budget, 2 when one round is long */
Test(stats, rounds) {
  int n;
  for (n = 0; cb_timing_more(1, n, n * 50000.0); n++) {}
  cr_expect_eq(n, 3, "quick: %d rounds", n);
  for (n = 0; cb_timing_more(0, n, n * 1.0); n++) {}
  cr_expect_eq(n, 5, "full, 1 ms rounds: %d", n);
  for (n = 0; cb_timing_more(0, n, n * 0.6 * CB_TIMING_BUDGET_MS); n++) {}
  cr_expect_eq(n, 3, "full, rounds of 0.6 x the budget: %d", n);
  for (n = 0; cb_timing_more(0, n, n * 0.3 * CB_TIMING_BUDGET_MS); n++) {}
  cr_expect_eq(n, 4, "full, rounds of 0.3 x the budget: %d", n);
  for (n = 0; cb_timing_more(0, n, n * 1.5 * CB_TIMING_LONG_MS); n++) {}
  cr_expect_eq(n, 2, "full, long rounds: %d", n);
}

Test(stats, each_field_round_trips) {
  cb_timing t = {0}, u;
  cb_timing_add(&t, 1.25);
  cb_timing_add(&t, 0.5);
  cb_timing_add(&t, 2);
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  cb_timing_csv(f, &t, 2.0);
  fputc('|', f);
  cb_timing_csv_each(f, &t, 2.0);
  fclose(f);
  cr_expect_str_eq(buf, "2.500000,1.000000,4.000000|2.500000;1.000000;4.000000");
  cr_expect_eq(cb_timing_parse(strchr(buf, '|') + 1, &u), 3);
  cr_expect(u.ms[0] == 2.5 && u.ms[1] == 1 && u.ms[2] == 4);
  free(buf);
  cr_expect_eq(cb_timing_parse("", &u), 0);
  cr_expect_eq(cb_timing_parse("1;x", &u), 0);
  cr_expect_eq(u.n, 0);
  cr_expect_eq(cb_timing_parse("1,2", &u), 0);
}

Test(stats, median_over_states_per_repeat) {
  cb_timing v[3] = {{3, {1, 2, 3}}, {3, {3, 2, 1}}, {3, {2, 9, 2}}}, out;
  cr_assert_eq(cb_timing_median_over(v, 3, &out), 0);
  cr_expect(out.n == 3 && out.ms[0] == 2 && out.ms[1] == 2 && out.ms[2] == 2, "%g %g %g", out.ms[0], out.ms[1],
            out.ms[2]);
  v[2].n = 2; /* the repeats every state has: the first two */
  cr_assert_eq(cb_timing_median_over(v, 3, &out), 0);
  cr_expect(out.n == 2 && out.ms[0] == 2 && out.ms[1] == 2, "%d: %g %g", out.n, out.ms[0], out.ms[1]);
  v[1].n = 0;
  cr_expect_eq(cb_timing_median_over(v, 3, &out), -1);
  cr_expect_eq(out.n, 0);
}
