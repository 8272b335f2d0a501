/* nonlinear: the GAMES103 lab's own iteration and the other nonlinear
 * iterations on the implicit-Euler objective F (claims J3 panel a, W1, P1),
 * and error against run time for every implicit method.
 *
 * Outputs (results/):
 *   nonlinear.csv             J3, the lab's iteration: per rho, a trajectory of the lab scene
 *                             (chebyshev-nl, 32 iterations, d = m/dt^2 + 4k, damping 0.99):
 *                             whether and at which frame it diverged, the median relative
 *                             |grad F| after the 32 iterations, the linearised rho along the run
 *   nonlinear_spectrum.csv    rho(I - D^-1 A(x)) at sampled frames of each run (A = M/dt^2 + H(x),
 *                             exact Hessian, D the lab's diagonal; Lanczos)
 *   nonlinear_w1.csv          W1: iterations and wall time to relative |grad F| 1e-2 and 1e-4,
 *                             jacobi-nl vs chebyshev-nl and pd vs pd-chebyshev, at 21^2, 64^2, 128^2
 *                             (each traced run rerun with a larger cap until it reaches 1e-4)
 *   nonlinear_w1_trace.csv    the relative |grad F| per iteration of those steps (the figure)
 *   nonlinear_p1.csv          P1: per frame of an 81^2 cloth (and a stiff one), wall time and
 *                             step error against the converged step, for pd (10 iterations),
 *                             converged Newton (exact Hessian with line search, and drop) and
 *                             Baraff-Witkin
 *   nonlinear_p1_error.csv    P1: per frame, the iterations and wall time pd and exact Newton
 *                             need to reach step error 1e-2 and 1e-3
 *   nonlinear_error_time.csv  one step of every implicit method at several iteration counts:
 *                             step error and relative |grad F| against wall time
 * The scenes are the table SCENES below, the work four sweeps of cells (one
 * per phase), run by the shared sweep runner; --shard I/N splits them.
 * --smoke runs one small cell per sweep, on the lab scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include "csv.h"
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "reference.h"
#include "scene_decl.h"
#include "spectrum.h"
#include "stats.h"
#include "sweep.h"

static const char *const ABOUT =
    "Decides J3 on the lab's own iteration (panel a; panel b is linear_solvers' linear-solve rows),\n"
    "W1 (Wang 2015: Chebyshev accelerates the nonlinear iteration >= 10x) and P1 (Liu 2013:\n"
    "projective dynamics reaches a visually converged step much faster than exact Newton), and\n"
    "measures error against run time for every implicit method on the same steps.";

/* Scenes: configs/lab.ini (the lab's cloth and method) with these overrides.
 * Roles: "j3" = one trajectory per rho of RHOS (tables main and spectrum; one
 * cell per (scene, rho)); "w1" = one step of the W1 methods from a start
 * state (tables w1 and w1_trace); "p1" = one step of the P1 methods from
 * each of P1's start states (table p1; one cell per (scene, start state));
 * "error_time" = one step of every implicit method at 1, 2, 4, ... iterations
 * (table error_time). A "w1" or "error_time" scene is one cell: its methods
 * share the start state and the reference step computed from it. quick: the
 * scene runs in --quick too.
 *
 * The lab cloth at 21^2, and the same cloth (441 kg, k, 10 m) at 64^2, 128^2
 * quads (129^2 = 16 641 vertices, Wang's dress size) and 81^2 (6561 vertices,
 * Liu's cloth, P1), pinned at the lab's corners 0 and n-1; P1's stiff variant. */
typedef struct {
  cb_scene_decl scene;
  int quick; /* 1: in --quick too; 2: in --smoke too; 3: in --smoke only */
} scene_plan;
#define G64 "mesh.n=64", "material.vertex_mass=441/4096", "scene.pins=0 63"
#define G128 "mesh.n=129", "material.vertex_mass=441/16641", "scene.pins=0 128" /* 128^2 quads */
#define G81 "mesh.n=81", "material.vertex_mass=441/6561", "scene.pins=0 80"
static const scene_plan SCENES[] = {
    {{"lab", "lab.ini", {NULL}, "j3"}, 2},
    {{"lab", "lab.ini", {NULL}, "w1"}, 2},
    {{"grid64", "lab.ini", {G64, NULL}, "w1"}, 1},
    {{"grid128", "lab.ini", {G128, NULL}, "w1"}, 0},
    {{"grid81", "lab.ini", {G81, NULL}, "p1"}, 1},
    {{"grid81_stiff", "lab.ini", {G81, "material.stretch_k=1e6", NULL}, "p1"}, 1},
    {{"lab", "lab.ini", {NULL}, "p1"}, 3},
    {{"lab", "lab.ini", {NULL}, "error_time"}, 2},
    {{"grid64", "lab.ini", {G64, NULL}, "error_time"}, 0},
};
enum { NSCENES = sizeof SCENES / sizeof SCENES[0] };
enum { T_J3, T_SPECTRUM, T_W1, T_W1_TRACE, T_P1, T_P1_ERROR, T_ERROR_TIME }; /* tables, in the order opened */

/* J3's rho values and sampled frames */
static const char *const RHOS[] = {"0", "0.9", "0.95", "0.97", "0.99", "0.995", "0.999", "0.9995", "0.9999", "auto"};
enum { NRHO = sizeof RHOS / sizeof RHOS[0] };
static const int SAMPLE[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 1500, 2000};

enum { MAXSETS = 16 };

/* The plan: the scenes of each role this run (--quick or not) and its sizes. */
typedef struct {
 const cb_experiment *e;
  int quick, smoke;
  int rho0, nrho;    /* J3's rho values: RHOS[rho0 .. rho0 + nrho) */
  int frames;        /* J3 frames per trajectory */
  int state_frames;  /* frames of the lab's method before the W1 and error-time step */
  int p1_states;     /* P1 start states per scene: frames 5, 10, ... */
  int j3[NSCENES], nj3, w1[NSCENES], nw1, p1[NSCENES], np1, et[NSCENES], net; /* SCENES indices by role */
  long nv[NSCENES];  /* vertices of each scene (cost hints) */
  int mesh_n[NSCENES];
} plan;

