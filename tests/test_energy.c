/* Energy terms: finite-difference checks of every term's gradient and
 * Hessian, symmetry, the definiteness policy on single springs and on grids,
 * and A = s M + H + mu I.
 *
 * All expected numbers are derived here: gradients and Hessians by central
 * differences of the library's energy (resp. gradient), spring eigenvalues
 * from the lecture's formula H_e = k uu^T + k(1 - L/l)(I - uu^T), masses from
 * the rest triangle areas. */
#include <criterion/criterion.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support.h"
#include "rng.h"

/* ---- helpers ---------------------------------------------------------------- */

typedef struct {
  int n, m;
  const char *diag; /* regular | alternating */
  const char *bend; /* none | spring */
  double scale;     /* scene.initial_scale */
  const char *pins; /* scene.pins */
  int uniform_mass; /* 1: vertex_mass = 0.25, 0: density-lumped */
} ecase;

static cb_scene *case_scene(const ecase *c) {
  char n[32], m[32], diag[64], bend[64], scale[64], pins[128], mass[64];
  snprintf(n, sizeof n, "mesh.n=%d", c->n);
  snprintf(m, sizeof m, "mesh.m=%d", c->m);
  snprintf(diag, sizeof diag, "mesh.diagonal=%s", c->diag);
  snprintf(bend, sizeof bend, "material.bend=%s", c->bend);
  snprintf(scale, sizeof scale, "scene.initial_scale=%.17g", c->scale);
  snprintf(pins, sizeof pins, "scene.pins=%s", c->pins);
  snprintf(mass, sizeof mass, "material.vertex_mass=%s", c->uniform_mass ? "0.25" : "0");
  const char *sets[] = {n,
                        m,
                        diag,
                        bend,
                        scale,
                        pins,
                        mass,
                        "mesh.size=1 0.8",
                        "material.stretch_k=8000",
                        "material.bend_k=37",
                        "material.density=0.3",
                        "scene.gravity=0.5 -9.8 1.25",
                        NULL};
  return test_scene(sets);
}

static void case_name(const ecase *c, char *buf, size_t n) {
  snprintf(buf, n, "%dx%d %s bend=%s scale=%g pins=%s %s", c->n, c->m, c->diag, c->bend, c->scale, c->pins,
           c->uniform_mass ? "uniform" : "lumped");
}

/* x = x0 (already scaled about the centroid) + jitter in all three axes. */
static double *jittered(const cb_scene *s, double amp, uint64_t seed) {
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double));
  cr_assert(x);
  cb_rng st = cb_rng_raw(seed);
  for (int i = 0; i < n3; i++) x[i] = s->x0[i] + amp * (2.0 * cb_rng_uniform(&st) - 1.0);
  return x;
}

/* The cases the checks loop over: both diagonals, bending on/off, stretched
 * and compressed, with and without pins, lumped and uniform masses. */
static const ecase cases[] = {
    {4, 3, "regular", "none", 1.3, "none", 0},
    {4, 3, "regular", "spring", 1.3, "none", 0},
    {4, 3, "alternating", "spring", 0.7, "none", 0},
    {4, 3, "regular", "spring", 0.7, "top-corners", 1},
    {4, 3, "alternating", "spring", 1.3, "top-edge", 0},
    {4, 3, "alternating", "none", 0.7, "1, 6, 11", 1},
    {3, 4, "regular", "spring", 1.3, "5", 0},
    {3, 4, "alternating", "spring", 0.7, "corners", 0},
    {5, 4, "alternating", "spring", 1.0, "0 7", 0},
};
enum { NCASES = (int)(sizeof cases / sizeof cases[0]) };

static const double FD_H = 1e-6; /* m; edges are ~0.27-0.33 m */
static const double JITTER = 0.03;

/* Energy of one term (no gradient). */
static double term_E(const cb_term *t, const double *x) { return t->type->energy(t, x, NULL); }

/* Gradient of one term into g (zeroed first). */
static void term_grad(const cb_term *t, const double *x, double *g, int n3) {
  memset(g, 0, (size_t)n3 * sizeof(double));
  t->type->energy(t, x, g);
}

/* Dense Hessian of one term over the free DOFs: zero the system's values,
 * let the term add its blocks, copy. A term without a Hessian gives 0. */
static gsl_matrix *term_hessian(cb_scene *s, const cb_term *t, const double *x, cb_projection proj) {
  cb_sparse *A = &s->sys.A;
  memset(A->val, 0, (size_t)A->nnz * sizeof(double));
  if (t->type->hessian) t->type->hessian(t, x, proj, A->val);
  return test_dense(A);
}

static double mat_maxabs(const gsl_matrix *M) {
  double m = 0;
  for (size_t i = 0; i < M->size1; i++)
    for (size_t j = 0; j < M->size2; j++) m = fmax(m, fabs(gsl_matrix_get(M, i, j)));
  return m;
}

