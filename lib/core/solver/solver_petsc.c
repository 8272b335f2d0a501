/* PETSc's Krylov methods and preconditioners as one solver family
 * (KSP/PC; DESIGN.md, "Solvers from libraries").
 *
 *   analyze(pattern)  the AIJ matrix (block size 3) preallocated from our CSC
 *                     pattern, which holds both triangles and so reads as CSR;
 *                     a KSP with its own options database, filled from the
 *                     preset's options and then solver.petsc's (later wins)
 *   factor(values)    the values copied in; the preconditioner is set up again
 *                     at every factorisation (solver.pc_reuse = iteration)
 *                     or at a step's first once in solver.pc_reuse_steps
 *                     steps (step), or as the preset chose (auto), and
 *                     reused in between
 *                     (PCSetReusePreconditioner); at each set-up the matrix
 *                     gets the rigid-body modes of the step's vertex
 *                     positions as its near-null space (solver.rigid_modes)
 *   solve(b, x)       KSPSolve from the initial guess x, stopped at the
 *                     relative residual |b - A x| / |b| <= solver.tol (the
 *                     unpreconditioned norm where the Krylov method has it);
 *                     the true residual is computed afterwards and decides
 *
 * Registered names (each one registry line): `petsc` (solver.petsc alone,
 * default "-ksp_type cg -pc_type gamg"), and the presets `petsc-gamg`
 * (smoothed aggregation), `petsc-hypre` (BoomerAMG with nodal coarsening),
 * `petsc-ml` (Trilinos ML) and `petsc-icc` (incomplete Cholesky, shifted to
 * stay positive definite), each CG with that preconditioner; solver.petsc's
 * options are applied after a preset's, so they can change any of them.
 *
 * Options live in PETSc's one database under a prefix of the solver's own
 * (cb<k>_), which its KSP passes to its PC and to what they create (a
 * multigrid's levels), and are cleared when the solver is freed.
 *
 * PETSc is loaded when the first PETSc solver is made (dlopen of
 * libpetsc_real.so), never before: linking it would load about a hundred
 * shared libraries (MPI among them) into every program, 150 ms at each start,
 * whether it solves with PETSc or not. PetscInitialize runs once per process,
 * without PETSc's signal handlers, with errors returned (never printed or
 * aborted on), and a KSP reads only options under its own prefix: the
 * environment (PETSC_OPTIONS, .petscrc) does not change a run unless it names
 * that prefix, so runs stay reproducible.
 * PETSc's errors and its KSP's reasons become our statuses: a diverged or
 * stopped solve is CB_NOT_CONVERGED (CB_INDEFINITE for an indefinite matrix
 * or preconditioner, CB_DIVERGED for a residual that grew past 1e5 |b| or went
 * NaN), named with PETSc's reason, never a crash. Threads: one per process, as
 * for every solver; MPI runs of one solve are not supported (PETSC_COMM_SELF).
 *
 * PETSc's own allocations are not counted by cb_alloc_fail_at (its
 * allocator is its own); ours are (the work struct, the index copies). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/solver.h>
#include <clothbench/status.h>

#if defined(CB_HAVE_PETSC) && defined(__has_include)
#if __has_include(<petscksp.h>) && __has_include(<dlfcn.h>)
#define CB_PETSC 1
#endif
#endif

#ifdef CB_PETSC
#include <dlfcn.h>
#include <petscksp.h>

/* Under LeakSanitizer (make san), what PETSc's MPI allocates while it is loaded and initialised is PETSc's, kept
 * for the process and partly owned by Open MPI components that are unloaded again, so no suppression can name
 * it: LSan ignores the allocations of this thread between these two calls. Ours are made outside them. */
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#define LSAN_OFF() __lsan_disable()
#define LSAN_ON() __lsan_enable()
#else
#define LSAN_OFF() ((void)0)
#define LSAN_ON() ((void)0)
#endif

#ifndef CB_PETSC_LIB
#define CB_PETSC_LIB "libpetsc_real.so"
#endif