static const cb_scene_decl *scene_of(int i) { return &SCENES[i].scene; }

/* ---- J3 panel a: the lab's iteration over 2000 frames, rho swept ------------ */

/* rho(I - D^-1 A(x)) with A = M/dt^2 + H(x) (exact Hessian: the linearisation
 * of the iteration) and D the lab's diagonal, by Lanczos on D^-1/2 A D^-1/2. */
static int linear_rho(cb_scene *s, const double *x, double dt, double *lmin, double *lmax, int *steps) {
  cb_sparse *A = &s->sys.A;
  cb_system_assemble(&s->sys, x, 1.0 / (dt * dt), CB_DEF_NONE, 0.0);
  int n = A->n;
  double *d = malloc((size_t)n * sizeof(double)), *work = malloc((size_t)n * sizeof(double));
  if (!d || !work) { free(d); free(work); return CB_ENOMEM; }
  for (int b = 0; b < s->model.nfree; b++) {
    double dd = s->mass[s->free_vertex[b]] / (dt * dt) + 4 * s->def.stretch_k; /* lab: m/dt^2 + 4k */
    for (int a = 0; a < 3; a++) d[3 * b + a] = 1.0 / sqrt(dd);
  }
  cb_scaled_op op = {A, d, work};
  cb_lanczos_params lp = cb_lanczos_params_default();
  lp.max_steps = 400;
  lp.tol = 1e-6;
  cb_eig_result r;
  int st = cb_lanczos(n, cb_scaled_op_apply, &op, &lp, &r);
  *lmin = r.lmin;
  *lmax = r.lmax;
  *steps = r.steps;
  free(d);
  free(work);
  return st == CB_NOT_CONVERGED ? CB_OK : st;
}

/* Cell i: scene j3[i / nrho], rho RHOS[rho0 + i % nrho]: one trajectory, its row and its spectrum rows. */
static int j3_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = scene_of(p->j3[i / p->nrho]);
  const char *rho = RHOS[p->rho0 + i % p->nrho];
  int frames = p->frames;
  char set[64];
  snprintf(set, sizeof set, "integrator.rho=%s", rho);
  const char *sets[] = {set, NULL};
  cb_config c;
  cb_scene *s = NULL;
  cb_integrator *it = NULL;
  cb_run run;
  memset(&run, 0, sizeof run);
  double *rel = malloc((size_t)frames * sizeof(double)), *ms = malloc((size_t)frames * sizeof(double));
  int st = rel && ms ? CB_OK : cb_fail_status(CB_ENOMEM, "out of memory");
  if (st == CB_OK) st = cb_scene_decl_build(p->e, d, sets, &c, &s);
  if (st == CB_OK) st = cb_integrator_from_config(&c, s, NULL, &it);
  if (st == CB_OK) st = cb_run_init(&run, s, it);
  int div_frame = -1, up = 0, n = 0, ns = 0;
  double rho_used = 0, rl[32], lmin_min = INFINITY, lmax_max = -INFINITY;
  const char *status = "ok";
  for (int f = 1; st == CB_OK && f <= frames; f++) {
    int sst = cb_run_step(&run);
    rho_used = run.last.rho;
    if (cb_status_is_fatal(sst) || sst == CB_DIVERGED) {
      div_frame = f;
      status = cb_status_name(sst);
      break;
    }
    rel[n] = run.last.rel_grad_hat;
    ms[n] = run.last.wall_ms;
    up += rel[n] > 1.0;
    n++;
    int sample = f == frames; /* the sampled frames, and the last */
    for (int k = 0; k < (int)(sizeof SAMPLE / sizeof SAMPLE[0]); k++) sample |= SAMPLE[k] == f;
    if (sample && ns < 32) {
      double lmin, lmax;
      int steps;
      if ((st = linear_rho(s, run.x, c.dt, &lmin, &lmax, &steps))) break;
      double rho_lin = cb_jacobi_rho(lmin, lmax, 1.0);
      rl[ns++] = rho_lin;
      if (lmin < lmin_min) lmin_min = lmin;
      if (lmax > lmax_max) lmax_max = lmax;
      cb_csv_printf(out[T_SPECTRUM], "%s,%s,%d,%.17g,%.17g,%.17g,%d\n", d->label, rho, f, lmin, lmax, rho_lin, steps);
    }
  }
  if (st == CB_OK) {
    double med = n ? cb_median(rel, n) : NAN, mx = 0, p90 = NAN;
    for (int k = 0; k < n; k++) mx = fmax(mx, rel[k]);
    if (n) { /* 90th percentile */
      double *cp = malloc((size_t)n * sizeof(double));
      if (!cp) st = cb_fail_status(CB_ENOMEM, "out of memory");
      else {
        memcpy(cp, rel, (size_t)n * sizeof(double));
        for (int a = 1; a < n; a++) /* insertion sort is fine for <= 2000 */
          for (int b = a; b > 0 && cp[b] < cp[b - 1]; b--) { double t = cp[b]; cp[b] = cp[b - 1]; cp[b - 1] = t; }
        p90 = cp[(int)floor(0.9 * (n - 1))];
        free(cp);
      }
    }
    double rl_max = 0;
    for (int k = 0; k < ns; k++) rl_max = fmax(rl_max, rl[k]);
    double rl_med = ns ? cb_median(rl, ns) : NAN;
    /* not applicable, written empty: the divergence frame of a run that did not diverge (-1), the statistics
     * of the frames when none ran, those of the sampled spectra when none was sampled */
    double na = cb_csv_na();
    if (st == CB_OK)
      cb_csv_printf(out[T_J3], "lab_iteration,%s,%s,%s,%.17g,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.6f,%s\n",
                    d->label, it->type->name, rho, rho_used, frames, n, div_frame > 0, div_frame > 0 ? div_frame : na,
                    n ? med : na, n ? p90 : na, n ? mx : na, up, ns ? rl_med : na, ns ? rl_max : na, ns ? lmin_min : na,
                    ns ? lmax_max : na, n ? cb_median(ms, n) : na, status);
  }
  cb_run_free(&run);
  cb_integrator_free(it);
  cb_scene_free(s);
  free(rel);
  free(ms);
  return st;
}

