/* One thread knob for every library that starts threads, and a way to see
 * how many threads actually ran.
 *
 * Two libraries start threads in this process: OpenBLAS (its own pthread
 * pool, sized by OPENBLAS_NUM_THREADS or openblas_set_num_threads) and
 * CHOLMOD, whose supernodal factorisation opens OpenMP regions with a
 * hard-coded num_threads(4) clause in Debian's build, which OMP_NUM_THREADS
 * does not cap. libgomp's dynamic adjustment does cap it: with
 * omp_set_dynamic(1) a region gets at most min(clause, nthreads-var, online
 * CPUs) threads (fewer when the 15-minute load average is high), so
 * omp_set_num_threads(n) + omp_set_dynamic(1) bounds every region by n.
 *
 * The requested count comes from the environment the Makefile's THREADS=n
 * knob sets (OPENBLAS_NUM_THREADS and OMP_NUM_THREADS; each defaults to 1).
 * What actually ran is measured, by the probes of
 * lib/instruments/thread_probe.h (cb_threads_info_get runs them once). */
#ifndef CB_THREADS_H
#define CB_THREADS_H

typedef struct cb_threads_info {
  int blas_requested;   /* OpenBLAS threads set at start-up */
  int omp_requested;    /* OpenMP nthreads-var set at start-up (dynamic adjustment on) */
  int cholmod_observed; /* threads that ran during a CHOLMOD supernodal factorisation of the probe */
  int dgemm_observed;   /* threads that ran during an OpenBLAS dgemm of the probe */
} cb_threads_info;

/* Reads OPENBLAS_NUM_THREADS and OMP_NUM_THREADS (unset or empty: 1) and
 * applies them to OpenBLAS and libgomp (with dynamic adjustment on).
 * Returns CB_OK, or CB_EINVAL with a message when a variable is not an
 * integer in 1..1024. Called by cb_runtime_init. */
int cb_threads_init(void);

/* The requested counts, and the observed ones measured once per process on
 * a fixed probe (thread_probe.h: a CHOLMOD supernodal factorisation and a
 * dgemm). An observed count < 0 means it could not be measured. */
const cb_threads_info *cb_threads_info_get(void);

#endif
