/* bench_petsc: the PETSc family's choices measured on the hanging cloth
 * (issue 36; docs/solvers-petsc.md holds the tables). Not part of make bench.
 *
 *   --mode solve (default)  one Newton solve per variant: configs/hanging.ini
 *       at mesh.n = N, the state after 3 Newton steps (one iteration each,
 *       CHOLMOD), then one Newton iteration (integrator.max_iters = 1) with
 *       the variant's solver to solver.tol = --tol (default 1e-6, relative
 *       residual |b - A dx| / |b|), from the same state each time. Per
 *       variant: the preconditioner's set-up (factor_ms: values copied in,
 *       near-null space, KSPSetUp), the Krylov solve (solve_ms), their sum,
 *       the iterations, the true relative residual, and the step's distance
 *       to CHOLMOD's step |x - x_chol| / |x_chol - x_start| (one Newton
 *       iteration both: the same linear system, solved inexactly).
 *   --mode reuse            a short Newton run per variant and
 *       solver.pc_reuse choice: --steps (default 10) steps of the hanging
 *       cloth from rest at mesh.n = N, Newton to integrator.tol 1e-6 (at most
 *       50 iterations), solver.tol = --tol; per run the sums over its steps
 *       of set-up time, solve time, Krylov iterations, Newton iterations and
 *       preconditioner set-ups, and the last step's relative gradient.
 *
 * Variants (--variants, comma-separated; default: every one for solve, the
 * four presets for reuse): cholmod (solve mode only), gamg (petsc-gamg as
 * registered), gamg-norigid (solver.rigid_modes = 0), gamg-rigid
 * (solver.rigid_modes = 1), hypre (petsc-hypre as registered), hypre-nodal
 * (-pc_hypre_boomeramg_nodal_coarsen 1), hypre-nonodal (... 0), ml, icc.
 * Rounds interleave the variants (--reps rounds, default 3; median, min
 * and max); a variant that fails keeps its row with its status. Wall times
 * on a shared machine: run it pinned (taskset -c 1) and compare ratios
 * within one run. --sizes N,N,... (default 128,256).
 * Output: results/bench_petsc_<mode>.csv (or --out). */
#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include <clothbench/timer.h>
#include "bind.h"
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"

typedef struct {
  const char *name, *solver;
  const char *sets[3];
} variant;

static const variant VARIANTS[] = {
    {"cholmod", "cholmod", {NULL}},
    {"gamg", "petsc-gamg", {NULL}},
    {"gamg-norigid", "petsc-gamg", {"solver.rigid_modes=0", NULL}},
    {"gamg-rigid", "petsc-gamg", {"solver.rigid_modes=1", NULL}},
    {"hypre", "petsc-hypre", {NULL}},
    {"hypre-nodal", "petsc-hypre", {"solver.petsc=-pc_hypre_boomeramg_nodal_coarsen 1", NULL}},
    {"hypre-nonodal", "petsc-hypre", {"solver.petsc=-pc_hypre_boomeramg_nodal_coarsen 0", NULL}},
    {"ml", "petsc-ml", {NULL}},
    {"icc", "petsc-icc", {NULL}},
};
enum { NVARIANTS = sizeof VARIANTS / sizeof VARIANTS[0], MAXSEL = 16, MAXREPS = 15, MAXSIZES = 8 };

typedef struct {
  const char *name, *sets[2];
} reuse_choice;
static const reuse_choice REUSE[] = {
    {"iteration", {"solver.pc_reuse=iteration", NULL}},
    {"step", {"solver.pc_reuse=step", NULL}},
    {"step5", {"solver.pc_reuse=step", "solver.pc_reuse_steps=5"}},
};
enum { NREUSE = sizeof REUSE / sizeof REUSE[0] };

static int find_variant(const char *name) {
  for (int k = 0; k < NVARIANTS; k++)
    if (!strcmp(VARIANTS[k].name, name)) return k;
  return -1;
}

/* An integrator of the base config with these sets; NULL (message printed) on failure. */
static cb_integrator *make(const cb_config *base, cb_scene *s, const char *solver, const char *const *sets1,
                           const char *const *sets2) {
  cb_config c = *base;
  char m[96];
  snprintf(m, sizeof m, "solver.method=%s", solver);
  if (cb_config_set(&c, m)) goto fail;
  for (int i = 0; sets1 && i < 3 && sets1[i]; i++)
    if (cb_config_set(&c, sets1[i])) goto fail;
  for (int i = 0; sets2 && i < 2 && sets2[i]; i++)
    if (cb_config_set(&c, sets2[i])) goto fail;
  cb_integrator *it = NULL;
  if (cb_integrator_from_config(&c, s, NULL, &it)) goto fail;
  return it;
fail:
  fprintf(stderr, "bench_petsc: %s\n", cb_error_message());
  return NULL;
}

