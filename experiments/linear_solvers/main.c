/* linear_solvers: Jacobi(alpha), Chebyshev-Jacobi, CG, PCG and CHOLMOD on real
 * Newton systems A dx = b, A = M/dt^2 + H, captured mid-simulation (claims
 * J1-J4 and the inexact-Newton table). See README "### linear_solvers".
 *
 * Per scene: simulate to t_capture, copy the system of the first Newton
 * iteration of that step (lib/instruments/capture.c), compute the spectrum of D^-1 A
 * (Lanczos + shift-invert Lanczos; GSL dense when small: lib/instruments/spectrum.c) and
 * the reference x* (CHOLMOD, refined once), then trace every solve
 * iteration by iteration against x* (lib/instruments/solve_trace.c).
 *
 * Outputs: results/linear_solvers.csv (one row per scene, sweep, solver,
 * parameters, iteration), _scenes.csv (spectra), _runs.csv (one row per
 * run: rates, iterations to 1e-6), _newton.csv (step error cut at K). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "capture.h"
#include <clothbench/solver.h>
#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include "experiment.h"
#include "memory.h"
#include "provenance.h"
#include "scene_decl.h"
#include "sweep.h"
#include "solve_trace.h"
#include "spectrum.h"
#include "stats.h"

/* Scenes: the lab cloth (10 m square, total mass 441 kg: vertex_mass = 441/n^2)
 * at n^2 vertices, stiffness k and time step dt. Roles: "spectrum" = the
 * spectrum only; "edges" = every solver, and the alpha sweep only past the
 * limit; "full" = every solver and the whole alpha sweep; "j3" = "full" plus
 * the Chebyshev rho sweep (J3). t_capture: simulated time of the captured
 * step (s); when: QUICK, FULL or BOTH. One cell per scene of the mode. */
enum { QUICK = 1, FULL = 2, BOTH = 3 };
typedef struct {
  cb_scene_decl scene;
  double t_capture;
  int when;
} scene_plan;
#define LAB(n, m, k, dt) \
  "mesh.n=" #n, "material.vertex_mass=441/" #m, "material.stretch_k=" #k, "integrator.dt=" dt, NULL
static const scene_plan scenes[] = {{{"small11", "hanging.ini", {LAB(11, 121, 8000, "1/30")}, "full"}, 0.5, BOTH},
                                    {{"lab", "hanging.ini", {LAB(21, 441, 8000, "1/30")}, "j3"}, 0.5, BOTH},
                                    {{"lab_rest", "hanging.ini", {LAB(21, 441, 8000, "1/30")}, "spectrum"}, 0.0, BOTH},
                                    {{"k1e5", "hanging.ini", {LAB(21, 441, 1e5, "1/30")}, "full"}, 0.5, BOTH},
                                    {{"k1e7", "hanging.ini", {LAB(21, 441, 1e7, "1/30")}, "edges"}, 0.5, BOTH},
                                    {{"dt240", "hanging.ini", {LAB(21, 441, 8000, "1/240")}, "full"}, 0.5, BOTH},
                                    {{"n32", "hanging.ini", {LAB(32, 1024, 8000, "1/30")}, "edges"}, 0.5, QUICK},
                                    {{"n64", "hanging.ini", {LAB(64, 4096, 8000, "1/30")}, "edges"}, 0.5, FULL},
                                    {{"n128", "hanging.ini", {LAB(128, 16384, 8000, "1/30")}, "edges"}, 0.5, FULL}};
enum { NSCENES = sizeof scenes / sizeof scenes[0] };
enum { T_MAIN, T_SCENES, T_RUNS, T_NEWTON, T_SCALING }; /* tables, in the order opened */

/* J4's scaling family: the lab cloth at grid_n^2 vertices, the system of the first Newton iteration of
 * step SCALE_STEP (one Newton iteration per step before it), with a manufactured solution x* (b = A x*).
 * Quick runs stop at 32^2, smoke runs 8^2 alone, full runs at 512^2; --scale (SCALE=1) adds 1024^2. */
static const int scale_n[] = {8, 16, 32, 64, 128, 256, 512, 1024};
#define SCALE_QUICK_MAX 32
#define SCALE_FULL_MAX 512 /* 1024^2 (about 1.5 h of this cell alone) only with --scale / SCALE=1 */
#define SCALE_STEP 1       /* captured step (0-based): the cloth has started to fall */
#define SCALE_ERR 1e-6     /* the error |x - x*|/|x*| every solver is timed to */
#define SCALE_BUDGET \
  2.0 /* an iterative solver gets SCALE_BUDGET x CHOLMOD's time + SCALE_FLOOR_MS to reach it: one that \
         needs more is not the best unless all do, and then CHOLMOD is the cheaper either way */
#define SCALE_FLOOR_MS 50.0
#define SCALE_FLOOR_QUICK_MS \
  1000.0 /* --quick (up to 32^2): every solver gets there, so the CSV is the same from run to run */
#define SCALE_COLUMNS \
  "scene,grid_n,n_dofs,nnz,solver,alpha,rho,iters_to_err,budget_ms,error,analyze_ms,factor_ms,solve_ms," \
  "wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,capped_wall_ms,nnz_factor,lmax_over_lmin,mem_peak_mib," \
  "status"
