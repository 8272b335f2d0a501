/* Timing-based numbers with their spread over repeats (see claims.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "claims.h"

/* col with "_min", "_max" or "_each" inserted before its "_ms" (the first
 * "_ms" that ends the name or is followed by '_'); "" if col has none. */
void cb_claim_spread_column(const char *col, const char *what, char *buf, size_t n) {
  buf[0] = 0;
  for (const char *p = strstr(col, "_ms"); p; p = strstr(p + 1, "_ms"))
    if (p[3] == 0 || p[3] == '_') {
      snprintf(buf, n, "%.*s_%s%s", (int)(p - col), col, what, p);
      return;
    }
}

static int has(const cb_claim_timing *t) { return isfinite(t->min) && isfinite(t->max); }
static int varies(const cb_claim_timing *t) { return t->n > 0 || t->bounds; }

static void from_each(cb_claim_timing *t) {
  t->n = t->each.n;
  t->min = cb_timing_min(&t->each);
  t->max = cb_timing_max(&t->each);
}

cb_claim_timing cb_claim_timing_value(double v) {
  cb_claim_timing t;
  memset(&t, 0, sizeof t);
  t.med = t.min = t.max = v;
  return t;
}

cb_claim_timing cb_claim_timing_at(const cb_table *t, int r, const char *col) {
  cb_claim_timing x;
  memset(&x, 0, sizeof x);
  x.med = cb_table_num(t, r, cb_table_col(t, col));
  x.min = x.max = NAN;
  char name[128];
  cb_claim_spread_column(col, "min", name, sizeof name);
  int cmin = name[0] ? cb_table_col(t, name) : -1;
  cb_claim_spread_column(col, "max", name, sizeof name);
  int cmax = name[0] ? cb_table_col(t, name) : -1;
  cb_claim_spread_column(col, "each", name, sizeof name);
  int ceach = name[0] ? cb_table_col(t, name) : -1, crep = cb_table_col(t, "wall_repeats");
  if (ceach >= 0 && cb_timing_parse(cb_table_str(t, r, ceach), &x.each) > 0) from_each(&x);
  if (cmin >= 0 && cmax >= 0) {
    x.min = cb_table_num(t, r, cmin);
    x.max = cb_table_num(t, r, cmax);
    if (x.n == 0 && crep >= 0) {
      int k = cb_table_int(t, r, crep); /* -1 for nan, inf or past 1e9: no count */
      x.n = k > 0 ? k : 0;
    }
    if (x.n == 0 && has(&x)) x.n = 1; /* a spread without a count: at least one repeat */
  }
  return x;
}

/* op 0: a / b, 1: a - b */
static double apply(int op, double a, double b) { return op ? a - b : a / b; }

static cb_claim_timing combine(const cb_claim_timing *a, const cb_claim_timing *b, int op) {
  cb_claim_timing r;
  memset(&r, 0, sizeof r);
  r.med = apply(op, a->med, b->med);
  if (a->each.n > 0 && a->each.n == b->each.n) { /* paired repeats */
    for (int i = 0; i < a->each.n; i++) cb_timing_add(&r.each, apply(op, a->each.ms[i], b->each.ms[i]));
    from_each(&r);
    r.bounds = a->bounds || b->bounds;
    r.paired = 1;
  } else if (varies(a) && varies(b)) { /* conservative: the extremes of each operand */
    r.min = op ? a->min - b->max : a->min / b->max;
    r.max = op ? a->max - b->min : a->max / b->min;
    r.n = a->n < b->n ? a->n : b->n;
    r.bounds = 1;
  } else if (varies(a) || varies(b)) { /* one operand is a constant: exact */
    const cb_claim_timing *v = varies(a) ? a : b;
    double lo = apply(op, varies(a) ? a->min : a->med, varies(a) ? b->med : b->max);
    double hi = apply(op, varies(a) ? a->max : a->med, varies(a) ? b->med : b->min);
    r.min = fmin(lo, hi);
    r.max = fmax(lo, hi);
    r.n = v->n;
    r.bounds = v->bounds;
    r.paired = v->paired;
    for (int i = 0; i < v->each.n; i++)
      cb_timing_add(&r.each, varies(a) ? apply(op, a->each.ms[i], b->med) : apply(op, a->med, b->each.ms[i]));
  } else { /* constants, or no spread recorded */
    r.min = apply(op, a->min, b->max);
    r.max = apply(op, a->max, b->min);
  }
  return r;
}

cb_claim_timing cb_claim_timing_ratio(const cb_claim_timing *a, const cb_claim_timing *b) { return combine(a, b, 0); }
cb_claim_timing cb_claim_timing_diff(const cb_claim_timing *a, const cb_claim_timing *b) { return combine(a, b, 1); }