/* ---- shared by W1, P1 and the error-time sweep: one step from a state ----- */

/* single steps compare methods on one F: no damping */
static const char *const STEP_SETS[] = {"integrator.damping=1", NULL};

typedef struct {
  cb_scene *s;
  cb_config c;
  double *x0, *v0;   /* the start state */
  double *xstar;     /* the converged step from it (reference) */
  double *x, *v;     /* scratch */
  int n3;
} state_t;

static void free_state(state_t *S) {
  cb_scene_free(S->s);
  free(S->x0); free(S->v0); free(S->xstar); free(S->x); free(S->v);
  memset(S, 0, sizeof *S);
}

/* The scene and a start state: `frames` frames of the lab's method (with
 * its damping), then the reference step from there. On error S is freed. */
static int make_state(const cb_experiment *e, const cb_scene_decl *d, int frames, state_t *S) {
  memset(S, 0, sizeof *S);
  cb_integrator *it = NULL;
  cb_run run;
  memset(&run, 0, sizeof run);
  int st = cb_scene_decl_build(e, d, NULL, &S->c, &S->s);
  if (st == CB_OK) st = cb_integrator_from_config(&S->c, S->s, NULL, &it);
  if (st == CB_OK) st = cb_run_init(&run, S->s, it);
  for (int f = 0; st == CB_OK && f < frames; f++) {
    int sst = cb_run_step(&run);
    if (cb_status_is_fatal(sst))
      st = cb_fail_status(sst, "scene %s: start state, frame %d: %s", d->label, f + 1, cb_error_message());
  }
  if (st == CB_OK) {
    S->n3 = 3 * S->s->mesh.nv;
    size_t b = (size_t)S->n3 * sizeof(double);
    S->x0 = malloc(b); S->v0 = malloc(b); S->xstar = malloc(b); S->x = malloc(b); S->v = malloc(b);
    if (!S->x0 || !S->v0 || !S->xstar || !S->x || !S->v) st = cb_fail_status(CB_ENOMEM, "out of memory");
    else {
      memcpy(S->x0, run.x, b);
      memcpy(S->v0, run.v, b);
    }
  }
  cb_run_free(&run);
  cb_integrator_free(it);
  if (st == CB_OK) {
    cb_reference_params rp = cb_reference_params_default();
    rp.dt = S->c.dt;
    cb_reference *ref = NULL;
    cb_reference_stats rs;
    st = cb_reference_alloc(S->s, &rp, &ref);
    if (st == CB_OK) {
      int rst = cb_reference_step(ref, S->x0, S->v0, S->xstar, &rs);
      if (rst > CB_NOT_CONVERGED || rst < 0)
        st = cb_fail_status(rst, "scene %s: reference step after %d frames: %s", d->label, frames, cb_status_name(rst));
    }
    cb_reference_free(ref);
  }
  if (st) free_state(S);
  return st;
}

typedef struct {
  double wall_ms, setup_ms, alloc_ms, error, rel_grad, rho;
  int iters, status;
  int fallback; /* the step hit a non-SPD factorisation and was rerun with the method's fallback */
  cb_timing wall; /* the step's time at every timed repeat (wall_ms: their median) */
} step_result;

/* The config of the method `sets` names (plus STEP_SETS) on scene d. */
static int step_config(const cb_experiment *e, const cb_scene_decl *d, const char *const *sets, cb_config *c) {
  const char *all[MAXSETS + 4];
  int n = 0;
  for (int i = 0; sets[i] && n < MAXSETS; i++) all[n++] = sets[i];
  all[n++] = STEP_SETS[0];
  all[n] = NULL;
  return cb_scene_decl_config(e, d, all, c);
}

/* One run: a fresh integrator from c, one step from S's start state; r gets its results, *wall its
 * time. hook may observe it. */
static int run_once(state_t *S, const cb_config *c, cb_newton_hook hook, void *ctx, step_result *r, double *wall) {
  cb_integrator_params ip;
  cb_integrator_params_from_config(c, &ip);
  ip.hook = hook;
  ip.hook_ctx = ctx;
  cb_integrator *it = NULL;
  double t0 = cb_now_ms();
  int st = cb_integrator_from_config(c, S->s, &ip, &it);
  if (st) return st;
  r->alloc_ms = cb_now_ms() - t0; /* pd: its one factorisation */
  memcpy(S->x, S->x0, (size_t)S->n3 * sizeof(double));
  memcpy(S->v, S->v0, (size_t)S->n3 * sizeof(double));
  cb_step_stats ss;
  r->status = cb_integrator_step(it, S->x, S->v, &ss);
  /* the fixed-iteration methods' factor_ms is the auto rho's estimate, once per run, not a step's cost
     (pd factorises in alloc, alloc_ms); Newton's is its factorisations, which are */
  int once = strcmp(it->type->name, "newton") != 0;
  *wall = ss.wall_ms - (once ? ss.factor_ms : 0.0);
  r->setup_ms = ss.factor_ms;
  r->rel_grad = ss.rel_grad_hat;
  r->iters = ss.newton_iters;
  r->rho = ss.rho;
  r->error = cb_step_error(S->s, S->x, S->xstar, S->x0);
  cb_integrator_free(it);
  return CB_OK;
}

/* run_once, and when the step ends at a non-SPD factorisation and fb is given, the same step again with fb
 * (the method's fallback, e.g. Newton's exact Hessian falling back to `drop` for that step): *wall is both
 * runs' time, r the fallback's results with r->fallback = 1. */
static int run_fallback(state_t *S, const cb_config *c, const cb_config *fb, cb_newton_hook hook, void *ctx, step_result *r,
                        double *wall) {
  int st = run_once(S, c, hook, ctx, r, wall);
  r->fallback = 0;
  if (st || !fb || r->status != CB_NOT_SPD) return st;
  double w2;
  st = run_once(S, fb, hook, ctx, r, &w2);
  r->fallback = 1;
  *wall += w2;
  return st;
}