enum { SCALE_COLS = 23 };
static const double alpha_fracs[] = {0.1, 0.25, 0.5, 0.75, 0.9, 0.98, 1.02, 1.1, 1.5}; /* x alpha_max (J1) */
static const double rhos[] = {0.90, 0.92, 0.94, 0.95, 0.96, 0.97, 0.98, 0.99, 0.995, 0.999, 0.9999}; /* J3 */
static const int newton_k[] = {4, 8, 16, 32, 64};
#define PRE_NEWTON_ITERS 5 /* Newton iterations per step on the way to the capture */
#define TOL 1e-10          /* relative residual at which every iterative run stops */

typedef struct {
  cb_experiment e;
  FILE *const *out;          /* the running cell's tables */
  int cell[NSCENES], ncells; /* scenes of this mode */
  int nscale;                /* sizes of the scaling sweep in this mode */
  const char *scene;
  const cb_capture *cap;
  const double *xref;
  double lmin, lmax; /* of D^-1 A: dense if computed, else Lanczos */
  int max_iters, sweep_iters;
} ctx;

static void fmt(char *buf, size_t n, double v) { /* empty for "not applicable" */
  if (isnan(v)) buf[0] = 0;
  else snprintf(buf, n, "%.17g", v);
}

/* A solve to trace: sweep, solver, alpha and rho (NaN: not applicable), iteration cap. */
typedef struct {
  const char *sweep, *solver;
  double alpha, rho;
  int max_iters;
} run_spec;

static int trace_one(ctx *c, const run_spec *r, cb_trace *t) {
  cb_solver_params p = cb_solver_params_default();
  p.tol = TOL;
  p.max_iters = r->max_iters;
  p.alpha = isnan(r->alpha) ? 1.0 : r->alpha;
  p.rho = isnan(r->rho) || r->rho == 0 ? CB_AUTO : r->rho; /* the spec's rho 0: auto */
  return cb_trace_solve(r->solver, &p, &c->cap->A, c->cap->b, c->xref, NULL, NULL, t);
}

/* The repeats of one solve trace the same iterations (the solve is deterministic); only their times differ. */
static int same_rows(const cb_trace *a, const cb_trace *b) {
  if (a->nrows != b->nrows || a->status != b->status) return 0;
  for (int i = 0; i < a->nrows; i++)
    if (a->rows[i].iter != b->rows[i].iter) return 0;
  return 1;
}

/* Writes one solve's rows (repeats t[0..nrep), identical but for their times): the main table with
 * every row's wall_ms as the median over the repeats and its spread, the runs summary and (main
 * runs) its inexact-Newton rows. */
static void write_run(ctx *c, const run_spec *spec, const cb_trace *t, int nrep) {
  double alpha = spec->alpha, rho = spec->rho;
  const cb_trace *t0 = &t[0];
  if (!strcmp(spec->solver, "chebyshev")) rho = t0->rho; /* the estimate when rho = auto */
  char a[32], an[32], r[32], pr[32], rt[32], rp[32];
  fmt(a, sizeof a, alpha);
  fmt(r, sizeof r, rho);
  const char *status = cb_status_name(t0->status);
  cb_timing w6 = {0}, setup = {0}, rho_ms = {0}, total = {0};
  const cb_trace_row *hit = NULL, *last = t0->nrows ? &t0->rows[t0->nrows - 1] : NULL;
  int ihit = -1;
  for (int i = 0; i < t0->nrows && !hit; i++)
    if (t0->rows[i].rel_residual <= 1e-6) hit = &t0->rows[ihit = i];
  for (int k = 0; k < nrep; k++) {
    cb_timing_add(&setup, t[k].setup_ms);
    cb_timing_add(&rho_ms, t[k].rho_ms);
    cb_timing_add(&total, t[k].wall_ms);
    if (hit) cb_timing_add(&w6, t[k].rows[ihit].wall_ms);
  }
  for (int i = 0; i < t0->nrows; i++) {
    const cb_trace_row *w = &t0->rows[i];
    cb_timing wr = {0};
    for (int k = 0; k < nrep; k++) cb_timing_add(&wr, t[k].rows[i].wall_ms);
    cb_csv_printf(c->out[T_MAIN], "%s,%s,%s,%s,%s,%d,%.17g,", c->scene, spec->sweep, spec->solver, a, r, w->iter,
                  w->rel_residual);
    cb_timing_csv(c->out[T_MAIN], &wr, 1.0);
    fputc(',', c->out[T_MAIN]);
    if (nrep > 1) cb_timing_csv_each(c->out[T_MAIN], &wr, 1.0);
    cb_csv_printf(c->out[T_MAIN], ",%d,%s,%.17g\n", nrep, status, w->error);
  }
  fmt(pr, sizeof pr, isnan(alpha) ? NAN : cb_jacobi_rho(c->lmin, c->lmax, alpha));
  fmt(an, sizeof an, alpha * c->lmax / 2);
  fmt(rt, sizeof rt, cb_trace_rate(t0->rows, t0->nrows, 0.25));
  fmt(rp, sizeof rp, cb_trace_rate_window(t0->rows, t0->nrows, 0.5, 0.75));
  cb_csv_printf(c->out[T_RUNS], "%s,%s,%s,%s,%s,%s,%s,%d,%.17g,%s,%s,", c->scene, spec->sweep, spec->solver, a, an, r,
                pr, t0->iters, last ? last->rel_residual : cb_csv_na(), rt, rp);
  if (hit) cb_csv_printf(c->out[T_RUNS], "%d,%.6f,", hit->iter, cb_timing_median(&w6));
  else fputs(",,", c->out[T_RUNS]);
  cb_csv_printf(c->out[T_RUNS], "%.6f,%.6f,", cb_timing_median(&setup), cb_timing_median(&rho_ms));
  cb_timing_csv(c->out[T_RUNS], &total, 1.0);
  cb_csv_printf(c->out[T_RUNS], ",%d,%s\n", nrep, status);
  int lab995 =
      !strcmp(spec->sweep, "rho") && fabs(rho - 0.995) < 1e-12 && fabs(alpha - 2 / (c->lmin + c->lmax)) < 1e-12;
  if ((!strcmp(spec->sweep, "main") && strcmp(spec->solver, "cholmod")) || lab995)
    for (size_t k = 0; k < sizeof newton_k / sizeof *newton_k; k++) {
      const cb_trace_row *w = cb_trace_at(t0, newton_k[k]);
      if (!w) continue;
      cb_timing wk = {0};
      for (int q = 0; q < nrep; q++) cb_timing_add(&wk, t[q].rows[w - t0->rows].wall_ms);
      int cut = w->iter == newton_k[k] && w->iter < t0->iters; /* stopped by the cut, not by the run */
      const char *s = cut ? (w->rel_residual <= TOL ? "ok" : "max_iters") : status;
      cb_csv_printf(c->out[T_NEWTON], "%s,%s,%s,%s,%d,%d,%.17g,%.17g,%.6f,%s\n", c->scene, spec->solver, a, r,
                    newton_k[k], w->iter, w->rel_residual, w->error, cb_timing_median(&wk), s);
    }
}