/* Largest |(dE/dx)_fd - dE/dx| over all 3nv coordinates, and max |dE/dx|. */
static void fd_gradient(const cb_term *t, const double *x0, int n3, double *err, double *gmax) {
  double *x = malloc((size_t)n3 * sizeof(double)), *g = malloc((size_t)n3 * sizeof(double));
  cr_assert(x && g);
  memcpy(x, x0, (size_t)n3 * sizeof(double));
  term_grad(t, x, g, n3);
  *err = 0;
  *gmax = 0;
  for (int i = 0; i < n3; i++) {
    double xi = x[i];
    x[i] = xi + FD_H;
    double Ep = term_E(t, x);
    x[i] = xi - FD_H;
    double Em = term_E(t, x);
    x[i] = xi;
    double fd = (Ep - Em) / (2 * FD_H); /* central difference */
    *err = fmax(*err, fabs(fd - g[i]));
    *gmax = fmax(*gmax, fabs(g[i]));
  }
  free(x);
  free(g);
}

/* Dense FD Hessian over the free DOFs from a gradient function. */
typedef void (*gradfn)(const void *ctx, const double *x, double *g);

static gsl_matrix *fd_hessian(const cb_scene *s, gradfn gf, const void *ctx, const double *x0) {
  int n3 = 3 * s->mesh.nv, nf = s->model.nfree;
  gsl_matrix *H = gsl_matrix_calloc((size_t)3 * nf, (size_t)3 * nf);
  double *x = malloc((size_t)n3 * sizeof(double));
  double *gp = malloc((size_t)n3 * sizeof(double)), *gm = malloc((size_t)n3 * sizeof(double));
  cr_assert(H && x && gp && gm);
  memcpy(x, x0, (size_t)n3 * sizeof(double));
  for (int v = 0; v < s->mesh.nv; v++) {
    int bv = s->free_index[v];
    if (bv < 0) continue;
    for (int a = 0; a < 3; a++) {
      double xi = x[3 * v + a];
      x[3 * v + a] = xi + FD_H;
      gf(ctx, x, gp);
      x[3 * v + a] = xi - FD_H;
      gf(ctx, x, gm);
      x[3 * v + a] = xi;
      for (int w = 0; w < s->mesh.nv; w++) {
        int bw = s->free_index[w];
        if (bw < 0) continue;
        for (int b = 0; b < 3; b++)
          gsl_matrix_set(H, (size_t)(3 * bw + b), (size_t)(3 * bv + a),
                         (gp[3 * w + b] - gm[3 * w + b]) / (2 * FD_H)); /* d(dE/dx_wb)/dx_va */
      }
    }
  }
  free(x);
  free(gp);
  free(gm);
  return H;
}

typedef struct {
  const cb_term *t;
  int n3;
} term_ctx;

static void term_gradfn(const void *ctx, const double *x, double *g) {
  const term_ctx *c = ctx;
  term_grad(c->t, x, g, c->n3);
}

static void system_gradfn(const void *ctx, const double *x, double *g) {
  cb_system_energy((const cb_system *)ctx, x, g, NULL);
}

static double max_diff(const gsl_matrix *A, const gsl_matrix *B) {
  double m = 0;
  for (size_t i = 0; i < A->size1; i++)
    for (size_t j = 0; j < A->size2; j++) m = fmax(m, fabs(gsl_matrix_get(A, i, j) - gsl_matrix_get(B, i, j)));
  return m;
}

/* Number of pinned vertices that the spec names, by the documented grid
 * convention (vertex (i, j) = j*n + i, row j = m-1 is the top edge). */
static int expected_pins(const ecase *c) {
  if (strcmp(c->pins, "none") == 0) return 0;
  if (strcmp(c->pins, "top-corners") == 0) return 2;
  if (strcmp(c->pins, "corners") == 0) return 4;
  if (strcmp(c->pins, "top-edge") == 0) return c->n;
  int cnt = 0; /* comma/space separated distinct indices */
  for (const char *p = c->pins; *p;) {
    while (*p == ' ' || *p == ',') p++;
    if (!*p) break;
    cnt++;
    while (*p && *p != ' ' && *p != ',') p++;
  }
  return cnt;
}

/* ---- gradient ---------------------------------------------------------------- */

Test(energy, gradient_matches_central_differences_for_every_term) {
  double worst = 0;
  for (int c = 0; c < NCASES; c++) {
    char name[160];
    case_name(&cases[c], name, sizeof name);
    cb_scene *s = case_scene(&cases[c]);
    int expect_terms = 1 + (strcmp(cases[c].bend, "spring") == 0) + 1;
    cr_assert_eq(s->sys.nterms, expect_terms, "%s: %d terms, expected %d", name, s->sys.nterms, expect_terms);
    double *x = jittered(s, JITTER, 1000 + (uint64_t)c);
    for (int k = 0; k < s->sys.nterms; k++) {
      const cb_term *t = s->sys.terms[k];
      double err, gmax;
      fd_gradient(t, x, 3 * s->mesh.nv, &err, &gmax);
      cr_assert(gmax > 0, "%s: term %s has a zero gradient at a generic state", name, t->label);
      double rel = err / gmax;
      worst = fmax(worst, rel);
      cr_expect(rel <= 1e-6, "%s: term %s: |grad_fd - grad|_inf / |grad|_inf = %.3g", name, t->label, rel);
    }
    free(x);
    cb_scene_free(s);
  }
  cr_log_info("energy gradient FD: worst relative error %.3g\n", worst);
}

