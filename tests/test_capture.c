/* Capturing a Newton system mid-simulation (lib/instruments/capture.c). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "capture.h"
#include "support.h"

static const char *const small[] = {"mesh.n=6", "material.vertex_mass=1", "integrator.max_iters=5", NULL};

/* Counts the systems the integrator assembles and keeps a copy of one. */
typedef struct {
  int step, target_step, target_iter, seen;
  double *val, *b;
} spy;
static void spy_hook(void *ctx, int event, const cb_newton_event *ev) {
  spy *s = ctx;
  if (event != CB_NEWTON_SYSTEM || s->step != s->target_step || ev->iter != s->target_iter) return;
  memcpy(s->val, ev->A->val, (size_t)ev->A->nnz * sizeof(double));
  memcpy(s->b, ev->b, (size_t)ev->A->n * sizeof(double));
  s->seen = 1;
}

Test(capture, copies_the_system_newton_assembles) {
  cb_config c;
  test_config(&c, small);
  cb_capture cap;
  cr_assert_eq(cb_capture_newton_system(&c, 4, 1, &cap), CB_OK, "%s", cb_error_message());
  cr_expect_eq(cap.step, 4);
  cr_expect_eq(cap.iter, 1);
  cr_expect_float_eq(cap.t_s, 4 * c.dt, 1e-12);
  /* an independent run of the same scene, spying through the hook */
  cb_scene *s = NULL;
  cr_assert_eq(cb_scene_from_config(&c, &s), CB_OK);
  spy sp = {0, 4, 1, 0, malloc((size_t)s->sys.A.nnz * sizeof(double)), malloc((size_t)s->sys.A.n * sizeof(double))};
  cb_integrator_params ip;
  cb_integrator_params_from_config(&c, &ip);
  ip.hook = spy_hook;
  ip.hook_ctx = &sp;
  cb_integrator *it = NULL;
  cr_assert_eq(cb_integrator_from_config(&c, s, &ip, &it), CB_OK);
  cb_run r;
  cr_assert_eq(cb_run_init(&r, s, it), CB_OK);
  for (sp.step = 0; sp.step <= 4; sp.step++) cb_run_step(&r);
  cr_assert(sp.seen);
  cr_expect_eq(cap.A.nnz, s->sys.A.nnz);
  cr_expect_eq(memcmp(cap.A.val, sp.val, (size_t)cap.A.nnz * sizeof(double)), 0, "A differs");
  cr_expect_eq(memcmp(cap.b, sp.b, (size_t)cap.A.n * sizeof(double)), 0, "b differs");
  /* the captured A is M/dt^2 + H(x) at the captured iterate x */
  cb_system_assemble(&s->sys, cap.x, 1 / (c.dt * c.dt), CB_DEF_DROP, 0);
  for (int q = 0; q < cap.A.nnz; q++)
    cr_expect_float_eq(cap.A.val[q], s->sys.A.val[q], 1e-9 * (1 + fabs(s->sys.A.val[q])));
  cb_run_free(&r);
  cb_integrator_free(it);
  cb_scene_free(s);
  free(sp.val);
  free(sp.b);
  cb_capture_free(&cap);
}

Test(capture, a_step_that_ends_before_the_iteration_is_a_status) {
  cb_config c;
  test_config(&c, (const char *const[]){"mesh.n=6", "material.vertex_mass=1", "integrator.max_iters=2", NULL});
  cb_capture cap;
  cr_expect_eq(cb_capture_newton_system(&c, 1, 5, &cap), CB_NOT_CONVERGED);
  cr_expect_null(cap.scene);
  cr_expect_eq(cb_capture_newton_system(&c, -1, 0, &cap), CB_EINVAL);
}

Test(capture, diagonal_dominance_count) {
  cb_config c;
  test_config(&c, small);
  cb_capture cap;
  cr_assert_eq(cb_capture_newton_system(&c, 0, 0, &cap), CB_OK);
  int bad;
  double ratio;
  cb_diag_dominance(&cap.A, &bad, &ratio);
  /* recount by hand */
  int bad2 = 0;
  for (int j = 0; j < cap.A.n; j++) {
    double d = 0, off = 0;
    for (int q = cap.A.colp[j]; q < cap.A.colp[j + 1]; q++) {
      if (cap.A.rowi[q] == j) d = cap.A.val[q];
      else off += fabs(cap.A.val[q]);
    }
    bad2 += d < off;
  }
  cr_expect_eq(bad, bad2);
  cr_expect_gt(ratio, 0);
  cb_capture_free(&cap);
}
