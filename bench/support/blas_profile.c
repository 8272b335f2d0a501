/* BLAS-call profile (blas_profile.h). cb_bench_dgemm and the others are
 * linked under the Fortran BLAS names (Makefile: BENCH_INTERPOSE, ld --defsym
 * dgemm_=cb_bench_dgemm and so on), so CHOLMOD's calls into OpenBLAS come
 * here first. The real routines are resolved with
 * dlsym(RTLD_NEXT) on first use, so a program that links this file but
 * never calls them needs no BLAS. Nested calls (a LAPACK routine calling
 * dgemm_ through the PLT) are timed once, as part of the outermost call. */
#define _GNU_SOURCE
#include "blas_profile.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/timer.h>

static int on, depth;
static cb_blas_profile prof;

/* The next definition of name into *fn (a function pointer of sizeof(void *);
 * copied, as POSIX allows, since ISO C has no object-to-function cast). */
static void resolve(const char *name, void *fn) {
  void *f = dlsym(RTLD_NEXT, name);
  if (!f) {
    fprintf(stderr, "blas_profile: %s not found in the libraries after the program (%s)\n", name, dlerror());
    abort();
  }
  memcpy(fn, &f, sizeof f);
}

static int class_of(double flops) { return flops < 1e4 ? 0 : flops < 1e6 ? 1 : flops < 1e8 ? 2 : 3; }

static double enter(void) { return on && depth++ == 0 ? cb_now_ms() : 0.0; }

static void leave(int routine, double t0, double flops) {
  if (!on || --depth) return;
  int c = class_of(flops);
  prof.calls[routine][c]++;
  prof.ms[routine][c] += cb_now_ms() - t0;
  prof.flops[routine][c] += flops;
}

typedef void gemm_fn(const char *, const char *, const int *, const int *, const int *, const double *, const double *,
                     const int *, const double *, const int *, const double *, double *, const int *);
typedef void syrk_fn(const char *, const char *, const int *, const int *, const double *, const double *, const int *,
                     const double *, double *, const int *);
typedef void trsm_fn(const char *, const char *, const char *, const char *, const int *, const int *, const double *,
                     const double *, const int *, double *, const int *);
typedef void potrf_fn(const char *, const int *, double *, const int *, int *);

void cb_bench_dgemm(const char *ta, const char *tb, const int *m, const int *n, const int *k, const double *alpha,
                    const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c,
                    const int *ldc);
void cb_bench_dsyrk(const char *uplo, const char *tr, const int *n, const int *k, const double *alpha, const double *a,
                    const int *lda, const double *beta, double *c, const int *ldc);
void cb_bench_dtrsm(const char *side, const char *uplo, const char *tr, const char *diag, const int *m, const int *n,
                    const double *alpha, const double *a, const int *lda, double *b, const int *ldb);
void cb_bench_dpotrf(const char *uplo, const int *n, double *a, const int *lda, int *info);

void cb_bench_dgemm(const char *ta, const char *tb, const int *m, const int *n, const int *k, const double *alpha,
                    const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c,
                    const int *ldc) {
  static gemm_fn *f;
  if (!f) resolve("dgemm_", &f);
  double t0 = enter();
  f(ta, tb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
  leave(CB_BLAS_GEMM, t0, 2.0 * *m * *n * *k);
}

void cb_bench_dsyrk(const char *uplo, const char *tr, const int *n, const int *k, const double *alpha, const double *a,
                    const int *lda, const double *beta, double *c, const int *ldc) {
  static syrk_fn *f;
  if (!f) resolve("dsyrk_", &f);
  double t0 = enter();
  f(uplo, tr, n, k, alpha, a, lda, beta, c, ldc);
  leave(CB_BLAS_SYRK, t0, (double)*n * (*n + 1) * *k);
}

void cb_bench_dtrsm(const char *side, const char *uplo, const char *tr, const char *diag, const int *m, const int *n,
                    const double *alpha, const double *a, const int *lda, double *b, const int *ldb) {
  static trsm_fn *f;
  if (!f) resolve("dtrsm_", &f);
  double t0 = enter();
  f(side, uplo, tr, diag, m, n, alpha, a, lda, b, ldb);
  double tri = (*side == 'L' || *side == 'l') ? *m : *n, other = (*side == 'L' || *side == 'l') ? *n : *m;
  leave(CB_BLAS_TRSM, t0, tri * tri * other);
}

void cb_bench_dpotrf(const char *uplo, const int *n, double *a, const int *lda, int *info) {
  static potrf_fn *f;
  if (!f) resolve("dpotrf_", &f);
  double t0 = enter();
  f(uplo, n, a, lda, info);
  leave(CB_BLAS_POTRF, t0, (double)*n * *n * *n / 3.0);
}

void cb_blas_profile_start(void) {
  memset(&prof, 0, sizeof prof);
  depth = 0;
  on = 1;
}

void cb_blas_profile_stop(cb_blas_profile *out) {
  on = 0;
  if (out) *out = prof;
}

const char *cb_blas_routine_name(int routine) {
  static const char *const names[] = {"dgemm", "dsyrk", "dtrsm", "dpotrf"};
  return routine >= 0 && routine < CB_BLAS_NROUTINES ? names[routine] : "?";
}

const char *cb_blas_class_name(int cls) {
  static const char *const names[] = {"<1e4", "1e4-1e6", "1e6-1e8", ">=1e8"};
  return cls >= 0 && cls < CB_BLAS_NCLASSES ? names[cls] : "?";
}
