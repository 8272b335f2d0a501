/* bench_nonlinear: the cost of the nonlinear iterations (make bench).
 *
 * On the lab's cloth (configs/lab.ini: 1 kg per vertex, k = 8000, chebyshev-nl
 * with 32 iterations, d = m/dt^2 + 4k, rho = 0.995) at 21^2, 64^2, 129^2 (128^2
 * quads, 16 641 vertices, the size of Wang 2015's 37 FPS dress) and 256^2
 * vertices, one core:
 *   - the lab's frame (32 iterations and the final gradient), median ms and
 *     frames per second, with the library's kernel (lib/core/energy/nl_kernel.h) and
 *     with the old one (bench/support/nl_old.c: one spring at a time, its
 *     gradient scattered; gravity, objective and update as separate passes),
 *     in interleaved rounds (new frame, old frame, one triad pass); the ratio
 *     old / new; whether the two give bit-identical states (x, v, F and
 *     |grad F|/|grad F(xhat)| after a step from the same state), else the
 *     largest relative difference;
 *   - one iteration, the frame's time / 32 (the frame also evaluates the
 *     final gradient, so this is an upper bound), in ns per spring, and
 *     against its bound: the bytes one iteration must move (model below) at
 *     the bandwidth of a STREAM triad measured in the same rounds;
 *   - pd: its one factorisation per scene (at alloc) and a frame of 10
 *     iterations (10 local steps and back-solves); the factorisations inside a
 *     step (the solver's factor time before and after must not change);
 *   - allocations inside a step of each nonlinear type (after a warm-up step).
 * Bytes one iteration must move (each array once, nothing kept in cache
 * between iterations; nv vertices, nf free, ns springs): x_k read 24 nv
 * (springs and update), masses 8 nv, free_index 4 nv; xhat 24 nf, 1/d 8 nf,
 * x_{k-1} read 24 nf, x_{k+1} written 24 nf; the springs' ends and rest
 * lengths 16 ns. About 164 bytes per vertex on a grid (ns ~ 3 nv).
 * Output: results/bench_nonlinear.csv. CB_BENCH_NL_SIZES="129" (sizes n,
 * blank-separated) runs those sizes only, for development. */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include <clothbench/timer.h>
#include "csv.h"
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"
#include "support/bench_support.h"
#include "support/nl_old.h"

#include <math.h>

