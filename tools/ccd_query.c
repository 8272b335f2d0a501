/* ccd-query: runs conservative CCD over a file of queries (docs/geometry-ccd.md).
 *
 *   ccd-query FILE.csv --kind vf|ee [--eta E] [--tol T] [--max-boxes N] [--method NAME] [--stats] [-o OUT]
 *
 * FILE.csv is in the format of Wang et al. 2021's CCD benchmark (lib/io/ccd_csv.h). One output line per
 * query: `hit,toi` (hit 0 or 1; toi with %.17g, empty when there is no hit). --stats adds a summary on
 * stderr: queries, hits, the file's truth column against them (false negatives, false positives and their
 * rate), the budget overruns, and queries per second (the CCD calls only, wall clock).
 * Exit status: 0 ok; 1 malformed input or a query the CCD refused (message with file:line:column or the
 * query's number); 2 usage; 3 a file could not be read or written; 4 a false negative against the file's
 * truth column (with --stats). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/ccd.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

#include "ccd_csv.h"
#include "outfile.h"

static void usage(FILE *f) {
  fprintf(f, "usage: ccd-query FILE.csv --kind vf|ee [--eta E] [--tol T] [--max-boxes N] [--method NAME]\n"
             "                 [--stats] [-o OUT]\n"
             "Conservative continuous collision detection over a file of queries in the format of\n"
             "Wang et al. 2021's CCD benchmark: 8 rows a query, x_num,x_den,y_num,y_den,z_num,z_den,truth;\n"
             "rows 1-4 at t = 0, rows 5-8 at t = 1; vf: the point then the triangle, ee: edge then edge.\n"
             "Writes one line per query, `hit,toi` (toi empty when no hit), to OUT (default stdout).\n"
             "  --kind vf|ee     query kind (required)\n"
             "  --eta E          minimum separation, >= 0 (default 0)\n"
             "  --tol T          relative distance tolerance, > 0 (default 1e-6)\n"
             "  --max-boxes N    box budget per query (default 1000000)\n"
             "  --method NAME    CCD method (default: the first registered:");
  for (int i = 0; cb_ccd_types[i]; i++) fprintf(f, " %s", cb_ccd_types[i]->name);
  fprintf(f, ")\n"
             "  --stats          summary on stderr: hits, false negatives/positives against the truth\n"
             "                   column, queries per second\n"
             "Exit: 0 ok, 1 bad input, 2 usage, 3 i/o error, 4 a false negative (--stats).\n");
}

static int number(const char *opt, const char *s, double *x) {
  char *end;
  errno = 0;
  *x = strtod(s, &end);
  if (errno || end == s || *end) {
    fprintf(stderr, "ccd-query: %s: '%s' is not a number\n", opt, s);
    return -1;
  }
  return 0;
}

int main(int argc, char **argv) {
  const char *file = NULL, *kind_s = NULL, *method = NULL, *out_path = "-";
  cb_ccd_params p = cb_ccd_params_default();
  int stats = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    int has = i + 1 < argc;
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout);
      return 0;
    } else if (!strcmp(a, "--stats")) stats = 1;
    else if (!strcmp(a, "--kind") && has) kind_s = argv[++i];
    else if (!strcmp(a, "--method") && has) method = argv[++i];
    else if (!strcmp(a, "-o") && has) out_path = argv[++i];
    else if (!strcmp(a, "--eta") && has) {
      if (number(a, argv[++i], &p.eta)) return 2;
    } else if (!strcmp(a, "--tol") && has) {
      if (number(a, argv[++i], &p.tol)) return 2;
    } else if (!strcmp(a, "--max-boxes") && has) {
      double x;
      if (number(a, argv[++i], &x)) return 2;
      if (!(x >= 1 && x <= 1e15 && x == (long)x)) {
        fprintf(stderr, "ccd-query: --max-boxes: '%s' is not an integer in [1, 1e15]\n", argv[i]);
        return 2;
      }
      p.max_boxes = (long)x;
    } else if (a[0] == '-' && a[1]) {
      fprintf(stderr, "ccd-query: unknown option or missing value: %s\n", a);
      usage(stderr);
      return 2;
    } else if (!file) file = a;
    else {
      fprintf(stderr, "ccd-query: one input file only (%s, then %s)\n", file, a);
      return 2;
    }
  }
  if (!file || !kind_s) {
    fprintf(stderr, "ccd-query: %s\n", !file ? "no input file" : "--kind vf|ee is required");
    usage(stderr);
    return 2;
  }
  int kind = !strcmp(kind_s, "vf") ? CB_CCD_VF : !strcmp(kind_s, "ee") ? CB_CCD_EE : -1;
  if (kind < 0) {
    fprintf(stderr, "ccd-query: --kind '%s': expected vf or ee\n", kind_s);
    return 2;
  }
  const cb_ccd_type *type = cb_ccd_type_find(method);
  if (!type) {
    fprintf(stderr, "ccd-query: --method '%s': no such CCD method\n", method);
    return 2;
  }
  if (!(p.eta >= 0) || p.eta > 1e300 || !(p.tol > 0) || p.tol > 1e300) {
    fprintf(stderr, "ccd-query: --eta must be finite and >= 0, --tol finite and > 0\n");
    return 2;
  }

  cb_ccd_file in;
  int rc = cb_ccd_file_load(file, &in);
  if (rc) {
    fprintf(stderr, "ccd-query: %s\n", cb_error_message());
    return rc == CB_EIO ? 3 : 1;
  }
  cb_ccd_result *res = calloc((size_t)in.n + 1, sizeof *res);
  if (!res) {
    fprintf(stderr, "ccd-query: out of memory\n");
    cb_ccd_file_free(&in);
    return 1;
  }
  long over = 0;
  double t0 = cb_now_ms();
  for (int i = 0; i < in.n; i++) {
    int s = cb_ccd_run(type, kind, &in.q[i], &p, &res[i]);
    if (s < 0) {
      fprintf(stderr, "ccd-query: %s: query %d (rows %d-%d): %s\n", file, i + 1, 8 * i + 1, 8 * i + 8,
              cb_error_message());
      free(res);
      cb_ccd_file_free(&in);
      return 1;
    }
    over += s == CB_NOT_CONVERGED;
  }
  double ms = cb_now_ms() - t0;

  cb_outfile o;
  if (cb_outfile_open(&o, out_path)) {
    fprintf(stderr, "ccd-query: %s\n", cb_error_message());
    free(res);
    cb_ccd_file_free(&in);
    return 3;
  }
  for (int i = 0; i < in.n; i++) {
    if (res[i].hit) fprintf(o.f, "1,%.17g\n", res[i].toi);
    else fprintf(o.f, "0,\n");
  }
  if (cb_outfile_commit(&o)) {
    fprintf(stderr, "ccd-query: %s\n", cb_error_message());
    free(res);
    cb_ccd_file_free(&in);
    return 3;
  }
  int code = 0;
  if (stats) {
    long hits = 0, pos = 0, fn = 0, fp = 0, neg = 0, boxes = 0;
    for (int i = 0; i < in.n; i++) {
      hits += res[i].hit;
      pos += in.truth[i];
      neg += !in.truth[i];
      fn += in.truth[i] && !res[i].hit;
      fp += !in.truth[i] && res[i].hit;
      boxes += res[i].boxes;
    }
    fprintf(stderr,
            "ccd-query: %s (%s, method %s, eta %g, tol %g): %d queries, %ld hits; truth column: %ld positive, "
            "%ld negative; false negatives %ld, false positives %ld (rate %.4g of the negatives); "
            "%ld over the box budget; %ld inexact coordinates; %.4g boxes/query; %.1f ms, %.4g queries/s\n",
            file, kind_s, type->name, p.eta, p.tol, in.n, hits, pos, neg, fn, fp, neg ? (double)fp / neg : 0.0, over,
            in.inexact, in.n ? (double)boxes / in.n : 0.0, ms, ms > 0 ? in.n / (ms * 1e-3) : 0.0);
    if (fn) code = 4;
  }
  free(res);
  cb_ccd_file_free(&in);
  return code;
}
