/* Where a factorisation's time goes inside the BLAS: bench/support/
 * blas_profile.c interposes the four routines CHOLMOD's supernodal
 * factorisation calls (dgemm_, dsyrk_, dtrsm_, dpotrf_) and, while
 * switched on, times each outermost call and sorts it by its flop count.
 * Off (the default) a call costs one branch more. */
#ifndef CB_BLAS_PROFILE_H
#define CB_BLAS_PROFILE_H

enum { CB_BLAS_GEMM, CB_BLAS_SYRK, CB_BLAS_TRSM, CB_BLAS_POTRF, CB_BLAS_NROUTINES };
enum { CB_BLAS_NCLASSES = 4 }; /* flops per call < 1e4, < 1e6, < 1e8, >= 1e8 */

typedef struct {
  long calls[CB_BLAS_NROUTINES][CB_BLAS_NCLASSES];
  double ms[CB_BLAS_NROUTINES][CB_BLAS_NCLASSES];
  double flops[CB_BLAS_NROUTINES][CB_BLAS_NCLASSES]; /* 2 per multiply-add, as Common->fl counts */
} cb_blas_profile;

void cb_blas_profile_start(void);                /* zero the counts and switch timing on */
void cb_blas_profile_stop(cb_blas_profile *out); /* switch off and copy the counts */
const char *cb_blas_routine_name(int routine);   /* "dgemm", ... */
const char *cb_blas_class_name(int cls);         /* "<1e4", ... */

#endif
