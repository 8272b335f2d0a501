/* The PETSc family's own choices (lib/core/solver/solver_petsc.c): the
 * rigid-body near-null space GAMG is given (solver.rigid_modes), queried
 * back through PETSc, and the solve with it against CHOLMOD's; when the
 * preconditioner is set up (solver.pc_reuse), counted against the steps and
 * factorisations the integrator reports. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"

/* The first Newton system of a step: b copied, A the system's (its values stay until the next assembly). */
typedef struct {
  const cb_sparse *A;
  double *b;
} sys_capture;

static void capture(void *ctx, int event, const cb_newton_event *ev) {
  sys_capture *c = ctx;
  if (event != CB_NEWTON_SYSTEM || c->b) return;
  c->A = ev->A;
  c->b = malloc((size_t)ev->A->n * sizeof(double));
  cr_assert_not_null(c->b);
  memcpy(c->b, ev->b, (size_t)ev->A->n * sizeof(double));
}

static int step(cb_integrator *it, cb_scene *s, double *x, double *v, cb_step_stats *st) {
  (void)s;
  return cb_integrator_step(it, x, v, st);
}

/* One Newton step of a 16^2 hanging cloth with the given solver sets; returns the integrator (x, v advanced). */
static cb_integrator *one_step(cb_scene *s, const char *const *extra, double *x, double *v, sys_capture *cap) {
  const char *sets[16] = {"mesh.n=16",
                          "scene.pins=top-corners",
                          "integrator.method=newton",
                          "integrator.dt=1/30",
                          "integrator.definiteness=drop",
                          "integrator.max_iters=1",
                          "integrator.tol=0",
                          "solver.tol=1e-10",
                          "solver.max_iters=10000"};
  int k = 9;
  for (int i = 0; extra && extra[i] && k < 15; i++) sets[k++] = extra[i];
  sets[k] = NULL;
  cb_integrator *it = test_integrator(sets, s, cap ? capture : NULL, cap);
  cb_step_stats st;
  int r = step(it, s, x, v, &st);
  cr_assert(r == CB_OK || r == CB_NOT_CONVERGED, "step: %s", cb_error_message());
  cr_assert_eq(st.linear_status, CB_OK, "linear solve: %s", cb_error_message());
  return it;
}

static cb_scene *sheet(void) {
  const char *const sets[] = {"mesh.n=16", "scene.pins=top-corners", NULL};
  return test_scene(sets);
}

/* Six rigid-body modes attached when asked (PETSc's MatGetNearNullSpace reports them back), none when not. */
Test(petsc, rigid_modes_attached) {
  cb_scene *s = sheet();
  size_t n3 = (size_t)3 * s->mesh.nv;
  double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v);
  for (int on = 0; on <= 1; on++) {
    memcpy(x, s->x0, n3 * sizeof *x);
    memcpy(v, s->v0, n3 * sizeof *v);
    const char *const extra[] = {"solver.method=petsc-gamg", on ? "solver.rigid_modes=1" : "solver.rigid_modes=0",
                                 NULL};
    cb_integrator *it = one_step(s, extra, x, v, NULL);
    cr_assert_eq(it->solver->stats.near_null, on ? 6 : 0, "rigid_modes=%d: %d near-null vectors", on,
                 it->solver->stats.near_null);
    cr_assert_not_null(it->solver->coords);
    /* the coordinates the solver read are the free vertices' at the step's start (the initial state here) */
    for (int k = 0; k < s->model.nfree; k++)
      for (int a = 0; a < 3; a++) cr_assert_eq(it->solver->coords[3 * k + a], s->x0[3 * s->free_vertex[k] + a]);
    cb_integrator_free(it);
  }
  free(x);
  free(v);
  cb_scene_free(s);
}

/* Collinear vertices (a chain) have only five independent rigid-body modes: none are given, and the solve still
 * runs. The fixture for the independence test. */
Test(petsc, chain_gets_no_modes) {
  const char *const sets[] = {"mesh.type=chain", "mesh.n=12", "material.vertex_mass=1", "scene.pins=0", NULL};
  cb_scene *s = test_scene(sets);
  size_t n3 = (size_t)3 * s->mesh.nv;
  double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v);
  memcpy(x, s->x0, n3 * sizeof *x);
  memcpy(v, s->v0, n3 * sizeof *v);
  const char *const it_sets[] = {"mesh.type=chain",          "mesh.n=12",
                                 "material.vertex_mass=1",   "scene.pins=0",
                                 "integrator.method=newton", "integrator.max_iters=1",
                                 "integrator.tol=0",         "solver.method=petsc-gamg",
                                 "solver.rigid_modes=1",     NULL};
  cb_integrator *it = test_integrator(it_sets, s, NULL, NULL);
  cb_step_stats st;
  step(it, s, x, v, &st);
  cr_assert_eq(st.linear_status, CB_OK, "%s", cb_error_message());
  cr_assert_eq(it->solver->stats.near_null, 0);
  cb_integrator_free(it);
  free(x);
  free(v);
  cb_scene_free(s);
}

