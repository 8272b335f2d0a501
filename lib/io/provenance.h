/* Run-time set-up shared by every program, and the provenance lines that open
 * every CSV: git revision, compiler and flags, library versions, BLAS
 * threads, config, command and date. */
#ifndef CB_PROVENANCE_H
#define CB_PROVENANCE_H

#include <stdio.h>

#include "config.h"

/* Written by the build (build/version.c). */
extern const char cb_build_git[];   /* "abc1234" or "unknown" */
extern const char cb_build_dirty[]; /* "clean" or "dirty" */
extern const char cb_build_cflags[];

/* Turns GSL's abort-on-error handler off (we check return codes), and sets
 * the threads of OpenBLAS and of CHOLMOD's OpenMP regions from
 * OPENBLAS_NUM_THREADS and OMP_NUM_THREADS (default 1 each; threads.h), so
 * that timings compare and reruns agree. Call first thing in main(); a
 * non-zero return (a malformed variable) has its message in
 * cb_error_message(). */
int cb_runtime_init(void);

/* Writes s with backslash, newline, carriage return, tab and every other
 * control character escaped (\\ \n \r \t \xNN), so that a value (an
 * argument, a path, a --set value) can never end its "# key: value" line and
 * forge lines of the CSV. */
void cb_provenance_escaped(FILE *f, const char *s);
/* cb_config_write(cfg, f, " "), escaped the same way. */
void cb_provenance_config(FILE *f, const cb_config *cfg);

/* "model name" of the first processor in /proc/cpuinfo, or "unknown". */
void cb_cpu_model(char *out, size_t n);

/* "# key: value" lines (every value escaped by cb_provenance_escaped),
 * including the BLAS kernel and how it was chosen (blas_kernel.h), the
 * requested and the observed thread counts (the first call runs
 * the probes of threads.h, a few ms). cfg may be NULL (experiments describe their sweep in
 * extra lines); argv is echoed as the command. */
void cb_provenance_write(FILE *f, const char *program, int argc, char **argv, const cb_config *cfg);

#endif
