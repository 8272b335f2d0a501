/* newton_vs_bw measurements, part 1: one step of every method from states
 * of the reference trajectory, and Newton's |grad F| sequences (I2). */
#include "newton_study.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pareto.h"
#include "csv.h"
#include <clothbench/status.h>
#include "stats.h"

const char *const cb_study_steps_header = "scene,n,dt_s,k_n_per_m,stretch,step,method,max_newton_iters,inner_solver,"
                                          "line_search,newton_iters,linear_iters,"
                                          "ls_reduced,ls_backtracks,step_error,rel_grad,f_minus_fstar_j,assemble_ms,"
                                          "factor_ms,setup_ms,solve_ms,wall_ms,"
                                          "wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,status,ref_iters,ref_rel_"
                                          "grad,ref_grad_norm_n,ref_last_dx_m,ref_status";

/* x, v, xstar: 3*nv each */
typedef struct {
  double *x, *v, *xs;
} state3;

static int state_alloc(const cb_scene *s, state3 *w) {
  size_t n3 = (size_t)3 * s->mesh.nv;
  w->x = cb_malloc(n3, sizeof(double));
  w->v = cb_malloc(n3, sizeof(double));
  w->xs = cb_malloc(n3, sizeof(double));
  if (!w->x || !w->v || !w->xs) return CB_ENOMEM;
  memcpy(w->x, s->x0, n3 * sizeof(double));
  memcpy(w->v, s->v0, n3 * sizeof(double));
  return CB_OK;
}

static void state_free(state3 *w) {
  free(w->x);
  free(w->v);
  free(w->xs);
}

static void scene_cols(FILE *f, const cb_scene *s, const char *label, double dt) {
  cb_csv_printf(f, "%s,%d,%.17g,%.17g,%.17g,", label, s->def.grid.n, dt, s->def.stretch_k, s->def.initial_scale);
}

