/* bench_core: what one step costs, how close the factorisation gets to the
 * machine's dgemm, and how close the sparse matrix-vector product gets to
 * the memory bandwidth. For grids of 32^2 .. 256^2 (the lab scene's cloth at
 * finer resolution) it records, as medians with min and max of repeated runs
 * at a mid-simulation state:
 *   - one explicit step; one Newton iteration with CHOLMOD split into
 *     assembly (gradient + Hessian), numeric factorisation and solve;
 *   - the same factorisation by bare CHOLMOD (its own defaults, our arrays),
 *     once under the thread settings every program uses and once with
 *     libgomp's dynamic adjustment off (Debian's CHOLMOD then starts its
 *     hard-coded 4 threads), paired sample by sample, with the threads
 *     observed during each (thread_probe.h);
 *   - factorisation GFlop/s (Common->fl / time) next to a single-thread
 *     dgemm interleaved with it, and the analysis next to the
 *     factorisations of a run (integrator.steps x Newton iterations);
 *   - the DOFs and the nonzeros of A and of CHOLMOD's factor L;
 *   - heap allocations made inside a step (malloc is interposed below and
 *     counted, including calls from CHOLMOD and OpenBLAS);
 *   - the SpMV of the iterative solvers (upper-block storage) and of the
 *     full matrix: achieved bandwidth (bytes moved / time) next to a
 *     STREAM-triad bandwidth measured interleaved with it.
 * Side files: results/bench_core_cholmod.csv (ordering x supernode
 * relaxation x storage x subnormals, the table behind the solver.*
 * defaults), results/bench_core_blas.csv (one more factorisation per size
 * with CHOLMOD's BLAS calls timed by routine and size: where the gap to
 * dgemm comes from) and results/bench_core_step.csv (whole implicit steps
 * with 32-iteration inner solves: steps per second and the share of the
 * rho estimate).
 * With CB_BENCH_MATRIX_DIR set, each size's A is also written there as
 * bench_matrix_<n>.bin (CSR: int32 n, int32 nnz, int32 indptr[n+1],
 * int32 indices[nnz], float64 data[nnz]) for bench/spmv_scipy.py.
 * Output: results/bench_core.csv (make bench). */
#define _GNU_SOURCE
#include <cblas.h>
#include <cholmod.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/definiteness.h>
#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>
#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include <clothbench/timer.h>
#include "csv.h"
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include <clothbench/timer.h>
#include "stats.h"
#include "support/bench_support.h"
#include "support/blas_profile.h"
#include "thread_probe.h"
#include "threads.h"


/* ---- statistics: every figure is a median with its min and max ---- */

enum { MAXREP = 16 };
typedef struct {
  double med, lo, hi;
} mstat;

static mstat stat_of(const double *v, int n) {
  double w[MAXREP];
  mstat m = {NAN, INFINITY, -INFINITY};
  for (int i = 0; i < n; i++) {
    w[i] = v[i];
    m.lo = fmin(m.lo, v[i]);
    m.hi = fmax(m.hi, v[i]);
  }
  m.med = cb_median(w, n);
  return m;
}

/* not measured (a failed factorisation, no step done): written empty */
static mstat unmeasured(void) {
  double na = cb_csv_na();
  return (mstat){na, na, na};
}
static void put(FILE *f, mstat m) { cb_csv_printf(f, ",%.6g,%.6g,%.6g", m.med, m.lo, m.hi); }
/* name, name_min, name_max, the unit suffix kept last (README.md, "CSV convention"): a timing x_ms gets
 * x_min_ms and x_max_ms, a rate x_gflops x_min_gflops, ...; a ratio x_over_y gets x_over_y_min */
static void put_hdr(char *h, size_t cap, const char *name) {
  static const char *const units[] = {"_ms", "_gflops", "_gbs", NULL};
  size_t u = strlen(h), len = strlen(name);
  for (int k = 0; units[k]; k++) {
    size_t ul = strlen(units[k]);
    if (len > ul && !strcmp(name + len - ul, units[k])) {
      int b = (int)(len - ul);
      snprintf(h + u, cap - u, ",%s,%.*s_min%s,%.*s_max%s", name, b, name, units[k], b, name, units[k]);
      return;
    }
  }
  snprintf(h + u, cap - u, ",%s,%s_min,%s_max", name, name, name);
}

