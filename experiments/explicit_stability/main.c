/* explicit_stability: where explicit integration breaks, and what implicit
 * costs (claims E1, E2, I1). The physics (classifier, equilibrium, prediction,
 * bisection) is in lib/instruments/stability.c; this file holds the sweep plan and the CSV
 * rows. README.md, section "explicit_stability", explains every choice. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/definiteness.h>
#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>
#include <clothbench/status.h>
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "reference.h"
#include "scene_decl.h"
#include "sweep.h"
#include "stability.h"
#include "stats.h"

/* Scenes. Roles: "map" = the k x dt map (explicit sweep, bisection, Newton
 * cells, boundary row, E2 timings at some k; one cell per swept k);
 * "resolution" = E2 only (no grid: the boundary bracketed from the prediction,
 * timings at the k_res of the plan; one cell per k_res). The cloths are the
 * GAMES103 lab cloth (10 m, 21^2, 1 kg a vertex = 441 kg) refined at the same
 * total mass, hanging vertically (plane xy). E2 families: "stretch" (stretch
 * springs only: omega_max^2 ~ k/m ~ n) and "bending" (the same cloth with the
 * quadratic bending model at k_b = BEND_K N m, whose Hessian ~ k_b/h^2 makes
 * omega_max^2 ~ k_b/(h^2 m) ~ n^2 dominate the stretch springs' k/m). Plan
 * data: [0] = full run, [1] = --quick. Newton cells (I1) run the explicit
 * cells' steps (the same simulated time) at the dt of the sweep with
 * j % nt_dt_stride == (ndt - 1) % nt_dt_stride and dt >= nt_dt_min, at every
 * nt_k_stride-th k counted from the stiffest (0 = none). A cloth cell at
 * dt >= 0.01 runs 200 steps of converged Newton (0.5-8 s on 21^2, up to 50
 * iterations a step at k = 1e7; ~4.5x that on 41^2), so the cloths get few:
 * 21^2 at 3 dt x 3 k (1 dt with --quick), 41^2 none. */
typedef struct {
  cb_scene_decl scene;
  const char *family;                  /* E2 family of its timing rows */
  int k_stride[2];                     /* sweep every stride-th k */
  int nt_dt_stride[2], nt_k_stride[2]; /* Newton cells: every stride-th dt and k ... */
  double nt_dt_min[2];                 /* ... with dt >= this */
  int e2_k_stride[2];                  /* E2 timings every stride-th k (0 = none) */
  int nres[2];                         /* "resolution": timed at the first nres k_res */
} scene_plan;

#define CLOTH(n, m) "mesh.n=" #n, "material.vertex_mass=441/" #m, "mesh.plane=xy"
#define BEND_K "1e4"
#define BENT(n, m) CLOTH(n, m), "material.bend=quadratic", "material.bend_k=" BEND_K
static const scene_plan scenes[] = {
    {{"spring", "single_spring.ini", {NULL}, "map"}, "stretch", {1, 1}, {1, 1}, {1, 1}, {0, 0}, {0, 0}, {0, 0}},
    {{"chain20", "chain20.ini", {NULL}, "map"}, "stretch", {1, 1}, {1, 1}, {1, 1}, {0, 0}, {0, 0}, {0, 0}},
    {{"cloth21", "hanging.ini", {CLOTH(21, 441), NULL}, "map"},
     "stretch",
     {1, 1},
     {3, 1},
     {6, 3},
     {9e-3, 0.09},
     {2, 3},
     {0, 0}},
    {{"cloth41", "hanging.ini", {CLOTH(41, 1681), NULL}, "map"},
     "stretch",
     {1, 3},
     {1, 1},
     {0, 0},
     {0.09, 1},
     {4, 0},
     {0, 0}},
    {{"cloth81", "hanging.ini", {CLOTH(81, 6561), NULL}, "resolution"},
     "stretch",
     {1, 1},
     {1, 1},
     {0, 0},
     {0, 0},
     {0, 0},
     {2, 1}},
    {{"bend11", "hanging.ini", {BENT(11, 121), NULL}, "resolution"},
     "bending",
     {1, 1},
     {1, 1},
     {0, 0},
     {0, 0},
     {0, 0},
     {1, 1}},
    {{"bend21", "hanging.ini", {BENT(21, 441), NULL}, "resolution"},
     "bending",
     {1, 1},
     {1, 1},
     {0, 0},
     {0, 0},
     {0, 0},
     {1, 1}},
    {{"bend41", "hanging.ini", {BENT(41, 1681), NULL}, "resolution"},
     "bending",
     {1, 1},
     {1, 1},
     {0, 0},
     {0, 0},
     {0, 0},
     {1, 1}},
};
enum { NSCENES = sizeof scenes / sizeof scenes[0], MAXG = 64 };
enum { T_MAIN, T_BOUNDARY, T_TIMING }; /* tables, in the order opened */

/* grid vertices per side (the mesh.n override), 0 for a chain */
static int grid_n(const cb_scene_decl *d) {
  const char *v = cb_scene_decl_override(d, "mesh.n");
  return v ? atoi(v) : 0;
}

typedef struct {
  int quick, smoke, nk, ndt, bisect_iters;
  double k[MAXG], dt[MAXG];
  cb_stability_params ex, nt; /* explicit and Newton cells */
  double k_res[2];            /* E2 resolution study (21^2, 41^2, 81^2) */
  double e2_time;             /* E2: simulated time of a timed run, s (1; shorter with --smoke) */
} plan;

static FILE *fmain, *fbound, *ftime;
static const char *cur_scene;
static double cur_k;
static int cur_nv;