/* Traces the solves g[0..n): once each (repeat = 0), or in interleaved rounds (every solve once per
 * round; stats.h: 3 rounds with --quick, 2-5 in a full run by their cost; a solve under 25 ms timed
 * right after an untimed one of its own), and writes their rows. */
static int run_group(ctx *c, const run_spec *g, int n, int repeat) {
  enum { MAXG = 16 };
  static cb_trace t[MAXG][CB_TIMING_MAX];
  if (n > MAXG) return cb_fail("linear_solvers: more than %d solves in one group", MAXG);
  int st = CB_OK, rounds = 0;
  double spent = 0;
  for (; st == CB_OK && (rounds == 0 || (repeat && cb_timing_more(c->e.quick, rounds, spent))); rounds++)
    for (int i = 0; i < n; i++) {
      memset(&t[i][rounds], 0, sizeof t[i][rounds]);
      if (st == CB_OK) st = trace_one(c, &g[i], &t[i][rounds]);
      if (st == CB_OK && repeat && cb_timing_warm(t[i][rounds].wall_ms)) { /* a short solve: that was its warm-up */
        cb_trace_free(&t[i][rounds]);
        st = trace_one(c, &g[i], &t[i][rounds]);
      }
      if (st == CB_OK && rounds > 0 && !same_rows(&t[i][0], &t[i][rounds]))
        st = cb_fail("linear_solvers: %s %s on %s: repeat %d traced other iterations than the first", g[i].sweep,
                     g[i].solver, c->scene, rounds + 1);
      spent += t[i][rounds].wall_ms;
    }
  for (int i = 0; st == CB_OK && i < n; i++) write_run(c, &g[i], t[i], rounds);
  for (int i = 0; i < n; i++)
    for (int k = 0; k < rounds; k++) cb_trace_free(&t[i][k]);
  return st;
}

static int run(ctx *c, const char *sweep, const char *solver, double alpha, double rho, int max_iters) {
  run_spec r = {sweep, solver, alpha, rho, max_iters};
  return run_group(c, &r, 1, !strcmp(sweep, "rho_auto")); /* rho_auto: its estimate's time is reported (J3) */
}

/* A scene whose capture or spectrum failed (e.g. the run diverged, A not SPD) keeps its row. */
static int failed(FILE *sc, const char *label, int n, int status) {
  cb_csv_printf(sc, "%s,%d,,,,,,,,,,,,,,,,,,,,,,,,,,,%s\n", label, n, cb_status_name(status));
  fprintf(stderr, "linear_solvers: scene %s: %s (kept as a row)\n", label, cb_error_message());
  return CB_OK;
}