Test(energy, system_gradient_is_the_sum_of_term_gradients_and_energy_the_sum) {
  for (int c = 0; c < NCASES; c++) {
    cb_scene *s = case_scene(&cases[c]);
    int n3 = 3 * s->mesh.nv;
    double *x = jittered(s, JITTER, 2000 + (uint64_t)c);
    double *g = calloc((size_t)n3, sizeof(double)), *gs = calloc((size_t)n3, sizeof(double));
    double *gt = calloc((size_t)n3, sizeof(double));
    cr_assert(g && gs && gt);
    double per[CB_MAX_TERMS], Esum = 0, scale = 0;
    double E = cb_system_energy(&s->sys, x, g, per);
    for (int k = 0; k < s->sys.nterms; k++) {
      double e = term_E(s->sys.terms[k], x);
      cr_expect(fabs(per[k] - e) <= 1e-14 * fmax(1, fabs(e)), "per-term energy %d", k);
      Esum += e;
      scale += fabs(e);
      term_grad(s->sys.terms[k], x, gt, n3);
      for (int i = 0; i < n3; i++) gs[i] += gt[i];
    }
    cr_expect(fabs(E - Esum) <= 1e-13 * scale, "E = %.17g vs sum %.17g", E, Esum);
    for (int i = 0; i < n3; i++) cr_expect(fabs(g[i] - gs[i]) <= 1e-12 * (1 + fabs(gs[i])), "grad[%d]", i);
    /* elastic energy = everything but gravity */
    double Eel = 0;
    for (int k = 0; k < s->sys.nterms; k++)
      if (strcmp(s->sys.terms[k]->label, "gravity") != 0) Eel += per[k];
    cr_expect(fabs(cb_system_elastic_energy(&s->sys, x) - Eel) <= 1e-13 * fmax(1, Eel));
    free(g);
    free(gs);
    free(gt);
    free(x);
    cb_scene_free(s);
  }
}

/* ---- Hessian ------------------------------------------------------------------ */

Test(energy, term_hessian_matches_differences_of_the_gradient) {
  double worst = 0;
  for (int c = 0; c < NCASES; c++) {
    char name[160];
    case_name(&cases[c], name, sizeof name);
    cb_scene *s = case_scene(&cases[c]);
    cr_assert_eq(s->sys.A.n, 3 * (s->mesh.nv - expected_pins(&cases[c])), "%s: matrix size %d", name, s->sys.A.n);
    double *x = jittered(s, JITTER, 3000 + (uint64_t)c);
    for (int k = 0; k < s->sys.nterms; k++) {
      const cb_term *t = s->sys.terms[k];
      term_ctx ctx = {t, 3 * s->mesh.nv};
      gsl_matrix *Hfd = fd_hessian(s, term_gradfn, &ctx, x);
      gsl_matrix *H = term_hessian(s, t, x, CB_PROJ_NONE);
      double scale = mat_maxabs(H), err = max_diff(H, Hfd);
      if (strcmp(t->label, "gravity") == 0) { /* linear energy: zero Hessian */
        cr_expect(t->type->hessian == NULL || scale == 0, "%s: gravity Hessian not zero", name);
        cr_expect(mat_maxabs(Hfd) <= 1e-6, "%s: gravity FD Hessian %.3g", name, mat_maxabs(Hfd));
      } else {
        cr_assert(scale > 0, "%s: %s Hessian is zero", name, t->label);
        worst = fmax(worst, err / scale);
        cr_expect(err <= 1e-6 * scale, "%s: %s Hessian: max |H - H_fd| = %.3g, max |H| = %.3g", name, t->label, err,
                  scale);
      }
      gsl_matrix_free(H);
      gsl_matrix_free(Hfd);
    }
    free(x);
    cb_scene_free(s);
  }
  cr_log_info("term Hessian FD: worst relative error %.3g\n", worst);
}

Test(energy, assembled_hessian_matches_differences_of_the_system_gradient) {
  double worst = 0;
  for (int c = 0; c < NCASES; c++) {
    char name[160];
    case_name(&cases[c], name, sizeof name);
    cb_scene *s = case_scene(&cases[c]);
    double *x = jittered(s, JITTER, 4000 + (uint64_t)c);
    gsl_matrix *Hfd = fd_hessian(s, system_gradfn, &s->sys, x);
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
    gsl_matrix *H = test_dense(&s->sys.A);
    double scale = mat_maxabs(H), err = max_diff(H, Hfd);
    worst = fmax(worst, err / scale);
    cr_expect(err <= 1e-6 * scale, "%s: max |H - H_fd| = %.3g, max |H| = %.3g", name, err, scale);
    gsl_matrix_free(H);
    gsl_matrix_free(Hfd);
    free(x);
    cb_scene_free(s);
  }
  cr_log_info("assembled Hessian FD: worst relative error %.3g\n", worst);
}

Test(energy, assembled_matrix_is_symmetric) {
  for (int c = 0; c < NCASES; c++) {
    char name[160];
    case_name(&cases[c], name, sizeof name);
    cb_scene *s = case_scene(&cases[c]);
    double *x = jittered(s, JITTER, 5000 + (uint64_t)c);
    for (int d = 0; d < CB_DEF_COUNT; d++) {
      cb_system_assemble(&s->sys, x, 900.0, (cb_definiteness)d, 0.5);
      gsl_matrix *A = test_dense(&s->sys.A);
      double asym = 0;
      for (size_t i = 0; i < A->size1; i++)
        for (size_t j = 0; j < i; j++) asym = fmax(asym, fabs(gsl_matrix_get(A, i, j) - gsl_matrix_get(A, j, i)));
      cr_expect(asym <= 1e-14 * mat_maxabs(A), "%s def=%s: max |A - A^T| = %.3g", name, cb_definiteness_names[d], asym);
      gsl_matrix_free(A);
    }
    free(x);
    cb_scene_free(s);
  }
}

