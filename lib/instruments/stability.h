/* Explicit stability: where symplectic Euler breaks, and how to measure it
 * (claims E1, E2, I1; experiments/explicit_stability/main.c).
 *
 * 1. Prediction. Linearised about an equilibrium x* (forces balance, v = 0),
 *    the explicit step  v <- v - dt M^-1 K dx,  dx <- dx + dt v  (K = the
 *    Hessian of E at x*, restricted to the free vertices) decouples in the
 *    eigenvectors of M^-1 K into scalar oscillators u'' = -w^2 u. For one of
 *    them the step matrix is [[1 - h^2 w^2, h], [-h w^2, 1]]: determinant 1,
 *    trace 2 - h^2 w^2, so it is bounded iff |2 - h^2 w^2| < 2, i.e. h < 2/w.
 *    Hence
 *        dt_crit = 2 / omega_max,   omega_max^2 = lambda_max(M^-1 K)
 *                                              = lambda_max(M^-1/2 K M^-1/2).
 *    K is the exact Hessian (definiteness `none`): the explicit step uses the
 *    exact force. Gravity is linear in x, so it adds nothing to K; it only sets
 *    the configuration x* (the hanging state) at which K is evaluated. Dense
 *    GSL on small scenes, Lanczos (lib/core/util/eigen.c) on large ones.
 *
 * 2. The cell classifier. A cell is one run of a fixed simulated time from a
 *    given start state (x0, v0). With E = kinetic + elastic + gravity
 *    potential (a conserved quantity of the exact dynamics) and S the energy
 *    scale of the start state (cb_stability_energy_scale: its elastic and
 *    kinetic energy plus the work gravity can do across the rest bounding
 *    box), the classifier follows r(t) = (E(t) - E(0)) / S:
 *      diverged  a position, velocity or energy is NaN/Inf, or r > R_d
 *                (diverge_ratio, default 10); the cell stops at once;
 *      unstable  r rose above R_u (unstable_ratio, default 1) at some time but
 *                the run neither met a NaN nor passed R_d before its end;
 *      stable    r <= R_u throughout;
 *      failed    the integrator reported a fatal non-energy status (linear
 *                solver failure, not SPD, line search failure).
 *    A conservative system cannot gain energy, so a gain of S (the whole
 *    energy budget of the scene) is an instability of the integrator, not
 *    physics; a bounded symplectic-Euler run gains at most the energy of its
 *    oscillation times 1/(1 - (h w/2)^2), which is far below S when the start
 *    state is an equilibrium plus a small perturbation. max_energy_ratio is
 *    max(0, max_t r(t)).
 *
 * 3. Boundary. The largest stable dt is bracketed on the sweep grid (the
 *    largest grid dt below the first non-stable one) and refined by bisection
 *    in log dt. */
#ifndef CB_STABILITY_H
#define CB_STABILITY_H

#include "config.h"
#include <clothbench/integrator.h>
#include <clothbench/scene.h>

typedef enum { CB_CELL_STABLE = 0, CB_CELL_UNSTABLE = 1, CB_CELL_DIVERGED = 2, CB_CELL_FAILED = 3 } cb_cell_class;

/* "stable", "unstable", "diverged", "failed" (or "?"). */
const char *cb_cell_class_name(int cls);

typedef struct cb_stability_params {
  double sim_time;       /* simulated time per cell, s. Default 2 */
  long min_steps;        /* at least this many steps, so that a large dt still sees growth. Default 200 */
  long max_steps;        /* at most this many steps; 0 = no cap. Default 0 */
  double unstable_ratio; /* R_u: max (E - E0)/S above this -> unstable. Default 1 */
  double diverge_ratio;  /* R_d: (E - E0)/S above this, or NaN/Inf -> diverged (stops). Default 10 */
  int energy_every;      /* E sampled every this many steps and at the last; 0 = last only. Default 1 */
  double mark_time;      /* also record E at the first step with t >= mark_time, s; 0 = none. Default 0 */
} cb_stability_params;

cb_stability_params cb_stability_params_default(void);

/* Steps of a cell at time step dt: ceil(sim_time/dt) clamped to [min_steps, max_steps]. */
long cb_stability_steps(const cb_stability_params *p, double dt);

/* ---- classifier ----------------------------------------------------------- */

typedef struct cb_classifier {
  double max_ratio;  /* max(0, max of r over the samples) */
  double last_ratio; /* the last r */
  int cls;           /* cb_cell_class so far */
  long samples;
} cb_classifier;

void cb_classifier_init(cb_classifier *c);
/* Feeds one sample r = (E - E0)/S (NaN or Inf for a non-finite state).
 * Returns 1 once the cell is decided for good (diverged), 0 to go on. */