/* Capture, spectra and the scenes row; then the runs the scene's role asks for. */
static int scene(ctx *c, const scene_plan *d, FILE *sc) {
  char pre[64];
  snprintf(pre, sizeof pre, "integrator.max_iters=%d", PRE_NEWTON_ITERS);
  const char *const more[] = {pre, NULL};
  cb_config cfg;
  int st = cb_scene_decl_config(&c->e, &d->scene, more, &cfg);
  if (st) return st;
  const char *label = d->scene.label;
  const int grid_n = cfg.mesh_n;
  const double mass = cfg.vertex_mass, dt = cfg.dt, stiff = cfg.stretch_k;
  cb_capture cap;
  st = cb_capture_newton_system(&cfg, (int)lround(d->t_capture / dt), 0, &cap);
  if (st > 0) return failed(sc, label, grid_n, st);
  if (st) return st;
  int n = cap.A.n, bad;
  double ratio, *dh = cb_malloc((size_t)n, sizeof(double)), *xref = cb_malloc((size_t)n, sizeof(double));
  cb_spectrum lz, de = {NAN, NAN, 0, 0, 0, 0, NAN}, lab = {0};
  st = !dh || !xref ? CB_ENOMEM : cb_jacobi_scaling(&cap.A, dh);
  if (st == CB_OK) st = cb_spectrum_lanczos(&cap.A, dh, &lz);
  if (st == CB_OK && n <= (c->e.quick ? 400 : 1500)) st = cb_spectrum_dense(&cap.A, dh, &de);
  double clab = mass / (dt * dt) + 4 * stiff; /* the lab's constant diagonal m/dt^2 + 4k */
  for (int i = 0; st == CB_OK && i < n; i++) dh[i] = 1 / sqrt(clab);
  if (st == CB_OK) st = cb_spectrum_lanczos(&cap.A, dh, &lab);
  if (st == CB_OK) st = cb_trace_reference(&cap.A, cap.b, xref);
  if (st > 0) {
    st = failed(sc, label, grid_n, st);
    goto done;
  }
  if (st) goto done;
  cb_diag_dominance(&cap.A, &bad, &ratio);
  int dense = !isnan(de.lmin);
  c->lmin = dense ? de.lmin : lz.lmin;
  c->lmax = dense ? de.lmax : lz.lmax;
  double amax = 2 / c->lmax, astar = 2 / (c->lmin + c->lmax);
  cb_csv_printf(sc, "%s,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%d,%.17g,", label, grid_n, n, cap.A.nnz, stiff, dt,
                mass, cap.t_s, cap.step, cap.sim_ms, bad, ratio);
  /* the dense spectrum only on small systems: elsewhere its columns are empty */
  cb_csv_printf(sc, "%.17g,%.17g,%.17g,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%s,", lz.lmin, lz.lmax, lz.res_min,
                lz.res_max, lz.steps_min, lz.steps_max, lz.ms, dense ? de.lmin : cb_csv_na(),
                dense ? de.lmax : cb_csv_na(), dense ? de.ms : cb_csv_na(), dense ? "dense" : "lanczos");
  cb_csv_printf(sc, "%.17g,%.17g,%.17g,%.17g,%.17g,ok\n", amax, astar, cb_jacobi_rho(c->lmin, c->lmax, 1.0),
                cb_jacobi_rho(c->lmin, c->lmax, astar), cb_jacobi_rho(lab.lmin, lab.lmax, 1.0));
  int j3 = cb_scene_decl_is(&d->scene, "j3") || c->e.smoke; /* smoke: its one scene runs every sweep */
  int full = cb_scene_decl_is(&d->scene, "full") || j3;
  if (cb_scene_decl_is(&d->scene, "spectrum")) goto done;
  c->scene = label;
  c->cap = &cap;
  c->xref = xref;
  /* every registered solver; Jacobi-type ones at alpha*, Chebyshev with rho = auto; timed in interleaved rounds */
  run_spec mains[16];
  int nmain = 0;
  for (int s = 0; cb_solver_types[s] && nmain < 16; s++) {
    unsigned f = cb_solver_types[s]->flags;
    mains[nmain++] = (run_spec){"main", cb_solver_types[s]->name, f & CB_SOLVER_USES_ALPHA ? astar : NAN,
                                f & CB_SOLVER_USES_RHO ? 0.0 : NAN, c->max_iters};
  }
  if (st == CB_OK) st = run_group(c, mains, nmain, 1);
  /* J1: vanilla alpha = 1 and fractions of the predicted limit 2/lambda_max */
  st = st ? st : run(c, "alpha", "jacobi", 1.0, NAN, c->sweep_iters);
  for (size_t i = 0; st == CB_OK && i < sizeof alpha_fracs / sizeof *alpha_fracs; i++)
    if (full || alpha_fracs[i] > 1) st = run(c, "alpha", "jacobi", alpha_fracs[i] * amax, NAN, c->sweep_iters);
  /* J3 (lab): the rho sweep at alpha*, at alpha_max/2 and at vanilla alpha = 1 */
  const double alphas[] = {astar, 0.5 * amax, 1.0};
  for (int i = 0; st == CB_OK && j3 && i < 3; i++) {
    for (size_t j = 0; st == CB_OK && j < sizeof rhos / sizeof *rhos; j++)
      st = run(c, "rho", "chebyshev", alphas[i], rhos[j], c->sweep_iters);
    if (st == CB_OK && i > 0) st = run(c, "rho_auto", "chebyshev", alphas[i], 0.0, c->sweep_iters);
  }
done:
  free(dh);
  free(xref);
  cb_capture_free(&cap);
  return st;
}

/* ---- J4: cost to a manufactured solution against mesh size ------------------------------------ */

/* x*: a smooth field over the cloth, sin(pi u) sin(pi v) scaled per axis (a Newton step is smooth: the
 * hard part for an iterative solver), plus 10% of a fixed pseudo-random field in [-1, 1]. */
