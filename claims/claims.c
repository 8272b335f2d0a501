#include "claims.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <clothbench/status.h>

/* The table, from the one list of claims (claims_list.h). */
#define CB_CLAIM_ROW(check_, id_, experiment_, text_, decided_by_, figure_) \
  {.id = id_, .experiment = experiment_, .text = text_, .decided_by = decided_by_, .figure = figure_, .check = check_},
const cb_claim cb_claims[] = {CB_CLAIMS(CB_CLAIM_ROW)};
const int cb_nclaims = (int)(sizeof cb_claims / sizeof cb_claims[0]);

void cb_claim_figures(FILE *f, const cb_claim *c, const char *dir, const char *sep) {
  if (!c->figure || !c->figure[0]) {
    if (!dir) fputs("-", f);
    return;
  }
  for (const char *p = c->figure; *p;) {
    size_t n = strcspn(p, " ");
    if (n > 0) {
      if (dir) fprintf(f, "%s![%s](%s/%.*s)", p == c->figure ? "" : sep, c->id, dir, (int)n, p);
      else fprintf(f, "%s`%.*s`", p == c->figure ? "" : sep, (int)n, p);
    }
    p += n;
    while (*p == ' ') p++;
  }
}

const char *cb_verdict_name(cb_verdict v) {
  switch (v) {
  case CB_REPRODUCED: return "reproduced";
  case CB_PARTLY: return "partly reproduced";
  case CB_NOT_REPRODUCED: return "not reproduced";
  case CB_UNDECIDED: return "undecided (within the spread)";
  default: return "not run";
  }
}

static void vappend(char *buf, size_t cap, const char *fmt, va_list ap) {
  size_t n = strlen(buf);
  if (n + 1 < cap) vsnprintf(buf + n, cap - n, fmt, ap);
}

void cb_claim_numbers(cb_claim_result *r, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vappend(r->numbers, sizeof r->numbers, fmt, ap);
  va_end(ap);
}

void cb_claim_reason(cb_claim_result *r, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vappend(r->reason, sizeof r->reason, fmt, ap);
  va_end(ap);
}

/* The result being decided (claims.h): cb_claim_timing_side records its
 * deciding numbers there (the report decides one claim at a time). */
cb_claim_result *cb_claim_deciding_now;

void cb_claim_decide(const cb_claim *c, const char *results_dir, cb_claim_result *out) {
  memset(out, 0, sizeof *out);
  out->verdict = CB_NOT_RUN;
  if (!c->experiment || !c->check) {
    cb_claim_reason(out, "No experiment decides this claim yet.");
    return;
  }
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.csv", results_dir, c->experiment);
  cb_table t;
  int st = cb_table_read(path, &t);
  if (st == CB_EIO) {
    cb_claim_reason(out, "%s is missing: run `make experiments` (or build/%s).", path, c->experiment);
    return;
  }
  if (st) {
    cb_claim_reason(out, "%s could not be read: %s", path, cb_error_message());
    return;
  }
  cb_claim_deciding_now = out;
  c->check(&t, results_dir, out);
  cb_claim_deciding_now = NULL;
  cb_table_free(&t);
}

void cb_fit_line(const double *x, const double *y, int n, double *slope, double *intercept) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int i = 0; i < n; i++) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  double d = n * sxx - sx * sx;
  *slope = d != 0 ? (n * sxy - sx * sy) / d : 0;
  *intercept = n > 0 ? (sy - *slope * sx) / n : 0;
}

int cb_claim_side_table(const char *dir, const char *experiment, const char *table, cb_table *t, cb_claim_result *out) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s_%s.csv", dir, experiment, table);
  int st = cb_table_read(path, t);
  if (st) cb_claim_reason(out, "%s is missing or unreadable: run build/%s.", path, experiment);
  return st;
}

int cb_claim_columns(const cb_table *t, const char *const *names, int *idx, int n, const char *file,
                     cb_claim_result *out) {
  for (int i = 0; i < n; i++)
    if ((idx[i] = cb_table_col(t, names[i])) < 0) {
      cb_claim_reason(out, "%s lacks the column %s.", file, names[i]);
      return -1;
    }
  return 0;
}