/* ---- single-thread dgemm (the peak a factorisation's BLAS could reach) ---- */

typedef struct {
  int n;
  double *a, *b, *c;
} gemm_arrays;

static int gemm_alloc(gemm_arrays *g, int n) {
  size_t nn = (size_t)n * (size_t)n;
  g->n = n;
  g->a = malloc(nn * sizeof(double));
  g->b = malloc(nn * sizeof(double));
  g->c = malloc(nn * sizeof(double));
  if (!g->a || !g->b || !g->c) return -1;
  for (size_t i = 0; i < nn; i++) {
    g->a[i] = 1.0 / (double)(i % 101 + 1);
    g->b[i] = (double)(i % 7) - 3.0;
    g->c[i] = 0;
  }
  return 0;
}

/* One n^3 dgemm on one OpenBLAS thread; returns GFlop/s (2 n^3 flops). */
static double gemm_once(gemm_arrays *g, int threads) {
  openblas_set_num_threads(1);
  double t0 = cb_now_ms();
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, g->n, g->n, g->n, 1.0, g->a, g->n, g->b, g->n, 0.0, g->c,
              g->n);
  double ms = cb_now_ms() - t0;
  openblas_set_num_threads(threads);
  return 2.0 * g->n * (double)g->n * g->n / (ms * 1e-3) / 1e9;
}

/* ---- bare CHOLMOD: its defaults, reading our arrays ---- */

typedef struct {
  cholmod_common c;
  cholmod_sparse A;
  cholmod_factor *L;
  int ok;
} bare_cholmod;

static void bare_wrap(cholmod_sparse *s, const cb_sparse *A) {
  memset(s, 0, sizeof *s);
  s->nrow = s->ncol = (size_t)A->n;
  s->nzmax = (size_t)A->nnz;
  s->p = A->colp;
  s->i = A->rowi;
  s->x = A->val;
  s->stype = 1;
  s->itype = CHOLMOD_INT;
  s->xtype = CHOLMOD_REAL;
  s->dtype = CHOLMOD_DOUBLE;
  s->sorted = 1;
  s->packed = 1;
}

static double bare_analyze(bare_cholmod *b, const cb_sparse *A) {
  cholmod_start(&b->c);
  b->c.print = 0;
  b->c.error_handler = NULL;
  b->c.final_ll = 1;
  bare_wrap(&b->A, A);
  double t0 = cb_now_ms();
  b->L = cholmod_analyze(&b->A, &b->c);
  double ms = cb_now_ms() - t0;
  b->ok = b->L != NULL;
  return ms;
}

static void bare_factor(void *ctx) {
  bare_cholmod *b = ctx;
  if (b->ok) cholmod_factorize(&b->A, b->L, &b->c);
}

static void bare_free(bare_cholmod *b) {
  cholmod_free_factor(&b->L, &b->c);
  cholmod_finish(&b->c);
}

typedef struct {
  cb_solver *s;
  const cb_sparse *A;
  int status;
} our_factor_ctx;

static void our_factor(void *ctx) {
  our_factor_ctx *o = ctx;
  o->status = cb_solver_factor(o->s, o->A);
}

/* Times fn(ctx) and counts the threads that ran meanwhile. */
static double timed_count(void (*fn)(void *), void *ctx, double *threads) {
  double t0 = cb_now_ms();
  int k = cb_threads_count_during(fn, ctx);
  *threads = k;
  return cb_now_ms() - t0;
}

/* ---- the matrix for bench/spmv_scipy.py ---- */