/* The PETSc functions we call, looked up once: X(name). */
#define PETSC_FUNCS(X) \
  X(PetscInitializeNoArguments) \
  X(PetscInitialized) \
  X(PetscOptionsSetValue) \
  X(PetscPushErrorHandler) \
  X(PetscReturnErrorHandler) \
  X(PetscOptionsInsertString) \
  X(PetscOptionsClearValue) \
  X(KSPSetOptionsPrefix) \
  X(MatCreate) \
  X(MatSetSizes) \
  X(MatSetType) \
  X(MatSetBlockSize) \
  X(MatSeqAIJSetPreallocationCSR) \
  X(MatSeqAIJGetArray) \
  X(MatSeqAIJRestoreArray) \
  X(MatSetOption) \
  X(MatDestroy) \
  X(VecCreateSeqWithArray) \
  X(VecPlaceArray) \
  X(VecResetArray) \
  X(VecDestroy) \
  X(KSPCreate) \
  X(KSPSetOperators) \
  X(KSPSetTolerances) \
  X(KSPSetInitialGuessNonzero) \
  X(KSPSetNormType) \
  X(KSPSetFromOptions) \
  X(KSPGetPC) \
  X(KSPSetUp) \
  X(KSPSolve) \
  X(KSPGetIterationNumber) \
  X(KSPGetConvergedReason) \
  X(KSPDestroy) \
  X(PCSetReusePreconditioner) \
  X(PCSetUp) \
  X(MatNullSpaceCreateRigidBody) \
  X(MatSetNearNullSpace) \
  X(MatGetNearNullSpace) \
  X(MatNullSpaceGetVecs) \
  X(MatNullSpaceDestroy) \
  X(KSPMonitorSet) \
  X(KSPBuildSolution) \
  X(VecGetArrayRead) \
  X(VecRestoreArrayRead) \
  X(PetscErrorMessage)

static struct {
  int tried, ok;
  char why[512];
#define PETSC_FIELD(f) __typeof__(f) *f;
  PETSC_FUNCS(PETSC_FIELD)
#undef PETSC_FIELD
  const char *const *reasons; /* KSPConvergedReasons: indexed by the reason itself (negative ones too) */
  MPI_Comm self;              /* PETSC_COMM_SELF, which names a symbol of libmpi: looked up like the functions */
} P;

/* dlopen once, look every function up, PetscInitialize once. 0 or a status
 * whose message says what is missing. */
