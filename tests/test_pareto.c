/* Pareto front, cheapest method at an error level, convergence order
 * (lib/instruments/pareto.c), on hand-made data. */
#include <criterion/criterion.h>
#include <math.h>

#include "pareto.h"

Test(pareto, front) {
  /* (cost, err): 0 (1, 1e-2) front; 1 (2, 1e-3) front; 2 (2, 1e-2) dominated by 0 and 1;
   * 3 (5, 1e-3) dominated by 1; 4 (9, 1e-9) front; 5 (0.5, Inf) front (cheapest, failed);
   * 6 (NaN, 1e-12) never; 7 (3, 1e-3) dominated by 1 */
  double cost[] = {1, 2, 2, 5, 9, 0.5, NAN, 3}, err[] = {1e-2, 1e-3, 1e-2, 1e-3, 1e-9, INFINITY, 1e-12, 1e-3};
  int f[8], want[] = {1, 1, 0, 0, 1, 0, 0, 0};
  cb_pareto_front(8, cost, err, f);
  for (int i = 0; i < 8; i++) cr_assert_eq(f[i], want[i], "point %d", i);
}

Test(pareto, equal_points_both_on_front) {
  double cost[] = {1, 1}, err[] = {1e-3, 1e-3};
  int f[2];
  cb_pareto_front(2, cost, err, f);
  cr_assert(f[0] && f[1]);
}

Test(pareto, cheapest_at_level) {
  double cost[] = {1, 2, 5, 9, 0.5}, err[] = {2e-2, 1e-3, 1e-7, 1e-9, INFINITY};
  cr_assert_eq(cb_cheapest_at(5, cost, err, 1e-2), 1);
  cr_assert_eq(cb_cheapest_at(5, cost, err, 1e-1), 0);
  cr_assert_eq(cb_cheapest_at(5, cost, err, 1e-6), 2);
  cr_assert_eq(cb_cheapest_at(5, cost, err, 1e-12), -1);
}

Test(pareto, order_quadratic_linear_and_floor) {
  double q[] = {1, 0.5, 0.1, 1e-2, 1e-4, 1e-8, 1e-15}; /* last value below the 1e-11 floor */
  double p;
  int k;
  cr_assert_eq(cb_convergence_order(q, NULL, 7, 0.1, 1e-11, &p, &k), 0);
  cr_assert_float_eq(p, 2.0, 1e-12);
  cr_assert_eq(k, 5);
  double lin[] = {1, 0.1, 1e-2, 1e-3, 1e-4, 1e-5};
  cr_assert_eq(cb_convergence_order(lin, NULL, 6, 0.1, 1e-11, &p, NULL), 0);
  cr_assert_float_eq(p, 1.0, 1e-12);
  double cubic[] = {1, 0.1, 1e-3, 1e-9};
  cr_assert_eq(cb_convergence_order(cubic, NULL, 4, 0.1, 1e-11, &p, NULL), 0);
  cr_assert_float_eq(p, 3.0, 1e-12);
  /* not decreasing, or nothing in the local regime: no estimate */
  double up[] = {1, 0.5, 0.6, 0.7};
  cr_assert_eq(cb_convergence_order(up, NULL, 4, 0.1, 1e-11, &p, NULL), 1);
  cr_assert(isnan(p));
  /* the mask: updates 4 and 5 not "exact" -> the last usable triple is (1, 2, 3) */
  double g[] = {1, 0.1, 1e-2, 1e-4, 1e-5, 1e-6};
  int use[] = {0, 1, 1, 1, 0, 0};
  cr_assert_eq(cb_convergence_order(g, use, 6, 0.1, 1e-11, &p, &k), 0);
  cr_assert_eq(k, 3);
  cr_assert_float_eq(p, 2.0, 1e-12);
}
