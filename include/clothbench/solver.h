/* Linear solvers for A dx = b behind one interface, as a table of plug-ins
 * (gsl_multiroot_fsolver_type style): analyze(pattern) once per run, then
 * factor(values) once per Newton iteration, then solve(b, x).
 *
 * For iterative solvers `factor` builds the diagonal or preconditioner. Every
 * solver fills the same statistics: iterations, residual history, times and a
 * status. A matrix that is not positive definite, a breakdown or a divergence
 * is a positive status, never a crash. */
#ifndef CB_SOLVER_H
#define CB_SOLVER_H

#include "params.h"
#include "sparse.h"

/* Optional per-iteration callback of the iterative solvers: called after the
 * stopping test of iteration k (k = 0 for the initial guess) with the relative
 * residual |b - A x_k| / |b| and the iterate x_k (read only; n doubles). It
 * lets a caller measure the error of every iterate against a reference
 * without changing the solve. Direct solvers do not call it. */
typedef void (*cb_solver_monitor)(void *ctx, int k, double rel_residual, const double *x);

typedef struct cb_solver_params {
  int cookie;      /* CB_PARAMS_COOKIE, set by cb_solver_params_default() and checked by cb_solver_alloc (params.h) */
  double tol;      /* relative residual |b - Ax| / |b| to stop at (iterative). Default 1e-8 */
  int max_iters;   /* iterations at most (iterative). Default 1000 */
  double alpha;    /* Jacobi and Chebyshev weight, > 0, or CB_AUTO: alpha* = 2/(lambda_min + lambda_max) of
                      D^-1 A, estimated at run time. Default CB_AUTO (as solver.alpha's; until issue 32 the C
                      default was 1, vanilla Jacobi, which diverges where lambda_max(D^-1 A) >= 2) */
  double rho;      /* Chebyshev spectral radius in (0, 1), or CB_AUTO: estimated at run time. Default CB_AUTO */
  int history_cap; /* residuals kept per solve (0 = none). Default 0 */
  int ordering;    /* CHOLMOD: CB_ORDER_*. Default CB_ORDER_NESDIS (bench_core_cholmod.csv) */
  int nrelax[3];   /* CHOLMOD supernode relaxation (Common->nrelax). Default {16, 64, 128} (CHOLMOD's: 4, 16, 48) */
  int upper;       /* CHOLMOD reads a copy of the upper triangle (1) or the full matrix (0). Default 1 */
  int flush_denormals;      /* CHOLMOD: subnormal numbers read and produced as zero (x86 FTZ/DAZ) on the calling
                               thread during factorize and solve (1), or kept (0). Default 1 (bench_core_cholmod.csv) */
  int rho_reuse;            /* rho = auto / alpha = auto: reuse the last estimate while D stays put (1), or estimate at
                               every factor (0, the behaviour before the estimate was amortised). Default 1 */
  int residual;             /* direct solvers: compute stats.rel_residual = |b - Ax|/|b| after each solve (1, one more
                               product with A inside the solve), or leave it NaN (0: a caller that solves with one
                               constant factor many times a step, pd and lbfgs, and does not read it). Default 1 */
  char petsc_options[1024]; /* PETSc solvers: options for their KSP and PC, after the preset's (e.g. "-ksp_type cg
                              -pc_type gamg -pc_gamg_threshold 0.02"). Default "" */
  int pc_reuse;       /* PETSc solvers: CB_PC_REUSE_ITERATION (the preconditioner set up at every factorisation, i.e.
                         every Newton iteration), CB_PC_REUSE_STEP (set up at the first factorisation of a time step
                         once in pc_reuse_steps steps, reused by the others) or CB_PC_REUSE_AUTO (the preset's choice,
                         solver_petsc.c). Default CB_PC_REUSE_AUTO */
  int pc_reuse_steps; /* PETSc solvers, CB_PC_REUSE_STEP: set up once in this many time steps. Default 1 */
  int rigid_modes;    /* PETSc solvers: give the matrix the six rigid-body modes of solver->coords as its near-null
                         space (MatSetNearNullSpace; GAMG reads it) when the preconditioner is set up (1), or none
                         (0). Default 0 (docs/solvers-petsc.md measures both) */
  cb_solver_monitor monitor; /* per-iteration callback; NULL = none. Default NULL */
  void *monitor_ctx;
} cb_solver_params;

/* solver.pc_reuse */
enum { CB_PC_REUSE_AUTO = 0, CB_PC_REUSE_ITERATION = 1, CB_PC_REUSE_STEP = 2 };

/* solver.ordering: CHOLMOD's own choice (nmethods = 0), or one method. */
enum { CB_ORDER_DEFAULT = 0, CB_ORDER_AMD, CB_ORDER_METIS, CB_ORDER_NESDIS };
const char *cb_order_name(int ordering);

cb_solver_params cb_solver_params_default(void);