static void manufactured(const cb_capture *cap, int grid_n, double *xs) {
  const double pi = 3.14159265358979323846;
  unsigned long long h = 0x9e3779b97f4a7c15ULL;
  for (int blk = 0; blk < cap->A.n / 3; blk++) {
    int v = cap->scene->free_vertex[blk];
    double u = (double)(v % grid_n) / (grid_n - 1), w = (double)(v / grid_n) / (grid_n - 1);
    for (int k = 0; k < 3; k++) {
      h ^= h >> 12, h ^= h << 25, h ^= h >> 27; /* xorshift64 */
      double r = (double)((h * 2685821657736338717ULL) >> 11) / 9007199254740992.0 * 2 - 1;
      xs[3 * blk + k] = (1 + 0.5 * k) * sin(pi * u) * sin(pi * w) + 0.1 * r;
    }
  }
}

typedef struct {
  run_spec r;
  int reached;      /* the untimed traced run reached SCALE_ERR at iteration iters */
  int iters, cap;   /* iterations to SCALE_ERR (or run); the iteration cap of the traced run */
  double trace_ms;  /* the traced run's wall time (a lower bound when not reached) */
  double budget_ms; /* its time budget: SCALE_BUDGET x CHOLMOD's time + the floor */
  cb_timing total;
  double analyze[CB_TIMING_MAX], factor[CB_TIMING_MAX], solve[CB_TIMING_MAX], err, fnnz;
  double mem_bytes; /* the peak resident memory of its first timed solve beyond what was resident before (memory.h) */
  int status;
} scale_run;

/* One timed, untraced solve of a scaling run (for iterative ones: exactly its iterations to SCALE_ERR). */
static int scale_time(const ctx *c, const double *b, const double *xs, scale_run *u, cb_timed_solve *ts) {
  cb_solver_params p = cb_solver_params_default();
  p.tol = 0; /* run exactly max_iters iterations (direct solvers ignore both) */
  p.max_iters = u->iters > 0 ? u->iters : 1;
  p.alpha = isnan(u->r.alpha) ? 1.0 : u->r.alpha;
  p.rho = isnan(u->r.rho) || u->r.rho == 0 ? CB_AUTO : u->r.rho; /* the spec's rho 0: auto */
  return cb_trace_timed_solve(u->r.solver, &p, &c->cap->A, b, xs, ts);
}

/* A size whose capture or matrix failed keeps one row, with the status. */
static int scale_failed(FILE *f, const char *label, int grid_n, int status) {
  cb_csv_printf(f, "%s,%d", label, grid_n);
  for (int k = 0; k < SCALE_COLS - 3; k++) fputc(',', f);
  cb_csv_printf(f, ",%s\n", cb_status_name(status));
  fprintf(stderr, "linear_solvers: scene %s: %s (kept as a row)\n", label, cb_error_message());
  return CB_OK;
}