static void range(double *v, int n, double *med, double *lo, double *hi) {
  *med = cb_median(v, n);
  *lo = *hi = v[0];
  for (int i = 1; i < n; i++) *lo = fmin(*lo, v[i]), *hi = fmax(*hi, v[i]);
}

static int parse_list(const char *text, int *out, int cap) {
  int n = 0;
  for (const char *p = text; *p && n < cap;) {
    char *end;
    long v = strtol(p, &end, 10);
    if (end == p || v < 2 || v > 4096) return -1;
    out[n++] = (int)v;
    p = *end == ',' ? end + 1 : end;
    if (*end && *end != ',') return -1;
  }
  return n;
}

int main(int argc, char **argv) {
  const char *mode = "solve", *vlist = NULL;
  int sizes[MAXSIZES] = {128, 256}, nsizes = 2, reps = 3, steps = 10;
  double tol = 1e-6;
  char *rest[64];
  int nrest = 0;
  for (int i = 0; i < argc && nrest < 63; i++) { /* our options out, the experiment's in */
    int has = i + 1 < argc;
    if (!strcmp(argv[i], "--mode") && has) mode = argv[++i];
    else if (!strcmp(argv[i], "--variants") && has) vlist = argv[++i];
    else if (!strcmp(argv[i], "--sizes") && has) {
      if ((nsizes = parse_list(argv[++i], sizes, MAXSIZES)) <= 0) {
        fprintf(stderr, "bench_petsc: --sizes '%s': expected N,N,... with 2 <= N <= 4096\n", argv[i]);
        return 1;
      }
    } else if ((!strcmp(argv[i], "--reps") || !strcmp(argv[i], "--steps") || !strcmp(argv[i], "--tol")) && has) {
      char *end;
      double v = strtod(argv[i + 1], &end);
      int isint = strcmp(argv[i], "--tol") != 0;
      if (*end || !(v > 0) || (isint && (v != floor(v) || v > (strcmp(argv[i], "--reps") ? 10000 : MAXREPS))) ||
          (!isint && !(v < 1))) {
        fprintf(stderr, "bench_petsc: %s '%s': out of range\n", argv[i], argv[i + 1]);
        return 1;
      }
      if (!strcmp(argv[i], "--reps")) reps = (int)v;
      else if (!strcmp(argv[i], "--steps")) steps = (int)v;
      else tol = v;
      i++;
    } else rest[nrest++] = argv[i];
  }
  rest[nrest] = NULL;
  int reuse = !strcmp(mode, "reuse");
  if (!reuse && strcmp(mode, "solve")) {
    fprintf(stderr, "bench_petsc: --mode '%s': expected solve or reuse\n", mode);
    return 1;
  }
  int sel[MAXSEL], nsel = 0;
  if (!vlist) vlist = reuse ? "gamg,hypre,ml,icc" : "cholmod,gamg-norigid,gamg-rigid,hypre-nodal,hypre-nonodal,ml,icc";
  for (const char *p = vlist; *p && nsel < MAXSEL;) {
    const char *q = strchr(p, ',');
    size_t len = q ? (size_t)(q - p) : strlen(p);
    char name[32];
    snprintf(name, sizeof name, "%.*s", (int)(len < 31 ? len : 31), p);
    int k = find_variant(name);
    if (k < 0 || (reuse && k == 0)) {
      fprintf(stderr, "bench_petsc: --variants: '%s' is not a variant%s\n", name, reuse ? " of the reuse mode" : "");
      return 1;
    }
    sel[nsel++] = k;
    p = q ? q + 1 : p + len;
  }
  cb_experiment e;
  char name[32];
  snprintf(name, sizeof name, "bench_petsc_%s", reuse ? "reuse" : "solve");
  int r = cb_experiment_begin(&e, name,
                              "The PETSc family on the hanging cloth: near-null space and nodal coarsening (--mode "
                              "solve), preconditioner reuse (--mode reuse); issue 36, docs/solvers-petsc.md.",
                              nrest, rest);
  if (r) return r > 0 ? 0 : 1;
  e.argc = argc; /* the CSV's "# command:" line: the whole command, ours included */
  e.argv = argv;
  cb_experiment_timed(&e);
  cb_runtime_init();
  if (e.smoke) nsizes = 1, sizes[0] = 16, reps = 1, steps = 2;
  char extra[512];
  snprintf(extra, sizeof extra,
           "# scene: configs/hanging.ini at n^2; %s; solver.tol %g; rounds interleave the variants, times are "
           "medians with min and max\n",
           reuse ? "Newton to integrator.tol 1e-6 (at most 50 iterations) from rest, sums over the run's steps"
                 : "one Newton iteration from the state after 3 CHOLMOD steps",
           tol);
  cb_outfile csv;
  if (cb_experiment_csv(&e, &csv, NULL, extra,
                        reuse ? "n,unknowns,variant,solver,pc_reuse,steps,rounds,total_ms,total_min_ms,total_max_ms,"
                                "setup_ms,solve_ms,krylov_iters,newton_iters,pc_setups,last_rel_grad,status"
                              : "n,unknowns,variant,solver,rounds,total_ms,total_min_ms,total_max_ms,setup_ms,solve_"
                                "ms,iters,rel_residual,near_null,dist_to_cholmod,status")) {
    fprintf(stderr, "bench_petsc: %s\n", cb_error_message());
    return 2;
  }
  int status = 0;
  for (int si = 0; si < nsizes; si++) {
    int n = sizes[si];
    char setn[64];
    snprintf(setn, sizeof setn, "mesh.n=%d", n);
    const char *base_sets[] = {setn,
                               "integrator.method=newton",
                               reuse ? "integrator.max_iters=50" : "integrator.max_iters=1",
                               reuse ? "integrator.tol=1e-6" : "integrator.tol=0",
                               "solver.max_iters=100000",
                               NULL};
    cb_config c;
    cb_scene *s = NULL;
    if (cb_experiment_config(&e, "hanging.ini", base_sets, &c) || cb_config_validate(&c) ||
        cb_config_set(&c, (snprintf(extra, sizeof extra, "solver.tol=%.17g", tol), extra)) ||
        cb_scene_from_config(&c, &s)) {
      fprintf(stderr, "bench_petsc: %s\n", cb_error_message());
      return 1;
    }
    size_t nv3 = (size_t)3 * s->mesh.nv;
    double *xs = malloc(nv3 * sizeof(double)), *vs = malloc(nv3 * sizeof(double)), *x = malloc(nv3 * sizeof(double)),
           *v = malloc(nv3 * sizeof(double)), *xc = malloc(nv3 * sizeof(double));
    if (!xs || !vs || !x || !v || !xc) return 1;
    memcpy(xs, s->x0, nv3 * sizeof(double));
    memcpy(vs, s->v0, nv3 * sizeof(double));
    cb_step_stats st;
    if (!reuse) { /* the state the solves start from, and CHOLMOD's step from it */
      cb_integrator *warm = make(&c, s, "cholmod", NULL, NULL);
      if (!warm) return 1;
      for (int f = 0; f < 3; f++) cb_integrator_step(warm, xs, vs, &st);
      memcpy(xc, xs, nv3 * sizeof(double));
      memcpy(v, vs, nv3 * sizeof(double));
      cb_integrator_step(warm, xc, v, &st);
      cb_integrator_free(warm);
    }
    int nchoice = reuse ? NREUSE : 1;
    cb_integrator *it[MAXSEL][NREUSE] = {{NULL}};
    for (int k = 0; k < nsel; k++)
      for (int ch = 0; ch < nchoice; ch++) {
        const variant *vr = &VARIANTS[sel[k]];
        it[k][ch] = make(&c, s, vr->solver, vr->sets, reuse ? REUSE[ch].sets : NULL);
        if (!it[k][ch]) return 1;
      }
    double tot[MAXSEL][NREUSE][MAXREPS], set[MAXSEL][NREUSE][MAXREPS], sol[MAXSEL][NREUSE][MAXREPS];
    int iters[MAXSEL][NREUSE] = {{0}}, newton[MAXSEL][NREUSE] = {{0}}, setups[MAXSEL][NREUSE] = {{0}},
        stat[MAXSEL][NREUSE] = {{0}}, nnull[MAXSEL][NREUSE] = {{0}};
    double resid[MAXSEL][NREUSE] = {{0}}, dist[MAXSEL][NREUSE] = {{0}}, lastg[MAXSEL][NREUSE] = {{0}};
    for (int rd = 0; rd < reps; rd++)
      for (int k = 0; k < nsel; k++)
        for (int ch = 0; ch < nchoice; ch++) {
          cb_integrator *I = it[k][ch];
          memcpy(x, xs, nv3 * sizeof(double));
          memcpy(v, vs, nv3 * sizeof(double));
          cb_solver_forget(I->solver);
          I->solver->step = 0;
          double t_set = 0, t_sol = 0;
          int its = 0, nits = 0, stv = 0, setups0 = I->solver->stats.pc_setups;
          for (int t = 0; t < (reuse ? steps : 1); t++) {
            int rs = cb_integrator_step(I, x, v, &st);
            if (!reuse) rs = st.linear_status; /* one Newton iteration at tol 0 is "not converged" by design */
            if (rs != CB_OK && !stv) stv = rs;
            t_set += st.factor_ms;
            t_sol += st.solve_ms;
            its += st.linear_iters;
            nits += st.newton_iters;
            lastg[k][ch] = st.rel_grad;
          }
          tot[k][ch][rd] = t_set + t_sol;
          set[k][ch][rd] = t_set;
          sol[k][ch][rd] = t_sol;
          iters[k][ch] = its;
          newton[k][ch] = nits;
          setups[k][ch] = I->solver->stats.pc_setups - setups0;
          stat[k][ch] = stv;
          resid[k][ch] = I->solver->stats.rel_residual;
          nnull[k][ch] = I->solver->stats.near_null;
          if (!reuse) {
            double num = 0, den = 0;
            for (size_t i = 0; i < nv3; i++) {
              num += (x[i] - xc[i]) * (x[i] - xc[i]);
              den += (xc[i] - xs[i]) * (xc[i] - xs[i]);
            }
            dist[k][ch] = den > 0 ? sqrt(num / den) : sqrt(num);
          }
        }
    for (int k = 0; k < nsel; k++)
      for (int ch = 0; ch < nchoice; ch++) {
        const variant *vr = &VARIANTS[sel[k]];
        double med, lo, hi, smed, lo2, hi2, vmed;
        range(tot[k][ch], reps, &med, &lo, &hi);
        range(set[k][ch], reps, &smed, &lo2, &hi2);
        range(sol[k][ch], reps, &vmed, &lo2, &hi2);
        if (reuse) {
          cb_csv_printf(csv.f, "%d,%d,%s,%s,%s,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%d,%d,%.3g,%s\n", n,
                        (int)it[k][ch]->sys->A.n, vr->name, vr->solver, REUSE[ch].name, steps, reps, med, lo, hi, smed,
                        vmed, iters[k][ch], newton[k][ch], setups[k][ch], lastg[k][ch], cb_status_name(stat[k][ch]));
          printf("bench_petsc: %4d^2 %-14s %-9s total %9.1f ms [%9.1f, %9.1f] set-up %9.1f solve %9.1f, %6d Krylov "
                 "its, %3d Newton its, %3d set-ups, last rel grad %.2g, %s\n",
                 n, vr->name, REUSE[ch].name, med, lo, hi, smed, vmed, iters[k][ch], newton[k][ch], setups[k][ch],
                 lastg[k][ch], cb_status_name(stat[k][ch]));
        } else {
          cb_csv_printf(csv.f, "%d,%d,%s,%s,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%.3g,%d,%.3g,%s\n", n,
                        (int)it[k][ch]->sys->A.n, vr->name, vr->solver, reps, med, lo, hi, smed, vmed, iters[k][ch],
                        resid[k][ch], nnull[k][ch], dist[k][ch], cb_status_name(stat[k][ch]));
          printf("bench_petsc: %4d^2 %-14s total %9.1f ms [%9.1f, %9.1f] set-up %9.1f solve %9.1f, %6d its, rel "
                 "residual %.2g, near-null %d, to CHOLMOD's step %.2g, %s\n",
                 n, vr->name, med, lo, hi, smed, vmed, iters[k][ch], resid[k][ch], nnull[k][ch], dist[k][ch],
                 cb_status_name(stat[k][ch]));
        }
        if (stat[k][ch] && stat[k][ch] != CB_NOT_CONVERGED) status = 1;
        cb_integrator_free(it[k][ch]);
      }
    fflush(csv.f);
    fflush(stdout);
    cb_scene_free(s);
    free(xs);
    free(vs);
    free(x);
    free(v);
    free(xc);
  }
  if (cb_outfile_commit(&csv)) {
    fprintf(stderr, "bench_petsc: %s\n", cb_error_message());
    return 2;
  }
  return status;
}
