/* Definiteness policies (definiteness.c), the Choi-Ko response
 * (energy_spring_choi_ko.c), the shift loop (solver_shift.c), driven pins and
 * the SPD probes. Every expected number is derived here independently:
 * eigen-decompositions by GSL, closed forms of the spring Hessian's
 * eigenvalues, finite differences. */
#include <criterion/criterion.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/definiteness.h>
#include <clothbench/eigen.h>
#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>
#include <clothbench/solver_shift.h>
#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include "experiment.h"
#include "provenance.h"
#include "newton_trace.h"
#include "spd_probe.h"
#include "support.h"
#include "rng.h"

static const double PI = 3.14159265358979323846;

/* A single spring (2-vertex chain, L = 1, k = 8000, nothing pinned, no gravity). */
static cb_scene *one_spring(const char *policy) {
  char pol[64];
  snprintf(pol, sizeof pol, "integrator.definiteness=%s", policy);
  const char *sets[] = {"mesh.type=chain",     "mesh.n=2", "mesh.size=1", "material.vertex_mass=1", "scene.pins=none",
                        "scene.gravity=0 0 0", pol,        NULL};
  return test_scene(sets);
}

/* x: the spring from the origin to length l along a fixed oblique direction. */
static void spring_at(double l, double x[6]) {
  double u[3] = {0.48, -0.6, 0.64}; /* unit: 0.2304 + 0.36 + 0.4096 = 1 */
  for (int a = 0; a < 3; a++) {
    x[a] = 0.3;
    x[3 + a] = 0.3 + l * u[a];
  }
}

static gsl_matrix *hessian(cb_scene *s, const double *x, cb_definiteness def) {
  cb_system_assemble(&s->sys, x, 0.0, def, 0.0); /* A = H */
  return test_dense(&s->sys.A);
}

/* V f(Lambda) V^T of the exact Hessian, with f = clamp at 0 (mode 0) or |.| (mode 1). */
static gsl_matrix *spectral_map(const gsl_matrix *H, int mode) {
  size_t n = H->size1;
  gsl_matrix *A = gsl_matrix_alloc(n, n), *V = gsl_matrix_alloc(n, n), *R = gsl_matrix_calloc(n, n);
  gsl_vector *ev = gsl_vector_alloc(n);
  gsl_eigen_symmv_workspace *ws = gsl_eigen_symmv_alloc(n);
  gsl_matrix_memcpy(A, H);
  cr_assert_eq(gsl_eigen_symmv(A, ev, V, ws), 0);
  for (size_t k = 0; k < n; k++) {
    double l = gsl_vector_get(ev, k), f = mode ? fabs(l) : fmax(l, 0.0);
    for (size_t i = 0; i < n; i++)
      for (size_t j = 0; j < n; j++)
        gsl_matrix_set(R, i, j, gsl_matrix_get(R, i, j) + f * gsl_matrix_get(V, i, k) * gsl_matrix_get(V, j, k));
  }
  gsl_matrix_free(A);
  gsl_matrix_free(V);
  gsl_vector_free(ev);
  gsl_eigen_symmv_free(ws);
  return R;
}

static double max_diff(const gsl_matrix *A, const gsl_matrix *B) {
  double m = 0;
  for (size_t i = 0; i < A->size1; i++)
    for (size_t j = 0; j < A->size2; j++) m = fmax(m, fabs(gsl_matrix_get(A, i, j) - gsl_matrix_get(B, i, j)));
  return m;
}

Test(definiteness, names_round_trip) {
  for (int i = 0; i < CB_DEF_COUNT; i++) {
    cb_definiteness d;
    cr_assert_eq(cb_definiteness_from_name(cb_definiteness_names[i], &d), CB_OK);
    cr_assert_eq((int)d, i);
  }
  cr_assert_null(cb_definiteness_names[CB_DEF_COUNT]);
  cb_definiteness d;
  cr_assert_neq(cb_definiteness_from_name("clamp", &d), CB_OK);
  cr_assert_str_eq(cb_definiteness_names[CB_DEF_MIRROR], "mirror");
  cr_assert_str_eq(cb_definiteness_names[CB_DEF_CHOI_KO], "choi-ko");
}

