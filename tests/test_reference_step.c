/* The reference step (lib/instruments/reference.c), the M-norm error, the Newton
 * methods of lib/instruments/method.c, and the alpha = 1/3 bound for Chebyshev-Jacobi.
 * The implicit Euler residual is computed here from the spring and gravity
 * formulas, independently of the library's energy terms. */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "method.h"
#include "pareto.h"
#include "reference.h"
#include "support.h"

/* |M (x - x0 - dt v0)/dt^2 - f(x)| over free DOFs, f = springs + gravity,
 * divided by |M g| (the size of the forces at rest). */
static double ie_residual(const cb_scene *s, double dt, const double *x0, const double *v0, const double *x) {
  int nv = s->mesh.nv;
  double *f = calloc((size_t)3 * nv, sizeof(double));
  const double k = s->def.stretch_k;
  for (int e = 0; e < s->topo.ne; e++) { /* f_i += -k (l - L) u, u = (x_i - x_j)/l */
    int i = s->topo.edge[2 * e], j = s->topo.edge[2 * e + 1];
    double d[3], d0[3], l = 0, L = 0;
    for (int a = 0; a < 3; a++) {
      d[a] = x[3 * i + a] - x[3 * j + a];
      d0[a] = s->mesh.x[3 * i + a] - s->mesh.x[3 * j + a];
      l += d[a] * d[a];
      L += d0[a] * d0[a];
    }
    l = sqrt(l);
    L = sqrt(L);
    for (int a = 0; a < 3; a++) {
      double fa = -k * (l - L) * d[a] / l;
      f[3 * i + a] += fa;
      f[3 * j + a] -= fa;
    }
  }
  double r2 = 0, g2 = 0;
  for (int i = 0; i < nv; i++) {
    if (s->free_index[i] < 0) continue;
    for (int a = 0; a < 3; a++) {
      double mg = s->mass[i] * s->gravity[a];
      double r = s->mass[i] * (x[3 * i + a] - x0[3 * i + a] - dt * v0[3 * i + a]) / (dt * dt) - f[3 * i + a] - mg;
      r2 += r * r;
      g2 += mg * mg;
    }
  }
  free(f);
  return sqrt(r2 / g2);
}

static cb_scene *small_scene(const char *scale) {
  char s1[64];
  snprintf(s1, sizeof s1, "scene.initial_scale=%s", scale);
  const char *sets[] = {"mesh.n=7", "mesh.size=3", "material.vertex_mass=1", "material.stretch_k=5000", s1, NULL};
  return test_scene(sets);
}

Test(reference, converged_step_satisfies_implicit_euler) {
  const char *scales[] = {"1", "1.4", "0.8"}; /* rest, stretched, compressed (indefinite A) */
  for (int c = 0; c < 3; c++) {
    cb_scene *s = small_scene(scales[c]);
    int n3 = 3 * s->mesh.nv;
    double *v0 = malloc((size_t)n3 * sizeof(double)), *xs = malloc((size_t)n3 * sizeof(double));
    for (int i = 0; i < n3; i++) v0[i] = s->free_index[i / 3] >= 0 ? 0.3 * sin(1.7 * i) : 0.0;
    cb_reference_params p = cb_reference_params_default();
    p.dt = 1.0 / 30;
    cb_reference *r;
    cr_assert_eq(cb_reference_alloc(s, &p, &r), CB_OK, "%s", cb_error_message());
    cb_reference_stats st;
    cr_assert_eq(cb_reference_step(r, s->x0, v0, xs, &st), CB_OK, "scale %s: %s", scales[c], cb_status_name(st.status));
    double res = ie_residual(s, p.dt, s->x0, v0, xs);
    cr_assert(res < 1e-9, "scale %s: implicit Euler residual %g", scales[c], res);
    for (int i = 0; i < s->npinned; i++) /* pins stay */
      for (int a = 0; a < 3; a++) cr_assert_eq(xs[3 * s->pinned[i] + a], s->x0[3 * s->pinned[i] + a]);
    if (c == 2) cr_assert(st.not_spd_fallbacks > 0, "the compressed start should make A indefinite");
    cb_reference_free(r);
    free(v0);
    free(xs);
    cb_scene_free(s);
  }
}

