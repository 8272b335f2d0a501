/* CCD (lib/core/geometry/ccd*.c): every registered method over the project's exact query set tests/ccd/
 * (written by tests/ccd/gen.c, truth and a certified bracket toi_lo <= t* <= toi_hi in exact rational
 * arithmetic): no false negative, no toi later than toi_hi; the false-positive rate is printed. Then
 * minimum-separation closed forms, and bad input. docs/geometry-ccd.md. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gmp.h>

#include <clothbench/ccd.h>
#include <clothbench/status.h>

#include "ccd_csv.h"

/* the truth file's toi_hi of each query (exact rational), NULL entries for misses */
static mpq_t *read_hi(const char *path, int n) {
  FILE *f = fopen(path, "r");
  cr_assert(f, "cannot open %s", path);
  mpq_t *hi = calloc((size_t)n, sizeof *hi);
  char line[4096];
  cr_assert(fgets(line, sizeof line, f)); /* header */
  int i = 0;
  while (fgets(line, sizeof line, f)) {
    cr_assert(i < n, "%s: more rows than queries", path);
    char *fld[7];
    int k = 0;
    for (char *s = line; k < 7; k++) { /* split at commas, empty fields kept */
      fld[k] = s;
      char *end = s + strcspn(s, ",\n");
      int last = *end != ',';
      *end = '\0';
      if (last) {
        k++;
        break;
      }
      s = end + 1;
    }
    cr_assert(k == 7, "%s:%d: %d fields", path, i + 2, k);
    mpq_init(hi[i]);
    if (atoi(fld[2])) {
      mpz_set_str(mpq_numref(hi[i]), fld[5], 10);
      mpz_set_str(mpq_denref(hi[i]), fld[6], 10);
      mpq_canonicalize(hi[i]);
    } else mpq_set_si(hi[i], -1, 1); /* a miss */
    i++;
  }
  fclose(f);
  cr_assert(i == n, "%s: %d rows for %d queries", path, i, n);
  return hi;
}

static void run_set(const char *kind_s, int kind) {
  char qpath[64], tpath[64];
  snprintf(qpath, sizeof qpath, "tests/ccd/%s.csv", kind_s);
  snprintf(tpath, sizeof tpath, "tests/ccd/%s_truth.csv", kind_s);
  cb_ccd_file in;
  cr_assert(cb_ccd_file_load(qpath, &in) == CB_OK, "%s", cb_error_message());
  cr_assert(in.n > 500 && in.inexact == 0);
  mpq_t *hi = read_hi(tpath, in.n);
  cb_ccd_params p = cb_ccd_params_default();
  p.max_boxes = 20000; /* a smaller budget: still conservative (an overrun is a hit at an early time) */
  mpq_t toi;
  mpq_init(toi);
  for (int m = 0; cb_ccd_types[m]; m++) {
    long fp = 0, neg = 0, over = 0;
    for (int i = 0; i < in.n; i++) {
      cb_ccd_result r;
      int s = cb_ccd_run(cb_ccd_types[m], kind, &in.q[i], &p, &r);
      cr_assert(s == CB_OK || s == CB_NOT_CONVERGED, "%s %s query %d: status %d", cb_ccd_types[m]->name, kind_s, i, s);
      over += s == CB_NOT_CONVERGED;
      cr_assert(r.hit == 0 || (r.toi >= 0 && r.toi <= 1), "toi %g outside [0, 1]", r.toi);
      if (in.truth[i]) {
        cr_assert(r.hit, "%s %s query %d: false negative", cb_ccd_types[m]->name, kind_s, i);
        mpq_set_d(toi, r.toi);
        cr_assert(mpq_cmp(toi, hi[i]) <= 0, "%s %s query %d: toi %.17g later than the certified bound %.17g",
                  cb_ccd_types[m]->name, kind_s, i, r.toi, mpq_get_d(hi[i]));
      } else {
        neg++;
        fp += r.hit;
      }
    }
    printf("ccd %s %s: %d queries, 0 false negatives, 0 late; false positives %ld of %ld negatives (%.4g); %ld over "
           "a budget of %ld boxes\n",
           cb_ccd_types[m]->name, kind_s, in.n, fp, neg, (double)fp / neg, over, p.max_boxes);
  }
  mpq_clear(toi);
  for (int i = 0; i < in.n; i++) mpq_clear(hi[i]);
  free(hi);
  cb_ccd_file_free(&in);
}

