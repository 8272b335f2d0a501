/* The single-step bench (lib/instruments/step_bench.h) that field and nonlinear time their methods with:
 * the shared blow-up check (no method writes a blow-up as an ok row) and the warm-up step of an
 * integrator with history (VBD's adaptive initial guess must fire in the timed step). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "step_bench.h"
#include "support.h"
#include <clothbench/status.h>

Test(step_bench, classify_records_growth_past_the_bound_as_diverged) {
  /* the row of issue 31 §6: xpbd 64 x 1 on the stiff 81^2 cloth, relative |grad F| 1695, status ok */
  cr_expect_eq(cb_step_classify(CB_OK, 1695.0), CB_DIVERGED);
  cr_expect_eq(cb_step_classify(CB_OK, 2 * CB_STEP_GROWTH_BOUND), CB_DIVERGED);
  cr_expect_eq(cb_step_classify(CB_NOT_CONVERGED, INFINITY), CB_DIVERGED);
  cr_expect_eq(cb_step_classify(CB_OK, NAN), CB_DIVERGED, "a NaN end is not ok");
  /* a step that only moved away a little, or converged, keeps its own status */
  cr_expect_eq(cb_step_classify(CB_OK, 0.5), CB_OK);
  cr_expect_eq(cb_step_classify(CB_OK, 0.5 * CB_STEP_GROWTH_BOUND), CB_OK);
  cr_expect_eq(cb_step_classify(CB_NOT_CONVERGED, 3.0), CB_NOT_CONVERGED);
  /* a fatal status stays what it was */
  cr_expect_eq(cb_step_classify(CB_LINEAR_FAILED, 1e9), CB_LINEAR_FAILED);
}

static const char *const CLOTH[] = {"mesh.n=9",
                                    "mesh.size=1",
                                    "material.vertex_mass=0.01",
                                    "material.stretch_k=500",
                                    "scene.pins=0 8",
                                    "integrator.method=newton",
                                    "integrator.dt=0.02",
                                    NULL};

/* A vbd step of the bench from a start state after 3 frames equals, bit for bit, a fresh integrator that
 * stepped once from the frame before and then from the start state (the warm-up reproduced by hand), and
 * differs from a fresh integrator's first step (whose adaptive guess has no last velocity: inertia). */
Test(step_bench, a_vbd_step_is_warmed_by_the_frame_before) {
  cb_config c;
  test_config(&c, CLOTH);
  cb_scene *s = NULL;
  cr_assert_eq(cb_scene_from_config(&c, &s), CB_OK, "%s", cb_error_message());
  cb_step_state S;
  cr_assert_eq(cb_step_state_init(&S, "cloth", &c, s, 3), CB_OK, "%s", cb_error_message());
  cr_assert(S.xm && S.vm);
  const char *vbd[] = {"integrator.method=vbd", "integrator.iters=4", NULL};
  static cb_config cv;
  cr_assert_eq(cb_step_config(&S, vbd, &cv), CB_OK);
  cb_step_result r;
  double w;
  cr_assert_eq(cb_step_once(&S, &cv, NULL, NULL, &r, &w), CB_OK);
  cr_expect_eq(r.status, CB_OK);
  int n3 = S.n3;
  double *bench = malloc((size_t)n3 * sizeof(double)), *x = malloc((size_t)n3 * sizeof(double)),
         *v = malloc((size_t)n3 * sizeof(double));
  cr_assert(bench && x && v);
  memcpy(bench, S.x, (size_t)n3 * sizeof(double));
  /* by hand: the same config (damping 1), a fresh integrator, the frame before, then the start state */
  const char *sets[] = {"mesh.n=9",
                        "mesh.size=1",
                        "material.vertex_mass=0.01",
                        "material.stretch_k=500",
                        "scene.pins=0 8",
                        "integrator.dt=0.02",
                        "integrator.method=vbd",
                        "integrator.iters=4",
                        "integrator.damping=1",
                        NULL};
  for (int warm = 0; warm < 2; warm++) {
    cb_integrator *it = test_integrator(sets, S.s, NULL, NULL);
    cb_step_stats ss;
    if (warm) {
      memcpy(x, S.xm, (size_t)n3 * sizeof(double));
      memcpy(v, S.vm, (size_t)n3 * sizeof(double));
      cb_integrator_step(it, x, v, &ss);
    }
    memcpy(x, S.x0, (size_t)n3 * sizeof(double));
    memcpy(v, S.v0, (size_t)n3 * sizeof(double));
    cr_assert_eq(cb_integrator_step(it, x, v, &ss), CB_OK);
    double d = 0;
    for (int k = 0; k < n3; k++) d = fmax(d, fabs(x[k] - bench[k]));
    if (warm) cr_expect_eq(d, 0.0, "the bench's vbd step is the warmed one: max |dx| %.3g", d);
    else cr_expect_gt(d, 0.0, "a fresh vbd step (no last velocity) differs from the warmed one");
    cb_integrator_free(it);
  }
  free(bench);
  free(x);
  free(v);
  cb_step_state_free(&S);
}
