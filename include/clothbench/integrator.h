/* Time integrators behind one interface (a plug-in table each):
 *
 *   explicit  symplectic Euler: v <- v + dt M^-1 f(x);  x <- x + dt v
 *   newton    implicit Euler as x1 = argmin F(x),
 *             F(x) = 1/(2 dt^2) |x - x0 - dt v0|_M^2 + E(x),  v1 = (x1 - x0)/dt,
 *             by Newton's method: (M/dt^2 + H) dx = -grad F;  x += dx.
 *             max_iters = 1 is Baraff-Witkin's single linear solve.
 *   pbd, xpbd Müller et al. 2007, Macklin et al. 2016: Gauss-Seidel projection of one distance
 *             constraint per spring, with substeps (integrator_xpbd.c).
 *   lbfgs     Liu et al. 2017: L-BFGS on F with projective dynamics' matrix as the initial
 *             Hessian, and a line search (integrator_lbfgs.c).
 *   vbd, vbd-chebyshev  Chen et al. 2024: per-vertex 3x3 Newton steps in Gauss-Seidel order over a
 *             vertex colouring, optionally Chebyshev-accelerated (integrator_vbd.c).
 *   shape_matching  Müller et al. 2005: v <- v + alpha (g - x)/dt + dt f_ext/m;
 *             x <- x + dt v, goals g from one-ring clusters (integrator_shape_matching.c).
 *
 * Newton minimises the shared implicit-Euler objective (objective.h); each
 * integrator owns its loop, and the linear solver is a parameter. After every
 * step of every type the scene's post-step responses run (scene.h).
 * Parameters: the generic ones (dt, hook) in cb_integrator_params, each
 * type's own in its struct (cb_newton_params), with its config keys declared
 * in its type table (cb_param_key; the config layer binds them).
 * Pinned vertices follow their prescribed velocity (x <- x + dt v, v fixed;
 * zero unless scene.pin_squeeze drives them). */
#ifndef CB_INTEGRATOR_H
#define CB_INTEGRATOR_H

#include "energy.h"
#include "objective.h"
#include "params.h"
#include "scene.h"
#include "solver.h"

typedef struct cb_step_stats {
  int status;          /* CB_OK, CB_NOT_CONVERGED (max_iters hit), CB_NOT_SPD, CB_DIVERGED, ... */
  int newton_iters;    /* iterations of the step: Newton's linear solves, the nonlinear Jacobi/Chebyshev
                          sweeps, the local/global rounds of projective dynamics (0 for explicit) */
  int linear_iters;    /* sum of the inner solver's iterations */
  int ls_backtracks;   /* halvings done by the line search */
  double rel_grad;     /* |grad F(x1)| / |grad F(x(0))| at the end of the step */
  double rel_grad_hat; /* |grad F(x1)| / |grad F(xhat)|, xhat = x0 + dt v0: one yardstick for every method that
                          minimises F (equal to rel_grad when the initial guess is xhat); 0 for explicit */
  double grad_norm;    /* |grad F(x1)|, free DOFs */
  double F;            /* F(x1), J */
  double assemble_ms, factor_ms, solve_ms, wall_ms;
  int linear_status;          /* status of the last inner solve */
  int factorizations;         /* factor calls (more than newton_iters when `shift` retried) */
  double shift_mu;            /* largest shift mu added to A in this step (`shift` policy), N/m; 0 = none */
  double rho;                 /* Chebyshev spectral radius the step used (given or estimated); 0 = none */
  double constraint_residual; /* pbd, xpbd: the last sweep's largest constraint residual over the rest length,
                                 max_c |C_c + alpha~ lambda_c| / L_c (xpbd; pbd: |C_c| / L_c) at the iterate
                                 before that sweep, in the step's last substep; 0 for the other types */
  int global_path;          /* pd, pd-chebyshev, lbfgs: the constant matrix P they solve with, CB_GLOBAL_SCALAR (n x n,
                               x, y and z as one 3-column right-hand side) or CB_GLOBAL_BLOCK (3n x 3n P (x) I_3);
                               CB_GLOBAL_NONE for the other methods */
  double global_factor_nnz; /* nonzeros of that matrix's factor (CHOLMOD), 0 = none */
  /* The contact term's phases in this step (cb_contact_stats' timers, differences over the step as the wrapper
   * measures it, begin_step included; 0 without a contact term), ms: broad phase, the step bound's CCD, the
   * barrier's pairs (value, gradient, Hessian). Parts of wall_ms; the Hessian's pairs are also inside assemble_ms,
   * and factor_ms + solve_ms are the linear solve (docs/performance.md, "Contact"). */
  double contact_broad_ms, contact_ccd_ms, contact_barrier_ms;
} cb_step_stats;

