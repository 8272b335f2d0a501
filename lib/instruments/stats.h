/* Statistics of repeated measurements. */
#ifndef CB_STATS_H
#define CB_STATS_H

#include <stdio.h>

/* Median of v[0..n) (sorts v in place; the mean of the middle two for even
 * n; NaN for n <= 0). The statistic every timing in the project is quoted by. */
double cb_median(double *v, int n);

/* ---- repeated timings -------------------------------------------------------
 *
 * Every wall time a claim is decided on is measured several times and quoted
 * as the median of the repeats, with the smallest and largest repeat as its
 * spread. Methods that a claim compares are repeated in interleaved rounds
 * (A B A B ..., not A A B B), so repeat i of A and repeat i of B ran at
 * nearly the same moment and their ratio is a paired sample.
 *
 * How many rounds (cb_timing_more): 3 with --quick; in a full run 5, but
 * only 3 once the rounds so far took CB_TIMING_BUDGET_MS (2 s), and only 2
 * when a single round takes more than CB_TIMING_LONG_MS (5 s: a run that
 * long already averages over many steps, and each repeat of it adds its
 * whole time to the experiment).
 *
 * CSV columns of a repeated timing <base>_ms<tail> (wall_ms, wall_ms_per_s):
 * <base>_ms<tail> the median, <base>_min_ms<tail> and <base>_max_ms<tail>
 * the smallest and largest repeat, <base>_each_ms<tail> every repeat in the
 * order run, separated by ';' (cb_timing_csv_each in lib/io/csv.h), and a count column
 * wall_repeats. Every such name ends in _ms or contains "wall", so
 * tests/determinism.sh leaves them out of its comparison.
 *
 * Interleaving puts another method's run before every repeat, which evicts
 * a short run's data from the caches (a 1 ms CHOLMOD step then takes 25%
 * longer than in the consecutive steps of a simulation). So each repeat
 * runs once, and if that run took less than CB_TIMING_WARM_MS it was only
 * the warm-up: the repeat is the next run, right after it (cb_timing_warm).
 * Longer runs warm their own caches and are timed as they are. */

enum { CB_TIMING_MAX = 8 };
#define CB_TIMING_BUDGET_MS 2000.0
#define CB_TIMING_LONG_MS 5000.0
#define CB_TIMING_WARM_MS 25.0

/* The repeats of one timed measurement, in the order they ran (ms). */
typedef struct cb_timing {
  int n;
  double ms[CB_TIMING_MAX];
} cb_timing;

/* Appends one repeat (ignored past CB_TIMING_MAX). */
void cb_timing_add(cb_timing *t, double ms);
/* Median, smallest and largest repeat (NaN when there is none); t is not
 * reordered. */
double cb_timing_median(const cb_timing *t);
double cb_timing_min(const cb_timing *t);
double cb_timing_max(const cb_timing *t);

/* Per repeat i, the median over v[0..n) of repeat i (v: one timing per start
 * state, say), for the repeats that every v has (a full run may give one
 * state more rounds than another): out gets as many as the fewest v has.
 * Returns 0, or -1 (out empty) when n <= 0 or some v has no repeat. */
int cb_timing_median_over(const cb_timing *v, int n, cb_timing *out);

/* 1 if another round of repeats is due after `done` rounds that took
 * spent_ms together (see above); 0 when done >= CB_TIMING_MAX. */
int cb_timing_more(int quick, int done, double spent_ms);

/* 1 if a run that took ms was short enough to be only the warm-up of the
 * repeat (which is then the next run). */
int cb_timing_warm(double ms);

/* Parses a field written by cb_timing_csv_each (lib/io/csv.h) into t; returns the number of
 * repeats read (0 for an empty or malformed field, which leaves t empty). */
int cb_timing_parse(const char *s, cb_timing *t);

#endif