static int export_matrix(const char *dir, int n, const cb_sparse *A) {
  char path[4096];
  snprintf(path, sizeof path, "%s/bench_matrix_%d.bin", dir, n);
  FILE *f = fopen(path, "wb");
  if (!f) {
    fprintf(stderr, "bench_core: cannot write %s\n", path);
    return -1;
  }
  int32_t hdr[2] = {A->n, A->nnz};
  int ok = fwrite(hdr, sizeof hdr, 1, f) == 1 &&
           fwrite(A->colp, sizeof(int), (size_t)A->n + 1, f) == (size_t)A->n + 1 &&
           fwrite(A->rowi, sizeof(int), (size_t)A->nnz, f) == (size_t)A->nnz &&
           fwrite(A->val, sizeof(double), (size_t)A->nnz, f) == (size_t)A->nnz; /* CSC of a symmetric A = its CSR */
  if (fclose(f) || !ok) {
    fprintf(stderr, "bench_core: writing %s failed\n", path);
    return -1;
  }
  return 0;
}

/* ---- factorisation choices (the table behind solver.ordering/nrelax/storage) ---- */

/* Every (ordering, nrelax, storage) analysed once, then factorised in turn,
 * rep after rep, so that all of them see the same machine; subnormals are
 * flushed in all of them (solver.denormals = flush), and one more row is the
 * defaults with subnormals kept. */
static void sweep_cholmod(FILE *f, int n, const cb_sparse *A, int reps) {
  const cb_solver_params def = cb_solver_params_default();
  static const int nrelax[][3] = {{4, 16, 48}, {16, 64, 128}};
  enum { NR = (int)(sizeof nrelax / sizeof nrelax[0]), NGRID = 4 * NR * 2, NC = NGRID + 1 };
  cb_solver *sv[NC] = {NULL};
  int st[NC], ord[NC], nr[NC][3], upp[NC], flush[NC];
  double tf[NC][MAXREP];
  for (int c = 0; c < NC; c++) {
    cb_solver_params p = cb_solver_params_default();
    if (c < NGRID) {
      ord[c] = c / (2 * NR);
      memcpy(nr[c], nrelax[(c / 2) % NR], sizeof nr[c]);
      upp[c] = c % 2;
    } else { /* the defaults, subnormals kept */
      ord[c] = def.ordering;
      memcpy(nr[c], def.nrelax, sizeof nr[c]);
      upp[c] = def.upper;
      p.flush_denormals = 0;
    }
    flush[c] = p.flush_denormals;
    p.ordering = ord[c];
    memcpy(p.nrelax, nr[c], sizeof p.nrelax);
    p.upper = upp[c];
    st[c] = cb_solver_alloc("cholmod", &p, A->n, &sv[c]);
    if (st[c] == CB_OK) st[c] = cb_solver_analyze(sv[c], A);
  }
  for (int k = 0; k < reps; k++)
    for (int c = 0; c < NC; c++)
      if (st[c] == CB_OK) {
        st[c] = cb_solver_factor(sv[c], A);
        tf[c][k] = sv[c]->stats.factor_ms;
      }
  for (int c = 0; c < NC; c++) {
    cb_solver *s = sv[c];
    int ok = st[c] == CB_OK;
    mstat m = ok ? stat_of(tf[c], reps) : unmeasured();
    int is_def = ord[c] == def.ordering && upp[c] == def.upper && flush[c] == def.flush_denormals &&
                 !memcmp(nr[c], def.nrelax, sizeof def.nrelax);
    double na = cb_csv_na(); /* what a solver that failed to allocate or factorise did not measure */
    cb_csv_printf(f, "%d,%s,%d %d %d,%s,%s,%.6g", n, cb_order_name(ord[c]), nr[c][0], nr[c][1], nr[c][2],
                  upp[c] ? "upper" : "full", flush[c] ? "flush" : "keep", s ? s->stats.analyze_ms : na);
    put(f, m);
    cb_csv_printf(f, ",%.6g,%.17g,%.17g,%d,%s\n", s && ok ? s->stats.factor_flops / (m.med * 1e-3) / 1e9 : na,
                  s && ok ? s->stats.factor_nnz : na, s && ok ? s->stats.factor_flops : na, is_def,
                  cb_status_name(st[c]));
    cb_solver_free(s);
  }
  fflush(f);
}

/* ---- the BLAS inside one factorisation ---- */

/* Rows of bench_core_blas.csv for one profiled factorisation of factor_ms:
 * each routine and flop class, then what was spent outside the four. */
