/* The claims report: one entry per claim of CLAIMS.md, each decided by a
 * checker that reads its experiment's CSV. Verdicts come from the data only.
 *
 * To add a claim: write claims/check_<experiment>.c with a function of type
 * cb_claim_check, and add a row to the table in claims/claims.c. */
#ifndef CB_CLAIMS_H
#define CB_CLAIMS_H

#include <stddef.h>
#include <stdio.h>

#include "table.h"

typedef enum { CB_NOT_RUN = 0, CB_REPRODUCED, CB_PARTLY, CB_NOT_REPRODUCED } cb_verdict;

typedef struct cb_claim_result {
  cb_verdict verdict;
  char reason[2048];   /* one or two sentences: why this verdict */
  char numbers[16384]; /* Markdown: the deciding numbers (a table or a list) */
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
int cb_claim_columns(const cb_table *t, const char *const *names, int *idx, int n, const char *file, cb_claim_result *out);

/* Least-squares slope and intercept of y on x over n points. */
void cb_fit_line(const double *x, const double *y, int n, double *slope, double *intercept);

#endif
