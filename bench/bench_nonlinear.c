/* bench_nonlinear: the cost of the nonlinear iterations (make bench).
 *
 * On the lab's cloth (configs/lab.ini: 1 kg per vertex, k = 8000, chebyshev-nl
 * with 32 iterations, d = m/dt^2 + 4k, rho = 0.995) at 21^2 and 64^2 vertices
 * and 128^2 quads (129^2 = 16 641 vertices, the size of Wang 2015's 37 FPS
 * dress), one core:
 *   - the lab's frame (32 iterations and the final gradient), median ms and frames per second;
 *   - one chebyshev-nl iteration, the frame's time / 32 (the frame also
 *     evaluates the final gradient, so this is an upper bound), and its
 *     achieved bandwidth: the bytes the iteration must move
 *     when nothing stays in cache (model below) over its time, against a
 *     STREAM triad measured in the same run;
 *   - pd: its one factorisation per scene (at alloc) and a frame of 10
 *     iterations (10 local steps and back-solves); the factorisations inside a
 *     step (the solver's factor time before and after must not change);
 *   - allocations inside a step of each nonlinear type (after a warm-up step).
 * Byte model of one iteration, per vertex (nf ~ nv, ns ~ 3 nv springs):
 *   gradient of E: x read 24, the springs' ends and rest lengths 3 x 16, dE/dx
 *     zeroed and accumulated 48; objective: x, xhat, dE/dx read 72, masses 8,
 *     free_vertex 4, grad F written 24; update: x, x_prev, grad F read 72, 1/d 8,
 *     free_vertex 4, x and x_prev written 48: 24 + 48 + 48 + 108 + 132 = 360 bytes.
 * Output: results/bench_nonlinear.csv. */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include <clothbench/timer.h>
#include "csv.h"
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"
#include "support/bench_support.h"


enum { BYTES_PER_VERTEX_ITER = 360 };

static int build(cb_experiment *e, int n, const char *const *more, cb_config *c, cb_scene **s) {
  char setn[64], mass[64], pins[64];
  snprintf(setn, sizeof setn, "mesh.n=%d", n);
  snprintf(mass, sizeof mass, "material.vertex_mass=1");
  snprintf(pins, sizeof pins, "scene.pins=0 %d", n - 1);
  const char *sets[16] = {setn, mass, pins};
  int k = 3;
  for (int i = 0; more && more[i] && k < 15; i++) sets[k++] = more[i];
  sets[k] = NULL;
  if (cb_experiment_config(e, "lab.ini", sets, c) || cb_config_validate(c) || cb_scene_from_config(c, s)) return -1;
  return 0;
}

/* median ms of `reps` steps of it from (xs, vs) */
static double frame_ms(cb_integrator *it, const double *xs, const double *vs, double *x, double *v, int nv3, int reps, cb_step_stats *st) {
  double t[32];
  for (int r = 0; r < reps; r++) {
    memcpy(x, xs, (size_t)nv3 * sizeof *x);
    memcpy(v, vs, (size_t)nv3 * sizeof *v);
    cb_integrator_step(it, x, v, st);
    t[r] = st->wall_ms;
  }
  return cb_median(t, reps);
}