int cb_study_steps(cb_scene *s, const char *label, double dt, const int *states, int nstates, const cb_method *methods,
                   int nmethods, int quick, FILE *csv, cb_study_point *pts) {
  cb_reference_params rp = cb_reference_params_default();
  rp.dt = dt;
  cb_reference *ref = NULL;
  cb_integrator **its = cb_calloc((size_t)nmethods, sizeof *its);
  cb_step_result *res = cb_calloc((size_t)nmethods, sizeof *res);
  cb_timing *tm = cb_calloc((size_t)5 * nmethods, sizeof *tm); /* per method: assemble, factor, setup, solve, wall */
  state3 w = {0};
  cb_method_work mw = {0};
  int st = its && res && tm ? cb_reference_alloc(s, &rp, &ref) : CB_ENOMEM;
  if (st == CB_OK) st = state_alloc(s, &w);
  if (st == CB_OK) st = cb_method_work_alloc(s, &mw);
  for (int m = 0; st == CB_OK && m < nmethods; m++)
    st = cb_method_integrator(&methods[m], s, dt, cb_method_hook, &mw, &its[m]);
  int last = nstates > 0 ? states[nstates - 1] : -1, next = 0;
  for (int step = 0; st == CB_OK && step <= last; step++) {
    cb_reference_stats rs;
    int rst = cb_reference_step(ref, w.x, w.v, w.xs, &rs);
    if (next < nstates && step == states[next]) {
      next++;
      double Fstar = cb_reference_objective(ref, w.x, w.v, w.xs, NULL);
      for (int m = 0; m < nmethods; m++)
        if (step == states[0]) { /* untimed warm-up: first-solve workspaces, caches */
          cb_newton_params *np = its[m]->type_params;
          int K = np->max_iters;
          np->max_iters = 1;
          cb_method_step(its[m], &mw, ref, w.x, w.v, w.xs, Fstar, &res[m]);
          np->max_iters = K;
        }
      /* timing: every method once per round, in interleaved rounds (stats.h: 3 with --quick, 2-5 in a
       * full run by their cost; a step under 25 ms timed right after an untimed one of its own); the
       * repeats compute the same step, only their times differ */
      memset(tm, 0, (size_t)5 * nmethods * sizeof *tm);
      double spent = 0;
      for (int round = 0; cb_timing_more(quick, round, spent); round++)
        for (int m = 0; m < nmethods; m++) {
          cb_step_result r;
          cb_method_step(its[m], &mw, ref, w.x, w.v, w.xs, Fstar, &r);
          if (cb_timing_warm(r.st.wall_ms)) /* a short step: that was its warm-up, time the next */
            cb_method_step(its[m], &mw, ref, w.x, w.v, w.xs, Fstar, &r);
          if (round == 0) res[m] = r;
          const double part[5] = {r.st.assemble_ms, r.st.factor_ms, r.setup_ms, r.st.solve_ms, r.st.wall_ms};
          for (int q = 0; q < 5; q++) cb_timing_add(&tm[5 * m + q], part[q]);
          spent += r.st.wall_ms;
        }
      for (int m = 0; m < nmethods; m++) {
        const cb_method *me = &methods[m];
        const cb_step_result *r = &res[m];
        const cb_timing *T = &tm[5 * m];
        scene_cols(csv, s, label, dt);
        cb_csv_printf(csv, "%d,%s,%d,%s,%d,%d,%d,%d,%d,%.17g,%.17g,%.17g,%.6f,%.6f,%.6f,%.6f,", step, me->name,
                      me->K > 0 ? me->K : CB_METHOD_CONVERGED_ITERS, me->inner, me->line_search, r->st.newton_iters,
                      r->st.linear_iters, r->ls_reduced, r->st.ls_backtracks, r->step_error, r->st.rel_grad,
                      r->f_minus_fstar, cb_timing_median(&T[0]), cb_timing_median(&T[1]), cb_timing_median(&T[2]),
                      cb_timing_median(&T[3]));
        cb_timing_csv(csv, &T[4], 1.0);
        fputc(',', csv);
        cb_timing_csv_each(csv, &T[4], 1.0);
        cb_csv_printf(csv, ",%d,%s,%d,%.17g,%.17g,%.17g,%s\n", T[4].n, cb_status_name(r->st.status), rs.iters,
                      rs.rel_grad, rs.grad_norm, rs.last_dx, cb_status_name(rst));
        if (pts) {
          cb_study_point *pt = &pts[(next - 1) * nmethods + m];
          pt->wall = T[4];
          pt->wall_ms = cb_timing_median(&T[4]);
          pt->setup_ms = cb_timing_median(&T[2]);
          pt->step_error = r->step_error;
          pt->failed = r->st.status != CB_OK && r->st.status != CB_NOT_CONVERGED;
        }
      }
    }
    /* advance along the reference trajectory: (x, v) <- (x*, (x* - x)/dt) */
    for (int i = 0; i < 3 * s->mesh.nv; i++) {
      w.v[i] = (w.xs[i] - w.x[i]) / dt;
      w.x[i] = w.xs[i];
    }
  }
  for (int m = 0; its && m < nmethods; m++) cb_integrator_free(its[m]);
  free(its);
  free(res);
  free(tm);
  cb_method_work_free(&mw);
  state_free(&w);
  cb_reference_free(ref);
  return st;
}

/* ---- summary ---------------------------------------------------------------- */

const char *const cb_study_pareto_header = "scene,method,max_newton_iters,k_index,inner_solver,inner_index,line_search,"
                                           "states,wall_ms,wall_min_ms,wall_max_ms,wall_no_setup_ms,"
                                           "step_error_max,failed,front_by_wall";

