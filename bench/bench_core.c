/* bench_core: what one step costs, and how close the sparse matrix-vector
 * product gets to the memory bandwidth. For grids of 32^2 .. 256^2 (the lab
 * scene's cloth at finer resolution) it records, as medians of repeated runs
 * at a mid-simulation state:
 *   - one explicit step; one Newton iteration with CHOLMOD split into
 *     assembly (gradient + Hessian), numeric factorisation and solve;
 *   - the DOFs and the nonzeros of A and of CHOLMOD's factor L;
 *   - heap allocations made inside a step (malloc is interposed below and
 *     counted, including calls from CHOLMOD and OpenBLAS);
 *   - the SpMV's achieved bandwidth (bytes moved / time) next to a
 *     STREAM-triad bandwidth measured in the same run.
 * Output: results/bench_core.csv (make bench). */
#define _GNU_SOURCE
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include <clothbench/timer.h>
#include "stats.h"

/* ---- allocation counter: interposes malloc & co. for the whole process ---- */
extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void *__libc_memalign(size_t, size_t);
static long nalloc;
void *malloc(size_t n) { nalloc++; return __libc_malloc(n); }
void *calloc(size_t a, size_t b) { nalloc++; return __libc_calloc(a, b); }
void *realloc(void *p, size_t n) { nalloc++; return __libc_realloc(p, n); }
void *memalign(size_t a, size_t n) { nalloc++; return __libc_memalign(a, n); }
int posix_memalign(void **p, size_t a, size_t n) { nalloc++; *p = __libc_memalign(a, n); return *p ? 0 : 12; }
void *aligned_alloc(size_t a, size_t n) { nalloc++; return __libc_memalign(a, n); }

/* STREAM triad a = b + s c over arrays far larger than the caches; bytes
 * counted as STREAM does: 3 x 8 per element (no write-allocate). */
typedef struct {
  size_t n;
  double *a, *b, *c;
} triad_arrays;

static int triad_alloc(triad_arrays *t) {
  t->n = (size_t)1 << 25; /* 32M doubles = 256 MiB per array */
  t->a = malloc(t->n * sizeof(double));
  t->b = malloc(t->n * sizeof(double));
  t->c = malloc(t->n * sizeof(double));
  if (!t->a || !t->b || !t->c) return -1;
  for (size_t i = 0; i < t->n; i++) { t->a[i] = 0; t->b[i] = 1.0; t->c[i] = 2.0; }
  return 0;
}

