/* lib/instruments/stability.c: the cell classifier on constructed energy histories, the
 * explicit limit against closed forms (one mass on a spring: 2 sqrt(m/k); a
 * fixed-free chain: the Dirichlet-Neumann Laplacian's top eigenvalue),
 * Lanczos against GSL, the hanging equilibrium against mg/k, and the
 * bisection against the closed form. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stability.h"
#include "support.h"

static cb_stability_params P(void) { return cb_stability_params_default(); }

/* ---- classifier --------------------------------------------------------------- */

Test(stability_classifier, bounded_oscillation_is_stable) {
  double r[200], want = 0;
  for (int i = 0; i < 200; i++) {
    r[i] = 1e-3 * sin(0.3 * i); /* r = (E - E0)/S oscillates, never past R_u = 1 */
    if (r[i] > want) want = r[i];
  }
  double m;
  cb_stability_params p = P();
  cr_assert_eq(cb_stability_classify(r, 200, &p, &m), CB_CELL_STABLE);
  cr_assert_eq(m, want);
}

Test(stability_classifier, energy_loss_is_stable_with_zero_growth) {
  double r[50];
  for (int i = 0; i < 50; i++) r[i] = -0.01 * i; /* implicit Euler only loses energy */
  double m = -1;
  cb_stability_params p = P();
  cr_assert_eq(cb_stability_classify(r, 50, &p, &m), CB_CELL_STABLE);
  cr_assert_eq(m, 0.0);
}

Test(stability_classifier, growth_past_the_unstable_bound_but_not_the_divergence_bound) {
  double r[] = {0, 0.1, 0.5, 0.99, 1.5, 3, 9.9, 5};
  double m;
  cb_stability_params p = P();
  cr_assert_eq(cb_stability_classify(r, 8, &p, &m), CB_CELL_UNSTABLE);
  cr_assert_eq(m, 9.9);
  cr_assert_eq(cb_stability_classify(r, 4, &p, &m), CB_CELL_STABLE); /* up to 0.99 only */
}

Test(stability_classifier, divergence_stops_at_the_bound_or_a_nan) {
  cb_stability_params p = P();
  cb_classifier c;
  cb_classifier_init(&c);
  cr_assert_eq(cb_classifier_push(&c, &p, 2.0), 0);
  cr_assert_eq(c.cls, CB_CELL_UNSTABLE);
  cr_assert_eq(cb_classifier_push(&c, &p, 10.5), 1); /* past R_d = 10: decided */
  cr_assert_eq(c.cls, CB_CELL_DIVERGED);
  cr_assert_eq(cb_classifier_push(&c, &p, 0.0), 1); /* stays decided */
  cr_assert_eq(c.cls, CB_CELL_DIVERGED);
  cr_assert_eq(c.max_ratio, 10.5);
  double r[] = {0, 0.2, NAN, 0};
  double m;
  cr_assert_eq(cb_stability_classify(r, 4, &p, &m), CB_CELL_DIVERGED);
  cr_assert_eq(m, 0.2);
  double inf[] = {0, INFINITY};
  cr_assert_eq(cb_stability_classify(inf, 2, &p, NULL), CB_CELL_DIVERGED);
  p.unstable_ratio = 0.1; /* the bounds are parameters */
  double small[] = {0, 0.2};
  cr_assert_eq(cb_stability_classify(small, 2, &p, NULL), CB_CELL_UNSTABLE);
  cr_assert_str_eq(cb_cell_class_name(CB_CELL_DIVERGED), "diverged");
}

Test(stability_classifier, cell_length_is_clamped) {
  cb_stability_params p = P();
  p.sim_time = 2;
  p.min_steps = 200;
  p.max_steps = 2000;
  cr_assert_eq(cb_stability_steps(&p, 0.1), 200);   /* 20 steps -> at least 200 */
  cr_assert_eq(cb_stability_steps(&p, 0.004), 500); /* 2 s / 4 ms */
  cr_assert_eq(cb_stability_steps(&p, 1e-5), 2000); /* 200000 -> at most 2000 */
  p.max_steps = 0;
  cr_assert_eq(cb_stability_steps(&p, 1e-5), 200000);
}