/* ---- mass_scale and shift ------------------------------------------------------- */


Test(energy, assemble_adds_mass_scale_times_M_plus_shift_on_the_diagonal) {
  for (int c = 0; c < NCASES; c++) {
    char name[160];
    case_name(&cases[c], name, sizeof name);
    cb_scene *s = case_scene(&cases[c]);
    double *x = jittered(s, JITTER, 6000 + (uint64_t)c);
    double *mass = malloc((size_t)s->mesh.nv * sizeof(double));
    cr_assert(mass);
    if (cases[c].uniform_mass)
      for (int i = 0; i < s->mesh.nv; i++) mass[i] = 0.25;
    else test_lumped_masses(&s->mesh, 0.3, mass);
    /* the rest area of the 1 x 0.8 grid is 0.8 m^2, so the masses add to density * 0.8 */
    if (!cases[c].uniform_mass) {
      double msum = 0;
      for (int i = 0; i < s->mesh.nv; i++) msum += mass[i];
      cr_expect(fabs(msum - 0.3 * 0.8) <= 1e-14, "%s: total mass %.17g", name, msum);
    }
    for (int d = 0; d < CB_DEF_COUNT; d++) {
      cb_system_assemble(&s->sys, x, 0.0, (cb_definiteness)d, 0.0);
      gsl_matrix *H = test_dense(&s->sys.A);
      const double ms = 7.5e3, mu = 0.125;
      cb_system_assemble(&s->sys, x, ms, (cb_definiteness)d, mu);
      gsl_matrix *A = test_dense(&s->sys.A);
      double scale = fmax(mat_maxabs(A), 1.0);
      for (int v = 0; v < s->mesh.nv; v++) {
        int bv = s->free_index[v];
        if (bv < 0) continue;
        for (int a = 0; a < 3; a++) {
          size_t r = (size_t)(3 * bv + a);
          double want = gsl_matrix_get(H, r, r) + ms * mass[v] + mu; /* A_rr = H_rr + s m_v + mu */
          cr_expect(fabs(gsl_matrix_get(A, r, r) - want) <= 1e-13 * scale, "%s: A(%zu,%zu) = %.17g, want %.17g", name,
                    r, r, gsl_matrix_get(A, r, r), want);
        }
      }
      for (size_t i = 0; i < A->size1; i++)
        for (size_t j = 0; j < A->size2; j++)
          if (i != j)
            cr_expect(gsl_matrix_get(A, i, j) == gsl_matrix_get(H, i, j), "%s: off-diagonal (%zu,%zu) changed", name, i,
                      j);
      gsl_matrix_free(A);
      gsl_matrix_free(H);
    }
    free(mass);
    free(x);
    cb_scene_free(s);
  }
}

Test(energy, gravity_gradient_is_minus_mass_times_g) {
  const ecase c = {4, 3, "alternating", "none", 1.0, "none", 0};
  cb_scene *s = case_scene(&c);
  int n3 = 3 * s->mesh.nv;
  double *mass = malloc((size_t)s->mesh.nv * sizeof(double)), *g = malloc((size_t)n3 * sizeof(double));
  cr_assert(mass && g);
  test_lumped_masses(&s->mesh, 0.3, mass);
  const double grav[3] = {0.5, -9.8, 1.25};
  const cb_term *t = NULL;
  for (int k = 0; k < s->sys.nterms; k++)
    if (strcmp(s->sys.terms[k]->label, "gravity") == 0) t = s->sys.terms[k];
  cr_assert(t, "no gravity term");
  double *x = jittered(s, 0.2, 7);
  term_grad(t, x, g, n3);
  double E = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    for (int a = 0; a < 3; a++) {
      cr_expect(fabs(g[3 * i + a] + mass[i] * grav[a]) <= 1e-15, "dE/dx[%d] = %.17g", 3 * i + a, g[3 * i + a]);
      E -= mass[i] * grav[a] * x[3 * i + a];
    }
  cr_expect(fabs(term_E(t, x) - E) <= 1e-14 * fmax(1, fabs(E)), "E_gravity %.17g vs %.17g", term_E(t, x), E);
  free(x);
  free(mass);
  free(g);
  cb_scene_free(s);
}

Test(energy, zero_gravity_builds_no_gravity_term) {
  const char *sets[] = {"mesh.n=3", "scene.gravity=0 0 0", NULL};
  cb_scene *s = test_scene(sets);
  for (int k = 0; k < s->sys.nterms; k++) cr_expect(strcmp(s->sys.terms[k]->label, "gravity") != 0);
  cr_expect_eq(s->sys.nterms, 1);
  cb_scene_free(s);
}

/* ---- definiteness: a single spring --------------------------------------------------- */

/* A model of two vertices joined by one spring of stiffness k: rest positions
 * r0, r1; pinned[v] = 1 eliminates vertex v. */
typedef struct {
  cb_mesh mesh;
  double rest[6], mass[2];
  int free_index[2];
  cb_model model;
  cb_system sys;
} one_spring;

