#include "stats.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

double cb_median(double *v, int n) {
  if (n <= 0) return NAN;
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void cb_timing_add(cb_timing *t, double ms) {
  if (t->n < CB_TIMING_MAX) t->ms[t->n++] = ms;
}

double cb_timing_median(const cb_timing *t) {
  double v[CB_TIMING_MAX];
  memcpy(v, t->ms, sizeof v);
  return cb_median(v, t->n);
}

double cb_timing_min(const cb_timing *t) {
  double m = NAN;
  for (int i = 0; i < t->n; i++)
    if (i == 0 || t->ms[i] < m) m = t->ms[i];
  return m;
}

double cb_timing_max(const cb_timing *t) {
  double m = NAN;
  for (int i = 0; i < t->n; i++)
    if (i == 0 || t->ms[i] > m) m = t->ms[i];
  return m;
}

int cb_timing_median_over(const cb_timing *v, int n, cb_timing *out) {
  out->n = 0;
  if (n <= 0) return -1;
  int reps = v[0].n;
  for (int k = 1; k < n; k++)
    if (v[k].n < reps) reps = v[k].n;
  if (reps <= 0) return -1;
  double *buf = malloc((size_t)n * sizeof *buf);
  if (!buf) return -1;
  for (int i = 0; i < reps; i++) {
    for (int k = 0; k < n; k++) buf[k] = v[k].ms[i];
    cb_timing_add(out, cb_median(buf, n));
  }
  free(buf);
  return 0;
}

int cb_timing_more(int quick, int done, double spent_ms) {
  if (done >= CB_TIMING_MAX) return 0;
  if (done < 2) return 1;
  if (quick) return done < 3;
  if (done < 3) return spent_ms / done <= CB_TIMING_LONG_MS; /* 2 rounds when one takes > 5 s */
  return done < 5 && spent_ms < CB_TIMING_BUDGET_MS;         /* 5 rounds while they are cheap */
}

int cb_timing_warm(double ms) { return ms < CB_TIMING_WARM_MS; }

int cb_timing_parse(const char *s, cb_timing *t) {
  t->n = 0;
  if (!s) return 0;
  while (*s && t->n < CB_TIMING_MAX) {
    char *end;
    double v = strtod(s, &end);
    if (end == s || (*end && *end != ';')) {
      t->n = 0;
      return 0;
    }
    t->ms[t->n++] = v;
    s = *end ? end + 1 : end;
  }
  if (*s) t->n = 0; /* more than CB_TIMING_MAX: not ours */
  return t->n;
}
