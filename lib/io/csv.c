#include "csv.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <clothbench/status.h>

/* a quiet NaN (exponent all ones, top mantissa bit set) with payload 0x4e41 ("NA") */
#define NA_BITS UINT64_C(0x7ff8000000004e41)
#define SIGN_BIT UINT64_C(0x8000000000000000)

double cb_csv_na(void) {
  uint64_t u = NA_BITS;
  double v;
  memcpy(&v, &u, sizeof v);
  return v;
}

int cb_csv_is_na(double v) {
  uint64_t u;
  memcpy(&u, &v, sizeof u);
  return (u & ~SIGN_BIT) == NA_BITS;
}

double cb_csv_na_if_nan(double v) { return isnan(v) ? cb_csv_na() : v; }

/* a non-finite or NA double: its spelling ("" for NA); NULL for a finite one */
static const char *special(long double v) {
  if (isnan(v)) return cb_csv_is_na((double)v) ? "" : "nan";
  if (isinf(v)) return v > 0 ? "inf" : "-inf";
  return NULL;
}

enum { LEN_NONE, LEN_HH, LEN_H, LEN_L, LEN_LL, LEN_J, LEN_Z, LEN_T, LEN_BIG_L };

/* One conversion: spec is "%<flags><width><.prec><length><conv>" with any
 * '*' already replaced by digits. Returns what fprintf returns. spec is one
 * conversion cut from the caller's format, which the compiler checked
 * (cb_csv_printf's format attribute), hence no -Wformat-nonliteral here. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
static int convert(FILE *f, const char *spec, int len, char conv, va_list *ap) {
  switch (conv) {
  case 'd':
  case 'i':
    switch (len) {
    case LEN_L: return fprintf(f, spec, va_arg(*ap, long));
    case LEN_LL: return fprintf(f, spec, va_arg(*ap, long long));
    case LEN_J: return fprintf(f, spec, va_arg(*ap, intmax_t));
    case LEN_Z: return fprintf(f, spec, va_arg(*ap, ptrdiff_t)); /* the signed type of size_t's width */
    case LEN_T: return fprintf(f, spec, va_arg(*ap, ptrdiff_t));
    default: return fprintf(f, spec, va_arg(*ap, int)); /* hh, h: promoted to int */
    }
  case 'u':
  case 'o':
  case 'x':
  case 'X':
    switch (len) {
    case LEN_L: return fprintf(f, spec, va_arg(*ap, unsigned long));
    case LEN_LL: return fprintf(f, spec, va_arg(*ap, unsigned long long));
    case LEN_J: return fprintf(f, spec, va_arg(*ap, uintmax_t));
    case LEN_Z: return fprintf(f, spec, va_arg(*ap, size_t));
    case LEN_T: return fprintf(f, spec, va_arg(*ap, size_t));
    default: return fprintf(f, spec, va_arg(*ap, unsigned));
    }
  case 'c': return fprintf(f, spec, va_arg(*ap, int));
  case 's': return fprintf(f, spec, va_arg(*ap, const char *));
  case 'p': return fprintf(f, spec, va_arg(*ap, void *));
  case 'f':
  case 'F':
  case 'e':
  case 'E':
  case 'g':
  case 'G':
  case 'a':
  case 'A': {
    if (len == LEN_BIG_L) {
      long double v = va_arg(*ap, long double);
      const char *s = special(v);
      return s ? fputs(s, f) < 0 ? -1 : (int)strlen(s) : fprintf(f, spec, v);
    }
    double v = va_arg(*ap, double);
    const char *s = special(v);
    return s ? fputs(s, f) < 0 ? -1 : (int)strlen(s) : fprintf(f, spec, v);
  }
  default: return -1; /* %n and anything unknown */
  }
}
#pragma GCC diagnostic pop