static void one_spring_init(one_spring *o, const double r[6], double k, int pin0) {
  memset(o, 0, sizeof *o);
  memcpy(o->rest, r, sizeof o->rest);
  o->mesh.nv = 2;
  o->mesh.nt = 0;
  o->mesh.x = o->rest;
  o->mass[0] = o->mass[1] = 2.0;
  o->free_index[0] = pin0 ? -1 : 0;
  o->free_index[1] = pin0 ? 0 : 1;
  o->model = (cb_model){&o->mesh, NULL, o->mass, o->free_index, pin0 ? 1 : 2};
  const int ends[2] = {0, 1};
  cb_term *t = NULL;
  cr_assert_eq(cb_spring_term_alloc(&o->model, "stretch", 1, ends, k, &t), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_system_init(&o->sys, &o->model, &t, 1), CB_OK, "%s", cb_error_message());
}

static void sym_eigenvalues(const gsl_matrix *A, double *ev) { /* ascending */
  size_t n = A->size1;
  gsl_matrix *W = gsl_matrix_alloc(n, n);
  gsl_vector *e = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc(n);
  gsl_matrix_memcpy(W, A);
  cr_assert_eq(gsl_eigen_symm(W, e, ws), 0);
  for (size_t i = 0; i < n; i++) ev[i] = gsl_vector_get(e, i);
  for (size_t i = 1; i < n; i++) /* insertion sort */
    for (size_t j = i; j > 0 && ev[j - 1] > ev[j]; j--) {
      double tmp = ev[j];
      ev[j] = ev[j - 1];
      ev[j - 1] = tmp;
    }
  gsl_eigen_symm_free(ws);
  gsl_vector_free(e);
  gsl_matrix_free(W);
}

static void sort3(double *v) {
  for (int i = 1; i < 3; i++)
    for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
      double t = v[j];
      v[j] = v[j - 1];
      v[j - 1] = t;
    }
}

/* Spring from (0,0,0) to (0.3, 0.4, 0) at rest (L = 0.5), vertex 1 moved to p. */
static void spring_block_eigen(double k, const double p[3], cb_definiteness def, int pin0, double *ev, size_t *n) {
  const double r[6] = {0, 0, 0, 0.3, 0.4, 0};
  one_spring o;
  one_spring_init(&o, r, k, pin0);
  double x[6] = {0, 0, 0, p[0], p[1], p[2]};
  cb_system_assemble(&o.sys, x, 0.0, def, 0.0);
  gsl_matrix *A = test_dense(&o.sys.A);
  *n = A->size1;
  sym_eigenvalues(A, ev);
  gsl_matrix_free(A);
  cb_system_free(&o.sys);
}

Test(energy, single_spring_energy_and_gradient_follow_the_lecture) {
  const double r[6] = {0, 0, 0, 0.3, 0.4, 0}, k = 250.0;
  one_spring o;
  one_spring_init(&o, r, k, 0);
  const double x[6] = {0.1, -0.2, 0.05, 0.7, 0.1, -0.3};
  double d[3] = {x[0] - x[3], x[1] - x[4], x[2] - x[5]};
  double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), L = 0.5;
  double g[6];
  double E = cb_system_energy(&o.sys, x, g, NULL);
  cr_expect(fabs(E - 0.5 * k * (l - L) * (l - L)) <= 1e-14 * E, "E = %.17g", E); /* 1/2 k (l - L)^2 */
  for (int a = 0; a < 3; a++) {
    double gi = k * (l - L) * d[a] / l; /* dE/dx_i = k (l - L) (x_i - x_j)/l */
    cr_expect(fabs(g[a] - gi) <= 1e-13 * k, "dE/dx_0[%d]", a);
    cr_expect(fabs(g[3 + a] + gi) <= 1e-13 * k, "dE/dx_1[%d]", a);
  }
  cb_system_free(&o.sys);
}

Test(energy, compressed_spring_exact_hessian_has_negative_transverse_eigenvalues) {
  const double k = 250.0, L = 0.5;
  const double p[3] = {0.12, 0.2, 0.1}; /* l = sqrt(0.0144 + 0.04 + 0.01) < L */
  double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  cr_assert(l < L);
  double tr = k * (1 - L / l), ev[6];
  cr_assert(tr < 0);
  size_t n;
  /* vertex 0 pinned: the matrix is the 3x3 block H_e itself */
  spring_block_eigen(k, p, CB_DEF_NONE, 1, ev, &n);
  cr_assert_eq(n, 3);
  double want[3] = {k, tr, tr};
  sort3(want);
  for (int i = 0; i < 3; i++)
    cr_expect(fabs(ev[i] - want[i]) <= 1e-12 * k, "none: eigenvalue %d = %.17g, want %.17g", i, ev[i], want[i]);
  spring_block_eigen(k, p, CB_DEF_DROP, 1, ev, &n);
  const double want_drop[3] = {0, 0, k};
  for (int i = 0; i < 3; i++)
    cr_expect(fabs(ev[i] - want_drop[i]) <= 1e-12 * k, "drop: eigenvalue %d = %.17g, want %.17g", i, ev[i],
              want_drop[i]);
  /* both free: [H -H; -H H] has eigenvalues 2 * eig(H_e) and three zeros */
  spring_block_eigen(k, p, CB_DEF_NONE, 0, ev, &n);
  cr_assert_eq(n, 6);
  double want6[6] = {2 * tr, 2 * tr, 0, 0, 0, 2 * k};
  for (int i = 0; i < 6; i++)
    cr_expect(fabs(ev[i] - want6[i]) <= 1e-12 * k, "none 6x6: eigenvalue %d = %.17g, want %.17g", i, ev[i], want6[i]);
  spring_block_eigen(k, p, CB_DEF_DROP, 0, ev, &n);
  const double want6d[6] = {0, 0, 0, 0, 0, 2 * k};
  for (int i = 0; i < 6; i++)
    cr_expect(fabs(ev[i] - want6d[i]) <= 1e-12 * k, "drop 6x6: eigenvalue %d = %.17g, want %.17g", i, ev[i], want6d[i]);
}

