/* nonlinear: the GAMES103 lab's own iteration and the other nonlinear
 * iterations on the implicit-Euler objective F (claims J3 panel a, W1, P1),
 * and error against run time for every implicit method.
 *
 * Scenes come from configs/lab.ini (the lab's cloth and method) with the
 * overrides below. Outputs (results/):
 *   nonlinear.csv             J3, the lab's iteration: per rho, a trajectory of the lab scene
 *                             (chebyshev-nl, 32 iterations, d = m/dt^2 + 4k, damping 0.99):
 *                             whether and at which frame it diverged, the median relative
 *                             |grad F| after the 32 iterations, the linearised rho along the run
 *   nonlinear_spectrum.csv    rho(I - D^-1 A(x)) at sampled frames of each run (A = M/dt^2 + H(x),
 *                             exact Hessian, D the lab's diagonal; Lanczos)
 *   nonlinear_w1.csv          W1: iterations and wall time to relative |grad F| 1e-2 and 1e-4,
 *                             jacobi-nl vs chebyshev-nl and pd vs pd-chebyshev, at 21^2, 64^2, 128^2
 *   nonlinear_w1_trace.csv    the relative |grad F| per iteration of those steps (the figure)
 *   nonlinear_p1.csv          P1: per frame of an 81^2 cloth (and a stiff one), wall time and
 *                             step error against the converged step, for pd (10 iterations),
 *                             converged Newton (CHOLMOD) and Baraff-Witkin
 *   nonlinear_error_time.csv  one step of every implicit method at several iteration counts:
 *                             step error and relative |grad F| against wall time
 * The main loops are plain loops over tables (scenes x methods), written so that
 * they can move onto a shared sweep runner. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "reference.h"
#include "spectrum.h"
#include "stats.h"

static const char *const ABOUT =
    "Decides J3 on the lab's own iteration (panel a; panel b is linear_solvers' linear-solve rows),\n"
    "W1 (Wang 2015: Chebyshev accelerates the nonlinear iteration >= 10x) and P1 (Liu 2013:\n"
    "projective dynamics reaches a visually converged step much faster than exact Newton), and\n"
    "measures error against run time for every implicit method on the same steps.";

enum { MAXSETS = 16 };

/* configs/lab.ini plus the NULL-terminated lists a and b. */
static int config(const cb_experiment *e, const char *const *a, const char *const *b, cb_config *c) {
  const char *sets[2 * MAXSETS + 1];
  int n = 0;
  for (int i = 0; a && a[i] && n < MAXSETS; i++) sets[n++] = a[i];
  for (int i = 0; b && b[i] && n < 2 * MAXSETS; i++) sets[n++] = b[i];
  sets[n] = NULL;
  int st = cb_experiment_config(e, "lab.ini", sets, c);
  if (st == CB_OK) st = cb_config_validate(c);
  return st;
}

static int fail(const char *what) {
  fprintf(stderr, "nonlinear: %s: %s\n", what, cb_error_message());
  return 1;
}

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

