/* The implicit-Euler objective of one step, shared by every method that
 * solves it (Newton in integrator_newton.c, the converged reference step in
 * lib/instruments/reference.c, and the nonlinear iterations to come):
 *
 *   xhat      = x0 + dt v0                          (the predictor; pins: their
 *                                                    prescribed x0 + dt v_pin)
 *   F(x)      = 1/(2 dt^2) |x - xhat|_M^2 + E(x)    (E includes gravity)
 *   grad F(x) = M (x - xhat) / dt^2 + dE/dx(x)      (free DOFs only)
 *   v1        = (x1 - x0) / dt                      (free vertices; pins keep v0)
 *
 * A step: cb_objective_begin(x0, v0, dt), cb_objective_guess for the initial
 * iterate, any number of cb_objective_eval, then cb_objective_velocity. The
 * workspaces are allocated once, in cb_objective_init. */
#ifndef CB_OBJECTIVE_H
#define CB_OBJECTIVE_H

#include "scene.h"

typedef struct cb_objective {
  const cb_scene *scene;
  double dt;    /* s, of the current step */
  double *x0;   /* 3*nv: the step's start */
  double *xhat; /* 3*nv: x0 + dt v0 */
  double *g;    /* 3*nv: dE/dx scratch */
} cb_objective;

int cb_objective_init(cb_objective *o, const cb_scene *s);
void cb_objective_free(cb_objective *o);

/* Starts a step of length dt from (x0, v0) (3*nv each): keeps x0 and sets
 * xhat = x0 + dt v0. x0 may be the array the step then updates in place. */
void cb_objective_begin(cb_objective *o, const double *x0, const double *v0, double dt);

/* Initial iterate: xhat (predict = 1) or x0 (predict = 0); either way every
 * pinned vertex at its prescribed position xhat. */
void cb_objective_guess(const cb_objective *o, double *x, int predict);

/* F(x), J. If gF is not NULL it receives grad F over the free DOFs
 * (3*nfree); if scale is not NULL it receives S = |x - xhat|_M^2/(2 dt^2) +
 * sum_t |E_t|, the size of F's summands (F's round-off is ~ eps S). */
double cb_objective_eval(cb_objective *o, const double *x, double *gF, double *scale);

/* v = (x - x0)/dt on the free vertices; pinned vertices keep their v. */
void cb_objective_velocity(const cb_objective *o, const double *x, double *v);

/* ---- shared by the fixed-point iterations on F (nonlinear Jacobi, projective
 * dynamics) and their Chebyshev acceleration (Wang 2015) ----
 * Chebyshev's weight of iteration k: omega_0 = 1, omega_1 = 2/(2 - rho^2),
 * omega_k = 4/(4 - rho^2 omega_{k-1}); the update is
 * x_{k+1} = omega_k y_k + (1 - omega_k) x_{k-1}, y_k the plain iteration's
 * result from x_k. rho = 0 gives omega = 1 throughout: the plain iteration. */
double cb_chebyshev_omega(int k, double rho, double omega_prev);
/* Wang's estimate of rho from the unaccelerated iteration: d[0..n-1] the
 * norms |x_{k+1} - x_k| of n plain iterations; rho = the geometric mean of
 * the ratio d_{k+1}/d_k over the second half, (d_{n-1}/d_{n/2})^(1/(n-1-n/2)),
 * the linearised iteration's dominant |eigenvalue| once the others have died
 * out. Clamped to [0, 0.9999]; 0 if n < 4 or a norm is 0 or not finite. */
double cb_rho_from_updates(const double *d, int n);

#endif