/* H_e has eigenvalues k (along u) and k(1 - L/l) twice; the element Hessian
 * [H_e -H_e; -H_e H_e] has 2k, 2k(1 - L/l) twice, and 0 three times. */
Test(definiteness, exact_spring_eigenvalues_sign_follows_compression) {
  cb_scene *s = one_spring("none");
  const double ls[] = {0.5, 0.8, 0.99, 1.0, 1.01, 1.5};
  for (size_t c = 0; c < sizeof ls / sizeof ls[0]; c++) {
    double x[6], ev[6];
    spring_at(ls[c], x);
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
    cr_assert_eq(cb_dense_eigenvalues(&s->sys.A, NULL, ev), CB_OK);
    double t = 2 * 8000 * (1 - 1 / ls[c]);
    double want[6] = {t < 0 ? t : 0, t < 0 ? t : 0, 0, t < 0 ? 0 : t, t < 0 ? 0 : t, 16000}; /* ascending */
    for (int i = 0; i < 6; i++)
      cr_assert(fabs(ev[i] - want[i]) < 1e-8 * 16000, "l=%g ev[%d]=%g want %g", ls[c], i, ev[i], want[i]);
    if (ls[c] != 1.0)
      cr_assert((ev[0] < -1e-8 * 16000) == (ls[c] < 1), "indefinite exactly when compressed (l = %g)", ls[c]);
  }
  cb_scene_free(s);
}

Test(definiteness, drop_is_transverse_eigenvalue_clamped_at_zero) {
  cb_scene *s = one_spring("drop");
  const double ls[] = {0.3, 0.7, 0.95, 1.0, 1.2, 2.0};
  for (size_t c = 0; c < sizeof ls / sizeof ls[0]; c++) {
    double x[6];
    spring_at(ls[c], x);
    gsl_matrix *H = hessian(s, x, CB_DEF_NONE), *D = hessian(s, x, CB_DEF_DROP), *C = spectral_map(H, 0);
    cr_assert(max_diff(D, C) < 1e-9 * 8000, "l = %g: drop differs from clamp by %g", ls[c], max_diff(D, C));
    if (ls[c] > 1) cr_assert(max_diff(D, H) == 0.0, "stretched: drop must not change H");
    gsl_matrix_free(H);
    gsl_matrix_free(D);
    gsl_matrix_free(C);
  }
  cb_scene_free(s);
}

Test(definiteness, mirror_is_absolute_eigenvalue) {
  cb_scene *s = one_spring("mirror");
  const double ls[] = {0.3, 0.7, 0.95, 1.0, 1.2};
  for (size_t c = 0; c < sizeof ls / sizeof ls[0]; c++) {
    double x[6];
    spring_at(ls[c], x);
    gsl_matrix *H = hessian(s, x, CB_DEF_NONE), *M = hessian(s, x, CB_DEF_MIRROR), *C = spectral_map(H, 1);
    cr_assert(max_diff(M, C) < 1e-9 * 8000, "l = %g: mirror differs from |Lambda| by %g", ls[c], max_diff(M, C));
    gsl_matrix_free(H);
    gsl_matrix_free(M);
    gsl_matrix_free(C);
  }
  cb_scene_free(s);
}

/* The spring pair: middle vertex between pins at +-q, both springs at l = q L. */
static cb_scene *pair(const char *policy, const char *solver) {
  char pol[64], sol[64];
  snprintf(pol, sizeof pol, "integrator.definiteness=%s", policy);
  snprintf(sol, sizeof sol, "solver.method=%s", solver);
  const char *sets[] = {"mesh.type=chain",
                        "mesh.n=3",
                        "mesh.size=2",
                        "mesh.plane=xy",
                        "material.vertex_mass=1",
                        "scene.pins=0 2",
                        "scene.gravity=0 0 0",
                        pol,
                        sol,
                        NULL};
  return test_scene(sets);
}