static int run_j3(cb_experiment *e, int frames) {
  static const char *const RHOS[] = {"0", "0.9", "0.95", "0.97", "0.99", "0.995", "0.999", "0.9995", "0.9999", "auto"};
  const int NR = (int)(sizeof RHOS / sizeof RHOS[0]);
  static const int SAMPLE[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 1500, 2000};
  char path[2048];
  cb_outfile sp = {0};
  cb_experiment_side_path(e, "spectrum.csv", path, sizeof path);
  char extra[256];
  snprintf(extra, sizeof extra, "# frames: %d (configs/lab.ini: chebyshev-nl, 32 iterations, damping 0.99; integrator.rho swept)\n", frames);
  if (cb_experiment_csv(e, &e->csv, NULL, extra,
                        "panel,scene,method,rho_given,rho,frames,frames_run,diverged,diverge_frame,median_rel_grad,"
                        "p90_rel_grad,max_rel_grad,frames_grad_up,rho_lin_median,rho_lin_max,lmin_min,lmax_max,"
                        "median_frame_ms,status") ||
      cb_experiment_csv(e, &sp, path, extra, "scene,rho_given,frame,lmin,lmax,rho_lin,lanczos_steps"))
    return fail("csv");
  cb_progress_start(&e->progress, "nonlinear J3", NR);
  double *rel = malloc((size_t)frames * sizeof(double)), *ms = malloc((size_t)frames * sizeof(double));
  if (!rel || !ms) return fail("memory");
  for (int r = 0; r < NR; r++) {
    char set[64];
    snprintf(set, sizeof set, "integrator.rho=%s", RHOS[r]);
    const char *sets[] = {set, NULL};
    cb_config c;
    cb_scene *s = NULL;
    cb_integrator *it = NULL;
    cb_run run;
    if (config(e, sets, NULL, &c) || cb_scene_from_config(&c, &s) || cb_integrator_from_config(&c, s, NULL, &it) ||
        cb_run_init(&run, s, it))
      return fail("lab scene");
    int div_frame = -1, up = 0, n = 0, ns = 0;
    double rho_used = 0, rl[32], lmin_min = INFINITY, lmax_max = -INFINITY;
    const char *status = "ok";
    for (int f = 1; f <= frames; f++) {
      int st = cb_run_step(&run);
      rho_used = run.last.rho;
      if (cb_status_is_fatal(st) || st == CB_DIVERGED) {
        div_frame = f;
        status = cb_status_name(st);
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
          if (linear_rho(s, run.x, c.dt, &lmin, &lmax, &steps)) return fail("lanczos");
          double rho_lin = cb_jacobi_rho(lmin, lmax, 1.0);
          rl[ns++] = rho_lin;
          if (lmin < lmin_min) lmin_min = lmin;
          if (lmax > lmax_max) lmax_max = lmax;
          fprintf(sp.f, "lab,%s,%d,%.17g,%.17g,%.17g,%d\n", RHOS[r], f, lmin, lmax, rho_lin, steps);
      }
    }
    double med = n ? cb_median(rel, n) : NAN, mx = 0, p90 = NAN;
    for (int i = 0; i < n; i++) mx = fmax(mx, rel[i]);
    if (n) { /* 90th percentile */
      double *cp = malloc((size_t)n * sizeof(double));
      memcpy(cp, rel, (size_t)n * sizeof(double));
      for (int i = 1; i < n; i++) /* insertion sort is fine for <= 2000 */
        for (int j = i; j > 0 && cp[j] < cp[j - 1]; j--) { double t = cp[j]; cp[j] = cp[j - 1]; cp[j - 1] = t; }
      p90 = cp[(int)floor(0.9 * (n - 1))];
      free(cp);
    }
    double rl_max = 0;
    for (int i = 0; i < ns; i++) rl_max = fmax(rl_max, rl[i]);
    double rl_med = ns ? cb_median(rl, ns) : NAN;
    fprintf(e->csv.f, "lab_iteration,lab,%s,%s,%.17g,%d,%d,%d,%d,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.6f,%s\n",
            it->type->name, RHOS[r], rho_used, frames, n, div_frame > 0, div_frame, med, p90, mx, up, rl_med, rl_max,
            lmin_min, lmax_max, n ? cb_median(ms, n) : 0.0, status);
    cb_run_free(&run);
    cb_integrator_free(it);
    cb_scene_free(s);
    cb_progress_update(&e->progress, r + 1);
  }
  cb_progress_end(&e->progress);
  free(rel);
  free(ms);
  if (cb_outfile_commit(&sp)) return fail("spectrum csv");
  return 0;
}

/* ---- shared by W1, P1 and the error-time sweep: one step from a state ----- */

typedef struct {
  const char *label;
  const char *sets[MAXSETS];
} scene_def;

/* the lab cloth at 21^2, and the same cloth (441 kg, k, 10 m) at 64^2, 128^2
 * quads (129^2 = 16 641 vertices, Wang's dress size) and 81^2 (6561 vertices,
 * Liu's cloth, P1), pinned at the lab's corners 0 and n-1; P1's stiff variant */
static const scene_def LAB = {"lab", {NULL}};
static const scene_def G64 = {"grid64", {"mesh.n=64", "material.vertex_mass=441/4096", "scene.pins=0 63", NULL}};
static const scene_def G128 = {"grid128", {"mesh.n=129", "material.vertex_mass=441/16641", "scene.pins=0 128", NULL}}; /* 128^2 quads */
static const scene_def G81 = {"grid81", {"mesh.n=81", "material.vertex_mass=441/6561", "scene.pins=0 80", NULL}};
static const scene_def G81S = {"grid81_stiff",
                               {"mesh.n=81", "material.vertex_mass=441/6561", "scene.pins=0 80", "material.stretch_k=1e6", NULL}};

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

/* The scene and a start state: `frames` frames of the lab's method (with
 * its damping), then the reference step from there. */