Test(stability_classifier, grid_bracket) {
  double dt[] = {1, 2, 4, 8, 16};
  int cls[] = {0, 0, 0, 2, 2}, mono;
  double lo, hi;
  cr_assert_eq(cb_stability_grid_bracket(dt, cls, 5, &lo, &hi, &mono), CB_OK);
  cr_assert(lo == 4 && hi == 8 && mono == 1);
  int nonmono[] = {0, 1, 0, 2, 2}; /* the first non-stable cell sets the bracket */
  cb_stability_grid_bracket(dt, nonmono, 5, &lo, &hi, &mono);
  cr_assert(lo == 1 && hi == 2 && mono == 0);
  int all[] = {0, 0, 0, 0, 0};
  cb_stability_grid_bracket(dt, all, 5, &lo, &hi, &mono);
  cr_assert(lo == 16 && hi == 0);
  int none[] = {2, 2, 2, 2, 2};
  cr_assert_eq(cb_stability_grid_bracket(dt, none, 5, &lo, &hi, &mono), CB_NOT_CONVERGED);
  cr_assert(lo == 0 && hi == 1);
}

/* ---- scenes -------------------------------------------------------------------- */

static cb_scene *spring_scene(double k, double m, const char *gravity) {
  char sk[64], sm[64], sg[64];
  snprintf(sk, sizeof sk, "material.stretch_k=%.17g", k);
  snprintf(sm, sizeof sm, "material.vertex_mass=%.17g", m);
  snprintf(sg, sizeof sg, "scene.gravity=%s", gravity);
  const char *sets[] = {
      "mesh.type=chain", "mesh.n=2", "mesh.size=1", "mesh.plane=yz", "scene.pins=1", sk, sm, sg, NULL};
  return test_scene(sets);
}

Test(stability_predict, one_mass_on_a_spring_is_two_sqrt_m_over_k) {
  double k = 400, m = 0.25; /* omega = sqrt(k/m) = 40 rad/s, dt_crit = 2 sqrt(m/k) = 0.05 s */
  cb_scene *s = spring_scene(k, m, "0 -9.8 0");
  cb_prediction p;
  cr_assert_eq(cb_stability_predict(s, s->mesh.x, CB_EIG_BOTH, &p), CB_OK); /* at rest: K = k u u^T */
  cr_assert_float_eq(p.lambda_dense, k / m, 1e-12 * k / m);
  cr_assert_float_eq(p.lambda_lanczos, k / m, 1e-9 * k / m);
  cr_assert_float_eq(p.dt_crit, 0.05, 1e-14);
  cr_assert_eq(p.ndof, 3);
  double *x = malloc(sizeof(double) * 6);
  memcpy(x, s->x0, sizeof(double) * 6);
  cb_equilibrium_stats es;
  cb_equilibrium_params ep = cb_equilibrium_params_default();
  ep.tol = 1e-12; /* residual force / weight */
  cr_assert_eq(cb_stability_equilibrium(s, x, &ep, &es), CB_OK);
  cr_assert_eq(es.status, CB_OK);
  /* hanging: the spring is stretched by mg/k (vertex 0 hangs below vertex 1) */
  double l = fabs(x[1] - x[4]);
  cr_assert_float_eq(l, 1.0 + m * 9.8 / k, 1e-9);
  cr_assert_float_eq(es.max_strain, m * 9.8 / k, 1e-9);
  /* and the axial eigenvalue is still k/m (the pendulum adds g/l to the transverse ones) */
  cr_assert_eq(cb_stability_predict(s, x, CB_EIG_DENSE, &p), CB_OK);
  cr_assert_float_eq(p.dt_crit, 2 * sqrt(m / k), 1e-12);
  cr_assert_float_eq(p.lambda_min_dense, 9.8 / l, 1e-6); /* pendulum: omega^2 = g/l */
  free(x);
  cb_scene_free(s);
}