/* The scaling cell's solves on the captured system (b = A x*): budget, traced runs, timed rounds, rows. */
static int scale_solvers(ctx *c, int grid_n, const char *label, const cb_capture *cap, const double *xs,
                         const double *b, const cb_spectrum *lz, scale_run *runs, FILE *const *out) {
  int st = CB_OK, nrun = 0;
  double astar = 2 / (lz->lmin + lz->lmax);
  c->cap = cap;
  for (int s = 0; st == CB_OK && cb_solver_types[s] && nrun < 16; s++) {
    unsigned f = cb_solver_types[s]->flags;
    scale_run *u = &runs[nrun++];
    u->r = (run_spec){"scaling", cb_solver_types[s]->name, f & CB_SOLVER_USES_ALPHA ? astar : NAN,
                      f & CB_SOLVER_USES_RHO ? 0.0 : NAN, 1};
    u->reached = (f & CB_SOLVER_DIRECT) != 0;
    u->iters = 1;
    u->mem_bytes = NAN;
  }
  /* CHOLMOD's time (one untimed run) sets the iterative solvers' budget */
  double chol_ms = 0;
  for (int i = 0; st == CB_OK && i < nrun; i++) {
    cb_timed_solve ts;
    if (!(cb_solver_types[i]->flags & CB_SOLVER_DIRECT)) continue;
    st = scale_time(c, b, xs, &runs[i], &ts);
    if (st == CB_OK && ts.status == CB_OK) chol_ms = fmax(chol_ms, ts.total_ms);
  }
  /* each iterative solver: a short probe for its cost per iteration, then one traced run (error at every
   * iteration) within the budget, which finds its first iteration with error <= SCALE_ERR */
  for (int i = 0; st == CB_OK && i < nrun; i++) {
    scale_run *u = &runs[i];
    if (u->reached) continue;
    cb_timed_solve ts;
    u->iters = 20;
    st = scale_time(c, b, xs, u, &ts);
    double per = ts.iters > 0 ? fmax(ts.solve_ms / ts.iters, 1e-6) : 1;
    u->budget_ms = SCALE_BUDGET * chol_ms + (c->e.quick ? SCALE_FLOOR_QUICK_MS : SCALE_FLOOR_MS);
    u->cap = (int)fmin(1e6, fmax(50, ceil((u->budget_ms - ts.factor_ms) / per)));
    cb_solver_params p = cb_solver_params_default();
    p.tol = 1e-15;
    p.max_iters = u->cap;
    p.alpha = isnan(u->r.alpha) ? 1.0 : u->r.alpha;
    p.rho = isnan(u->r.rho) || u->r.rho == 0 ? CB_AUTO : u->r.rho; /* the spec's rho 0: auto */
    cb_trace_params tp = cb_trace_params_default();
    tp.keep_all = 0;
    tp.growth = 2;
    tp.mark_err = SCALE_ERR;
    /* The traced run goes on to its cap after it has found the iteration (the solvers run max_iters
     * iterations unless they converge to tol), which made each iterative solver cost its whole budget.
     * So caps of 64, 128, ... iterations are tried first, up to u->cap: the iterations of a solver do not
     * depend on its cap, so the first with error <= SCALE_ERR is the same, and a run that does not get there
     * is the one at u->cap, as before (its status and time are the row's). */
    cb_trace t;
    memset(&t, 0, sizeof t);
    for (int tcap = u->cap < 64 ? u->cap : 64; st == CB_OK; tcap = tcap > u->cap / 2 ? u->cap : 2 * tcap) {
      p.max_iters = tcap;
      st = cb_trace_solve(u->r.solver, &p, &cap->A, b, xs, &tp, NULL, &t);
      if (st || t.iter_err >= 0 || tcap == u->cap) break;
      cb_trace_free(&t);
    }
    if (st == CB_OK) {
      u->reached = t.iter_err >= 0;
      u->iters = u->reached ? t.iter_err : t.iters;
      u->trace_ms = t.wall_ms;
      u->status = t.status;
    }
    cb_trace_free(&t);
  }
  /* the solvers that reached SCALE_ERR, timed untraced in interleaved rounds (stats.h) */
  int rounds = 0;
  double spent = 0;
  for (; st == CB_OK && (rounds == 0 || cb_timing_more(c->e.quick, rounds, spent)); rounds++)
    for (int i = 0; st == CB_OK && i < nrun; i++) {
      scale_run *u = &runs[i];
      if (!u->reached) continue;
      cb_timed_solve ts;
      cb_mem_probe mp;
      if (rounds == 0) cb_mem_probe_begin(&mp); /* outside the timed solve (scale_time times inside) */
      st = scale_time(c, b, xs, u, &ts);
      if (rounds == 0) u->mem_bytes = cb_mem_probe_end(&mp);
      if (st == CB_OK && cb_timing_warm(ts.total_ms)) st = scale_time(c, b, xs, u, &ts); /* that was its warm-up */
      if (st) break;
      cb_timing_add(&u->total, ts.total_ms);
      u->analyze[rounds] = ts.analyze_ms;
      u->factor[rounds] = ts.factor_ms;
      u->solve[rounds] = ts.solve_ms;
      u->err = ts.error;
      u->fnnz = ts.factor_nnz;
      u->status = ts.status;
      spent += ts.total_ms;
    }
  for (int i = 0; st == CB_OK && i < nrun; i++) {
    scale_run *u = &runs[i];
    char a[32], r[32], it[32], ms[3][32];
    fmt(a, sizeof a, u->r.alpha);
    fmt(r, sizeof r, u->r.rho);
    fmt(it, sizeof it, u->reached ? u->iters : NAN);
    int nrep = u->total.n;
    double m3[3];
    for (int k = 0; k < 3; k++) {
      double *v = k == 0 ? u->analyze : k == 1 ? u->factor : u->solve, tmp[CB_TIMING_MAX];
      memcpy(tmp, v, sizeof tmp);
      m3[k] = nrep ? cb_median(tmp, nrep) : NAN;
      if (isnan(m3[k])) ms[k][0] = 0;
      else snprintf(ms[k], sizeof ms[k], "%.6f", m3[k]);
    }
    /* not reached: the status of the capped traced run (max_iters, diverged, ...), its time a lower bound */
    /* reached: ok if the timed run's error is at the target (an iterative run stops at max_iters by design) */
    int direct = (cb_solver_types[i]->flags & CB_SOLVER_DIRECT) != 0;
    int st_row = !u->reached           ? (u->status == CB_OK ? CB_NOT_CONVERGED : u->status)
                 : direct              ? u->status
                 : u->err <= SCALE_ERR ? CB_OK
                                       : CB_NOT_CONVERGED;
    const char *status = cb_status_name(st_row);
    char cap_s[32], err[32], lb[32];
    fmt(cap_s, sizeof cap_s, direct ? NAN : u->budget_ms);
    fmt(err, sizeof err, u->reached ? u->err : NAN);
    fmt(lb, sizeof lb, u->reached ? NAN : u->trace_ms);
    cb_csv_printf(out[T_SCALING], "%s,%d,%d,%d,%s,%s,%s,%s,%s,%s,%s,%s,%s,", label, grid_n, cap->A.n, cap->A.nnz,
                  u->r.solver, a, r, it, cap_s, err, ms[0], ms[1], ms[2]);
    cb_timing_csv(out[T_SCALING], &u->total, 1.0);
    fputc(',', out[T_SCALING]);
    cb_timing_csv_each(out[T_SCALING], &u->total, 1.0);
    char mem[32];
    fmt(mem, sizeof mem, u->reached ? u->mem_bytes / (1024.0 * 1024.0) : NAN);
    cb_csv_printf(out[T_SCALING], ",%d,%s,%.17g,%.17g,%s,%s\n", nrep, lb, direct ? u->fnnz : cb_csv_na(),
                  lz->lmax / lz->lmin, mem, status);
  }
  return st;
}

