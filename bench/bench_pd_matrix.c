/* bench_pd_matrix: projective dynamics' and L-BFGS's constant matrix P, factored
 * as the 3n x 3n block matrix P (x) I_3 (the harness before issue 31) or as
 * the n x n P with x, y and z solved as one 3-column right-hand side (issue
 * 31 §1; pd_matrix.h).
 *
 * Liu's cloth of the field and nonlinear experiments (configs/lab.ini: 441 kg
 * in total, k = 8000 N/m, 10 m, pinned at two corners) at n^2 = 81^2 and
 * 161^2 (41^2 and 81^2 with --quick), from a state 5 frames in, one core. Per
 * size and method (pd, pd-chebyshev: 10 iterations; lbfgs: 10 iterations, tol
 * 0) three variants step from the same state in interleaved rounds (old,
 * block, scalar, old, ...):
 *   old     integrator.pd_matrix = block with the solver's per-solve residual
 *           product on (solver.residual = 1): the code before issue 31;
 *   block   the block matrix without the residual product;
 *   scalar  the n x n P, 3 right-hand sides (the default, `auto`).
 * Columns: the median step and back-solve times and their per-iteration
 * quotients (step / iterations: it includes the local steps or the objective
 * evaluations), the spread (min, max) of the step, the factor's nonzeros, the
 * old/scalar ratio of the medians, and the largest position difference of the
 * step against the old variant (round-off only).
 * Output: results/bench_pd_matrix.csv. */
#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "bind.h"
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"

enum { NVAR = 3, MAXROUNDS = 15, ITERS = 10 };
static const char *const VARIANT[NVAR] = {"old", "block", "scalar"};
static const char *const METHOD[] = {"pd", "pd-chebyshev", "lbfgs"};
enum { NMETHOD = sizeof METHOD / sizeof METHOD[0] };

static int configure(cb_experiment *e, int n, cb_config *c) {
  char setn[64], mass[64], pins[64];
  snprintf(setn, sizeof setn, "mesh.n=%d", n);
  snprintf(mass, sizeof mass, "material.vertex_mass=441/%d", n * n); /* Liu's 441 kg in total */
  snprintf(pins, sizeof pins, "scene.pins=0 %d", n - 1);
  const char *sets[] = {setn, mass, pins, "integrator.damping=1", NULL};
  if (cb_experiment_config(e, "lab.ini", sets, c) || cb_config_validate(c)) return -1;
  return 0;
}

