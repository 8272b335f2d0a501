/* bench_peers: clothbench's direct solve against two other sparse direct
 * solvers on the same Newton matrices, in interleaved rounds.
 *
 * On the matrices bench_core exports (CB_BENCH_MATRIX_DIR:
 * bench_matrix_<n>.bin for n = 64, 128, 256; --quick: 64 only), each round
 * runs, one after the other on the same A and b = (1, ..., 1):
 *   - clothbench: the "cholmod" solver with the solver.* defaults, exactly as
 *     the harness uses it (cb_solver_analyze / _factor / _solve; its solve
 *     includes the harness's own residual check, one product with A);
 *   - MUMPS (Debian's sequential libdmumps_seq, C API dmumps_c), symmetric
 *     positive definite mode (sym = 1), its automatic ordering (ICNTL(7) = 7):
 *     analysis (JOB = 1), factorisation (JOB = 2), solve (JOB = 3);
 *   - SuperLU (Debian's libsuperlu): the column ordering MMD on A' + A and its
 *     elimination tree (get_perm_c, sp_preorder) as the analysis, dgstrf with
 *     SymmetricMode and diagonal pivots (DiagPivotThresh = 0: the SPD setting
 *     of SuperLU's guide) as the factorisation, dgstrs as the solve.
 * Each solver starts from scratch in each round (analysis included). Every
 * solution's relative residual |b - A x| / |b| is computed the same way
 * (cb_relative_residual) and recorded; a direct solve above 1e-10 marks the
 * row "inaccurate". A ratio is peer / clothbench within a round, and every
 * figure is the median with min and max over the rounds.
 *
 *   bench_peers [--quick] --out results/bench_peers.csv
 *
 * For bench/peers_scipy.py (SciPy's splu, spsolve and cg against clothbench,
 * interleaved round by round in one process pair):
 *   bench_peers --provenance   prints the "# key: value" provenance lines
 *   bench_peers --serve FILE   loads FILE, prints "ready <n> <nnz>", then per
 *                              line on stdin: "direct" runs one clothbench
 *                              CHOLMOD round and prints "<analyse_ms>
 *                              <factor_ms> <solve_ms> <rel_residual>";
 *                              "cg K" runs K iterations of clothbench's CG
 *                              from x = 0 and prints "<ms per iteration>
 *                              <iterations> <rel_residual>"; "quit" or EOF
 *                              ends.
 * MUMPS and SuperLU are linked into this program only (the Makefile), never
 * into the library. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dmumps_c.h>
#include <slu_ddefs.h>

#include <clothbench/solver.h>
#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include <clothbench/timer.h>
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"
#include "support/bench_matrix.h"

#define MUMPS_COMM_WORLD (-987654) /* MUMPS's "use MPI_COMM_WORLD"; the sequential library ignores it */
#define DIRECT_TOL 1e-10           /* a direct solve's relative residual above this is "inaccurate" */

enum { MAXROUNDS = 16, CB_NPHASES = 5 };
static const char *const phase_name[CB_NPHASES] = {"analyse", "factorise", "analyse_factorise", "solve", "total"};

/* One solver's round: the three phases, the residual, what it says about itself. */
typedef struct {
  double analyse, factor, solve, resid;
  int ok;
  char detail[160];
} round_t;

static double phase_of(const round_t *r, int p) {
  switch (p) {
  case 0: return r->analyse;
  case 1: return r->factor;
  case 2: return r->analyse + r->factor;
  case 3: return r->solve;
  default: return r->analyse + r->factor + r->solve;
  }
}

/* ---- clothbench: the "cholmod" solver as the harness builds it ---- */

static int cb_direct_round(const cb_sparse *A, const double *b, double *x, double *work, round_t *r) {
  memset(r, 0, sizeof *r);
  cb_solver_params p = cb_solver_params_default();
  cb_solver *s = NULL;
  int st = cb_solver_alloc("cholmod", &p, A->n, &s);
  double t0 = cb_now_ms();
  if (st == CB_OK) st = cb_solver_analyze(s, A);
  double t1 = cb_now_ms();
  if (st == CB_OK) st = cb_solver_factor(s, A);
  double t2 = cb_now_ms();
  if (st == CB_OK) st = cb_solver_solve(s, A, b, x);
  double t3 = cb_now_ms();
  r->analyse = t1 - t0;
  r->factor = t2 - t1;
  r->solve = t3 - t2;
  r->ok = st == CB_OK;
  r->resid = r->ok ? cb_relative_residual(A, b, x, work) : NAN;
  if (s) snprintf(r->detail, sizeof r->detail, "nesdis (solver.ordering); nnz(L) %.0f", s->stats.factor_nnz);
  cb_solver_free(s);
  return r->ok ? 0 : -1;
}