/* One step of the method `sets` names from S's start state, for the error-time figure: repeated
 * (the median wall time kept) while the repeats add up to less than 30 ms, at most 5. With a hook
 * (an observed step is for its trace, not its time): once. */
static int one_step(const cb_experiment *e, const cb_scene_decl *d, state_t *S, const char *const *sets, cb_newton_hook hook,
                    void *ctx, step_result *r) {
  cb_config c;
  int st = step_config(e, d, sets, &c);
  if (st) return st;
  double walls[5], w;
  int reps = 0;
  memset(r, 0, sizeof *r);
  do {
    if ((st = run_once(S, &c, hook, ctx, r, &w))) return st;
    walls[reps++] = w;
    cb_timing_add(&r->wall, w);
    if (hook) break;
  } while (reps < 5 && cb_median(walls, reps) * reps < 30.0);
  r->wall_ms = cb_median(walls, reps);
  return CB_OK;
}

/* The steps of the methods sets[0..n) from S's start state, compared by a claim: timed in
 * interleaved rounds (every method once per round; stats.h: 3 rounds with --quick, 2-5 in a full
 * run by their cost; a step under 25 ms timed right after an untimed one of its own). r[i] gets
 * method i's results (every repeat computes the same step) and its repeats. */
static int time_group(const cb_experiment *e, const cb_scene_decl *d, state_t *S, const char *const *const *sets,
                      const char *const *const *fallback, int n, step_result *r) {
  enum { MAXG = 16 };
  static cb_config c[MAXG], cf[MAXG];
  if (n > MAXG) return cb_fail("nonlinear: more than %d steps in one group", MAXG);
  for (int i = 0; i < n; i++) {
    int st = step_config(e, d, sets[i], &c[i]);
    if (st == CB_OK && fallback && fallback[i]) st = step_config(e, d, fallback[i], &cf[i]);
    if (st) return st;
    memset(&r[i], 0, sizeof r[i]);
  }
  double spent = 0;
  for (int round = 0; cb_timing_more(e->quick, round, spent); round++)
    for (int i = 0; i < n; i++) {
      step_result x;
      double w;
      const cb_config *fb = fallback && fallback[i] ? &cf[i] : NULL;
      int st = run_fallback(S, &c[i], fb, NULL, NULL, &x, &w);
      if (st == CB_OK && cb_timing_warm(w)) st = run_fallback(S, &c[i], fb, NULL, NULL, &x, &w); /* that was the warm-up */
      if (st) return st;
      if (round == 0) {
        cb_timing keep = r[i].wall;
        r[i] = x;
        r[i].wall = keep;
      }
      cb_timing_add(&r[i].wall, w);
      spent += w;
    }
  for (int i = 0; i < n; i++) r[i].wall_ms = cb_timing_median(&r[i].wall);
  return CB_OK;
}

/* "median,min,max,each,repeats" of a step's timing (nan fields and no repeats when it was not timed) */
static void put_timing(FILE *f, const step_result *r, int timed) {
  cb_timing none = {0}; /* not timed: every field empty */
  cb_timing_csv(f, timed ? &r->wall : &none, 1.0);
  fputc(',', f);
  if (timed) cb_timing_csv_each(f, &r->wall, 1.0);
  cb_csv_printf(f, ",%.17g", timed ? (double)r->wall.n : cb_csv_na());
}

/* ---- W1: iterations and time to 1e-2 and 1e-4 -------------------------------- */

typedef struct {
  int n, cap;
  double *rel;
} trace_t;

static void record(void *ctx, int event, const cb_newton_event *ev) {
  trace_t *t = ctx;
  if (event == CB_NEWTON_GRADIENT && ev->iter < t->cap) {
    t->rel[ev->iter] = ev->rel_grad;
    if (ev->iter + 1 > t->n) t->n = ev->iter + 1;
  }
}

typedef struct {
  const char *label, *pair;
  const char *sets[4];
  int auto_rho; /* sets hold integrator.rho=auto: the estimate of the first run is given as a number to the rest */
} w1_method;
static const w1_method W1M[] = {
    {"jacobi-nl", "jacobi", {"integrator.method=jacobi-nl", NULL}, 0},
    {"chebyshev-nl auto", "jacobi", {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL}, 1},
    {"chebyshev-nl 0.995", "jacobi", {"integrator.method=chebyshev-nl", "integrator.rho=0.995", NULL}, 0},
    {"pd", "pd", {"integrator.method=pd", NULL}, 0},
    {"pd-chebyshev auto", "pd", {"integrator.method=pd-chebyshev", "integrator.rho=auto", NULL}, 1},
};
enum { NW1M = sizeof W1M / sizeof W1M[0] };
enum { W1_CAP0 = 500 }; /* the first traced run's iterations */

/* The largest iteration cap of W1 method m on an n^2 grid: a traced run that ends above the tolerance is
 * rerun with a larger cap (w1_cell) up to this one. pd at 128^2 (a 50k-DOF back-solve an iteration, ~10^4
 * iterations to 1e-4) is held to 2000 to keep the full run near 3 minutes, and so is pd in --quick
 * (which leaves 64^2's pd pair undecided there: its plain run needs 3000-4000 iterations and was most of
 * the quick run's time); a pair cut off there is undecided (status cut_off), never a failure. */
static int w1_capmax(int quick, int m, int n) {
  if (W1M[m].pair[0] == 'p') return n >= 128 || quick ? 2000 : 10000; /* --quick: 64^2's plain pd (~3000-4000) cut off */
  return quick ? 20000 : 100000;
}

/* the cap of the next traced run after one of `cap` iterations ended at t: the iterations the rate over its
 * second half needs to reach tol, with a quarter more, at least twice the cap, at most capmax */
static int w1_next_cap(const trace_t *t, int cap, int capmax, double tol) {
  int a = t->n / 2, b = t->n - 1;
  double need = 2.0 * cap;
  if (b > a && t->rel[a] > 0 && t->rel[b] > 0 && t->rel[b] < t->rel[a]) {
    double rate = pow(t->rel[b] / t->rel[a], 1.0 / (b - a));
    need = cap + log(tol / t->rel[b]) / log(rate);
  }
  double next = fmax(2.0 * cap, 1.25 * need);
  return next >= capmax ? capmax : (int)next;
}

