/* What produced a report: the provenance of each experiment's CSV, and the
 * run times `make experiments` records. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/readfile.h>

#include "claims.h"
#include "report.h"

/* The provenance of one experiment's CSV: the "# key: value" lines before
 * its header row. */
typedef struct {
  char revision[128], quick[16], smoke[16], date[64], blas[16], omp[16], cpu[256], cores[16], kernel[64], choice[1024];
  int found;
} csv_origin;

/* The kind of run a CSV comes from: --smoke (make test: one small cell per
 * sweep, so its verdicts mean nothing), --quick (QUICK=1) or full. A smoke
 * CSV says "# smoke: 1" beside "# quick: 1". */
enum run_kind { RUN_FULL, RUN_QUICK, RUN_SMOKE, RUN_KINDS };
static const char *first_claim_of_experiment(int i);
static const char *const run_kind_name[RUN_KINDS] = {[RUN_FULL] = "full", [RUN_QUICK] = "quick", [RUN_SMOKE] = "smoke"};
static const char *const run_kind_long[RUN_KINDS] = {
    [RUN_FULL] = "full", [RUN_QUICK] = "quick (`QUICK=1`)", [RUN_SMOKE] = "smoke (`--smoke`, make test)"};

static enum run_kind run_kind_of(const csv_origin *o) {
  if (!strcmp(o->smoke, "1")) return RUN_SMOKE;
  return !strcmp(o->quick, "1") ? RUN_QUICK : RUN_FULL;
}

static void meta_value(const char *line, const char *key, char *out, size_t n) {
  size_t k = strlen(key);
  if (strncmp(line, "# ", 2) == 0 && strncmp(line + 2, key, k) == 0 && line[2 + k] == ':' && line[3 + k] == ' ')
    snprintf(out, n, "%.*s", (int)strcspn(line + 4 + k, "\n"), line + 4 + k);
}

static csv_origin read_origin(const char *results, const char *experiment) {
  csv_origin o = {.revision = "?",
                  .quick = "?",
                  .smoke = "0",
                  .date = "?",
                  .blas = "?",
                  .omp = "?",
                  .cpu = "?",
                  .cores = "?",
                  .kernel = "?",
                  .choice = ""};
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.csv", results, experiment);
  FILE *f = cb_fopen_regular(path, NULL);
  if (!f) return o;
  o.found = 1;
  /* whole lines, however long: the "# config" lines before "# quick:" and
   * "# smoke:" hold every key of a scene (a fixed buffer cut them into
   * chunks, and a chunk not starting with '#' ended the header early) */
  char *line = NULL;
  size_t cap = 0;
  while (getline(&line, &cap, f) >= 0 && line[0] == '#') {
    meta_value(line, "git_revision", o.revision, sizeof o.revision);
    meta_value(line, "quick", o.quick, sizeof o.quick);
    meta_value(line, "smoke", o.smoke, sizeof o.smoke);
    meta_value(line, "date", o.date, sizeof o.date);
    meta_value(line, "blas_threads", o.blas, sizeof o.blas);
    meta_value(line, "omp_num_threads", o.omp, sizeof o.omp);
    meta_value(line, "cpu", o.cpu, sizeof o.cpu);
    meta_value(line, "cores", o.cores, sizeof o.cores);
    meta_value(line, "blas_kernel", o.kernel, sizeof o.kernel);
    meta_value(line, "blas_kernel_choice", o.choice, sizeof o.choice);
  }
  free(line);
  fclose(f);
  return o;
}

const char *cb_report_run_kind(const char *results, const char *experiment) {
  csv_origin o = read_origin(results, experiment);
  return o.found ? run_kind_long[run_kind_of(&o)] : NULL;
}

const char *cb_report_run_kind_all(const char *results) {
  const char *kind = NULL;
  for (int i = 0; i < cb_nclaims; i++) {
    const char *e = first_claim_of_experiment(i), *k = e ? cb_report_run_kind(results, e) : NULL;
    if (!k) continue;
    if (kind && strcmp(kind, k) != 0) return "mixed";
    kind = k;
  }
  return kind;
}

/* "SkylakeX (chosen)", "Cooperlake (detected)", "Prescott (environment)",
 * "Prescott (detected; SkylakeX refused)": the kernel and the first word of
 * how it came to run (lib/io/blas_kernel.h). */
static void kernel_cell(const csv_origin *o, char *out, size_t n) {
  const char *how = !strncmp(o->choice, "chosen", 6)                    ? "chosen"
                    : !strncmp(o->choice, "set by the environment", 22) ? "environment"
                    : strstr(o->choice, "; refused ")                   ? "detected; better one refused"
                    : !strncmp(o->choice, "detected", 8)
                        ? (strstr(o->choice, "fallback") ? "detected fallback" : "detected")
                        : "?";
  snprintf(out, n, "%s (%s)", o->kernel, how);
}

/* The experiment of claim i if no earlier claim names it, else NULL: each
 * experiment once, in the claims' order. */
static const char *first_claim_of_experiment(int i) {
  const char *e = cb_claims[i].experiment;
  for (int j = 0; e && j < i; j++)
    if (cb_claims[j].experiment && !strcmp(cb_claims[j].experiment, e)) return NULL;
  return e;
}

