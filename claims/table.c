#include "table.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/readfile.h>
#include <clothbench/status.h>

void cb_table_free(cb_table *t) {
  if (!t) return;
  for (int i = 0; i < t->ncols; i++) free(t->cols[i]);
  for (long i = 0; i < (long)t->nrows * t->ncols; i++) free(t->cells[i]);
  free(t->cols);
  free(t->cells);
  free(t->meta);
  memset(t, 0, sizeof *t);
}

static int split(char *line, char ***out, int *n) {
  int cap = 16, cnt = 0;
  char **f = malloc((size_t)cap * sizeof *f);
  if (!f) return CB_ENOMEM;
  size_t len = strlen(line);
  while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = '\0';
  char *p = line;
  for (;;) {
    char *c = strchr(p, ',');
    if (c) *c = '\0';
    if (cnt == cap) {
      cap *= 2;
      char **g = realloc(f, (size_t)cap * sizeof *f);
      if (!g) {
        for (int i = 0; i < cnt; i++) free(f[i]);
        free(f);
        return CB_ENOMEM;
      }
      f = g;
    }
    f[cnt++] = strdup(p);
    if (!c) break;
    p = c + 1;
  }
  *out = f;
  *n = cnt;
  return CB_OK;
}

int cb_table_read(const char *path, cb_table *t) {
  memset(t, 0, sizeof *t);
  FILE *f = cb_fopen_regular(path, NULL); /* a FIFO is refused, not waited on */
  if (!f && errno) return cb_fail_status(CB_EIO, "%s: not found", path);
  if (!f) return cb_fail_status(CB_EIO, "%s: not a regular file (a directory, device or pipe)", path);
  char *line = NULL;
  size_t cap = 0, mlen = 0, mcap = 0;
  long rcap = 0;
  int lineno = 0, st = CB_OK;
  for (ssize_t got; st == CB_OK && (got = getline(&line, &cap, f)) >= 0;) {
    lineno++;
    if (got == 0 || line[got - 1] != '\n') { /* the last line, cut: a row may have lost its tail */
      st = cb_fail("%s:%d: does not end with a newline (cut mid-row?); refusing it", path, lineno);
      break;
    }
    if (line[0] == '#') {
      size_t n = strlen(line);
      if (mlen + n + 1 > mcap) {
        mcap = 2 * (mlen + n + 1);
        char *m = realloc(t->meta, mcap);
        if (!m) {
          st = CB_ENOMEM;
          break;
        }
        t->meta = m;
      }
      memcpy(t->meta + mlen, line, n + 1);
      mlen += n;
      continue;
    }
    if (line[0] == '\n' || line[0] == '\0') continue;
    char **fields;
    int nf;
    if ((st = split(line, &fields, &nf))) break;
    if (!t->cols) {
      t->cols = fields;
      t->ncols = nf;
      continue;
    }
    if (nf != t->ncols) {
      for (int i = 0; i < nf; i++) free(fields[i]);
      free(fields);
      st = cb_fail("%s:%d: %d fields, header has %d", path, lineno, nf, t->ncols);
      break;
    }
    if (t->nrows == rcap) {
      rcap = rcap ? 2 * rcap : 256;
      char **c = realloc(t->cells, (size_t)rcap * t->ncols * sizeof *c);
      if (!c) {
        st = CB_ENOMEM;
        break;
      }
      t->cells = c;
    }
    memcpy(t->cells + (size_t)t->nrows * t->ncols, fields, (size_t)nf * sizeof *fields);
    free(fields);
    t->nrows++;
  }
  free(line);
  fclose(f);
  if (st == CB_OK && !t->cols) st = cb_fail("%s: no header row", path);
  if (st) cb_table_free(t);
  return st;
}

int cb_table_col(const cb_table *t, const char *name) {
  for (int i = 0; i < t->ncols; i++)
    if (strcmp(t->cols[i], name) == 0) return i;
  return -1;
}

const char *cb_table_str(const cb_table *t, int row, int col) {
  if (row < 0 || row >= t->nrows || col < 0 || col >= t->ncols) return "";
  return t->cells[(size_t)row * t->ncols + col];
}

double cb_table_num(const cb_table *t, int row, int col) {
  const char *s = cb_table_str(t, row, col);
  char *end;
  if (!*s) return NAN;
  double v = strtod(s, &end);
  return *end ? NAN : v;
}

int cb_table_int_of(double v) { return isfinite(v) && fabs(v) <= CB_TABLE_INT_MAX ? (int)v : -1; }

int cb_table_int(const cb_table *t, int row, int col) { return cb_table_int_of(cb_table_num(t, row, col)); }

const char *cb_table_meta(const cb_table *t, const char *key) {
  static char buf[4096];
  if (!t->meta) return NULL;
  size_t kl = strlen(key);
  for (const char *p = t->meta; p && *p;) {
    if (p[0] == '#' && p[1] == ' ' && strncmp(p + 2, key, kl) == 0 && p[2 + kl] == ':') {
      const char *v = p + 2 + kl + 1;
      while (*v == ' ') v++;
      const char *e = strchr(v, '\n');
      size_t n = e ? (size_t)(e - v) : strlen(v);
      if (n >= sizeof buf) n = sizeof buf - 1;
      memcpy(buf, v, n);
      buf[n] = '\0';
      return buf;
    }
    p = strchr(p, '\n');
    if (p) p++;
  }
  return NULL;
}