/* W1M[m]'s sets with rho (if not NULL) for integrator.rho=auto and "integrator.iters=K" into out */
static void w1_sets(int m, const char *rho, int K, char *buf, size_t nbuf, const char **out) {
  int n = 0;
  for (int k = 0; W1M[m].sets[k]; k++) out[n++] = rho && !strcmp(W1M[m].sets[k], "integrator.rho=auto") ? rho : W1M[m].sets[k];
  snprintf(buf, nbuf, "integrator.iters=%d", K);
  out[n++] = buf;
  out[n] = NULL;
}

/* Cell i: scene w1[i]: its start state, then every W1 method from it (a traced run for the iterations to
 * each tolerance, rerun with a larger cap until the tighter one is reached or the cap is w1_capmax), then
 * the steps of exactly that many iterations of every method, timed together (interleaved: the plain and the
 * accelerated iteration of a pair are compared). An auto rho is estimated in the first traced run (its time
 * is setup_ms); every later run of the method is given that estimate as a number, the same iteration. */
static int w1_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = scene_of(p->w1[i]);
  static const double TOLS[] = {1e-2, 1e-4};
  state_t S;
  int st = make_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  int n = S.s->mesh.grid_n, hit[NW1M][2], kmax[NW1M], job[NW1M][2], njobs = 0;
  double final_rel[NW1M], setup_ms[NW1M];
  step_result r[NW1M], rt[2 * NW1M];
  static char iters[2 * NW1M + NW1M][64], rhos[NW1M][64];
  static const char *sets[2 * NW1M + NW1M][6], *const *jobs[2 * NW1M];
  for (int m = 0; st == CB_OK && m < NW1M; m++) {
    int capmax = w1_capmax(p->quick, m, n);
    trace_t t = {0, 0, NULL};
    const char *rho = NULL;
    setup_ms[m] = cb_csv_na();
    for (kmax[m] = W1_CAP0 < capmax ? W1_CAP0 : capmax;; kmax[m] = w1_next_cap(&t, kmax[m], capmax, TOLS[1])) {
      free(t.rel);
      t = (trace_t){0, kmax[m] + 1, calloc((size_t)kmax[m] + 1, sizeof(double))};
      if (!t.rel) { st = cb_fail_status(CB_ENOMEM, "out of memory"); break; }
      w1_sets(m, rho, kmax[m], iters[m], sizeof iters[m], sets[m]);
      if ((st = one_step(p->e, d, &S, sets[m], record, &t, &r[m]))) break;
      if (W1M[m].auto_rho && !rho) { /* the estimate, from now on a number */
        setup_ms[m] = r[m].setup_ms;
        snprintf(rhos[m], sizeof rhos[m], "integrator.rho=%.17g", r[m].rho);
        rho = rhos[m];
      }
      int reached = 0;
      for (int k = 0; k < t.n && !reached; k++) reached = t.rel[k] <= TOLS[1];
      if (reached || kmax[m] >= capmax) break;
    }
    for (int k = 0; st == CB_OK && k < t.n; k++) /* every iteration up to 100, then ~50 per decade */
      if (k <= 100 || floor(50 * log10(k)) != floor(50 * log10(k - 1)) || k == t.n - 1)
        cb_csv_printf(out[T_W1_TRACE], "%s,%d,%s,%d,%.17g\n", d->label, n, W1M[m].label, k, t.rel[k]);
    final_rel[m] = t.n ? t.rel[t.n - 1] : cb_csv_na(); /* no iteration traced */
    for (int q = 0; st == CB_OK && q < 2; q++) {
      hit[m][q] = -1;
      for (int k = 0; k < t.n && hit[m][q] < 0; k++)
        if (t.rel[k] <= TOLS[q]) hit[m][q] = k;
      job[m][q] = -1;
      if (hit[m][q] > 0) { /* the time of a step of exactly that many iterations */
        int j = njobs++, slot = NW1M + j;
        w1_sets(m, rho, hit[m][q], iters[slot], sizeof iters[slot], sets[slot]);
        jobs[j] = sets[slot];
        job[m][q] = j;
      }
    }
    free(t.rel);
  }
  if (st == CB_OK) st = time_group(p->e, d, &S, jobs, NULL, njobs, rt);
  for (int m = 0; st == CB_OK && m < NW1M; m++)
    for (int q = 0; q < 2; q++) {
      int j = job[m][q];
      /* a tolerance never reached (hit < 0, status cut_off: not reached at the largest cap; hit = 0: reached
       * before any iteration) has no iteration count or time; a method without Chebyshev acceleration has no
       * rho, and one with a given rho no estimate (setup_ms) */
      double na = cb_csv_na(), rho = strstr(W1M[m].label, "chebyshev") ? r[m].rho : na;
      cb_csv_printf(out[T_W1], "%s,%d,%s,%s,%.17g,%d,%g,%.17g,", d->label, n, W1M[m].label, W1M[m].pair, rho, kmax[m],
                    TOLS[q], hit[m][q] >= 0 ? (double)hit[m][q] : na);
      put_timing(out[T_W1], j >= 0 ? &rt[j] : NULL, j >= 0);
      cb_csv_printf(out[T_W1], ",%.6f,%.6f,%.17g,%s\n", setup_ms[m], r[m].alloc_ms, final_rel[m],
                    hit[m][q] < 0 ? "cut_off" : cb_status_name(r[m].status));
    }
  free_state(&S);
  return st;
}

/* ---- P1: pd (10 iterations) against the fastest Newton and Baraff-Witkin ------ */

/* The methods, timed together at every start state. newton_exact is the fastest converging Newton the
 * harness has on these steps (exact Hessian, line search: 4-5 iterations a frame); a step whose exact
 * Hessian does not factorise (not SPD) is rerun with its fallback, drop, and the row counts it (its time is
 * both runs'). newton_drop is the definiteness fix the Newton default uses (linear convergence: 19-42
 * iterations), kept to show the difference; baraff_witkin is Newton's single iteration. */