Test(definiteness, shift_makes_cholmod_succeed_and_reports_mu) {
  cb_scene *s = pair("shift", "cholmod");
  double q = 0.7, x[9] = {-q, 0, 0, 0.01, 0.02, 0, q, 0, 0}, b[3] = {1, -2, 0.5}, dx[3], ev[3];
  cb_system_assemble(&s->sys, x, 900.0, CB_DEF_SHIFT, 0.0);
  cr_assert_eq(cb_dense_eigenvalues(&s->sys.A, NULL, ev), CB_OK);
  double lmin = ev[0];
  cr_assert(lmin < 0, "A must start indefinite, lambda_min = %g", lmin);
  cb_solver *ch;
  cr_assert_eq(cb_solver_alloc("cholmod", NULL, 3, &ch), CB_OK);
  cr_assert_eq(cb_solver_analyze(ch, &s->sys.A), CB_OK);
  cr_assert_eq(cb_solver_factor(ch, &s->sys.A), CB_NOT_SPD);
  cb_shift *sh;
  cr_assert_eq(cb_shift_alloc(3, NULL, &sh), CB_OK);
  cb_shift_stats st;
  double diag[3] = {s->sys.A.val[s->sys.diag[0]], s->sys.A.val[s->sys.diag[1]], s->sys.A.val[s->sys.diag[2]]};
  cr_assert_eq(cb_shift_solve(sh, ch, &s->sys.A, s->sys.diag, b, dx, &st), CB_OK);
  /* mu doubles from beta until A + mu I is SPD: -lambda_min < mu <= 2 (-lambda_min) (+ beta) */
  double beta = 1e-3 * (fabs(diag[0]) + fabs(diag[1]) + fabs(diag[2])) / 3;
  cr_assert(st.mu > -lmin && st.mu <= 2 * -lmin + beta, "mu = %g, lambda_min = %g", st.mu, lmin);
  cr_assert(st.factorizations >= 2);
  for (int i = 0; i < 3; i++) cr_assert(fabs(s->sys.A.val[s->sys.diag[i]] - diag[i] - st.mu) < 1e-9 * st.mu);
  double r[3];
  cb_sparse_matvec(&s->sys.A, dx, r); /* (A + mu I) dx = b */
  for (int i = 0; i < 3; i++) cr_assert(fabs(r[i] - b[i]) < 1e-9 * 3, "residual %g", r[i] - b[i]);
  /* an SPD matrix: no shift, one factorisation */
  double xs[9] = {-1.2, 0, 0, 0, 0, 0, 1.2, 0, 0};
  cb_system_assemble(&s->sys, xs, 900.0, CB_DEF_SHIFT, 0.0);
  cr_assert_eq(cb_shift_solve(sh, ch, &s->sys.A, s->sys.diag, b, dx, &st), CB_OK);
  cr_assert(st.mu == 0 && st.factorizations == 1);
  /* CG: a breakdown also makes shift retry */
  cb_solver *cg;
  cr_assert_eq(cb_solver_alloc("cg", NULL, 3, &cg), CB_OK);
  cr_assert_eq(cb_solver_analyze(cg, &s->sys.A), CB_OK);
  cb_system_assemble(&s->sys, x, 900.0, CB_DEF_SHIFT, 0.0);
  cr_assert_eq(cb_shift_solve(NULL, cg, &s->sys.A, s->sys.diag, b, dx, &st), CB_INDEFINITE);
  cr_assert_eq(cb_shift_solve(sh, cg, &s->sys.A, s->sys.diag, b, dx, &st), CB_OK);
  cr_assert(st.mu > -lmin, "CG shift mu = %g", st.mu);
  cb_solver_free(cg);
  cb_shift_free(sh);
  cb_solver_free(ch);
  cb_scene_free(s);
}

/* Newton on a compressed cloth: none stops at not_spd, shift goes through
 * and records mu in the step stats. */
Test(definiteness, newton_with_shift_on_compressed_cloth) {
  const char *pols[] = {"none", "shift"};
  for (int p = 0; p < 2; p++) {
    char pol[64];
    snprintf(pol, sizeof pol, "integrator.definiteness=%s", pols[p]);
    const char *sets[] = {"mesh.n=7", "mesh.size=3", "material.vertex_mass=1", "scene.initial_scale=0.7", pol, NULL};
    cb_scene *s = test_scene(sets);
    cb_integrator *it = test_integrator(sets, s, NULL, NULL);
    double x[3 * 49], v[3 * 49];
    memcpy(x, s->x0, sizeof x);
    memcpy(v, s->v0, sizeof v);
    cb_step_stats st;
    int r = cb_integrator_step(it, x, v, &st);
    if (p == 0) {
      cr_assert_eq(r, CB_NOT_SPD);
      cr_assert(st.shift_mu == 0);
    } else {
      cr_assert(r == CB_OK || r == CB_NOT_CONVERGED, "shift: %s", cb_status_name(r));
      cr_assert(st.shift_mu > 0 && st.factorizations > st.newton_iters, "mu %g, %d factorizations for %d iterations",
                st.shift_mu, st.factorizations, st.newton_iters);
    }
    cb_integrator_free(it);
    cb_scene_free(s);
  }
}