enum { ROUNDS_SMALL = 15, ROUNDS_LARGE = 9 };

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
static double frame_ms(cb_integrator *it, const double *xs, const double *vs, double *x, double *v, int nv3, int reps,
                       cb_step_stats *st) {
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
  int r = cb_experiment_begin(&e, "bench_nonlinear",
                              "Cost of the nonlinear iterations: the lab's frame rate, bandwidth, pd.", argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* timings: run alone */
  cb_runtime_init();
  cb_outfile csv;
  if (cb_experiment_csv(&e, &csv, NULL,
                        "# frame: the lab's step (chebyshev-nl, 32 iterations, d = m/dt^2 + 4k, rho = 0.995) from a "
                        "state 5 frames in, one core; "
                        "new kernel (lib/core/energy/nl_kernel.h) and old kernel (bench/support/nl_old.c), medians "
                        "of "
                        "interleaved rounds (new, old, one triad pass)\n"
                        "# iteration: frame / 32 (an upper bound: the frame also evaluates the final gradient); "
                        "ns_per_spring_iter = iteration / springs\n"
                        "# bound: bytes_per_iter (what one iteration must move: model in bench/bench_nonlinear.c) at "
                        "the triad's bandwidth; iter_over_bound = iteration / bound\n"
                        "# triad: a = b + s c, 3 arrays of 2^25 doubles, 24 bytes per element, median of the rounds' "
                        "passes\n"
                        "# old_new_identical: 1 if a step of each kernel from the same state gives bit-identical x, v, "
                        "F and rel_grad; old_new_max_rel_diff the largest relative difference of x and v\n"
                        "# pd: factor_ms is its one factorisation per scene (at alloc, CHOLMOD); frame_ms a step of 10 "
                        "iterations\n",
                        "n,vertices,springs,dofs,lab_frame_ms,lab_fps,old_frame_ms,speedup_vs_old,iter_ms,ns_per_"
                        "spring_iter,old_ns_per_spring_iter,"
                        "bytes_per_iter,triad_gbs,bound_ms,iter_over_bound,old_over_bound,old_new_identical,old_new_"
                        "max_rel_diff,pd_factor_ms,pd10_frame_ms,"
                        "pd_factorizations_in_step,allocs_jacobi_nl,allocs_chebyshev_nl,allocs_chebyshev_nl_exact,"
                        "allocs_pd,allocs_pd_chebyshev,"
                        "allocs_pbd,allocs_xpbd,allocs_lbfgs,status")) {
    fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message());
    return 2;
  }
  cb_triad ta;
  if (cb_triad_alloc(&ta)) {
    fprintf(stderr, "bench_nonlinear: out of memory for the triad\n");
    return 1;
  }
  cb_triad_once(&ta); /* first touch */
  int sizes[8] = {21, 64, 129, 256};
  int nsz = e.quick ? 2 : 4;
  const char *only = getenv("CB_BENCH_NL_SIZES"); /* a developer's subset, e.g. "129" or "64 129" */
  if (only && *only) {
    nsz = 0;
    for (char *end; nsz < 8; only = end) {
      long n = strtol(only, &end, 10);
      if (end == only) break;
      if (n >= 2 && n <= 4096) sizes[nsz++] = (int)n;
    }
  }
  for (int si = 0; si < nsz; si++) {
    int n = sizes[si];
    cb_config c;
    cb_scene *s = NULL;
    if (build(&e, n, NULL, &c, &s)) {
      fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message());
      return 1;
    }
    int nv3 = 3 * s->mesh.nv, reps = n >= 128 ? ROUNDS_LARGE : ROUNDS_SMALL;
    double *x = malloc((size_t)nv3 * sizeof *x), *v = malloc((size_t)nv3 * sizeof *v);
    double *xs = malloc((size_t)nv3 * sizeof *xs), *vs = malloc((size_t)nv3 * sizeof *vs);
    double *xo = malloc((size_t)nv3 * sizeof *xo), *vo = malloc((size_t)nv3 * sizeof *vo);
    static const char *const LAB[] = {"integrator.method=chebyshev-nl", NULL};
    cb_integrator *lab = make(&c, s, LAB);
    if (!x || !v || !xs || !vs || !xo || !vo || !lab) {
      fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message());
      return 1;
    }
    const cb_nljacobi_params *lp = lab->type_params;
    cb_old_lab old;
    if (cb_old_lab_init(&old, s, lab->params.dt, lab->params.damping, lp->iters, lp->alpha, lp->rho)) {
      fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message());
      return 1;
    }
    long springs = 0; /* of every spring term */
    for (int t = 0; t < s->sys.nterms; t++) {
      int ns;
      const int *ends;
      const double *rest;
      double k;
      if (s->sys.terms[t]->type == cb_term_spring &&
          cb_spring_term_springs(s->sys.terms[t], &ns, &ends, &rest, &k) == CB_OK)
        springs += ns;
    }
    memcpy(x, s->x0, (size_t)nv3 * sizeof *x);
    memcpy(v, s->v0, (size_t)nv3 * sizeof *v);
    cb_step_stats st;
    int status = CB_OK;
    for (int k = 0; k < 5; k++) status = cb_integrator_step(lab, x, v, &st); /* the cloth swinging */
    memcpy(xs, x, (size_t)nv3 * sizeof *x);
    memcpy(vs, v, (size_t)nv3 * sizeof *v);
    /* the two kernels from the same state: bit-identical? */
    double Fo, rgo;
    memcpy(xo, xs, (size_t)nv3 * sizeof *x);
    memcpy(vo, vs, (size_t)nv3 * sizeof *v);
    cb_integrator_step(lab, x, v, &st);
    cb_old_lab_step(&old, xo, vo, &Fo, &rgo);
    int identical = memcmp(x, xo, (size_t)nv3 * sizeof *x) == 0 && memcmp(v, vo, (size_t)nv3 * sizeof *v) == 0 &&
                    memcmp(&st.F, &Fo, sizeof Fo) == 0 && memcmp(&st.rel_grad, &rgo, sizeof rgo) == 0;
    double maxrel = 0.0;
    for (int q = 0; q < nv3; q++) {
      double a[2] = {x[q], v[q]}, b[2] = {xo[q], vo[q]};
      for (int h = 0; h < 2; h++) {
        double sc = fmax(fabs(a[h]), fabs(b[h]));
        if (sc > 0 && fabs(a[h] - b[h]) / sc > maxrel) maxrel = fabs(a[h] - b[h]) / sc;
      }
    }
    /* interleaved rounds: a new frame, an old frame, a triad pass */
    double tn[32], to[32], tr[32];
    for (int q = 0; q < reps; q++) {
      memcpy(x, xs, (size_t)nv3 * sizeof *x);
      memcpy(v, vs, (size_t)nv3 * sizeof *v);
      cb_integrator_step(lab, x, v, &st);
      tn[q] = st.wall_ms;
      memcpy(xo, xs, (size_t)nv3 * sizeof *x);
      memcpy(vo, vs, (size_t)nv3 * sizeof *v);
      double t0 = cb_now_ms();
      cb_old_lab_step(&old, xo, vo, &Fo, &rgo);
      to[q] = cb_now_ms() - t0;
      tr[q] = cb_triad_once(&ta);
    }
    double f32 = cb_median(tn, reps), fold = cb_median(to, reps), triad = cb_median(tr, reps);
    double iter_ms = f32 / 32.0, old_iter_ms = fold / 32.0;
    int nvx = s->mesh.nv, nfx = s->model.nfree;
    double bytes = 36.0 * nvx + 80.0 * nfx + 16.0 * (double)springs; /* the model above */
    double bound_ms = bytes / (triad * 1e9) * 1e3;
    /* pd: factorisation at alloc, then frames of 10 iterations */
    static const char *const PD[] = {"integrator.method=pd", "integrator.iters=10", NULL};
    double t0 = cb_now_ms();
    cb_integrator *pd = make(&c, s, PD);
    double pd_factor = cb_now_ms() - t0;
    if (!pd) {
      fprintf(stderr, "bench_nonlinear: pd: %s\n", cb_error_message());
      return 1;
    }
    double fact_before = pd->solver->stats.factor_ms;
    double pd10 = frame_ms(pd, xs, vs, x, v, nv3, reps, &st);
    int pd_fact_in_step = pd->solver->stats.factor_ms != fact_before;
    /* allocations inside a step, after a warm-up step */
    static const char *const J[] = {"integrator.method=jacobi-nl", NULL};
    static const char *const CE[] = {"integrator.method=chebyshev-nl", "integrator.diagonal=exact",
                                     "integrator.iters=4", NULL};
    static const char *const PC[] = {"integrator.method=pd-chebyshev", "integrator.rho=auto", "integrator.iters=10",
                                     NULL};
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
    cb_csv_printf(csv.f,
                  "%d,%d,%ld,%d,%.6f,%.3f,%.6f,%.4f,%.6f,%.4f,%.4f,%.0f,%.4f,%.6f,%.4f,%.4f,%d,%.6g,%.6f,%.6f,%d,%.17g,"
                  "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%s\n",
                  n, s->mesh.nv, springs, s->sys.A.n, f32, 1000.0 / f32, fold, fold / f32, iter_ms,
                  iter_ms * 1e6 / (double)springs, old_iter_ms * 1e6 / (double)springs, bytes, triad, bound_ms,
                  iter_ms / bound_ms, old_iter_ms / bound_ms, identical, maxrel, pd_factor, pd10, pd_fact_in_step,
                  al[0], al[1], al[2], al[3], al[4], al[5], al[6], al[7], cb_status_name(status));
    fflush(csv.f);
    printf("bench_nonlinear: %dx%d (%d vertices, %ld springs): lab frame %.3f ms = %.0f FPS (old kernel %.3f ms: "
           "%.2fx); "
           "iteration %.4f ms = %.2f ns per spring (old %.2f), %.2fx its bound (%.4f ms: %.0f bytes at the triad's "
           "%.2f GB/s; old %.2fx); "
           "old and new %s; pd factorisation %.1f ms once, pd 10-iteration frame %.3f ms\n",
           n, n, s->mesh.nv, springs, f32, 1000.0 / f32, fold, fold / f32, iter_ms, iter_ms * 1e6 / (double)springs,
           old_iter_ms * 1e6 / (double)springs, iter_ms / bound_ms, bound_ms, bytes, triad, old_iter_ms / bound_ms,
           identical ? "bit-identical" : "differ", pd_factor, pd10);
    cb_old_lab_free(&old);
    free(xo);
    free(vo);
    cb_integrator_free(lab);
    cb_integrator_free(pd);
    cb_scene_free(s);
    free(x);
    free(v);
    free(xs);
    free(vs);
  }
  cb_triad_free(&ta);
  if (cb_outfile_commit(&csv)) {
    fprintf(stderr, "bench_nonlinear: %s\n", cb_error_message());
    return 2;
  }
  return 0;
}
