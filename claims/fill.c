/* build/report --fill: regenerates the marked blocks of a Markdown file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/readfile.h>
#include <clothbench/status.h>

#include "outfile.h"
#include "report.h"

#define END_MARK "<!-- /report -->"

void cb_report_verdicts(FILE *f, const cb_claim_result *res) {
  fputs("| claim | verdict | why (computed by `claims/check_*.c`) | figure (`plots/out/`) |\n|---|---|---|---|\n", f);
  for (int i = 0; i < cb_nclaims; i++) {
    const cb_claim *c = &cb_claims[i];
    fprintf(f, "| %s | %s | ", c->id, cb_verdict_name(res[i].verdict));
    for (const char *p = res[i].reason; *p; p++) { /* one table cell: no newlines or bars */
      if (*p == '\n') fputc(' ', f);
      else if (*p == '|') fputs("\\|", f);
      else fputc(*p, f);
    }
    fputs(" | ", f);
    cb_claim_figures(f, c, NULL, " ");
    fputs(" |\n", f);
  }
  fputs("\n", f);
  cb_report_counts(f, res);
}

void cb_report_counts(FILE *f, const cb_claim_result *res) {
  int n[CB_UNDECIDED + 1] = {0};
  for (int i = 0; i < cb_nclaims; i++)
    if (res[i].verdict >= 0 && res[i].verdict <= CB_UNDECIDED) n[res[i].verdict]++;
  fprintf(f, "%d claims: %d reproduced, %d partly reproduced, %d not reproduced, **%d undecided (within the spread)**",
          cb_nclaims, n[CB_REPRODUCED], n[CB_PARTLY], n[CB_NOT_REPRODUCED], n[CB_UNDECIDED]);
  if (n[CB_UNDECIDED]) {
    fputs(" (", f);
    for (int i = 0, k = 0; i < cb_nclaims; i++)
      if (res[i].verdict == CB_UNDECIDED) fprintf(f, "%s%s", k++ ? ", " : "", cb_claims[i].id);
    fputs(": a timing whose paired spread straddles its threshold; each says its margin and how many repeats "
          "would decide it)",
          f);
  }
  fprintf(f, ", %d not run.\n", n[CB_NOT_RUN]);
}

static int claim_index(const char *id) {
  for (int i = 0; i < cb_nclaims; i++)
    if (!strcmp(cb_claims[i].id, id)) return i;
  return -1;
}

/* Writes the generated text of marker `m` (the text after "<!-- report:",
 * up to " -->") to f; CB_EINVAL for an unknown marker. */
static int generate(FILE *f, const char *m, size_t len, const cb_claim_result *res, const char *results) {
  char name[128];
  if (len >= sizeof name) return cb_fail("unknown report marker '%.*s'", (int)len, m);
  memcpy(name, m, len);
  name[len] = '\0';
  /* a page's block may say "the last full run": verdicts of any other kind of
   * run are marked as such, in the block itself */
  const char *kind = NULL, *what = NULL;
  if (!strcmp(name, "verdicts")) kind = cb_report_run_kind_all(results), what = "the experiments";
  else if (!strncmp(name, "claim ", 6) || !strncmp(name, "claim-short ", 12)) {
    int i = claim_index(name + (name[5] == '-' ? 12 : 6));
    if (i >= 0 && cb_claims[i].experiment) kind = cb_report_run_kind(results, what = cb_claims[i].experiment);
  }
  if (kind && strcmp(kind, "full") != 0)
    fprintf(f,
            "> **Not a full run:** these verdicts come from a %s run of %s%s%s; they are not the results of a full "
            "run.\n\n",
            kind, strcmp(what, "the experiments") ? "`" : "", what, strcmp(what, "the experiments") ? "`" : "");
  if (!strcmp(name, "verdicts")) cb_report_verdicts(f, res);
  else if (!strcmp(name, "counts")) cb_report_counts(f, res);
  else if (!strcmp(name, "origin")) cb_report_origin(f, results);
  else if (!strcmp(name, "runtimes")) cb_report_runtimes(f, results);
  else if (!strncmp(name, "claim ", 6) || !strncmp(name, "claim-short ", 12)) {
    int shrt = name[5] == '-';
    const char *id = name + (shrt ? 12 : 6);
    int i = claim_index(id);
    if (i < 0) return cb_fail("report marker '%s': no claim %s", name, id);
    fprintf(f, "**%s: %s.** %s\n", cb_claims[i].id, cb_verdict_name(res[i].verdict), res[i].reason);
    if (!shrt && res[i].numbers[0]) fprintf(f, "\n%s\n", res[i].numbers);
  } else
    return cb_fail("unknown report marker '%s' (verdicts, counts, origin, runtimes, claim ID, claim-short ID)", name);
  return CB_OK;
}