/* "What produced it": one row per experiment whose CSV is there, and a
 * summary line saying whether the run is smoke, quick, full or mixed and
 * whether every CSV comes from one clean revision. */
void cb_report_origin(FILE *f, const char *results) {
  int kinds[RUN_KINDS] = {0}, dirty = 0, nrev = 0, n = 0, missing = 0;
  char first_rev[128] = "";
  fputs("## What produced this report\n\n"
        "| experiment | run | git revision | date (UTC) | BLAS threads | OpenMP threads | OpenBLAS kernel | CPU | "
        "cores |\n"
        "|---|---|---|---|---|---|---|---|---|\n",
        f);
  for (int i = 0; i < cb_nclaims; i++) {
    const char *e = first_claim_of_experiment(i);
    if (!e) continue;
    csv_origin o = read_origin(results, e);
    if (!o.found) {
      fprintf(f, "| %s | not run | | | | | | | |\n", e);
      missing++;
      continue;
    }
    n++;
    enum run_kind k = run_kind_of(&o);
    kinds[k]++;
    if (strstr(o.revision, "dirty")) dirty++;
    if (!first_rev[0]) snprintf(first_rev, sizeof first_rev, "%s", o.revision);
    if (strcmp(first_rev, o.revision) != 0) nrev++;
    char kernel[128];
    kernel_cell(&o, kernel, sizeof kernel);
    fprintf(f, "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", e, run_kind_long[k], o.revision, o.date, o.blas,
            o.omp, kernel, o.cpu, o.cores);
  }
  if (n == 0) {
    fputs("\nNo experiment CSV was found: every claim is `not run`.\n\n", f);
    return;
  }
  /* "smoke", "quick", "full", or "mixed (smoke and full)" etc. */
  char kind[64] = "";
  int nkinds = 0;
  for (int k = RUN_KINDS - 1; k >= 0; k--)
    if (kinds[k]) nkinds++;
  for (int k = RUN_KINDS - 1, m = 0; k >= 0; k--) {
    if (!kinds[k]) continue;
    size_t len = strlen(kind);
    snprintf(kind + len, sizeof kind - len, "%s%s",
             m == 0            ? (nkinds > 1 ? "mixed (" : "")
             : m == nkinds - 1 ? " and "
                               : ", ",
             run_kind_name[k]);
    m++;
  }
  if (nkinds > 1) strncat(kind, ")", sizeof kind - strlen(kind) - 1);
  fprintf(f, "\nThis is a **%s** run of %d experiment%s%s%s%s.\n\n", kind, n, n == 1 ? "" : "s",
          missing ? " (the others were not run)" : "", nrev ? "; the CSVs come from different revisions" : "",
          dirty ? "; some CSVs come from a working tree with uncommitted changes" : "");
  if (kinds[RUN_SMOKE])
    fputs("A smoke run (`--smoke`, what `make test` runs) is one small cell of each sweep: it shows that every table "
          "and "
          "column is written, and its verdicts decide nothing about the claims.\n\n",
          f);
}


enum { RUNTIME_MAX_S = 366 * 24 * 3600 };

/* results/<experiment>.runtime, written by make experiments: "wall_s: S";
 * -1 when missing, -2 when not a run time (non-finite, negative, > a year). */
static double read_runtime(const char *results, const char *experiment) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.runtime", results, experiment);
  FILE *f = cb_fopen_regular(path, NULL);
  if (!f) return -1;
  double s = -1;
  if (fscanf(f, "wall_s: %lf", &s) != 1) s = -1;
  fclose(f);
  /* nan, inf, negative or past a year is not a run time (and past INT_MAX
   * minutes the conversion to int below would be undefined) */
  if (!isfinite(s) || s < 0 || s > RUNTIME_MAX_S) return -2;
  return s;
}

void cb_report_runtimes(FILE *f, const char *results) {
  fputs("| experiment | run | wall time | git revision | date (UTC) |\n|---|---|---|---|---|\n", f);
  double total = 0;
  int n = 0;
  for (int i = 0; i < cb_nclaims; i++) {
    const char *e = first_claim_of_experiment(i);
    if (!e) continue;
    csv_origin o = read_origin(results, e);
    double s = read_runtime(results, e);
    if (!o.found) continue;
    char t[64];
    if (s == -2) snprintf(t, sizeof t, "not a run time (%s.runtime)", e);
    else if (s < 0) snprintf(t, sizeof t, "not recorded");
    else if (s < 60) snprintf(t, sizeof t, "%.0f s", s);
    else snprintf(t, sizeof t, "%d min %02.0f s", (int)(s / 60), s - 60 * (int)(s / 60));
    if (s >= 0) {
      total += s;
      n++;
    }
    fprintf(f, "| %s | %s | %s | %s | %s |\n", e, run_kind_name[run_kind_of(&o)], t, o.revision, o.date);
  }
  if (n > 0)
    fprintf(f, "| all experiments | | %d min %02.0f s | | |\n", (int)(total / 60), total - 60 * (int)(total / 60));
}