/* An integrator of the method and variant; NULL (message printed) on failure. */
static cb_integrator *make(const cb_config *base, cb_scene *s, const char *method, int variant) {
  cb_config c = *base;
  char m[64], it_s[64];
  snprintf(m, sizeof m, "integrator.method=%s", method);
  snprintf(it_s, sizeof it_s, "integrator.iters=%d", ITERS);
  const char *sets[] = {m, it_s, variant == 2 ? "integrator.pd_matrix=auto" : "integrator.pd_matrix=block",
                        strcmp(method, "lbfgs") == 0 ? "integrator.tol=0" : NULL, NULL};
  for (int i = 0; sets[i]; i++)
    if (cb_config_set(&c, sets[i])) return NULL;
  cb_integrator *it = NULL;
  if (cb_integrator_from_config(&c, s, NULL, &it)) {
    fprintf(stderr, "bench_pd_matrix: %s\n", cb_error_message());
    return NULL;
  }
  if (variant == 0) it->solver->params.residual = 1; /* the old code's per-solve |b - Ax|/|b| */
  return it;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r =
      cb_experiment_begin(&e, "bench_pd_matrix",
                          "pd, pd-chebyshev and lbfgs with the 3n x 3n block P or the n x n P (issue 31).", argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* timings: run alone */
  cb_runtime_init();
  cb_outfile csv;
  if (cb_experiment_csv(&e, &csv, NULL,
                        "# scene: configs/lab.ini at n^2 with 441 kg in total, pinned at two corners, from 5 frames of "
                        "pd-chebyshev; one step of 10 iterations (lbfgs: tol 0) per variant in interleaved rounds\n"
                        "# variants: old = block matrix with the per-solve residual product (before issue 31), block = "
                        "block "
                        "matrix without it, scalar = n x n P with 3 right-hand sides (default)\n"
                        "# iter_ms = step_ms / 10 (local steps and objective evaluations included), solve_iter_ms = "
                        "back-solve "
                        "time / 10; old_over = the old variant's median step / this variant's; max_dx_vs_old_m the "
                        "largest "
                        "position difference of the step against the old variant\n",
                        "n,vertices,method,variant,global_matrix,rounds,step_ms,step_min_ms,step_max_ms,iter_ms,solve_"
                        "iter_ms,"
                        "factor_nnz,old_over,max_dx_vs_old_m,status")) {
    fprintf(stderr, "bench_pd_matrix: %s\n", cb_error_message());
    return 2;
  }
  int sizes[2] = {81, 161};
  if (e.quick || e.smoke) sizes[0] = 41, sizes[1] = e.smoke ? 0 : 81;
  int status = 0;
  for (int si = 0; si < 2 && sizes[si]; si++) {
    int n = sizes[si], rounds = n > 100 ? 7 : MAXROUNDS;
    if (e.smoke) rounds = 3;
    cb_config c;
    cb_scene *s = NULL;
    if (configure(&e, n, &c) || cb_scene_from_config(&c, &s)) {
      fprintf(stderr, "bench_pd_matrix: %s\n", cb_error_message());
      return 1;
    }
    size_t nv3 = (size_t)3 * s->mesh.nv;
    double *xs = malloc(nv3 * sizeof(double)), *vs = malloc(nv3 * sizeof(double)), *x = malloc(nv3 * sizeof(double)),
           *v = malloc(nv3 * sizeof(double)), *xold = malloc(nv3 * sizeof(double));
    if (!xs || !vs || !x || !v || !xold) return 1;
    memcpy(xs, s->x0, nv3 * sizeof(double));
    memcpy(vs, s->v0, nv3 * sizeof(double));
    cb_step_stats st;
    cb_integrator *warm = make(&c, s, "pd-chebyshev", 2);
    if (!warm) return 1;
    for (int f = 0; f < 5; f++) cb_integrator_step(warm, xs, vs, &st);
    cb_integrator_free(warm);
    for (int mi = 0; mi < NMETHOD; mi++) {
      cb_integrator *it[NVAR];
      for (int k = 0; k < NVAR; k++)
        if (!(it[k] = make(&c, s, METHOD[mi], k))) return 1;
      double t[NVAR][MAXROUNDS], sv[NVAR][MAXROUNDS], dx[NVAR] = {0}, nnz[NVAR] = {0};
      int path[NVAR] = {0}, stat[NVAR] = {0};
      for (int rd = 0; rd < rounds; rd++)
        for (int k = 0; k < NVAR; k++) {
          memcpy(x, xs, nv3 * sizeof(double));
          memcpy(v, vs, nv3 * sizeof(double));
          int rs = cb_integrator_step(it[k], x, v, &st);
          if (rs != CB_OK && rs != CB_NOT_CONVERGED) stat[k] = rs;
          t[k][rd] = st.wall_ms;
          sv[k][rd] = st.solve_ms;
          path[k] = st.global_path;
          nnz[k] = st.global_factor_nnz;
          if (k == 0) memcpy(xold, x, nv3 * sizeof(double));
          for (size_t i = 0; i < nv3; i++) dx[k] = fmax(dx[k], fabs(x[i] - xold[i]));
        }
      double med0 = cb_median(t[0], rounds);
      for (int k = 0; k < NVAR; k++) {
        double med = cb_median(t[k], rounds), lo = t[k][0], hi = t[k][0];
        for (int rd = 1; rd < rounds; rd++) lo = fmin(lo, t[k][rd]), hi = fmax(hi, t[k][rd]);
        double smed = cb_median(sv[k], rounds);
        cb_csv_printf(csv.f, "%d,%d,%s,%s,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%s\n", n, s->mesh.nv,
                      METHOD[mi], VARIANT[k], cb_global_path_name(path[k]), rounds, med, lo, hi, med / ITERS,
                      smed / ITERS, nnz[k], med0 / med, dx[k], cb_status_name(stat[k]));
        printf("bench_pd_matrix: %d^2 %-12s %-6s (%s) step %8.3f ms [%8.3f, %8.3f], iteration %7.3f ms, back-solve "
               "%7.3f ms, factor nnz %.3g, old/this %.2fx, max |dx| vs old %.2g m\n",
               n, METHOD[mi], VARIANT[k], cb_global_path_name(path[k]), med, lo, hi, med / ITERS, smed / ITERS, nnz[k],
               med0 / med, dx[k]);
        if (stat[k]) status = 1;
        cb_integrator_free(it[k]);
      }
      fflush(csv.f);
    }
    cb_scene_free(s);
    free(xs);
    free(vs);
    free(x);
    free(v);
    free(xold);
  }
  if (cb_outfile_commit(&csv)) {
    fprintf(stderr, "bench_pd_matrix: %s\n", cb_error_message());
    return 2;
  }
  return status;
}