static void write_blas_profile(FILE *f, int n, const cb_blas_profile *p, double factor_ms) {
  double in_blas = 0;
  for (int r = 0; r < CB_BLAS_NROUTINES; r++)
    for (int c = 0; c < CB_BLAS_NCLASSES; c++) {
      in_blas += p->ms[r][c];
      if (!p->calls[r][c]) continue;
      cb_csv_printf(f, "%d,%s,%s,%ld,%.6g,%.6g,%.6g,%.6g,%.6g\n", n, cb_blas_routine_name(r), cb_blas_class_name(c),
                    p->calls[r][c], p->ms[r][c], p->flops[r][c] / 1e9, p->flops[r][c] / (p->ms[r][c] * 1e-3) / 1e9,
                    p->ms[r][c] / factor_ms, factor_ms);
    }
  double na = cb_csv_na(); /* flops_class, calls, gflop and gflops do not apply outside the BLAS */
  cb_csv_printf(f, "%d,outside,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", n, na, na, factor_ms - in_blas, na, na,
                (factor_ms - in_blas) / factor_ms, factor_ms);
  fflush(f);
}

/* ---- whole implicit steps: K = 1 Newton, inner solve cut at 32 iterations ---- */

typedef struct {
  const char *label, *solver;
  double alpha; /* 0 = auto */
  int reuse;    /* amortised rho estimate */
} step_method;