static void make_plan(plan *p, int quick, int smoke, double sim_time) {
  memset(p, 0, sizeof *p);
  p->quick = quick;
  p->smoke = smoke;
  p->nk = smoke ? 1 : quick ? 7 : 13;   /* k = 10^1 .. 10^7 N/m, log-spaced (--smoke: 10^4) */
  p->ndt = smoke ? 5 : quick ? 13 : 25; /* dt = 10^-5 .. 10^-1 s, log-spaced */
  for (int i = 0; i < p->nk; i++) p->k[i] = p->nk > 1 ? pow(10.0, 1.0 + 6.0 * i / (p->nk - 1)) : 1e4;
  for (int j = 0; j < p->ndt; j++) p->dt[j] = pow(10.0, -5.0 + 4.0 * j / (p->ndt - 1));
  p->bisect_iters = smoke ? 3 : quick ? 6 : 10;
  p->ex = cb_stability_params_default();
  p->ex.sim_time = sim_time > 0 ? sim_time : smoke ? 0.05 : quick ? 1.0 : 2.0;
  p->ex.min_steps = smoke ? 5 : 200;                   /* a large dt still gets 200 steps to show growth */
  p->ex.max_steps = smoke ? 100 : quick ? 1000 : 2000; /* a cell still below R_u after this many steps is stable */
  p->ex.energy_every = 4;
  p->nt = p->ex;         /* Newton (I1): the explicit cells' steps, so the same simulated time ... */
  p->nt.mark_time = 0.1; /* ... and the energy lost over the first 0.1 s, common to every dt that reaches it */
  p->nt.energy_every = 1;
  p->k_res[0] = 1e4;
  p->k_res[1] = 1e6;
  p->e2_time = smoke ? 2.0 / 30 : 1.0;
}

/* The scene at stiffness k; Newton stops at a 0.1 nm step (round-off). */
static int scene_config(const cb_experiment *e, const cb_scene_decl *d, double k, cb_config *c) {
  char sk[64];
  snprintf(sk, sizeof sk, "material.stretch_k=%.17g", k);
  /* converged Newton (I1, E2): the exact Hessian with a shift where A is indefinite, and a line search, the
   * fastest converging variant (drop, the lecture's, converges linearly on these compressed equilibria) */
  const char *more[] = {sk, "integrator.tol_dx=1e-10", "integrator.definiteness=shift", "integrator.line_search=1",
                        NULL};
  return cb_scene_decl_config(e, d, more, c);
}

/* window: the requested energy-loss window (mark_time), 0 if none (written empty);
 * meas: the bisected dt_crit, NaN if none was measured (written empty); the
 * Newton columns of an explicit cell are empty (no Newton iteration there). */
static void cell_row(const char *kind, const char *cas, const char *method, const cb_cell_result *r, double pred,
                     double meas, double kinetic0, double window, const char *note) {
  double loss = r->t_mark > 0 ? (r->energy0 - r->energy_mark) / r->t_mark : cb_csv_na(); /* W: J per simulated s */
  int nt = !strcmp(method, "newton");
  double na = cb_csv_na();
  cb_csv_printf(fmain,
                "%s,%s,%s,%d,%.17g,%.17g,%s,%s,%.17g,%.17g,%ld,%.17g,%.6f,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%."
                "17g,"
                "%.17g,%.17g,%.17g,%.17g,%s,%s\n",
                kind, cas, cur_scene, cur_nv, cur_k, r->dt, method, cb_cell_class_name(r->cls), r->max_energy_ratio,
                r->final_energy_ratio, r->steps, r->t_end, r->wall_ms, pred, cb_csv_na_if_nan(meas), r->energy0,
                r->energy_end, r->energy_scale, kinetic0, window > 0 ? window : na, r->t_mark, loss,
                nt ? (double)r->newton_iters : na, nt ? r->max_newton_iters : na,
                nt ? (double)r->not_converged_steps : na, cb_status_name(r->step_status), note);
}

typedef struct {
  cb_cell_result r[MAXG * 2];
  int n;
} cell_list;
static void keep(void *ctx, const cb_cell_result *r) {
  cell_list *l = ctx;
  if (l->n < MAXG * 2) l->r[l->n++] = *r;
}

/* Converged Newton in E2 iterates to integrator.tol, at most this many times a
 * step (with the lecture's drop fix it converges linearly: up to ~100
 * iterations a step at k = 1e7); steps that still stop there are counted in
 * the timing table's not_converged_steps, and the report says so. */
enum { E2_CONVERGED_MAX_ITERS = 400 };
/* Step error of an implicit method (E2's accuracy condition): over its first
 * steps from the start state, each step's result against the converged
 * minimiser x* of the same step, solved from the method's own state; the
 * largest |x - x*|_M / |x* - x0|_M. Baraff-Witkin is checked over its first 10
 * steps (1/3 s; 3 above 21^2) against converged Newton's step (relative
 * |grad F| 1e-8, far below the 1% that decides; 1 above 41^2); converged
 * Newton over its first 3 steps (1 above 21^2) against the independent reference solve
 * (lib/instruments/reference.h, 1e-12; F is not convex, so a different local
 * minimiser shows as an error). */
enum { E2_ERR_STEPS_BW = 10, E2_ERR_STEPS_CONVERGED = 3 };

/* x* of the step from (x, v): ref_it's step on copies (xs, vs) if ref_it, else the reference solve */
static int minimiser(cb_integrator *ref_it, cb_reference *ref, const double *x, const double *v, double *xs, double *vs,
                     size_t n3) {
  if (!ref_it) {
    cb_reference_stats rs;
    return cb_reference_step(ref, x, v, xs, &rs);
  }
  cb_step_stats ss;
  memcpy(xs, x, n3 * sizeof *xs);
  memcpy(vs, v, n3 * sizeof *vs);
  return cb_integrator_step(ref_it, xs, vs, &ss);
}

static int step_error(cb_integrator *it, cb_integrator *ref_it, cb_reference *ref, const cb_stability_case *c,
                      double dt, int steps, double *err, int *done) {
  const cb_scene *s = c->scene;
  size_t n3 = (size_t)3 * s->mesh.nv;
  double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v), *x0 = malloc(n3 * sizeof *x0),
         *xs = malloc(n3 * sizeof *xs), *vs = malloc(n3 * sizeof *vs);
  int st = x && v && x0 && xs && vs ? CB_OK : cb_fail("explicit_stability: out of memory (step error)");
  *err = 0;
  *done = 0;
  if (st == CB_OK) {
    memcpy(x, c->x_start, n3 * sizeof *x);
    memcpy(v, c->v_start, n3 * sizeof *v);
    it->params.dt = dt;
    if (ref_it) ref_it->params.dt = dt;
  }
  for (int k = 0; st == CB_OK && k < steps; k++) {
    cb_step_stats ss;
    memcpy(x0, x, n3 * sizeof *x);
    int r = minimiser(ref_it, ref, x, v, xs, vs, n3);
    if (r != CB_OK && r != CB_NOT_CONVERGED) break; /* no x*: the steps checked so far stand */
    r = cb_integrator_step(it, x, v, &ss);
    if (r != CB_OK && r != CB_NOT_CONVERGED) {
      *err = INFINITY;
      ++*done;
      break;
    } /* a failed step is no accurate step */
    double e = cb_step_error(s, x, xs, x0);
    *err = isfinite(e) ? fmax(*err, e) : INFINITY;
    ++*done;
  }
  free(x);
  free(v);
  free(x0);
  free(xs);
  free(vs);
  return st;
}