int cb_csv_vprintf(FILE *f, const char *fmt, va_list ap) {
  va_list aq;
  va_copy(aq, ap);
  long total = 0;
  int st = 0;
  for (const char *p = fmt; *p && st >= 0;) {
    if (*p != '%') { /* literal text up to the next conversion */
      size_t n = strcspn(p, "%");
      if (fwrite(p, 1, n, f) != n) st = -1;
      total += (long)n;
      p += n;
      continue;
    }
    if (p[1] == '%') {
      if (fputc('%', f) == EOF) st = -1;
      total++;
      p += 2;
      continue;
    }
    char spec[64];
    size_t k = 0;
    spec[k++] = *p++;
    while (*p && strchr("-+ #0'", *p) && k < 40) spec[k++] = *p++;
    if (*p == '*') { /* width from the arguments */
      k += (size_t)snprintf(spec + k, sizeof spec - k, "%d", va_arg(aq, int));
      p++;
    } else
      while (*p >= '0' && *p <= '9' && k < 48) spec[k++] = *p++;
    if (*p == '.') {
      p++;
      int prec = 0;
      if (*p == '*') {
        prec = va_arg(aq, int);
        p++;
      } else
        while (*p >= '0' && *p <= '9') prec = 10 * prec + (*p++ - '0');
      if (prec >= 0) k += (size_t)snprintf(spec + k, sizeof spec - k, ".%d", prec); /* a negative one: as if omitted */
    }
    int len = LEN_NONE;
    if (*p == 'h') {
      len = p[1] == 'h' ? LEN_HH : LEN_H;
      p += len == LEN_HH ? 2 : 1;
    } else if (*p == 'l') {
      len = p[1] == 'l' ? LEN_LL : LEN_L;
      p += len == LEN_LL ? 2 : 1;
    } else if (*p == 'j') {
      len = LEN_J;
      p++;
    } else if (*p == 'z') {
      len = LEN_Z;
      p++;
    } else if (*p == 't') {
      len = LEN_T;
      p++;
    } else if (*p == 'L') {
      len = LEN_BIG_L;
      p++;
    }
    static const char *const mods[] = {"", "hh", "h", "l", "ll", "j", "z", "t", "L"};
    char conv = *p;
    if (!conv || k + 4 >= sizeof spec) {
      st = -1;
      break;
    }
    p++;
    k += (size_t)snprintf(spec + k, sizeof spec - k, "%s%c", mods[len], conv);
    int w = convert(f, spec, len, conv, &aq);
    if (w < 0) st = -1;
    else total += w;
  }
  va_end(aq);
  if (st < 0 || ferror(f)) return -1;
  return total > 0x7fffffff ? 0x7fffffff : (int)total;
}

int cb_csv_printf(FILE *f, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int n = cb_csv_vprintf(f, fmt, ap);
  va_end(ap);
  return n;
}

/* ---- the rows of the instruments' timings and of simulate's trajectories ---- */

void cb_timing_csv(FILE *f, const cb_timing *t, double scale) {
  if (t->n == 0) { /* not measured: three empty fields */
    double na = cb_csv_na();
    cb_csv_printf(f, "%.6f,%.6f,%.6f", na, na, na);
    return;
  }
  cb_csv_printf(f, "%.6f,%.6f,%.6f", cb_timing_median(t) * scale, cb_timing_min(t) * scale, cb_timing_max(t) * scale);
}

void cb_timing_csv_each(FILE *f, const cb_timing *t, double scale) {
  for (int i = 0; i < t->n; i++) cb_csv_printf(f, "%s%.6f", i ? ";" : "", t->ms[i] * scale);
}

void cb_run_csv_header(FILE *f) { cb_run_csv_header_extra(f, NULL); }

void cb_run_csv_header_extra(FILE *f, const char *extra) {
  fputs("step,t_s,kinetic_j,elastic_j,gravity_j,total_j,pin_work_j,newton_iters,rel_grad,rel_grad_hat,linear_iters,"
        "assemble_ms,factor_ms,solve_ms,wall_ms,status,contacts,rho",
        f);
  if (extra) fprintf(f, ",%s", extra);
  fputc('\n', f);
}

void cb_run_csv_row(FILE *f, const cb_run *r, int status) { cb_run_csv_row_extra(f, r, status, NULL); }

void cb_run_csv_row_extra(FILE *f, const cb_run *r, int status, const char *extra) {
  const cb_step_stats *s = &r->last;
  /* the Chebyshev rho the step used, given or estimated (rho = auto): the integrator's, else its linear solver's */
  double rho = s->rho > 0 ? s->rho : r->integ->solver ? r->integ->solver->stats.rho : 0.0;
  cb_csv_printf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%d,%.6f,%.6f,%.6f,%.6f,%s,%d,%.17g", r->step,
                r->t, r->kinetic, r->elastic, r->gravity, r->kinetic + r->potential, r->work, s->newton_iters,
                s->rel_grad, s->rel_grad_hat, s->linear_iters, s->assemble_ms, s->factor_ms, s->solve_ms, s->wall_ms,
                cb_status_name(status), cb_scene_contacts(r->scene, r->x), rho);
  if (extra) fprintf(f, ",%s", extra);
  fputc('\n', f);
}

void cb_timing_csv_repeats(FILE *f, const cb_timing *t) {
  cb_timing none = {0}; /* not timed: every field empty */
  cb_timing_csv(f, t ? t : &none, 1.0);
  fputc(',', f);
  if (t) cb_timing_csv_each(f, t, 1.0);
  cb_csv_printf(f, ",%.17g", t ? (double)t->n : cb_csv_na());
}