int cb_study_pareto(FILE *csv, const char *label, const cb_method *methods, int nmethods, const cb_study_point *pts,
                    int nstates) {
  static const char *const inners[] = {"cholmod", "cg32", "cheb32", "cg_tol", "cheb_tol", "cheb32_alpha1"};
  static const int Ks[] = {1, 2, 3, 5, 10, 0};
  double *cost = cb_malloc((size_t)nmethods, sizeof(double)), *nos = cb_malloc((size_t)nmethods, sizeof(double));
  double *err = cb_malloc((size_t)nmethods, sizeof(double)), *tmp = cb_malloc((size_t)nstates + 1, sizeof(double));
  double *lo = cb_malloc((size_t)nmethods, sizeof(double)), *hi = cb_malloc((size_t)nmethods, sizeof(double));
  cb_timing *each = cb_malloc((size_t)nstates + 1, sizeof *each);
  int *front = cb_malloc((size_t)nmethods, sizeof(int));
  int *failed = cb_calloc((size_t)nmethods, sizeof(int));
  int st = cost && nos && err && tmp && lo && hi && each && front && failed && nstates > 0 ? CB_OK : CB_ENOMEM;
  for (int m = 0; st == CB_OK && m < nmethods; m++) {
    err[m] = 0;
    for (int k = 0; k < nstates; k++) {
      const cb_study_point *p = &pts[k * nmethods + m];
      double e = p->failed || !isfinite(p->step_error) ? INFINITY : p->step_error;
      failed[m] |= p->failed;
      if (e > err[m]) err[m] = e;
      tmp[k] = p->wall_ms;
    }
    cost[m] = cb_median(tmp, nstates);
    for (int k = 0; k < nstates; k++) tmp[k] = pts[k * nmethods + m].wall_ms - pts[k * nmethods + m].setup_ms;
    nos[m] = cb_median(tmp, nstates);
    cb_timing per; /* the spread of the median over states */
    for (int k = 0; k < nstates; k++) each[k] = pts[k * nmethods + m].wall;
    if (cb_timing_median_over(each, nstates, &per) == 0) {
      lo[m] = cb_timing_min(&per);
      hi[m] = cb_timing_max(&per);
    } else {
      for (int k = 0; k < nstates; k++) tmp[k] = cb_timing_min(&each[k]);
      lo[m] = cb_median(tmp, nstates);
      for (int k = 0; k < nstates; k++) tmp[k] = cb_timing_max(&each[k]);
      hi[m] = cb_median(tmp, nstates);
    }
  }
  if (st == CB_OK) {
    /* rows in method order, not by cost: the file's deterministic columns are
     * then the same in every run; front_by_wall (1 on the error-against-wall-
     * time Pareto front) follows the timings, as its name says */
    cb_pareto_front(nmethods, cost, err, front);
    for (int m = 0; m < nmethods; m++) {
      int ki = 0, ii = 0;
      while (ki < 5 && Ks[ki] != methods[m].K) ki++;
      while (ii < 5 && strcmp(inners[ii], methods[m].inner)) ii++;
      cb_csv_printf(csv, "%s,%s,%d,%d,%s,%d,%d,%d,%.6f,%.6f,%.6f,%.6f,%.17g,%d,%d\n", label, methods[m].name,
                    methods[m].K > 0 ? methods[m].K : CB_METHOD_CONVERGED_ITERS, ki, methods[m].inner, ii,
                    methods[m].line_search, nstates, cost[m], lo[m], hi[m], nos[m], err[m], failed[m], front[m]);
    }
  }
  free(cost);
  free(nos);
  free(err);
  free(tmp);
  free(lo);
  free(hi);
  free(each);
  free(front);
  free(failed);
  return st;
}

/* ---- I2 -------------------------------------------------------------------- */

const char *const cb_study_order_header = "scene,n,dt_s,k_n_per_m,stretch,definiteness,line_search,step,iter,grad_norm_"
                                          "n,rel_grad,f_j,alpha,hessian,step_status,"
                                          "step_iters";

enum { ORDER_MAX_ITERS = 60, ORDER_LOG = 256 };

typedef struct {
  int n, def; /* def: the Hessian every update of this run uses (1 exact, 3 drop) */
  double g[ORDER_LOG], rel[ORDER_LOG], F[ORDER_LOG], alpha[ORDER_LOG];
  int hessian[ORDER_LOG]; /* Hessian of the update that led to the iterate: 0 start, 1 exact, 2 shifted, 3 drop */
} order_log;

