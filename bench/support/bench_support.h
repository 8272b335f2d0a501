/* What the bench programs share (linked into every bench/<name>.c program):
 * the heap-allocation counter and the STREAM triad they measure against. */
#ifndef CB_BENCH_SUPPORT_H
#define CB_BENCH_SUPPORT_H

#include <stddef.h>

/* Heap allocations (malloc, calloc, realloc, memalign, posix_memalign,
 * aligned_alloc) the whole process has made so far: bench_support.c
 * interposes them. Differences around a step count its allocations. */
long cb_bench_allocations(void);

/* STREAM triad a = b + s c over arrays far larger than the caches; bytes
 * counted as STREAM does: 3 x 8 per element (no write-allocate). */
typedef struct {
  size_t n;
  double *a, *b, *c;
} cb_triad;

int cb_triad_alloc(cb_triad *t);   /* 3 arrays of 2^25 doubles (256 MiB each); 0 or -1 */
double cb_triad_once(cb_triad *t); /* one pass; GB/s */
void cb_triad_free(cb_triad *t);

#endif