Test(energy, stretched_spring_drop_equals_none) {
  const double k = 250.0, L = 0.5;
  const double p[3] = {0.5, 0.45, -0.2};
  double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  cr_assert(l > L);
  double tr = k * (1 - L / l), want[3] = {k, tr, tr}, ev[6], evd[6];
  sort3(want);
  size_t n;
  spring_block_eigen(k, p, CB_DEF_NONE, 1, ev, &n);
  spring_block_eigen(k, p, CB_DEF_DROP, 1, evd, &n);
  for (int i = 0; i < 3; i++) {
    cr_expect(fabs(ev[i] - want[i]) <= 1e-12 * k, "eigenvalue %d = %.17g, want %.17g", i, ev[i], want[i]);
    cr_expect(ev[i] == evd[i], "drop changed a stretched spring: %.17g vs %.17g", evd[i], ev[i]);
  }
}

Test(energy, definiteness_transverse_clamps_at_zero) {
  cr_expect_eq(cb_definiteness_transverse(CB_DEF_NONE, -3.5), -3.5);
  cr_expect_eq(cb_definiteness_transverse(CB_DEF_NONE, 2.25), 2.25);
  cr_expect_eq(cb_definiteness_transverse(CB_DEF_DROP, -3.5), 0.0);
  cr_expect_eq(cb_definiteness_transverse(CB_DEF_DROP, 2.25), 2.25);
  cr_expect_eq(cb_definiteness_transverse(CB_DEF_DROP, 0.0), 0.0);
  cb_definiteness d;
  cr_expect_eq(cb_definiteness_from_name("none", &d), CB_OK);
  cr_expect_eq(d, CB_DEF_NONE);
  cr_expect_eq(cb_definiteness_from_name("drop", &d), CB_OK);
  cr_expect_eq(d, CB_DEF_DROP);
  cr_expect_lt(cb_definiteness_from_name("clamp-ish", &d), 0);
  int n = 0;
  while (cb_definiteness_names[n]) n++;
  cr_expect_eq(n, CB_DEF_COUNT);
}

/* ---- definiteness on a grid --------------------------------------------------------- */

/* H_none - H_drop must be sum over compressed springs of k(1 - L/l) P_e
 * (P_e = I - uu^T) in the [+ - ; - +] block pattern, computed here from the
 * rest mesh: edges of the triangles and, for bending, opposite vertices. */
static void add_block(gsl_matrix *D, const int *fi, int i, int j, const double P[9], double c) {
  int bi = fi[i], bj = fi[j];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      double v = c * P[3 * a + b];
      if (bi >= 0) *gsl_matrix_ptr(D, (size_t)(3 * bi + a), (size_t)(3 * bi + b)) += v;
      if (bj >= 0) *gsl_matrix_ptr(D, (size_t)(3 * bj + a), (size_t)(3 * bj + b)) += v;
      if (bi >= 0 && bj >= 0) {
        *gsl_matrix_ptr(D, (size_t)(3 * bi + a), (size_t)(3 * bj + b)) -= v;
        *gsl_matrix_ptr(D, (size_t)(3 * bj + a), (size_t)(3 * bi + b)) -= v;
      }
    }
}

/* Vertex pairs (i < j) of one spring family: triangle edges, or the opposite
 * vertices of triangles sharing an edge. Returns the count. */
static int spring_pairs(const cb_mesh *m, int bending, int *pairs, int cap) {
  int np = 0;
  if (!bending) {
    char *seen = calloc((size_t)m->nv * m->nv, 1);
    cr_assert(seen);
    for (int t = 0; t < m->nt; t++)
      for (int e = 0; e < 3; e++) {
        int a = m->tri[3 * t + e], b = m->tri[3 * t + (e + 1) % 3];
        int i = a < b ? a : b, j = a < b ? b : a;
        if (seen[(size_t)i * m->nv + j]) continue;
        seen[(size_t)i * m->nv + j] = 1;
        cr_assert(np < cap);
        pairs[2 * np] = i;
        pairs[2 * np + 1] = j;
        np++;
      }
    free(seen);
    return np;
  }
  for (int t = 0; t < m->nt; t++)
    for (int u = t + 1; u < m->nt; u++) {
      const int *A = m->tri + 3 * t, *B = m->tri + 3 * u;
      int shared = 0, oa = -1, ob = -1;
      for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++) shared += A[p] == B[q];
      if (shared != 2) continue;
      for (int p = 0; p < 3; p++) {
        if (A[p] != B[0] && A[p] != B[1] && A[p] != B[2]) oa = A[p];
        if (B[p] != A[0] && B[p] != A[1] && B[p] != A[2]) ob = B[p];
      }
      cr_assert(np < cap);
      pairs[2 * np] = oa < ob ? oa : ob;
      pairs[2 * np + 1] = oa < ob ? ob : oa;
      np++;
    }
  return np;
}