/* E2: wall time to simulate 1 s from the case's start state. The methods are
 * timed in interleaved rounds (explicit, Newton, Baraff-Witkin, explicit, ...;
 * lib/instruments/stats.h: 3 rounds with --quick, 2-5 in a full run by their
 * cost; a run under 25 ms timed right after an untimed one of its own), and
 * each row holds the median, min and max over its repeats and every repeat
 * (repeat i of one method ran in the same round as repeat i of the others).
 * Methods (bit 1 << index in e2_methods[], CSV label): explicit; newton,
 * converged Newton as the map runs it (definiteness shift, line search,
 * CHOLMOD: the fastest converging variant; the lecture's drop converges
 * linearly here, 3x the iterations); newton_bw, Baraff-Witkin (one Newton
 * iteration, the lecture's drop, no line search); newton_bw_shift,
 * Baraff-Witkin on the exact Hessian (shift); newton_2 .. newton_5, Newton
 * stopped after 2-5 iterations a step (shift, line search: converged
 * Newton's variant, cut short); chebyshev_nl, the lab's nonlinear
 * Chebyshev-Jacobi (rho 0.995, lab diagonal); pd, projective dynamics (plain,
 * CHOLMOD). The last two run a fixed number of iterations a step, so each has
 * a ladder of counts: an untimed pass measures the step error at each count,
 * smallest first, and the smallest count within E2_ERR_TOL is the one timed
 * (the largest of the ladder if none is; its row then shows the error that
 * keeps it out of the baseline). That is the fair-baseline rule (CLAIMS.md,
 * E2: the fastest implicit method within 1%) applied to a method whose
 * accuracy is a parameter. pd covers stretch springs and gravity only: on the
 * bending family it is rejected when built and has no row.
 * Explicit runs at its measured largest stable dt (dt_crit_meas_s), the
 * implicit methods at 1/30 s. Converged Newton on grids above 21^2 runs 3
 * steps (0.1 s), above 41^2 one (~30 iterations on 81^2); Newton with 2-5
 * iterations runs 3 steps above 41^2; wall_ms_per_s scales every row to 1 s.
 * After the timed rounds, an untimed pass measures each implicit method's
 * step error. */
#define E2_ERR_TOL 0.01 /* CLAIMS.md E2: an implicit method counts when its step error is within 1% */
enum { E2_LADDER = 3 };
typedef struct {
  const char *label, *type; /* CSV label, integrator type */
  int newton_iters;         /* newton: max_iters (0: not newton) */
  int definiteness, line_search;
  int ladder[E2_LADDER]; /* fixed-iteration methods: the counts tried, ascending (0: none) */
} e2_method;
static const e2_method e2_methods[] = {
    {"explicit", "explicit", 0, 0, 0, {0}},
    {"newton", "newton", E2_CONVERGED_MAX_ITERS, CB_DEF_SHIFT, 1, {0}},
    {"newton_bw", "newton", 1, CB_DEF_DROP, 0, {0}},
    {"newton_bw_shift", "newton", 1, CB_DEF_SHIFT, 0, {0}},
    {"newton_2", "newton", 2, CB_DEF_SHIFT, 1, {0}},
    {"newton_3", "newton", 3, CB_DEF_SHIFT, 1, {0}},
    {"newton_4", "newton", 4, CB_DEF_SHIFT, 1, {0}},
    {"newton_5", "newton", 5, CB_DEF_SHIFT, 1, {0}},
    {"chebyshev_nl", "chebyshev-nl", 0, 0, 0, {32, 128, 512}},
    {"pd", "pd", 0, 0, 0, {10, 32, 128}},
};
enum { E2_METHODS = sizeof e2_methods / sizeof e2_methods[0], E2_ALL = (1 << E2_METHODS) - 1 };

/* Builds method m at dt = 1/30 s (pd factors M/dt^2 + L when built) with `iters` iterations a step for a
 * ladder method; *out NULL and CB_OK when the method does not cover the scene (pd on bending). */
static int e2_alloc(const cb_stability_case *c, int m, int iters, cb_integrator **out) {
  const e2_method *d = &e2_methods[m];
  cb_integrator_params ip = c->newton->params;
  ip.dt = 1.0 / 30.0;
  *out = NULL;
  const char *solver = c->newton->solver->type->name;
  const cb_solver_params *sp = &c->newton->solver->params;
  if (d->newton_iters > 0) {
    cb_newton_params np = *(const cb_newton_params *)c->newton->type_params; /* the case's Newton, from its config */
    np.max_iters = d->newton_iters;
    np.line_search = d->line_search;
    np.definiteness = (cb_definiteness)d->definiteness;
    return cb_integrator_alloc("newton", c->scene, &ip, &np, solver, sp, out);
  }
  int st;
  if (!strcmp(d->type, "pd")) {
    cb_pd_params pp = cb_pd_params_default();
    pp.rho = 0; /* plain pd (the default is pd-chebyshev's) */
    pp.iters = iters;
    st = cb_integrator_alloc("pd", c->scene, &ip, &pp, solver, sp, out);
  } else {
    cb_nljacobi_params jp = cb_nljacobi_params_default(); /* the lab's: rho 0.995, lab diagonal */
    jp.iters = iters;
    st = cb_integrator_alloc(d->type, c->scene, &ip, &jp, solver, sp, out);
  }
  if (st == CB_EINVAL && !strcmp(d->type, "pd")) { /* a term pd does not cover: no row */
    *out = NULL;
    return CB_OK;
  }
  return st;
}