Test(reference, objective_gradient_matches_finite_differences) {
  cb_scene *s = small_scene("1.2");
  int n3 = 3 * s->mesh.nv, nf = s->sys.A.n;
  double *v0 = calloc((size_t)n3, sizeof(double)), *x = malloc((size_t)n3 * sizeof(double));
  double *g = malloc((size_t)nf * sizeof(double));
  for (int i = 0; i < n3; i++) x[i] = s->x0[i] + 0.01 * cos(0.9 * i);
  cb_reference_params p = cb_reference_params_default();
  cb_reference *r;
  cr_assert_eq(cb_reference_alloc(s, &p, &r), CB_OK);
  cb_reference_objective(r, s->x0, v0, x, g);
  for (int k = 0; k < nf; k += 7) {
    int i = 3 * s->free_vertex[k / 3] + k % 3;
    double h = 1e-6, xi = x[i];
    x[i] = xi + h;
    double Fp = cb_reference_objective(r, s->x0, v0, x, NULL);
    x[i] = xi - h;
    double Fm = cb_reference_objective(r, s->x0, v0, x, NULL);
    x[i] = xi;
    double fd = (Fp - Fm) / (2 * h);
    cr_assert(fabs(fd - g[k]) <= 1e-5 * (1 + fabs(g[k])), "dof %d: fd %g, grad %g", k, fd, g[k]);
  }
  cb_reference_free(r);
  free(v0);
  free(x);
  free(g);
  cb_scene_free(s);
}

Test(reference, mnorm_error) {
  cb_scene *s = small_scene("1");
  int n3 = 3 * s->mesh.nv, v = s->free_vertex[3];
  double *a = malloc((size_t)n3 * sizeof(double)), *b = malloc((size_t)n3 * sizeof(double));
  memcpy(a, s->x0, (size_t)n3 * sizeof(double));
  memcpy(b, s->x0, (size_t)n3 * sizeof(double));
  cr_assert_eq(cb_mnorm_diff(s, a, b), 0.0);
  b[3 * v + 1] += 0.5; /* one free vertex moved by 0.5 m: |a - b|_M = sqrt(m) 0.5 */
  cr_assert_float_eq(cb_mnorm_diff(s, a, b), sqrt(s->mass[v]) * 0.5, 1e-15);
  /* x = x*: error 0; x = x0: error 1 */
  cr_assert_eq(cb_step_error(s, b, b, a), 0.0);
  cr_assert_float_eq(cb_step_error(s, a, b, a), 1.0, 1e-15);
  /* pinned vertices do not count */
  int p = s->pinned[0];
  b[3 * p] += 3.0;
  cr_assert_float_eq(cb_mnorm_diff(s, a, b), sqrt(s->mass[v]) * 0.5, 1e-15);
  double msum = 0;
  for (int i = 0; i < s->mesh.nv; i++) msum += s->free_index[i] >= 0 ? s->mass[i] : 0;
  cr_assert_float_eq(cb_free_mass(s), msum, 1e-12);
  free(a);
  free(b);
  cb_scene_free(s);
}

/* The reference's last iterations are Newton's: quadratic convergence. */
static double glog[256];
static int hlog[256], nlog;
static void logger(void *ctx, int iter, double gn, double rel, double F, double alpha, int hessian) {
  (void)ctx;
  (void)iter;
  (void)rel;
  (void)F;
  (void)alpha;
  if (nlog < 256) {
    glog[nlog] = gn;
    hlog[nlog] = hessian == 1;
    nlog++;
  }
}

Test(reference, converges_quadratically_from_a_stretched_start) {
  cb_scene *s = small_scene("1.5");
  int n3 = 3 * s->mesh.nv;
  double *xs = malloc((size_t)n3 * sizeof(double));
  cb_reference_params p = cb_reference_params_default();
  p.log = logger;
  cb_reference *r;
  cr_assert_eq(cb_reference_alloc(s, &p, &r), CB_OK);
  cb_reference_stats st;
  nlog = 0;
  cr_assert_eq(cb_reference_step(r, s->x0, s->v0, xs, &st), CB_OK);
  cr_assert_eq(nlog, st.iters + 1);
  double q;
  cr_assert_eq(cb_convergence_order(glog, hlog, nlog, 0.1, 1e-11, &q, NULL), 0, "no triple in the local regime");
  cr_assert(q > 1.8, "order %g", q);
  cb_reference_free(r);
  free(xs);
  cb_scene_free(s);
}

