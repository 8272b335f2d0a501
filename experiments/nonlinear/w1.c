/* nonlinear, W1: iterations and wall time to relative |grad F| 1e-2 and 1e-4, plain against
 * Chebyshev-accelerated (jacobi-nl, pd), each traced run rerun with a larger cap until it reaches 1e-4. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "nonlinear.h"

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
/* the pairs: W1M[PAIR0[q] .. PAIR0[q + 1]) share a pair label; a cell is one (scene, pair) */
static const int PAIR0[NL_W1_PAIRS + 1] = {0, 3, NW1M};
enum { W1_CAP0 = 500 }; /* the first traced run's iterations */

/* The largest iteration cap of W1 method m on an n^2 grid: a traced run that ends above the tolerance is
 * rerun with a larger cap (w1_cell) up to this one. pd at 128^2 (a 50k-DOF back-solve an iteration, ~10^4
 * iterations to 1e-4) is held to 2000 to keep the full run near 3 minutes, and so is pd in --quick
 * (which leaves 64^2's pd pair undecided there: its plain run needs 3000-4000 iterations and was most of
 * the quick run's time); a pair cut off there is undecided (status cut_off), never a failure. */
static int w1_capmax(int quick, int m, int n) {
  if (W1M[m].pair[0] == 'p')
    return n >= 128 || quick ? 2000 : 10000; /* --quick: 64^2's plain pd (~3000-4000) cut off */
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
  for (int k = 0; W1M[m].sets[k]; k++)
    out[n++] = rho && !strcmp(W1M[m].sets[k], "integrator.rho=auto") ? rho : W1M[m].sets[k];
  snprintf(buf, nbuf, "integrator.iters=%d", K);
  out[n++] = buf;
  out[n] = NULL;
}

/* Cell i: scene w1[i / NL_W1_PAIRS], pair i % NL_W1_PAIRS: its start state, then every W1 method of the pair from it (a
 * traced run for the iterations to each tolerance, rerun with a larger cap until the tighter one is reached or the cap
 * is w1_capmax), then the steps of exactly that many iterations of every method, timed together (interleaved: the plain
 * and the accelerated iteration of a pair are compared). An auto rho is estimated in the first traced run (its time is
 * setup_ms); every later run of the method is given that estimate as a number, the same iteration. */
int nl_w1_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = nl_scene_of(p->w1[i / NL_W1_PAIRS]);
  const int m0 = PAIR0[i % NL_W1_PAIRS], m1 = PAIR0[i % NL_W1_PAIRS + 1];
  static const double TOLS[] = {1e-2, 1e-4};
  cb_step_state S;
  int st = nl_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  int n = S.s->mesh.grid_n, hit[NW1M][2], kmax[NW1M], job[NW1M][2], njobs = 0;
  double final_rel[NW1M], setup_ms[NW1M];
  cb_step_result r[NW1M], rt[2 * NW1M];
  static char iters[2 * NW1M + NW1M][64], rhos[NW1M][64];
  static const char *sets[2 * NW1M + NW1M][6], *const *jobs[2 * NW1M];
  for (int m = m0; st == CB_OK && m < m1; m++) {
    int capmax = w1_capmax(p->quick, m, n);
    trace_t t = {0, 0, NULL};
    const char *rho = NULL;
    setup_ms[m] = cb_csv_na();
    for (kmax[m] = W1_CAP0 < capmax ? W1_CAP0 : capmax;; kmax[m] = w1_next_cap(&t, kmax[m], capmax, TOLS[1])) {
      free(t.rel);
      t = (trace_t){0, kmax[m] + 1, calloc((size_t)kmax[m] + 1, sizeof(double))};
      if (!t.rel) {
        st = cb_fail_status(CB_ENOMEM, "out of memory");
        break;
      }
      w1_sets(m, rho, kmax[m], iters[m], sizeof iters[m], sets[m]);
      if ((st = cb_step_repeat(&S, sets[m], record, &t, &r[m]))) break;
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
  if (st == CB_OK) st = cb_step_time_group(p->e->quick, &S, jobs, NULL, njobs, rt);
  for (int m = m0; st == CB_OK && m < m1; m++)
    for (int q = 0; q < 2; q++) {
      int j = job[m][q];
      /* a tolerance never reached (hit < 0, status cut_off: not reached at the largest cap; hit = 0: reached
       * before any iteration) has no iteration count or time; a method without Chebyshev acceleration has no
       * rho, and one with a given rho no estimate (setup_ms) */
      double na = cb_csv_na(), rho = strstr(W1M[m].label, "chebyshev") ? r[m].rho : na;
      cb_csv_printf(out[T_W1], "%s,%d,%s,%s,%.17g,%d,%g,%.17g,", d->label, n, W1M[m].label, W1M[m].pair, rho, kmax[m],
                    TOLS[q], hit[m][q] >= 0 ? (double)hit[m][q] : na);
      cb_timing_csv_repeats(out[T_W1], j >= 0 ? &rt[j].wall : NULL);
      cb_csv_printf(out[T_W1], ",%.6f,%.6f,%.17g,%s\n", setup_ms[m], r[m].alloc_ms, final_rel[m],
                    hit[m][q] < 0 ? "cut_off" : cb_status_name(r[m].status));
    }
  cb_step_state_free(&S);
  return st;
}

/* cost hint: the pair's traced iterations (two first runs of W1_CAP0, the plain method's ~1/4 of its cap),
 * ms per iteration and vertex 4.5e-5 for the Jacobi pair and 1e-3 for pd (a back-solve each), growing like
 * vertices^1.45 (measured on a --quick run: 0.19 and 1.3 s at 21^2, 4.7 and 32 s at 64^2) */
double nl_w1_cost(long i, void *ctx) {
  const plan *p = ctx;
  int sc = p->w1[i / NL_W1_PAIRS], q = (int)(i % NL_W1_PAIRS);
  double it = 0;
  for (int m = PAIR0[q]; m < PAIR0[q + 1]; m++)
    it += 2 * W1_CAP0 + (m == 0 || m == 3 ? w1_capmax(p->quick, m, p->mesh_n[sc]) / 4 : 0);
  return (q ? 1e-3 : 4.5e-5) * it * p->nv[sc] * pow(p->nv[sc] / 441.0, 0.45);
}
