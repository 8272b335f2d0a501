/* report: writes results/REPORT.md from the experiments' CSV files. Every
 * verdict is computed by the checkers in claims/check_*.c from the data. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"
#include "outfile.h"
#include "provenance.h"
#include <clothbench/status.h>

/* The provenance of one experiment's CSV: the "# key: value" lines before
 * its header row. */
typedef struct {
  char revision[128], quick[16], date[64], blas[16], omp[16], cpu[256], cores[16];
  int found;
} csv_origin;

static void meta_value(const char *line, const char *key, char *out, size_t n) {
  size_t k = strlen(key);
  if (strncmp(line, "# ", 2) == 0 && strncmp(line + 2, key, k) == 0 && line[2 + k] == ':' && line[3 + k] == ' ')
    snprintf(out, n, "%.*s", (int)strcspn(line + 4 + k, "\n"), line + 4 + k);
}

static csv_origin read_origin(const char *results, const char *experiment) {
  csv_origin o = {.revision = "?", .quick = "?", .date = "?", .blas = "?", .omp = "?", .cpu = "?", .cores = "?"};
  char path[4096], line[8192];
  snprintf(path, sizeof path, "%s/%s.csv", results, experiment);
  FILE *f = fopen(path, "r");
  if (!f) return o;
  o.found = 1;
  while (fgets(line, sizeof line, f) && line[0] == '#') {
    meta_value(line, "git_revision", o.revision, sizeof o.revision);
    meta_value(line, "quick", o.quick, sizeof o.quick);
    meta_value(line, "date", o.date, sizeof o.date);
    meta_value(line, "blas_threads", o.blas, sizeof o.blas);
    meta_value(line, "omp_num_threads", o.omp, sizeof o.omp);
    meta_value(line, "cpu", o.cpu, sizeof o.cpu);
    meta_value(line, "cores", o.cores, sizeof o.cores);
  }
  fclose(f);
  return o;
}

/* "What produced it": one row per experiment whose CSV is there, and a
 * summary line saying whether the run is quick, full or mixed and whether
 * every CSV comes from one clean revision. */
static void write_origin(FILE *f, const char *results) {
  int quick = 0, full = 0, dirty = 0, nrev = 0, n = 0, missing = 0;
  char first_rev[128] = "";
  fputs("## What produced this report\n\n"
        "| experiment | run | git revision | date (UTC) | BLAS threads | OpenMP threads | CPU | cores |\n"
        "|---|---|---|---|---|---|---|---|\n", f);
  for (int i = 0; i < cb_nclaims; i++) {
    const char *e = cb_claims[i].experiment;
    int seen = 0;
    for (int j = 0; j < i && !seen; j++) seen = cb_claims[j].experiment && e && !strcmp(cb_claims[j].experiment, e);
    if (!e || seen) continue;
    csv_origin o = read_origin(results, e);
    if (!o.found) {
      fprintf(f, "| %s | not run | | | | | | |\n", e);
      missing++;
      continue;
    }
    n++;
    if (!strcmp(o.quick, "1")) quick++;
    else full++;
    if (strstr(o.revision, "dirty")) dirty++;
    if (!first_rev[0]) snprintf(first_rev, sizeof first_rev, "%s", o.revision);
    if (strcmp(first_rev, o.revision) != 0) nrev++;
    fprintf(f, "| %s | %s | %s | %s | %s | %s | %s | %s |\n", e, !strcmp(o.quick, "1") ? "quick (`QUICK=1`)" : "full", o.revision,
            o.date, o.blas, o.omp, o.cpu, o.cores);
  }
  if (n == 0) fputs("\nNo experiment CSV was found: every claim is `not run`.\n\n", f);
  else
    fprintf(f, "\nThis is a **%s** run of %d experiment%s%s%s%s.\n\n", quick && full ? "mixed (quick and full)" : quick ? "quick" : "full", n,
            n == 1 ? "" : "s", missing ? " (the others were not run)" : "", nrev ? "; the CSVs come from different revisions" : "",
            dirty ? "; some CSVs come from a working tree with uncommitted changes" : "");
}

/* Path of directory `to` relative to directory `from` (which exists), for
 * links inside a file written in `from`. `to` need not exist yet (the plots
 * may be drawn later): then it is taken relative to the working directory. */
