/* field, Q1 and V1's speed: from each scene's start state, every minimiser's relative |grad F| per
 * iteration (|grad F(x_k)| / |grad F(xhat)|, the same denominator for every method: fd_grad_hat), its
 * relative objective error (F(x_k) - F*) / (F(xhat) - F*) and its step error |x_k - x*|_M / |x* - x0|_M,
 * traced once with a hook up to a cap; per measure the first iteration that reaches each tolerance
 * (|grad F|: 1e-3, 1e-5; objective and step error: 1e-2, 1e-3; issue 31 §2); then a step of exactly that
 * many iterations of every method that reached it, timed together in interleaved rounds (no hook: the
 * hook's evaluations are not the method's cost). A tolerance not reached within the cap is cut_off (no
 * time). The trace table keeps the three measures and (F - F(x*)) / |F(x*)| per iteration with the traced
 * run's elapsed time (which includes the hook's work). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "field.h"

typedef struct {
  const char *label, *family;
  const char *sets[8], *fallback[8];
  const char *key;
  int newton;
  int stops; /* the method has integrator.tol: its traced run stops at TRACE_TOL (relative |grad F| from xhat) */
} tl_method;
/* The traced run of a method with its own stopping test (Newton, L-BFGS: |grad F| <= tol |grad F(xhat)|,
 * both start at xhat) stops at 1e-7, 100x below the last tolerance: what follows only repeats
 * iterations below every tolerance (Newton ran 30 iterations at 81^2, L-BFGS 1000, to 1e-12). */
#define TRACE_TOL_S "1e-7"
#define NEWTON_EXACT \
  "integrator.method=newton", "integrator.definiteness=none", "integrator.line_search=1", "integrator.tol=1e-12"
#define NEWTON_DROP \
  "integrator.method=newton", "integrator.definiteness=drop", "integrator.line_search=1", "integrator.tol=1e-12"
static const tl_method TM[] = {
    {"newton_exact", "newton", {NEWTON_EXACT, NULL}, {NEWTON_DROP, NULL}, "integrator.max_iters", 1, 1},
    {"newton_drop", "newton", {NEWTON_DROP, NULL}, {NULL}, "integrator.max_iters", 1, 1},
    {"lbfgs", "lbfgs", {"integrator.method=lbfgs", "integrator.tol=1e-12", NULL}, {NULL}, "integrator.iters", 0, 1},
    {"pd", "pd", {"integrator.method=pd", NULL}, {NULL}, "integrator.iters", 0, 0},
    {"pd-chebyshev auto",
     "pd",
     {"integrator.method=pd-chebyshev", "integrator.rho=auto", NULL},
     {NULL},
     "integrator.iters",
     0,
     0},
    {"vbd", "vbd", {"integrator.method=vbd", NULL}, {NULL}, "integrator.iters", 0, 0},
    {"vbd line search",
     "vbd",
     {"integrator.method=vbd", "integrator.vbd_line_search=1", NULL},
     {NULL},
     "integrator.iters",
     0,
     0},
    {"vbd-chebyshev auto",
     "vbd",
     {"integrator.method=vbd-chebyshev", "integrator.rho=auto", NULL},
     {NULL},
     "integrator.iters",
     0,
     0},
    {"jacobi-nl", "jacobi-nl", {"integrator.method=jacobi-nl", NULL}, {NULL}, "integrator.iters", 0, 0},
    {"chebyshev-nl auto",
     "jacobi-nl",
     {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL},
     {NULL},
     "integrator.iters",
     0,
     0},
};
enum { NTM = sizeof TM / sizeof TM[0] };
/* The measures (issue 31 §2) and their tolerances: relative |grad F| (|grad F(x_k)| / |grad F(xhat)|) at 1e-3
 * and 1e-5; the relative objective error (F(x_k) - F*) / (F(xhat) - F*) and the step error
 * |x_k - x*|_M / |x* - x0|_M (cb_step_error) at 1e-2 and 1e-3, the measures Liu et al. 2013 and 2017 judge
 * real-time accuracy by. Q1 is decided on the last two. */
enum { M_GRAD, M_OBJ, M_STEP, NMEAS };
static const char *const MEASURE[NMEAS] = {"rel_grad", "obj_error", "step_error"};
static const double TOLS[NMEAS][2] = {{1e-3, 1e-5}, {1e-2, 1e-3}, {1e-2, 1e-3}};
/* a step to a tolerance that takes a second or more is timed once (in the first interleaved round):
 * repeats of it add nothing a median needs at that length, and they were half of the cell's time */
#define ONCE_MS 1000.0
enum { NTOL = 2 };

/* appends one set to a NULL-terminated list (room for it: the lists hold 16) */
static void add_set(const char **sets, const char *set) {
  int n = 0;
  while (sets[n]) n++;
  sets[n] = set;
  sets[n + 1] = NULL;
}

static int cap_of(const fd_plan *p, int m) {
  return TM[m].newton ? (p->smoke ? 5 : 30) : p->smoke ? 10 : p->quick ? 100 : 1000;
}