/* ---- Choi-Ko --------------------------------------------------------------- */

Test(choi_ko, arc_geometry_and_limits) {
  double L = 0.5, kb = 0.01, E, dE, d2E;
  const double rho[] = {0.999999, 0.99, 0.9, 0.7, 0.5, 0.2, 0.01};
  for (size_t i = 0; i < sizeof rho / sizeof rho[0]; i++) {
    double th = cb_choi_ko_response(L, rho[i] * L, kb, &E, &dE, &d2E);
    cr_assert(fabs(sin(th) / th - rho[i]) < 1e-13, "sinc(theta) = %.17g, want %g", sin(th) / th, rho[i]);
    double kappa = 2 * th / L;
    cr_assert(fabs(E - 0.5 * kb * L * kappa * kappa) < 1e-12 * E, "E = k_b L kappa^2 / 2");
    double fb = kb * kappa * kappa / (sin(th) / th - cos(th)); /* the paper's buckling force */
    if (th > 1e-3) cr_assert(fabs(-dE - fb) < 1e-10 * fb, "f_b = %g, -dE/dl = %g", fb, -dE);
  }
  cb_choi_ko_response(L, L * (1 - 1e-12), kb, &E, &dE, &d2E);
  cr_assert(fabs(-dE - 12 * kb / (L * L)) < 1e-6 * 12 * kb / (L * L), "f_b(L-) = 12 k_b/L^2, got %g", -dE);
  cr_assert(fabs(d2E - 36 * kb / (5 * L * L * L)) < 1e-6 * d2E, "E''(L-) = 36 k_b/(5 L^3), got %g", d2E);
  cb_choi_ko_response(L, 1e-9 * L, kb, &E, &dE, &d2E);
  cr_assert(fabs(-dE - 4 * PI * PI * kb / (L * L)) < 1e-6 * -dE, "f_b(0+) = 4 pi^2 k_b/L^2, got %g", -dE);
  cb_choi_ko_response(L, L, kb, &E, &dE, &d2E);
  cr_assert(E == 0 && dE == 0 && d2E == 0, "no buckling energy at l = L");
}

Test(choi_ko, derivatives_match_finite_differences_and_stiffness_is_positive) {
  double L = 0.7, kb = 0.03;
  for (double r = 0.02; r < 0.999; r += 0.0371) {
    double l = r * L, h = 1e-6 * L, E, dE, d2E, Ep, dEp, d2Ep, Em, dEm, d2Em;
    cb_choi_ko_response(L, l, kb, &E, &dE, &d2E);
    cb_choi_ko_response(L, l + h, kb, &Ep, &dEp, &d2Ep);
    cb_choi_ko_response(L, l - h, kb, &Em, &dEm, &d2Em);
    double fd1 = (Ep - Em) / (2 * h), fd2 = (dEp - dEm) / (2 * h);
    cr_assert(fabs(fd1 - dE) < 1e-6 * fabs(dE), "l/L = %g: dE/dl %g, FD %g", r, dE, fd1);
    cr_assert(fabs(fd2 - d2E) < 1e-5 * fabs(d2E), "l/L = %g: d2E/dl2 %g, FD %g", r, d2E, fd2);
    cr_assert(d2E > 0, "the buckled spring's longitudinal stiffness is positive (l/L = %g)", r);
    /* transverse eigenvalue E'/l is negative but bounded by the bending stiffness */
    cr_assert(dE / l < 0 && -dE / l <= 4 * PI * PI * kb / (L * L * l) * (1 + 1e-12));
  }
}