int cb_classifier_push(cb_classifier *c, const cb_stability_params *p, double r);
/* The class of a whole history r[0..n-1]; *max_ratio (may be NULL) gets max(0, max r). */
int cb_stability_classify(const double *r, long n, const cb_stability_params *p, double *max_ratio);

/* ---- start state and energy scale -------------------------------------------- */

/* S = elastic(x) + kinetic(v) + (sum_i m_i) g D + 1e-12 J, with D the rest
 * bounding-box diagonal and g = |gravity|, or 9.8 m/s^2 if gravity is off (so
 * that S stays a meaningful scale for a free-floating cloth). */
double cb_stability_energy_scale(const cb_scene *s, const double *x, const double *v);

/* v = a deterministic pseudo-random velocity on the free vertices (uniform
 * in [-1,1] per component, 64-bit LCG seeded by seed) scaled to kinetic
 * energy ke (J); pinned vertices get 0. It seeds every mode, so that an
 * unstable one has something to grow from. */
void cb_stability_perturb(const cb_scene *s, double ke, unsigned seed, double *v);

/* v += c dir on every free vertex, with c such that the added uniform
 * velocity alone has kinetic energy ke (J): a coherent swing (for a hanging
 * scene, mostly its lowest pendulum-like modes). */
void cb_stability_swing(const cb_scene *s, double ke, const double dir[3], double *v);

typedef struct cb_equilibrium_params {
  double dt0;    /* first proximal step, s. Default 0.05 */
  double dt_max; /* proximal step cap, s. Default 10 */
  int max_steps; /* proximal steps at most. Default 200 */
  double tol;    /* stop at max_i |grad_i E| <= tol * max_i m_i g. Default 1e-4 */
} cb_equilibrium_params;

typedef struct cb_equilibrium_stats {
  int steps; /* proximal steps taken */
  long newton_iters;
  double residual;   /* max_i |grad_i E| / (max_i m_i g) at the end */
  int status;        /* CB_OK, or CB_NOT_CONVERGED (residual above tol), or a solver status */
  double max_strain; /* max over springs of (l - L)/L at the end */
  double min_strain;
  double ms;
} cb_equilibrium_stats;

cb_equilibrium_params cb_equilibrium_params_default(void);

/* Static equilibrium (the hanging state) reached from x (in/out) by proximal
 * Newton steps: x <- argmin_y E(y) + |y - x|_M^2 / (2 h^2), which is one
 * implicit Euler step from rest (Newton + CHOLMOD, exact convergence), with h
 * doubling from dt0 to dt_max. Each step lowers E, so this ends in a local
 * minimum of E (gravity included) near x. */
int cb_stability_equilibrium(cb_scene *s, double *x, const cb_equilibrium_params *p, cb_equilibrium_stats *st);

/* ---- prediction -------------------------------------------------------------- */

typedef enum { CB_EIG_AUTO = 0, CB_EIG_DENSE, CB_EIG_LANCZOS, CB_EIG_BOTH } cb_eig_method;

/* Scenes with at most this many free DOFs use the dense solver under AUTO. */
#define CB_STABILITY_DENSE_MAX 1500

typedef struct cb_prediction {
  double lambda_max;   /* lambda_max(M^-1 K), 1/s^2 (the dense value when it ran) */
  double omega_max;    /* sqrt(lambda_max), rad/s */
  double dt_crit;      /* 2 / omega_max, s (Inf if lambda_max <= 0) */
  int method;          /* CB_EIG_DENSE or CB_EIG_LANCZOS: which produced lambda_max */
  double lambda_dense; /* NaN if the dense solver did not run */
  double lambda_min_dense;
  double lambda_lanczos; /* NaN if Lanczos did not run */
  double lanczos_res;    /* residual bound of its largest Ritz pair */
  int lanczos_steps, lanczos_status;
  int ndof; /* free DOFs */
  double ms;
} cb_prediction;

/* Assembles K = H(x) (exact Hessian, free DOFs) in the scene's system matrix
 * (scratch) and computes lambda_max(M^-1 K). */
int cb_stability_predict(cb_scene *s, const double *x, cb_eig_method method, cb_prediction *out);

/* ---- cells ----------------------------------------------------------------- */

typedef struct cb_cell_result {
  int cls;         /* cb_cell_class */
  int step_status; /* the last non-ok integrator status (CB_OK if none) */
  long steps, steps_planned;
  double dt, t_end;                         /* s */
  double max_energy_ratio;                  /* max(0, max_t (E - E0)/S) */
  double final_energy_ratio;                /* (E_end - E0)/S at the last sample */
  double energy0, energy_end, energy_scale; /* E(0), E at the last sample, S; J */
  double t_mark, energy_mark;               /* first step time >= mark_time and E there (the end if no mark
                                               or not reached: then t_mark = t_end < mark_time) */
  double wall_ms;                           /* stepping loop with its energy samples */
  long newton_iters;                        /* sum over steps */
  int max_newton_iters;                     /* per step */
  long not_converged_steps;                 /* steps that stopped at max_iters */
} cb_cell_result;

