/* report --stability: do the verdicts hold over the recorded spread? (issue 31 §7)
 *
 * Every timing column X_ms of every results CSV that has its spread columns X_min_ms and X_max_ms
 * (lib/instruments/stats.h) is replaced by one end of its spread, and every claim is decided again on
 * those copies. Four variants: every median at its row's fastest repeat ("low"), at its slowest
 * ("high"), and alternately row by row ("zigzag": even rows low, odd rows high; "zagzig": the other
 * way round), so that two timings that are compared move apart as well as together. The per-repeat
 * lists (X_each_ms) are left alone.
 *
 * A verdict that uses cb_claim_timing_side holds its side for any median inside the spread it
 * decides on: so the only allowed change is to or from "undecided (within the spread)". A verdict
 * that changes between two decided values was decided by a median alone: the check fails. */
#define _XOPEN_SOURCE 700 /* mkdtemp, glob */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"
#include "report.h"

enum { NMODES = 4 }; /* low, high, zigzag, zagzig */

/* Splits line (modified in place) at commas into f[0..cap); returns the count. */
static int split(char *line, char **f, int cap) {
  int n = 0;
  for (char *p = line;;) {
    if (n < cap) f[n++] = p;
    char *c = strchr(p, ',');
    if (!c) break;
    *c = '\0';
    p = c + 1;
  }
  return n;
}

static int is_number(const char *s) {
  char *end;
  if (!s[0]) return 0;
  double v = strtod(s, &end);
  return *end == '\0' && isfinite(v);
}

/* Copies CSV `in` to `out` with every median timing at one end of its spread (mode as above). */
static int perturb(const char *in, const char *out, int mode) {
  FILE *fi = fopen(in, "r"), *fo = fi ? fopen(out, "w") : NULL;
  if (!fi || !fo) {
    if (fi) fclose(fi);
    return -1;
  }
  enum { MAXC = 1024 };
  static char line[1 << 20], head[1 << 16];
  static char *f[MAXC], *h[MAXC];
  int lo[MAXC], hi[MAXC], nh = 0, row = 0, st = 0;
  while (fgets(line, sizeof line, fi)) {
    size_t len = strlen(line);
    int nl = len > 0 && line[len - 1] == '\n';
    if (nl) line[--len] = '\0';
    if (line[0] == '#' || (nh > 0 && !line[0])) {
      fprintf(fo, "%s\n", line);
      continue;
    }
    if (nh == 0) { /* the header: each timing column's spread columns */
      if (len >= sizeof head) {
        fprintf(stderr, "report --stability: %s: header longer than %zu bytes\n", in, sizeof head - 1);
        fclose(fi);
        fclose(fo);
        return -1;
      }
      memcpy(head, line, len + 1);
      nh = split(head, h, MAXC);
      for (int c = 0; c < nh; c++) {
        char name[256];
        lo[c] = hi[c] = -1;
        cb_claim_spread_column(h[c], "min", name, sizeof name);
        for (int k = 0; name[0] && k < nh; k++)
          if (!strcmp(h[k], name)) lo[c] = k;
        cb_claim_spread_column(h[c], "max", name, sizeof name);
        for (int k = 0; name[0] && k < nh; k++)
          if (!strcmp(h[k], name)) hi[c] = k;
      }
      fprintf(fo, "%s\n", line);
      continue;
    }
    int n = split(line, f, MAXC), low = mode == 0 || (mode == 2 && row % 2 == 0) || (mode == 3 && row % 2 == 1);
    row++;
    for (int c = 0; c < n && c < nh; c++) {
      if (lo[c] < 0 || hi[c] < 0 || lo[c] >= n || hi[c] >= n || !is_number(f[c])) continue;
      const char *end = low ? f[lo[c]] : f[hi[c]];
      if (is_number(end)) f[c] = (char *)end;
    }
    for (int c = 0; c < n; c++) fprintf(fo, "%s%s", c ? "," : "", f[c]);
    fputc('\n', fo);
  }
  if (ferror(fi)) st = -1;
  fclose(fi);
  if (fclose(fo)) st = -1;
  return st;
}

int cb_report_stability(FILE *f, const char *results, const cb_claim_result *base) {
  char pattern[4096], tmp[4096];
  snprintf(pattern, sizeof pattern, "%s/*.csv", results);
  const char *td = getenv("TMPDIR");
  snprintf(tmp, sizeof tmp, "%s/cbstability.XXXXXX", td && td[0] ? td : "/tmp");
  if (!mkdtemp(tmp)) {
    fprintf(stderr, "report --stability: cannot make a temporary folder in %s\n", td && td[0] ? td : "/tmp");
    return 2;
  }
  glob_t g;
  int gst = glob(pattern, 0, NULL, &g);
  size_t nfiles = gst == 0 ? g.gl_pathc : 0;
  cb_verdict(*v)[NMODES] = calloc((size_t)cb_nclaims, sizeof *v);
  cb_claim_result *r = malloc(sizeof *r);
  int rc = 0;
  if (!v || !r) rc = 2;
  for (int m = 0; m < NMODES && rc == 0; m++) {
    for (size_t k = 0; k < nfiles && rc == 0; k++) {
      const char *name = strrchr(g.gl_pathv[k], '/');
      char out[8192];
      snprintf(out, sizeof out, "%s/%s", tmp, name ? name + 1 : g.gl_pathv[k]);
      if (perturb(g.gl_pathv[k], out, m)) {
        fprintf(stderr, "report --stability: cannot copy %s to %s\n", g.gl_pathv[k], out);
        rc = 2;
      }
    }
    for (int i = 0; i < cb_nclaims && rc == 0; i++) {
      cb_claim_decide(&cb_claims[i], tmp, r);
      v[i][m] = r->verdict;
    }
  }
  for (size_t k = 0; k < nfiles; k++) { /* the copies go, whatever happened */
    const char *name = strrchr(g.gl_pathv[k], '/');
    char out[8192];
    snprintf(out, sizeof out, "%s/%s", tmp, name ? name + 1 : g.gl_pathv[k]);
    remove(out);
  }
  remove(tmp);
  if (gst == 0) globfree(&g);
  if (rc == 0) {
    int bad = 0, changed = 0;
    fprintf(f,
            "Verdicts with every timing median moved to an end of its recorded spread (%zu CSV files of %s):\n\n"
            "| claim | as measured | low | high | zigzag | zagzig | holds |\n|---|---|---|---|---|---|---|\n",
            nfiles, results);
    for (int i = 0; i < cb_nclaims; i++) {
      int ok = 1, same = 1;
      for (int m = 0; m < NMODES; m++) {
        same &= v[i][m] == base[i].verdict;
        if (v[i][m] != base[i].verdict && v[i][m] != CB_UNDECIDED && base[i].verdict != CB_UNDECIDED) ok = 0;
      }
      bad += !ok;
      changed += !same;
      fprintf(f, "| %s | %s |", cb_claims[i].id, cb_verdict_name(base[i].verdict));
      for (int m = 0; m < NMODES; m++) fprintf(f, " %s |", cb_verdict_name(v[i][m]));
      fprintf(f, " %s |\n", !ok ? "**no: changed between decided verdicts**" : same ? "yes" : "yes (via undecided)");
    }
    fprintf(f,
            "\n%d claim(s) changed verdict between the variants, %d of them between two decided verdicts "
            "(allowed: only to or from undecided).\n",
            changed, bad);
    if (bad) rc = 3;
  }
  free(v);
  free(r);
  return rc;
}