Test(choi_ko, regularised_response_is_continuous) {
  double k = 8000, L = 0.5, kb = 0.01, E1, d1, s1, E2, d2, s2;
  cb_choi_ko c;
  cr_assert_eq(cb_choi_ko_init(&c, k, L, kb), CB_OK);
  double ls = L - c.lc, fb, Eb, d2b;
  cb_choi_ko_response(L, ls, kb, &Eb, &fb, &d2b);
  cr_assert(fabs(k * c.lc + fb) < 1e-9 * k * c.lc, "at l*: k (L - l*) = f_b(l*)");
  cr_assert(c.lc > 0 && c.lc < 1e-3 * L, "buckles after %g m of compression", c.lc);
  cb_choi_ko_eval(&c, ls * (1 + 1e-12), &E1, &d1, &s1);
  cb_choi_ko_eval(&c, ls * (1 - 1e-12), &E2, &d2, &s2);
  cr_assert(fabs(E1 - E2) < 1e-12 && fabs(d1 - d2) < 1e-6 * fabs(d1), "E and E' continuous at l*");
  cr_assert(s1 == k && s2 < 1, "stiffness k before l*, the arc's after");
  cb_choi_ko_eval(&c, L, &E1, &d1, &s1);
  cr_assert(E1 == 0 && d1 == 0);
  /* a too stiff k_b is refused */
  cr_assert_neq(cb_choi_ko_init(&c, k, L, 20.0), CB_OK);
}

/* FD of the scene energy's gradient and of the Hessian on a crumpled cloth
 * where springs are stretched, slightly and strongly compressed. */
Test(choi_ko, spring_term_gradient_and_hessian_match_finite_differences) {
  const char *sets[] = {"mesh.n=4",
                        "mesh.size=1.5",
                        "material.vertex_mass=1",
                        "scene.pins=none",
                        "scene.gravity=0 0 0",
                        "integrator.definiteness=choi-ko",
                        "material.buckling_kb=0.002",
                        NULL};
  cb_scene *s = test_scene(sets);
  int n = 3 * s->mesh.nv;
  double x[48], g[48], gp[48], gm[48];
  cb_rng r = cb_rng_raw(12345);
  for (int i = 0; i < n; i++) /* 0.95 x rest + a deterministic perturbation */
    x[i] = 0.95 * s->mesh.x[i] + 0.25 * (cb_rng_uniform(&r) - 0.5);
  double f = cb_compressed_fraction(&s->sys, x);
  cr_assert(f > 0.2 && f < 0.9, "a mix of compressed and stretched springs (%g)", f);
  cb_system_energy(&s->sys, x, g, NULL);
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_CHOI_KO, 0.0);
  gsl_matrix *H = test_dense(&s->sys.A);
  double worst_small = 0; /* FD error on entries of buckled springs (|H_ij| < 1) */
  int nsmall = 0;
  for (int i = 0; i < n; i++) {
    double h = 1e-6, xi = x[i];
    x[i] = xi + h;
    double Ep = cb_system_energy(&s->sys, x, gp, NULL);
    x[i] = xi - h;
    double Em = cb_system_energy(&s->sys, x, gm, NULL);
    x[i] = xi;
    cr_assert(fabs((Ep - Em) / (2 * h) - g[i]) < 1e-5 * (1 + fabs(g[i])), "grad[%d] %g vs FD %g", i, g[i],
              (Ep - Em) / (2 * h));
    for (int j = 0; j < n; j++) {
      double fd = (gp[j] - gm[j]) / (2 * h), hij = gsl_matrix_get(H, (size_t)j, (size_t)i);
      cr_assert(fabs(fd - hij) < 1e-6 * fabs(hij) + 1e-5, "H[%d][%d] %g vs FD %g", j, i, hij, fd);
      if (fabs(hij) < 1 && fabs(hij) > 1e-3) {
        worst_small = fmax(worst_small, fabs(fd - hij) / fabs(hij));
        nsmall++;
      }
      cr_assert(fabs(hij - gsl_matrix_get(H, (size_t)i, (size_t)j)) == 0.0, "symmetric");
    }
  }
  cr_assert(nsmall > 20, "the crumpled cloth has buckled springs (%d small entries)", nsmall);
  cr_assert(worst_small < 1e-3, "buckled springs' Hessian entries within %g relative", worst_small);
  gsl_matrix_free(H);
  cb_scene_free(s);
}

