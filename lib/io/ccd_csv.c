/* CCD query files (ccd_csv.h). */
#include "ccd_csv.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gmp.h>

#include <clothbench/status.h>

/* rational num/den as the interval [lo, hi] of doubles around it; 0 ok, else a message in msg */
static int to_interval(const mpz_t num, const mpz_t den, double *lo, double *hi, int *exact, char *msg, size_t len) {
  if (mpz_sgn(den) == 0) {
    snprintf(msg, len, "zero denominator");
    return -1;
  }
  mpq_t q, d;
  mpq_init(q);
  mpq_init(d);
  mpq_set_num(q, num);
  mpq_set_den(q, den);
  mpq_canonicalize(q);
  int rc = 0;
  /* |q| > 2^500 is refused before converting (mpq_get_d of a huge value is system dependent) */
  mpq_set_ui(d, 1, 1);
  mpq_mul_2exp(d, d, 500);
  mpq_t a;
  mpq_init(a);
  mpq_abs(a, q);
  if (mpq_cmp(a, d) > 0) {
    snprintf(msg, len, "|value| exceeds 2^500");
    rc = -1;
  } else {
    double x = mpq_get_d(q); /* rounds toward zero */
    mpq_set_d(d, x);
    int c = mpq_cmp(q, d);
    *exact = c == 0;
    *lo = c < 0 ? nextafter(x, -INFINITY) : x;
    *hi = c > 0 ? nextafter(x, INFINITY) : x;
    /* check the bracket exactly rather than trust the rounding direction */
    mpq_set_d(d, *lo);
    int ok = mpq_cmp(d, q) <= 0;
    mpq_set_d(d, *hi);
    ok = ok && mpq_cmp(q, d) <= 0;
    if (!ok || !isfinite(*lo) || !isfinite(*hi)) {
      snprintf(msg, len, "value cannot be bracketed by doubles");
      rc = -1;
    }
  }
  mpq_clear(a);
  mpq_clear(q);
  mpq_clear(d);
  return rc;
}

/* an optionally signed decimal integer in s[0..n) */
static int is_integer(const char *s, size_t n) {
  size_t i = 0;
  if (i < n && (s[i] == '-' || s[i] == '+')) i++;
  if (i == n) return 0;
  for (; i < n; i++)
    if (s[i] < '0' || s[i] > '9') return 0;
  return 1;
}