typedef struct {
  const char *label;
  const char *sets[6], *fallback[6];
} p1_method;
#define NEWTON_EXACT "integrator.method=newton", "integrator.definiteness=none", "integrator.line_search=1"
#define NEWTON_DROP_LS "integrator.method=newton", "integrator.definiteness=drop", "integrator.line_search=1"
static const p1_method P1M[] = {
    {"pd10", {"integrator.method=pd", "integrator.iters=10", NULL}, {NULL}},
    {"newton_exact", {NEWTON_EXACT, "integrator.max_iters=50", "integrator.tol=1e-8", NULL},
     {NEWTON_DROP_LS, "integrator.max_iters=50", "integrator.tol=1e-8", NULL}},
    {"newton_drop", {"integrator.method=newton", "integrator.max_iters=50", "integrator.tol=1e-8", NULL}, {NULL}},
    {"baraff_witkin", {"integrator.method=newton", "integrator.max_iters=1", NULL}, {NULL}},
};
enum { NP1M = sizeof P1M / sizeof P1M[0] };

/* Time to equal step error: the families traced iteration by iteration (step error against the reference),
 * then a step of exactly the iterations that reach each tolerance, timed with the methods above. */
typedef struct {
  const char *label, *iters_key; /* the key that sets the iteration count */
  const char *sets[6], *fallback[6];
  int cap, cap_q;
} p1_family;
static const p1_family P1F[] = {
    {"pd", "integrator.iters", {"integrator.method=pd", NULL}, {NULL}, 400, 200},
    {"newton_exact", "integrator.max_iters", {NEWTON_EXACT, "integrator.tol=1e-8", NULL},
     {NEWTON_DROP_LS, "integrator.tol=1e-8", NULL}, 50, 50},
};
enum { NP1F = sizeof P1F / sizeof P1F[0] };
static const double P1_TOLS[] = {1e-2, 1e-3};
enum { NP1T = sizeof P1_TOLS / sizeof P1_TOLS[0] };

typedef struct {
  const state_t *S;
  int n, cap;
  double *err;
} err_trace;

static void record_error(void *ctx, int event, const cb_newton_event *ev) {
  err_trace *t = ctx;
  if (event == CB_NEWTON_GRADIENT && ev->iter < t->cap) {
    t->err[ev->iter] = cb_step_error(t->S->s, ev->x, t->S->xstar, t->S->x0);
    if (ev->iter + 1 > t->n) t->n = ev->iter + 1;
  }
}

/* sets, then "key=K", into out (NULL-terminated); buf holds the "key=K" */
static void with_iters(const char *const *sets, const char *key, int K, char *buf, size_t nbuf, const char **out) {
  int k = 0;
  for (; sets[k]; k++) out[k] = sets[k];
  snprintf(buf, nbuf, "%s=%d", key, K);
  out[k++] = buf;
  out[k] = NULL;
}

/* Cell i: scene p1[i / p1_states], the start state after 5 (i % p1_states + 1) frames; every P1 method from
 * it, and each family's step of the iterations that reach each tolerance. */
static int p1_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = scene_of(p->p1[i / p->p1_states]);
  int frame = 5 * (int)(i % p->p1_states + 1);
  state_t S;
  int st = make_state(p->e, d, frame, &S);
  if (st) return st;
  enum { NJ = NP1M + NP1F * NP1T };
  step_result r[NJ];
  const char *const *sets[NJ], *const *fb[NJ];
  static const char *fsets[NJ][8], *ffb[NJ][8];
  static char fbuf[NJ][2][64];
  int nj = 0, hit[NP1F][NP1T], job[NP1F][NP1T], cap[NP1F];
  for (int m = 0; m < NP1M; m++, nj++) {
    sets[nj] = P1M[m].sets;
    fb[nj] = P1M[m].fallback[0] ? P1M[m].fallback : NULL;
  }
  for (int f = 0; st == CB_OK && f < NP1F; f++) { /* trace each family's step error */
    cap[f] = p->smoke ? 20 : p->quick ? P1F[f].cap_q : P1F[f].cap;
    err_trace t = {&S, 0, cap[f] + 1, calloc((size_t)cap[f] + 1, sizeof(double))};
    if (!t.err) { st = cb_fail_status(CB_ENOMEM, "out of memory"); break; }
    const char *ts[8], *tf[8];
    char b1[64], b2[64];
    with_iters(P1F[f].sets, P1F[f].iters_key, cap[f], b1, sizeof b1, ts);
    if (P1F[f].fallback[0]) with_iters(P1F[f].fallback, P1F[f].iters_key, cap[f], b2, sizeof b2, tf);
    cb_config c, cf;
    st = step_config(p->e, d, ts, &c);
    if (st == CB_OK && P1F[f].fallback[0]) st = step_config(p->e, d, tf, &cf);
    step_result tr;
    double w;
    if (st == CB_OK) st = run_fallback(&S, &c, P1F[f].fallback[0] ? &cf : NULL, record_error, &t, &tr, &w);
    if (st == CB_OK && t.n > tr.iters + 1) t.n = tr.iters + 1; /* a fallback's trace replaced the first run's */
    for (int q = 0; st == CB_OK && q < NP1T; q++) {
      hit[f][q] = job[f][q] = -1;
      for (int k = 1; k < t.n && hit[f][q] < 0; k++)
        if (t.err[k] <= P1_TOLS[q]) hit[f][q] = k;
      if (hit[f][q] < 0) continue;
      with_iters(P1F[f].sets, P1F[f].iters_key, hit[f][q], fbuf[nj][0], sizeof fbuf[nj][0], fsets[nj]);
      sets[nj] = fsets[nj];
      fb[nj] = NULL;
      if (P1F[f].fallback[0]) {
        with_iters(P1F[f].fallback, P1F[f].iters_key, hit[f][q], fbuf[nj][1], sizeof fbuf[nj][1], ffb[nj]);
        fb[nj] = ffb[nj];
      }
      job[f][q] = nj++;
    }
    free(t.err);
  }
  if (st == CB_OK) st = time_group(p->e, d, &S, sets, fb, nj, r); /* interleaved: pd10, newton_exact, ..., pd10, ... */
  double k = S.s->def.stretch_k, na = cb_csv_na();
  int n = S.s->mesh.grid_n;
  for (int m = 0; st == CB_OK && m < NP1M; m++) {
    cb_csv_printf(out[T_P1], "%s,%d,%.17g,%s,%d,%d,", d->label, n, k, P1M[m].label, frame, r[m].iters);
    put_timing(out[T_P1], &r[m], 1);
    cb_csv_printf(out[T_P1], ",%.6f,%.17g,%.17g,%d,%s\n", r[m].alloc_ms, r[m].error, r[m].rel_grad, r[m].fallback,
                  cb_status_name(r[m].status));
  }
  for (int f = 0; st == CB_OK && f < NP1F; f++)
    for (int q = 0; q < NP1T; q++) {
      int j = job[f][q];
      /* a tolerance not reached within the cap: no iteration count, time or error, status cut_off */
      cb_csv_printf(out[T_P1_ERROR], "%s,%d,%.17g,%s,%d,%g,%d,%.17g,", d->label, n, k, P1F[f].label, frame, P1_TOLS[q], cap[f],
                    j >= 0 ? (double)hit[f][q] : na);
      put_timing(out[T_P1_ERROR], j >= 0 ? &r[j] : NULL, j >= 0);
      cb_csv_printf(out[T_P1_ERROR], ",%.17g,%.17g,%s\n", j >= 0 ? r[j].error : na, j >= 0 ? (double)r[j].fallback : na,
                    j >= 0 ? cb_status_name(r[j].status) : "cut_off");
    }
  free_state(&S);
  return st;
}