static int timing(const cb_experiment *e, const plan *pl, const char *family, cb_stability_case *c, double meas,
                  int timed) {
  cb_stability_params p = cb_stability_params_default();
  p.min_steps = 1;
  p.max_steps = 0;
  p.energy_every = 0;
  cb_integrator *it[E2_METHODS] = {c->expl};
  int iters[E2_METHODS] = {0}; /* a ladder method's count, as timed */
  cb_reference *ref = NULL;
  cb_reference_params rp = cb_reference_params_default();
  rp.dt = 1.0 / 30.0;
  int st = CB_OK, built = timed | ((timed & ~3) ? 2 : 0); /* converged Newton is the others' x*: built even where
                                                            not timed */
  for (int m = 1; st == CB_OK && m < E2_METHODS; m++)
    if ((built & (1 << m)) && !e2_methods[m].ladder[0]) st = e2_alloc(c, m, 0, &it[m]);
  if (st == CB_OK && (timed & 2)) st = cb_reference_alloc(c->scene, &rp, &ref);
  /* how many steps the step error is checked over: converged Newton 3 (1 above 21^2) against the reference,
   * the others 10 (3 above 21^2, 1 above 41^2) against converged Newton */
  int err_want[E2_METHODS];
  for (int m = 1; m < E2_METHODS; m++) {
    err_want[m] = m == 1 ? E2_ERR_STEPS_CONVERGED : E2_ERR_STEPS_BW;
    if (cur_nv > 441) err_want[m] = m == 1 || cur_nv > 1681 ? 1 : 3;
    int run = (int)lround(pl->e2_time * 30); /* no more than a timed run's steps (--smoke: 2) */
    if (err_want[m] > run) err_want[m] = run;
  }
  double err[E2_METHODS];
  int err_steps[E2_METHODS] = {0};
  for (int m = 0; m < E2_METHODS; m++) err[m] = NAN;
  /* the ladder methods: the smallest count within E2_ERR_TOL (untimed), else the largest */
  for (int m = 1; st == CB_OK && m < E2_METHODS; m++) {
    if (!(timed & (1 << m)) || !e2_methods[m].ladder[0]) continue;
    for (int q = 0; st == CB_OK && q < E2_LADDER && e2_methods[m].ladder[q] > 0; q++) {
      cb_integrator *t = NULL;
      if ((st = e2_alloc(c, m, e2_methods[m].ladder[q], &t)) || !t) break;
      cb_integrator_free(it[m]);
      it[m] = t;
      iters[m] = e2_methods[m].ladder[q];
      st = step_error(it[m], it[1], ref, c, 1.0 / 30.0, err_want[m], &err[m], &err_steps[m]);
      if (err_steps[m] == 0) err[m] = NAN;
      if (err[m] <= E2_ERR_TOL) break;
    }
    if (!it[m]) timed &= ~(1 << m); /* not covered: no row */
  }
  cb_cell_result first[E2_METHODS];
  cb_timing wall[E2_METHODS];
  memset(wall, 0, sizeof wall);
  double spent = 0;
  for (int round = 0; st == CB_OK && cb_timing_more(e->quick, round, spent); round++)
    for (int m = 0; st == CB_OK && m < E2_METHODS; m++) {
      if (!(timed & (1 << m))) continue;
      double dt = m == 0 ? meas : 1.0 / 30.0; /* explicit at its measured largest stable dt; implicit at 1/30 s */
      /* converged Newton: 3 steps above 21^2, 1 above 41^2 (~30 iterations a step on 81^2); Newton with 2-5
       * iterations: 3 steps above 41^2 */
      int nw = e2_methods[m].newton_iters;
      p.sim_time = m == 1                     ? (cur_nv <= 441    ? pl->e2_time
                                                 : cur_nv <= 1681 ? pl->e2_time / 10
                                                                  : pl->e2_time / 30)
                   : nw >= 2 && cur_nv > 1681 ? pl->e2_time / 10
                                              : pl->e2_time;
      cb_cell_result r;
      if ((st = cb_stability_cell(it[m], dt, c->x_start, c->v_start, c->S, &p, &c->work, &r))) break;
      if (cb_timing_warm(r.wall_ms) && /* a short run: that was its warm-up, time the next */
          (st = cb_stability_cell(it[m], dt, c->x_start, c->v_start, c->S, &p, &c->work, &r)))
        break;
      if (round == 0) first[m] = r; /* every repeat computes the same run; only its time differs */
      cb_timing_add(&wall[m], r.wall_ms);
      spent += r.wall_ms;
    }
  for (int m = 1; st == CB_OK && m < E2_METHODS; m++)
    if ((timed & (1 << m)) && !e2_methods[m].ladder[0]) {
      int want = err_want[m];
      if (want > first[m].steps) want = (int)first[m].steps;
      st = step_error(it[m], m == 1 ? NULL : it[1], ref, c, 1.0 / 30.0, want, &err[m], &err_steps[m]);
      if (err_steps[m] == 0) err[m] = NAN; /* the reference failed at once: not measured */
    }
  for (int m = 0; st == CB_OK && m < E2_METHODS; m++) {
    if (!(timed & (1 << m))) continue;
    const cb_cell_result *b = &first[m];
    double dt = m == 0 ? meas : 1.0 / 30.0;
    cb_csv_printf(ftime, "%s,%s,%d,%.17g,%s,%.17g,%ld,%.17g,%.6f,", cur_scene, family, cur_nv, cur_k,
                  e2_methods[m].label, dt, b->steps, b->t_end, cb_timing_median(&wall[m]));
    cb_timing_csv(ftime, &wall[m], 1 / b->t_end); /* wall_ms_per_s, its min and max */
    fputc(',', ftime);
    cb_timing_csv_each(ftime, &wall[m], 1 / b->t_end);
    /* explicit has no Newton iterations and no step error; a method with a fixed count a step (Baraff-Witkin,
     * Newton 2-5, the ladder methods) is never "not converged": stopping there is the method */
    double na = cb_csv_na();
    int cap = e2_methods[m].newton_iters > 0 && m != 1 ? e2_methods[m].newton_iters : iters[m];
    cb_csv_printf(ftime, ",%d,%s,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", wall[m].n, cb_cell_class_name(b->cls),
                  cb_status_name(b->step_status), m == 0 ? na : (double)b->newton_iters, meas, c->pred.dt_crit,
                  m == 1 ? (double)b->not_converged_steps : na, m == 0 ? na : cb_csv_na_if_nan(err[m]),
                  m == 0 ? na : (double)err_steps[m], cap > 0 ? (double)cap : na);
  }
  cb_reference_free(ref);
  for (int m = 1; m < E2_METHODS; m++) cb_integrator_free(it[m]);
  return st;
}