typedef struct {
  int n, cap;
  double ghat, t0;
  double *rel, *F, *ms, *obj, *serr; /* per iteration: the three measures (rel, obj, serr), F, elapsed time */
  cb_step_state *S;
} trace_t;

static void record(void *ctx, int event, const cb_newton_event *ev) {
  trace_t *t = ctx;
  if (event != CB_NEWTON_GRADIENT || ev->iter < 0 || ev->iter >= t->cap) return;
  if (ev->iter == 0) t->t0 = cb_now_ms();
  t->rel[ev->iter] = ev->grad_norm / t->ghat;
  t->F[ev->iter] = ev->F;
  t->obj[ev->iter] = t->S->Fhat != t->S->Fstar ? (ev->F - t->S->Fstar) / (t->S->Fhat - t->S->Fstar) : NAN;
  t->serr[ev->iter] = ev->x ? cb_step_error(t->S->s, ev->x, t->S->xstar, t->S->x0) : NAN;
  t->ms[ev->iter] = cb_now_ms() - t->t0;
  if (ev->iter + 1 > t->n) t->n = ev->iter + 1;
}

static void trace_free(trace_t *t) {
  free(t->rel);
  free(t->F);
  free(t->ms);
  free(t->obj);
  free(t->serr);
}

/* Q1's methods (the size sweep runs these only) */
static int q1_method(int m) {
  return !strcmp(TM[m].family, "newton") || !strcmp(TM[m].family, "lbfgs") || !strcmp(TM[m].family, "pd");
}