Test(stability_predict, fixed_free_chain_matches_the_closed_form) {
  /* N free masses below a fixed point: the axial block of M^-1 K is (k/m) times the
   * Dirichlet-Neumann Laplacian, eigenvalues (4k/m) sin^2((2j-1) pi / (2(2N+1))). */
  const char *sets[] = {"mesh.type=chain",
                        "mesh.n=21",
                        "mesh.size=1",
                        "mesh.plane=yz",
                        "scene.pins=20",
                        "material.vertex_mass=0.01",
                        "material.stretch_k=1000",
                        NULL};
  cb_scene *s = test_scene(sets);
  int N = 20;
  const double pi = 3.14159265358979323846;
  double lam = 4 * 1000 / 0.01 * pow(sin((2.0 * N - 1) * pi / (2.0 * (2 * N + 1))), 2);
  cb_prediction p;
  cr_assert_eq(cb_stability_predict(s, s->mesh.x, CB_EIG_BOTH, &p), CB_OK);
  cr_assert_float_eq(p.lambda_dense, lam, 1e-10 * lam);
  cr_assert_float_eq(p.lambda_lanczos, lam, 1e-8 * lam);
  cb_scene_free(s);
}

Test(stability_predict, lanczos_agrees_with_gsl_on_a_hanging_cloth) {
  const char *sets[] = {
      "mesh.n=9", "mesh.size=2", "mesh.plane=xy", "material.vertex_mass=0.1", "material.stretch_k=5000", NULL};
  cb_scene *s = test_scene(sets);
  double *x = malloc(sizeof(double) * 3 * s->mesh.nv);
  memcpy(x, s->x0, sizeof(double) * 3 * s->mesh.nv);
  cb_equilibrium_stats es;
  cr_assert_eq(cb_stability_equilibrium(s, x, NULL, &es), CB_OK);
  cr_assert_lt(es.residual, 1e-4);
  cr_assert_gt(es.max_strain, 0); /* the corners carry the weight */
  cb_prediction p;
  cr_assert_eq(cb_stability_predict(s, x, CB_EIG_BOTH, &p), CB_OK);
  cr_assert_eq(p.method, CB_EIG_DENSE);
  cr_assert_float_eq(p.lambda_lanczos, p.lambda_dense, 1e-8 * p.lambda_dense);
  /* Gershgorin-type bound: each free vertex has at most 6 springs, each adding at most
   * 2k to a row sum of |K|, so lambda_max(M^-1 K) <= 12 k / m. */
  cr_assert_lt(p.lambda_dense, 12 * 5000 / 0.1);
  cr_assert_gt(p.lambda_dense, 5000 / 0.1);
  free(x);
  cb_scene_free(s);
}

/* ---- start state ------------------------------------------------------------------ */

Test(stability_start, energy_scale_perturbation_and_swing) {
  cb_scene *s = spring_scene(100, 0.5, "0 -9.8 0");
  double v[6] = {0};
  /* S = elastic + kinetic + (sum of all masses) |g| D, D = 1 m (the chain) */
  cr_assert_float_eq(cb_stability_energy_scale(s, s->mesh.x, v), 1.0 * 9.8 * 1.0 + 1e-12, 1e-12);
  cb_stability_perturb(s, 0.3, 7, v);
  cr_assert_float_eq(cb_scene_kinetic(s, v), 0.3, 1e-14);
  cr_assert(v[3] == 0 && v[4] == 0 && v[5] == 0); /* vertex 1 is pinned */
  double w[6] = {0};
  cb_stability_perturb(s, 0.3, 7, w);
  cr_assert_arr_eq(v, w, sizeof v); /* deterministic */
  double u[6] = {0}, dir[3] = {0, 0, 2};
  cb_stability_swing(s, 0.25, dir, u); /* 1/2 m c^2 = 0.25 J: c = 1 m/s along z */
  cr_assert_float_eq(u[2], 1.0, 1e-15);
  cr_assert(u[0] == 0 && u[1] == 0 && u[5] == 0);
  cb_scene_free(s);
  /* without gravity S uses 9.8 m/s^2, so a free cloth still has a scale */
  cb_scene *f = spring_scene(100, 0.5, "0 0 0");
  double z[6] = {0};
  cr_assert_float_eq(cb_stability_energy_scale(f, f->mesh.x, z), 9.8 + 1e-12, 1e-12);
  cb_scene_free(f);
}

/* ---- cells and the boundary ------------------------------------------------------ */