static int petsc_load_inner(void);
static int petsc_load(void) {
  if (P.tried) return P.ok ? CB_OK : cb_fail_status(CB_EINVAL, "%s", P.why);
  P.tried = 1;
  LSAN_OFF();
  int st = petsc_load_inner();
  LSAN_ON();
  return st;
}
static int petsc_load_inner(void) {
  void *h = dlopen(CB_PETSC_LIB, RTLD_NOW | RTLD_GLOBAL);
  if (!h) {
    snprintf(P.why, sizeof P.why, "PETSc solvers: cannot load %s (%s): install libpetsc-real-dev (make deps does)",
             CB_PETSC_LIB, dlerror());
    return cb_fail_status(CB_EINVAL, "%s", P.why);
  }
#define PETSC_LOOKUP(f) \
  if (!(*(void **)&P.f = dlsym(h, #f))) { \
    snprintf(P.why, sizeof P.why, "PETSc solvers: %s lacks %s", CB_PETSC_LIB, #f); \
    return cb_fail_status(CB_EINVAL, "%s", P.why); \
  }
  PETSC_FUNCS(PETSC_LOOKUP)
#undef PETSC_LOOKUP
  const char *const *const *reasons = dlsym(h, "KSPConvergedReasons"); /* a pointer variable into PETSc's table */
  P.reasons = reasons ? *reasons : NULL;
  void *comm_self = dlsym(h, "ompi_mpi_comm_self"); /* MPI_COMM_SELF of Open MPI, which Debian's PETSc uses */
  if (!comm_self) {
    snprintf(P.why, sizeof P.why, "PETSc solvers: %s's MPI is not Open MPI (no ompi_mpi_comm_self)", CB_PETSC_LIB);
    return cb_fail_status(CB_EINVAL, "%s", P.why);
  }
  P.self = (MPI_Comm)comm_self;
  PetscBool inited = PETSC_FALSE;
  P.PetscInitialized(&inited);
  if (!inited) {
    /* before PetscInitialize: no signal handlers (a crash must stay ours, and ASan's), no options report */
    P.PetscOptionsSetValue(NULL, "-no_signal_handler", "true");
    P.PetscOptionsSetValue(NULL, "-options_left", "false");
    /* Open MPI unloads the components it did not select; what they allocated then has no module a leak checker
     * can name (make san's tests/lsan.supp names Open MPI's): keep them loaded (unless the caller said otherwise) */
    setenv("OMPI_MCA_mca_base_component_disable_dlclose", "1", 0);
    if (P.PetscInitializeNoArguments()) {
      snprintf(P.why, sizeof P.why, "PETSc solvers: PetscInitialize failed");
      return cb_fail_status(CB_EINVAL, "%s", P.why);
    }
  }
  P.PetscPushErrorHandler(P.PetscReturnErrorHandler, NULL);
  P.ok = 1;
  return CB_OK;
}

/* A PETSc error code as our status, with PETSc's text. */
static int petsc_fail(PetscErrorCode e, const char *what) {
  const char *text = NULL;
  P.PetscErrorMessage(e, &text, NULL);
  if (e == PETSC_ERR_MEM) return cb_fail_status(CB_ENOMEM, "PETSc %s: out of memory", what);
  return cb_fail_status(CB_EINVAL, "PETSc %s: %s (error %d)", what, text ? text : "?", (int)e);
}
#define PCALL(expr, what) \
  do { \
    PetscErrorCode e_ = (expr); \
    if (e_) return petsc_fail(e_, what); \
  } while (0)

typedef struct {
  cb_solver *s;
  double bnorm;
} petsc_monitor_ctx;

typedef struct {
  const char *preset; /* the preset's options, applied before solver.petsc's */
  int reuse_steps;    /* solver.pc_reuse = auto: the preset's choice, set up once in this many steps (0: at every
                         factorisation, i.e. every Newton iteration) */
  Mat A;
  KSP ksp;
  Vec b, x;
  Vec xc;          /* the vertices' coordinates (block size 3) over solver->coords: the rigid-body modes' source */
  char prefix[32]; /* cb<k>_: this solver's options in PETSc's database, and nobody else's */
  char *names;     /* the option names it put there (NUL-separated), cleared when it is freed */
  size_t names_len;
  PetscInt *rowp, *coli; /* our pattern as PetscInt (a copy only when PetscInt is not int) */
  petsc_monitor_ctx mon;
  long factors;    /* factorisations since analyze (or forget) */
  long setup_step; /* solver->step at the last preconditioner set-up */
  double *r;       /* n: the residual b - A x after a solve (allocated at analyze: a step never allocates) */
} petsc_work;

static void petsc_free(cb_solver *s) {
  petsc_work *w = s->work;
  if (!w) return;
  if (P.ok) {
    if (w->ksp) P.KSPDestroy(&w->ksp);
    if (w->A) P.MatDestroy(&w->A);
    if (w->b) P.VecDestroy(&w->b);
    if (w->x) P.VecDestroy(&w->x);
    if (w->xc) P.VecDestroy(&w->xc);
    for (size_t k = 0; w->names && k < w->names_len; k += strlen(w->names + k) + 1)
      P.PetscOptionsClearValue(NULL, w->names + k);
  }
  free(w->names);
  free(w->r);
  if ((void *)w->rowp != NULL && sizeof(PetscInt) != sizeof(int)) {
    free(w->rowp);
    free(w->coli);
  }
  free(w);
  s->work = NULL;
}

/* "-ksp_type cg -pc_type gamg" -> PETSc's options database under this
 * solver's prefix ("-cb3_ksp_type cg -cb3_pc_type gamg"), so that its KSP,
 * its PC and what they create (a multigrid's levels: -cb3_mg_levels_...)
 * read them, and no other object does; later options override earlier ones.
 * A token that starts with '-' and a letter is an option name; any other is
 * a value. The names are kept to be cleared when the solver is freed. */
static int petsc_options(petsc_work *w, const char *text) {
  if (!text || !*text) return CB_OK;
  size_t n = strlen(text), cap = 2 * n + 64 * (n / 2 + 1);
  char *buf = cb_malloc(cap, 1);
  if (!buf) return CB_ENOMEM;
  size_t u = 0;
  for (const char *p = text; *p;) {
    while (*p == ' ' || *p == '\t' || *p == '\n') buf[u++] = *p++;
    if (!*p) break;
    const char *t = p;
    while (*p && *p != ' ' && *p != '\t' && *p != '\n') p++;
    if (t[0] == '-' && ((t[1] >= 'a' && t[1] <= 'z') || (t[1] >= 'A' && t[1] <= 'Z'))) {
      size_t len = (size_t)(p - t) + strlen(w->prefix);
      char *nn = realloc(w->names, w->names_len + len + 1);
      if (!nn) {
        free(buf);
        return CB_ENOMEM;
      }
      w->names = nn;
      snprintf(w->names + w->names_len, len + 1, "-%s%.*s", w->prefix, (int)(p - t - 1), t + 1);
      w->names_len += len + 1;
      u += (size_t)snprintf(buf + u, cap - u, "-%s", w->prefix);
      t++;
    }
    memcpy(buf + u, t, (size_t)(p - t));
    u += (size_t)(p - t);
  }
  buf[u] = '\0';
  PetscErrorCode e = P.PetscOptionsInsertString(NULL, buf);
  free(buf);
  if (e) return petsc_fail(e, "options");
  return CB_OK;
}

static int petsc_alloc_preset(cb_solver *s, int n, const char *preset, int reuse_steps) {
  (void)n;
  int st = petsc_load();
  if (st) return st;
  petsc_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  s->work = w;
  w->preset = preset;
  w->reuse_steps = reuse_steps;
  static unsigned long instances; /* a prefix per solver object of the process */
  snprintf(w->prefix, sizeof w->prefix, "cb%lu_", ++instances);
  return CB_OK;
}

/* KSP's monitor: every iteration's relative residual into the history and to
 * the caller's monitor with the iterate, as the other iterative solvers do
 * (solver_iterative.h). rnorm is the KSP's norm: the true residual's where
 * the method has it (unpreconditioned CG). */
static PetscErrorCode petsc_monitor(KSP ksp, PetscInt k, PetscReal rnorm, void *ctx) {
  petsc_monitor_ctx *m = ctx;
  cb_solver *s = m->s;
  double rel = m->bnorm > 0 ? rnorm / m->bnorm : rnorm;
  if (s->stats.history && s->stats.history_len < s->params.history_cap) s->stats.history[s->stats.history_len++] = rel;
  if (s->params.monitor) {
    Vec v = NULL;
    const PetscScalar *xv = NULL;
    if (!P.KSPBuildSolution(ksp, NULL, &v) && !P.VecGetArrayRead(v, &xv)) {
      s->params.monitor(s->params.monitor_ctx, (int)k, rel, xv);
      P.VecRestoreArrayRead(v, &xv);
    }
  }
  return 0;
}

static int petsc_analyze(cb_solver *s, const cb_sparse *A) {
  petsc_work *w = s->work;
  if (w->ksp) P.KSPDestroy(&w->ksp);
  if (w->A) P.MatDestroy(&w->A);
  if (w->b) P.VecDestroy(&w->b);
  if (w->x) P.VecDestroy(&w->x);
  if (w->xc) P.VecDestroy(&w->xc);
  if (!w->r && !(w->r = cb_malloc((size_t)A->n, sizeof *w->r))) return CB_ENOMEM;
  if (sizeof(PetscInt) == sizeof(int)) {
    w->rowp = (PetscInt *)A->colp; /* both triangles: the CSC arrays read as CSR */
    w->coli = (PetscInt *)A->rowi;
  } else {
    if (!w->rowp) {
      w->rowp = cb_malloc((size_t)A->n + 1, sizeof *w->rowp);
      w->coli = cb_malloc((size_t)A->nnz, sizeof *w->coli);
      if (!w->rowp || !w->coli) return CB_ENOMEM;
    }
    for (int i = 0; i <= A->n; i++) w->rowp[i] = A->colp[i];
    for (int k = 0; k < A->nnz; k++) w->coli[k] = A->rowi[k];
  }
  /* the options go in once everything of ours is allocated: a run that fails before leaves PETSc untouched */
  if (!w->names) {
    int st = petsc_options(w, w->preset);
    if (!st) st = petsc_options(w, s->params.petsc_options);
    if (st) return cb_fail_status(st, "solver.petsc: %s", cb_error_message());
  }
  PCALL(P.MatCreate(P.self, &w->A), "MatCreate");
  PCALL(P.MatSetSizes(w->A, A->n, A->n, A->n, A->n), "MatSetSizes");
  PCALL(P.MatSetType(w->A, MATSEQAIJ), "MatSetType");
  PCALL(P.MatSetBlockSize(w->A, 3), "MatSetBlockSize"); /* one vertex's x, y, z: AMG's nodes */
  PCALL(P.MatSeqAIJSetPreallocationCSR(w->A, w->rowp, w->coli, A->val), "preallocation");
  PCALL(P.MatSetOption(w->A, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
  PCALL(P.MatSetOption(w->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
  PCALL(P.VecCreateSeqWithArray(P.self, 3, A->n, NULL, &w->b), "VecCreate");
  PCALL(P.VecCreateSeqWithArray(P.self, 3, A->n, NULL, &w->x), "VecCreate");
  PCALL(P.VecCreateSeqWithArray(P.self, 3, A->n, NULL, &w->xc), "VecCreate");
  PCALL(P.KSPCreate(P.self, &w->ksp), "KSPCreate");
  PCALL(P.KSPSetOptionsPrefix(w->ksp, w->prefix), "options");
  PCALL(P.KSPSetOperators(w->ksp, w->A, w->A), "KSPSetOperators");
  PCALL(P.KSPSetTolerances(w->ksp, s->params.tol, 0.0, 1e5, s->params.max_iters), "KSPSetTolerances");
  PCALL(P.KSPSetInitialGuessNonzero(w->ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
  w->mon.s = s;
  if (s->params.monitor || s->params.history_cap > 0)
    PCALL(P.KSPMonitorSet(w->ksp, petsc_monitor, &w->mon, NULL), "KSPMonitorSet");
  PCALL(P.KSPSetFromOptions(w->ksp), "solver.petsc");
  /* the true residual where the method has it (CG does); a method that does not keeps its own norm, and the
   * residual computed after the solve decides */
  if (P.KSPSetNormType(w->ksp, KSP_NORM_UNPRECONDITIONED)) P.KSPSetFromOptions(w->ksp);
  w->factors = 0;
  s->stats.pc_setups = 0;
  s->stats.near_null = 0;
  return CB_OK;
}

/* Whether the six rigid-body modes of nv points c are linearly independent, which PETSc's orthonormalisation needs.
 * The translations always are, and are orthogonal to the rotations about the centroid; the rotations w x (p - g)
 * have the Gram matrix w^T (tr(S) I - S) w, S = sum (p - g)(p - g)^T, singular only when two of S's eigenvalues
 * vanish (collinear points, a chain): then the sum of S's principal 2x2 minors, s1 s2 + s1 s3 + s2 s3, vanishes
 * too. Independent: that sum above 1e-12 tr(S)^2. */
static int rigid_modes_independent(const double *c, int nv) {
  if (nv < 3) return 0;
  double g[3] = {0, 0, 0}, S[3][3] = {{0}};
  for (int i = 0; i < nv; i++)
    for (int a = 0; a < 3; a++) g[a] += c[3 * i + a] / nv;
  for (int i = 0; i < nv; i++)
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) S[a][b] += (c[3 * i + a] - g[a]) * (c[3 * i + b] - g[b]);
  double tr = S[0][0] + S[1][1] + S[2][2];
  double m2 = S[0][0] * S[1][1] - S[0][1] * S[0][1] + S[0][0] * S[2][2] - S[0][2] * S[0][2] + S[1][1] * S[2][2] -
              S[1][2] * S[1][2];
  return isfinite(tr) && tr > 0 && m2 > 1e-12 * tr * tr;
}

/* The six rigid-body modes of the vertices at solver->coords (three translations, three infinitesimal rotations
 * about their centroid, orthonormalised by PETSc: MatNullSpaceCreateRigidBody) as the matrix's near-null space,
 * which GAMG's aggregation interpolates exactly: an elastic solid's Hessian maps them to zero, so the coarse spaces
 * must carry them or the smoother is left with the slowest modes. Then stats.near_null is what PETSc reports back. */
static int rigid_modes_independent(const double *c, int nv);
static int petsc_near_null(cb_solver *s, petsc_work *w) {
  if (s->params.rigid_modes && s->coords && rigid_modes_independent(s->coords, s->n / 3)) {
    MatNullSpace nsp = NULL;
    PCALL(P.VecPlaceArray(w->xc, s->coords), "VecPlaceArray");
    PetscErrorCode e = P.MatNullSpaceCreateRigidBody(w->xc, &nsp);
    P.VecResetArray(w->xc);
    if (e) return petsc_fail(e, "MatNullSpaceCreateRigidBody");
    e = P.MatSetNearNullSpace(w->A, nsp);
    P.MatNullSpaceDestroy(&nsp); /* the matrix holds its own reference */
    if (e) return petsc_fail(e, "MatSetNearNullSpace");
  } else PCALL(P.MatSetNearNullSpace(w->A, NULL), "MatSetNearNullSpace");
  MatNullSpace q = NULL;
  PCALL(P.MatGetNearNullSpace(w->A, &q), "MatGetNearNullSpace");
  s->stats.near_null = 0;
  if (q) {
    PetscBool has_const = PETSC_FALSE;
    PetscInt nv = 0;
    const Vec *v = NULL;
    PCALL(P.MatNullSpaceGetVecs(q, &has_const, &nv, &v), "MatNullSpaceGetVecs");
    s->stats.near_null = (int)nv + (has_const ? 1 : 0);
  }
  return CB_OK;
}

static int petsc_factor(cb_solver *s, const cb_sparse *A) {
  petsc_work *w = s->work;
  if (!w->A) {
    int st = petsc_analyze(s, A);
    if (st) return st;
  }
  PetscScalar *a;
  PCALL(P.MatSeqAIJGetArray(w->A, &a), "MatSeqAIJGetArray");
  memcpy(a, A->val, (size_t)A->nnz * sizeof *a);
  PCALL(P.MatSeqAIJRestoreArray(w->A, &a), "MatSeqAIJRestoreArray");
  PC pc;
  PCALL(P.KSPGetPC(w->ksp, &pc), "KSPGetPC");
  /* solver.pc_reuse: set up at every factorisation (iteration), or at the first of a step once in pc_reuse_steps
   * steps (step; solver->step is the integrator's count, and stays 0 without one: then set up once) */
  int mode = s->params.pc_reuse, steps = s->params.pc_reuse_steps > 0 ? s->params.pc_reuse_steps : 1;
  if (mode == CB_PC_REUSE_AUTO) { /* the preset's choice (docs/solvers-petsc.md's reuse table) */
    mode = w->reuse_steps > 0 ? CB_PC_REUSE_STEP : CB_PC_REUSE_ITERATION;
    steps = w->reuse_steps > 0 ? w->reuse_steps : 1;
  }
  int reuse = w->factors > 0 && mode == CB_PC_REUSE_STEP && s->step - w->setup_step < steps;
  PCALL(P.PCSetReusePreconditioner(pc, reuse ? PETSC_TRUE : PETSC_FALSE), "PCSetReusePreconditioner");
  w->factors++;
  if (!reuse) {
    int st = petsc_near_null(s, w);
    if (st) return st;
    /* KSPSetUp sets the PC up only at the first call (or after new operators); PCSetUp itself sees the values
     * changed (the matrix's state) and builds now, so factor_ms holds the set-up and solve_ms the solve alone */
    PetscErrorCode e = P.KSPSetUp(w->ksp);
    if (!e) e = P.PCSetUp(pc);
    if (e) return petsc_fail(e, "preconditioner set-up");
    w->setup_step = s->step;
    s->stats.pc_setups++;
  }
  return CB_OK;
}

/* The next factor() sets the preconditioner up, as the first after analyze() (cb_solver_forget). */
static void petsc_forget(cb_solver *s) {
  petsc_work *w = s->work;
  if (w) w->factors = 0;
}

static const char *reason_name(KSPConvergedReason r) {
  if (P.reasons && r >= KSP_DIVERGED_PC_FAILED && r <= KSP_CONVERGED_STEP_LENGTH) return P.reasons[r];
  return "unknown reason";
}

static int petsc_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  petsc_work *w = s->work;
  double bb = 0;
  for (int i = 0; i < A->n; i++) bb += b[i] * b[i];
  w->mon.bnorm = sqrt(bb);
  PCALL(P.VecPlaceArray(w->b, b), "VecPlaceArray");
  PCALL(P.VecPlaceArray(w->x, x), "VecPlaceArray");
  PetscErrorCode e = P.KSPSolve(w->ksp, w->b, w->x);
  P.VecResetArray(w->b);
  P.VecResetArray(w->x);
  if (e) return petsc_fail(e, "KSPSolve");
  PetscInt its = 0;
  KSPConvergedReason why = KSP_CONVERGED_ITERATING;
  P.KSPGetIterationNumber(w->ksp, &its);
  P.KSPGetConvergedReason(w->ksp, &why);
  s->stats.iters = (int)its;
  double rel = cb_relative_residual(A, b, x, w->r);
  s->stats.rel_residual = rel;
  if (!isfinite(rel) || why == KSP_DIVERGED_NANORINF || why == KSP_DIVERGED_DTOL)
    return cb_fail_status(CB_DIVERGED, "PETSc KSP diverged (%s) after %d iterations, relative residual %g",
                          reason_name(why), (int)its, rel);
  if (why == KSP_DIVERGED_INDEFINITE_PC || why == KSP_DIVERGED_INDEFINITE_MAT)
    return cb_fail_status(CB_INDEFINITE,
                          "PETSc KSP: %s after %d iterations (A or its preconditioner is not "
                          "positive definite)",
                          reason_name(why), (int)its);
  if (rel > s->params.tol)
    return cb_fail_status(CB_NOT_CONVERGED,
                          "PETSc KSP stopped (%s) after %d iterations at relative residual %g > "
                          "solver.tol %g",
                          reason_name(why), (int)its, rel, s->params.tol);
  return CB_OK;
}

#define PETSC_PRESET(id, opts, reuse_steps) \
  static int id##_alloc(cb_solver *s, int n) { return petsc_alloc_preset(s, n, opts, reuse_steps); }
#else /* built without PETSc's headers: the names exist, and say what to install */
static int petsc_missing(void) {
  return cb_fail_status(CB_EINVAL, "PETSc solvers: this build has no PETSc (libpetsc-real-dev was not installed when "
                                   "it was compiled): run make deps, then make clean all");
}
#define PETSC_PRESET(id, opts, reuse_steps) \
  static int id##_alloc(cb_solver *s, int n) { \
    (void)s; \
    (void)n; \
    (void)opts; \
    (void)(reuse_steps); \
    return petsc_missing(); \
  }
static int petsc_analyze(cb_solver *s, const cb_sparse *A) {
  (void)s;
  (void)A;
  return petsc_missing();
}
static int petsc_factor(cb_solver *s, const cb_sparse *A) { return petsc_analyze(s, A); }
static int petsc_solve(cb_solver *s, const cb_sparse *A, const double *b, double *x) {
  (void)b;
  (void)x;
  return petsc_analyze(s, A);
}
static void petsc_free(cb_solver *s) { free(s->work); }
static void petsc_forget(cb_solver *s) { (void)s; }
#endif

/* GAMG's levels smoothed by SOR: its default Chebyshev-Jacobi smoother, whose eigenvalue estimate falls short,
 * made the preconditioner indefinite on the hanging cloth at 64^2 (step 5: DIVERGED_INDEFINITE_PC), with the
 * rigid-body modes too. With them, an aggregate of one or two vertices cannot carry six independent modes, so its
 * surplus coarse unknowns get zero columns of the interpolation and zero rows (and diagonals) on the coarse levels,
 * on which SOR stopped (zero pivot: DIVERGED_PC_FAILED at 32^2); the shift of 1e-12 added to SOR's diagonal makes
 * such a row's update 0 / 1e-12 = 0 and is nothing beside the others' (M/dt^2 alone is 900 kg/s^2 per vertex). */
#define GAMG_OPTS \
  "-ksp_type cg -pc_type gamg -mg_levels_ksp_type richardson -mg_levels_pc_type sor -mg_levels_pc_sor_diagonal_shift " \
  "1e-12"
/* The last number: solver.pc_reuse = auto's choice, measured on the hanging cloth at 128^2 over 10 steps
 * (docs/solvers-petsc.md): 0 sets the preconditioner up at every Newton iteration, k once in k steps. GAMG: every
 * step (1.7x faster than every iteration, the same Krylov iterations); BoomerAMG: every iteration (reused, its
 * iterations grew 1.3x in a step, 3.8x over 5 steps); ML: every 5 steps (its set-up is the costly part, and 5
 * steps' reuse added 4% of iterations); ICC: every iteration (its set-up is cheap, reuse over 5 steps cost 3x the
 * iterations). */
PETSC_PRESET(generic, GAMG_OPTS, 0) /* `petsc`: solver.petsc says what, so no reuse unless asked */
PETSC_PRESET(gamg, GAMG_OPTS, 1)
PETSC_PRESET(hypre, "-ksp_type cg -pc_type hypre -pc_hypre_type boomeramg -pc_hypre_boomeramg_nodal_coarsen 1", 0)
PETSC_PRESET(ml, "-ksp_type cg -pc_type ml", 5)
PETSC_PRESET(icc, "-ksp_type cg -pc_type icc -pc_factor_shift_type positive_definite", 0)

#define PETSC_TYPE(id, name_) \
  const cb_solver_type cb_solver_petsc_##id = {.name = name_, \
                                               .flags = CB_SOLVER_LIBRARY_HEAP | CB_SOLVER_USES_COORDS, \
                                               .alloc = id##_alloc, \
                                               .analyze = petsc_analyze, \
                                               .factor = petsc_factor, \
                                               .solve = petsc_solve, \
                                               .free = petsc_free, \
                                               .forget = petsc_forget};
PETSC_TYPE(generic, "petsc")
PETSC_TYPE(gamg, "petsc-gamg")
PETSC_TYPE(hypre, "petsc-hypre")
PETSC_TYPE(ml, "petsc-ml")
PETSC_TYPE(icc, "petsc-icc")
