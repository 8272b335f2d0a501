/* field, the main figure: from each scene's start state, one step of every method at 1, 2, 4, ...
 * iterations (Newton: max_iters; XPBD 1 x n: iterations, n x 1: substeps), its step error against the
 * converged step and its wall time per frame; each method's error-time front (the points of that method
 * no other of its points beats in both) and the scene's front over all points (pareto.h). A method that
 * refuses the scene (xpbd: the drape's penalty sphere and dihedral bending) gets one row, status
 * unsupported. XPBD's gap: its fixed point (1 x n at the largest n) against converged Newton. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "field.h"
#include "pareto.h"

typedef struct {
  const char *label, *family;
  const char *sets[8];
  const char *key;         /* the key set to 1, 2, 4, ...; NULL: the sets fix the step */
  int kmax, kmax_q;        /* the largest count, full run and --quick */
  const char *fallback[8]; /* rerun a non-SPD step with these (Newton's exact Hessian -> drop) */
} fr_method;
#define NEWTON_EXACT \
  "integrator.method=newton", "integrator.definiteness=none", "integrator.line_search=1", "integrator.tol=1e-10"
#define NEWTON_DROP \
  "integrator.method=newton", "integrator.definiteness=drop", "integrator.line_search=1", "integrator.tol=1e-10"
static const fr_method FM[] = {
    {"newton_exact", "newton", {NEWTON_EXACT, NULL}, "integrator.max_iters", 16, 8, {NEWTON_DROP, NULL}},
    {"newton_drop", "newton", {NEWTON_DROP, NULL}, "integrator.max_iters", 32, 16, {NULL}},
    {"baraff_witkin", "newton", {"integrator.method=newton", "integrator.max_iters=1", NULL}, NULL, 0, 0, {NULL}},
    {"jacobi-nl", "jacobi-nl", {"integrator.method=jacobi-nl", NULL}, "integrator.iters", 256, 32, {NULL}},
    {"chebyshev-nl auto",
     "jacobi-nl",
     {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL},
     "integrator.iters",
     256,
     32,
     {NULL}},
    {"pd", "pd", {"integrator.method=pd", NULL}, "integrator.iters", 256, 32, {NULL}},
    {"pd-chebyshev auto",
     "pd",
     {"integrator.method=pd-chebyshev", "integrator.rho=auto", NULL},
     "integrator.iters",
     256,
     32,
     {NULL}},
    {"lbfgs", "lbfgs", {"integrator.method=lbfgs", "integrator.tol=1e-10", NULL}, "integrator.iters", 128, 32, {NULL}},
    {"vbd", "vbd", {"integrator.method=vbd", NULL}, "integrator.iters", 256, 32, {NULL}},
    {"vbd line search",
     "vbd",
     {"integrator.method=vbd", "integrator.vbd_line_search=1", NULL},
     "integrator.iters",
     256,
     32,
     {NULL}},
    {"vbd-chebyshev auto",
     "vbd",
     {"integrator.method=vbd-chebyshev", "integrator.rho=auto", NULL},
     "integrator.iters",
     256,
     32,
     {NULL}},
    {"xpbd 1xn",
     "xpbd",
     {"integrator.method=xpbd", "integrator.substeps=1", NULL},
     "integrator.iters",
     512,
     64,
     {NULL}},
    {"xpbd nx1", "xpbd", {"integrator.method=xpbd", "integrator.iters=1", NULL}, "integrator.substeps", 64, 16, {NULL}},
};
enum { NFM = sizeof FM / sizeof FM[0] };
enum { MAXPTS = 512 };
enum { M_NEWTON_EXACT = 0, M_NEWTON_DROP = 1, M_XPBD_1XN = 11 };
#define ERR_FLOOR 1e-10 /* step error at the reference's own accuracy (its tolerance): the ladder stops */
#define ERR_BLOWN 10.0  /* step error of a blown-up step (10 |x* - x0|_M away): the ladder stops */

