/* The claims report: one entry per claim of CLAIMS.md, each decided by a
 * checker that reads its experiment's CSV. Verdicts come from the data only.
 *
 * To add a claim: write its checker, a function of type cb_claim_check, in
 * claims/check_<experiment>.c, and add its X(...) entry to the list in
 * claims/claims_list.h (which declares the checker and puts it in cb_claims[]). */
#ifndef CB_CLAIMS_H
#define CB_CLAIMS_H

#include <stddef.h>
#include <stdio.h>

#include "stats.h"
#include "table.h"

/* CB_UNDECIDED: a timing verdict whose paired spread straddles its threshold
 * (CLAIMS.md, "Verdicts that hold"): the median alone never decides it. */
typedef enum { CB_NOT_RUN = 0, CB_REPRODUCED, CB_PARTLY, CB_NOT_REPRODUCED, CB_UNDECIDED } cb_verdict;

/* A timing number a verdict was decided on, recorded by cb_claim_timing_side
 * (the one rule every timing verdict uses) while its claim is decided: make
 * compare pairs them between two runs and asks whether the runs differ
 * within their spreads. */
typedef struct cb_claim_deciding {
  double med, min, max; /* min, max: NaN without a spread */
  double thr;           /* the threshold it was held against */
  int side;             /* cb_claim_timing_side's answer: +1 above, -1 below, 0 straddles */
} cb_claim_deciding;
#define CB_CLAIM_DECIDING_MAX 64

typedef struct cb_claim_result {
  cb_verdict verdict;
  int ndeciding; /* the first CB_CLAIM_DECIDING_MAX are kept, in the order they were decided */
  cb_claim_deciding deciding[CB_CLAIM_DECIDING_MAX];
  char reason[4096];   /* one or two sentences: why this verdict */
  char numbers[32768]; /* Markdown: the deciding numbers (a table or a list) */
} cb_claim_result;

/* csv: results/<experiment>.csv; results_dir: where side CSVs live. */
typedef void (*cb_claim_check)(const cb_table *csv, const char *results_dir, cb_claim_result *out);

typedef struct cb_claim {
  const char *id;         /* "E1" */
  const char *experiment; /* CSV stem in results/, or NULL if no experiment exists yet */
  const char *text;       /* the claim */
  const char *decided_by; /* the deciding measurement */
  const char *figure;     /* PNGs in plots/out/, separated by spaces (the first is the main one), or NULL */
  cb_claim_check check;
} cb_claim;

/* Every checker of the list, declared from it. */
#include "claims_list.h"
#define CB_CLAIM_DECLARE(check_, id_, experiment_, text_, decided_by_, figure_) \
  void check_(const cb_table *csv, const char *results_dir, cb_claim_result *out);
CB_CLAIMS(CB_CLAIM_DECLARE)
#undef CB_CLAIM_DECLARE
/* J3's linear panel (check_linear_solvers.c), which cb_check_nonlinear_j3 runs. */
void cb_check_j3(const cb_table *csv, const char *dir, cb_claim_result *out);

extern const cb_claim cb_claims[];
extern const int cb_nclaims;

const char *cb_verdict_name(cb_verdict v);

/* Writes each figure of c as `name` (code) or ![id](dir/name) (image), with
 * sep between them; "-" (code) or nothing (image) when c has none. */
void cb_claim_figures(FILE *f, const cb_claim *c, const char *dir, const char *sep);

