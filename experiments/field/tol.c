/* field, Q1 and V1's speed: from each scene's start state, every minimiser's relative |grad F| per
 * iteration (|grad F(x_k)| / |grad F(xhat)|, the same denominator for every method: fd_grad_hat), traced
 * once with a hook up to a cap; the first iteration that reaches 1e-3 and 1e-5; then a step of exactly
 * that many iterations of every method that reached it, timed together in interleaved rounds (no hook:
 * the hook's gradient evaluations are not the method's cost). A tolerance not reached within the cap
 * is cut_off (no time). The trace table keeps the relative |grad F| and (F - F(x*)) / |F(x*)| per
 * iteration with the traced run's elapsed time (which includes the hook's gradients). */
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
static const double TOLS[] = {1e-3, 1e-5};
/* a step to a tolerance that takes a second or more is timed once (in the first interleaved round):
 * repeats of it add nothing a median needs at that length, and they were half of the cell's time */
#define ONCE_MS 1000.0
enum { NTOL = sizeof TOLS / sizeof TOLS[0] };

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
  double *rel, *F, *ms;
} trace_t;

static void record(void *ctx, int event, const cb_newton_event *ev) {
  trace_t *t = ctx;
  if (event != CB_NEWTON_GRADIENT || ev->iter < 0 || ev->iter >= t->cap) return;
  if (ev->iter == 0) t->t0 = cb_now_ms();
  t->rel[ev->iter] = ev->grad_norm / t->ghat;
  t->F[ev->iter] = ev->F;
  t->ms[ev->iter] = cb_now_ms() - t->t0;
  if (ev->iter + 1 > t->n) t->n = ev->iter + 1;
}

int fd_tol_scene(const fd_plan *p, const cb_scene_decl *d, cb_step_state *S, fd_rho_cache *rc, FILE *const *out) {
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
  int hit[NTM][NTOL], cap[NTM], ok[NTM];
  double final_rel[NTM], alloc_ms[NTM];
  static char buf[NTM][NTOL][2][64];
  static const char *js[NTM][NTOL][16], *jf[NTM][NTOL][16], *msets[NTM][16];
  static char rbuf[NTM][64];
  for (int m = 0; st == CB_OK && m < NTM; m++) {
    char why[512];
    for (int q = 0; q < NTOL; q++) hit[m][q] = -1;
    final_rel[m] = alloc_ms[m] = cb_csv_na();
    cap[m] = cap_of(p, m);
    ok[m] = fd_supported(S, TM[m].sets, why, sizeof why);
    if (ok[m] < 0) {
      st = ok[m];
      break;
    }
    if (!ok[m]) continue;
    trace_t t = {0,
                 cap[m] + 1,
                 ghat,
                 0,
                 calloc((size_t)cap[m] + 1, sizeof(double)),
                 calloc((size_t)cap[m] + 1, sizeof(double)),
                 calloc((size_t)cap[m] + 1, sizeof(double))};
    if (!t.rel || !t.F || !t.ms) st = cb_fail_status(CB_ENOMEM, "out of memory");
    const char *ts[16], *tf[16];
    char b1[64], b2[64];
    static cb_config c, cf;
    double est_ms;
    if (st == CB_OK)
      st = fd_fix_rho(S, rc, TM[m].sets, msets[m], rbuf[m], sizeof rbuf[m], &est_ms); /* an auto rho: estimated once */
    if (st) {
      free(t.rel);
      free(t.F);
      free(t.ms);
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
          cb_csv_printf(out[T_TOL_TRACE], "%s,%s,%d,%.17g,%.17g,%.6f\n", d->label, TM[m].label, k, t.rel[k],
                        (t.F[k] - Fstar) / fabs(Fstar), t.ms[k]);
      for (int q = 0; q < NTOL; q++) {
        for (int k = 1; k < t.n && hit[m][q] < 0; k++)
          if (t.rel[k] <= TOLS[q] && isfinite(t.rel[k])) hit[m][q] = k;
        if (hit[m][q] < 0) continue;
        fd_with(msets[m], TM[m].key, hit[m][q], buf[m][q][0], sizeof buf[m][q][0], js[m][q]);
        if (TM[m].fallback[0])
          fd_with(TM[m].fallback, TM[m].key, hit[m][q], buf[m][q][1], sizeof buf[m][q][1], jf[m][q]);
      }
    }
    free(t.rel);
    free(t.F);
    free(t.ms);
  }
  /* the timed steps: per tolerance, every method that reached it, interleaved */
  for (int q = 0; st == CB_OK && q < NTOL; q++) {
    const char *const *sets[NTM], *const *fb[NTM];
    int job[NTM], nj = 0;
    for (int m = 0; m < NTM; m++) {
      job[m] = -1;
      if (hit[m][q] < 0) continue;
      sets[nj] = js[m][q];
      fb[nj] = TM[m].fallback[0] ? jf[m][q] : NULL;
      job[m] = nj++;
    }
    cb_step_result r[NTM];
    if (nj) st = cb_step_time_group_ex(p->quick, ONCE_MS, S, sets, fb, nj, r, NULL);
    double na = cb_csv_na();
    for (int m = 0; st == CB_OK && m < NTM; m++) {
      int j = job[m];
      cb_csv_printf(out[T_TOL], "%s,%ld,%s,%s,%g,%d,%.17g,", d->label, (long)S->s->mesh.nv, TM[m].label, TM[m].family,
                    TOLS[q], cap[m], j >= 0 ? (double)hit[m][q] : na);
      cb_timing_csv_repeats(out[T_TOL], j >= 0 ? &r[j].wall : NULL);
      cb_csv_printf(out[T_TOL], ",%.6f,%.17g,%.17g,%s\n", alloc_ms[m], final_rel[m],
                    j >= 0 ? (double)r[j].fallback : na,
                    !ok[m]   ? "unsupported"
                    : j >= 0 ? cb_status_name(r[j].status)
                             : "cut_off");
    }
  }
  return st;
}

/* cost hint: every method's traced cap (a gradient per iteration) and the timed steps, ~5e-4 ms per
 * vertex an iteration */
double fd_tol_cost(const fd_plan *p, int scene) {
  double it = 0;
  for (int m = 0; m < NTM; m++) it += 2.0 * cap_of(p, m);
  return 500.0 + 5e-4 * it * p->nv[scene];
}