static int tol_scene(const fd_plan *p, const cb_scene_decl *d, cb_step_state *S, fd_rho_cache *rc, FILE *const *out,
                     int q1only) {
  int st = CB_OK;
  double ghat = fd_grad_hat(S), Fstar = NAN;
  { /* F(x*) */
    cb_objective o;
    if ((st = cb_objective_init(&o, S->s)) == CB_OK) {
      cb_objective_begin(&o, S->x0, S->v0, S->c.dt);
      Fstar = cb_objective_eval(&o, S->xstar, NULL, NULL);
      cb_objective_free(&o);
    }
  }
  int hit[NTM][NMEAS][NTOL], cap[NTM], ok[NTM];
  double final_rel[NTM], alloc_ms[NTM];
  static char buf[NTM][NMEAS][NTOL][2][64];
  static const char *js[NTM][NMEAS][NTOL][16], *jf[NTM][NMEAS][NTOL][16], *msets[NTM][16];
  static char rbuf[NTM][64];
  for (int m = 0; st == CB_OK && m < NTM; m++) {
    char why[512];
    for (int me = 0; me < NMEAS; me++)
      for (int q = 0; q < NTOL; q++) hit[m][me][q] = -1;
    final_rel[m] = alloc_ms[m] = cb_csv_na();
    cap[m] = cap_of(p, m);
    if (q1only && !q1_method(m)) {
      ok[m] = 0;
      continue;
    }
    ok[m] = fd_supported(S, TM[m].sets, why, sizeof why);
    if (ok[m] < 0) {
      st = ok[m];
      break;
    }
    if (!ok[m]) continue;
    size_t tn = (size_t)cap[m] + 1;
    trace_t t = {0,
                 cap[m] + 1,
                 ghat,
                 0,
                 calloc(tn, sizeof(double)),
                 calloc(tn, sizeof(double)),
                 calloc(tn, sizeof(double)),
                 calloc(tn, sizeof(double)),
                 calloc(tn, sizeof(double)),
                 S};
    if (!t.rel || !t.F || !t.ms || !t.obj || !t.serr) st = cb_fail_status(CB_ENOMEM, "out of memory");
    const char *ts[16], *tf[16];
    char b1[64], b2[64];
    static cb_config c, cf;
    double est_ms;
    if (st == CB_OK)
      st = fd_fix_rho(S, rc, TM[m].sets, msets[m], rbuf[m], sizeof rbuf[m], &est_ms); /* an auto rho: estimated once */
    if (st) {
      trace_free(&t);
      break;
    }
    fd_with(msets[m], TM[m].key, cap[m], b1, sizeof b1, ts);
    if (TM[m].fallback[0]) fd_with(TM[m].fallback, TM[m].key, cap[m], b2, sizeof b2, tf);
    if (TM[m].stops) { /* the traced run stops past the last tolerance (the timed steps keep the method's tol) */
      add_set(ts, "integrator.tol=" TRACE_TOL_S);
      if (TM[m].fallback[0]) add_set(tf, "integrator.tol=" TRACE_TOL_S);
    }
    if (st == CB_OK) st = cb_step_config(S, ts, &c);
    if (st == CB_OK && TM[m].fallback[0]) st = cb_step_config(S, tf, &cf);
    cb_step_result r;
    double w;
    if (st == CB_OK) st = cb_step_fallback(S, &c, TM[m].fallback[0] ? &cf : NULL, record, &t, &r, &w);
    if (st == CB_OK && r.fallback && t.n > r.iters + 1)
      t.n = r.iters + 1; /* the fallback's trace replaced the first run's */
    if (st == CB_OK) {
      alloc_ms[m] = r.alloc_ms;
      final_rel[m] = t.n ? t.rel[t.n - 1] : cb_csv_na();
      for (int k = 0; k < t.n; k++) /* every iteration up to 100, then ~50 per decade, and the last */
        if (k <= 100 || floor(50 * log10(k)) != floor(50 * log10(k - 1)) || k == t.n - 1)
          cb_csv_printf(out[T_TOL_TRACE], "%s,%s,%d,%.17g,%.17g,%.6f,%.17g,%.17g\n", d->label, TM[m].label, k, t.rel[k],
                        (t.F[k] - Fstar) / fabs(Fstar), t.ms[k], t.obj[k], t.serr[k]);
      const double *meas[NMEAS] = {t.rel, t.obj, t.serr};
      for (int me = 0; me < NMEAS; me++)
        for (int q = 0; q < NTOL; q++) {
          int *h = &hit[m][me][q];
          /* the first iteration at or below the tolerance (|obj| for the objective error: it can dip a round-off
             below 0 where x* is converged only to its own tolerance) */
          for (int k = 1; k < t.n && *h < 0; k++)
            if (fabs(meas[me][k]) <= TOLS[me][q] && isfinite(meas[me][k])) *h = k;
          if (*h < 0) continue;
          fd_with(msets[m], TM[m].key, *h, buf[m][me][q][0], sizeof buf[m][me][q][0], js[m][me][q]);
          if (TM[m].fallback[0])
            fd_with(TM[m].fallback, TM[m].key, *h, buf[m][me][q][1], sizeof buf[m][me][q][1], jf[m][me][q]);
        }
    }
    trace_free(&t);
  }
  /* the timed steps: per measure and tolerance, every method that reached it, interleaved */
  for (int mq = 0; st == CB_OK && mq < NMEAS * NTOL; mq++) {
    int me = mq / NTOL, q = mq % NTOL;
    const char *const *sets[NTM], *const *fb[NTM];
    int job[NTM], nj = 0;
    for (int m = 0; m < NTM; m++) {
      job[m] = -1;
      if (hit[m][me][q] < 0) continue;
      sets[nj] = js[m][me][q];
      fb[nj] = TM[m].fallback[0] ? jf[m][me][q] : NULL;
      job[m] = nj++;
    }
    cb_step_result r[NTM];
    if (nj) st = cb_step_time_group_ex(p->quick, ONCE_MS, S, sets, fb, nj, r, NULL);
    double na = cb_csv_na();
    for (int m = 0; st == CB_OK && m < NTM; m++) {
      int j = job[m];
      if (q1only && !q1_method(m)) continue; /* not run: no row */
      cb_csv_printf(out[T_TOL], "%s,%ld,%s,%s,%s,%g,%d,%.17g,", d->label, (long)S->s->mesh.nv, TM[m].label,
                    TM[m].family, MEASURE[me], TOLS[me][q], cap[m], j >= 0 ? (double)hit[m][me][q] : na);
      cb_timing_csv_repeats(out[T_TOL], j >= 0 ? &r[j].wall : NULL);
      cb_csv_printf(out[T_TOL], ",%.6f,%.17g,%.17g,%s,%s\n", alloc_ms[m], final_rel[m],
                    j >= 0 ? (double)r[j].fallback : na, j >= 0 ? cb_global_path_name(r[j].global_path) : "none",
                    !ok[m]   ? "unsupported"
                    : j >= 0 ? cb_status_name(r[j].status)
                             : "cut_off");
    }
  }
  return st;
}

int fd_tol_scene(const fd_plan *p, const cb_scene_decl *d, cb_step_state *S, fd_rho_cache *rc, FILE *const *out) {
  return tol_scene(p, d, S, rc, out, 0);
}

/* Q1's size sweep (issue 31 §3): cell i is scene p->tolsz[i], Q1's methods only, from its own start state. */
int fd_tolsize_cell(long i, void *ctx, FILE *const *out) {
  const fd_plan *p = ctx;
  const cb_scene_decl *d = p->decl[p->tolsz[i]];
  cb_step_state S;
  int st = fd_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  static fd_rho_cache rc;
  fd_rho_cache_clear(&rc);
  st = tol_scene(p, d, &S, &rc, out, 1);
  cb_step_state_free(&S);
  return st;
}

double fd_tolsize_cost(long i, void *ctx) {
  const fd_plan *p = ctx;
  return 2000.0 + fd_tol_cost(p, p->tolsz[i]);
}

/* cost hint: every method's traced cap (a gradient per iteration) and the timed steps, ~5e-4 ms per
 * vertex an iteration */
double fd_tol_cost(const fd_plan *p, int scene) {
  double it = 0;
  for (int m = 0; m < NTM; m++) it += 2.0 * cap_of(p, m);
  return 500.0 + 5e-4 * it * p->nv[scene];
}