enum { CB_GLOBAL_NONE = 0, CB_GLOBAL_SCALAR = 1, CB_GLOBAL_BLOCK = 2 };
/* "none", "scalar", "block" (the CSV's global_matrix column), NULL past them. */
const char *cb_global_path_name(int path);

/* What a Newton hook sees. Events: CB_NEWTON_GRADIENT after each evaluation
 * of grad F (iter = solves done so far, 0 at the initial guess), and
 * CB_NEWTON_SYSTEM after A has been assembled and before it is factorised,
 * with b = -grad F over the free DOFs. */
enum { CB_NEWTON_GRADIENT = 1, CB_NEWTON_SYSTEM = 2, CB_NEWTON_SOLVED = 3 };
typedef struct cb_newton_event {
  int iter;
  double F, grad_norm, rel_grad;
  double step_max;         /* max |alpha dx| of the update that led here (iter > 0) */
  double alpha;            /* line-search step length of that update */
  const double *x;         /* current iterate, 3*nv */
  const cb_sparse *A;      /* SYSTEM/SOLVED: the matrix */
  const double *b;         /* SYSTEM/SOLVED: right-hand side (free DOFs) */
  const double *dx;        /* SOLVED: solution (free DOFs) */
  const cb_solver *solver; /* SOLVED: its stats */
  int status;              /* SOLVED: factor/solve status */
  double shift_mu;         /* SOLVED: mu in A + mu I (`shift` policy), N/m; 0 = none */
} cb_newton_event;
typedef void (*cb_newton_hook)(void *ctx, int event, const cb_newton_event *ev);

/* Parameters every integrator reads. */
typedef struct cb_integrator_params {
  int cookie; /* CB_PARAMS_COOKIE, set by cb_integrator_params_default() and checked by cb_integrator_alloc (params.h)
               */
  double dt;  /* time step, s. Default 1/30 */
  double damping;      /* velocity damping: v <- damping v on the free vertices at the start of
                          every step, before the predictor (the GAMES103 lab's 0.99), for every
                          type; in [0, 1], 1 = none. Default 1 */
  cb_newton_hook hook; /* optional observer of the step's iterations (events above); NULL = none */
  void *hook_ctx;
} cb_integrator_params;

cb_integrator_params cb_integrator_params_default(void);

/* Newton's own parameters (the newton type's params_size). */
typedef struct cb_newton_params {
  int cookie;    /* CB_PARAMS_COOKIE, set by cb_newton_params_default() and checked by cb_integrator_alloc (params.h) */
  int max_iters; /* linear solves per step at most; 1 = Baraff-Witkin. Default 50 */
  double tol;    /* relative |grad F| to stop at. Default 1e-8 */
  double tol_dx; /* max |dx| to stop at, m; 0 = off. Default 0 */
  int init_predict;             /* initial guess: 1 = x0 + dt v0, 0 = x0. Default 1 */
  int line_search;              /* backtracking Armijo line search. Default 0 */
  cb_definiteness definiteness; /* compressed-spring treatment; must match the scene's springs
                                   (choi-ko is built into them). Default drop */
} cb_newton_params;

cb_newton_params cb_newton_params_default(void);