typedef struct cb_solve_stats {
  int status;          /* CB_OK, CB_NOT_SPD, CB_NOT_CONVERGED, CB_DIVERGED, CB_INDEFINITE */
  int iters;           /* iterations of the last solve (1 for a direct solve) */
  double rel_residual; /* |b - Ax| / |b| after the last solve */
  double analyze_ms;   /* symbolic analysis (once) */
  double factor_ms;    /* last numeric factorisation / preconditioner set-up (includes setup_ms) */
  double solve_ms;     /* last solve */
  double setup_ms;     /* part of factor_ms spent estimating rho (Chebyshev with rho = auto) */
  double rho;          /* Chebyshev: the rho used (estimated or given) */
  int rho_steps;       /* Lanczos steps of the rho estimates in the last factor and solve */
  int rho_estimates;   /* Lanczos runs in the last factor and solve: 0 when the last bounds were reused,
                          2 when a solve on a reused estimate restarted with a fresh one */
  double rho_ms;       /* their time (a restart's estimate also counts in solve_ms) */
  double alpha;        /* Jacobi/Chebyshev: the weight used (alpha* with alpha = auto) */
  double factor_nnz;   /* nonzeros of the factor L (direct solvers) */
  double factor_flops; /* floating-point operations of one numeric factorisation (CHOLMOD's Common->fl) */
  int near_null;       /* PETSc solvers: vectors of the near-null space attached to the matrix at the last
                          preconditioner set-up, as PETSc reports it back (MatGetNearNullSpace): 6 rigid-body modes,
                          or 0 */
  int pc_setups;       /* PETSc solvers: preconditioner set-ups since analyze (the others reused one) */
  int history_len;     /* residuals recorded in history */
  double *history;     /* rel. residual after each iteration (history_cap entries) */
} cb_solve_stats;

typedef struct cb_solver cb_solver;

/* What a solver reads from cb_solver_params besides tol and max_iters, so
 * that sweeps and CSVs give alpha and rho only to solvers that use them. */
/* CB_SOLVER_LIBRARY_HEAP: the solver's library allocates through its own allocator and keeps bookkeeping for the
 * process that grows as its objects come and go (PETSc): its allocations are not counted by cb_alloc_fail_at and
 * the heap in use is not the same after a run as before (test_enomem.c). */
/* CB_SOLVER_USES_COORDS: the solver reads cb_solver.coords (the integrator that owns it keeps them). */
enum {
  CB_SOLVER_DIRECT = 1u,
  CB_SOLVER_USES_ALPHA = 2u,
  CB_SOLVER_USES_RHO = 4u,
  CB_SOLVER_LIBRARY_HEAP = 8u,
  CB_SOLVER_USES_COORDS = 16u
};

typedef struct cb_solver_type {
  const char *name;
  unsigned flags; /* CB_SOLVER_* */
  int (*alloc)(cb_solver *s, int n);
  int (*analyze)(cb_solver *s, const cb_sparse *A); /* symbolic analysis, once per pattern; NULL: none needed */
  int (*factor)(cb_solver *s, const cb_sparse *A);
  int (*solve)(cb_solver *s, const cb_sparse *A, const double *b, double *x);
  void (*free)(cb_solver *s);
  /* Drops what the solver carries from one factorisation to the next (an
   * amortised estimate, such as Chebyshev's reused spectral bounds), so the
   * next factor() works as the first one after analyze() did. NULL: the
   * solver carries nothing. */
  void (*forget)(cb_solver *s);
  /* Solves A X = B for nrhs right-hand sides at once: B and X column-major,
   * n x nrhs (column c at b + c n). A direct solver does it with one pass
   * over its factor (CHOLMOD's dense multi-column solve). NULL: the wrapper
   * cb_solver_solve_n calls solve once per column. */
  int (*solve_n)(cb_solver *s, const cb_sparse *A, int nrhs, const double *b, double *x);
} cb_solver_type;

struct cb_solver {
  const cb_solver_type *type;
  cb_solver_params params;
  cb_solve_stats stats;
  int n;
  void *work;
  /* Kept by the integrator that owns the solver (cb_integrator_step), read by solvers that want them; a caller
   * without an integrator may set them itself. */
  long step;            /* time steps begun so far (0: none counted) */
  const double *coords; /* n doubles: the position (x, y, z) of each unknown's vertex at the start of the step, in
                           the unknowns' order (CB_SOLVER_USES_COORDS); NULL: not known */
};

/* The registry (lib/core/solver/solver.c): one entry per plug-in file
 * (solver_<name>.c), NULL-terminated. solver.method in a config names one of
 * them; tests and experiments loop over all. */
extern const cb_solver_type *const cb_solver_types[];
/* i-th registered name, or NULL past the end (used for config choices). */
const char *cb_solver_name(int i);

const cb_solver_type *cb_solver_type_find(const char *name);
int cb_solver_alloc(const char *name, const cb_solver_params *p, int n, cb_solver **out);
int cb_solver_analyze(cb_solver *s, const cb_sparse *A);
int cb_solver_factor(cb_solver *s, const cb_sparse *A);
/* x holds the initial guess on entry for iterative solvers (set it to 0 for
 * the lecture's choice) and the solution on return. */
int cb_solver_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x);
/* A X = B with nrhs columns (column-major, column c at b + c n, x likewise; x holds the initial guesses of an
 * iterative solver). stats.iters sums the columns' iterations, stats.solve_ms is the whole call's time. */
int cb_solver_solve_n(cb_solver *s, const cb_sparse *A, int nrhs, const double *b, double *x);
void cb_solver_free(cb_solver *s);
/* The type's forget (above), if it has one: a computation that must not
 * depend on what the solver did before (one measured step, repeated a number
 * of times that depends on the clock) calls it first. */
void cb_solver_forget(cb_solver *s);

/* rho(I - alpha D^-1 A) estimated by Lanczos on D^-1/2 A D^-1/2 (dhalf =
 * D^-1/2), widened by the Ritz residual bounds; steps = Lanczos steps. */
int cb_jacobi_spectral_radius(const cb_sparse *A, const double *dhalf, double alpha, double *rho, int *steps);

/* |b - A x| / |b| (|b| = 0 gives |A x|). Uses work (n doubles). */
double cb_relative_residual(const cb_sparse *A, const double *b, const double *x, double *work);

#endif