static cb_integrator *make(const cb_config *base, cb_scene *s, const char *const *sets) {
  cb_config c = *base;
  for (int i = 0; sets[i]; i++)
    if (cb_config_set(&c, sets[i])) return NULL;
  cb_integrator *it = NULL;
  return cb_integrator_from_config(&c, s, NULL, &it) ? NULL : it;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bench_nonlinear", "Cost of the nonlinear iterations: the lab's frame rate, bandwidth, pd.", argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* timings: run alone */
  cb_runtime_init();
  cb_outfile csv;
  if (cb_experiment_csv(&e, &csv, NULL,
                        "# frame: the lab's step (chebyshev-nl, 32 iterations, d = m/dt^2 + 4k, rho = 0.995) from a state 5 frames in, median of repeated steps, one core\n"
                        "# iteration: frame / 32 (an upper bound: the frame also evaluates the final gradient); bytes per iteration: 360 per vertex (model in bench/bench_nonlinear.c)\n"
                        "# triad: a = b + s c, 3 arrays of 2^25 doubles, 24 bytes per element, median of passes\n"
                        "# pd: factor_ms is its one factorisation per scene (at alloc, CHOLMOD); frame_ms a step of 10 iterations\n",
                        "n,vertices,dofs,lab_frame_ms,lab_fps,iter_ms,iter_gbs,triad_gbs,iter_over_triad,pd_factor_ms,pd10_frame_ms,"
                        "pd_factorizations_in_step,allocs_jacobi_nl,allocs_chebyshev_nl,allocs_chebyshev_nl_exact,allocs_pd,allocs_pd_chebyshev,"
                        "allocs_pbd,allocs_xpbd,allocs_lbfgs,status")) {
    fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message());
    return 2;
  }
  cb_triad ta;
  if (cb_triad_alloc(&ta)) { fprintf(stderr, "bench_nonlinear: out of memory for the triad\n"); return 1; }
  const int sizes[] = {21, 64, 129};
  int nsz = e.quick ? 2 : 3;
  for (int si = 0; si < nsz; si++) {
    int n = sizes[si];
    cb_config c;
    cb_scene *s = NULL;
    if (build(&e, n, NULL, &c, &s)) { fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message()); return 1; }
    int nv3 = 3 * s->mesh.nv, reps = n >= 128 ? 9 : 15;
    double *x = malloc((size_t)nv3 * sizeof *x), *v = malloc((size_t)nv3 * sizeof *v);
    double *xs = malloc((size_t)nv3 * sizeof *xs), *vs = malloc((size_t)nv3 * sizeof *vs);
    static const char *const LAB[] = {"integrator.method=chebyshev-nl", NULL};
    cb_integrator *lab = make(&c, s, LAB);
    if (!x || !v || !xs || !vs || !lab) { fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message()); return 1; }
    memcpy(x, s->x0, (size_t)nv3 * sizeof *x);
    memcpy(v, s->v0, (size_t)nv3 * sizeof *v);
    cb_step_stats st;
    int status = CB_OK;
    for (int k = 0; k < 5; k++) status = cb_integrator_step(lab, x, v, &st); /* the cloth swinging */
    memcpy(xs, x, (size_t)nv3 * sizeof *x);
    memcpy(vs, v, (size_t)nv3 * sizeof *v);
    double f32 = frame_ms(lab, xs, vs, x, v, nv3, reps, &st);
    double iter_ms = f32 / 32.0;
    double tr[16];
    for (int k = 0; k < 7; k++) tr[k] = cb_triad_once(&ta);
    double triad = cb_median(tr, 7);
    double gbs = (double)BYTES_PER_VERTEX_ITER * s->mesh.nv / (iter_ms * 1e-3) / 1e9;
    /* pd: factorisation at alloc, then frames of 10 iterations */
    static const char *const PD[] = {"integrator.method=pd", "integrator.iters=10", NULL};
    double t0 = cb_now_ms();
    cb_integrator *pd = make(&c, s, PD);
    double pd_factor = cb_now_ms() - t0;
    if (!pd) { fprintf(stderr, "bench_nonlinear: pd: %s\n", cb_error_message()); return 1; }
    double fact_before = pd->solver->stats.factor_ms;
    double pd10 = frame_ms(pd, xs, vs, x, v, nv3, reps, &st);
    int pd_fact_in_step = pd->solver->stats.factor_ms != fact_before;
    /* allocations inside a step, after a warm-up step */
    static const char *const J[] = {"integrator.method=jacobi-nl", NULL};
    static const char *const CE[] = {"integrator.method=chebyshev-nl", "integrator.diagonal=exact", "integrator.iters=4", NULL};
    static const char *const PC[] = {"integrator.method=pd-chebyshev", "integrator.rho=auto", "integrator.iters=10", NULL};
    static const char *const CA[] = {"integrator.method=chebyshev-nl", "integrator.rho=auto", NULL};
    static const char *const PB[] = {"integrator.method=pbd", "integrator.substeps=4", "integrator.iters=8", NULL};
    static const char *const XP[] = {"integrator.method=xpbd", "integrator.substeps=4", "integrator.iters=8", NULL};
    static const char *const LB[] = {"integrator.method=lbfgs", "integrator.iters=10", NULL};
    enum { NALLOC = 8 };
    const char *const *types[NALLOC] = {J, CA, CE, PD, PC, PB, XP, LB};
    long allocs[NALLOC];
    for (int q = 0; q < NALLOC; q++) {
      cb_integrator *it = make(&c, s, types[q]);
      allocs[q] = -1;
      if (!it) continue;
      memcpy(x, xs, (size_t)nv3 * sizeof *x);
      memcpy(v, vs, (size_t)nv3 * sizeof *v);
      cb_integrator_step(it, x, v, &st);
      long a0 = cb_bench_allocations();
      cb_integrator_step(it, x, v, &st);
      allocs[q] = cb_bench_allocations() - a0;
      cb_integrator_free(it);
    }
    double na = cb_csv_na(), al[NALLOC]; /* an integrator that failed to build (-1) counted nothing */
    for (int q = 0; q < NALLOC; q++) al[q] = allocs[q] < 0 ? na : (double)allocs[q];
    cb_csv_printf(csv.f, "%d,%d,%d,%.6f,%.3f,%.6f,%.4f,%.4f,%.4f,%.6f,%.6f,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%s\n",
                  n, s->mesh.nv, s->sys.A.n, f32, 1000.0 / f32, iter_ms, gbs, triad, gbs / triad, pd_factor, pd10,
                  pd_fact_in_step, al[0], al[1], al[2], al[3], al[4], al[5], al[6], al[7], cb_status_name(status));
    fflush(csv.f);
    printf("bench_nonlinear: %dx%d (%d vertices): lab frame (chebyshev-nl, 32 iterations) %.3f ms = %.0f FPS; "
           "iteration %.4f ms, %.2f GB/s = %.0f%% of triad (%.2f GB/s); pd factorisation %.1f ms once, pd 10-iteration frame %.3f ms\n",
           n, n, s->mesh.nv, f32, 1000.0 / f32, iter_ms, gbs, 100 * gbs / triad, triad, pd_factor, pd10);
    cb_integrator_free(lab);
    cb_integrator_free(pd);
    cb_scene_free(s);
    free(x); free(v); free(xs); free(vs);
  }
  cb_triad_free(&ta);
  if (cb_outfile_commit(&csv)) { fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message()); return 2; }
  return 0;
}