/* The nonlinear Jacobi iterations' parameters (jacobi-nl, chebyshev-nl;
 * integrator_nljacobi.c has the formulas). */
typedef struct cb_nljacobi_params {
  int cookie; /* CB_PARAMS_COOKIE, set by cb_nljacobi_params_default() and checked by cb_integrator_alloc (params.h) */
  int iters;  /* iterations per step (the lab: 32). Default 32 */
  int diagonal;                 /* D: 0 lab (m/dt^2 + 4k), 1 valence (m/dt^2 + k n_i), 2 exact (3x3 blocks of
                                   M/dt^2 + H). Default 0 (lab) */
  double alpha;                 /* step weight x <- x - alpha D^-1 g (Wang's gamma). Default 1 */
  double rho;                   /* Chebyshev rho in [0, 1), or CB_AUTO. Default 0.995 (chebyshev-nl),
                                   0 and not a key (jacobi-nl) */
  int rho_iters;                /* plain iterations of the `auto` estimate, run once. Default 64 */
  cb_definiteness definiteness; /* Hessian policy of the exact diagonal. Default drop */
} cb_nljacobi_params;
cb_nljacobi_params cb_nljacobi_params_default(void);   /* chebyshev-nl's */
extern const char *const cb_nljacobi_diagonal_names[]; /* "lab", "valence", "exact", NULL */

/* Projective dynamics' parameters (pd, pd-chebyshev; integrator_pd.c). */
typedef struct cb_pd_params {
  int cookie;    /* CB_PARAMS_COOKIE, set by cb_pd_params_default() and checked by cb_integrator_alloc (params.h) */
  int iters;     /* local/global iterations per step (Liu et al. 2013: 10). Default 32 */
  double rho;    /* pd-chebyshev's rho in [0, 1), or CB_AUTO. Default 0.995 (0 for pd) */
  int rho_iters; /* plain iterations of the `auto` estimate, run once. Default 64 */
  int matrix;    /* CB_PD_MATRIX_AUTO (the n x n P where it can) or CB_PD_MATRIX_BLOCK. Default auto */
} cb_pd_params;
/* integrator.pd_matrix (pd, pd-chebyshev, lbfgs): `auto` factors the n x n P and solves x, y, z as 3 right-hand
 * sides when the solver is direct (CHOLMOD) and every term's part of P is of the form P (x) I_3, else the 3n x 3n
 * block matrix; `block` always the block matrix (the harness before issue 31, kept to compare against). */
enum { CB_PD_MATRIX_AUTO = 0, CB_PD_MATRIX_BLOCK = 1 };
extern const char *const cb_pd_matrix_names[]; /* "auto", "block", NULL */
cb_pd_params cb_pd_params_default(void);       /* pd-chebyshev's */

/* Position-based dynamics' parameters (pbd, xpbd; integrator_xpbd.c). */
typedef struct cb_xpbd_params {
  int cookie;   /* CB_PARAMS_COOKIE, set by cb_xpbd_params_default() and checked by cb_integrator_alloc (params.h) */
  int iters;    /* constraint sweeps per substep. Default 32 */
  int substeps; /* substeps per step (Macklin et al. 2019's small steps). Default 1 */
  double stiffness; /* pbd's stiffness factor s in (0, 1] (xpbd uses material k). Default 1 */
} cb_xpbd_params;
cb_xpbd_params cb_xpbd_params_default(void);

/* L-BFGS's parameters (lbfgs; integrator_lbfgs.c). */
typedef struct cb_lbfgs_params {
  int cookie;    /* CB_PARAMS_COOKIE, set by cb_lbfgs_params_default() and checked by cb_integrator_alloc (params.h) */
  int iters;     /* iterations per step at most. Default 32 */
  double tol;    /* relative |grad F| to stop at (Newton's tol). Default 1e-8 */
  double tol_dx; /* max |alpha d| to stop at, m (Newton's tol_dx); 0 = off. Default 0 */
  int window;    /* (s, y) pairs kept, m. Default 5 */
  int line_search; /* 0 armijo, 1 wolfe (cb_lbfgs_line_search_names). Default 0 */
  int matrix;      /* H0's storage, as cb_pd_params.matrix. Default auto */
} cb_lbfgs_params;
cb_lbfgs_params cb_lbfgs_params_default(void);
extern const char *const cb_lbfgs_line_search_names[]; /* "armijo", "wolfe", NULL */