static int kmax_of(const fd_plan *p, int m) {
  return p->smoke ? (FM[m].kmax ? 2 : 0) : p->quick ? FM[m].kmax_q : FM[m].kmax;
}

typedef struct {
  int m, K;
  double wall, setup, err, rel, rho;
  int status, supported;
} point;

int fd_front_cell(long i, void *ctx, FILE *const *out) {
  const fd_plan *p = ctx;
  const cb_scene_decl *d = p->decl[p->front[i]];
  cb_step_state S;
  int st = fd_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  static fd_rho_cache rc; /* the auto rho estimates on this state, shared with the tolerance runs */
  fd_rho_cache_clear(&rc);
  static point pt[MAXPTS];
  static cb_config fbc;
  int np = 0;
  for (int m = 0; st == CB_OK && m < NFM; m++) {
    char why[512] = "";
    int ok = fd_supported(&S, FM[m].sets, why, sizeof why);
    if (ok < 0) {
      st = ok;
      break;
    }
    int kmax = kmax_of(p, m);
    if (!ok) {
      pt[np++] = (point){m, 0, NAN, NAN, INFINITY, NAN, NAN, CB_EINVAL, 0};
      continue;
    }
    const char *ms[16];
    char rb[64];
    double est_ms;
    if ((st = fd_fix_rho(&S, &rc, FM[m].sets, ms, rb, sizeof rb, &est_ms))) break;
    for (int K = FM[m].key ? 1 : 0; st == CB_OK && K <= kmax && np < MAXPTS; K = K ? 2 * K : 1) {
      const char *sets[16], *fb[16];
      char b1[64], b2[64];
      if (FM[m].key) fd_with(ms, FM[m].key, K, b1, sizeof b1, sets);
      else memcpy(sets, FM[m].sets, sizeof FM[m].sets);
      cb_step_result r;
      st = cb_step_repeat(&S, sets, NULL, NULL, &r);
      if (st == CB_OK && r.status == CB_NOT_SPD && FM[m].fallback[0]) { /* exact Hessian not SPD: drop for that step */
        fd_with(FM[m].fallback, FM[m].key, K, b2, sizeof b2, fb);
        double w;
        cb_step_result r2;
        st = cb_step_config(&S, fb, &fbc);
        if (st == CB_OK) st = cb_step_fallback(&S, &fbc, NULL, NULL, NULL, &r2, &w);
        if (st == CB_OK) {
          r2.wall_ms = w + r.wall_ms;
          r = r2;
        }
      }
      if (st) break;
      int bad = cb_status_is_fatal(r.status) && r.status != CB_LS_FAILED;
      pt[np++] = (point){m,
                         FM[m].key ? K : 1,
                         r.wall_ms,
                         r.setup_ms + est_ms,
                         bad || !isfinite(r.error) ? INFINITY : r.error,
                         r.rel_grad,
                         r.rho,
                         r.status,
                         1};
      if (!FM[m].key) break;
      /* the ladder ends where more iterations cannot move the point: Newton converged (a larger
       * max_iters repeats the same iterations), or the step at the reference's floor (ERR_FLOOR), or
       * blown up (error above ERR_BLOWN: ten times as far from x* as the start state) */
      const point *q = &pt[np - 1];
      if ((FM[m].family[0] == 'n' && q->status == CB_OK) || q->err <= ERR_FLOOR || !(q->err <= ERR_BLOWN)) break;
    }
  }
  /* the fronts: per method over its points, and over the scene's points */
  static double cost[MAXPTS], err[MAXPTS];
  static int onm[MAXPTS], ons[MAXPTS];
  for (int k = 0; k < np; k++) {
    cost[k] = pt[k].supported ? pt[k].wall : NAN;
    err[k] = pt[k].err;
  }
  cb_pareto_front(np, cost, err, ons);
  for (int a = 0; a < np;) {
    int b = a;
    while (b < np && pt[b].m == pt[a].m) b++;
    cb_pareto_front(b - a, cost + a, err + a, onm + a);
    a = b;
  }
  double na = cb_csv_na();
  long nv = S.s->mesh.nv;
  for (int k = 0; st == CB_OK && k < np; k++) {
    const fr_method *f = &FM[pt[k].m];
    int sub = !strcmp(f->label, "xpbd nx1") ? pt[k].K : 1, it = !strcmp(f->label, "xpbd nx1") ? 1 : pt[k].K;
    if (!pt[k].supported) {
      cb_csv_printf(out[T_FRONT], "%s,%ld,%s,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,0,0,unsupported\n", d->label,
                    nv, f->label, f->family, na, na, na, na, na, na, na);
      continue;
    }
    double rho = strstr(f->label, "chebyshev") ? pt[k].rho : na; /* no rho without Chebyshev */
    cb_csv_printf(out[T_FRONT], "%s,%ld,%s,%s,%d,%d,%.17g,%.6f,%.6f,%.17g,%.17g,%d,%d,%s\n", d->label, nv, f->label,
                  f->family, it, sub, rho, pt[k].wall, pt[k].setup, pt[k].err, pt[k].rel, onm[k], ons[k],
                  cb_status_name(pt[k].status));
  }
  /* XPBD's gap: its last two 1 x n points (n and n/2: a fixed point when they agree) against the
   * converged Newton step (the Newton variant with the smaller |grad F| at its largest count) */
  int x1 = -1, x0 = -1, nw = -1;
  for (int k = 0; k < np; k++) {
    if (pt[k].m == M_XPBD_1XN && pt[k].supported) {
      x0 = x1;
      x1 = k;
    }
    if ((pt[k].m == M_NEWTON_EXACT || pt[k].m == M_NEWTON_DROP) && pt[k].supported && isfinite(pt[k].err) &&
        (k + 1 == np || pt[k + 1].m != pt[k].m) && (nw < 0 || pt[k].rel < pt[nw].rel))
      nw = k;
  }
  if (st == CB_OK) {
    if (x1 < 0)
      cb_csv_printf(out[T_GAP], "%s,%ld,xpbd 1xn,%.17g,%.17g,%.17g,%.17g,%.17g,%s,%.17g,%.17g,unsupported\n", d->label,
                    nv, na, na, na, na, na, nw >= 0 ? FM[pt[nw].m].label : "", nw >= 0 ? pt[nw].rel : na,
                    nw >= 0 ? pt[nw].err : na);
    else
      cb_csv_printf(out[T_GAP], "%s,%ld,xpbd 1xn,%d,%.17g,%.17g,%.17g,%.17g,%s,%.17g,%.17g,%s\n", d->label, nv,
                    pt[x1].K, pt[x1].rel, x0 >= 0 ? pt[x0].rel : na, pt[x1].err, x0 >= 0 ? pt[x0].err : na,
                    nw >= 0 ? FM[pt[nw].m].label : "", nw >= 0 ? pt[nw].rel : na, nw >= 0 ? pt[nw].err : na,
                    cb_status_name(pt[x1].status));
  }
  /* Q1 and V1's speed on the same state, with the same rho estimates (tol.c) */
  int tol = 0;
  for (int k = 0; k < p->ntol; k++) tol |= p->tol[k] == p->front[i];
  if (st == CB_OK && tol) st = fd_tol_scene(p, d, &S, &rc, out);
  cb_step_state_free(&S);
  return st;
}

/* cost hint: ~2 kmax iterations per method (1 + 2 + ... + kmax) at ~3e-4 ms per vertex each, repeated
 * to 30 ms, plus a second of Newton */
double fd_front_cost(long i, void *ctx) {
  const fd_plan *p = ctx;
  double it = 0, tol = 0;
  for (int m = 0; m < NFM; m++) it += 2.0 * kmax_of(p, m);
  for (int k = 0; k < p->ntol; k++)
    if (p->tol[k] == p->front[i]) tol = fd_tol_cost(p, p->front[i]);
  return 1000.0 + 3e-4 * it * p->nv[p->front[i]] + tol;
}