/* ---- MUMPS, sequential, symmetric positive definite ---- */

typedef struct {
  MUMPS_INT *irn, *jcn; /* 1-based, the upper triangle */
  double *a;
  int64_t nz;
} mumps_input;

static int mumps_input_make(const cb_sparse *A, mumps_input *m) {
  int64_t nz = 0;
  for (int j = 0; j < A->n; j++)
    for (int q = A->colp[j]; q < A->colp[j + 1]; q++) nz += A->rowi[q] <= j;
  m->irn = malloc((size_t)nz * sizeof *m->irn);
  m->jcn = malloc((size_t)nz * sizeof *m->jcn);
  m->a = malloc((size_t)nz * sizeof *m->a);
  if (!m->irn || !m->jcn || !m->a) return -1;
  m->nz = 0;
  for (int j = 0; j < A->n; j++)
    for (int q = A->colp[j]; q < A->colp[j + 1]; q++)
      if (A->rowi[q] <= j) {
        m->irn[m->nz] = A->rowi[q] + 1;
        m->jcn[m->nz] = j + 1;
        m->a[m->nz++] = A->val[q];
      }
  return 0;
}

static const char *mumps_ordering_name(int k) { /* INFOG(7) */
  switch (k) {
  case 0: return "AMD";
  case 2: return "AMF";
  case 3: return "SCOTCH";
  case 4: return "PORD";
  case 5: return "METIS";
  case 6: return "QAMD";
  default: return "?";
  }
}

static int mumps_round(const cb_sparse *A, const mumps_input *m, const double *b, double *x, double *work, round_t *r) {
  memset(r, 0, sizeof *r);
  DMUMPS_STRUC_C id;
  memset(&id, 0, sizeof id);
  id.comm_fortran = MUMPS_COMM_WORLD;
  id.par = 1;
  id.sym = 1; /* symmetric positive definite: LDL' without pivoting */
  id.job = -1;
  dmumps_c(&id);
  if (id.infog[0] < 0) {
    snprintf(r->detail, sizeof r->detail, "initialisation failed: INFOG(1) = %d", (int)id.infog[0]);
    return -1;
  }
  id.icntl[0] = -1; /* no error, diagnostic or global output */
  id.icntl[1] = -1;
  id.icntl[2] = -1;
  id.icntl[3] = 0;
  id.n = A->n;
  id.nnz = m->nz;
  id.nz = (MUMPS_INT)m->nz;
  id.irn = m->irn;
  id.jcn = m->jcn;
  id.a = m->a;
  memcpy(x, b, (size_t)A->n * sizeof *x);
  id.rhs = x;
  const double t0 = cb_now_ms();
  id.job = 1;
  dmumps_c(&id);
  const double t1 = cb_now_ms();
  int ok = id.infog[0] >= 0;
  if (ok) {
    id.job = 2;
    dmumps_c(&id);
    ok = id.infog[0] >= 0;
  }
  const double t2 = cb_now_ms();
  if (ok) {
    id.job = 3;
    dmumps_c(&id);
    ok = id.infog[0] >= 0;
  }
  const double t3 = cb_now_ms();
  r->analyse = t1 - t0;
  r->factor = t2 - t1;
  r->solve = t3 - t2;
  r->ok = ok;
  if (ok)
    snprintf(r->detail, sizeof r->detail, "%s (INFOG(7)); nnz(L) %lld", mumps_ordering_name((int)id.infog[6]),
             (long long)(id.infog[28] >= 0 ? id.infog[28] : -1000000LL * id.infog[28]));
  else
    snprintf(r->detail, sizeof r->detail, "failed: INFOG(1) = %d, INFOG(2) = %d", (int)id.infog[0], (int)id.infog[1]);
  id.job = -2;
  dmumps_c(&id);
  r->resid = ok ? cb_relative_residual(A, b, x, work) : NAN;
  return ok ? 0 : -1;
}

/* ---- SuperLU: MMD(A' + A), symmetric mode, diagonal pivots ---- */