/* Vertex block descent's parameters (vbd, vbd-chebyshev; integrator_vbd.c). */
typedef struct cb_vbd_params {
  int cookie;      /* CB_PARAMS_COOKIE, set by cb_vbd_params_default() and checked by cb_integrator_alloc (params.h) */
  int iters;       /* sweeps over every vertex colour per step. Default 32 */
  int init;        /* initial guess: 0 inertia, 1 previous, 2 adaptive (cb_vbd_init_names). Default 2 */
  int line_search; /* backtracking on each vertex's own objective. Default 0 (the paper's update) */
  double rho;      /* vbd-chebyshev's rho in [0, 1), or CB_AUTO. Default 0.995 (0 for vbd) */
  int rho_iters;   /* plain sweeps of the `auto` estimate, run once. Default 64 */
  int collect;     /* sweeps between two collects of a term's moving elements (contact pairs) and their vertices'
                      displacement bounds (energy.h vertex_collect), >= 1. Default 1 */
} cb_vbd_params;
cb_vbd_params cb_vbd_params_default(void);    /* vbd-chebyshev's */
extern const char *const cb_vbd_init_names[]; /* "inertia", "previous", "adaptive", NULL */

/* Shape matching's parameters (shape_matching, integrator_shape_matching.c). */
typedef struct cb_shape_matching_params {
  int cookie;   /* CB_PARAMS_COOKIE, set by cb_shape_matching_params_default() and checked by cb_integrator_alloc
                   (params.h) */
  double alpha; /* pull toward the goals, in (0, 1]. Default 1 */
} cb_shape_matching_params;

cb_shape_matching_params cb_shape_matching_params_default(void);

typedef struct cb_integrator cb_integrator;

/* A type's config keys, `integrator.<name>`, are cb_param_key tables (params.h). */

/* What a type needs from the wrapper. */
enum {
  CB_INTEGRATOR_LINEAR_SOLVER = 1u,  /* solves with the linear solver named at alloc (analysed there, once) */
  CB_INTEGRATOR_HESSIAN = 2u,        /* assembles the system's matrix M/dt^2 + H into scene->sys.A, so a
                                        caller sharing that matrix knows a step overwrites it */
  CB_INTEGRATOR_OWN_ELASTICITY = 4u, /* ignores the scene's elastic terms (shape matching's goals replace
                                       them): a run's energy bound counts kinetic + gravity only */
  CB_INTEGRATOR_HISTORY = 8u,        /* a step reads what earlier steps left (VBD's adaptive initial guess uses the
                                        last step's velocity): a fresh integrator's first step is not a typical one,
                                        so a benchmark of one step warms it with an untimed step first */
  CB_INTEGRATOR_STEP_FILTER = 16u,   /* calls the line-search filter (cb_system_max_step, system.h) on every update, so
                                        a term with a step bound (contact.method = ipc) may be in its scene; the wrapper
                                        refuses such a scene for the other types */
  CB_INTEGRATOR_VERTEX_BOUNDS = 32u  /* keeps every vertex within the conservative displacement bounds of the terms
                                        that give them (cb_term_type.vertex_bound, energy.h), so no move reaches a
                                        contact: a term with a step bound that also gives vertex bounds may be in
                                        its scene without the line-search filter (vbd, vbd-chebyshev) */
};

/* A plug-in (gsl_multiroot_fsolver_type style). The wrapper allocates the
 * state (`size` bytes, zeroed) and the parameters (`params_size` bytes, a
 * copy of what the caller gives, or of `params_default`), so a type file
 * never touches the wrapper. */