static int scale_cell(ctx *c, int grid_n, FILE *const *out) {
  char mn[32], vm[48];
  snprintf(mn, sizeof mn, "mesh.n=%d", grid_n);
  snprintf(vm, sizeof vm, "material.vertex_mass=441/%d", grid_n * grid_n);
  char label[32];
  snprintf(label, sizeof label, "scale%d", grid_n);
  cb_scene_decl decl = {
      label, "hanging.ini", {mn, vm, "material.stretch_k=8000", "integrator.dt=1/30", NULL}, "scaling"};
  const char *const more[] = {"integrator.max_iters=1",
                              NULL}; /* one factorisation per step on the way (256^2: ~1.5 s) */
  cb_config cfg;
  int st = cb_scene_decl_config(&c->e, &decl, more, &cfg);
  if (st) return st;
  cb_capture cap;
  st = cb_capture_newton_system(&cfg, SCALE_STEP, 0, &cap);
  if (st > 0) return scale_failed(out[T_SCALING], label, grid_n, st);
  if (st) return st;
  int n = cap.A.n;
  double *xs = cb_malloc((size_t)n, sizeof(double)), *b = cb_malloc((size_t)n, sizeof(double)),
         *dh = cb_malloc((size_t)n, sizeof(double));
  scale_run *runs = cb_calloc(16, sizeof *runs);
  cb_spectrum lz = {0};
  st = !xs || !b || !dh || !runs ? CB_ENOMEM : CB_OK;
  if (st == CB_OK) {
    manufactured(&cap, grid_n, xs);
    cb_sparse_matvec(&cap.A, xs, b); /* b = A x* */
    st = cb_jacobi_scaling(&cap.A, dh);
  }
  if (st == CB_OK) st = cb_spectrum_lanczos(&cap.A, dh, &lz); /* alpha* for the Jacobi-type solvers (given free) */
  if (st > 0) st = scale_failed(out[T_SCALING], label, grid_n, st); /* A not SPD: no solver row */
  else if (st == CB_OK) st = scale_solvers(c, grid_n, label, &cap, xs, b, &lz, runs, out);
  c->cap = NULL;
  free(xs);
  free(b);
  free(dh);
  free(runs);
  cb_capture_free(&cap);
  return st;
}

static int scale_cell_run(long i, void *vc, FILE *const *out) { return scale_cell(vc, scale_n[i], out); }
static double scale_cost(long i, void *vc) {
  (void)vc;
  double g = scale_n[i];
  /* A quick run measured ~0.055 g^3 units up to 32^2 (0.06, 0.4 and 2.5 s at 8^2, 16^2, 32^2 on a busy
   * machine: about 1.4 ms a unit). Past that the cell grows about as g^2: the 512^2 cell took 595 s of CPU
   * (13.5 min on a shared machine), 17x less than g^3 from 32^2 predicts; the budgets of the solvers that
   * do not reach 1e-6 are a multiple of CHOLMOD's time, which grows slower than g^3 here. */
  return g <= 32 ? 15 + 0.055 * g * g * g : (15 + 0.055 * 32 * 32 * 32) * (g / 32) * (g / 32);
}

/* Cell i: the i-th scene of the mode. */
static int scene_cell(long i, void *vc, FILE *const *out) {
  ctx *c = vc;
  c->out = out;
  return scene(c, &scenes[c->cell[i]], out[T_SCENES]);
}

/* cost hint: the dofs, times the runs the role asks for (a quick run: 0.7-3 ms per unit) */
static double scene_cost(long i, void *vc) {
  const scene_plan *d = &scenes[((const ctx *)vc)->cell[i]];
  const char *mn = cb_scene_decl_override(&d->scene, "mesh.n"), *mk = cb_scene_decl_override(&d->scene, "material."
                                                                                                        "stretch_k");
  double n = mn ? atof(mn) : 1, k = mk ? atof(mk) : 8000;
  /* the iterative solves' iterations grow with the stiffness (scripts/calibrate-hints on a quick run: ~k^(1/4)) */
  return n * n * pow(k / 8000, 0.25) * (cb_scene_decl_is(&d->scene, "spectrum") ? 0.5 : 3);
}