Test(ccd, exact_set_vf_no_false_negative_no_late_toi, .timeout = 600) { run_set("vf", CB_CCD_VF); }
Test(ccd, exact_set_ee_no_false_negative_no_late_toi, .timeout = 600) { run_set("ee", CB_CCD_EE); }

/* A point falling face-on at speed s onto a static triangle from height h: the distance is h - s t, so with
 * minimum separation eta the first contact is (h - eta) / s. */
Test(ccd, minimum_separation_face_on_closed_form) {
  const double etas[] = {0.0, 0.1, 0.25, 0.5};
  for (int m = 0; cb_ccd_types[m]; m++)
    for (size_t e = 0; e < sizeof etas / sizeof *etas; e++) {
      double x0[12] = {0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
      double x1[12] = {0.25, 0.25, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
      cb_ccd_params p = cb_ccd_params_default();
      p.eta = etas[e];
      cb_ccd_result r;
      int s = cb_ccd_vf(cb_ccd_types[m], x0, x1, &p, &r);
      cr_assert(s == CB_OK, "status %d", s);
      double t = (1 - etas[e]) / 2; /* h = 1, s = 2 */
      cr_assert(r.hit && r.toi <= t, "eta %g: hit %d toi %.17g, first contact %.17g", etas[e], r.hit, r.toi, t);
      cr_assert(r.toi >= t - 1e-5, "eta %g: toi %.17g far earlier than %.17g", etas[e], r.toi, t);
      /* stopping at height 2 eta + 0.2 (a clear miss, also in the infinity norm) */
      x1[2] = 2 * etas[e] + 0.2;
      s = cb_ccd_vf(cb_ccd_types[m], x0, x1, &p, &r);
      cr_assert(s == CB_OK && !r.hit, "eta %g: a miss by 0.2 reported as a hit at %g", etas[e], r.toi);
    }
}

/* Two crossing edges, one sliding down onto the other: distance 1 - t, so contact at eta is t = 1 - eta. */
Test(ccd, minimum_separation_edges_closed_form) {
  for (int m = 0; cb_ccd_types[m]; m++)
    for (double eta = 0; eta < 0.9; eta += 0.3) {
      double x0[12] = {-1, 0, 0, 1, 0, 0, 0, -1, 1, 0, 1, 1};
      double x1[12] = {-1, 0, 0, 1, 0, 0, 0, -1, 0, 0, 1, 0};
      cb_ccd_params p = cb_ccd_params_default();
      p.eta = eta;
      cb_ccd_result r;
      cr_assert(cb_ccd_ee(cb_ccd_types[m], x0, x1, &p, &r) == CB_OK);
      cr_assert(r.hit && r.toi <= 1 - eta && r.toi >= 1 - eta - 1e-5, "eta %g: toi %.17g", eta, r.toi);
    }
}

/* the budget: a query stopped early still reports a conservative hit */
Test(ccd, budget_overrun_is_a_conservative_hit) {
  double x0[12] = {0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0}, x1[12] = {0.25, 0.25, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  cb_ccd_params p = cb_ccd_params_default();
  p.max_boxes = 3;
  cb_ccd_result r;
  cr_assert(cb_ccd_vf(NULL, x0, x1, &p, &r) == CB_NOT_CONVERGED);
  cr_assert(r.hit && r.toi <= 0.5);
}

Test(ccd, nan_inf_and_bad_parameters_are_errors_not_misses) {
  double x0[12] = {0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0}, x1[12] = {0.25, 0.25, 2, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  cb_ccd_params p = cb_ccd_params_default();
  cb_ccd_result r;
  cr_assert(cb_ccd_vf(NULL, x0, x1, &p, &r) == CB_OK && !r.hit);
  double bad[] = {NAN, INFINITY, -INFINITY, 0x1p600};
  for (size_t i = 0; i < 4; i++) {
    x1[4] = bad[i];
    cr_assert(cb_ccd_vf(NULL, x0, x1, &p, &r) == CB_EINVAL, "value %g accepted", bad[i]);
    cr_assert(r.hit == 1 && r.toi == 0, "an error must not read as 'no hit'");
    cr_assert(strstr(cb_error_message(), "point 5 coordinate 1"), "%s", cb_error_message());
    cr_assert(cb_ccd_ee(NULL, x0, x1, &p, &r) == CB_EINVAL);
  }
  x1[4] = 0;
  p.eta = -1;
  cr_assert(cb_ccd_vf(NULL, x0, x1, &p, &r) == CB_EINVAL);
  p.eta = NAN;
  cr_assert(cb_ccd_vf(NULL, x0, x1, &p, &r) == CB_EINVAL);
  p = cb_ccd_params_default();
  p.tol = 0;
  cr_assert(cb_ccd_vf(NULL, x0, x1, &p, &r) == CB_EINVAL);
  cr_assert(cb_ccd_type_find("no_such_method") == NULL && cb_ccd_type_find(NULL) == cb_ccd_types[0]);
}

/* the reader: line:column messages, and rationals that are no double become intervals around them */
static int read_text(const char *text, cb_ccd_file *out) {
  FILE *f = fmemopen((void *)text, strlen(text), "r");
  cr_assert(f);
  int rc = cb_ccd_file_read(f, "x.csv", out);
  fclose(f);
  return rc;
}

static const char *query8(const char *row1) {
  static char buf[1024];
  snprintf(buf, sizeof buf, "%s\n%s", row1,
           "0,1,0,1,0,1,0\n1,1,0,1,0,1,0\n0,1,1,1,0,1,0\n1,4,1,4,1,1,0\n0,1,0,1,0,1,0\n1,1,0,1,0,1,0\n0,1,1,1,0,1,0\n");
  return buf;
}

Test(ccd, reader_reports_line_and_column) {
  cb_ccd_file in;
  cr_assert(read_text(query8("1,4,1,4,1,1,0"), &in) == CB_OK && in.n == 1 && in.inexact == 0);
  cr_assert(in.q[0].lo[0][0] == 0.25 && in.q[0].hi[4][2] == 1.0);
  cb_ccd_file_free(&in);
  /* 1/3 is no double: the interval of its two neighbours */
  cr_assert(read_text(query8("1,3,1,4,1,1,0"), &in) == CB_OK && in.inexact == 1);
  cr_assert(in.q[0].lo[0][0] < 1.0 / 3 || in.q[0].hi[0][0] > 1.0 / 3);
  cr_assert(in.q[0].lo[0][0] <= 1.0 / 3 && 1.0 / 3 <= in.q[0].hi[0][0] && in.q[0].lo[0][0] < in.q[0].hi[0][0]);
  cb_ccd_file_free(&in);
  /* numerators beyond 64 bits */
  cr_assert(read_text(query8("100000000000000000000000000000,400000000000000000000000000000,1,4,1,1,0"), &in) == CB_OK);
  cr_assert(in.q[0].lo[0][0] == 0.25 && in.inexact == 0);
  cb_ccd_file_free(&in);
  static const struct {
    const char *row, *where;
  } bad[] = {{"nan,1,1,4,1,1,0", "x.csv:1:1:"}, {"1,4,inf,1,1,1,0", "x.csv:1:5:"}, {"1,0,1,4,1,1,0", "x.csv:1:1: zero"},
             {"1,4,1,4,1,1", "x.csv:1:"},       {"1,4,1,4,1,1,2", "x.csv:1:13:"},  {"1,4,1,4,1,1,0,0", "x.csv:1:15:"},
             {"1.5,4,1,4,1,1,0", "x.csv:1:1:"}, {"1,4,1,4,1,1,1", "x.csv:2:"}};
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    int rc = read_text(query8(bad[i].row), &in);
    cr_assert(rc == CB_EINVAL, "'%s' accepted", bad[i].row);
    cr_assert(strstr(cb_error_message(), bad[i].where), "'%s': %s", bad[i].row, cb_error_message());
  }
  /* a file ending inside a query */
  cr_assert(read_text("1,4,1,4,1,1,0\n", &in) == CB_EINVAL && strstr(cb_error_message(), "ends inside a query"));
}
