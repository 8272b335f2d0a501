#include <clothbench/csv.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

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
  case 'd': case 'i':
    switch (len) {
    case LEN_L: return fprintf(f, spec, va_arg(*ap, long));
    case LEN_LL: return fprintf(f, spec, va_arg(*ap, long long));
    case LEN_J: return fprintf(f, spec, va_arg(*ap, intmax_t));
    case LEN_Z: return fprintf(f, spec, va_arg(*ap, ptrdiff_t)); /* the signed type of size_t's width */
    case LEN_T: return fprintf(f, spec, va_arg(*ap, ptrdiff_t));
    default: return fprintf(f, spec, va_arg(*ap, int)); /* hh, h: promoted to int */
    }
  case 'u': case 'o': case 'x': case 'X':
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
  case 'f': case 'F': case 'e': case 'E': case 'g': case 'G': case 'a': case 'A': {
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
    if (*p == 'h') { len = p[1] == 'h' ? LEN_HH : LEN_H; p += len == LEN_HH ? 2 : 1; }
    else if (*p == 'l') { len = p[1] == 'l' ? LEN_LL : LEN_L; p += len == LEN_LL ? 2 : 1; }
    else if (*p == 'j') { len = LEN_J; p++; }
    else if (*p == 'z') { len = LEN_Z; p++; }
    else if (*p == 't') { len = LEN_T; p++; }
    else if (*p == 'L') { len = LEN_BIG_L; p++; }
    static const char *const mods[] = {"", "hh", "h", "l", "ll", "j", "z", "t", "L"};
    char conv = *p;
    if (!conv || k + 4 >= sizeof spec) { st = -1; break; }
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