/* ---- error against run time: every implicit method on the same steps ---------- */

typedef struct {
  const char *label, *family;
  const char *sets[4];
  int kmax; /* iteration counts 1, 2, 4, ..., kmax; 0: the sets fix it */
} et_method;
static const et_method ETM[] = {
    {"newton K=1", "newton", {"integrator.method=newton", "integrator.max_iters=1", NULL}, 0},
    {"newton K=2", "newton", {"integrator.method=newton", "integrator.max_iters=2", NULL}, 0},
    {"newton K=3", "newton", {"integrator.method=newton", "integrator.max_iters=3", NULL}, 0},
    {"newton converged", "newton", {"integrator.method=newton", "integrator.max_iters=50", "integrator.tol=1e-8", NULL}, 0},
    {"jacobi-nl lab", "jacobi-nl", {"integrator.method=jacobi-nl", "integrator.diagonal=lab", NULL}, 4096},
    {"jacobi-nl exact", "jacobi-nl", {"integrator.method=jacobi-nl", "integrator.diagonal=exact", NULL}, 1024},
    {"chebyshev-nl 0.9", "chebyshev-nl", {"integrator.method=chebyshev-nl", "integrator.rho=0.9", NULL}, 4096},
    {"chebyshev-nl 0.99", "chebyshev-nl", {"integrator.method=chebyshev-nl", "integrator.rho=0.99", NULL}, 4096},
    {"chebyshev-nl 0.995", "chebyshev-nl", {"integrator.method=chebyshev-nl", "integrator.rho=0.995", NULL}, 4096},
    {"chebyshev-nl auto", "chebyshev-nl", {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL}, 4096},
    {"pd", "pd", {"integrator.method=pd", NULL}, 512},
    {"pd-chebyshev auto", "pd", {"integrator.method=pd-chebyshev", "integrator.rho=auto", NULL}, 512},
};
enum { NETM = sizeof ETM / sizeof ETM[0] };

/* the largest iteration count of error-time method m (0: fixed by its sets) */
static int et_kmax(const plan *p, int m) {
  int cap = p->smoke ? 4 : p->quick ? 256 : ETM[m].kmax;
  return ETM[m].kmax > cap ? cap : ETM[m].kmax;
}

/* Cell i: scene et[i]: its start state, then every method at every iteration count from it. */
static int et_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = scene_of(p->et[i]);
  state_t S;
  int st = make_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  for (int m = 0; st == CB_OK && m < NETM; m++) {
    int kmax = et_kmax(p, m);
    for (int K = kmax ? 1 : 0; st == CB_OK && K <= kmax; K = K ? 2 * K : 1) {
      char iters[64];
      snprintf(iters, sizeof iters, "integrator.iters=%d", K);
      const char *sets[6];
      int ns = 0;
      for (int k = 0; ETM[m].sets[k]; k++) sets[ns++] = ETM[m].sets[k];
      if (kmax) sets[ns++] = iters;
      sets[ns] = NULL;
      step_result r;
      if ((st = one_step(p->e, d, &S, sets, NULL, NULL, &r))) break;
      double rho = strstr(ETM[m].label, "chebyshev") ? r.rho : cb_csv_na(); /* no rho without Chebyshev */
      cb_csv_printf(out[T_ERROR_TIME], "%s,%d,%s,%s,%d,%.17g,%.6f,%.6f,%.17g,%.17g,%s\n", d->label, S.s->mesh.grid_n, ETM[m].label,
                    ETM[m].family, r.iters, rho, r.wall_ms, r.setup_ms, r.error, r.rel_grad, cb_status_name(r.status));
      if (!kmax) break;
    }
  }
  free_state(&S);
  return st;
}

/* ---- cost hints ----------------------------------------------------------------- */

/* Estimated ms of a cell, from a --quick run (one BLAS thread) and the full
 * run's phase times: a J3 frame 0.3 ms and a Lanczos sample 120 ms (x
 * vertices / 441); a W1 or error-time iteration 1e-4 ms per vertex (the
 * error-time sweep runs 1 + 2 + ... + kmax ~ 2 kmax of them, plus ~1 s of
 * Newton and repeats); a P1 cell 1 ms per vertex (two converged Newtons and the step-error traces). */