static int superlu_round(const cb_sparse *A, const double *b, double *x, double *work, round_t *r) {
  memset(r, 0, sizeof *r);
  const int n = A->n;
  SuperMatrix As, AC, L, U, B;
  superlu_options_t opt;
  set_default_options(&opt);
  opt.ColPerm = MMD_AT_PLUS_A;
  opt.SymmetricMode = YES;
  opt.DiagPivotThresh = 0.0;
  opt.PrintStat = NO;
  /* SuperLU reads A through its own struct, without copying or changing it */
  dCreate_CompCol_Matrix(&As, n, n, A->nnz, A->val, A->rowi, A->colp, SLU_NC, SLU_D, SLU_GE);
  int *perm_c = malloc((size_t)n * sizeof *perm_c), *perm_r = malloc((size_t)n * sizeof *perm_r);
  int *etree = malloc((size_t)n * sizeof *etree);
  if (!perm_c || !perm_r || !etree) {
    free(perm_c);
    free(perm_r);
    free(etree);
    Destroy_SuperMatrix_Store(&As);
    snprintf(r->detail, sizeof r->detail, "out of memory");
    return -1;
  }
  SuperLUStat_t stat;
  StatInit(&stat);
  GlobalLU_t glu;
  int info = 0;
  const double t0 = cb_now_ms();
  get_perm_c(opt.ColPerm, &As, perm_c);
  sp_preorder(&opt, &As, perm_c, etree, &AC);
  const double t1 = cb_now_ms();
  dgstrf(&opt, &AC, sp_ienv(2), sp_ienv(1), etree, NULL, 0, perm_c, perm_r, &L, &U, &glu, &stat, &info);
  const double t2 = cb_now_ms();
  int ok = info == 0;
  memcpy(x, b, (size_t)n * sizeof *x);
  if (ok) {
    dCreate_Dense_Matrix(&B, n, 1, x, n, SLU_DN, SLU_D, SLU_GE);
    dgstrs(NOTRANS, &L, &U, perm_c, perm_r, &B, &stat, &info);
    ok = info == 0;
    Destroy_SuperMatrix_Store(&B);
  }
  const double t3 = cb_now_ms();
  r->analyse = t1 - t0;
  r->factor = t2 - t1;
  r->solve = t3 - t2;
  r->ok = ok;
  if (info == 0 || ok) {
    const SCformat *ls = L.Store;
    const NCformat *us = U.Store;
    snprintf(r->detail, sizeof r->detail, "MMD(A'+A); symmetric mode; diagonal pivots; L and U stores nnz - n = %lld",
             (long long)ls->nnz + (long long)us->nnz - n);
  } else {
    snprintf(r->detail, sizeof r->detail, "failed: info = %d", info);
  }
  if (t2 > t1 && (ok || info > 0)) {
    Destroy_SuperNode_Matrix(&L);
    Destroy_CompCol_Matrix(&U);
  }
  Destroy_CompCol_Permuted(&AC);
  Destroy_SuperMatrix_Store(&As);
  StatFree(&stat);
  free(perm_c);
  free(perm_r);
  free(etree);
  r->resid = ok ? cb_relative_residual(A, b, x, work) : NAN;
  return ok ? 0 : -1;
}

/* ---- rows ---- */

static void put3(FILE *f, const double *v, int n) {
  double w[MAXROUNDS], lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < n; i++) {
    w[i] = v[i];
    lo = fmin(lo, v[i]);
    hi = fmax(hi, v[i]);
  }
  cb_csv_printf(f, ",%.6g,%.6g,%.6g", cb_median(w, n), lo, hi);
}

static double worst(const round_t *r, int n) {
  double m = 0;
  for (int i = 0; i < n; i++) m = fmax(m, r[i].resid);
  return m;
}

/* The rows of one peer at one size: one per phase. */
static void write_peer(FILE *f, int n, const cb_sparse *A, const char *peer, const round_t *pr, const round_t *cr,
                       int rounds, int failed) {
  double pres = worst(pr, rounds), cres = worst(cr, rounds);
  const char *status = failed ? "failed" : pres > DIRECT_TOL || cres > DIRECT_TOL ? "inaccurate" : "ok";
  for (int p = 0; p < CB_NPHASES; p++) {
    double pv[MAXROUNDS], cv[MAXROUNDS], rv[MAXROUNDS];
    for (int k = 0; k < rounds; k++) {
      pv[k] = phase_of(&pr[k], p);
      cv[k] = phase_of(&cr[k], p);
      rv[k] = pv[k] / cv[k];
    }
    cb_csv_printf(f, "%d,%d,%d,%s,cholmod,%s,%d", n, A->n, A->nnz, peer, phase_name[p], rounds);
    if (failed) {
      double na = cb_csv_na();
      cb_csv_printf(f, ",%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g", na, na, na, na, na, na, na, na, na);
    } else {
      put3(f, pv, rounds);
      put3(f, cv, rounds);
      put3(f, rv, rounds);
    }
    cb_csv_printf(f, ",%.3g,%.3g,%s,%s\n", failed ? cb_csv_na() : pres, cres, pr[0].detail, status);
  }
  fflush(f);
}

