/* The pieces of results/REPORT.md that other documents reuse: the README and
 * docs/ carry marked blocks that `build/report --fill` regenerates from the
 * same data, so no number in them is typed by hand. */
#ifndef CB_REPORT_H
#define CB_REPORT_H

#include <stdio.h>

#include "claims.h"

/* "What produced this report": run kind, revision, date, threads, machine of
 * every experiment CSV in results/, and a summary line. */
void cb_report_origin(FILE *f, const char *results);
/* The kind of run of results/<experiment>.csv: "full", "quick (`QUICK=1`)" or
 * "smoke (`--smoke`, make test)"; NULL when there is no CSV. _all: the kind
 * of every experiment CSV there, "mixed" when they differ, NULL when none. */
const char *cb_report_run_kind(const char *results, const char *experiment);
const char *cb_report_run_kind_all(const char *results);
/* A table of each experiment's wall time (results/<experiment>.runtime). */
void cb_report_runtimes(FILE *f, const char *results);
/* The verdict table: claim, verdict, why (the checker's reason), figure. */
void cb_report_verdicts(FILE *f, const cb_claim_result *res);
/* Rewrites the marked blocks of path (see report --help) from res; the file
 * is written atomically and left untouched on any error (an unknown marker,
 * a marker without its end). */
int cb_report_fill(const char *path, const cb_claim_result *res, const char *results);

/* make compare (claims/compare.c): how a claim's verdict in this run stands
 * against the reference run's. */
typedef enum {
  CB_COMPARE_SAME = 0,     /* the same verdict */
  CB_COMPARE_WITHIN,       /* another verdict, explained by overlapping spreads of a deciding timing */
  CB_COMPARE_DIFFERS,      /* another verdict that no deciding timing's spread explains */
  CB_COMPARE_NOT_COMPARED, /* either run lacks the claim, or either verdict is undecided */
  CB_COMPARE_NEW,          /* this run decides a claim whose experiment the reference run has no CSV of (a claim
                              newer than the reference): "new claim, no reference", never a failure */
} cb_compare_kind;
cb_compare_kind cb_report_compare_claim(const cb_claim_result *ours, const cb_claim_result *ref);
/* Decides every claim in both directories and writes the comparison table to
 * f. Returns 1 when some verdict differs outside the spreads, 0 otherwise, 2
 * on an error. */
int cb_report_compare(FILE *f, const char *ours_dir, const char *ref_dir);
/* One line counting the claims by verdict, the undecided ones apart and named. */
void cb_report_counts(FILE *f, const cb_claim_result *res);
/* report --stability (claims/stability.c): decides every claim again on copies of the results CSV files whose
 * timing medians sit at one end of their recorded spread (low, high, and alternating row by row), and
 * writes a table of the verdicts to f. 0 when every verdict held or changed only to or from undecided,
 * 3 when one changed between two decided verdicts, 2 on an I/O error. */
int cb_report_stability(FILE *f, const char *results, const cb_claim_result *base);

#endif