static int make_state(cb_experiment *e, const scene_def *d, int frames, state_t *S) {
  memset(S, 0, sizeof *S);
  cb_integrator *it = NULL;
  cb_run run;
  if (config(e, d->sets, NULL, &S->c) || cb_scene_from_config(&S->c, &S->s) || cb_integrator_from_config(&S->c, S->s, NULL, &it) ||
      cb_run_init(&run, S->s, it))
    return fail(d->label);
  for (int f = 0; f < frames; f++)
    if (cb_status_is_fatal(cb_run_step(&run))) return fail("start state");
  S->n3 = 3 * S->s->mesh.nv;
  size_t b = (size_t)S->n3 * sizeof(double);
  S->x0 = malloc(b); S->v0 = malloc(b); S->xstar = malloc(b); S->x = malloc(b); S->v = malloc(b);
  if (!S->x0 || !S->v0 || !S->xstar || !S->x || !S->v) return fail("memory");
  memcpy(S->x0, run.x, b);
  memcpy(S->v0, run.v, b);
  cb_run_free(&run);
  cb_integrator_free(it);
  cb_reference_params rp = cb_reference_params_default();
  rp.dt = S->c.dt;
  cb_reference *ref = NULL;
  cb_reference_stats rs;
  if (cb_reference_alloc(S->s, &rp, &ref) || cb_reference_step(ref, S->x0, S->v0, S->xstar, &rs) > CB_NOT_CONVERGED)
    return fail("reference step");
  cb_reference_free(ref);
  return 0;
}

static void free_state(state_t *S) {
  cb_scene_free(S->s);
  free(S->x0); free(S->v0); free(S->xstar); free(S->x); free(S->v);
}

typedef struct {
  double wall_ms, setup_ms, alloc_ms, error, rel_grad, rho;
  int iters, status;
} step_result;

/* One step of the method `sets` names from S's start state; repeated (the
 * median wall time kept) while it is short. hook may observe it. */