static char *slurp(const char *path, size_t *n) {
  FILE *f = cb_fopen_regular(path, NULL); /* a FIFO is refused, not waited on */
  if (!f) return NULL;
  size_t cap = 1 << 16, len = 0;
  char *buf = malloc(cap + 1);
  for (size_t r; buf && (r = fread(buf + len, 1, cap - len, f)) > 0;) {
    len += r;
    if (len == cap) {
      char *nb = realloc(buf, 2 * cap + 1);
      if (!nb) {
        free(buf);
        buf = NULL;
        break;
      }
      buf = nb;
      cap *= 2;
    }
  }
  int bad = ferror(f);
  fclose(f);
  if (bad) {
    free(buf);
    return NULL;
  }
  if (buf) buf[len] = '\0';
  *n = len;
  return buf;
}

int cb_report_fill(const char *path, const cb_claim_result *res, const char *results) {
  size_t n = 0;
  char *text = slurp(path, &n);
  if (!text) return cb_fail_status(CB_EIO, "%s: cannot read", path);
  const char *nul = memchr(text, '\0', n);
  if (nul) { /* the text after it would be lost: string functions stop there */
    int at = 1;
    for (const char *q = text; q < nul; q++) at += *q == '\n';
    free(text);
    return cb_fail("%s:%d: NUL byte; not a text file, nothing filled", path, at);
  }
  cb_outfile o;
  int st = cb_outfile_open(&o, path);
  if (st) {
    free(text);
    return st;
  }
  const char *p = text;
  int line = 1;
  for (;;) {
    const char *m = strstr(p, "<!-- report:");
    while (m && m != text && m[-1] != '\n') m = strstr(m + 1, "<!-- report:"); /* markers start a line */
    if (!m) break;
    for (const char *q = p; q < m; q++) line += *q == '\n';
    const char *close = strstr(m, " -->");
    const char *eol = strchr(m, '\n');
    if (!close || !eol || close > eol) {
      st = cb_fail("%s:%d: report marker without its closing ' -->'", path, line);
      break;
    }
    const char *end = strstr(eol, "\n" END_MARK);
    if (end) end++; /* the end marker starts a line too */
    if (!end) {
      st = cb_fail("%s:%d: report marker with no " END_MARK " after it", path, line);
      break;
    }
    const char *next = strstr(eol, "\n<!-- report:"); /* a block may not run on into the next one */
    if (next && next < end) {
      int at = line;
      for (const char *q = m; q <= next; q++) at += *q == '\n';
      st = cb_fail("%s:%d: report marker with no " END_MARK " before the next marker (line %d)", path, line, at);
      break;
    }
    fwrite(p, 1, (size_t)(eol + 1 - p), o.f); /* everything up to and including the marker line */
    const char *name = m + strlen("<!-- report:");
    st = generate(o.f, name, (size_t)(close - name), res, results);
    if (st) {
      char msg[1024];
      snprintf(msg, sizeof msg, "%s", cb_error_message());
      st = cb_fail("%s:%d: %s", path, line, msg);
      break;
    }
    for (const char *q = m; q < end; q++) line += *q == '\n';
    p = end; /* the end marker and what follows are copied next */
  }
  if (st == CB_OK) {
    fputs(p, o.f);
    st = cb_outfile_commit(&o);
  } else cb_outfile_abort(&o);
  free(text);
  return st;
}
