#include "pareto.h"

#include <math.h>

void cb_pareto_front(int n, const double *cost, const double *err, int *on_front) {
  for (int i = 0; i < n; i++) {
    on_front[i] = !isnan(cost[i]) && !isnan(err[i]) && isfinite(cost[i]) && isfinite(err[i]);
    for (int j = 0; on_front[i] && j < n; j++) {
      if (j == i || isnan(cost[j]) || isnan(err[j])) continue;
      int no_worse = cost[j] <= cost[i] && err[j] <= err[i];
      int better = cost[j] < cost[i] || err[j] < err[i];
      if (no_worse && better) on_front[i] = 0; /* j dominates i */
    }
  }
}

int cb_cheapest_at(int n, const double *cost, const double *err, double level) {
  int best = -1;
  for (int i = 0; i < n; i++) {
    if (isnan(cost[i]) || isnan(err[i]) || !(err[i] <= level)) continue;
    if (best < 0 || cost[i] < cost[best]) best = i;
  }
  return best;
}

int cb_convergence_order(const double *g, const int *use, int n, double local_rel, double floor_rel, double *order,
                         int *k_used) {
  *order = NAN;
  if (k_used) *k_used = -1;
  if (n < 3 || !(g[0] > 0)) return 1;
  for (int k = n - 2; k >= 1; k--) {
    double a = g[k - 1], b = g[k], c = g[k + 1];
    if (!(a <= local_rel * g[0]) || !(c >= floor_rel * g[0])) continue;
    if (!(a > b && b > c && c > 0)) continue;
    if (use && !(use[k] && use[k + 1])) continue;
    *order = log(c / b) / log(b / a); /* p = log(g_{k+1}/g_k) / log(g_k/g_{k-1}) */
    if (k_used) *k_used = k + 1;
    return 0;
  }
  return 1;
}
