/* Time integrators behind one interface (a plug-in table each):
 *
 *   explicit  symplectic Euler: v <- v + dt M^-1 f(x);  x <- x + dt v
 *   newton    implicit Euler as x1 = argmin F(x),
 *             F(x) = 1/(2 dt^2) |x - x0 - dt v0|_M^2 + E(x),  v1 = (x1 - x0)/dt,
 *             by Newton's method: (M/dt^2 + H) dx = -grad F;  x += dx.
 *             max_iters = 1 is Baraff-Witkin's single linear solve.
 *
 * The integrator owns the Newton loop; the linear solver is a parameter.
 * Pinned vertices follow their prescribed velocity (x <- x + dt v, v fixed;
 * zero unless scene.pin_squeeze drives them). */
#ifndef CB_INTEGRATOR_H
#define CB_INTEGRATOR_H

#include "energy.h"
#include "scene.h"
#include "solver.h"

typedef struct cb_step_stats {
  int status;           /* CB_OK, CB_NOT_CONVERGED (max_iters hit), CB_NOT_SPD, CB_DIVERGED, ... */
  int newton_iters;     /* linear solves in this step (0 for explicit) */
  int linear_iters;     /* sum of the inner solver's iterations */
  int ls_backtracks;    /* halvings done by the line search */
  double rel_grad;      /* |grad F(x1)| / |grad F(x(0))| at the end of the step */
  double grad_norm;     /* |grad F(x1)|, free DOFs */
  double F;             /* F(x1), J */
  double assemble_ms, factor_ms, solve_ms, wall_ms;
  int linear_status;    /* status of the last inner solve */
  int factorizations;   /* factor calls (more than newton_iters when `shift` retried) */
  double shift_mu;      /* largest shift mu added to A in this step (`shift` policy), N/m; 0 = none */
} cb_step_stats;

/* What a Newton hook sees. Events: CB_NEWTON_GRADIENT after each evaluation
 * of grad F (iter = solves done so far, 0 at the initial guess), and
 * CB_NEWTON_SYSTEM after A has been assembled and before it is factorised,
 * with b = -grad F over the free DOFs. */
enum { CB_NEWTON_GRADIENT = 1, CB_NEWTON_SYSTEM = 2, CB_NEWTON_SOLVED = 3 };
typedef struct cb_newton_event {
  int iter;
  double F, grad_norm, rel_grad;
  double step_max;        /* max |alpha dx| of the update that led here (iter > 0) */
  double alpha;           /* line-search step length of that update */
  const double *x;        /* current iterate, 3*nv */
  const cb_sparse *A;     /* SYSTEM/SOLVED: the matrix */
  const double *b;        /* SYSTEM/SOLVED: right-hand side (free DOFs) */
  const double *dx;       /* SOLVED: solution (free DOFs) */
  const cb_solver *solver;/* SOLVED: its stats */
  int status;             /* SOLVED: factor/solve status */
  double shift_mu;        /* SOLVED: mu in A + mu I (`shift` policy), N/m; 0 = none */
} cb_newton_event;
typedef void (*cb_newton_hook)(void *ctx, int event, const cb_newton_event *ev);

typedef struct cb_integrator_params {
  double dt;                   /* time step, s. Default 1/30 */
  int max_iters;               /* Newton iterations per step. Default 50 */
  double tol;                  /* relative |grad F| to stop at. Default 1e-8 */
  double tol_dx;               /* max |dx| to stop at, m; 0 = off. Default 0 */
  int init_predict;            /* initial guess: 1 = x0 + dt v0, 0 = x0. Default 1 */
  int line_search;             /* backtracking Armijo line search. Default 0 */
  cb_definiteness definiteness;/* compressed-spring treatment. Default drop */
  cb_newton_hook hook;         /* optional; NULL = none */
  void *hook_ctx;
} cb_integrator_params;

cb_integrator_params cb_integrator_params_default(void);
int cb_integrator_params_from_config(const cb_config *c, cb_integrator_params *p);

typedef struct cb_integrator cb_integrator;

typedef struct cb_integrator_type {
  const char *name;
  int (*alloc)(cb_integrator *it);
  /* Advances (x, v) by one step in place. */
  int (*step)(cb_integrator *it, double *x, double *v, cb_step_stats *st);
  void (*free)(cb_integrator *it);
} cb_integrator_type;

struct cb_integrator {
  const cb_integrator_type *type;
  const cb_scene *scene;
  cb_system *sys;             /* the scene's system (matrix values are scratch) */
  cb_integrator_params params;
  cb_solver *solver;          /* owned; NULL for explicit */
  void *work;
};

extern const cb_integrator_type cb_integrator_explicit;
extern const cb_integrator_type cb_integrator_newton;
extern const cb_integrator_type *const cb_integrator_types[]; /* NULL-terminated */
const char *cb_integrator_name(int i);

/* Builds the integrator named by method for a scene. solver may be NULL for
 * explicit; otherwise it is the name of a registered linear solver, and the
 * symbolic analysis runs here, once. */
int cb_integrator_alloc(const char *method, cb_scene *scene, const cb_integrator_params *p,
                        const char *solver, const cb_solver_params *sp, cb_integrator **out);
/* Same, with everything taken from the scene's config. */
int cb_integrator_from_config(cb_scene *scene, cb_integrator **out);
int cb_integrator_step(cb_integrator *it, double *x, double *v, cb_step_stats *st);
void cb_integrator_free(cb_integrator *it);

#endif