static double dist(const double *x, int i, int j) {
  double d0 = x[3 * i] - x[3 * j], d1 = x[3 * i + 1] - x[3 * j + 1], d2 = x[3 * i + 2] - x[3 * j + 2];
  return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

Test(energy, drop_removes_exactly_the_compressed_transverse_terms) {
  const ecase list[] = {
      {4, 3, "regular", "spring", 0.7, "none", 0},
      {4, 3, "alternating", "spring", 0.95, "top-corners", 0}, /* mixed: some compressed, some stretched */
      {5, 4, "regular", "spring", 1.0, "2 13", 1},
  };
  for (size_t c = 0; c < sizeof list / sizeof list[0]; c++) {
    char name[160];
    case_name(&list[c], name, sizeof name);
    cb_scene *s = case_scene(&list[c]);
    double *x = jittered(s, 0.06, 8000 + c);
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
    gsl_matrix *Hn = test_dense(&s->sys.A);
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_DROP, 0.0);
    gsl_matrix *Hd = test_dense(&s->sys.A);
    gsl_matrix *D = gsl_matrix_calloc(Hn->size1, Hn->size2);
    int cap = 4 * s->mesh.nt + 16, *pairs = malloc((size_t)2 * cap * sizeof(int));
    cr_assert(pairs);
    int ncomp = 0, nstr = 0;
    for (int fam = 0; fam < 2; fam++) {
      double k = fam ? 37.0 : 8000.0;
      int np = spring_pairs(&s->mesh, fam, pairs, cap);
      for (int e = 0; e < np; e++) {
        int i = pairs[2 * e], j = pairs[2 * e + 1];
        double L = dist(s->mesh.x, i, j), l = dist(x, i, j);
        if (l >= L) {
          nstr++;
          continue;
        }
        ncomp++;
        double u[3] = {(x[3 * i] - x[3 * j]) / l, (x[3 * i + 1] - x[3 * j + 1]) / l, (x[3 * i + 2] - x[3 * j + 2]) / l};
        double P[9];
        for (int a = 0; a < 3; a++)
          for (int b = 0; b < 3; b++) P[3 * a + b] = (a == b) - u[a] * u[b];
        add_block(D, s->free_index, i, j, P, k * (1 - L / l));
      }
    }
    cr_assert(ncomp > 0, "%s: no compressed spring", name);
    if (list[c].scale != 0.7) cr_assert(nstr > 0, "%s: no stretched spring", name);
    double err = 0;
    for (size_t i = 0; i < Hn->size1; i++)
      for (size_t j = 0; j < Hn->size2; j++)
        err = fmax(err, fabs(gsl_matrix_get(Hn, i, j) - gsl_matrix_get(Hd, i, j) - gsl_matrix_get(D, i, j)));
    cr_expect(err <= 1e-11 * mat_maxabs(Hn), "%s: |H_none - H_drop - sum_compressed| = %.3g", name, err);
    free(pairs);
    gsl_matrix_free(D);
    gsl_matrix_free(Hd);
    gsl_matrix_free(Hn);
    free(x);
    cb_scene_free(s);
  }
}

Test(energy, drop_makes_a_compressed_grid_hessian_psd_and_none_does_not) {
  const ecase c = {4, 4, "alternating", "spring", 0.7, "none", 0};
  cb_scene *s = case_scene(&c);
  double *x = jittered(s, 0.03, 9);
  size_t n = (size_t)s->sys.A.n;
  double *ev = malloc(n * sizeof(double));
  cr_assert(ev);
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
  gsl_matrix *H = test_dense(&s->sys.A);
  sym_eigenvalues(H, ev);
  double scale = fmax(fabs(ev[0]), fabs(ev[n - 1]));
  cr_expect(ev[0] < -0.05 * scale, "exact Hessian of a compressed grid: lambda_min = %.6g (scale %.6g)", ev[0], scale);
  gsl_matrix_free(H);
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_DROP, 0.0);
  H = test_dense(&s->sys.A);
  sym_eigenvalues(H, ev);
  cr_expect(ev[0] >= -1e-12 * ev[n - 1], "drop: lambda_min = %.6g", ev[0]);
  /* free cloth: the 6 rigid motions are in the kernel of H */
  for (int i = 0; i < 6; i++) cr_expect(fabs(ev[i]) <= 1e-10 * ev[n - 1], "drop: eigenvalue %d = %.3g", i, ev[i]);
  gsl_matrix_free(H);
  free(ev);
  free(x);
  cb_scene_free(s);
}

