/* nonlinear, the error-time figure: one step of every implicit method at 1, 2, 4, ... iterations
 * from the same start state, step error and relative |grad F| against wall time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "nonlinear.h"

/* ---- error against run time: every implicit method on the same steps ---------- */

typedef struct {
  const char *label, *family;
  const char *sets[4];
  int kmax;    /* iteration counts 1, 2, 4, ..., kmax; 0: the sets fix it */
  double a, b; /* cost hint, ms per vertex: a once (Newton's steps, an auto rho's estimates), b per iteration */
} et_method;
static const et_method ETM[] = {
    {"newton K=1", "newton", {"integrator.method=newton", "integrator.max_iters=1", NULL}, 0, 0.1, 0},
    {"newton K=2", "newton", {"integrator.method=newton", "integrator.max_iters=2", NULL}, 0, 0.1, 0},
    {"newton K=3", "newton", {"integrator.method=newton", "integrator.max_iters=3", NULL}, 0, 0.1, 0},
    {"newton converged",
     "newton",
     {"integrator.method=newton", "integrator.max_iters=50", "integrator.tol=1e-8", NULL},
     0,
     0.1,
     0},
    {"jacobi-nl lab",
     "jacobi-nl",
     {"integrator.method=jacobi-nl", "integrator.diagonal=lab", NULL},
     4096,
     0.05,
     0.00019},
    {"jacobi-nl exact",
     "jacobi-nl",
     {"integrator.method=jacobi-nl", "integrator.diagonal=exact", NULL},
     1024,
     0.05,
     0.00062},
    {"chebyshev-nl 0.9",
     "chebyshev-nl",
     {"integrator.method=chebyshev-nl", "integrator.rho=0.9", NULL},
     4096,
     0.05,
     6e-05},
    {"chebyshev-nl 0.99",
     "chebyshev-nl",
     {"integrator.method=chebyshev-nl", "integrator.rho=0.99", NULL},
     4096,
     0.05,
     6e-05},
    {"chebyshev-nl 0.995",
     "chebyshev-nl",
     {"integrator.method=chebyshev-nl", "integrator.rho=0.995", NULL},
     4096,
     0.05,
     6e-05},
    {"chebyshev-nl auto",
     "chebyshev-nl",
     {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL},
     4096,
     0.2,
     6e-05},
    {"pd", "pd", {"integrator.method=pd", NULL}, 512, 0.05, 0.0013},
    {"pd-chebyshev auto", "pd", {"integrator.method=pd-chebyshev", "integrator.rho=auto", NULL}, 512, 14.5, 0.0013},
};
enum { NETM = sizeof ETM / sizeof ETM[0] };
_Static_assert((int)NETM == (int)NL_ET_METHODS, "nonlinear.h: NL_ET_METHODS");

/* the largest iteration count of error-time method m (0: fixed by its sets) */
static int et_kmax(const plan *p, int m) {
  int cap = p->smoke ? 4 : p->quick ? 256 : ETM[m].kmax;
  return ETM[m].kmax > cap ? cap : ETM[m].kmax;
}

/* Cell i: scene et[i / NETM], method i % NETM: the scene's start state, then the method at every iteration
 * count from it (the cells of one scene compute the same start state and reference step). */
int nl_et_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = nl_scene_of(p->et[i / NETM]);
  cb_step_state S;
  int st = nl_state(p->e, d, p->state_frames, &S);
  if (st) return st;
  const int m = (int)(i % NETM), kmax = et_kmax(p, m);
  for (int K = kmax ? 1 : 0; st == CB_OK && K <= kmax; K = K ? 2 * K : 1) {
    char iters[64];
    snprintf(iters, sizeof iters, "integrator.iters=%d", K);
    const char *sets[6];
    int ns = 0;
    for (int k = 0; ETM[m].sets[k]; k++) sets[ns++] = ETM[m].sets[k];
    if (kmax) sets[ns++] = iters;
    sets[ns] = NULL;
    cb_step_result r;
    if ((st = cb_step_repeat(&S, sets, NULL, NULL, &r))) break;
    double rho = strstr(ETM[m].label, "chebyshev") ? r.rho : cb_csv_na(); /* no rho without Chebyshev */
    cb_csv_printf(out[T_ERROR_TIME], "%s,%d,%s,%s,%d,%.17g,%.6f,%.6f,%.17g,%.17g,%s\n", d->label, S.s->mesh.grid_n,
                  ETM[m].label, ETM[m].family, r.iters, rho, r.wall_ms, r.setup_ms, r.error, r.rel_grad,
                  cb_status_name(r.status));
    if (!kmax) break;
  }
  cb_step_state_free(&S);
  return st;
}

/* cost hint: 1 + 2 + ... + kmax ~ 2 kmax iterations at the method's ms per vertex and iteration, plus its
 * fixed part (from a --quick run's cell times: Newton ~0.1 ms per vertex, pd ~20x a Jacobi iteration, an
 * auto rho for pd-chebyshev estimated at every step) */
double nl_et_cost(long i, void *ctx) {
  const plan *p = ctx;
  const et_method *m = &ETM[i % NETM];
  return (m->a + m->b * 2.0 * et_kmax(p, (int)(i % NETM))) * p->nv[p->et[i / NETM]];
}
