/* nonlinear, P1: pd (10 iterations) against the fastest converging Newton and Baraff-Witkin on
 * 81^2 and its stiff variant (and, as Liu 2017's set-up, L-BFGS's 10 iterations), and the time pd and
 * Newton need to reach step error and relative objective error 1e-2 and 1e-3 and relative |grad F| 1e-3
 * and 1e-5 (issue 31 §2). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "nonlinear.h"

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
    /* Liu, Bouaziz and Kavan 2017's set-up: 10 L-BFGS iterations a frame (against Baraff-Witkin's one Newton
       iteration a frame); a labelled row of the report, not part of P1's verdict */
    {"lbfgs10", {"integrator.method=lbfgs", "integrator.iters=10", "integrator.tol=0", NULL}, {NULL}},
    {"newton_exact",
     {NEWTON_EXACT, "integrator.max_iters=50", "integrator.tol=1e-8", NULL},
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
    {"newton_exact",
     "integrator.max_iters",
     {NEWTON_EXACT, "integrator.tol=1e-8", NULL},
     {NEWTON_DROP_LS, "integrator.tol=1e-8", NULL},
     50,
     50},
};
enum { NP1F = sizeof P1F / sizeof P1F[0] };
/* The measures (issue 31 §2): the step error |x - x*|_M/|x* - x0|_M (P1's own), the relative objective error
 * (F - F*)/(F(xhat) - F*), each at 1e-2 and 1e-3, and relative |grad F| at 1e-3 and 1e-5; rows per measure. */
enum { PM_STEP, PM_OBJ, PM_GRAD, NPM };
static const char *const P1_MEASURE[NPM] = {"step_error", "obj_error", "rel_grad"};
static const double P1_TOLS[NPM][2] = {{1e-2, 1e-3}, {1e-2, 1e-3}, {1e-3, 1e-5}};
enum { NP1T = 2 };

typedef struct {
  cb_step_state *S;
  int n, cap;
  double *err[NPM]; /* per iteration, per measure */
} err_trace;