Test(energy, all_springs_stretched_drop_equals_none) {
  const ecase c = {4, 3, "alternating", "spring", 1.3, "top-corners", 0};
  cb_scene *s = case_scene(&c);
  double *x = jittered(s, 0.01, 10);
  int cap = 4 * s->mesh.nt + 16, *pairs = malloc((size_t)2 * cap * sizeof(int));
  cr_assert(pairs);
  for (int fam = 0; fam < 2; fam++) {
    int np = spring_pairs(&s->mesh, fam, pairs, cap);
    for (int e = 0; e < np; e++)
      cr_assert(dist(x, pairs[2 * e], pairs[2 * e + 1]) > dist(s->mesh.x, pairs[2 * e], pairs[2 * e + 1]));
  }
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
  gsl_matrix *Hn = test_dense(&s->sys.A);
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_DROP, 0.0);
  gsl_matrix *Hd = test_dense(&s->sys.A);
  cr_expect(max_diff(Hn, Hd) == 0.0, "drop changed a fully stretched Hessian by %.3g", max_diff(Hn, Hd));
  gsl_matrix_free(Hn);
  gsl_matrix_free(Hd);
  free(pairs);
  free(x);
  cb_scene_free(s);
}

Test(energy, spring_counts_match_the_mesh) {
  /* n x m grid: (n-1)m + n(m-1) + (n-1)(m-1) edges; interior edges = edges - boundary edges */
  const ecase c = {5, 4, "alternating", "spring", 1.0, "none", 0};
  cb_scene *s = case_scene(&c);
  int cap = 4 * s->mesh.nt + 16, *pairs = malloc((size_t)2 * cap * sizeof(int));
  cr_assert(pairs);
  int ne = spring_pairs(&s->mesh, 0, pairs, cap), nb = spring_pairs(&s->mesh, 1, pairs, cap);
  cr_expect_eq(ne, 4 * 4 + 5 * 3 + 4 * 3);
  cr_expect_eq(nb, ne - 2 * (4 + 3));
  /* the library's terms have the same number of springs: E at a uniform scaling
   * s of the rest shape is 1/2 k (s-1)^2 sum L^2 per family */
  double *x = malloc((size_t)3 * s->mesh.nv * sizeof(double));
  cr_assert(x);
  for (int i = 0; i < 3 * s->mesh.nv; i++) x[i] = 1.1 * s->mesh.x[i];
  for (int fam = 0; fam < 2; fam++) {
    int np = spring_pairs(&s->mesh, fam, pairs, cap);
    double k = fam ? 37.0 : 8000.0, want = 0;
    for (int e = 0; e < np; e++) {
      double L = dist(s->mesh.x, pairs[2 * e], pairs[2 * e + 1]);
      want += 0.5 * k * 0.01 * L * L;
    }
    const char *label = fam ? "bend" : "stretch";
    const cb_term *t = NULL;
    for (int k2 = 0; k2 < s->sys.nterms; k2++)
      if (strcmp(s->sys.terms[k2]->label, label) == 0) t = s->sys.terms[k2];
    cr_assert(t, "no %s term", label);
    double E = term_E(t, x);
    cr_expect(fabs(E - want) <= 1e-12 * want, "%s: E = %.17g, want %.17g", label, E, want);
  }
  free(x);
  free(pairs);
  cb_scene_free(s);
}

/* The same single-spring eigenvalues through a scene: a 2-vertex chain
 * (mesh.type = chain) pinned at one end. */
Test(energy, chain_scene_single_spring_block) {
  const char *sets[] = {"mesh.type=chain",
                        "mesh.n=2",
                        "mesh.size=0.5",
                        "mesh.plane=xy",
                        "material.vertex_mass=1",
                        "material.stretch_k=300",
                        "scene.pins=0",
                        "scene.gravity=0 0 0",
                        NULL};
  cb_scene *s = test_scene(sets);
  cr_assert_eq(s->sys.A.n, 3);
  cr_assert_eq(s->sys.nterms, 1);
  const double k = 300, L = 0.5;
  for (int c = 0; c < 2; c++) {
    /* vertex 0 stays at (-0.25, 0, 0); vertex 1 goes to a compressed / stretched place */
    double x[6] = {-0.25, 0, 0, -0.25 + (c ? 0.4 : 0.1), c ? 0.35 : 0.15, c ? -0.2 : 0.1};
    double l = dist(x, 0, 1), tr = k * (1 - L / l);
    cr_assert(c ? l > L : l < L);
    double want[3] = {k, tr, tr}, ev[3];
    sort3(want);
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0);
    gsl_matrix *H = test_dense(&s->sys.A);
    sym_eigenvalues(H, ev);
    for (int i = 0; i < 3; i++)
      cr_expect(fabs(ev[i] - want[i]) <= 1e-12 * k, "%s none: eigenvalue %d = %.17g, want %.17g",
                c ? "stretched" : "compressed", i, ev[i], want[i]);
    gsl_matrix_free(H);
    cb_system_assemble(&s->sys, x, 0.0, CB_DEF_DROP, 0.0);
    H = test_dense(&s->sys.A);
    sym_eigenvalues(H, ev);
    double wd[3] = {k, fmax(tr, 0), fmax(tr, 0)};
    sort3(wd);
    for (int i = 0; i < 3; i++)
      cr_expect(fabs(ev[i] - wd[i]) <= 1e-12 * k, "%s drop: eigenvalue %d = %.17g, want %.17g",
                c ? "stretched" : "compressed", i, ev[i], wd[i]);
    gsl_matrix_free(H);
    double E = cb_system_energy(&s->sys, x, NULL, NULL);
    cr_expect(fabs(E - 0.5 * k * (l - L) * (l - L)) <= 1e-13 * fmax(E, 1e-300), "E = %.17g", E);
  }
  cb_scene_free(s);
}