Test(method, newton_errors_shrink_with_K_and_converged_matches_reference) {
  cb_scene *s = small_scene("1.3");
  int n3 = 3 * s->mesh.nv;
  double *xs = malloc((size_t)n3 * sizeof(double));
  cb_reference_params p = cb_reference_params_default();
  cb_reference *r;
  cr_assert_eq(cb_reference_alloc(s, &p, &r), CB_OK);
  cb_reference_stats rs;
  cr_assert_eq(cb_reference_step(r, s->x0, s->v0, xs, &rs), CB_OK);
  double Fs = cb_reference_objective(r, s->x0, s->v0, xs, NULL);
  cb_method_work w;
  cr_assert_eq(cb_method_work_alloc(s, &w), CB_OK);
  const int Ks[] = {1, 2, 3, 0};
  const char *inner[] = {"cholmod", "cg_tol", "cheb_tol"};
  for (int i = 0; i < 3; i++) {
    double prev = INFINITY;
    for (int k = 0; k < 4; k++) {
      cb_method m;
      cr_assert_eq(cb_method_make(Ks[k], 1, inner[i], &m), CB_OK);
      cb_integrator *it;
      cr_assert_eq(cb_method_integrator(&m, s, p.dt, cb_method_hook, &w, &it), CB_OK, "%s", cb_error_message());
      cb_step_result res;
      int st = cb_method_step(it, &w, r, s->x0, s->v0, xs, Fs, &res);
      cr_assert(st == CB_OK || st == CB_NOT_CONVERGED, "%s %s: %s", m.name, inner[i], cb_status_name(st));
      cr_assert(res.step_error < prev, "%s %s: error %g not below %g", m.name, inner[i], res.step_error, prev);
      cr_assert(res.f_minus_fstar > -1e-8 * fabs(Fs), "F(x) below F(x*) by %g", res.f_minus_fstar);
      if (Ks[k] == 1) cr_assert_eq(res.st.newton_iters, 1);
      if (Ks[k] == 0) cr_assert(res.step_error < 1e-6, "converged %s: error %g", inner[i], res.step_error);
      prev = res.step_error;
      cb_integrator_free(it);
    }
  }
  cb_method_work_free(&w);
  cb_reference_free(r);
  free(xs);
  cb_scene_free(s);
}

Test(method, labels) {
  cb_method m;
  cr_assert_eq(cb_method_make(1, 0, "cg32", &m), CB_OK);
  cr_assert_str_eq(m.solver, "cg");
  cr_assert_eq(m.sp.max_iters, 32);
  cr_assert_str_eq(m.name, "newton_k1");
  cr_assert_eq(cb_method_make(0, 1, "cheb_tol", &m), CB_OK);
  cr_assert_str_eq(m.name, "newton_converged");
  cr_assert_float_eq(m.sp.alpha, 1.0 / 3.0, 1e-15);
  cr_assert_float_eq(m.sp.tol, 1e-8, 1e-20);
  cr_assert_eq(cb_method_make(1, 0, "cheb32_alpha1", &m), CB_OK);
  cr_assert_eq(m.sp.alpha, 1.0);
  cr_assert_neq(cb_method_make(1, 0, "gauss_seidel", &m), CB_OK);
  cr_assert_neq(cb_method_make(-1, 0, "cholmod", &m), CB_OK);
}

/* method.h's argument: lambda_max(D^-1 A) < 6 for A = M/dt^2 + H_drop, so
 * alpha = 1/3 makes weighted Jacobi converge; checked by dense eigenvalues
 * on stretched, compressed and crumpled states. */