/* With the rigid-body modes, GAMG's solve of the Newton system is CHOLMOD's to within what the residual bound
 * allows: |x - x*| / |x*| <= cond(A) |b - A x| / |b|; cond(A) <= lambda_max / lambda_min, bounded here by
 * Gershgorin's row sums over the smallest diagonal of M/dt^2 (A = M/dt^2 + H with H positive semi-definite after
 * the definiteness fix, so lambda_min >= min m / dt^2). */
Test(petsc, gamg_with_modes_matches_cholmod) {
  cb_scene *s = sheet();
  size_t n3 = (size_t)3 * s->mesh.nv;
  double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v);
  memcpy(x, s->x0, n3 * sizeof *x);
  memcpy(v, s->v0, n3 * sizeof *v);
  sys_capture cap = {0};
  const char *const extra[] = {"solver.method=petsc-gamg", "solver.rigid_modes=1", NULL};
  cb_integrator *it = one_step(s, extra, x, v, &cap);
  cr_assert_not_null(cap.b);
  const cb_sparse *A = cap.A;
  int n = A->n;
  cr_assert_eq(it->solver->stats.near_null, 6);
  double *xg = calloc((size_t)n, sizeof *xg), *xc = calloc((size_t)n, sizeof *xc), *w = malloc((size_t)n * sizeof *w);
  cr_assert_eq(cb_solver_factor(it->solver, A), CB_OK, "%s", cb_error_message()); /* set up on these values */
  cr_assert_eq(it->solver->stats.near_null, 6);
  cr_assert_eq(cb_solver_solve(it->solver, A, cap.b, xg), CB_OK, "%s", cb_error_message());
  cr_assert_gt(it->solver->stats.iters, 0);
  cb_solver *chol = NULL;
  cr_assert_eq(cb_solver_alloc("cholmod", NULL, n, &chol), CB_OK);
  cr_assert_eq(cb_solver_analyze(chol, A), CB_OK);
  cr_assert_eq(cb_solver_factor(chol, A), CB_OK);
  cr_assert_eq(cb_solver_solve(chol, A, cap.b, xc), CB_OK);
  double rel = cb_relative_residual(A, cap.b, xg, w);
  cr_assert_leq(rel, 1e-10);
  double lmax = 0;
  for (int j = 0; j < n; j++) { /* Gershgorin: column sums of |A| (A symmetric) */
    double sum = 0;
    for (int q = A->colp[j]; q < A->colp[j + 1]; q++) sum += fabs(A->val[q]);
    lmax = fmax(lmax, sum);
  }
  double mmin = INFINITY, dt = 1.0 / 30;
  for (int k = 0; k < s->model.nfree; k++) mmin = fmin(mmin, s->mass[s->free_vertex[k]]);
  double lmin = mmin / (dt * dt), num = 0, den = 0;
  cr_assert_gt(lmin, 0);
  for (int i = 0; i < n; i++) num += (xg[i] - xc[i]) * (xg[i] - xc[i]), den += xc[i] * xc[i];
  cr_assert_gt(den, 0);
  double bound = lmax / lmin * rel;
  cr_assert_leq(sqrt(num / den), bound * (1 + 1e-6) + 1e-13, "|x - x_cholmod| / |x_cholmod| = %g > %g", sqrt(num / den),
                bound);
  cb_solver_free(chol);
  free(xg);
  free(xc);
  free(w);
  free(cap.b);
  cb_integrator_free(it);
  free(x);
  free(v);
  cb_scene_free(s);
}

/* solver.pc_reuse: the set-ups counted against the integrator's own counts. `iteration`: one per factorisation;
 * `step`: one per step; `step` with pc_reuse_steps = 2 over 4 steps: steps 1 and 3; `auto`: the preset's choice
 * (GAMG every step, ML every 5 steps: steps 1 and 6 of 6, ICC every iteration). Newton to 1e-9 takes more than one
 * iteration a step, so a reuse is actually made. */