static double j3_cost(long i, void *ctx) {
  const plan *p = ctx;
  int ns = 1;
  for (int k = 0; k < (int)(sizeof SAMPLE / sizeof SAMPLE[0]); k++) ns += SAMPLE[k] < p->frames;
  return (0.3 * p->frames + 120.0 * ns) * p->nv[p->j3[i / p->nrho]] / 441.0;
}
static double w1_cost(long i, void *ctx) {
  const plan *p = ctx;
  double it = 0;
  for (int m = 0; m < NW1M; m++) it += 2 * W1_CAP0 + (m == 0 || m == 3 ? w1_capmax(p->quick, m, p->mesh_n[p->w1[i]]) / 4 : 0);
  return 1e-4 * it * p->nv[p->w1[i]] * (p->nv[p->w1[i]] / 441.0); /* measured: a W1 cell grows like vertices^2 */
}
static double p1_cost(long i, void *ctx) {
  const plan *p = ctx;
  return (0.75 + 0.5 * (double)(i % p->p1_states)) * p->nv[p->p1[i / p->p1_states]]; /* measured: later states cost more */
}
static double et_cost(long i, void *ctx) {
  const plan *p = ctx;
  double it = 0;
  for (int m = 0; m < NETM; m++) it += 2.0 * et_kmax(p, m);
  return 4.0 * (1000.0 + 1e-4 * it * p->nv[p->et[i]]); /* measured: ~4x the estimate */
}

/* the plan's vertex counts and grid sizes, from the scenes' configs (so a bad
 * declaration fails here, naming the scene, before any cell runs) */
static int scene_sizes(plan *p) {
  for (int i = 0; i < NSCENES; i++) {
    cb_config c;
    int st = cb_scene_decl_config(p->e, scene_of(i), NULL, &c);
    if (st) return st;
    p->nv[i] = cb_scene_decl_vertices(&c);
    p->mesh_n[i] = c.mesh_n;
  }
  return CB_OK;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "nonlinear", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* W1, P1 and the error-time figure are wall times: run alone */
  int q = e.quick, sm = e.smoke; /* smoke: the lab scene only, one rho, a few frames, one P1 state */
  plan p = {.e = &e, .quick = q, .smoke = sm, .rho0 = sm ? NRHO - 1 : 0, .nrho = sm ? 1 : NRHO,
            .frames = sm ? 5 : q ? 300 : 2000, .state_frames = sm ? 2 : q ? 10 : 20, .p1_states = sm ? 1 : q ? 2 : 3};
  for (int i = 0; i < NSCENES; i++) {
    const cb_scene_decl *d = scene_of(i);
    int level = SCENES[i].quick;
    if (sm ? level < 2 : level == 3 || (q && level < 1)) continue;
    if (cb_scene_decl_is(d, "j3")) p.j3[p.nj3++] = i;
    else if (cb_scene_decl_is(d, "w1")) p.w1[p.nw1++] = i;
    else if (cb_scene_decl_is(d, "p1")) p.p1[p.np1++] = i;
    else if (cb_scene_decl_is(d, "error_time")) p.et[p.net++] = i;
  }
  if ((b = scene_sizes(&p))) return cb_experiment_end(&e, b), 1;
  char j3_extra[256], p1_extra[256];
  snprintf(j3_extra, sizeof j3_extra,
           "# frames: %d (configs/lab.ini: chebyshev-nl, 32 iterations, damping 0.99; integrator.rho swept)\n", p.frames);
  snprintf(p1_extra, sizeof p1_extra,
           "# frames: %d (start states: frames 5, 10, ... of the lab's method; the step without damping)\n", p.p1_states);
  const char *state_extra = "# state: 20 frames of the lab's method (10 in --quick, 2 in --smoke); the step without damping\n";
  if (cb_experiment_table(&e, NULL, j3_extra,
                          "panel,scene,method,rho_given,rho,frames,frames_run,diverged,diverge_frame,median_rel_grad,"
                          "p90_rel_grad,max_rel_grad,frames_grad_up,rho_lin_median,rho_lin_max,lmin_min,lmax_max,"
                          "median_frame_ms,status") != T_J3 ||
      cb_experiment_table(&e, "spectrum", j3_extra, "scene,rho_given,frame,lmin,lmax,rho_lin,lanczos_steps") != T_SPECTRUM ||
      cb_experiment_table(&e, "w1", state_extra,
                          "scene,n,method,pair,rho,max_iters,tol,iters_to_tol,wall_to_tol_ms,wall_to_tol_min_ms,"
                          "wall_to_tol_max_ms,wall_to_tol_each_ms,wall_repeats,setup_ms,alloc_ms,"
                          "final_rel_grad,status") != T_W1 ||
      cb_experiment_table(&e, "w1_trace", NULL, "scene,n,method,iter,rel_grad") != T_W1_TRACE ||
      cb_experiment_table(&e, "p1", p1_extra,
                          "scene,n,k_n_per_m,method,frame,iters,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,"
                          "alloc_ms,step_error,rel_grad,fallback,status") != T_P1 ||
      cb_experiment_table(&e, "p1_error", p1_extra,
                          "scene,n,k_n_per_m,method,frame,tol,max_iters,iters_to_tol,wall_to_tol_ms,wall_to_tol_min_ms,"
                          "wall_to_tol_max_ms,wall_to_tol_each_ms,wall_repeats,step_error,fallback,status") != T_P1_ERROR ||
      cb_experiment_table(&e, "error_time", state_extra,
                          "scene,n,method,family,iters,rho,wall_ms,setup_ms,step_error,rel_grad,status") != T_ERROR_TIME)
    return cb_experiment_end(&e, CB_EIO), 2;
  const cb_sweep sweeps[] = {
      {"J3", (long)p.nj3 * p.nrho, j3_cell, j3_cost, &p},
      {"W1", p.nw1, w1_cell, w1_cost, &p},
      {"P1", (long)p.np1 * p.p1_states, p1_cell, p1_cost, &p},
      {"error-time", p.net, et_cell, et_cost, &p},
  };
  int st = cb_sweep_run(&e, sweeps, 4);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