/* One triad pass; returns GB/s. */
static double triad_once(triad_arrays *t) {
  double t0 = cb_now_ms();
  for (size_t i = 0; i < t->n; i++) t->a[i] = t->b[i] + 3.0 * t->c[i];
  double ms = cb_now_ms() - t0;
  return 24.0 * (double)t->n / (ms * 1e-3) / 1e9;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bench_core", "Per-step cost of the core and SpMV bandwidth against a STREAM triad.", argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* its numbers include wall times: run alone */
  const int sizes[] = {32, 64, 128, 256};
  const int nsizes = e.quick ? 2 : 4;
  cb_outfile csv;
  if (cb_experiment_csv(&e, &csv, NULL,
                        "# bytes moved by one SpMV (cb_sparse_matvec_bytes): 8 nnz (values) + 4 nnz/9 (block-row indices) + 4 (n/3+1) + 16 n (x read, y written)\n"
                        "# allocs_*: heap allocations inside one step after warm-up; newton_iterative: the most over CG, PCG and Chebyshev (rho = auto) as the inner solver (our code only),\n"
                        "#   newton_cholmod adds CHOLMOD's own (its permuted copy of A, workspace, and libgomp's per-parallel-region teams)\n"
                        "# triad: a = b + s c over 3 arrays of 2^25 doubles, 24 bytes per element (STREAM convention), median of passes interleaved with the SpMV samples\n",
                        "n,dofs,nnz_a,nnz_l,explicit_step_ms,assemble_ms,factor_ms,solve_ms,newton_iter_ms,"
                        "assemble_over_factor,allocs_explicit_step,allocs_newton_iterative_step,allocs_newton_cholmod_step,spmv_ms,spmv_gbs,triad_gbs,spmv_over_triad,status")) {
    fprintf(stderr, "bench_core: %s\n", cb_error_message());
    return 2;
  }
  triad_arrays ta;
  if (triad_alloc(&ta)) { fprintf(stderr, "bench_core: out of memory for the triad arrays\n"); return 1; }
  cb_progress_start(&e.progress, "bench_core", nsizes);
  for (int si = 0; si < nsizes; si++) {
    int n = sizes[si];
    char setn[64];
    snprintf(setn, sizeof setn, "mesh.n=%d", n);
    const char *sets[] = {setn, NULL};
    cb_config cfg;
    cb_scene *s = NULL;
    cb_integrator *nt = NULL, *ex = NULL;
    if (cb_experiment_config(&e, "hanging.ini", sets, &cfg) || cb_scene_from_config(&cfg, &s) || cb_integrator_from_config(&cfg, s, NULL, &nt)) {
      fprintf(stderr, "bench_core: %s\n", cb_error_message());
      return 1;
    }
    cb_integrator_params ep = nt->params;
    ep.dt = 1e-5;
    cb_integrator_alloc("explicit", s, &ep, NULL, NULL, NULL, &ex);
    int nv3 = 3 * s->mesh.nv, reps = n >= 256 ? 5 : n >= 128 ? 7 : 11;
    double *x = malloc((size_t)nv3 * sizeof *x), *v = malloc((size_t)nv3 * sizeof *v);
    double *xs = malloc((size_t)nv3 * sizeof *xs), *vs = malloc((size_t)nv3 * sizeof *vs);
    double *g = malloc((size_t)nv3 * sizeof *g);
    memcpy(x, s->x0, (size_t)nv3 * sizeof *x);
    memcpy(v, s->v0, (size_t)nv3 * sizeof *v);
    cb_step_stats st;
    int status = CB_OK;
    for (int k = 0; k < 3 && !cb_status_is_fatal(status); k++) status = cb_integrator_step(nt, x, v, &st); /* swing a little */
    memcpy(xs, x, (size_t)nv3 * sizeof *x);
    memcpy(vs, v, (size_t)nv3 * sizeof *v);
    /* allocations inside one Newton step and one explicit step (after warm-up) */
    long a0 = nalloc;
    cb_integrator_step(nt, x, v, &st);
    long allocs_newton = nalloc - a0;
    long allocs_iter = 0; /* Newton with each iterative solver (Chebyshev with rho = auto) */
    const char *iters[] = {"cg", "pcg", "chebyshev"};
    for (int q = 0; q < 3; q++) {
      cb_solver_params sp = cb_solver_params_default();
      sp.max_iters = 200;
      sp.alpha = 0.4;
      cb_integrator *it = NULL;
      if (cb_integrator_alloc("newton", s, &nt->params, nt->type_params, iters[q], &sp, &it)) continue;
      cb_integrator_step(it, x, v, &st);
      a0 = nalloc;
      cb_integrator_step(it, x, v, &st);
      if (nalloc - a0 > allocs_iter) allocs_iter = nalloc - a0;
      cb_integrator_free(it);
    }
    cb_integrator_step(ex, x, v, &st);
    a0 = nalloc;
    cb_integrator_step(ex, x, v, &st);
    long allocs_explicit = nalloc - a0;
    /* explicit step */
    double tex[16], tas[16], tfa[16], tso[16], tmv[16];
    for (int k = 0; k < reps; k++) {
      memcpy(x, xs, (size_t)nv3 * sizeof *x);
      memcpy(v, vs, (size_t)nv3 * sizeof *v);
      cb_integrator_step(ex, x, v, &st);
      tex[k] = st.wall_ms;
    }
    /* one Newton iteration at the saved state, split into its parts */
    cb_sparse *A = &s->sys.A;
    double *b = malloc((size_t)A->n * sizeof *b), *dx = malloc((size_t)A->n * sizeof *dx), *y = malloc((size_t)A->n * sizeof *y);
    for (int i = 0; i < A->n; i++) b[i] = 1.0;
    for (int k = 0; k < reps; k++) {
      double t0 = cb_now_ms();
      cb_system_energy(&s->sys, xs, g, NULL);
      cb_system_assemble(&s->sys, xs, 1.0 / (cfg.dt * cfg.dt), CB_DEF_DROP, 0.0);
      tas[k] = cb_now_ms() - t0;
      t0 = cb_now_ms();
      status = cb_solver_factor(nt->solver, A);
      tfa[k] = cb_now_ms() - t0;
      t0 = cb_now_ms();
      if (status == CB_OK) status = cb_solver_solve(nt->solver, A, b, dx);
      tso[k] = cb_now_ms() - t0;
    }
    /* SpMV (enough products per sample for ~20 ms), interleaved with triad
     * passes so that both see the same machine */
    int inner = 1 + (int)(2e7 / (double)A->nnz);
    double ttr[16];
    for (int k = 0; k < reps; k++) {
      ttr[k] = triad_once(&ta);
      double t0 = cb_now_ms();
      for (int q = 0; q < inner; q++) cb_sparse_matvec(A, q & 1 ? y : b, q & 1 ? dx : y);
      tmv[k] = (cb_now_ms() - t0) / inner;
    }
    double triad = cb_median(ttr, reps);
    double mas = cb_median(tas, reps), mfa = cb_median(tfa, reps), mso = cb_median(tso, reps), mmv = cb_median(tmv, reps);
    double bytes = (double)cb_sparse_matvec_bytes(A);
    double gbs = bytes / (mmv * 1e-3) / 1e9;
    fprintf(csv.f, "%d,%d,%d,%.17g,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%ld,%ld,%ld,%.6f,%.6f,%.6f,%.6f,%s\n", n, A->n, A->nnz,
            nt->solver->stats.factor_nnz, cb_median(tex, reps), mas, mfa, mso, mas + mfa + mso, mas / mfa, allocs_explicit,
            allocs_iter, allocs_newton, mmv, gbs, triad, gbs / triad, cb_status_name(status));
    fflush(csv.f);
    free(x); free(v); free(xs); free(vs); free(g); free(b); free(dx); free(y);
    cb_integrator_free(ex);
    cb_integrator_free(nt);
    cb_scene_free(s);
    cb_progress_update(&e.progress, si + 1);
  }
  cb_progress_end(&e.progress);
  free(ta.a); free(ta.b); free(ta.c);
  if (cb_outfile_commit(&csv)) { fprintf(stderr, "bench_core: %s\n", cb_error_message()); return 2; }
  fprintf(stderr, "bench_core: wrote %s\n", e.out);
  return 0;
}