/* Whether the map runs a Newton cell at (k[ik], dt[j]) (see scenes[]); --smoke: the largest dt only. */
static int newton_cell(const plan *p, const scene_plan *d, int ik, int j) {
  int q = p->quick, sd = d->nt_dt_stride[q], sk = d->nt_k_stride[q];
  if (sk <= 0) return 0;
  if (p->smoke) return j == p->ndt - 1;
  return j % sd == (p->ndt - 1) % sd && ik % sk == (p->nk - 1) % sk && p->dt[j] >= d->nt_dt_min[q] * 0.999;
}

/* Whether a (scene, k) times E2 (when its bisection found the boundary): --smoke, every "resolution"
 * scene, a "map" scene at every e2_k_stride-th k and at the resolution study's k_res. */
static int e2_timed(const plan *p, const scene_plan *d, int ik) {
  int q = p->quick, n = grid_n(&d->scene), grid = cb_scene_decl_is(&d->scene, "map");
  double k = p->k[ik];
  return p->smoke || !grid || (d->e2_k_stride[q] > 0 && ik % d->e2_k_stride[q] == 0) ||
         (n > 0 && (k == p->k_res[0] || (!q && k == p->k_res[1])));
}

/* The parts of a (scene, k), each its own cell, in this order: the explicit sweep and bisection rows and the
 * boundary row (PART_MAP), the Newton cells' rows (PART_NEWTON), E2's timing rows (PART_E2). A part needs
 * the case (equilibrium, prediction) and the measured boundary, so each cell computes those (the same
 * numbers); the parts' rows, in this order, are the rows one cell for the whole (scene, k) wrote. */
enum { PART_MAP = 1, PART_NEWTON = 2, PART_E2 = 4, PART_ALL = 7 };

/* One (scene, k): explicit sweep, bisection, Newton cells, boundary row, E2; the rows of `parts` only. */
static int run_case(const cb_experiment *e, const plan *p, const scene_plan *d, int ik, int parts) {
  static cell_list sweep, bis, newton;
  int n = grid_n(&d->scene), grid = cb_scene_decl_is(&d->scene, "map"); /* no grid: E2 only */
  double k = p->k[ik];
  cb_config cfg;
  cb_case_params cp = cb_case_params_default();
  /* dense GSL on the chains, and on cloth21 at three k to check Lanczos; Lanczos otherwise */
  cp.eig = n == 0 || (n == 21 && grid && !p->smoke && ik % ((p->nk - 1) / 2) == 0) ? CB_EIG_BOTH : CB_EIG_LANCZOS;
  cp.predict_rest = grid;
  /* the Newton and E2 rows use only the prediction's dt_crit, which comes from the dense eigensolver where
   * there is one: the Lanczos check (~10 s on 21^2 at k = 1e7) and the rest shape's prediction are for the
   * boundary row, the map part's */
  if (!(parts & PART_MAP)) {
    cp.predict_rest = 0;
    if (cp.eig == CB_EIG_BOTH) cp.eig = CB_EIG_DENSE;
  }
  cb_stability_case c;
  int st = scene_config(e, &d->scene, k, &cfg);
  if (st == CB_OK) st = cb_stability_case_init(&c, &cfg, &cp);
  if (st) return st;
  cur_scene = d->scene.label;
  cur_k = k;
  cur_nv = c.scene->mesh.nv;
  sweep.n = bis.n = newton.n = 0;
  int cls[MAXG], mono = -1;
  double lo = NAN, hi = NAN;
  cb_bisect_result b;
  for (int j = 0; grid && st == CB_OK && j < p->ndt; j++, sweep.n++) {
    st = cb_stability_cell(c.expl, p->dt[j], c.x_start, c.v_start, c.S, &p->ex, &c.work, &sweep.r[j]);
    cls[j] = sweep.r[j].cls;
  }
  if (st == CB_OK && grid) {
    cb_stability_grid_bracket(p->dt, cls, p->ndt, &lo, &hi, &mono);
    st = cb_stability_bisect(c.expl, c.x_start, c.v_start, c.S, &p->ex, &c.work, lo, hi, pow(10.0, 4.0 / (p->ndt - 1)),
                             p->bisect_iters, keep, &bis, &b);
  } else if (st == CB_OK) /* no grid: bracket from the prediction, 5% steps */
    st = cb_stability_boundary_from_guess(c.expl, c.x_start, c.v_start, c.S, &p->ex, &c.work, c.pred.dt_crit, 1.05,
                                          p->bisect_iters - 2, keep, &bis, &b);
  const cb_stability_params pn = p->nt;
  for (int j = 0; grid && (parts & PART_NEWTON) && st == CB_OK && j < p->ndt; j++)
    if (newton_cell(p, d, ik, j))
      st = cb_stability_cell(c.newton, p->dt[j], c.x_start, c.v_start, c.S, &pn, &c.work, &newton.r[newton.n++]);
  double meas = st == CB_OK ? b.dt_stable : NAN;
  for (int i = 0; (parts & PART_MAP) && st == CB_OK && i < sweep.n; i++)
    cell_row("sweep", "map", "explicit", &sweep.r[i], c.pred.dt_crit, meas, c.kinetic0, 0, "");
  for (int i = 0; (parts & PART_MAP) && st == CB_OK && i < bis.n; i++)
    cell_row("bisect", "boundary", "explicit", &bis.r[i], c.pred.dt_crit, meas, c.kinetic0, 0, "");
  for (int i = 0; st == CB_OK && i < newton.n; i++)
    cell_row("sweep", "map", "newton", &newton.r[i], c.pred.dt_crit, meas, c.kinetic0, pn.mark_time, "");
  /* not applicable, written empty: the eigensolver that did not run (its lambda is NaN), the rest-shape
   * prediction without a grid (NaN), the grid bracket without a grid (NaN) or without a stable / an unstable
   * grid dt (0), the grid's monotonicity without a grid (-1), a bisection bound not found (NaN) */
  const cb_prediction *pr = &c.pred;
  int lz = !isnan(pr->lambda_lanczos);
  if (st == CB_OK && (parts & PART_MAP))
    cb_csv_printf(fbound,
                  "%s,%d,%d,%.17g,%.17g,%.17g,%d,%s,%.17g,%.17g,%.17g,%s,%.17g,%.17g,%.17g,%s,%.17g,%.17g,%.17g,%.17g,"
                  "%.17g,%.17g,%.17g,%.17g,%d,%s,%.3f,%.3f\n",
                  cur_scene, cur_nv, c.scene->model.nfree, k, c.scene->mass[c.scene->free_vertex[0]], c.eq.residual,
                  c.eq.steps, cb_status_name(c.eq.status), c.eq.max_strain, c.eq.min_strain, pr->lambda_max,
                  pr->method == CB_EIG_DENSE ? "gsl_dense" : "lanczos", cb_csv_na_if_nan(pr->lambda_dense),
                  cb_csv_na_if_nan(pr->lambda_lanczos), lz ? pr->lanczos_steps : cb_csv_na(),
                  lz ? cb_status_name(pr->lanczos_status) : "", cb_csv_na_if_nan(c.pred_rest.lambda_max), pr->dt_crit,
                  cb_csv_na_if_nan(c.pred_rest.dt_crit), lo > 0 ? lo : cb_csv_na(), hi > 0 ? hi : cb_csv_na(),
                  mono >= 0 ? mono : cb_csv_na(), cb_csv_na_if_nan(b.dt_stable), cb_csv_na_if_nan(b.dt_unstable),
                  b.runs, cb_status_name(b.status), c.eq.ms, c.pred.ms + c.pred_rest.ms);
  /* E2: 1 explicit, 2 converged Newton, 4 and 8 Baraff-Witkin (drop, shift); converged Newton
   * above 41^2 (~3 s a step on 81^2) only at k_res[0] */
  int timed = (parts & PART_E2) && e2_timed(p, d, ik);
  int methods = c.scene->mesh.nv > 1681 && k != p->k_res[0] ? E2_ALL & ~2 : E2_ALL;
  if (p->smoke) methods &= ~((1 << 5) | (1 << 6) | (1 << 7)); /* --smoke: of Newton with 2-5 iterations, 2 only */
  if (st == CB_OK && timed && b.status == CB_OK) st = timing(e, p, d->family, &c, meas, methods);
  cb_stability_case_free(&c);
  return st;
}