/* State arrays for cells on one scene, allocated once. */
typedef struct cb_cell_work {
  double *x, *v;
} cb_cell_work;

int cb_cell_work_alloc(const cb_scene *s, cb_cell_work *w);
void cb_cell_work_free(cb_cell_work *w);

/* One cell: sets it->params.dt = dt, starts from (x0, v0) and steps
 * cb_stability_steps(p, dt) times or until diverged. S is the energy scale
 * (cb_stability_energy_scale of the start state). Returns CB_OK (the outcome
 * is in out->cls) or a negative error. */
int cb_stability_cell(cb_integrator *it, double dt, const double *x0, const double *v0, double S,
                      const cb_stability_params *p, cb_cell_work *w, cb_cell_result *out);

/* ---- boundary ---------------------------------------------------------------- */

/* On a grid dt[0..n-1] (ascending) with classes cls[]: lo = the largest dt
 * below the first non-stable cell, hi = that cell's dt. All stable: lo =
 * dt[n-1], hi = 0 (the bisection then searches upward). *monotone = 1 if no
 * stable cell lies above the first non-stable one. Returns CB_OK, or
 * CB_NOT_CONVERGED if even dt[0] is not stable (lo = 0). */
int cb_stability_grid_bracket(const double *dt, const int *cls, int n, double *lo, double *hi, int *monotone);

typedef void (*cb_cell_hook)(void *ctx, const cb_cell_result *r);

typedef struct cb_bisect_result {
  double dt_stable;   /* the largest dt found stable, s */
  double dt_unstable; /* the smallest dt found not stable above it, s */
  int runs;           /* cells run */
  int status;         /* CB_OK, or CB_NOT_CONVERGED if no bracket was found */
} cb_bisect_result;

/* Refines a bracket lo (stable) < hi (not stable) by `iters` bisections of
 * log dt, running one cell at the midpoint each time. If hi <= 0 it first
 * multiplies lo by grow (> 1) until a cell is not stable (at most 40 times);
 * if lo <= 0 it divides hi by grow until a cell is stable. Every cell run is
 * passed to hook (may be NULL). */
int cb_stability_bisect(cb_integrator *it, const double *x0, const double *v0, double S, const cb_stability_params *p,
                        cb_cell_work *w, double lo, double hi, double grow, int iters, cb_cell_hook hook, void *ctx,
                        cb_bisect_result *out);

/* Runs one cell at the guess dt, then brackets from it (upward by grow if
 * it was stable, downward otherwise) and bisects iters times: for scenes
 * without a sweep grid. */
int cb_stability_boundary_from_guess(cb_integrator *it, const double *x0, const double *v0, double S,
                                     const cb_stability_params *p, cb_cell_work *w, double guess, double grow,
                                     int iters, cb_cell_hook hook, void *ctx, cb_bisect_result *out);

/* ---- a case: one scene with its start state, prediction and integrators ---- */

typedef struct cb_case_params {
  int equilibrium;     /* 1: start from the static equilibrium reached from the scene's x0. Default 1 */
  double perturb;      /* random velocity: kinetic energy as a fraction of S0 = S(x_start, 0). Default 1e-6 */
  double swing;        /* uniform velocity along swing_dir: kinetic energy as a fraction of S0. Default 1e-3 */
  double swing_dir[3]; /* unit vector. Default (0, 0, 1): across a chain in plane yz or a cloth in plane xy */
  unsigned seed;       /* perturbation seed. Default 1 */
  cb_eig_method eig;   /* solver for the prediction at the start state. Default AUTO */
  int predict_rest;    /* 1: also predict at the rest shape (mesh.x). Default 1 */
  cb_equilibrium_params eq;
} cb_case_params;

cb_case_params cb_case_params_default(void);

typedef struct cb_stability_case {
  cb_scene *scene;
  double *x_start, *v_start; /* start state of every cell, 3*nv each */
  double S;                  /* energy scale of (x_start, v_start), J */
  double kinetic0;           /* kinetic energy of v_start, J */
  int has_equilibrium;
  cb_equilibrium_stats eq; /* valid if has_equilibrium */
  cb_prediction pred;      /* at x_start */
  cb_prediction pred_rest; /* at the rest shape (NaN fields if not asked) */
  cb_cell_work work;
  cb_integrator *expl;   /* explicit symplectic Euler */
  cb_integrator *newton; /* Newton with the config's solver, tol and max_iters */
} cb_stability_case;

/* Builds the scene (a bad config or mesh returns its error with the
 * library's message), the start state, the predictions and both
 * integrators. On failure everything is freed. */
int cb_stability_case_init(cb_stability_case *c, const cb_config *cfg, const cb_case_params *p);
void cb_stability_case_free(cb_stability_case *c);

#endif
