/* One implicit-Euler step of a method from a fixed start state, measured
 * against the converged step from that state: what the nonlinear and field
 * experiments compare methods on (step error, relative |grad F|, wall time).
 *
 *   cb_step_state   a scene, its config, a start state (x0, v0) reached by
 *                   some frames of the scene's own method, and the converged
 *                   reference step x* from it (cb_reference_step)
 *   cb_step_config  a method's config: the scene's config, the method's
 *                   "section.key=value" sets, then integrator.damping=1
 *                   (single steps compare methods on one F: no damping)
 *   cb_step_once    a fresh integrator, one step from (x0, v0); an integrator whose
 *                   step reads the earlier steps (CB_INTEGRATOR_HISTORY: VBD's
 *                   adaptive initial guess) first takes one untimed, unobserved
 *                   step from the state a frame before (xm, vm), so that the timed
 *                   step is a typical one (its guess fires), not a first one
 *   blow-up check   every step's status goes through cb_step_classify: a step
 *                   that ends with a non-finite relative |grad F| or one above
 *                   CB_STEP_GROWTH_BOUND (its end is far worse than doing nothing,
 *                   xhat) is recorded CB_DIVERGED, whatever its method said, so no
 *                   method writes a blow-up as an `ok` row
 *   cb_step_repeat  the step repeated while the repeats add up to < 30 ms
 *                   (at most 5; once with a hook), the median time kept
 *   cb_step_time_group  several methods' steps timed in interleaved rounds
 *                   (stats.h's round rule), for the claims that compare them
 *
 * A method whose step ends at a non-SPD factorisation can be given a
 * fallback config (e.g. Newton's exact Hessian falling back to drop): the
 * step is rerun with it, the time counts both runs and the result says so.
 * Every workspace is allocated in cb_step_state_init; the steps allocate only
 * what their integrators allocate in init. */
#ifndef CB_STEP_BENCH_H
#define CB_STEP_BENCH_H

#include <stdio.h>

#include "config.h"
#include "stats.h"
#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/scene.h>

typedef struct cb_step_state {
  const char *label; /* the scene's name in errors */
  cb_scene *s;       /* owned */
  cb_config c;       /* the scene's config (no method sets) */
  double *x0, *v0;   /* the start state */
  double *xm, *vm;   /* the state one frame before it (the warm-up step's start); NULL when frames = 0 */
  double *xstar;     /* the converged step from it (reference) */
  double *x, *v;     /* scratch: the last step's end state */
  int n3;
  cb_objective obj;   /* F of the step from (x0, v0) */
  double Fhat, Fstar; /* F(xhat), F(x*): the objective error's yardsticks (cb_step_obj_error) */
} cb_step_state;

/* The relative objective error (F(x) - F(x*)) / (F(xhat) - F(x*)) of S's step at x (Liu et al. 2017's
 * measure; 1 at xhat, 0 at the converged step; it may be slightly negative where x* is converged only to its
 * tolerance). NaN when F(xhat) = F(x*). */
double cb_step_obj_error(cb_step_state *S, const double *x);

/* Takes s (built from c; freed on error too): `frames` frames of c's method
 * (with its damping) from the scene's initial state, then the reference step
 * from there. label names the scene in errors. */
int cb_step_state_init(cb_step_state *S, const char *label, const cb_config *c, cb_scene *s, int frames);
void cb_step_state_free(cb_step_state *S);

typedef struct cb_step_result {
  double wall_ms, setup_ms, alloc_ms, error, rel_grad, rho;
  double obj_error; /* cb_step_obj_error at the end state */
  int iters, status;
  int global_path; /* pd, pd-chebyshev, lbfgs: CB_GLOBAL_SCALAR or CB_GLOBAL_BLOCK (integrator.h); 0 others */
  int fallback;    /* the step hit a non-SPD factorisation and was rerun with the method's fallback */
  cb_timing wall;  /* the step's time at every timed repeat (wall_ms: their median) */
} cb_step_result;

/* A step's end may not be worse than its start guess xhat by more than this: relative |grad F| =
 * |grad F(x1)| / |grad F(xhat)| above it (or not finite) is a blow-up, CB_DIVERGED. 100: two decades
 * above doing nothing. The rows that gave it (issue 31 §6): XPBD 64 substeps x 1 iteration on the stiff
 * 81^2 cloth, relative |grad F| 1695 and 23x the largest strain of 32 substeps, recorded `ok`. */
#define CB_STEP_GROWTH_BOUND 100.0
/* the status a step is recorded with: a fatal status as it is; otherwise CB_DIVERGED when rel_grad_hat is
 * not finite or above CB_STEP_GROWTH_BOUND, else the step's own status */
int cb_step_classify(int status, double rel_grad_hat);

/* S's config with sets (NULL-terminated, at most 16) and integrator.damping=1, validated. */
int cb_step_config(const cb_step_state *S, const char *const *sets, cb_config *out);

/* One step: a fresh integrator from c, one step from S's start state (end state in S->x, S->v); r gets
 * its results, *wall its time (without a fixed-iteration method's once-per-run rho estimate, setup_ms).
 * hook may observe it. */
int cb_step_once(cb_step_state *S, const cb_config *c, cb_newton_hook hook, void *ctx, cb_step_result *r, double *wall);

/* cb_step_once, and when the step ends at a non-SPD factorisation and fb is given, the same step again
 * with fb: *wall is both runs' time, r the fallback's results with r->fallback = 1. */
int cb_step_fallback(cb_step_state *S, const cb_config *c, const cb_config *fb, cb_newton_hook hook, void *ctx,
                     cb_step_result *r, double *wall);

/* The step of the method `sets` names, repeated while the repeats add up to less than 30 ms, at most 5,
 * the median wall time kept; with a hook (an observed step is for its trace, not its time): once. */
int cb_step_repeat(cb_step_state *S, const char *const *sets, cb_newton_hook hook, void *ctx, cb_step_result *r);

enum { CB_STEP_GROUP_MAX = 16 };
/* The steps of the methods sets[0..n) (fallback[i] may be NULL, fallback itself NULL), timed in
 * interleaved rounds (every method once per round; cb_timing_more(quick, ...); a step under the warm
 * limit timed right after an untimed one of its own). r[i] gets method i's results and its repeats. */
int cb_step_time_group(int quick, cb_step_state *S, const char *const *const *sets, const char *const *const *fallback,
                       int n, cb_step_result *r);
/* cb_step_time_group, and: a step whose first timed run takes once_ms or more is timed in the first
 * round only (its one time is its median; INFINITY: every step every round, cb_step_time_group);
 * xend (may be NULL, as may xend[i]) gets method i's end state x of its first timed run (3 nv). */
int cb_step_time_group_ex(int quick, double once_ms, cb_step_state *S, const char *const *const *sets,
                          const char *const *const *fallback, int n, cb_step_result *r, double *const *xend);


#endif
