/* Bad input to the core's API (without the config layer, which refuses
 * most of it first): each gives its status and a message that names the
 * parameter, and nothing is built. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"

#define assert_fails(call, status, needle) \
  do { \
    cb_error_clear(); \
    int st_ = (call); \
    cr_assert_eq(st_, (status), "%s returned %s: %s", #call, cb_status_name(st_), cb_error_message()); \
    cr_assert(strstr(cb_error_message(), (needle)), "%s: message '%s' lacks '%s'", #call, cb_error_message(), \
              (needle)); \
  } while (0)

static cb_scene_def small_def(void) {
  cb_scene_def d = cb_scene_def_default();
  d.grid.n = d.grid.m = 4;
  return d;
}

Test(core_errors, scene_definition) {
  cb_scene *s = NULL;
  const char *key = NULL;
  cb_scene_def d = small_def();
  d.stretch = "rubber";
  assert_fails(cb_scene_build(&d, &s, &key), CB_EINVAL, "unknown model 'rubber'");
  cr_assert_str_eq(key, "material.stretch");
  cr_assert_null(s);
  d = small_def();
  d.stretch = "fem";
  d.fem_hessian = "approximate";
  assert_fails(cb_scene_build(&d, &s, &key), CB_EINVAL, "unknown Hessian 'approximate'");
  cr_assert_str_eq(key, "material.fem_hessian");
  d = small_def();
  d.collider = "penalty";
  d.sphere.thickness = -0.1;
  assert_fails(cb_scene_build(&d, &s, &key), CB_EINVAL, "collider.thickness");
  d = small_def();
  d.collider = "penalty";
  d.sphere.stiffness = -1;
  assert_fails(cb_scene_build(&d, &s, &key), CB_EINVAL, "collider.stiffness");
  d = small_def();
  d.nresponses = CB_MAX_RESPONSES + 1;
  assert_fails(cb_scene_build(&d, &s, &key), CB_EINVAL, "post-step responses");
  d = small_def();
  d.nresponses = 1; /* responses[0].type left NULL */
  assert_fails(cb_scene_build(&d, &s, &key), CB_EINVAL, "has no type");
  cr_assert_null(s);
}

Test(core_errors, linear_solver_parameters) {
  cb_solver *sv = NULL;
  cb_solver_params p = cb_solver_params_default();
  p.nrelax[1] = p.nrelax[0] - 1; /* must not decrease */
  assert_fails(cb_solver_alloc("cholmod", &p, 4, &sv), CB_EINVAL, "solver.nrelax");
  cr_assert_null(sv);
  p = cb_solver_params_default();
  p.rho = 1.5;
  assert_fails(cb_solver_alloc("chebyshev", &p, 4, &sv), CB_EINVAL, "solver.rho");
  cr_assert_null(sv);
  assert_fails(cb_solver_alloc("gauss", NULL, 4, &sv), CB_EINVAL, "unknown linear solver 'gauss'");
  cb_shift *sh = NULL;
  cb_shift_params q = cb_shift_params_default();
  q.grow = 1.0;
  assert_fails(cb_shift_alloc(4, &q, &sh), CB_EINVAL, "grow > 1");
  q = cb_shift_params_default();
  q.max_tries = 0;
  assert_fails(cb_shift_alloc(4, &q, &sh), CB_EINVAL, "max_tries >= 1");
  cr_assert_null(sh);
}

Test(core_errors, integrator_parameters) {
  cb_scene *s = test_scene((const char *const[]){"mesh.n=4", NULL});
  cb_integrator *it = NULL;
  cb_integrator_params p = cb_integrator_params_default();
  assert_fails(cb_integrator_alloc("leapfrog", s, &p, NULL, NULL, NULL, &it), CB_EINVAL, "unknown integrator");
  p.dt = 0;
  assert_fails(cb_integrator_alloc("explicit", s, &p, NULL, NULL, NULL, &it), CB_EINVAL, "dt must be > 0");
  p = cb_integrator_params_default();
  p.damping = 1.5;
  assert_fails(cb_integrator_alloc("explicit", s, &p, NULL, NULL, NULL, &it), CB_EINVAL, "damping");
  p = cb_integrator_params_default();
  assert_fails(cb_integrator_alloc("newton", s, &p, NULL, NULL, NULL, &it), CB_EINVAL, "needs a linear solver");
  cb_nljacobi_params nj = cb_nljacobi_params_default();
  nj.rho = 1.0; /* chebyshev-nl's rho must be in [0, 1) */
  assert_fails(cb_integrator_alloc("chebyshev-nl", s, &p, &nj, NULL, NULL, &it), CB_EINVAL, "rho must be in [0, 1)");
  nj = cb_nljacobi_params_default();
  nj.diagonal = 2;
  nj.definiteness = CB_DEF_SHIFT; /* a linear-solve policy: the exact diagonal takes none of it */
  assert_fails(cb_integrator_alloc("chebyshev-nl", s, &p, &nj, NULL, NULL, &it), CB_EINVAL, "linear-solve policy");
  cr_assert_null(it);
  cb_scene_free(s);
}

/* cb_jacobi_spectral_radius (public, no caller in lib/ yet) against the
 * dense eigenvalues of D^-1/2 A D^-1/2: rho(I - alpha D^-1 A) =
 * max |1 - alpha lambda|, and the Lanczos bound must not be below it. */
Test(core_errors, jacobi_spectral_radius_bounds_the_dense_one) {
  cb_scene *s = test_scene((const char *const[]){"mesh.n=5", "material.stretch_k=1000", "material.vertex_mass=0.1",
                                                 "scene.initial_scale=1.2", NULL});
  cb_system_assemble(&s->sys, s->x0, 1.0 / (0.01 * 0.01), CB_DEF_DROP, 0.0);
  const cb_sparse *A = &s->sys.A;
  int n = A->n;
  double *dhalf = cb_malloc((size_t)n, sizeof(double)), *eval = cb_malloc((size_t)n, sizeof(double));
  cr_assert(dhalf && eval);
  for (int i = 0; i < n; i++) dhalf[i] = 1.0 / sqrt(A->val[s->sys.diag[i]]);
  cr_assert_eq(cb_dense_eigenvalues(A, dhalf, eval), CB_OK, "%s", cb_error_message());
  for (int k = 0; k < 2; k++) {
    double alpha = k ? 0.8 : 1.0, exact = 0;
    for (int i = 0; i < n; i++) exact = fmax(exact, fabs(1 - alpha * eval[i]));
    double rho = -1;
    int steps = 0;
    cr_assert_eq(cb_jacobi_spectral_radius(A, dhalf, alpha, &rho, &steps), CB_OK, "%s", cb_error_message());
    cr_assert_gt(steps, 0);
    cr_assert_geq(rho, exact * (1 - 1e-9), "alpha %g: rho %.12g below the dense %.12g", alpha, rho, exact);
    cr_assert_leq(rho, exact + 1e-3, "alpha %g: rho %.12g far above the dense %.12g", alpha, rho, exact);
  }
  free(dhalf);
  free(eval);
  cb_scene_free(s);
}