Test(petsc, pc_reuse_counts) {
  static const struct {
    const char *solver, *mode, *steps;
    int nsteps, want; /* want: set-ups, or -1 for one per factorisation */
  } cases[] = {
      {"solver.method=petsc-gamg", "solver.pc_reuse=iteration", "solver.pc_reuse_steps=1", 4, -1},
      {"solver.method=petsc-gamg", "solver.pc_reuse=step", "solver.pc_reuse_steps=1", 4, 4},
      {"solver.method=petsc-gamg", "solver.pc_reuse=step", "solver.pc_reuse_steps=2", 4, 2},
      {"solver.method=petsc-gamg", "solver.pc_reuse=auto", "solver.pc_reuse_steps=3", 4, 4},
      {"solver.method=petsc-ml", "solver.pc_reuse=auto", "solver.pc_reuse_steps=1", 6, 2},
      {"solver.method=petsc-icc", "solver.pc_reuse=auto", "solver.pc_reuse_steps=1", 3, -1},
  };
  for (size_t m = 0; m < sizeof cases / sizeof cases[0]; m++) {
    cb_scene *s = sheet();
    size_t n3 = (size_t)3 * s->mesh.nv;
    double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v);
    memcpy(x, s->x0, n3 * sizeof *x);
    memcpy(v, s->v0, n3 * sizeof *v);
    const char *const sets[] = {"mesh.n=16",
                                "scene.pins=top-corners",
                                "integrator.method=newton",
                                "integrator.max_iters=30",
                                "integrator.tol=1e-9",
                                "solver.tol=1e-8",
                                "solver.max_iters=10000",
                                cases[m].solver,
                                cases[m].mode,
                                cases[m].steps,
                                NULL};
    cb_integrator *it = test_integrator(sets, s, NULL, NULL);
    int factorizations = 0, nsteps = cases[m].nsteps;
    for (int t = 0; t < nsteps; t++) {
      cb_step_stats st;
      int r = step(it, s, x, v, &st);
      cr_assert_eq(r, CB_OK, "%s %s: step %d: %s", cases[m].solver, cases[m].mode, t, cb_error_message());
      cr_assert_gt(st.factorizations, 1, "a step of one Newton iteration tests no reuse");
      factorizations += st.factorizations;
    }
    int want = cases[m].want < 0 ? factorizations : cases[m].want;
    cr_assert_eq(it->solver->stats.pc_setups, want, "%s %s %s: %d set-ups, expected %d", cases[m].solver, cases[m].mode,
                 cases[m].steps, it->solver->stats.pc_setups, want);
    cr_assert_eq(it->solver->step, nsteps);
    cb_integrator_free(it);
    free(x);
    free(v);
    cb_scene_free(s);
  }
}

/* A solver without an integrator counts no steps: under `step` it is set up at its first factorisation only, and
 * again after cb_solver_forget. */
Test(petsc, pc_reuse_without_integrator) {
  cb_scene *s = sheet();
  size_t n3 = (size_t)3 * s->mesh.nv;
  double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v);
  memcpy(x, s->x0, n3 * sizeof *x);
  memcpy(v, s->v0, n3 * sizeof *v);
  sys_capture cap = {0};
  const char *const extra[] = {"solver.method=cholmod", NULL};
  cb_integrator *it = one_step(s, extra, x, v, &cap);
  cb_solver_params p = cb_solver_params_default();
  p.pc_reuse = CB_PC_REUSE_STEP;
  p.tol = 1e-8;
  cb_solver *ps = NULL;
  cr_assert_eq(cb_solver_alloc("petsc-gamg", &p, cap.A->n, &ps), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_solver_analyze(ps, cap.A), CB_OK, "%s", cb_error_message());
  for (int k = 0; k < 3; k++) cr_assert_eq(cb_solver_factor(ps, cap.A), CB_OK, "%s", cb_error_message());
  cr_assert_eq(ps->stats.pc_setups, 1);
  cr_assert_eq(ps->stats.near_null, 0, "no coordinates, no modes");
  cb_solver_forget(ps);
  cr_assert_eq(cb_solver_factor(ps, cap.A), CB_OK);
  cr_assert_eq(ps->stats.pc_setups, 2);
  double *dx = calloc((size_t)cap.A->n, sizeof *dx);
  cr_assert_eq(cb_solver_solve(ps, cap.A, cap.b, dx), CB_OK, "%s", cb_error_message());
  free(dx);
  cb_solver_free(ps);
  free(cap.b);
  cb_integrator_free(it);
  free(x);
  free(v);
  cb_scene_free(s);
}

Test(petsc, pc_reuse_key_checked) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_neq(cb_config_set(&c, "solver.pc_reuse=sometimes"), 0);
  cr_assert_neq(cb_config_set(&c, "solver.pc_reuse_steps=0"), 0);
  cr_assert_neq(cb_config_set(&c, "solver.rigid_modes=2"), 0);
  cr_assert_eq(cb_config_set(&c, "solver.pc_reuse=step"), 0);
}