typedef struct cb_integrator_type {
  const char *name;
  unsigned flags;             /* CB_INTEGRATOR_* */
  size_t size;                /* bytes of it->state */
  size_t params_size;         /* bytes of it->type_params; 0 = the type has none */
  const void *params_default; /* the type's defaults (params_size bytes), or NULL */
  const cb_param_key *keys;   /* its config keys (ended by a NULL name), or NULL for none */
  /* Sets up it->state (workspaces) and checks it->type_params against the
   * scene; on failure it leaves what free can release. */
  int (*init)(cb_integrator *it);
  /* Advances (x, v) by one step in place. */
  int (*step)(cb_integrator *it, double *x, double *v, cb_step_stats *st);
  void (*free)(cb_integrator *it); /* frees what init allocated, not it->state itself */
} cb_integrator_type;

struct cb_integrator {
  const cb_integrator_type *type;
  const cb_scene *scene;
  cb_system *sys; /* the scene's system (matrix values are scratch) */
  cb_integrator_params params;
  void *type_params; /* the type's parameters (e.g. cb_newton_params *); NULL if none */
  cb_solver *solver; /* owned; NULL unless the type's flags ask for one */
  void *state;       /* the type's state */
  double *coords;    /* 3 nfree: the free vertices' positions at the start of the step, for a solver that reads
                        them (CB_SOLVER_USES_COORDS: solver->coords points here); NULL otherwise */
  double *x_start;   /* 3 nv: the positions at the start of the current step, for the post-step responses */
};

/* The number of vertex colours of a vbd or vbd-chebyshev integrator (its
 * Gauss-Seidel order, computed once per scene), or -1 for another type. */
int cb_vbd_colors(const cb_integrator *it);
/* The vertex updates of its last step that a displacement bound shortened (contact: docs/contact.md), or -1 for
 * another type. */
long cb_vbd_truncated(const cb_integrator *it);

/* The registry (lib/core/integrator/integrator.c, one X(id) line per type), NULL-terminated;
 * a type is reached by its name (cb_integrator_type_find), never by a symbol. */
extern const cb_integrator_type *const cb_integrator_types[];
const char *cb_integrator_name(int i);
const cb_integrator_type *cb_integrator_type_find(const char *name);

/* Builds the integrator named by method for a scene. type_params points to
 * the type's parameter struct (cb_newton_params for newton), or is NULL for
 * the type's defaults. solver names a registered linear solver for types
 * that need one (CB_INTEGRATOR_LINEAR_SOLVER; its symbolic analysis runs
 * here, once) and is ignored by the others. lib/config/bind.h builds one from
 * a config (cb_integrator_from_config). */
int cb_integrator_alloc(const char *method, cb_scene *scene, const cb_integrator_params *p, const void *type_params,
                        const char *solver, const cb_solver_params *sp, cb_integrator **out);
/* One step of the type, then the scene's post-step responses (scene.h). */
int cb_integrator_step(cb_integrator *it, double *x, double *v, cb_step_stats *st);

/* The measurement that the fixed-iteration methods on F (pd, vbd, xpbd) make
 * at an iterate x, for their step stats and their hook: F(x) and |grad F(x)|
 * (gF: 3 nfree scratch, receives grad F) into st, with rel_grad =
 * |grad F| / *g0 (iter 0 sets *g0) and rel_grad_hat the same, or
 * |grad F| / g_hat when g_hat >= 0 (a method whose first iterate is not
 * xhat); newton_iters = iter; the evaluation's time added to assemble_ms.
 * Then hook's CB_NEWTON_GRADIENT event (iter, F, |grad F|, rel_grad, x), if
 * hook is not NULL. Returns CB_DIVERGED, before any event, when F or
 * |grad F| is not finite; else CB_OK. */
int cb_integrator_measure(const cb_integrator *it, cb_objective *o, const double *x, double *gF, int iter, double *g0,
                          double g_hat, cb_newton_hook hook, cb_step_stats *st);
void cb_integrator_free(cb_integrator *it);

#endif
