/* The reference for solver-error measurements: one implicit Euler step solved
 * to convergence from a given state, and the norms that compare a step's
 * result with it.
 *
 *   F(x)  = 1/(2 dt^2) |x - xhat|_M^2 + E(x),   xhat = x0 + dt v0
 *   x*    = argmin F  (the exact implicit Euler step), v* = (x* - x0)/dt
 *
 * x* is found by Newton's method with CHOLMOD and a backtracking (Armijo)
 * line search, a loop written here independently of integrator_newton.c:
 *   - Newton matrix A = M/dt^2 + H(x) with the exact spring Hessian when that
 *     A is positive definite (CHOLMOD succeeds), so the final iterations are
 *     Newton's and converge quadratically near a minimiser where A is SPD.
 *     When CHOLMOD reports a non-positive pivot (compressed springs make A
 *     indefinite), that iteration uses A + mu I instead, mu = mu0 = 1e-3
 *     mean(m)/dt^2 at the first failure of a step and the last mu/4 after
 *     that, multiplied by 4 until CHOLMOD succeeds (a Levenberg-Marquardt
 *     shift; counted in not_spd_fallbacks). The shift keeps the compressive
 *     curvature that the lecture's drop fix throws away: on the stretched lab
 *     cloth (initial_scale 1.5) drop needed > 200 iterations in 2 of 30 steps,
 *     the shift <= 55. Either way dx is a descent direction. (If no mu up to
 *     1e12 mu0 works, drop is the last resort.)
 *   - F is not convex when springs are compressed, so x* is the local
 *     minimiser this descent reaches from xhat; a method may end in another
 *     one (F(x) - F(x*) < 0 then shows it).
 *   - Line search: alpha = 1, 1/2, ... until F(x + alpha dx) <= F(x) +
 *     1e-4 alpha grad F . dx; when |grad F . dx| is below 1e-12 S (S the size of
 *     F's summands, so the decrease is below F's round-off) the full step is
 *     taken, as in integrator_newton.c.
 *   - Stop when |grad F| <= tol |grad F(xhat)| (tol = 1e-12), or, the absolute
 *     floor near round-off, when the last applied update had max|alpha dx| <=
 *     tol_dx (default 1e-12 x the diagonal of the rest mesh's bounding box:
 *     ~1.4e-11 m on the 10 m lab cloth). Relative |grad F| cannot reach 1e-12
 *     when the springs are stiff: F's gradient carries round-off ~ eps k L per
 *     spring, e.g. ~1e-9 N at k = 1e7, while |grad F(xhat)| ~ m g ~ 10 N.
 *     In Newton's quadratic regime the error left after an update of size d is
 *     O(d^2), so the floor bounds |x - x*| far below the step errors measured.
 *
 * F, grad F, xhat and the velocity update are the core's implicit-Euler
 * objective (clothbench/objective.h), the one Newton minimises, so every
 * method is measured with the same F; the M-norm lives here. The solve is
 * the reference's own (above), kept independent of integrator_newton.c. */
#ifndef CB_REFERENCE_H
#define CB_REFERENCE_H

#include <clothbench/scene.h>
#include <clothbench/solver.h>

typedef struct cb_reference_params {
  double dt;  /* time step, s. Default 1/30 */
  double tol; /* relative |grad F| (to |grad F(xhat)|) to stop at. Default 1e-12 */
  double
      tol_dx; /* m: stop when the last update had max|alpha dx| <= tol_dx; 0 = 1e-12 x rest bbox diagonal. Default 0 */
  int max_iters; /* Newton iterations at most. Default 500 */
  /* Optional log of every iterate: iter (0 = xhat), |grad F|, relative
   * |grad F|, F, the line-search alpha of the update that led here (1 at
   * iter 0) and the Hessian of that update (0 none/start, 1 exact, 2 exact +
   * shift). NULL = off. Default NULL */
  void (*log)(void *ctx, int iter, double grad_norm, double rel_grad, double F, double alpha, int hessian);
  void *log_ctx;
} cb_reference_params;

cb_reference_params cb_reference_params_default(void);

typedef struct cb_reference_stats {
  int status;            /* CB_OK, CB_NOT_CONVERGED (max_iters), CB_LS_FAILED, CB_DIVERGED, ... */
  int iters;             /* Newton iterations (linear solves) */
  int not_spd_fallbacks; /* iterations whose exact-Hessian A was not SPD (shift used) */
  double max_shift;      /* largest mu used, kg/s^2 (0 if none) */
  int ls_backtracks;     /* halvings done by the line search */
  int by_dx;             /* 1 if it stopped by the tol_dx floor rather than by tol */
  double rel_grad;       /* |grad F(x*)| / |grad F(xhat)| */
  double grad_norm;      /* |grad F(x*)|, free DOFs */
  double last_dx;        /* max|alpha dx| of the last update, m */
  double F;              /* F(x*), J */
  double wall_ms;
} cb_reference_stats;

typedef struct cb_reference cb_reference;

/* Builds the reference solver for a scene (CHOLMOD's symbolic analysis runs
 * here, once; every workspace is allocated here). */
int cb_reference_alloc(cb_scene *s, const cb_reference_params *p, cb_reference **out);
void cb_reference_free(cb_reference *r);
const cb_reference_params *cb_reference_get_params(const cb_reference *r);

/* x* from (x0, v0) (3*nv each); xstar (3*nv) receives the minimiser (pinned
 * vertices keep x0). Returns st->status. */
int cb_reference_step(cb_reference *r, const double *x0, const double *v0, double *xstar, cb_reference_stats *st);

/* One reference step in place: (x, v) <- (x*, (x* - x)/dt) (pinned
 * vertices keep their prescribed v, as in every integrator). */
int cb_reference_advance(cb_reference *r, double *x, double *v, cb_reference_stats *st);

/* Total energy kinetic + potential (elastic + gravity) of a state, J. */
double cb_state_energy(const cb_scene *s, const double *x, const double *v);

/* F(x) of the step from (x0, v0) with the reference's dt; if gF != NULL it
 * receives grad F over the free DOFs (3*nfree). */
double cb_reference_objective(cb_reference *r, const double *x0, const double *v0, const double *x, double *gF);

/* |a - b|_M = sqrt(sum_free m_i |a_i - b_i|^2), kg^1/2 m (free vertices only). */
double cb_mnorm_diff(const cb_scene *s, const double *a, const double *b);

/* Step error |x - x*|_M / |x* - x0|_M (dimensionless; 0 when x = x*). When
 * x* = x0 the denominator is 0 and the absolute |x - x*|_M is returned. */
double cb_step_error(const cb_scene *s, const double *x, const double *xstar, const double *x0);

/* Total mass of the free vertices, kg (|a - b|_M / sqrt(that) is an RMS
 * distance in m). */
double cb_free_mass(const cb_scene *s);

#endif
