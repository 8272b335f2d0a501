/* The measurements of the newton_vs_bw experiment (claims I2, I3), as
 * library pieces: each one runs on a scene and writes CSV rows.
 *
 *   cb_study_steps        one step of every method from states of the reference
 *                         trajectory, against x* (error against run time)
 *   cb_study_trajectories trajectories of some methods against the reference
 *                         trajectory (converged steps at the same dt)
 *   cb_study_dt_error     converged implicit Euler at dt against dt/refine
 *   cb_study_regime_cell  Baraff-Witkin (K = 1, CHOLMOD) on one (dt, k, stretch)
 *                         cell: trajectory divergence and one-step errors
 *   cb_study_order        |grad F| at every Newton iteration (exact Hessian and
 *                         drop, with and without line search) for I2
 *
 * Scene labels, k and stretch are copied into the rows from the scene's
 * config. Every workspace is allocated before the time steps. Each is one
 * cell of the experiment's sweeps (main.c); progress is the runner's. */
#ifndef CB_NEWTON_STUDY_H
#define CB_NEWTON_STUDY_H

#include <stdio.h>

#include "method.h"
#include "stats.h"
#include "reference.h"
#include <clothbench/scene.h>

/* ---- one step of every method -------------------------------------------- */
extern const char *const cb_study_steps_header;
/* What cb_study_steps keeps of each (state, method) for the summary. */
typedef struct cb_study_point {
  cb_timing wall;                       /* the step's wall time, every repeat */
  double wall_ms, setup_ms, step_error; /* medians over the repeats */
  int failed;                           /* a status other than ok / max_iters (fixed K ends at max_iters by design) */
} cb_study_point;
/* states: steps of the reference trajectory to start from (ascending). At
 * each state every method's step is timed in interleaved rounds (each method
 * once per round; stats.h: 3 rounds with quick, 2-5 in a full run by their
 * cost; a step shorter than CB_TIMING_WARM_MS timed right after an untimed
 * one of its own), after one untimed warm-up step of every method at the first state;
 * a row holds the medians over the repeats, and for wall_ms also the min,
 * max and every repeat. */
int cb_study_steps(cb_scene *s, const char *label, double dt, const int *states, int nstates, const cb_method *methods,
                   int nmethods, int quick, FILE *csv, cb_study_point *pts);

/* ---- the error / run-time summary of one scene ---------------------------- */
extern const char *const cb_study_pareto_header;
/* pts[state * nmethods + m] from cb_study_steps. One row per method: median
 * wall_ms (and without Chebyshev's rho set-up) over the states, with its
 * spread (wall_min_ms, wall_max_ms: over the repeats that every state has,
 * per repeat the median over the states), max step error (Inf if a
 * step failed), and whether the method is on the Pareto front of (median
 * wall_ms, max step error). Rows in method order. */
int cb_study_pareto(FILE *csv, const char *label, const cb_method *methods, int nmethods, const cb_study_point *pts,
                    int nstates);

/* ---- trajectories ---------------------------------------------------------- */
extern const char *const cb_study_traj_header;
/* nsteps steps at dt of every method and of the reference (method
 * "reference"); a method's trajectory stops at its first fatal status (its
 * row has that status: the first diverging step). */
int cb_study_trajectories(cb_scene *s, const char *label, double dt, int nsteps, const cb_method *methods, int nmethods,
                          FILE *csv);

/* ---- time-discretisation error ------------------------------------------- */
extern const char *const cb_study_dt_header;
/* Reference trajectories at dt and dt/refine over nsteps coarse steps; one
 * row per coarse step with the M-norm RMS distance between the two. */
int cb_study_dt_error(cb_scene *s, const char *label, double dt, int refine, int nsteps, FILE *csv);

/* ---- the K = 1 regime map ------------------------------------------------ */
extern const char *const cb_study_regime_header;
/* Baraff-Witkin over duration_s from the scene's initial state (stretched by
 * scene.initial_scale); one-step errors against x* from nsamples states of
 * its own trajectory (steps 0, N/nsamples, ...). fail_level: the one-step
 * error above which the cell counts as failed (0.01). dt_index, k_index,
 * stretch_index place the cell in the map. One row. */
int cb_study_regime_cell(cb_scene *s, const char *label, double dt, double duration_s, int nsamples, double fail_level,
                         int dt_index, int k_index, int stretch_index, FILE *csv);

/* ---- I2: Newton's |grad F| sequences ------------------------------------- */
extern const char *const cb_study_order_header;
/* From each of the first nsteps states of the reference trajectory at dt
 * (state 0 = the scene's initial state): Newton with CHOLMOD, definiteness
 * none (exact Hessian) and drop, line search off and on, to relative
 * |grad F| 1e-14, the reference's tol_dx floor or 60 iterations; and the
 * reference step itself ("exact_or_shift": exact Hessian where A is SPD,
 * shifted otherwise, line search). One row per gradient evaluation; column hessian
 * names the Hessian of the update that led to the iterate. */
int cb_study_order(cb_scene *s, const char *label, double dt, int nsteps, FILE *csv);

#endif