/* Stiff and extreme cases on the 21^2 cloth, one cell each: each has rows
 * and a note. A case's scene is the 21^2 cloth with its own overrides; its
 * label is the case. */
typedef struct {
  cb_scene_decl scene;
  double k;
  int eq;
  double ex[2]; /* explicit dt: f > 0: f x dt_crit_pred at the start; f < 0: |f| x at the rest shape; else a fixed dt */
  const char *note;
} extreme_case;
static const extreme_case extreme_cases[] = {
    {{"k_1e8", "hanging.ini", {CLOTH(21, 441), NULL}, "extreme"},
     1e8,
     1,
     {0.9, 1.1},
     "k = 1e8 N/m from the hanging equilibrium: explicit at 0.9 and 1.1 x dt_crit_pred; Newton at 1/30 s"},
    {{"dt_0.1", "hanging.ini", {CLOTH(21, 441), NULL}, "extreme"},
     8000,
     1,
     {0.1, 0},
     "the lab stiffness 8000 N/m from the hanging equilibrium at dt = 0.1 s (12 x dt_crit_pred)"},
    {{"stretched_2x", "hanging.ini", {CLOTH(21, 441), "scene.initial_scale=2", NULL}, "extreme"},
     8000,
     0,
     {0.9, -0.9},
     "starts at 2x the rest size (no equilibrium); explicit at 0.9 x dt_crit_pred at that start and at the rest shape"},
    {{"compressed_0.5x", "hanging.ini", {CLOTH(21, 441), "scene.initial_scale=0.5", NULL}, "extreme"},
     8000,
     0,
     {0.9, -0.9},
     "starts at 0.5x the rest size (no equilibrium); explicit at 0.9 x dt_crit_pred at that start and at the rest "
     "shape"},
    {{"zero_rest_length",
      "hanging.ini",
      {CLOTH(21, 441), "mesh.type=obj", "mesh.file=zero_rest_length.obj", "scene.pins=0", NULL},
      "extreme"},
     8000,
     1,
     {0.9, 0},
     "configs/zero_rest_length.obj joins two coincident vertices by a line element"},
    {{"zero_gravity_no_pins",
      "hanging.ini",
      {CLOTH(21, 441), "scene.gravity=0 0 0", "scene.pins=none", NULL},
      "extreme"},
     8000,
     1,
     {0.9, 1.1},
     "no gravity and no pins: a free cloth with a random velocity (K has six rigid-body zero eigenvalues)"},
};
enum { NEXTREMES = sizeof extreme_cases / sizeof extreme_cases[0] };

static int extreme(const cb_experiment *e, const plan *p, const extreme_case *x) {
  cb_stability_params pe = p->ex, pn = p->ex;
  pn.sim_time = 1.0;
  pn.min_steps = 1;
  pn.max_steps = 0;
  pn.energy_every = 1;
  if (p->quick) pn.sim_time = p->smoke ? 2.0 / 30.0 : 1.0 / 3.0;
  cb_config cfg;
  cb_case_params cp = cb_case_params_default();
  cp.equilibrium = x->eq;
  cp.eig = CB_EIG_LANCZOS;
  cb_stability_case c;
  const char *cas = x->scene.label;
  cur_scene = "cloth21";
  cur_k = x->k;
  cur_nv = 441;
  int st = scene_config(e, &x->scene, x->k, &cfg);
  if (st == CB_OK) st = cb_stability_case_init(&c, &cfg, &cp);
  if (st == CB_EINVAL) { /* bad input: a clear error, recorded in the row; what was never measured is empty */
    char msg[1024];
    snprintf(msg, sizeof msg, "%s: rejected when the scene is built: %s", x->note, cb_error_message());
    for (char *s = msg; *s; s++)
      if (*s == ',' || *s == '\n') *s = ';';
    cb_csv_printf(fmain, "extreme,%s,cloth21,,%.17g,,explicit,rejected,,,0,0,,,,,,,,,,,,,,invalid_input,%s\n", cas,
                  x->k, msg);
    return CB_OK;
  }
  if (st) return st;
  cur_nv = c.scene->mesh.nv;
  cb_cell_result r;
  for (int m = 0; m < 3 && st == CB_OK; m++) {
    double f = m < 2 ? x->ex[m] : 0, dt = f > 0.5 ? f * c.pred.dt_crit : f < 0 ? -f * c.pred_rest.dt_crit : f;
    if (m == 2) dt = !strcmp(cas, "dt_0.1") ? 0.1 : 1.0 / 30.0;
    if (!(dt > 0)) continue;
    st = cb_stability_cell(m == 2 ? c.newton : c.expl, dt, c.x_start, c.v_start, c.S, m == 2 ? &pn : &pe, &c.work, &r);
    if (st == CB_OK)
      cell_row("extreme", cas, m == 2 ? "newton" : "explicit", &r, c.pred.dt_crit, NAN, c.kinetic0, 0, x->note);
  }
  cb_stability_case_free(&c);
  return st;
}