Test(stability_cell, bisection_finds_two_sqrt_m_over_k) {
  cb_config c;
  const char *sets[] = {"mesh.type=chain",
                        "mesh.n=2",
                        "mesh.size=1",
                        "mesh.plane=yz",
                        "scene.pins=1",
                        "material.vertex_mass=0.01",
                        "material.stretch_k=10000",
                        NULL};
  test_config(&c, sets);
  cb_stability_case cs;
  cr_assert_eq(cb_stability_case_init(&cs, &c, NULL), CB_OK, "%s", cb_error_message());
  double exact = 2 * sqrt(0.01 / 10000.0); /* 2e-3 s */
  cr_assert_float_eq(cs.pred.dt_crit, exact, 1e-12);
  cb_stability_params p = P();
  cb_cell_result r;
  cr_assert_eq(cb_stability_cell(cs.expl, 0.9 * exact, cs.x_start, cs.v_start, cs.S, &p, &cs.work, &r), CB_OK);
  cr_assert_eq(r.cls, CB_CELL_STABLE);
  cr_assert_eq(r.steps, 1112); /* ceil(2 s / 1.8 ms) */
  cr_assert_lt(r.max_energy_ratio, 1e-3);
  cr_assert_eq(cb_stability_cell(cs.expl, 1.1 * exact, cs.x_start, cs.v_start, cs.S, &p, &cs.work, &r), CB_OK);
  cr_assert_eq(r.cls, CB_CELL_DIVERGED);
  cr_assert_lt(r.steps, 200); /* stopped early */
  cb_bisect_result b;
  cr_assert_eq(cb_stability_bisect(cs.expl, cs.x_start, cs.v_start, cs.S, &p, &cs.work, 0.5 * exact, 2 * exact, 1.5, 14,
                                   NULL, NULL, &b),
               CB_OK);
  cr_assert_eq(b.status, CB_OK);
  cr_assert_eq(b.runs, 14);
  cr_assert(b.dt_stable < b.dt_unstable);
  cr_assert_lt(fabs(b.dt_stable / exact - 1), 2e-3, "measured %.9g, exact %.9g", b.dt_stable, exact);
  cr_assert_eq(cb_stability_boundary_from_guess(cs.expl, cs.x_start, cs.v_start, cs.S, &p, &cs.work, 0.7 * exact, 1.2,
                                                10, NULL, NULL, &b),
               CB_OK); /* searches upward from a stable guess */
  cr_assert_lt(fabs(b.dt_stable / exact - 1), 5e-3);
  /* Newton (implicit Euler) at 10x the explicit limit: stable, and it only loses energy */
  p.mark_time = 0.1;
  cr_assert_eq(cb_stability_cell(cs.newton, 10 * exact, cs.x_start, cs.v_start, cs.S, &p, &cs.work, &r), CB_OK);
  cr_assert_eq(r.cls, CB_CELL_STABLE);
  cr_assert_eq(r.max_energy_ratio, 0.0);
  cr_assert_float_eq(r.t_mark, 0.1, 1e-12);
  cr_assert_lt(r.energy_mark, r.energy0);
  cb_stability_case_free(&cs);
}

Test(stability_cell, bad_input_is_an_error_not_a_crash) {
  cb_config c;
  const char *sets[] = {"mesh.type=chain", "mesh.n=2", "scene.pins=1", "material.vertex_mass=1", NULL};
  test_config(&c, sets);
  cb_stability_case cs;
  cr_assert_eq(cb_stability_case_init(&cs, &c, NULL), CB_OK);
  cb_stability_params p = P();
  cb_cell_result r;
  cr_assert_lt(cb_stability_cell(cs.expl, 0.0, cs.x_start, cs.v_start, cs.S, &p, &cs.work, &r), 0);
  cr_assert_lt(cb_stability_cell(cs.expl, 1e-3, cs.x_start, cs.v_start, 0.0, &p, &cs.work, &r), 0);
  cb_stability_case_free(&cs);
  const char *bad[] = {"mesh.type=chain", "mesh.n=2", "scene.pins=1", NULL}; /* no vertex mass */
  test_config(&c, bad);
  cr_assert_lt(cb_stability_case_init(&cs, &c, NULL), 0);
  cr_assert_neq(strstr(cb_error_message(), "mass"), NULL);
}