/* ---- serve mode for bench/peers_scipy.py ---- */

static int serve(const char *path) {
  cb_sparse A;
  if (cb_bench_matrix_read("bench_peers", path, &A)) return 1;
  const int n = A.n;
  double *b = malloc((size_t)n * sizeof *b), *x = malloc((size_t)n * sizeof *x), *w = malloc((size_t)n * sizeof *w);
  if (!b || !x || !w) {
    fprintf(stderr, "bench_peers: out of memory\n");
    return 1;
  }
  for (int i = 0; i < n; i++) b[i] = 1.0;
  printf("ready %d %d\n", n, A.nnz);
  fflush(stdout);
  char line[128];
  cb_solver *cg = NULL;
  int rc = 0;
  while (fgets(line, sizeof line, stdin)) {
    int k = 0;
    if (!strncmp(line, "quit", 4)) break;
    if (!strncmp(line, "direct", 6)) {
      round_t r;
      cb_direct_round(&A, b, x, w, &r);
      printf("%.6f %.6f %.6f %.6g\n", r.analyse, r.factor, r.solve, r.ok ? r.resid : NAN);
    } else if (sscanf(line, "cg %d", &k) == 1 && k > 0) {
      cb_solver_params p = cb_solver_params_default();
      p.max_iters = k;
      p.tol = 1e-300; /* the cut, not the tolerance, ends the solve */
      if (!cg && (cb_solver_alloc("cg", &p, n, &cg) || cb_solver_analyze(cg, &A) || cb_solver_factor(cg, &A))) {
        fprintf(stderr, "bench_peers: cg: %s\n", cb_error_message());
        rc = 1;
        break;
      }
      cg->params.max_iters = k;
      memset(x, 0, (size_t)n * sizeof *x);
      double t0 = cb_now_ms();
      int st = cb_solver_solve(cg, &A, b, x);
      double ms = cb_now_ms() - t0;
      if (cb_status_is_fatal(st) || cg->stats.iters <= 0) {
        fprintf(stderr, "bench_peers: cg: %s\n", cb_status_name(st));
        rc = 1;
        break;
      }
      printf("%.6f %d %.6g\n", ms / cg->stats.iters, cg->stats.iters, cb_relative_residual(&A, b, x, w));
    } else {
      fprintf(stderr, "bench_peers: --serve: unknown command: %s", line);
      rc = 1;
      break;
    }
    fflush(stdout);
  }
  cb_solver_free(cg);
  cb_sparse_free(&A);
  free(b);
  free(x);
  free(w);
  return rc;
}