cb_claim_timing cb_claim_timing_scale(const cb_claim_timing *a, double s) {
  cb_claim_timing r = *a;
  r.med *= s;
  r.min *= s;
  r.max *= s;
  for (int i = 0; i < r.each.n; i++) r.each.ms[i] *= s;
  return r;
}

cb_claim_timing cb_claim_timing_median(const cb_claim_timing *v, int n) {
  cb_claim_timing r;
  memset(&r, 0, sizeof r);
  r.med = r.min = r.max = NAN;
  if (n <= 0) return r;
  static double buf[256];
  int m = n < 256 ? n : 256, reps = v[0].each.n, nmin = 0;
  for (int k = 0; k < m; k++) {
    buf[k] = v[k].med;
    if (v[k].each.n < reps) reps = v[k].each.n; /* the repeats every v has */
    r.bounds |= v[k].bounds;
    r.paired |= v[k].paired;
    if (v[k].n > 0 && (nmin == 0 || v[k].n < nmin)) nmin = v[k].n;
  }
  r.med = cb_median(buf, m);
  if (reps > 0) { /* per repeat i (of those every v has), the median over v of repeat i */
    cb_timing each[256];
    for (int k = 0; k < m; k++) each[k] = v[k].each;
    if (cb_timing_median_over(each, m, &r.each) == 0) {
      from_each(&r);
      /* the median of the same series, so that it lies inside its spread (the median over v
       * of v's medians need not: with 3 repeats of 5 frames it fell outside in a full run) */
      r.med = cb_timing_median(&r.each);
      return r;
    }
  }
  int bad = 0, vary = 0;
  for (int k = 0; k < m; k++) {
    bad |= !has(&v[k]);
    vary |= varies(&v[k]);
  }
  if (bad) return r;
  for (int k = 0; k < m; k++) buf[k] = v[k].min;
  r.min = cb_median(buf, m);
  for (int k = 0; k < m; k++) buf[k] = v[k].max;
  r.max = cb_median(buf, m);
  r.n = nmin;
  r.bounds |= vary;
  return r;
}

int cb_claim_verdict_median_only = 0;

int cb_claim_timing_has_spread(const cb_claim_timing *t) { return has(t) && varies(t); }

/* t against thr, as a deciding number of the claim being decided */
static void record_deciding(const cb_claim_timing *t, double thr, int side) {
  cb_claim_result *r = cb_claim_deciding_now;
  if (!r || r->ndeciding >= CB_CLAIM_DECIDING_MAX) return;
  r->deciding[r->ndeciding++] = (cb_claim_deciding){.med = t->med,
                                                    .min = cb_claim_timing_has_spread(t) ? t->min : NAN,
                                                    .max = cb_claim_timing_has_spread(t) ? t->max : NAN,
                                                    .thr = thr,
                                                    .side = side};
}

int cb_claim_timing_side(const cb_claim_timing *t, double thr) {
  double lo = t->med, hi = t->med;
  if (!cb_claim_verdict_median_only && cb_claim_timing_has_spread(t)) {
    lo = fmin(t->min, t->med); /* the median lies inside its spread; guard bounds that do not hold it */
    hi = fmax(t->max, t->med);
  }
  int side = lo > thr ? 1 : hi < thr ? -1 : 0;
  record_deciding(t, thr, side);
  return side;
}

static size_t put_spread(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit) {
  size_t u = 0;
  u += (size_t)snprintf(buf, n, fmt, t->med);
  if (u < n) u += (size_t)snprintf(buf + u, n - u, "%s", unit);
  if (!cb_claim_timing_has_spread(t)) return u;
  if (u < n) u += (size_t)snprintf(buf + u, n - u, " (");
  if (u < n) u += (size_t)snprintf(buf + u, n - u, fmt, t->min);
  if (u < n) u += (size_t)snprintf(buf + u, n - u, "-");
  if (u < n) u += (size_t)snprintf(buf + u, n - u, fmt, t->max);
  if (u < n) u += (size_t)snprintf(buf + u, n - u, "%s", unit);
  return u;
}

const char *cb_claim_spread(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit) {
  size_t u = put_spread(buf, n, fmt, t, unit);
  if (cb_claim_timing_has_spread(t) && u < n) snprintf(buf + u, n - u, ")");
  return buf;
}

const char *cb_claim_spread_long(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit) {
  size_t u = put_spread(buf, n, fmt, t, unit);
  if (!cb_claim_timing_has_spread(t) || u >= n) return buf;
  if (t->bounds) snprintf(buf + u, n - u, ", bounds from the min and max of %d repeats)", t->n);
  else snprintf(buf + u, n - u, " over %d%s repeats)", t->n, t->paired ? " paired" : "");
  return buf;
}

void cb_claim_repeats_add(cb_claim_repeats *r, const cb_claim_timing *t) {
  if (!cb_claim_timing_has_spread(t) || t->n <= 0) return;
  if (r->lo == 0 || t->n < r->lo) r->lo = t->n;
  if (t->n > r->hi) r->hi = t->n;
}

