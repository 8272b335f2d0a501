/* nonlinear, J3 panel a: the lab's own iteration (chebyshev-nl, 32 iterations a frame) over
 * 2000 frames, rho swept: divergence, |grad F| and the linearised rho along the run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "nonlinear.h"

const char *const nl_rhos[NL_NRHO] = {"0", "0.9", "0.95", "0.97", "0.99", "0.995", "0.999", "0.9995", "0.9999", "auto"};
static const int SAMPLE[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 1500, 2000};

/* ---- J3 panel a: the lab's iteration over 2000 frames, rho swept ------------ */

/* rho(I - D^-1 A(x)) with A = M/dt^2 + H(x) (exact Hessian: the linearisation
 * of the iteration) and D the lab's diagonal, by Lanczos on D^-1/2 A D^-1/2. */
static int linear_rho(cb_scene *s, const double *x, double dt, double *lmin, double *lmax, int *steps) {
  cb_sparse *A = &s->sys.A;
  cb_system_assemble(&s->sys, x, 1.0 / (dt * dt), CB_DEF_NONE, 0.0);
  int n = A->n;
  double *d = malloc((size_t)n * sizeof(double)), *work = malloc((size_t)n * sizeof(double));
  if (!d || !work) {
    free(d);
    free(work);
    return CB_ENOMEM;
  }
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

/* Cell i: scene j3[i / nrho], rho nl_rhos[rho0 + i % nrho]: one trajectory, its row and its spectrum rows. */
int nl_j3_cell(long i, void *ctx, FILE *const *out) {
  const plan *p = ctx;
  const cb_scene_decl *d = nl_scene_of(p->j3[i / p->nrho]);
  const char *rho = nl_rhos[p->rho0 + i % p->nrho];
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
          for (int b = a; b > 0 && cp[b] < cp[b - 1]; b--) {
            double t = cp[b];
            cp[b] = cp[b - 1];
            cp[b - 1] = t;
          }
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
      cb_csv_printf(out[T_J3],
                    "lab_iteration,%s,%s,%s,%.17g,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.6f,%"
                    "s\n",
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

/* Estimated ms of a cell, from a --quick run (one BLAS thread) and the full
 * run's phase times: a J3 frame 0.3 ms and a Lanczos sample 120 ms (x
 * vertices / 441); a W1 or error-time iteration 1e-4 ms per vertex (the
 * error-time sweep runs 1 + 2 + ... + kmax ~ 2 kmax of them, plus ~1 s of
 * Newton and repeats); a P1 cell 1 ms per vertex (two converged Newtons and the step-error traces). */
double nl_j3_cost(long i, void *ctx) {
  const plan *p = ctx;
  int ns = 1;
  for (int k = 0; k < (int)(sizeof SAMPLE / sizeof SAMPLE[0]); k++) ns += SAMPLE[k] < p->frames;
  return (0.3 * p->frames + 120.0 * ns) * p->nv[p->j3[i / p->nrho]] / 441.0;
}