int main(int argc, char **argv) {
  if (argc == 3 && !strcmp(argv[1], "--serve")) {
    if (cb_runtime_init()) {
      fprintf(stderr, "bench_peers: %s\n", cb_error_message());
      return 1;
    }
    return serve(argv[2]);
  }
  if (argc == 2 && !strcmp(argv[1], "--provenance")) {
    if (cb_runtime_init()) {
      fprintf(stderr, "bench_peers: %s\n", cb_error_message());
      return 1;
    }
    cb_provenance_write(stdout, "bench_peers", argc, argv, NULL);
    return fflush(stdout) ? 1 : 0;
  }
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bench_peers",
                              "clothbench's CHOLMOD solve against MUMPS and SuperLU on bench_core's exported Newton "
                              "matrices "
                              "(CB_BENCH_MATRIX_DIR), interleaved rounds; --serve and --provenance for "
                              "bench/peers_scipy.py.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e);
  const char *mdir = getenv("CB_BENCH_MATRIX_DIR");
  if (!mdir || !*mdir) {
    fprintf(stderr, "bench_peers: CB_BENCH_MATRIX_DIR is not set: run bench_core with it first (make bench does)\n");
    return 1;
  }
  const int sizes[] = {64, 128, 256};
  const int nsizes = e.quick ? 1 : 3;
  char extra[1024];
  snprintf(extra, sizeof extra,
           "# matrices: %s/bench_matrix_<n>.bin (bench_core's Newton matrix of the lab cloth at n^2 vertices); b = (1, "
           "..., 1)\n"
           "# each round: clothbench (solver cholmod, solver.* defaults; its solve includes the harness's residual "
           "check), MUMPS %s "
           "(sequential, sym = 1, ICNTL(7) = 7 automatic ordering), SuperLU (MMD on A'+A, SymmetricMode, "
           "DiagPivotThresh 0), each from scratch\n"
           "# peer_ms, clothbench_ms: median, _min, _max over the rounds; peer_over_clothbench: of the ratios within a "
           "round\n"
           "# *_rel_residual: the largest |b - Ax| / |b| over the rounds; status inaccurate: above %g\n",
           mdir, MUMPS_VERSION, DIRECT_TOL);
  if (cb_experiment_csv(&e, &e.csv, NULL, extra,
                        "n,dofs,nnz,peer,clothbench,phase,rounds,peer_ms,peer_min_ms,peer_max_ms,clothbench_ms,"
                        "clothbench_min_ms,"
                        "clothbench_max_ms,peer_over_clothbench,peer_over_clothbench_min,peer_over_clothbench_max,"
                        "peer_rel_residual,clothbench_rel_residual,peer_detail,status")) {
    fprintf(stderr, "bench_peers: %s\n", cb_error_message());
    return 2;
  }
  cb_progress_start(&e.progress, "bench_peers", nsizes);
  for (int si = 0; si < nsizes; si++) {
    const int n = sizes[si], rounds = e.quick ? 3 : n >= 256 ? 3 : n >= 128 ? 5 : 7;
    char path[4096];
    cb_bench_matrix_path(mdir, n, path, sizeof path);
    cb_sparse A;
    if (cb_bench_matrix_read("bench_peers", path, &A)) {
      cb_outfile_abort(&e.csv);
      return 1;
    }
    mumps_input mi;
    double *b = malloc((size_t)A.n * sizeof *b), *x = malloc((size_t)A.n * sizeof *x),
           *w = malloc((size_t)A.n * sizeof *w);
    if (!b || !x || !w || mumps_input_make(&A, &mi)) {
      fprintf(stderr, "bench_peers: out of memory at %d^2\n", n);
      cb_outfile_abort(&e.csv);
      return 1;
    }
    for (int i = 0; i < A.n; i++) b[i] = 1.0;
    round_t cbm[MAXROUNDS], cbs[MAXROUNDS], mu[MAXROUNDS], su[MAXROUNDS];
    int cb_failed = 0, mu_failed = 0, su_failed = 0;
    for (int k = 0; k < rounds; k++) { /* clothbench before each peer: each ratio pairs neighbours */
      cb_failed |= cb_direct_round(&A, b, x, w, &cbm[k]);
      mu_failed |= mumps_round(&A, &mi, b, x, w, &mu[k]);
      cb_failed |= cb_direct_round(&A, b, x, w, &cbs[k]);
      su_failed |= superlu_round(&A, b, x, w, &su[k]);
      if (mu_failed && k == 0) fprintf(stderr, "bench_peers: MUMPS at %d^2: %s\n", n, mu[k].detail);
      if (su_failed && k == 0) fprintf(stderr, "bench_peers: SuperLU at %d^2: %s\n", n, su[k].detail);
    }
    if (cb_failed) {
      fprintf(stderr, "bench_peers: clothbench's CHOLMOD solve failed at %d^2\n", n);
      cb_outfile_abort(&e.csv);
      return 1;
    }
    write_peer(e.csv.f, n, &A, "mumps", mu, cbm, rounds, mu_failed);
    write_peer(e.csv.f, n, &A, "superlu", su, cbs, rounds, su_failed);
    double rm[MAXROUNDS], rs[MAXROUNDS];
    for (int k = 0; k < rounds; k++) {
      rm[k] = mu[k].factor / cbm[k].factor;
      rs[k] = su[k].factor / cbs[k].factor;
    }
    fprintf(stderr,
            "bench_peers: %d^2: factorise MUMPS / clothbench %.2f, SuperLU / clothbench %.2f (medians of %d rounds)\n",
            n, cb_median(rm, rounds), cb_median(rs, rounds), rounds);
    free(mi.irn);
    free(mi.jcn);
    free(mi.a);
    free(b);
    free(x);
    free(w);
    cb_sparse_free(&A);
    cb_progress_update(&e.progress, si + 1);
  }
  cb_progress_end(&e.progress);
  if (cb_outfile_commit(&e.csv)) {
    fprintf(stderr, "bench_peers: %s\n", cb_error_message());
    return 2;
  }
  fprintf(stderr, "bench_peers: wrote %s\n", e.out);
  return 0;
}
