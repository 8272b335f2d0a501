#include "threads.h"

#include <cblas.h>
#include <errno.h>
#include <omp.h>
#include <stdlib.h>

#include <clothbench/status.h>

#include "thread_probe.h"

static cb_threads_info info = {1, 1, -2, -2}; /* -2: not measured yet */

static int env_threads(const char *name, int *out) {
  const char *s = getenv(name);
  *out = 1;
  if (!s || !*s) return CB_OK;
  char *end;
  errno = 0;
  long v = strtol(s, &end, 10);
  if (errno || end == s || *end || v < 1 || v > 1024)
    return cb_fail("%s='%s': must be a thread count in 1..1024 (make's THREADS=n sets it)", name, s);
  *out = (int)v;
  return CB_OK;
}

int cb_threads_init(void) {
  int st = env_threads("OPENBLAS_NUM_THREADS", &info.blas_requested);
  if (st == CB_OK) st = env_threads("OMP_NUM_THREADS", &info.omp_requested);
  if (st) return st;
  openblas_set_num_threads(info.blas_requested);
  omp_set_num_threads(info.omp_requested);
  omp_set_dynamic(1); /* caps CHOLMOD's num_threads(4) clauses at nthreads-var */
  return CB_OK;
}

const cb_threads_info *cb_threads_info_get(void) {
  if (info.cholmod_observed == -2) {
    info.dgemm_observed = cb_thread_probe_dgemm();
    info.cholmod_observed = cb_thread_probe_cholmod();
  }
  return &info;
}