/* Cost hints (estimated ms; scripts/calibrate-hints on a --quick and a full run's cell times): a case with
 * its explicit sweep and bisection ~0.5 ms per vertex on the 21^2 cloth, growing like vertices^1.5 (41^2:
 * the equilibrium and the sweep's steps), twice that at k = 10 (a long equilibrium), ~1 + 0.2 ms per vertex
 * on a chain or spring (a few ms, noisy), 3.5x that in a full run (25 dt of up to 2000 steps, 10
 * bisections; a chain 10 + 1 ms per vertex), plus ~3.5 s where the 21^2 cloth checks Lanczos against GSL's
 * dense eigensolver (~1.2 s for the dense alone, in the Newton and E2 parts); a Newton map cell (200 steps) ~4.8 ms per
 * vertex on a cloth at k = 1e4, its iterations growing like k^0.3, ~1 + 0.7 ms per vertex on a chain (a few iterations
 * at any k; twice the steps in a full run); E2's timed rounds and step errors ~4 ms per vertex on 21^2 and 41^2, in a
 * full run twice that and growing like k^0.15 (more rounds, stiffer Newton steps). */
static double case_ms(const plan *p, const scene_plan *d, int ik, double nv, int parts) {
  int n = grid_n(&d->scene), full = !p->quick && !p->smoke;
  int dense = n == 21 && !p->smoke && ik % ((p->nk - 1) / 2) == 0;
  double sweep = n ? 0.5 * nv * sqrt(nv / 441) * (1 + 10 / p->k[ik]) * (full ? 3.5 : 1) : full ? 10 + nv : 1 + 0.2 * nv;
  return sweep + (dense ? (parts & PART_MAP ? 3500 : 1200) : 0); /* without the Lanczos check: the dense alone */
}
static double newton_ms(const plan *p, const scene_plan *d, int ik, double nv, int ncells) {
  double steps = p->ex.max_steps / 1000.0;
  return ncells * (grid_n(&d->scene) ? 4.8 * nv * pow(p->k[ik] / 1e4, 0.3) : (1 + 0.7 * nv) * steps);
}
static double e2_ms(const plan *p, int ik, double nv) {
  return 4.0 * nv * (!p->quick && !p->smoke ? 2 * pow(p->k[ik] / 1e4, 0.15) : 1);
}

/* The cells: the parts (PART_MAP, PART_NEWTON, PART_E2) of the swept k of
 * every "map" scene, the k_res of every "resolution" scene (one cell: its
 * boundary row and E2), then the extreme cases. */
typedef struct {
  int scene, ik, parts;
  double cost;
} case_cell;
typedef struct {
  const cb_experiment *e;
  const plan *p;
  case_cell map[NSCENES * MAXG * 3], res[NSCENES * 2];
  double ext_cost[NEXTREMES];
  int nmap, nres;
} cells;

static void use(FILE *const *out) {
  fmain = out[T_MAIN];
  fbound = out[T_BOUNDARY];
  ftime = out[T_TIMING];
}

static int map_cell(long i, void *ctx, FILE *const *out) {
  const cells *c = ctx;
  use(out);
  return run_case(c->e, c->p, &scenes[c->map[i].scene], c->map[i].ik, c->map[i].parts);
}

static int res_cell(long i, void *ctx, FILE *const *out) {
  const cells *c = ctx;
  plan q = *c->p; /* no sweep: k[0] is the resolution study's k */
  q.k[0] = c->p->k_res[c->res[i].ik];
  use(out);
  return run_case(c->e, &q, &scenes[c->res[i].scene], 0, PART_ALL);
}

static int extreme_cell(long i, void *ctx, FILE *const *out) {
  const cells *c = ctx;
  use(out);
  return extreme(c->e, c->p, &extreme_cases[i]);
}

static double map_cost(long i, void *ctx) { return ((const cells *)ctx)->map[i].cost; }
/* Only E2's part times a comparison (its methods' wall_ms_per_s, in interleaved rounds); the explicit sweep's
 * and the Newton cells' wall_ms and the boundary row's set-up times are recorded, decide nothing, and are
 * measured beside other untimed work. */
static int map_timed(long i, void *ctx) { return ((const cells *)ctx)->map[i].parts == PART_E2; }
static double res_cost(long i, void *ctx) { return ((const cells *)ctx)->res[i].cost; }
static double extreme_cost(long i, void *ctx) { return ((const cells *)ctx)->ext_cost[i]; }

static const char *about = "Claims E1, E2, I1. Sweeps spring stiffness k (1e1..1e7 N/m) and time step dt\n"
                           "(1e-5..1e-1 s) on a single spring, a 20-spring chain and the hanging cloth at 21^2\n"
                           "and 41^2, each cell starting at the static (hanging) equilibrium plus a small random\n"
                           "velocity; classifies explicit and Newton cells (over the same steps) stable/unstable/\n"
                           "diverged; bisects the largest stable explicit dt against the prediction 2/omega_max;\n"
                           "times 1 s of simulation (explicit at its largest stable dt; converged Newton and\n"
                           "Baraff-Witkin at 1/30 s, with their step errors) against k and resolution, for a\n"
                           "stretch-dominated cloth (21^2, 41^2, 81^2) and a bending-dominated one (11^2, 21^2,\n"
                           "41^2); runs stiff and extreme cases. Writes <out>, <out>_boundary.csv and\n"
                           "<out>_timing.csv (stem of --out).\n"
                           "  --time SECONDS   simulated time per explicit cell (default 2; 1 with --quick)";