int cb_ccd_file_read(FILE *f, const char *name, cb_ccd_file *out) {
  memset(out, 0, sizeof *out);
  int cap = 0, rc = CB_OK;
  long line = 0;
  int row = 0; /* row within the current query, 0..7 */
  char *buf = NULL, *field = NULL;
  size_t bufcap = 0, fieldcap = 0;
  mpz_t num, den;
  mpz_init(num);
  mpz_init(den);
  cb_ccd_query cur;
  int truth = 0;
  ssize_t got;
  errno = 0;
  while ((got = getline(&buf, &bufcap, f)) >= 0) {
    line++;
    size_t n = (size_t)got;
    while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == '\r')) n--;
    buf[n] = '\0';
    if (n == 0) {
      rc = cb_fail("%s:%ld:1: empty line (each row holds x_num,x_den,y_num,y_den,z_num,z_den,truth)", name, line);
      goto done;
    }
    /* split into 7 fields */
    size_t start[7], len[7];
    int nf = 0;
    size_t s = 0;
    for (size_t i = 0; i <= n; i++)
      if (i == n || buf[i] == ',') {
        if (nf == 7) {
          rc = cb_fail("%s:%ld:%zu: more than 7 fields", name, line, s + 1);
          goto done;
        }
        start[nf] = s;
        len[nf] = i - s;
        nf++;
        s = i + 1;
      }
    if (nf != 7) {
      rc = cb_fail("%s:%ld:%zu: %d fields, expected 7 (x_num,x_den,y_num,y_den,z_num,z_den,truth)", name, line, n + 1,
                   nf);
      goto done;
    }
    for (int k = 0; k < 7; k++) {
      /* trim blanks */
      while (len[k] > 0 && (buf[start[k]] == ' ' || buf[start[k]] == '\t')) start[k]++, len[k]--;
      while (len[k] > 0 && (buf[start[k] + len[k] - 1] == ' ' || buf[start[k] + len[k] - 1] == '\t')) len[k]--;
      if (!is_integer(buf + start[k], len[k])) {
        rc = cb_fail("%s:%ld:%zu: '%.*s' is not an integer%s", name, line, start[k] + 1,
                     (int)(len[k] > 40 ? 40 : len[k]), buf + start[k], k == 6 ? " (truth: 0 or 1)" : "");
        goto done;
      }
      if (len[k] + 1 > fieldcap) {
        char *nb = realloc(field, len[k] + 1);
        if (!nb) {
          rc = cb_fail_status(CB_ENOMEM, "%s:%ld: out of memory", name, line);
          goto done;
        }
        field = nb;
        fieldcap = len[k] + 1;
      }
      memcpy(field, buf + start[k], len[k]);
      field[len[k]] = '\0';
      const char *digits = field[0] == '+' ? field + 1 : field;
      mpz_set_str(k % 2 == 0 ? num : den, digits, 10);
      if (k == 6) {
        if (mpz_cmp_ui(num, 0) != 0 && mpz_cmp_ui(num, 1) != 0) {
          rc = cb_fail("%s:%ld:%zu: truth '%s' is not 0 or 1", name, line, start[k] + 1, field);
          goto done;
        }
        int t = (int)mpz_get_ui(num);
        if (row == 0) truth = t;
        else if (t != truth) {
          rc = cb_fail("%s:%ld:%zu: truth %d differs from the query's first row (%d)", name, line, start[k] + 1, t,
                       truth);
          goto done;
        }
      } else if (k % 2 == 1) {
        char msg[80];
        int exact = 1, j = k / 2;
        if (to_interval(num, den, &cur.lo[row][j], &cur.hi[row][j], &exact, msg, sizeof msg)) {
          rc = cb_fail("%s:%ld:%zu: %s", name, line, start[k - 1] + 1, msg);
          goto done;
        }
        out->inexact += !exact;
      }
    }
    if (++row == 8) {
      if (out->n == cap) {
        int nc = cap ? 2 * cap : 64;
        cb_ccd_query *nq = realloc(out->q, (size_t)nc * sizeof *nq);
        if (nq) out->q = nq;
        int *nt = realloc(out->truth, (size_t)nc * sizeof *nt);
        if (nt) out->truth = nt;
        if (!nq || !nt) {
          rc = cb_fail_status(CB_ENOMEM, "%s:%ld: out of memory", name, line);
          goto done;
        }
        cap = nc;
      }
      out->q[out->n] = cur;
      out->truth[out->n] = truth;
      out->n++;
      row = 0;
    }
  }
  if (ferror(f)) {
    rc = cb_fail_status(CB_EIO, "%s:%ld: read error: %s", name, line + 1, strerror(errno));
    goto done;
  }
  if (row != 0) {
    rc = cb_fail("%s:%ld:1: the file ends inside a query (%ld rows, not a multiple of 8)", name, line + 1, line);
    goto done;
  }
done:
  free(buf);
  free(field);
  mpz_clear(num);
  mpz_clear(den);
  if (rc) cb_ccd_file_free(out);
  return rc;
}

int cb_ccd_file_load(const char *path, cb_ccd_file *out) {
  memset(out, 0, sizeof *out);
  FILE *f = fopen(path, "r");
  if (!f) return cb_fail_status(CB_EIO, "%s: cannot open: %s", path, strerror(errno));
  int rc = cb_ccd_file_read(f, path, out);
  fclose(f);
  return rc;
}

void cb_ccd_file_free(cb_ccd_file *file) {
  if (!file) return;
  free(file->q);
  free(file->truth);
  memset(file, 0, sizeof *file);
}