static void bench_steps(FILE *f, int n, cb_scene *s, const cb_integrator_params *ip0, const double *xs,
                        const double *vs, int nsteps) {
  static const step_method methods[] = {
      {"cg32", "cg", 1.0, 1},
      {"cheb32_auto", "chebyshev", 0.0, 1},
      {"cheb32_auto_every_factor", "chebyshev", 0.0, 0},
      {"cheb32_alpha0.5", "chebyshev", 0.5, 1},
      {"cheb32_alpha0.5_every_factor", "chebyshev", 0.5, 0},
  };
  int nv3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)nv3 * sizeof *x), *v = malloc((size_t)nv3 * sizeof *v);
  for (size_t q = 0; q < sizeof methods / sizeof methods[0]; q++) {
    const step_method *m = &methods[q];
    cb_integrator_params ip = *ip0;
    cb_newton_params np = cb_newton_params_default();
    np.max_iters = 1;
    np.tol = 0;
    np.tol_dx = 0;
    cb_solver_params sp = cb_solver_params_default();
    sp.max_iters = 32;
    sp.tol = 1e-300;                               /* the cut, not the tolerance, ends every solve */
    sp.alpha = m->alpha == 0 ? CB_AUTO : m->alpha; /* the table's 0: auto */
    sp.rho = CB_AUTO;
    sp.rho_reuse = m->reuse;
    cb_integrator *it = NULL;
    int status = cb_integrator_alloc("newton", s, &ip, &np, m->solver, &sp, &it);
    double wall[64], total = 0, rho_total = 0, iters = 0, logres = 0;
    int estimates = 0, done = 0;
    memcpy(x, xs, (size_t)nv3 * sizeof *x);
    memcpy(v, vs, (size_t)nv3 * sizeof *v);
    for (int k = 0; status == CB_OK && k < nsteps; k++) {
      cb_step_stats st;
      int r = cb_integrator_step(it, x, v, &st);
      if (cb_status_is_fatal(r)) {
        status = r;
        break;
      }
      wall[k] = st.wall_ms;
      total += st.wall_ms;
      rho_total += it->solver->stats.rho_ms;
      estimates += it->solver->stats.rho_estimates;
      iters += st.linear_iters;
      logres += log10(it->solver->stats.rel_residual);
      done++;
    }
    mstat ms = done ? stat_of(wall + (done > MAXREP ? done - MAXREP : 0), done > MAXREP ? MAXREP : done) : unmeasured();
    double na = cb_csv_na(); /* no step done: nothing measured */
    cb_csv_printf(f, "%d,%s,%s,%s,%s,%d", n, m->label, m->solver, m->alpha > 0 ? "fixed" : "auto",
                  m->reuse ? "amortised" : "every_factor", done);
    put(f, ms);
    cb_csv_printf(f, ",%.6g,%.6g,%d,%.6g,%.6g,%.6g,%s\n", done ? 1000.0 / ms.med : na, done ? rho_total / total : na,
                  estimates, done ? iters / done : na, done ? pow(10.0, logres / done) : na,
                  it && m->alpha == 0 ? it->solver->stats.alpha : m->alpha, cb_status_name(status));
    fflush(f);
    cb_integrator_free(it);
  }
  free(x);
  free(v);
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bench_core",
                              "Per-step cost of the core, factorisation against dgemm, and SpMV bandwidth against a "
                              "STREAM triad.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* its numbers include wall times: run alone */
  const int sizes[] = {32, 64, 128, 256};
  const int nsizes = e.quick ? 2 : 4, step_n = e.quick ? 64 : 128;
  const char *mdir = getenv("CB_BENCH_MATRIX_DIR");
  const cb_threads_info *th = cb_threads_info_get();
  char hdr[4096] = "n,dofs,nnz_a,nnz_l,factor_gflop";
  const char *timed[] = {"explicit_step_ms",    "assemble_ms",
                         "factor_ms",           "solve_ms",
                         "bare_factor_ms",      "factor_over_bare",
                         "bare_omp4_factor_ms", "bare_omp4_over_bare",
                         "factor_gflops",       "dgemm_gflops",
                         "factor_over_dgemm",   "spmv_ms",
                         "spmv_full_ms",        "spmv_full_over_sym",
                         "triad_gbs",           "spmv_gbs",
                         "spmv_over_triad",     NULL};
  for (int i = 0; timed[i]; i++) put_hdr(hdr, sizeof hdr, timed[i]);
  strcat(hdr, ",newton_iter_ms,assemble_over_factor,factor_threads,bare_omp4_threads,analyze_ms,bare_analyze_ms,"
              "factorizations_per_run,analyze_over_run_factor,spmv_bytes,spmv_full_bytes,"
              "allocs_explicit_step,allocs_newton_iterative_step,allocs_newton_cholmod_step,status");
  char extra[2048];
  snprintf(extra, sizeof extra,
           "# every timed figure: median, _min and _max of its samples; *_over_*: median (min, max) of ratios of "
           "samples taken side by side\n"
           "# factor: clothbench's CHOLMOD (solver.* defaults); bare: CHOLMOD's own defaults on the same arrays, same "
           "thread settings;\n"
           "#   bare_omp4: the same with libgomp's dynamic adjustment off, as before the thread fix (Debian's CHOLMOD "
           "asks for 4 threads)\n"
           "# *_threads: threads whose CPU time grew during one factorisation (median over samples); requested: "
           "openblas %d, openmp %d\n"
           "# factor_gflops = Common->fl / factor time; dgemm: %d^3 on one OpenBLAS thread, interleaved with the "
           "factorisations\n"
           "# factorizations_per_run = integrator.steps x Newton iterations per step (mean of 3 steps); "
           "analyze_over_run_factor = analyze_ms / (that x factor_ms)\n"
           "# spmv: the iterative solvers' product on the upper blocks (cb_sparse_sym_matvec_bytes: 72 nub values + 4 "
           "nub block rows + 4 (n/3+1) + 16 n);\n"
           "#   spmv_full: the full-storage kernel (cb_sparse_matvec_bytes: 8 nnz + 4 nnz/9 + 4 (n/3+1) + 16 n); GB/s "
           "use each one's own bytes\n"
           "# allocs_*: heap allocations inside one step after warm-up; newton_iterative: the most over CG, PCG and "
           "Chebyshev (rho = auto) as the inner solver (our code only),\n"
           "#   newton_cholmod adds CHOLMOD's own (its permuted copy of A, workspace)\n"
           "# triad: a = b + s c over 3 arrays of 2^25 doubles, 24 bytes per element (STREAM convention), passes "
           "interleaved with the SpMV samples\n",
           th->blas_requested, th->omp_requested, 1024);
  cb_outfile csv, chol, steps, blas;
  char chol_path[2100], step_path[2100], blas_path[2100];
  cb_experiment_side_path(&e, "cholmod.csv", chol_path, sizeof chol_path);
  cb_experiment_side_path(&e, "blas.csv", blas_path, sizeof blas_path);
  cb_experiment_side_path(&e, "step.csv", step_path, sizeof step_path);
  if (cb_experiment_csv(&e, &csv, NULL, extra, hdr) ||
      cb_experiment_csv(&e, &chol, chol_path,
                        "# one row per (size, ordering, supernode relaxation, storage, denormals): CHOLMOD analysis, "
                        "then numeric factorisations, the choices in turn rep after rep;\n"
                        "# denormals: solver.denormals (flush in every row of the grid; one more row per size is the "
                        "defaults with subnormals kept)\n"
                        "# default = 1 on the row of the solver.* defaults\n",
                        "n,ordering,nrelax,storage,denormals,analyze_ms,factor_ms,factor_min_ms,factor_max_ms,factor_"
                        "gflops,nnz_l,flops,default,status") ||
      cb_experiment_csv(&e, &steps, step_path,
                        "# implicit steps from the bench state: Newton with one iteration (Baraff-Witkin), inner solve "
                        "cut at 32 iterations;\n"
                        "# rho_share = time in Lanczos rho estimates / step time, summed over the steps; "
                        "rho_estimates: Lanczos runs over the steps;\n"
                        "# rel_residual_geomean: geometric mean over the steps of the inner solve's final |b - Ax| / "
                        "|b|\n",
                        "n,method,solver,alpha_setting,rho_estimate,steps,step_ms,step_min_ms,step_max_ms,steps_per_s,"
                        "rho_share,"
                        "rho_estimates,linear_iters_mean,rel_residual_geomean,alpha_used,status") ||
      cb_experiment_csv(&e, &blas, blas_path,
                        "# one extra factorisation per size (the solver.* defaults) with the BLAS calls CHOLMOD makes "
                        "timed one by one:\n"
                        "# per routine and flop class (flops per call, 2 per multiply-add), calls, time, GFlop and "
                        "GFlop/s;\n"
                        "# share = time / factor_ms (that factorisation's wall time, timing overhead included); "
                        "routine = outside: the rest\n",
                        "n,routine,flops_class,calls,ms,gflop,gflops,share,factor_ms")) {
    fprintf(stderr, "bench_core: %s\n", cb_error_message());
    return 2;
  }
  cb_triad ta;
  gemm_arrays ga;
  if (cb_triad_alloc(&ta) || gemm_alloc(&ga, 1024)) {
    fprintf(stderr, "bench_core: out of memory for the triad and dgemm arrays\n");
    return 1;
  }
  cb_progress_start(&e.progress, "bench_core", nsizes);
  for (int si = 0; si < nsizes; si++) {
    int n = sizes[si];
    char setn[64];
    snprintf(setn, sizeof setn, "mesh.n=%d", n);
    const char *sets[] = {setn, NULL};
    cb_config cfg;
    cb_scene *s = NULL;
    cb_integrator *nt = NULL, *ex = NULL;
    if (cb_experiment_config(&e, "hanging.ini", sets, &cfg) || cb_scene_from_config(&cfg, &s) ||
        cb_integrator_from_config(&cfg, s, NULL, &nt)) {
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
    int status = CB_OK, newton_iters = 0, warm = 0;
    for (int k = 0; k < 3 && !cb_status_is_fatal(status); k++) { /* swing a little */
      status = cb_integrator_step(nt, x, v, &st);
      newton_iters += st.newton_iters;
      warm++;
    }
    double per_run = (double)cfg.steps * newton_iters / warm;
    memcpy(xs, x, (size_t)nv3 * sizeof *x);
    memcpy(vs, v, (size_t)nv3 * sizeof *v);
    /* allocations inside one Newton step and one explicit step (after warm-up) */
    long a0 = cb_bench_allocations();
    cb_integrator_step(nt, x, v, &st);
    long allocs_newton = cb_bench_allocations() - a0;
    long allocs_iter = 0; /* Newton with each iterative solver (Chebyshev with rho = auto) */
    const char *iters[] = {"cg", "pcg", "chebyshev"};
    for (int q = 0; q < 3; q++) {
      cb_solver_params sp = cb_solver_params_default();
      sp.max_iters = 200;
      sp.alpha = 0.4;
      cb_integrator *it = NULL;
      if (cb_integrator_alloc("newton", s, &nt->params, nt->type_params, iters[q], &sp, &it)) continue;
      cb_integrator_step(it, x, v, &st);
      a0 = cb_bench_allocations();
      cb_integrator_step(it, x, v, &st);
      if (cb_bench_allocations() - a0 > allocs_iter) allocs_iter = cb_bench_allocations() - a0;
      cb_integrator_free(it);
    }
    cb_integrator_step(ex, x, v, &st);
    a0 = cb_bench_allocations();
    cb_integrator_step(ex, x, v, &st);
    long allocs_explicit = cb_bench_allocations() - a0;
    /* explicit step */
    double tex[MAXREP], tas[MAXREP], tfa[MAXREP], tso[MAXREP], tmv[MAXREP], tmf[MAXREP];
    double tbare[MAXREP], rbare[MAXREP], tb4[MAXREP], rb4[MAXREP], gfl[MAXREP], dgf[MAXREP], rdg[MAXREP];
    double thr[MAXREP], thr4[MAXREP], ttr[MAXREP], gmv[MAXREP], rmv[MAXREP], rfs[MAXREP];
    for (int k = 0; k < reps; k++) {
      memcpy(x, xs, (size_t)nv3 * sizeof *x);
      memcpy(v, vs, (size_t)nv3 * sizeof *v);
      cb_integrator_step(ex, x, v, &st);
      tex[k] = st.wall_ms;
    }
    /* one Newton iteration at the saved state, split into its parts, with
     * bare CHOLMOD's factorisations of the same matrix in between */
    cb_sparse *A = &s->sys.A;
    double *b = malloc((size_t)A->n * sizeof *b), *dx = malloc((size_t)A->n * sizeof *dx),
           *y = malloc((size_t)A->n * sizeof *y);
    for (int i = 0; i < A->n; i++) b[i] = 1.0;
    cb_system_energy(&s->sys, xs, g, NULL);
    cb_system_assemble(&s->sys, xs, 1.0 / (cfg.dt * cfg.dt), CB_DEF_DROP, 0.0);
    bare_cholmod bare;
    double bare_an = bare_analyze(&bare, A);
    bare_factor(&bare); /* warm-up */
    our_factor_ctx oc = {nt->solver, A, CB_OK};
    double fl = nt->solver->stats.factor_flops;
    for (int k = 0; k < reps; k++) {
      double t0 = cb_now_ms();
      cb_system_energy(&s->sys, xs, g, NULL);
      cb_system_assemble(&s->sys, xs, 1.0 / (cfg.dt * cfg.dt), CB_DEF_DROP, 0.0);
      tas[k] = cb_now_ms() - t0;
      tfa[k] = timed_count(our_factor, &oc, &thr[k]);
      status = oc.status;
      t0 = cb_now_ms();
      if (status == CB_OK) status = cb_solver_solve(nt->solver, A, b, dx);
      tso[k] = cb_now_ms() - t0;
      double dummy;
      tbare[k] = timed_count(bare_factor, &bare, &dummy);
      omp_set_dynamic(0); /* as before the fix: CHOLMOD's num_threads(4) stands */
      tb4[k] = timed_count(bare_factor, &bare, &thr4[k]);
      omp_set_dynamic(1);
      dgf[k] = gemm_once(&ga, th->blas_requested);
      rbare[k] = tfa[k] / tbare[k];
      rb4[k] = tb4[k] / tbare[k];
      gfl[k] = fl / (tfa[k] * 1e-3) / 1e9;
      rdg[k] = gfl[k] / dgf[k];
    }
    bare_free(&bare);
    /* one more factorisation, with its BLAS calls timed by size */
    cb_blas_profile_start();
    double thr_prof, tprof = timed_count(our_factor, &oc, &thr_prof);
    cb_blas_profile prof;
    cb_blas_profile_stop(&prof);
    write_blas_profile(blas.f, n, &prof, tprof);
    /* SpMV (enough products per sample for ~20 ms), interleaved with triad
     * passes so that both see the same machine */
    cb_sparse_sym S;
    if (cb_sparse_sym_alloc(&S, A)) {
      fprintf(stderr, "bench_core: %s\n", cb_error_message());
      return 1;
    }
    cb_sparse_sym_fill(&S, A);
    double bytes = (double)cb_sparse_sym_matvec_bytes(&S), bytes_full = (double)cb_sparse_matvec_bytes(A);
    int inner = 1 + (int)(2e7 / (double)A->nnz);
    for (int k = 0; k < reps; k++) {
      ttr[k] = cb_triad_once(&ta);
      double t0 = cb_now_ms();
      for (int q = 0; q < inner; q++) cb_sparse_sym_matvec(&S, q & 1 ? y : b, q & 1 ? dx : y);
      tmv[k] = (cb_now_ms() - t0) / inner;
      t0 = cb_now_ms();
      for (int q = 0; q < inner; q++) cb_sparse_matvec(A, q & 1 ? y : b, q & 1 ? dx : y);
      tmf[k] = (cb_now_ms() - t0) / inner;
      gmv[k] = bytes / (tmv[k] * 1e-3) / 1e9;
      rmv[k] = gmv[k] / ttr[k];
      rfs[k] = tmf[k] / tmv[k];
    }
    if (mdir && *mdir && export_matrix(mdir, n, A)) return 1;
    double mfa = stat_of(tfa, reps).med, an = nt->solver->stats.analyze_ms;
    cb_csv_printf(csv.f, "%d,%d,%d,%.17g,%.6g", n, A->n, A->nnz, nt->solver->stats.factor_nnz, fl / 1e9);
    mstat ms[] = {stat_of(tex, reps),   stat_of(tas, reps),   stat_of(tfa, reps), stat_of(tso, reps),
                  stat_of(tbare, reps), stat_of(rbare, reps), stat_of(tb4, reps), stat_of(rb4, reps),
                  stat_of(gfl, reps),   stat_of(dgf, reps),   stat_of(rdg, reps), stat_of(tmv, reps),
                  stat_of(tmf, reps),   stat_of(rfs, reps),   stat_of(ttr, reps), stat_of(gmv, reps),
                  stat_of(rmv, reps)};
    for (size_t q = 0; q < sizeof ms / sizeof ms[0]; q++) put(csv.f, ms[q]);
    cb_csv_printf(csv.f, ",%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.17g,%.17g,%ld,%ld,%ld,%s\n",
                  ms[1].med + ms[2].med + ms[3].med, ms[1].med / mfa, stat_of(thr, reps).med, stat_of(thr4, reps).med,
                  an, bare_an, per_run, an / (per_run * mfa), bytes, bytes_full, allocs_explicit, allocs_iter,
                  allocs_newton, cb_status_name(status));
    fflush(csv.f);
    cb_sparse_sym_free(&S);
    if (n >= 64) sweep_cholmod(chol.f, n, A, n >= 256 ? 5 : 7);
    if (n == step_n) bench_steps(steps.f, n, s, &nt->params, xs, vs, 20);
    free(x);
    free(v);
    free(xs);
    free(vs);
    free(g);
    free(b);
    free(dx);
    free(y);
    cb_integrator_free(ex);
    cb_integrator_free(nt);
    cb_scene_free(s);
    cb_progress_update(&e.progress, si + 1);
  }
  cb_progress_end(&e.progress);
  cb_triad_free(&ta);
  free(ga.a);
  free(ga.b);
  free(ga.c);
  if (cb_outfile_commit(&chol) || cb_outfile_commit(&steps) || cb_outfile_commit(&blas) || cb_outfile_commit(&csv)) {
    fprintf(stderr, "bench_core: %s\n", cb_error_message());
    return 2;
  }
  fprintf(stderr, "bench_core: wrote %s, %s, %s, %s\n", e.out, chol_path, step_path, blas_path);
  return 0;
}
