/* Statistics of repeated measurements. */
#ifndef CB_STATS_H
#define CB_STATS_H

/* Median of v[0..n) (sorts v in place; the mean of the middle two for even
 * n; NaN for n <= 0). The statistic every timing in the project is quoted by. */
double cb_median(double *v, int n);

#endif