static int one_step(cb_experiment *e, const scene_def *d, state_t *S, const char *const *sets, cb_newton_hook hook, void *ctx,
                    step_result *r) {
  cb_config c;
  const char *all[MAXSETS + 4];
  int n = 0;
  for (int i = 0; sets[i] && n < MAXSETS; i++) all[n++] = sets[i];
  all[n++] = STEP_SETS[0];
  all[n] = NULL;
  if (config(e, d->sets, all, &c)) return fail("method config");
  cb_integrator_params ip;
  cb_integrator_params_from_config(&c, &ip);
  ip.hook = hook;
  ip.hook_ctx = ctx;
  double walls[5];
  int reps = 0;
  memset(r, 0, sizeof *r);
  do {
    cb_integrator *it = NULL;
    double t0 = cb_now_ms();
    if (cb_integrator_from_config(&c, S->s, &ip, &it)) return fail("integrator");
    r->alloc_ms = cb_now_ms() - t0; /* pd: its one factorisation */
    memcpy(S->x, S->x0, (size_t)S->n3 * sizeof(double));
    memcpy(S->v, S->v0, (size_t)S->n3 * sizeof(double));
    cb_step_stats st;
    r->status = cb_integrator_step(it, S->x, S->v, &st);
    /* the fixed-iteration methods' factor_ms is the auto rho's estimate, once per run, not a step's cost
       (pd factorises in alloc, alloc_ms); Newton's is its factorisations, which are */
    int once = strcmp(it->type->name, "newton") != 0;
    walls[reps++] = st.wall_ms - (once ? st.factor_ms : 0.0);
    r->setup_ms = st.factor_ms;
    r->rel_grad = st.rel_grad_hat;
    r->iters = st.newton_iters;
    r->rho = st.rho;
    cb_integrator_free(it);
    if (hook) break; /* an observed step is for its trace, not its time */
  } while (reps < 5 && cb_median(walls, reps) * reps < 30.0);
  r->wall_ms = cb_median(walls, reps);
  r->error = cb_step_error(S->s, S->x, S->xstar, S->x0);
  return 0;
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

static int run_w1(cb_experiment *e, int quick) {
  const scene_def *scenes[] = {&LAB, &G64, &G128};
  int nsc = quick ? 2 : 3;
  typedef struct {
    const char *label, *pair;
    const char *sets[4];
    int kmax, kmax_q;
  } wm;
  static const wm M[] = {
      {"jacobi-nl", "jacobi", {"integrator.method=jacobi-nl", NULL}, 20000, 4000},
      {"chebyshev-nl auto", "jacobi", {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL}, 20000, 4000},
      {"chebyshev-nl 0.995", "jacobi", {"integrator.method=chebyshev-nl", "integrator.rho=0.995", NULL}, 20000, 4000},
      {"pd", "pd", {"integrator.method=pd", NULL}, 1000, 300},
      {"pd-chebyshev auto", "pd", {"integrator.method=pd-chebyshev", "integrator.rho=auto", NULL}, 1000, 300},
  };
  const int NM = (int)(sizeof M / sizeof M[0]);
  const double TOLS[] = {1e-2, 1e-4};
  char path[2048];
  cb_outfile o = {0}, tr = {0};
  cb_experiment_side_path(e, "w1.csv", path, sizeof path);
  if (cb_experiment_csv(e, &o, path, "# state: 20 frames of the lab's method (10 in --quick); the step without damping\n",
                        "scene,n,method,pair,rho,max_iters,tol,iters_to_tol,wall_ms_to_tol,setup_ms,alloc_ms,final_rel_grad,status"))
    return fail("csv");
  cb_experiment_side_path(e, "w1_trace.csv", path, sizeof path);
  if (cb_experiment_csv(e, &tr, path, NULL, "scene,n,method,iter,rel_grad")) return fail("csv");
  cb_progress_start(&e->progress, "nonlinear W1", nsc * NM);
  for (int sc = 0; sc < nsc; sc++) {
    state_t S;
    if (make_state(e, scenes[sc], quick ? 10 : 20, &S)) return 1;
    int n = S.s->mesh.grid_n;
    for (int m = 0; m < NM; m++) {
      int kmax = quick ? M[m].kmax_q : M[m].kmax;
      if (n >= 128 && M[m].pair[0] == 'p') kmax = quick ? 100 : 400; /* a 50k-DOF back-solve each */
      trace_t t = {0, kmax + 1, calloc((size_t)kmax + 1, sizeof(double))};
      char iters[64];
      snprintf(iters, sizeof iters, "integrator.iters=%d", kmax);
      const char *sets[6];
      int ns = 0;
      for (int i = 0; M[m].sets[i]; i++) sets[ns++] = M[m].sets[i];
      sets[ns++] = iters;
      sets[ns] = NULL;
      step_result r;
      if (!t.rel || one_step(e, scenes[sc], &S, sets, record, &t, &r)) return 1;
      for (int k = 0; k < t.n; k++) /* every iteration up to 100, then ~50 per decade */
        if (k <= 100 || floor(50 * log10(k)) != floor(50 * log10(k - 1)) || k == t.n - 1)
          fprintf(tr.f, "%s,%d,%s,%d,%.17g\n", scenes[sc]->label, n, M[m].label, k, t.rel[k]);
      for (int q = 0; q < 2; q++) {
        int hit = -1;
        for (int k = 0; k < t.n && hit < 0; k++)
          if (t.rel[k] <= TOLS[q]) hit = k;
        step_result rt = {0};
        rt.status = r.status;
        if (hit > 0) { /* the time of a step of exactly that many iterations */
          snprintf(iters, sizeof iters, "integrator.iters=%d", hit);
          if (one_step(e, scenes[sc], &S, sets, NULL, NULL, &rt)) return 1;
        }
        fprintf(o.f, "%s,%d,%s,%s,%.17g,%d,%g,%d,%.6f,%.6f,%.6f,%.17g,%s\n", scenes[sc]->label, n, M[m].label, M[m].pair, r.rho,
                kmax, TOLS[q], hit, hit > 0 ? rt.wall_ms : NAN, hit > 0 ? rt.setup_ms : NAN, r.alloc_ms, t.n ? t.rel[t.n - 1] : NAN,
                cb_status_name(r.status));
      }
      free(t.rel);
      cb_progress_update(&e->progress, sc * NM + m + 1);
    }
    free_state(&S);
  }
  cb_progress_end(&e->progress);
  if (cb_outfile_commit(&o) || cb_outfile_commit(&tr)) return fail("w1 csv");
  return 0;
}

/* ---- P1: pd (10 iterations) against converged Newton and Baraff-Witkin -------- */

static int run_p1(cb_experiment *e, int quick) {
  const scene_def *scenes[] = {&G81, &G81S};
  typedef struct {
    const char *label;
    const char *sets[4];
  } pm;
  static const pm M[] = {
      {"pd10", {"integrator.method=pd", "integrator.iters=10", NULL}},
      {"newton", {"integrator.method=newton", "integrator.max_iters=50", "integrator.tol=1e-8", NULL}},
      {"baraff_witkin", {"integrator.method=newton", "integrator.max_iters=1", NULL}},
  };
  const int NM = (int)(sizeof M / sizeof M[0]);
  int frames = quick ? 2 : 6;
  char path[2048], extra[256];
  cb_outfile o = {0};
  snprintf(extra, sizeof extra, "# frames: %d (start states: frames 5, 10, ... of the lab's method; the step without damping)\n", frames);
  cb_experiment_side_path(e, "p1.csv", path, sizeof path);
  if (cb_experiment_csv(e, &o, path, extra, "scene,n,k,method,frame,iters,wall_ms,alloc_ms,step_error,rel_grad,status"))
    return fail("csv");
  cb_progress_start(&e->progress, "nonlinear P1", 2 * frames);
  for (int sc = 0; sc < 2; sc++)
    for (int f = 0; f < frames; f++) {
      state_t S;
      if (make_state(e, scenes[sc], 5 * (f + 1), &S)) return 1;
      for (int m = 0; m < NM; m++) {
        step_result r;
        if (one_step(e, scenes[sc], &S, M[m].sets, NULL, NULL, &r)) return 1;
        fprintf(o.f, "%s,%d,%.17g,%s,%d,%d,%.6f,%.6f,%.17g,%.17g,%s\n", scenes[sc]->label, S.s->mesh.grid_n, S.s->def.stretch_k,
                M[m].label, 5 * (f + 1), r.iters, r.wall_ms, r.alloc_ms, r.error, r.rel_grad, cb_status_name(r.status));
      }
      free_state(&S);
      cb_progress_update(&e->progress, sc * frames + f + 1);
    }
  cb_progress_end(&e->progress);
  return cb_outfile_commit(&o) ? fail("p1 csv") : 0;
}

/* ---- error against run time: every implicit method on the same steps ---------- */

static int run_error_time(cb_experiment *e, int quick) {
  const scene_def *scenes[] = {&LAB, &G64};
  typedef struct {
    const char *label, *family;
    const char *sets[4];
    int kmax; /* iteration counts 1, 2, 4, ..., kmax; 0: the sets fix it */
  } em;
  static const em M[] = {
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
  const int NM = (int)(sizeof M / sizeof M[0]);
  int nsc = quick ? 1 : 2;
  char path[2048];
  cb_outfile o = {0};
  cb_experiment_side_path(e, "error_time.csv", path, sizeof path);
  if (cb_experiment_csv(e, &o, path, "# state: 20 frames of the lab's method (10 in --quick); the step without damping\n",
                        "scene,n,method,family,iters,rho,wall_ms,setup_ms,step_error,rel_grad,status"))
    return fail("csv");
  cb_progress_start(&e->progress, "nonlinear error-time", nsc * NM);
  for (int sc = 0; sc < nsc; sc++) {
    state_t S;
    if (make_state(e, scenes[sc], quick ? 10 : 20, &S)) return 1;
    for (int m = 0; m < NM; m++) {
      int kmax = M[m].kmax;
      if (quick && kmax > 256) kmax = 256;
      for (int K = kmax ? 1 : 0; K <= kmax; K = K ? 2 * K : 1) {
        char iters[64];
        snprintf(iters, sizeof iters, "integrator.iters=%d", K);
        const char *sets[6];
        int ns = 0;
        for (int i = 0; M[m].sets[i]; i++) sets[ns++] = M[m].sets[i];
        if (kmax) sets[ns++] = iters;
        sets[ns] = NULL;
        step_result r;
        if (one_step(e, scenes[sc], &S, sets, NULL, NULL, &r)) return 1;
        fprintf(o.f, "%s,%d,%s,%s,%d,%.17g,%.6f,%.6f,%.17g,%.17g,%s\n", scenes[sc]->label, S.s->mesh.grid_n, M[m].label,
                M[m].family, r.iters, r.rho, r.wall_ms, r.setup_ms, r.error, r.rel_grad,
                cb_status_name(r.status));
        if (!kmax) break;
      }
      cb_progress_update(&e->progress, sc * NM + m + 1);
    }
    free_state(&S);
  }
  cb_progress_end(&e->progress);
  return cb_outfile_commit(&o) ? fail("error-time csv") : 0;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "nonlinear", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* W1, P1 and the error-time figure are wall times: run alone */
  cb_runtime_init();
  int frames = e.quick ? 300 : 2000;
  if (run_j3(&e, frames) || run_w1(&e, e.quick) || run_p1(&e, e.quick) || run_error_time(&e, e.quick)) {
    cb_outfile_abort(&e.csv);
    return 1;
  }
  if (cb_outfile_commit(&e.csv)) return fail("csv");
  return 0;
}