/* One buckled spring: H_e = E'' uu^T + (E'/l)(I - uu^T), so the element
 * Hessian has eigenvalues 2 E'' and 2 E'/l (twice), E' and E'' being the
 * (FD-checked) scalar derivatives of the arc energy. */
Test(choi_ko, buckled_spring_hessian_eigenvalues) {
  const char *sets[] = {"mesh.type=chain",
                        "mesh.n=2",
                        "mesh.size=1",
                        "material.vertex_mass=1",
                        "scene.pins=none",
                        "scene.gravity=0 0 0",
                        "integrator.definiteness=choi-ko",
                        "material.buckling_kb=0.05",
                        NULL};
  cb_scene *s = test_scene(sets);
  double x[6], ev[6], E, dE, d2E;
  spring_at(0.6, x);
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_CHOI_KO, 0.0);
  cr_assert_eq(cb_dense_eigenvalues(&s->sys.A, NULL, ev), CB_OK);
  cb_choi_ko c;
  cr_assert_eq(cb_choi_ko_init(&c, 8000, 1.0, 0.05), CB_OK);
  cb_choi_ko_eval(&c, 0.6, &E, &dE, &d2E);
  double want[6] = {2 * dE / 0.6, 2 * dE / 0.6, 0, 0, 0, 2 * d2E};
  for (int i = 0; i < 6; i++) cr_assert(fabs(ev[i] - want[i]) < 1e-9, "ev[%d] = %g, want %g", i, ev[i], want[i]);
  cr_assert(fabs(cb_system_energy(&s->sys, x, NULL, NULL) - E) < 1e-14, "E(l)");
  cb_scene_free(s);
}

/* "SPD-friendly": on the spring pair compressed to 0.7 L the lecture's exact
 * A is indefinite (lambda_min = m/dt^2 + 2k(1 - L/l) < 0) while Choi-Ko's is
 * SPD, since its negative curvature is set by k_b, not k. */
Test(choi_ko, pair_matrix_is_spd_where_the_exact_one_is_not) {
  cb_scene *n = pair("none", "cholmod"), *c = pair("choi-ko", "cholmod");
  for (double q = 0.9; q > 0.15; q -= 0.1) {
    double x[9] = {-q, 0, 0, 0, 0, 0, q, 0, 0}, ev[3], evc[3];
    cb_system_assemble(&n->sys, x, 900.0, CB_DEF_NONE, 0.0);
    cb_system_assemble(&c->sys, x, 900.0, CB_DEF_CHOI_KO, 0.0);
    cr_assert_eq(cb_dense_eigenvalues(&n->sys.A, NULL, ev), CB_OK);
    cr_assert_eq(cb_dense_eigenvalues(&c->sys.A, NULL, evc), CB_OK);
    cr_assert(fabs(ev[0] - (900 + 2 * 8000 * (1 - 1 / q))) < 1e-8 * 16000, "exact lambda_min");
    cr_assert(ev[0] < 0 && evc[0] > 0, "q = %g: exact %g, choi-ko %g", q, ev[0], evc[0]);
    cr_assert(evc[0] >= 900 - 2 * 4 * PI * PI * 0.01 / q * (1 + 1e-12), "bounded by the bending stiffness");
  }
  cb_scene_free(n);
  cb_scene_free(c);
}