static void relative_dir(const char *from, const char *to, char *out, size_t n) {
  char a[PATH_MAX + 2], b[2 * PATH_MAX + 4], cwd[PATH_MAX];
  if (!realpath(from, a)) {
    snprintf(out, n, "%s", to);
    return;
  }
  if (!realpath(to, b)) {
    if (to[0] == '/') snprintf(b, sizeof b, "%s", to);
    else if (getcwd(cwd, sizeof cwd)) snprintf(b, sizeof b, "%s/%s", cwd, to);
    else {
      snprintf(out, n, "%s", to);
      return;
    }
  }
  size_t la = strlen(a), lb = strlen(b);
  if (la + 2 > sizeof a || lb + 2 > sizeof b) {
    snprintf(out, n, "%s", to);
    return;
  }
  strcat(a, "/"); /* both end in '/', so a shared prefix ends at a whole component */
  strcat(b, "/");
  size_t common = 0;
  for (size_t i = 0; a[i] && a[i] == b[i]; i++)
    if (a[i] == '/') common = i + 1;
  out[0] = '\0';
  for (const char *p = a + common; *p; p++)
    if (*p == '/') strncat(out, "../", n - strlen(out) - 1);
  strncat(out, b + common, n - strlen(out) - 1);
  size_t lo = strlen(out);
  if (lo > 0 && out[lo - 1] == '/') out[lo - 1] = '\0';
  if (!out[0]) snprintf(out, n, ".");
}

int main(int argc, char **argv) {
  const char *results = "results", *out = NULL, *plots = "plots/out";
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--version")) {
      printf("report (clothbench) %s (%s)\n", cb_build_git, cb_build_dirty);
      return 0;
    }
    if (!strcmp(argv[i], "--help")) {
      puts("usage: report [--results DIR] [--plots DIR] [--out PATH] [--version]\n"
           "Decides every claim of CLAIMS.md from DIR/<experiment>.csv (default results/)\n"
           "and writes DIR/REPORT.md (or PATH). A claim whose CSV is missing is `not run`.");
      return 0;
    }
    if (!strcmp(argv[i], "--results") && i + 1 < argc) results = argv[++i];
    else if (!strcmp(argv[i], "--plots") && i + 1 < argc) plots = argv[++i];
    else if (!strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
    else { fprintf(stderr, "report: unknown option %s\n", argv[i]); return 1; }
  }
  char outpath[4096];
  if (out) snprintf(outpath, sizeof outpath, "%s", out);
  else snprintf(outpath, sizeof outpath, "%s/REPORT.md", results);
  cb_claim_result *res = calloc((size_t)cb_nclaims, sizeof *res);
  if (!res) return 1;
  for (int i = 0; i < cb_nclaims; i++) cb_claim_decide(&cb_claims[i], results, &res[i]);
  cb_outfile o;
  if (cb_outfile_open(&o, outpath)) { fprintf(stderr, "report: %s\n", cb_error_message()); return 2; }
  FILE *f = o.f;
  char outdir[4096], plots_rel[4096];
  snprintf(outdir, sizeof outdir, "%s", outpath);
  char *slash = strrchr(outdir, '/');
  if (slash) *slash = '\0';
  else snprintf(outdir, sizeof outdir, ".");
  relative_dir(outdir, plots, plots_rel, sizeof plots_rel);
  fprintf(f, "# clothbench: the lecture's claims, decided from the data\n\n"
             "Generated by `make report` (build/report) from the CSV files in `%s/`; every verdict\n"
             "below is computed from those files by `claims/check_*.c`. Do not edit by hand.\n\n",
          results);
  write_origin(f, results);
  fputs("## Verdicts\n\n| claim | verdict | experiment | figure |\n|---|---|---|---|\n", f);
  for (int i = 0; i < cb_nclaims; i++) {
    const cb_claim *c = &cb_claims[i];
    fprintf(f, "| [%s](#%s) | %s | %s | %s%s%s |\n", c->id, c->id, cb_verdict_name(res[i].verdict),
            c->experiment ? c->experiment : "-", c->figure ? "`" : "", c->figure ? c->figure : "-", c->figure ? "`" : "");
  }
  for (int i = 0; i < cb_nclaims; i++) {
    const cb_claim *c = &cb_claims[i];
    fprintf(f, "\n<a id=\"%s\"></a>\n## %s: %s\n\n", c->id, c->id, cb_verdict_name(res[i].verdict));
    fprintf(f, "**Claim.** %s\n\n**Deciding measurement.** %s\n\n", c->text, c->decided_by);
    if (res[i].numbers[0]) fprintf(f, "**Numbers** (from `%s/%s.csv`):\n\n%s\n\n", results, c->experiment, res[i].numbers);
    fprintf(f, "**Verdict: %s.** %s\n", cb_verdict_name(res[i].verdict), res[i].reason);
    if (c->figure && res[i].verdict != CB_NOT_RUN) fprintf(f, "\n![%s](%s/%s)\n", c->id, plots_rel, c->figure);
  }
  free(res);
  if (cb_outfile_commit(&o)) { fprintf(stderr, "report: %s\n", cb_error_message()); return 2; }
  fprintf(stderr, "report: wrote %s\n", outpath);
  return 0;
}