const char *cb_claim_repeats_text(char *buf, size_t n, const cb_claim_repeats *r) {
  if (r->lo <= 0) snprintf(buf, n, "%s", "");
  else if (r->lo == r->hi) snprintf(buf, n, "%d repeat%s", r->lo, r->lo == 1 ? "" : "s");
  else snprintf(buf, n, "%d-%d repeats", r->lo, r->hi);
  return buf;
}

/* ---- undecided verdicts: range, repeats to decide, margin (claims.h) ---------------------------- */


void cb_claim_timing_range(const cb_claim_timing *t, double *lo, double *hi) {
  *lo = *hi = t->med;
  if (cb_claim_verdict_median_only || !cb_claim_timing_has_spread(t)) return;
  *lo = fmin(t->min, t->med); /* the median lies inside its spread; guard bounds that do not hold it */
  *hi = fmax(t->max, t->med);
}

int cb_claim_timing_side_ge(const cb_claim_timing *t, double thr, int ge) {
  double lo, hi;
  cb_claim_timing_range(t, &lo, &hi);
  if (lo == hi) return (ge ? t->med >= thr : t->med > thr) ? 1 : -1; /* no spread: the claim's own comparison */
  return cb_claim_timing_side(t, thr);
}

int cb_claim_timing_repeats_to_decide(const cb_claim_timing *t, double thr) {
  double lo, hi;
  cb_claim_timing_range(t, &lo, &hi);
  if (lo > thr || hi < thr) return 0;
  double d = fabs(t->med - thr), h = t->med >= thr ? t->med - lo : hi - t->med;
  if (!(d > 0) || !isfinite(h)) return -1; /* the median on the threshold: no number of repeats moves it off */
  int n = t->n > 0 ? t->n : 1;
  double need = n * (h / d) * (h / d); /* half-width h sqrt(n / N) < d */
  return need > 1e6 ? 1000000 : (int)floor(need) + 1;
}

const char *cb_claim_undecided_text(char *buf, size_t n, const char *what, const char *fmt, const cb_claim_timing *t,
                                    const char *unit, double thr) {
  char sp[160], a[48], b[48], c[48];
  double lo, hi;
  cb_claim_timing_range(t, &lo, &hi);
  int above = t->med >= thr, reps = cb_claim_timing_repeats_to_decide(t, thr);
  snprintf(a, sizeof a, fmt, thr);
  snprintf(b, sizeof b, fmt, fabs(t->med - thr));
  snprintf(c, sizeof c, fmt, above ? lo : hi);
  size_t u = (size_t)snprintf(buf, n, "%s %s straddles %s%s: margin %s%s%s (median %s", what,
                              cb_claim_spread_long(sp, sizeof sp, fmt, t, unit), a, unit, above ? "+" : "-", b, unit,
                              above ? "above" : "below");
  if (u < n && thr != 0) u += (size_t)snprintf(buf + u, n - u, " by %.0f%%", 100 * fabs(t->med / thr - 1));
  if (u < n) u += (size_t)snprintf(buf + u, n - u, "), while the spread reaches %s%s on the other side; ", c, unit);
  if (u >= n) return buf;
  if (reps < 0) snprintf(buf + u, n - u, "no number of repeats decides it (the median is on the threshold)");
  else
    snprintf(buf + u, n - u,
             "about %d repeats would decide it (the spread's half-width on the threshold's side taken to shrink as "
             "1/sqrt(repeats))",
             reps);
  return buf;
}

const char *cb_claim_margin_text(char *buf, size_t n, const char *fmt, const cb_claim_timing *t, const char *unit,
                                 double thr) {
  double lo, hi;
  cb_claim_timing_range(t, &lo, &hi);
  char a[48], b[48], c[48];
  int side = lo > thr ? 1 : hi < thr ? -1 : 0;
  if (side == 0) return cb_claim_undecided_text(buf, n, "the ratio", fmt, t, unit, thr);
  double near = side > 0 ? lo : hi;
  snprintf(a, sizeof a, fmt, thr);
  snprintf(b, sizeof b, fmt, fabs(near - thr));
  snprintf(c, sizeof c, fmt, near);
  size_t u = (size_t)snprintf(buf, n, "margin %s%s%s: the %s %s%s lies %s %s%s", side > 0 ? "+" : "-", b, unit,
                              lo == hi   ? "value"
                              : side > 0 ? "spread's low end"
                                         : "spread's high end",
                              c, unit, side > 0 ? "above" : "below", a, unit);
  if (u < n && thr != 0) snprintf(buf + u, n - u, " (by %.0f%%)", 100 * fabs(near / thr - 1));
  return buf;
}

cb_verdict cb_claim_verdict_either(cb_verdict a, cb_verdict b) { return a == b ? a : CB_UNDECIDED; }