Test(choi_ko, integrator_refuses_a_scene_built_without_it) {
  const char *sets[] = {"mesh.n=4", "integrator.definiteness=drop", NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator_params p = cb_integrator_params_default();
  cb_newton_params np = cb_newton_params_default();
  np.definiteness = CB_DEF_CHOI_KO;
  cb_integrator *it = NULL;
  cr_assert_neq(cb_integrator_alloc("newton", s, &p, &np, "cholmod", NULL, &it), CB_OK);
  cr_assert_null(it);
  cb_scene_free(s);
}

/* ---- driven pins ----------------------------------------------------------- */

Test(pins, squeeze_moves_pins_at_constant_velocity_in_both_integrators) {
  const char *methods[] = {"explicit", "newton"};
  for (int m = 0; m < 2; m++) {
    char meth[64];
    snprintf(meth, sizeof meth, "integrator.method=%s", methods[m]);
    const char *sets[] = {"mesh.n=5",
                          "mesh.size=2",
                          "material.vertex_mass=1",
                          "scene.pins=0 5 10 15 20 4 9 14 19 24",
                          "scene.pin_squeeze=0.5 0 0",
                          "integrator.dt=1/100",
                          meth,
                          NULL};
    cb_scene *s = test_scene(sets);
    for (int k = 0; k < s->npinned; k++) { /* columns i = 0 (x = -1) move +x, i = 4 (x = +1) move -x */
      int i = s->pinned[k];
      double want = s->mesh.x[3 * i] < 0 ? 0.5 : -0.5;
      cr_assert(s->v0[3 * i] == want && s->v0[3 * i + 1] == 0 && s->v0[3 * i + 2] == 0, "pin %d v0", i);
    }
    cb_integrator *it = test_integrator(sets, s, NULL, NULL);
    double x[75], v[75];
    memcpy(x, s->x0, sizeof x);
    memcpy(v, s->v0, sizeof v);
    cb_step_stats st;
    for (int n = 1; n <= 20; n++) {
      int r = cb_integrator_step(it, x, v, &st);
      cr_assert(r == CB_OK || r == CB_NOT_CONVERGED, "%s step %d: %s", methods[m], n, cb_status_name(r));
      for (int k = 0; k < s->npinned; k++) {
        int i = s->pinned[k];
        for (int a = 0; a < 3; a++) {
          cr_assert(fabs(x[3 * i + a] - (s->x0[3 * i + a] + n * 0.01 * s->v0[3 * i + a])) < 1e-12, "pin position");
          cr_assert(v[3 * i + a] == s->v0[3 * i + a], "pin velocity kept");
        }
      }
    }
    cb_integrator_free(it);
    cb_scene_free(s);
  }
}

Test(pins, zero_squeeze_keeps_pins_fixed) {
  const char *sets[] = {"mesh.n=5", "material.vertex_mass=1", NULL};
  cb_scene *s = test_scene(sets);
  for (int i = 0; i < 3 * s->mesh.nv; i++) cr_assert(s->v0[i] == 0);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  double x[75], v[75];
  memcpy(x, s->x0, sizeof x);
  memcpy(v, s->v0, sizeof v);
  cb_step_stats st;
  cb_integrator_step(it, x, v, &st);
  for (int k = 0; k < s->npinned; k++)
    for (int a = 0; a < 3; a++) cr_assert(x[3 * s->pinned[k] + a] == s->x0[3 * s->pinned[k] + a]);
  cb_integrator_free(it);
  cb_scene_free(s);
}

/* ---- SPD probes ------------------------------------------------------------ */

/* Textbook CG from x = 0 (A dense-free: cb_sparse_matvec), written here so that the probe's CG
 * witness is checked against an independent run: returns CB_INDEFINITE with *iters = k at the first
 * k with p^T A p <= 0, CB_OK with *iters = k + 1 once |r|/|b| <= tol, else CB_NOT_CONVERGED. */
static int textbook_cg(const cb_sparse *A, const double *b, double tol, int max_iters, int *iters) {
  int n = A->n, st = CB_NOT_CONVERGED;
  double *x = calloc((size_t)n, sizeof *x), *r = malloc((size_t)n * sizeof *r), *p = malloc((size_t)n * sizeof *p),
         *q = malloc((size_t)n * sizeof *q);
  cr_assert(x && r && p && q);
  double rr = 0, bb = 0;
  for (int i = 0; i < n; i++) r[i] = p[i] = b[i], rr += b[i] * b[i];
  bb = rr;
  *iters = max_iters;
  for (int k = 0; k < max_iters; k++) {
    cb_sparse_matvec(A, p, q);
    double pq = 0;
    for (int i = 0; i < n; i++) pq += p[i] * q[i];
    if (pq <= 0) {
      st = CB_INDEFINITE;
      *iters = k;
      break;
    }
    double a = rr / pq, rr1 = 0;
    for (int i = 0; i < n; i++) x[i] += a * p[i], r[i] -= a * q[i], rr1 += r[i] * r[i];
    if (sqrt(rr1 / bb) <= tol) {
      st = CB_OK;
      *iters = k + 1;
      break;
    }
    for (int i = 0; i < n; i++) p[i] = r[i] + rr1 / rr * p[i];
    rr = rr1;
  }
  free(x), free(r), free(p), free(q);
  return st;
}

Test(probe, witnesses_agree_with_dense_eigenvalues) {
  gsl_set_error_handler_off();
  const char *sets[] = {"mesh.n=12", "material.vertex_mass=1", "integrator.definiteness=none", NULL};
  cb_scene *s = test_scene(sets);
  double scales[] = {1.0, 0.9};
  for (int c = 0; c < 2; c++) {
    double x[3 * 144];
    for (int i = 0; i < 3 * 144; i++) x[i] = scales[c] * s->mesh.x[i];
    cb_system_assemble(&s->sys, x, 900.0, CB_DEF_NONE, 0.0);
    int n = s->sys.A.n;
    double ev[3 * 144], b[3 * 144];
    for (int i = 0; i < n; i++) b[i] = sin(1.0 + i);
    cr_assert_eq(cb_dense_eigenvalues(&s->sys.A, NULL, ev), CB_OK);
    cb_spd_probe_params pp = cb_spd_probe_params_default();
    pp.dense_max = 0; /* force Lanczos */
    pp.lanczos.max_steps = 300;
    pp.lanczos.tol = 1e-10;
    cb_spd_probe *pr;
    cr_assert_eq(cb_spd_probe_alloc(&s->sys.A, &pp, &pr), CB_OK);
    cb_spd_probe_result r;
    cr_assert_eq(cb_spd_probe_run(pr, &s->sys.A, b, CB_PROBE_CHOLMOD | CB_PROBE_EIG | CB_PROBE_CG, &r), CB_OK);
    cr_assert(r.min_eig >= ev[0] - 1e-6 * fabs(ev[0]), "a Ritz value is never below lambda_min");
    cr_assert(fabs(r.min_eig - ev[0]) < 1e-6 * fabs(ev[n - 1]), "Lanczos %g vs dense %g", r.min_eig, ev[0]);
    cr_assert_eq(r.cholmod_status == CB_OK, ev[0] > 0, "CHOLMOD agrees with the sign of lambda_min (%g)", ev[0]);
    /* the CG witness against an independent textbook CG on the same (A, b, tol, cap) */
    int it_ref, st_ref = textbook_cg(&s->sys.A, b, pp.cg.tol, pp.cg.max_iters, &it_ref);
    if (ev[0] > 0) cr_assert_eq(r.cg_status, CB_OK);
    cr_assert_eq(r.cg_status, st_ref, "probe CG %s, textbook CG %s", cb_status_name(r.cg_status),
                 cb_status_name(st_ref));
    if (st_ref == CB_INDEFINITE)
      cr_assert_eq(r.cg_iters, it_ref, "breakdown at %d, textbook at %d", r.cg_iters, it_ref);
    else cr_assert(abs(r.cg_iters - it_ref) <= 1, "CG iterations %d, textbook %d", r.cg_iters, it_ref);
    cr_assert_eq(c == 1, ev[0] < 0, "rest is SPD, 0.9x compressed is not");
    cb_spd_probe_free(pr);
  }
  cb_scene_free(s);
}

Test(probe, restricted_spring_pair_1d_is_spd_2d_3d_are_not) {
  gsl_set_error_handler_off();
  cb_scene *s = pair("none", "cholmod");
  double q = 0.7, x[9] = {-q, 0, 0, 0, 0, 0, q, 0, 0};
  cb_system_assemble(&s->sys, x, 900.0, CB_DEF_NONE, 0.0);
  for (int dim = 1; dim <= 3; dim++) {
    int keep[3] = {1, dim >= 2, dim >= 3}, ok;
    double lmin;
    cr_assert_eq(cb_dense_restricted_spd(&s->sys.A, keep, &lmin, &ok), CB_OK);
    double want = dim == 1 ? 900 + 2 * 8000 : 900 + 2 * 8000 * (1 - 1 / q); /* E'' = k in 1D */
    cr_assert(fabs(lmin - want) < 1e-8 * 16000, "dim %d: %g want %g", dim, lmin, want);
    cr_assert_eq(ok, dim == 1);
  }
  cb_scene_free(s);
}