int main(int argc, char **argv) {
  double sim_time = 0;
  int ac = 0;
  for (int i = 0; i < argc; i++) /* our own option, taken out before the common ones */
    if (!strcmp(argv[i], "--time") && i + 1 < argc) {
      if (cb_parse_double(argv[++i], &sim_time) || !(sim_time > 0)) {
        fprintf(stderr, "explicit_stability: --time: '%s' is not a positive number of seconds\n", argv[i]);
        return 1;
      }
    } else argv[ac++] = argv[i];
  cb_experiment e;
  int st = cb_experiment_begin(&e, "explicit_stability", about, ac, argv);
  if (st) return st > 0 ? 0 : 1;
  /* E2's timings run alone (the map's E2 cells and the resolution cells, which hold a whole case); the explicit
   * sweeps, Newton cells and extreme cases time nothing a claim compares and run beside other untimed work */
  cb_experiment_timed_cells(&e, (const char *const[]){"extremes", NULL});
  plan p;
  make_plan(&p, e.quick, e.smoke, sim_time);
  char info[1024];
  snprintf(info, sizeof info,
           "# plan: %d k x %d dt; explicit cells %g s with %ld..%ld steps; bisection %d; Newton cells "
           "%g s (energy mark); start: equilibrium + random velocity 1e-6 S0 + swing 1e-3 S0; R_u %g; R_d %g\n",
           p.nk, p.ndt, p.ex.sim_time, p.ex.min_steps, p.ex.max_steps, p.bisect_iters, p.nt.sim_time,
           p.ex.unstable_ratio, p.ex.diverge_ratio);
  if (cb_experiment_table(&e, NULL, info,
                          "kind,case,scene,n_vertices,k_n_per_m,dt_s,method,status,max_energy_ratio,final_energy_ratio,"
                          "steps,t_end_s,wall_ms,"
                          "dt_crit_pred_s,dt_crit_meas_s,energy0_j,energy_end_j,energy_scale_j,kinetic0_j,window_s,t_"
                          "mark_s,energy_loss_w,newton_iters,"
                          "max_newton_iters,not_converged_steps,step_status,note") != T_MAIN ||
      cb_experiment_table(&e, "boundary", info,
                          "scene,n_vertices,n_free,k_n_per_m,vertex_mass_kg,equilibrium_residual,equilibrium_steps,"
                          "equilibrium_status,max_strain,"
                          "min_strain,lambda_max_per_s2,eig_method,lambda_dense_per_s2,lambda_lanczos_per_s2,lanczos_"
                          "steps,lanczos_status,"
                          "lambda_max_rest_per_s2,dt_crit_pred_s,dt_crit_pred_rest_s,dt_stable_grid_s,dt_unstable_grid_"
                          "s,grid_monotone,"
                          "dt_crit_meas_s,dt_crit_meas_hi_s,bisect_runs,bisect_status,equilibrium_ms,predict_ms") !=
          T_BOUNDARY ||
      cb_experiment_table(&e, "timing", info,
                          "scene,family,n_vertices,k_n_per_m,method,dt_s,steps,sim_time_s,wall_ms,wall_ms_per_s,wall_"
                          "min_ms_per_s,"
                          "wall_max_ms_per_s,wall_each_ms_per_s,wall_repeats,status,step_status,newton_iters,dt_crit_"
                          "meas_s,dt_crit_pred_s,"
                          "not_converged_steps,step_error_max,step_error_steps,iters_per_step") != T_TIMING)
    return cb_experiment_end(&e, CB_EIO), 2;
  /* cost hints, estimated ms (scripts/calibrate-hints on a --quick run's measured cell times): every part
   * of a (scene, k) builds the case and runs the explicit sweep and bisection (case_ms); the Newton part adds
   * its 200-step Newton cells, the E2 part the timed rounds and step errors; a resolution cell is its E2 */
  static cells cl;
  cl.e = &e;
  cl.p = &p;
  for (int s = 0; st == CB_OK && s < NSCENES; s++) {
    const scene_plan *d = &scenes[s];
    cb_scene_size z;
    if ((st = cb_sweep_scene_size(&e, &d->scene, &z))) break;
    /* --smoke: cloth21 at k = 1e4 (every part of a map cell) and the smallest bending cloth */
    if (p.smoke && strcmp(d->scene.label, "cloth21") && strcmp(d->scene.label, "bend11")) continue;
    double nv = (double)z.nv;
    if (cb_scene_decl_is(&d->scene, "map"))
      for (int i = 0; i < p.nk; i += d->k_stride[p.quick]) {
        int nn = 0;
        for (int j = 0; j < p.ndt; j++) nn += newton_cell(&p, d, i, j);
        double ms = case_ms(&p, d, i, nv, PART_NEWTON); /* the case of a Newton or E2 part */
        cl.map[cl.nmap++] = (case_cell){s, i, PART_MAP, case_ms(&p, d, i, nv, PART_MAP)};
        if (nn) cl.map[cl.nmap++] = (case_cell){s, i, PART_NEWTON, ms + newton_ms(&p, d, i, nv, nn)};
        if (e2_timed(&p, d, i)) cl.map[cl.nmap++] = (case_cell){s, i, PART_E2, ms + e2_ms(&p, i, nv)};
      }
    if (cb_scene_decl_is(&d->scene, "resolution"))
      for (int r = 0; r < d->nres[p.quick]; r++)
        cl.res[cl.nres++] = (case_cell){
            s, r, PART_ALL, nv * (!strcmp(d->family, "bending") ? 2 + sqrt(nv) / 10 : 4.4 * (1 + sqrt(nv) / 50))};
  }
  /* an extreme case: ~1 ms per vertex; an OBJ mesh (zero_rest_length: rejected when the scene is built) ~5 ms */
  for (int i = 0; st == CB_OK && i < NEXTREMES; i++) {
    cb_scene_size z;
    if ((st = cb_sweep_scene_size(&e, &extreme_cases[i].scene, &z))) break;
    cl.ext_cost[i] = z.nv ? (double)z.nv : 5;
  }
  if (st) return cb_experiment_end(&e, st), 1;
  const cb_sweep sweeps[] = {{"map", cl.nmap, map_cell, map_cost, &cl, map_timed},
                             {"resolution", cl.nres, res_cell, res_cost, &cl, NULL},
                             {"extremes", p.smoke ? 1 : NEXTREMES, extreme_cell, extreme_cost, &cl, NULL}};
  st = cb_sweep_run(&e, sweeps, 3);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