static void record_error(void *ctx, int event, const cb_newton_event *ev) {
  err_trace *t = ctx;
  if (event == CB_NEWTON_GRADIENT && ev->iter < t->cap) {
    t->err[PM_STEP][ev->iter] = cb_step_error(t->S->s, ev->x, t->S->xstar, t->S->x0);
    t->err[PM_OBJ][ev->iter] = t->S->Fhat != t->S->Fstar ? (ev->F - t->S->Fstar) / (t->S->Fhat - t->S->Fstar) : NAN;
    t->err[PM_GRAD][ev->iter] = ev->rel_grad; /* both families start at xhat: |grad F|/|grad F(xhat)| */
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
int nl_p1_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = nl_scene_of(p->p1[i / p->p1_states]);
  int frame = 5 * (int)(i % p->p1_states + 1);
  cb_step_state S;
  int st = nl_state(p->e, d, frame, &S);
  if (st) return st;
  enum { NJ = NP1M + NP1F * NPM * NP1T };
  cb_step_result r[NJ];
  const char *const *sets[NJ], *const *fb[NJ];
  static const char *fsets[NJ][8], *ffb[NJ][8];
  static char fbuf[NJ][2][64];
  int nj = 0, hit[NP1F][NPM][NP1T], job[NP1F][NPM][NP1T], cap[NP1F];
  for (int m = 0; m < NP1M; m++, nj++) {
    sets[nj] = P1M[m].sets;
    fb[nj] = P1M[m].fallback[0] ? P1M[m].fallback : NULL;
  }
  for (int f = 0; st == CB_OK && f < NP1F; f++) { /* trace each family's step error */
    cap[f] = p->smoke ? 20 : p->quick ? P1F[f].cap_q : P1F[f].cap;
    err_trace t = {&S, 0, cap[f] + 1, {NULL}};
    int oom = 0;
    for (int me = 0; me < NPM; me++) oom |= !(t.err[me] = calloc((size_t)cap[f] + 1, sizeof(double)));
    if (oom) {
      for (int me = 0; me < NPM; me++) free(t.err[me]);
      st = cb_fail_status(CB_ENOMEM, "out of memory");
      break;
    }
    const char *ts[8], *tf[8];
    char b1[64], b2[64];
    with_iters(P1F[f].sets, P1F[f].iters_key, cap[f], b1, sizeof b1, ts);
    if (P1F[f].fallback[0]) with_iters(P1F[f].fallback, P1F[f].iters_key, cap[f], b2, sizeof b2, tf);
    cb_config c, cf;
    st = cb_step_config(&S, ts, &c);
    if (st == CB_OK && P1F[f].fallback[0]) st = cb_step_config(&S, tf, &cf);
    cb_step_result tr;
    double w;
    if (st == CB_OK) st = cb_step_fallback(&S, &c, P1F[f].fallback[0] ? &cf : NULL, record_error, &t, &tr, &w);
    if (st == CB_OK && t.n > tr.iters + 1) t.n = tr.iters + 1; /* a fallback's trace replaced the first run's */
    for (int mq = 0; mq < NPM * NP1T; mq++) hit[f][mq / NP1T][mq % NP1T] = job[f][mq / NP1T][mq % NP1T] = -1;
    for (int mq = 0; st == CB_OK && mq < NPM * NP1T; mq++) {
      int me = mq / NP1T, q = mq % NP1T, *h = &hit[f][me][q];
      for (int k = 1; k < t.n && *h < 0; k++) /* |obj|: it can dip a round-off below 0 (x* is converged to a tol) */
        if (fabs(t.err[me][k]) <= P1_TOLS[me][q]) *h = k;
      if (*h < 0) continue;
      with_iters(P1F[f].sets, P1F[f].iters_key, *h, fbuf[nj][0], sizeof fbuf[nj][0], fsets[nj]);
      sets[nj] = fsets[nj];
      fb[nj] = NULL;
      if (P1F[f].fallback[0]) {
        with_iters(P1F[f].fallback, P1F[f].iters_key, *h, fbuf[nj][1], sizeof fbuf[nj][1], ffb[nj]);
        fb[nj] = ffb[nj];
      }
      job[f][me][q] = nj++;
    }
    for (int me = 0; me < NPM; me++) free(t.err[me]);
  }
  if (st == CB_OK)
    st = cb_step_time_group(p->e->quick, &S, sets, fb, nj, r); /* interleaved: pd10, newton_exact, ..., pd10, ... */
  double k = S.s->def.stretch_k, na = cb_csv_na();
  int n = S.s->mesh.grid_n;
  for (int m = 0; st == CB_OK && m < NP1M; m++) {
    cb_csv_printf(out[T_P1], "%s,%d,%.17g,%s,%d,%d,", d->label, n, k, P1M[m].label, frame, r[m].iters);
    cb_timing_csv_repeats(out[T_P1], &r[m].wall);
    cb_csv_printf(out[T_P1], ",%.6f,%.17g,%.17g,%.17g,%d,%s,%s\n", r[m].alloc_ms, r[m].error, r[m].obj_error,
                  r[m].rel_grad, r[m].fallback, cb_global_path_name(r[m].global_path), cb_status_name(r[m].status));
  }
  for (int f = 0; st == CB_OK && f < NP1F; f++)
    for (int mq = 0; mq < NPM * NP1T; mq++) {
      int me = mq / NP1T, q = mq % NP1T, j = job[f][me][q];
      /* a tolerance not reached within the cap: no iteration count, time or error, status cut_off */
      cb_csv_printf(out[T_P1_ERROR], "%s,%d,%.17g,%s,%d,%s,%g,%d,%.17g,", d->label, n, k, P1F[f].label, frame,
                    P1_MEASURE[me], P1_TOLS[me][q], cap[f], j >= 0 ? (double)hit[f][me][q] : na);
      cb_timing_csv_repeats(out[T_P1_ERROR], j >= 0 ? &r[j].wall : NULL);
      cb_csv_printf(out[T_P1_ERROR], ",%.17g,%.17g,%.17g,%.17g,%s,%s\n", j >= 0 ? r[j].error : na,
                    j >= 0 ? r[j].obj_error : na, j >= 0 ? r[j].rel_grad : na, j >= 0 ? (double)r[j].fallback : na,
                    j >= 0 ? cb_global_path_name(r[j].global_path) : "none",
                    j >= 0 ? cb_status_name(r[j].status) : "cut_off");
    }
  cb_step_state_free(&S);
  return st;
}

/* cost hint: a P1 cell ~1.6 ms per vertex (two converged Newtons and the step-error traces); the later start
 * state a little more (two --quick runs: 9-21 s a cell on 81^2, varying by 2x from run to run) */
double nl_p1_cost(long i, void *ctx) {
  const plan *p = ctx;
  return 1.6 * (1.0 + 0.15 * (double)(i % p->p1_states)) * p->nv[p->p1[i / p->p1_states]];
}
