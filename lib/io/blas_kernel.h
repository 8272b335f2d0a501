/* Which OpenBLAS kernel runs, and whether a better safe one exists.
 *
 * Debian's OpenBLAS (DYNAMIC_ARCH) picks its kernels at load time from the
 * CPU model it knows; on a CPU model it does not know it falls back to old
 * SSE3 kernels (openblas_get_corename() says "Prescott") even where the CPU
 * has AVX2+FMA or AVX-512. OPENBLAS_CORETYPE, read at load time, forces a
 * kernel. This module:
 *   - ranks OpenBLAS's x86-64 core names by the instruction set their
 *     kernels need, and names the best core the CPU's instruction set
 *     supports (AVX-512 F/BW/VL/DQ: SkylakeX; AVX2 + FMA: Haswell);
 *   - decides whether a run should get that core (only when
 *     OPENBLAS_CORETYPE is unset and the detected core ranks below it);
 *   - runs the numerical self-test a candidate must pass first (dgemm,
 *     dsyrk, dtrsm, dpotrf against straightforward loops, 1e-12 relative);
 *   - describes the kernel that runs for the provenance of every CSV.
 * The choice itself is made before a program starts, by build/blas-kernel
 * (tools/blas_kernel.c), which the Makefile puts in front of every program
 * make starts: it sets OPENBLAS_CORETYPE and CB_BLAS_CHOICE (what it did,
 * with the self-test's result) for the program it executes.
 *
 * For tests, CB_BLAS_TEST_CORENAME stands in for the detected core and
 * CB_BLAS_TEST_CPUFLAGS (a space-separated list as in /proc/cpuinfo, e.g.
 * "avx2 fma") for the CPU's flags, so the fallback path can be exercised on
 * a machine whose CPU OpenBLAS knows. */
#ifndef CB_BLAS_KERNEL_H
#define CB_BLAS_KERNEL_H

#include <stddef.h>
#include <stdio.h>

#define CB_BLAS_SELFTEST_TOL 1e-12

/* Instruction-set level of an OpenBLAS x86-64 core name (case-insensitive):
 * 0 SSE2/SSE3/SSE4, 1 AVX, 2 AVX2 + FMA, 3 AVX-512; -1 for a name this
 * table does not know (never replaced). */
int cb_blas_core_level(const char *core);

/* The best core the flags support ("SkylakeX" for avx512f avx512bw avx512vl
 * avx512dq, else "Haswell" for avx2 and fma), or NULL. flags: space- or
 * comma-separated words. */
const char *cb_blas_best_core(const char *flags);

/* The CPU's flags relevant here (CB_BLAS_TEST_CPUFLAGS if set, else cpuid
 * through __builtin_cpu_supports, which also checks the OS enables the
 * registers), written to out as space-separated words. */
void cb_blas_cpu_flags(char *out, size_t n);

/* The core OpenBLAS detected (CB_BLAS_TEST_CORENAME if set, else
 * openblas_get_corename()). *injected is set to 1 when it came from the
 * environment variable. */
const char *cb_blas_detected_core(int *injected);

/* What to do for a run: candidate is the core to try, or NULL with why
 * saying why not (OPENBLAS_CORETYPE set, the detected core is as good, no
 * better core, an unknown core name). env_coretype may be NULL (unset). */
typedef struct cb_blas_plan {
  const char *candidate;
  char why[256];
} cb_blas_plan;
void cb_blas_plan_make(const char *env_coretype, const char *detected, const char *flags, cb_blas_plan *p);

/* max_i |x_i - ref_i| / max_i |ref_i| (1 for a zero reference with a nonzero
 * x, inf for a NaN). */
double cb_blas_rel_error(const double *x, const double *ref, size_t n);

/* The self-test of the running kernel: dgemm (NN, TN, NT), dsyrk, dtrsm and
 * dpotrf on random matrices of sizes that cross OpenBLAS's blocking and its
 * edge kernels, against straightforward loops. Returns the largest relative
 * error (cb_blas_rel_error); msg gets "routine: error" of the worst one, or
 * the reason it could not run (then the return is a negative number). */
double cb_blas_selftest(char *msg, size_t n);

/* The running core (*core) and how it came to run (how): chosen by
 * clothbench (CB_BLAS_CHOICE, checked against OPENBLAS_CORETYPE and the
 * running core) with its self-test, set by the environment, or detected
 * (with a note when it is a fallback below what the CPU supports, and
 * clothbench's refusal with its reason if any). The provenance's
 * "# blas_kernel:" and "# blas_kernel_choice:" lines. */
void cb_blas_kernel_describe(const char **core, char *how, size_t n);

/* For a program run directly: when the running kernel is a detected
 * fallback below what the CPU supports, writes one line to f naming the
 * setting to use, prefixed by program; returns 1 if it wrote, else 0. */
int cb_blas_kernel_warning(FILE *f, const char *program);

#endif