Test(method, chebyshev_alpha_bound) {
  cb_scene *s = small_scene("1");
  int n3 = 3 * s->mesh.nv, n = s->sys.A.n;
  double *x = malloc((size_t)n3 * sizeof(double)), *d = malloc((size_t)n * sizeof(double));
  double *ev = malloc((size_t)n * sizeof(double));
  for (int c = 0; c < 4; c++) {
    for (int i = 0; i < n3; i++) {
      double crumple = c == 3 ? 0.2 * sin(2.3 * i) + 0.2 * cos(0.7 * i * i) : 0.0;
      x[i] = s->x0[i] * (c == 0 ? 1.0 : c == 1 ? 2.0 : 0.5) + crumple;
    }
    cb_system_assemble(&s->sys, x, 1e-6, CB_DEF_DROP, 0.0); /* tiny mass term: the worst case */
    for (int i = 0; i < n; i++) d[i] = 1.0 / sqrt(s->sys.A.val[s->sys.diag[i]]);
    cr_assert_eq(cb_dense_eigenvalues(&s->sys.A, d, ev), CB_OK);
    cr_assert(ev[n - 1] < 6.0, "case %d: lambda_max(D^-1 A) = %g", c, ev[n - 1]);
    cr_assert(ev[0] > 0, "case %d: lambda_min = %g", c, ev[0]);
  }
  free(x);
  free(d);
  free(ev);
  cb_scene_free(s);
}

/* A measured step is the same however many steps the integrator made before
 * it (issue 21: newton_vs_bw's stiff/newton_k2/cheb32 row differed between
 * two full runs of one binary; the timing rounds repeat a step a number of
 * times that depends on the clock, and the Chebyshev inner solve reused its
 * spectral bounds across them): Newton K = 2 with 32 Chebyshev iterations on
 * a stiff cloth, measured first and again after 7 more steps, bit for bit. */
Test(reference_step, a_measured_step_does_not_depend_on_the_steps_before) {
  const char *sets[] = {"mesh.n=10", "material.stretch_k=1e6", "material.vertex_mass=0.05", NULL};
  cb_scene *s = test_scene(sets);
  int n3 = 3 * s->mesh.nv;
  double *x0 = malloc((size_t)n3 * sizeof(double)), *v0 = malloc((size_t)n3 * sizeof(double));
  double *xs = malloc((size_t)n3 * sizeof(double)), *first = malloc((size_t)n3 * sizeof(double));
  memcpy(x0, s->x0, (size_t)n3 * sizeof(double));
  memcpy(v0, s->v0, (size_t)n3 * sizeof(double));
  cb_reference_params p = cb_reference_params_default();
  cb_reference *r;
  cr_assert_eq(cb_reference_alloc(s, &p, &r), CB_OK);
  cb_reference_stats rs;
  for (int k = 0; k < 3; k++) { /* a swinging state along the reference trajectory */
    cr_assert_eq(cb_reference_step(r, x0, v0, xs, &rs), CB_OK);
    for (int i = 0; i < n3; i++) {
      v0[i] = (xs[i] - x0[i]) / p.dt;
      x0[i] = xs[i];
    }
  }
  cr_assert_eq(cb_reference_step(r, x0, v0, xs, &rs), CB_OK);
  double Fs = cb_reference_objective(r, x0, v0, xs, NULL);
  cb_method m;
  cr_assert_eq(cb_method_make(2, 0, "cheb32", &m), CB_OK);
  cb_method_work w;
  cr_assert_eq(cb_method_work_alloc(s, &w), CB_OK);
  cb_integrator *it;
  cr_assert_eq(cb_method_integrator(&m, s, p.dt, cb_method_hook, &w, &it), CB_OK, "%s", cb_error_message());
  cb_step_result a, b;
  cb_method_step(it, &w, r, x0, v0, xs, Fs, &a);
  memcpy(first, w.x, (size_t)n3 * sizeof(double));
  for (int k = 0; k < 7; k++) cb_method_step(it, &w, r, x0, v0, xs, Fs, &b);
  cr_expect(memcmp(first, w.x, (size_t)n3 * sizeof(double)) == 0, "the step's positions differ after 7 more steps");
  cr_expect(a.step_error == b.step_error, "step error %.17g first, %.17g after 7 more steps", a.step_error,
            b.step_error);
  cr_expect(a.st.linear_iters == b.st.linear_iters);
  cr_log_info("newton_k2/cheb32 on a stiff cloth: step error %.6g, %d Chebyshev iterations\n", a.step_error,
              a.st.linear_iters);
  cb_integrator_free(it);
  cb_method_work_free(&w);
  cb_reference_free(r);
  free(x0);
  free(v0);
  free(xs);
  free(first);
  cb_scene_free(s);
}
