/* Error against cost: the Pareto front of a set of methods, the cheapest
 * method at an error level, and the order of convergence of an iteration
 * from its residual sequence. Shared by experiments and the claims checkers,
 * so the figures and the verdicts use the same definitions. */
#ifndef CB_PARETO_H
#define CB_PARETO_H

/* on_front[i] = 1 when no other point j is at least as good in both cost and
 * error and strictly better in one (cost_j <= cost_i, err_j <= err_i, one
 * strict). Points with a NaN cost or error are never on the front and never
 * dominate; +Inf error is allowed (a failed method) and is dominated by any
 * finite one. */
void cb_pareto_front(int n, const double *cost, const double *err, int *on_front);

/* Index of the cheapest point with err <= level (ties: the lower index), or -1. */
int cb_cheapest_at(int n, const double *cost, const double *err, double level);

/* Order of convergence from a residual sequence g[0..n-1] (e.g. |grad F| of
 * Newton's iterates): p_k = log(g[k+1]/g[k]) / log(g[k]/g[k-1]), which tends
 * to the order q when g[k+1] ~ C g[k]^q. Uses the last triple (k-1, k, k+1)
 * that is in the local regime, g[k-1] <= local_rel g[0], and above round-off,
 * g[k+1] >= floor_rel g[0], with g decreasing along it, and (if use != NULL)
 * whose two updates are marked use[k] = use[k+1] = 1 (use[i] refers to the
 * update that produced g[i], e.g. "made with the exact Hessian"). Returns 0
 * and sets *order and *k_used (the index k+1 of the last residual used), or
 * 1 when no triple qualifies (*order = NaN). */
int cb_convergence_order(const double *g, const int *use, int n, double local_rel, double floor_rel, double *order,
                         int *k_used);

#endif