int main(int argc, char **argv) {
  ctx c;
  memset(&c, 0, sizeof c);
  int rc = cb_experiment_begin(&c.e, "linear_solvers",
                               "Jacobi(alpha), Chebyshev-Jacobi, CG, PCG and CHOLMOD on Newton systems captured at "
                               "t = 0.5 s of the hanging-cloth scenes: alpha sweep (J1), iterations to 1e-6 (J2), "
                               "rho sweep (J3), error against wall time (J4), inexact Newton (side CSV).",
                               argc, argv);
  if (rc) return rc > 0 ? 0 : 1;
  /* every cell times a comparison (a scene's main solves, the scaling's solvers): each runs alone, and the
   * set-up before the first cell runs beside other untimed work */
  cb_experiment_timed_cells(&c.e, NULL);
  c.max_iters = c.e.quick ? 20000 : 1000000;
  c.sweep_iters = c.e.quick ? 1500 : 4000;
  char extra[1024];
  snprintf(extra, sizeof extra,
           "# capture: first Newton iteration of the step at t_capture; %d Newton iterations per step before it\n"
           "# solves: x0 = 0, tol = %g, max_iters = %d (sweeps %d); jacobi/chebyshev main runs at alpha* = "
           "2/(lmin+lmax) of D^-1 A\n# reference x*: CHOLMOD refined once; wall_ms includes set-up, not CHOLMOD's "
           "symbolic analysis; main and rho_auto solves are repeated (wall_ms: the median, wall_min_ms, wall_max_ms, "
           "wall_each_ms: the spread and every repeat, per row), the main ones in interleaved rounds\n",
           PRE_NEWTON_ITERS, TOL, c.max_iters, c.sweep_iters);
  char scale_extra[1024];
  snprintf(scale_extra, sizeof scale_extra,
           "# J4 scaling: the system of the first Newton iteration of step %d (0-based; one Newton iteration per step "
           "before it) of the lab cloth at grid_n^2, "
           "vertex mass 441/grid_n^2 kg, k = 8000 N/m, dt = 1/30 s; b = A x* for a manufactured x* "
           "(sin(pi u) sin(pi v) (1, 1.5, 2) per axis + 0.1 x a fixed random field in [-1, 1]); error = |x - x*|/|x*|\n"
           "# every solver from x = 0; an iterative solver's iters_to_err is its first iteration with error <= %g "
           "(found by a traced run whose iteration cap is worth budget_ms, %g x CHOLMOD's time + %g ms; "
           "capped_wall_ms: "
           "the traced time of a run that did not get there), then timed untraced for exactly those iterations; "
           "wall_ms = analyze + factor + solve, a fresh solver each time, all solvers of a size in interleaved rounds "
           "(wall_each_ms); Jacobi-type solvers get alpha* = 2/(lmin+lmax) of D^-1 A from Lanczos for free, "
           "Chebyshev estimates rho (counted); lmax_over_lmin = lmax/lmin of D^-1 A\n",
           SCALE_STEP, SCALE_ERR, SCALE_BUDGET, c.e.quick ? SCALE_FLOOR_QUICK_MS : SCALE_FLOOR_MS);
  rc = cb_experiment_table(&c.e, NULL, extra,
                           "scene,sweep,solver,alpha,rho,iter,rel_residual,wall_ms,wall_min_ms,wall_max_ms,"
                           "wall_each_ms,wall_repeats,status,error") != T_MAIN ||
       cb_experiment_table(&c.e, "scenes", extra,
                           "scene,grid_n,n_dofs,nnz,stretch_k_n_per_m,dt_s,vertex_mass_kg,capture_t_s,"
                           "capture_step,capture_ms,non_dd_rows,max_offdiag_ratio,lmin_lanczos,lmax_lanczos,"
                           "lmin_bound,lmax_bound,lmin_steps,lmax_steps,lanczos_ms,lmin_dense,lmax_dense,"
                           "dense_ms,spectrum,alpha_max,alpha_star,rho_vanilla,rho_star,rho_lab,status") != T_SCENES ||
       cb_experiment_table(&c.e, "runs", extra,
                           "scene,sweep,solver,alpha,alpha_over_max,rho,rho_predicted,iters,rel_residual,rate,rate_"
                           "prev,"
                           "iters_1e6,wall_to_1e6_ms,setup_ms,rho_ms,wall_ms,wall_min_ms,wall_max_ms,wall_repeats,"
                           "status") != T_RUNS ||
       cb_experiment_table(&c.e, "newton", extra,
                           "scene,solver,alpha,rho,max_iters,iters,rel_residual,step_error,wall_ms,status") !=
           T_NEWTON ||
       cb_experiment_table(&c.e, "scaling", scale_extra, SCALE_COLUMNS) != T_SCALING;
  if (rc) return cb_experiment_end(&c.e, CB_EIO), 2;
  int mode = c.e.quick ? QUICK : FULL;
  for (int i = 0; i < NSCENES; i++)
    if (c.e.smoke ? i == 0 : (scenes[i].when & mode) != 0) c.cell[c.ncells++] = i; /* smoke: small11 alone */
  for (size_t i = 0; i < sizeof scale_n / sizeof *scale_n; i++)
    if (c.e.smoke ? i == 0 : c.e.quick ? scale_n[i] <= SCALE_QUICK_MAX : c.e.scale || scale_n[i] <= SCALE_FULL_MAX)
      c.nscale = (int)i + 1;
  cb_sweep sw[] = {{"scenes", c.ncells, scene_cell, scene_cost, &c, NULL},
                   {"scaling", c.nscale, scale_cell_run, scale_cost, &c, NULL}};
  rc = cb_sweep_run(&c.e, sw, 2);
  rc = cb_experiment_end(&c.e, rc);
  return rc == CB_OK ? 0 : rc == CB_EIO ? 2 : 1;
}
