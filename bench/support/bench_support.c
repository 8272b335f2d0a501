#define _GNU_SOURCE
#include "bench_support.h"

#include <malloc.h>
#include <stdlib.h>

#include <clothbench/timer.h>

/* ---- allocation counter: interposes malloc & co. for the whole process ----
 * The functions carry their own names; the link gives them libc's (Makefile:
 * BENCH_INTERPOSE, ld --defsym malloc=cb_bench_malloc and so on), so every
 * allocation of the process, CHOLMOD's and OpenBLAS's included, comes here,
 * while the library's sources only ever call libc's malloc. */
extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void *__libc_memalign(size_t, size_t);
void *cb_bench_malloc(size_t n);
void *cb_bench_calloc(size_t a, size_t b);
void *cb_bench_realloc(void *p, size_t n);
void *cb_bench_memalign(size_t a, size_t n);
int cb_bench_posix_memalign(void **p, size_t a, size_t n);
void *cb_bench_aligned_alloc(size_t a, size_t n);
static long nalloc;
void *cb_bench_malloc(size_t n) {
  nalloc++;
  return __libc_malloc(n);
}
void *cb_bench_calloc(size_t a, size_t b) {
  nalloc++;
  return __libc_calloc(a, b);
}
void *cb_bench_realloc(void *p, size_t n) {
  nalloc++;
  return __libc_realloc(p, n);
}
void *cb_bench_memalign(size_t a, size_t n) {
  nalloc++;
  return __libc_memalign(a, n);
}
int cb_bench_posix_memalign(void **p, size_t a, size_t n) {
  nalloc++;
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;
}
void *cb_bench_aligned_alloc(size_t a, size_t n) {
  nalloc++;
  return __libc_memalign(a, n);
}

long cb_bench_allocations(void) { return nalloc; }

/* ---- STREAM triad ---- */
int cb_triad_alloc(cb_triad *t) {
  t->n = (size_t)1 << 25; /* 32M doubles = 256 MiB per array */
  t->a = malloc(t->n * sizeof(double));
  t->b = malloc(t->n * sizeof(double));
  t->c = malloc(t->n * sizeof(double));
  if (!t->a || !t->b || !t->c) return -1;
  for (size_t i = 0; i < t->n; i++) {
    t->a[i] = 0;
    t->b[i] = 1.0;
    t->c[i] = 2.0;
  }
  return 0;
}

double cb_triad_once(cb_triad *t) {
  double t0 = cb_now_ms();
  for (size_t i = 0; i < t->n; i++) t->a[i] = t->b[i] + 3.0 * t->c[i];
  double ms = cb_now_ms() - t0;
  return 24.0 * (double)t->n / (ms * 1e-3) / 1e9;
}

void cb_triad_free(cb_triad *t) {
  free(t->a);
  free(t->b);
  free(t->c);
  t->a = t->b = t->c = NULL;
}