/* Append printf-style text to a result's numbers or reason. */
void cb_claim_numbers(cb_claim_result *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void cb_claim_reason(cb_claim_result *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Runs one claim's check on the files in results_dir (not run if its CSV is
 * missing or it has no experiment). */
void cb_claim_decide(const cb_claim *c, const char *results_dir, cb_claim_result *out);

/* Reads the side table <dir>/<experiment>_<table>.csv into t; on failure
 * (missing or unreadable) adds a reason naming the file and the program to
 * run, and returns non-zero. */
int cb_claim_side_table(const char *dir, const char *experiment, const char *table, cb_table *t, cb_claim_result *out);
/* Column indices of names[0..n) in t; 0 if all exist, else a reason naming
 * file and the first missing column, and -1. */
int cb_claim_columns(const cb_table *t, const char *const *names, int *idx, int n, const char *file,
                     cb_claim_result *out);

/* Least-squares slope and intercept of y on x over n points. */
void cb_fit_line(const double *x, const double *y, int n, double *slope, double *intercept);

/* ---- timing-based numbers and their spread (claims/spread.c) ----------------
 *
 * A timing-based number is quoted as its median with its spread, the
 * smallest and largest of the repeats behind it (lib/instruments/stats.h has
 * the CSV columns). Numbers derived from timings (ratios, differences,
 * medians over start states) carry a spread too: from paired repeats when
 * both operands list their repeats and have the same number of them (the
 * experiments interleave what they compare, so repeat i of A and of B ran
 * together), else conservative bounds from the operands' min and max (the
 * flag bounds). The median itself is always computed from the operands'
 * medians, as before the spread existed, so verdicts do not depend on it. */
typedef struct cb_claim_timing {
  double med, min, max; /* min, max: NaN when the CSV records no spread */
  int n;                /* repeats behind the number (0: unknown) */
  int bounds;           /* 1: min and max are bounds from min/max columns, not observed repeats */
  int paired;           /* 1: a ratio or difference whose spread comes from paired repeats */
  cb_timing each;       /* the repeats (or paired derived values) in order; each.n = 0 if not listed */
} cb_claim_timing;

/* The timing whose median is column col (e.g. "wall_ms") of row r, with the
 * spread columns derived from col (wall_min_ms, wall_max_ms, wall_each_ms;
 * wall_ms_per_s gives wall_min_ms_per_s ...) and the count wall_repeats if
 * present. A CSV without them gives min = max = NaN, n = 0. */
cb_claim_timing cb_claim_timing_at(const cb_table *t, int r, const char *col);
/* The name of col's spread column: what ("min", "max", "each") inserted before its "_ms" (the first
 * "_ms" that ends the name or is followed by '_'): wall_ms_per_s gives wall_min_ms_per_s; "" if col has
 * no "_ms". */
void cb_claim_spread_column(const char *col, const char *what, char *buf, size_t n);
/* A number without repeats (no spread). */
cb_claim_timing cb_claim_timing_value(double v);
/* a / b and a - b, with the spread described above. */
cb_claim_timing cb_claim_timing_ratio(const cb_claim_timing *a, const cb_claim_timing *b);
cb_claim_timing cb_claim_timing_diff(const cb_claim_timing *a, const cb_claim_timing *b);
/* a x s for a constant s > 0. */
cb_claim_timing cb_claim_timing_scale(const cb_claim_timing *a, double s);
/* The median over v[0..n) (e.g. over start states or frames). When every v
 * lists its repeats: for each repeat i (of those every v has) the median over
 * v of repeat i, and of that series the median, min and max (so the median
 * lies inside its spread). Else (some v lists none) the median of the
 * medians, of the mins and of the maxes (bounds). */
cb_claim_timing cb_claim_timing_median(const cb_claim_timing *v, int n);
/* 1 if t has a spread to show. */
int cb_claim_timing_has_spread(const cb_claim_timing *t);
/* Where t stands against a threshold thr, over its whole spread: +1 when the
 * spread lies above thr (min > thr), -1 when below (max < thr), 0 when it
 * straddles thr (undecided within the spread). A number without a spread is
 * placed by its median (and is never 0 unless med == thr). The one rule every
 * timing verdict uses, so that no verdict flips with the machine's load. */
int cb_claim_timing_side(const cb_claim_timing *t, double thr);
/* The claim being decided (set by cb_claim_decide, NULL between claims): cb_claim_timing_side records
 * each timing against its threshold there as a deciding number. */
extern cb_claim_result *cb_claim_deciding_now;

/* The ends over which a timing verdict must hold: [min(min, med), max(max, med)], or [med, med] for a
 * number without a spread (or under cb_claim_verdict_median_only). */
void cb_claim_timing_range(const cb_claim_timing *t, double *lo, double *hi);
/* cb_claim_timing_side for a claim that reads "value >= thr" (ge = 1) or "value > thr" (ge = 0): the
 * same, except that a number without a spread is placed by that comparison (never 0). */
int cb_claim_timing_side_ge(const cb_claim_timing *t, double thr, int ge);
/* How many repeats would decide t against thr, estimated from the observed spread: the spread's
 * half-width on the threshold's side, h, is taken to shrink as 1/sqrt(repeats), so N repeats decide it
 * once h sqrt(n/N) < |med - thr| (n: t's repeats, at least 1). 0 when t is decided already, -1 when
 * no number would (the median on the threshold). An estimate, not a promise. */
int cb_claim_timing_repeats_to_decide(const cb_claim_timing *t, double thr);
/* The sentence for a straddled threshold: "<what> 1.3x (1.0-1.7x over 2 paired repeats) straddles 2x:
 * margin -0.7x (median below by 35%), while the spread reaches 1.7x on the other side; about 12 repeats
 * would decide it (...)". Returns buf. */
const char *cb_claim_undecided_text(char *buf, size_t n, const char *what, const char *fmt, const cb_claim_timing *t,
                                    const char *unit, double thr);
/* The margin of a decided t to thr: "margin +0.3x: the spread's low end 2.3x lies above 2x (by 15%)"
 * (the undecided sentence when t straddles thr). Returns buf. */
const char *cb_claim_margin_text(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit,
                                 double thr);
/* a when a == b, else CB_UNDECIDED: the verdict of a claim whose timing part is undecided, from the
 * verdicts it would have on either side of the threshold. */
cb_verdict cb_claim_verdict_either(cb_verdict a, cb_verdict b);
/* 1: every timing verdict is taken by the median alone (the spread ignored), the rule before issue 31;
 * only for the verdict-stability test's own fixture (report --median-verdicts), never for a report. */
extern int cb_claim_verdict_median_only;

/* "<med><unit> (<min>-<max><unit>)" with printf format fmt for each number
 * (e.g. "%.3g"), or "<med><unit>" when t has no spread. Returns buf. */
const char *cb_claim_spread(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit);
/* The same followed by how the spread was obtained, inside the brackets:
 * "12.0x (11.6-12.4x over 5 paired repeats)", "(... bounds from the min and
 * max of 3 repeats)", "(... over 5 repeats)". Returns buf. */
const char *cb_claim_spread_long(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit);

/* The range of repeat counts seen over a table's timings, for its note. */
typedef struct cb_claim_repeats {
  int lo, hi;
} cb_claim_repeats;
void cb_claim_repeats_add(cb_claim_repeats *r, const cb_claim_timing *t);
/* "5 repeats" or "3-5 repeats" ("" if none seen). Returns buf. */
const char *cb_claim_repeats_text(char *buf, size_t n, const cb_claim_repeats *r);

#endif