static void order_hook(void *ctx, int event, const cb_newton_event *ev) {
  order_log *L = ctx;
  if (event != CB_NEWTON_GRADIENT || L->n >= ORDER_LOG) return;
  L->g[L->n] = ev->grad_norm;
  L->rel[L->n] = ev->rel_grad;
  L->F[L->n] = ev->F;
  L->alpha[L->n] = ev->iter > 0 ? ev->alpha : 1.0;
  L->hessian[L->n] = ev->iter > 0 ? L->def : 0;
  L->n++;
}

static void order_ref_log(void *ctx, int iter, double gn, double rel, double F, double alpha, int hessian) {
  order_log *L = ctx;
  (void)iter;
  if (L->n >= ORDER_LOG) return;
  L->g[L->n] = gn;
  L->rel[L->n] = rel;
  L->F[L->n] = F;
  L->alpha[L->n] = alpha;
  L->hessian[L->n] = hessian;
  L->n++;
}

static void order_rows(FILE *csv, const cb_scene *s, const char *label, double dt, const char *def, int ls, int step,
                       const order_log *L, int status, int iters) {
  static const char *const hname[] = {"-", "exact", "shifted", "drop"};
  for (int i = 0; i < L->n; i++) {
    scene_cols(csv, s, label, dt);
    cb_csv_printf(csv, "%s,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%s,%s,%d\n", def, ls, step, i, L->g[i], L->rel[i], L->F[i],
                  L->alpha[i], hname[L->hessian[i]], cb_status_name(status), iters);
  }
}

int cb_study_order(cb_scene *s, const char *label, double dt, int nsteps, FILE *csv) {
  order_log log;
  cb_reference_params rp = cb_reference_params_default();
  rp.dt = dt;
  rp.log = order_ref_log; /* the reference step is the "exact_or_shift" variant */
  rp.log_ctx = &log;
  cb_reference *ref = NULL;
  cb_integrator *its[4] = {NULL};
  state3 w = {0};
  double *xt = NULL, *vt = NULL;
  int st = cb_reference_alloc(s, &rp, &ref);
  if (st == CB_OK) st = state_alloc(s, &w);
  size_t n3 = (size_t)3 * s->mesh.nv;
  if (st == CB_OK) {
    xt = cb_malloc(n3, sizeof(double));
    vt = cb_malloc(n3, sizeof(double));
    if (!xt || !vt) st = CB_ENOMEM;
  }
  for (int v = 0; st == CB_OK && v < 4; v++) { /* v = 2 def + ls: none/drop x off/on */
    cb_integrator_params p = cb_integrator_params_default();
    p.dt = dt;
    p.hook = order_hook;
    p.hook_ctx = &log;
    cb_newton_params np = cb_newton_params_default();
    np.max_iters = ORDER_MAX_ITERS;
    np.tol = 1e-14;
    np.tol_dx = cb_reference_get_params(ref)->tol_dx; /* the round-off floor of the reference */
    np.definiteness = v / 2 == 0 ? CB_DEF_NONE : CB_DEF_DROP;
    np.line_search = v % 2;
    cb_solver_params sp = cb_solver_params_default();
    st = cb_integrator_alloc("newton", s, &p, &np, "cholmod", &sp, &its[v]);
  }
  for (int step = 0; st == CB_OK && step < nsteps; step++) {
    for (int v = 0; v < 4; v++) {
      memcpy(xt, w.x, n3 * sizeof(double));
      memcpy(vt, w.v, n3 * sizeof(double));
      log.n = 0;
      log.def = v / 2 == 0 ? 1 : 3;
      cb_step_stats ss;
      int sst = cb_integrator_step(its[v], xt, vt, &ss);
      order_rows(csv, s, label, dt, v / 2 == 0 ? "none" : "drop", v % 2, step, &log, sst, ss.newton_iters);
    }
    log.n = 0;
    cb_reference_stats rs;
    int rst = cb_reference_advance(ref, w.x, w.v, &rs); /* logged; then the next state of the trajectory */
    order_rows(csv, s, label, dt, "exact_or_shift", 1, step, &log, rst, rs.iters);
  }
  for (int v = 0; v < 4; v++) cb_integrator_free(its[v]);
  free(xt);
  free(vt);
  state_free(&w);
  cb_reference_free(ref);
  return st;
}
