/* Conformance of every registered energy term, in the manner of GSL's
 * multiroots/test.c: the loop runs over cb_term_types[] (the registry), not
 * over a list kept here, and builds each type's examples (its `example`
 * hook) on small meshes and states. A new term is checked by registering it.
 *
 * For every (type, example, mesh, state):
 *   - the gradient matches central differences of the energy (all 3nv
 *     coordinates, pinned vertices included);
 *   - under every integrator.definiteness policy whose projection is `none`
 *     (none, shift, choi-ko) the assembled Hessian matches central
 *     differences of the gradient over the free DOFs;
 *   - under `drop` (clamp) and `mirror` (abs) it is positive semidefinite
 *     (smallest eigenvalue by GSL); on the one-element meshes (a single
 *     spring; two triangles, one neighbouring pair) the term's matrix is a
 *     single element's, so there this is the element check;
 *   - the matrix is symmetric under every policy;
 *   - a type without a Hessian gives an exactly zero matrix and a gradient
 *     that does not change with x; a type flagged CB_TERM_CONSTANT_HESSIAN
 *     gives the same matrix at every state; a type flagged
 *     CB_TERM_MODEL_HESSIAN (a PSD model such as the frozen-rotation FEM
 *     matrix) is checked for PSD instead of against the FD Hessian.
 * Then: the dihedral's Gauss-Newton matrix (type dihedral) against its exact
 * Hessian (type dihedral_exact) and finite differences.
 * Then: the system's constant-Hessian path on a term defined here (a
 * zero-length spring to fixed anchors, E = k/2 |x - a|^2, H = k I), whose
 * Hessian callback must run once; and the stencil helper on 3-vertex
 * elements against a dense assembly done here. */
#include <criterion/criterion.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"
#include "support.h"

/* ---- small models -------------------------------------------------------------- */

typedef struct {
  cb_mesh mesh;
  cb_topology topo;
  double *mass;
  int *free_index;
  cb_model model;
  const char *name;
} tmodel;

enum { NMESHES = 5 };

/* 0: one spring (2-vertex chain); 1: two triangles (5 edges, 1 pair);
 * 2: 3x3 alternating grid with a non-planar, jittered rest shape;
 * 3: 4x3 grid with vertices 0 and 5 pinned; 4: 3x4 grid with a whole row
 * pinned (elements between two pinned vertices). Random masses. */
static void model_init(tmodel *t, int kind, uint64_t seed0) {
  cb_rng seed = cb_rng_raw(seed0);
  memset(t, 0, sizeof *t);
  static const char *const names[NMESHES] = {"one spring", "two triangles", "3x3 jittered", "4x3 pinned 0,5",
                                             "3x4 pinned row"};
  t->name = names[kind];
  if (kind == 0) {
    cr_assert_eq(cb_mesh_chain(2, 0.6, CB_PLANE_XY, &t->mesh), CB_OK);
  } else {
    cb_grid_params g = cb_grid_params_default();
    static const int n[NMESHES] = {0, 2, 3, 4, 3}, m[NMESHES] = {0, 2, 3, 3, 4};
    g.n = n[kind];
    g.m = m[kind];
    g.size[0] = 1.0;
    g.size[1] = 0.8;
    g.diagonal = kind == 2 ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
    cr_assert_eq(cb_mesh_grid(&g, &t->mesh), CB_OK);
  }
  if (kind == 2)
    for (int i = 0; i < 3 * t->mesh.nv; i++) t->mesh.x[i] += 0.05 * (2 * cb_rng_uniform(&seed) - 1);
  cr_assert_eq(cb_topology_build(&t->mesh, &t->topo), CB_OK);
  int nv = t->mesh.nv, nfree = 0;
  t->mass = malloc((size_t)nv * sizeof(double));
  t->free_index = malloc((size_t)nv * sizeof(int));
  cr_assert(t->mass && t->free_index);
  for (int i = 0; i < nv; i++) {
    t->mass[i] = 0.5 + cb_rng_uniform(&seed);
    int pinned = (kind == 3 && (i == 0 || i == 5)) || (kind == 4 && i >= 9);
    t->free_index[i] = pinned ? -1 : nfree++;
  }
  t->model = (cb_model){&t->mesh, &t->topo, t->mass, t->free_index, nfree};
}

static void model_free(tmodel *t) {
  cb_mesh_free(&t->mesh);
  cb_topology_free(&t->topo);
  free(t->mass);
  free(t->free_index);
}

enum { NSTATES = 3 };
static const char *const state_names[NSTATES] = {"stretched", "compressed", "random"};

/* x = c + s (X - c) + jitter: s = 1.3 (stretched), 0.7 (compressed), or the
 * rest shape with large 3D jitter (random). */
static void state(const tmodel *t, int kind, uint64_t seed0, double *x) {
  cb_rng seed = cb_rng_raw(seed0);
  int nv = t->mesh.nv;
  double c[3] = {0, 0, 0};
  for (int i = 0; i < nv; i++)
    for (int a = 0; a < 3; a++) c[a] += t->mesh.x[3 * i + a] / nv;
  double s = kind == 0 ? 1.3 : kind == 1 ? 0.7 : 1.0, amp = kind == 2 ? 0.12 : 0.02;
  for (int i = 0; i < 3 * nv; i++)
    x[i] = c[i % 3] + s * (t->mesh.x[i] - c[i % 3]) + amp * (2 * cb_rng_uniform(&seed) - 1);
}

/* ---- the checks ------------------------------------------------------------------- */

/* A term flagged CB_TERM_CONSTANT_HESSIAN: the first H is kept in *H0, every later one must equal it. */
static void expect_constant_hessian(const gsl_matrix *H, gsl_matrix **H0, const char *where) {
  if (!*H0) {
    *H0 = gsl_matrix_alloc(H->size1, H->size2);
    gsl_matrix_memcpy(*H0, H);
    return;
  }
  for (size_t i = 0; i < H->size1; i++)
    for (size_t j = 0; j < H->size2; j++)
      cr_expect(gsl_matrix_get(H, i, j) == gsl_matrix_get(*H0, i, j), "%s: constant Hessian changed", where);
}

static const double FD_H = 1e-6; /* m; rest lengths are 0.27-0.6 m */

static double mat_maxabs(const gsl_matrix *M) {
  double m = 0;
  for (size_t i = 0; i < M->size1; i++)
    for (size_t j = 0; j < M->size2; j++) m = fmax(m, fabs(gsl_matrix_get(M, i, j)));
  return m;
}

static double min_eigenvalue(const gsl_matrix *H, double *maxabs) {
  size_t n = H->size1;
  gsl_matrix *A = gsl_matrix_alloc(n, n);
  gsl_vector *ev = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace *ws = gsl_eigen_symm_alloc(n);
  gsl_matrix_memcpy(A, H);
  cr_assert_eq(gsl_eigen_symm(A, ev, ws), 0);
  double lo = INFINITY;
  *maxabs = 0;
  for (size_t k = 0; k < n; k++) {
    lo = fmin(lo, gsl_vector_get(ev, k));
    *maxabs = fmax(*maxabs, fabs(gsl_vector_get(ev, k)));
  }
  gsl_matrix_free(A);
  gsl_vector_free(ev);
  gsl_eigen_symm_free(ws);
  return lo;
}

/* Dense FD Hessian over the free DOFs: central differences of the gradient. */
static gsl_matrix *fd_hessian(const cb_system *s, const tmodel *t, const double *x0) {
  int n3 = 3 * t->mesh.nv, nf = t->model.nfree;
  gsl_matrix *H = gsl_matrix_calloc((size_t)3 * nf, (size_t)3 * nf);
  double *x = malloc((size_t)n3 * sizeof(double)), *gp = malloc((size_t)n3 * sizeof(double)),
         *gm = malloc((size_t)n3 * sizeof(double));
  cr_assert(H && x && gp && gm);
  memcpy(x, x0, (size_t)n3 * sizeof(double));
  for (int v = 0; v < t->mesh.nv; v++) {
    int bv = t->free_index[v];
    if (bv < 0) continue;
    for (int a = 0; a < 3; a++) {
      double xi = x[3 * v + a];
      x[3 * v + a] = xi + FD_H;
      cb_system_energy(s, x, gp, NULL);
      x[3 * v + a] = xi - FD_H;
      cb_system_energy(s, x, gm, NULL);
      x[3 * v + a] = xi;
      for (int w = 0; w < t->mesh.nv; w++) {
        int bw = t->free_index[w];
        if (bw < 0) continue;
        for (int b = 0; b < 3; b++) /* d(dE/dx_wb)/dx_va */
          gsl_matrix_set(H, (size_t)(3 * bw + b), (size_t)(3 * bv + a), (gp[3 * w + b] - gm[3 * w + b]) / (2 * FD_H));
      }
    }
  }
  free(x);
  free(gp);
  free(gm);
  return H;
}

/* Largest |dE/dx - central difference of E| over all 3nv coordinates. */
static double fd_gradient_error(const cb_system *s, const tmodel *t, const double *x0, double *gmax) {
  int n3 = 3 * t->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *g = malloc((size_t)n3 * sizeof(double));
  cr_assert(x && g);
  memcpy(x, x0, (size_t)n3 * sizeof(double));
  cb_system_energy(s, x, g, NULL);
  double err = 0;
  *gmax = 0;
  for (int i = 0; i < n3; i++) {
    double xi = x[i];
    x[i] = xi + FD_H;
    double Ep = cb_system_energy(s, x, NULL, NULL);
    x[i] = xi - FD_H;
    double Em = cb_system_energy(s, x, NULL, NULL);
    x[i] = xi;
    err = fmax(err, fabs((Ep - Em) / (2 * FD_H) - g[i]));
    *gmax = fmax(*gmax, fabs(g[i]));
  }
  free(x);
  free(g);
  return err;
}

/* All checks of one term type on every mesh and state; returns the number of
 * (example, mesh, state) cases checked. */
/* A type with per-element access (cb_term_type.element): its elements'
 * energies, scattered gradients and scattered Hessians (each projection)
 * equal the term's own energy, gradient and assembled Hessian at x. */
static void check_elements(const cb_term *term, cb_system *sys, const tmodel *t, const double *x, const char *where) {
  const cb_term_type *type = term->type;
  cr_expect((type->element != NULL) == (type->stencil != NULL), "%s: element and stencil go together", where);
  if (!type->element) return;
  const cb_stencil *st = type->stencil(term);
  int k3 = 3 * st->k, n3 = 3 * t->mesh.nv, nf3 = sys->A.n;
  double *g = calloc((size_t)n3, sizeof(double)), *gt = calloc((size_t)n3, sizeof(double));
  double *ge = malloc((size_t)k3 * sizeof(double)), *He = malloc((size_t)k3 * k3 * sizeof(double));
  cr_assert(g && gt && ge && He);
  double Et = type->energy(term, x, gt), E = 0;
  for (int d = 0; d < CB_DEF_COUNT; d++) {
    cb_projection proj = cb_definiteness_projection((cb_definiteness)d);
    gsl_matrix *Hs = gsl_matrix_calloc((size_t)(nf3 > 0 ? nf3 : 1), (size_t)(nf3 > 0 ? nf3 : 1));
    for (int e = 0; e < st->ne; e++) {
      double Ee = type->element(term, e, x, proj, ge, He);
      const int *v = st->vert + (size_t)st->k * e;
      if (d == 0) {
        E += Ee;
        for (int a = 0; a < st->k; a++)
          for (int c = 0; c < 3; c++) g[3 * v[a] + c] += ge[3 * a + c];
      }
      for (int a = 0; a < st->k; a++)
        for (int b = 0; b < st->k; b++) {
          int fa = t->model.free_index[v[a]], fb = t->model.free_index[v[b]];
          if (fa < 0 || fb < 0) continue;
          for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
              *gsl_matrix_ptr(Hs, (size_t)(3 * fa + r), (size_t)(3 * fb + c)) += He[(3 * a + r) * k3 + 3 * b + c];
        }
    }
    cb_system_assemble(sys, x, 0.0, (cb_definiteness)d, 0.0); /* A = H */
    gsl_matrix *H = test_dense(&sys->A);
    double hmax = mat_maxabs(H), err = 0;
    for (size_t i = 0; i < H->size1; i++)
      for (size_t j = 0; j < H->size2; j++) err = fmax(err, fabs(gsl_matrix_get(H, i, j) - gsl_matrix_get(Hs, i, j)));
    cr_expect(err <= 1e-12 * fmax(hmax, 1.0), "%s, %s: element Hessians - assembled = %.3g (max %.3g)", where,
              cb_definiteness_names[d], err, hmax);
    gsl_matrix_free(H);
    gsl_matrix_free(Hs);
  }
  cr_expect(fabs(E - Et) <= 1e-12 * fmax(fabs(Et), 1.0), "%s: element energies %.17g, term %.17g", where, E, Et);
  double gerr = 0, gm = 0;
  for (int i = 0; i < n3; i++) {
    gerr = fmax(gerr, fabs(g[i] - gt[i]));
    gm = fmax(gm, fabs(gt[i]));
  }
  cr_expect(gerr <= 1e-12 * fmax(gm, 1.0), "%s: element gradients - term gradient = %.3g", where, gerr);
  /* element_vertex: each vertex's blocks of element's gradient and unprojected Hessian, and its energy, bit for
   * bit; with g and H NULL the same energy */
  int bad = 0;
  for (int e = 0; type->element_vertex && e < st->ne; e++) {
    double Ee = type->element(term, e, x, CB_PROJ_NONE, ge, He);
    for (int a = 0; a < st->k; a++) {
      double gv[3], Hv[9];
      double Ev = type->element_vertex(term, e, a, x, gv, Hv), E0 = type->element_vertex(term, e, a, x, NULL, NULL);
      int same = memcmp(&Ev, &Ee, sizeof Ee) == 0 && memcmp(&E0, &Ee, sizeof Ee) == 0 &&
                 memcmp(gv, ge + 3 * a, sizeof gv) == 0;
      for (int r = 0; r < 3; r++)
        same = same && memcmp(Hv + 3 * r, He + (3 * a + r) * k3 + 3 * a, 3 * sizeof(double)) == 0;
      bad += !same;
    }
  }
  cr_expect_eq(bad, 0, "%s: %d (element, vertex) pairs whose element_vertex differs from element", where, bad);
  free(g);
  free(gt);
  free(ge);
  free(He);
}

static int check_type(const cb_term_type *type) {
  int cases = 0;
  for (int ex = 0; ex < type->nexamples; ex++)
    for (int mk = 0; mk < NMESHES; mk++) {
      tmodel t;
      model_init(&t, mk, 1000 + 17 * (uint64_t)mk);
      cb_term *term = NULL;
      int st = type->example(&t.model, ex, &term);
      cr_assert_eq(st, CB_OK, "%s example %d on %s: %s", type->name, ex, t.name, cb_error_message());
      cr_assert(term && term->type == type, "%s example %d: built a term of another type", type->name, ex);
      cb_system sys;
      cr_assert_eq(cb_system_init(&sys, &t.model, &term, 1), CB_OK, "%s: %s", type->name, cb_error_message());
      int n3 = 3 * t.mesh.nv;
      double *x = malloc((size_t)n3 * sizeof(double));
      cr_assert(x);
      gsl_matrix *H0 = NULL; /* exact Hessian at the first state (constant-Hessian check) */
      for (int sk = 0; sk < NSTATES; sk++, cases++) {
        state(&t, sk, 77 + 31 * (uint64_t)(sk + NSTATES * mk), x);
        char where[160];
        snprintf(where, sizeof where, "%s example %d, %s, %s", type->name, ex, t.name, state_names[sk]);
        double gmax, gerr = fd_gradient_error(&sys, &t, x, &gmax);
        cr_expect(gerr <= 1e-6 * fmax(gmax, 1.0), "%s: gradient error %.3g (max |g| %.3g)", where, gerr, gmax);
        gsl_matrix *Hfd = fd_hessian(&sys, &t, x);
        double fdmax = mat_maxabs(Hfd);
        for (int d = 0; d < CB_DEF_COUNT; d++) {
          cb_system_assemble(&sys, x, 0.0, (cb_definiteness)d, 0.0); /* A = H */
          gsl_matrix *H = test_dense(&sys.A);
          double hmax = mat_maxabs(H), asym = 0;
          for (size_t i = 0; i < H->size1; i++)
            for (size_t j = 0; j < i; j++) asym = fmax(asym, fabs(gsl_matrix_get(H, i, j) - gsl_matrix_get(H, j, i)));
          cr_expect(asym <= 1e-14 * hmax, "%s, %s: max |H - H^T| = %.3g", where, cb_definiteness_names[d], asym);
          if (!type->hessian) cr_expect(hmax == 0, "%s: a term without a Hessian assembled %.3g", where, hmax);
          if (cb_definiteness_projection((cb_definiteness)d) == CB_PROJ_NONE && (type->flags & CB_TERM_MODEL_HESSIAN)) {
            /* a model of the Hessian: PSD and constant if flagged, not the FD Hessian */
            double emax, lmin = H->size1 > 0 ? min_eigenvalue(H, &emax) : 0;
            if (H->size1 > 0)
              cr_expect(lmin >= -1e-12 * fmax(emax, 1.0), "%s, %s: model Hessian has eigenvalue %.3g (max %.3g)", where,
                        cb_definiteness_names[d], lmin, emax);
            if (d == CB_DEF_NONE && (type->flags & CB_TERM_CONSTANT_HESSIAN)) expect_constant_hessian(H, &H0, where);
          } else if (cb_definiteness_projection((cb_definiteness)d) == CB_PROJ_NONE) {
            double err = 0;
            for (size_t i = 0; i < H->size1; i++)
              for (size_t j = 0; j < H->size2; j++)
                err = fmax(err, fabs(gsl_matrix_get(H, i, j) - gsl_matrix_get(Hfd, i, j)));
            cr_expect(err <= 1e-6 * fmax(fmax(hmax, fdmax), 1.0), "%s, %s: Hessian - FD = %.3g (max |H| %.3g)", where,
                      cb_definiteness_names[d], err, hmax);
            if (d == CB_DEF_NONE && (type->flags & CB_TERM_CONSTANT_HESSIAN)) expect_constant_hessian(H, &H0, where);
          } else if (H->size1 > 0) {
            double emax, lmin = min_eigenvalue(H, &emax);
            cr_expect(lmin >= -1e-12 * fmax(emax, 1.0), "%s, %s: projected Hessian has eigenvalue %.3g (max %.3g)",
                      where, cb_definiteness_names[d], lmin, emax);
          }
          gsl_matrix_free(H);
        }
        gsl_matrix_free(Hfd);
        check_elements(term, &sys, &t, x, where);
      }
      if (H0) gsl_matrix_free(H0);
      free(x);
      cb_system_free(&sys);
      model_free(&t);
    }
  return cases;
}

Test(energy_conformance, registry_entries_are_complete_and_unique) {
  int n = 0, spring = 0, gravity = 0;
  for (int i = 0; cb_term_types[i]; i++, n++) {
    const cb_term_type *t = cb_term_types[i];
    cr_assert(t->name && t->name[0], "type %d has no name", i);
    cr_expect(cb_term_type_find(t->name) == t, "%s: name not unique or not found", t->name);
    cr_expect(t->energy && t->free, "%s: energy and free are required", t->name);
    cr_expect(t->nexamples >= 1 && t->example, "%s: no example to check it on", t->name);
    cr_expect(!t->hessian || (t->pattern && t->bind), "%s: a Hessian needs pattern and bind", t->name);
    cr_expect(!(t->flags & CB_TERM_CONSTANT_HESSIAN) || t->hessian, "%s: constant flag without a Hessian", t->name);
    spring += t == cb_term_spring;
    gravity += t == cb_term_gravity;
  }
  cr_expect(n >= 2);
  cr_expect_eq(spring, 1, "the spring is registered once");
  cr_expect_eq(gravity, 1, "gravity is registered once");
  cr_expect_null(cb_term_type_find("no-such-term"));
}

Test(energy_conformance, every_registered_type_passes_fd_symmetry_and_projection_checks) {
  int types = 0;
  for (int i = 0; cb_term_types[i]; i++, types++) {
    int cases = check_type(cb_term_types[i]);
    cr_expect_eq(cases, cb_term_types[i]->nexamples * NMESHES * NSTATES, "%s: %d cases", cb_term_types[i]->name, cases);
  }
  cr_expect(types >= 2);
}

Test(energy_conformance, every_bending_model_builds_a_registered_type) {
  tmodel t;
  model_init(&t, 2, 5);
  int n = 0;
  for (int i = 0; cb_bend_names[i]; i++, n++) {
    cb_term *b = NULL;
    cr_assert_eq(cb_bend_term_alloc(cb_bend_names[i], &t.model, 37.0, &b), CB_OK, "%s: %s", cb_bend_names[i],
                 cb_error_message());
    if (strcmp(cb_bend_names[i], "none") == 0) {
      cr_expect_null(b);
      continue;
    }
    cr_assert(b);
    cr_expect(cb_term_type_find(b->type->name) == b->type, "bend %s: type %s is not registered", cb_bend_names[i],
              b->type->name);
    cb_term_free(b);
  }
  cr_expect(n >= 2);
  cb_term *b = NULL;
  cr_expect_neq(cb_bend_term_alloc("dihedral-ish", &t.model, 1.0, &b), CB_OK);
  cr_expect_null(b);
  model_free(&t);
}

/* ---- the dihedral's Gauss-Newton Hessian against its exact one ------------------- */

static double mat_diffabs(const gsl_matrix *A, const gsl_matrix *B) {
  double m = 0;
  for (size_t i = 0; i < A->size1; i++)
    for (size_t j = 0; j < A->size2; j++) m = fmax(m, fabs(gsl_matrix_get(A, i, j) - gsl_matrix_get(B, i, j)));
  return m;
}

static gsl_matrix *assembled(cb_system *s, const double *x) {
  cb_system_assemble(s, x, 0.0, CB_DEF_NONE, 0.0); /* A = H, no projection */
  return test_dense(&s->A);
}

/* x = R (X - X0) + X0 + (0.1, -0.2, 0.3): a rigid motion of the rest shape (every theta = theta_bar),
 * R the rotation by 0.7 rad about (1, 2, 3)/|.| (Rodrigues). */
static void rigid_rest(const tmodel *t, double *x) {
  double k[3] = {1, 2, 3}, nk = sqrt(14.0), a = 0.7, c = cos(a), sn = sin(a);
  for (int i = 0; i < 3; i++) k[i] /= nk;
  for (int v = 0; v < t->mesh.nv; v++) {
    const double *p = t->mesh.x + 3 * v;
    double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2],
           kx[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
    static const double off[3] = {0.1, -0.2, 0.3};
    for (int i = 0; i < 3; i++) x[3 * v + i] = p[i] * c + kx[i] * sn + k[i] * kp * (1 - c) + off[i];
  }
}

/* H_GN = c grad theta grad theta^T (energy_dihedral.c): symmetric and PSD at every state; on one hinge
 * equal to grad E grad E^T / (2E) with grad E from central differences of E; equal to the FD Hessian
 * where theta = theta_bar (rigid motions of the rest shape, planar and non-planar); and not equal to it
 * on a folded hinge, where the exact Hessian's dropped part c (theta - theta_bar) d2theta grows
 * linearly with the fold. */
Test(energy_conformance, dihedral_gauss_newton_hessian_is_the_exact_one_without_its_curvature_term) {
  for (int mk = 1; mk <= 2; mk++) { /* two triangles (one hinge); 3x3 jittered non-planar rest */
    tmodel t;
    model_init(&t, mk, 1000 + 17 * (uint64_t)mk);
    cb_term *gn = NULL, *ex = NULL;
    cr_assert_eq(cb_hinge_term_alloc(&t.model, "bend", 0.37, &gn), CB_OK);
    cr_assert_eq(cb_hinge_term_alloc(&t.model, "bend", 0.37, &ex), CB_OK);
    cr_assert_eq(cb_hinge_term_set_hessian(ex, CB_BEND_EXACT), CB_OK);
    cr_expect_str_eq(gn->type->name, "dihedral");
    cr_expect_str_eq(ex->type->name, "dihedral_exact");
    cr_expect(gn->type->flags & CB_TERM_MODEL_HESSIAN, "the Gauss-Newton matrix is a model of the Hessian");
    cb_system sg, se;
    cr_assert_eq(cb_system_init(&sg, &t.model, &gn, 1), CB_OK);
    cr_assert_eq(cb_system_init(&se, &t.model, &ex, 1), CB_OK);
    int n3 = 3 * t.mesh.nv;
    double *x = malloc((size_t)n3 * sizeof(double)), *g = malloc((size_t)n3 * sizeof(double));
    cr_assert(x && g);
    /* at theta = theta_bar: H_GN = the FD Hessian */
    rigid_rest(&t, x);
    gsl_matrix *H = assembled(&sg, x), *Hfd = fd_hessian(&sg, &t, x);
    double err = mat_diffabs(H, Hfd), hmax = mat_maxabs(H);
    cr_expect(hmax > 0 && err <= 1e-6 * hmax, "%s at rest (rigidly moved): |H_GN - FD| = %.3g of %.3g", t.name, err,
              hmax);
    gsl_matrix_free(H);
    gsl_matrix_free(Hfd);
    for (int sk = 0; sk < NSTATES; sk++) {
      state(&t, sk, 77 + 31 * (uint64_t)(sk + NSTATES * mk), x);
      H = assembled(&sg, x);
      gsl_matrix *He = assembled(&se, x);
      Hfd = fd_hessian(&se, &t, x);
      hmax = mat_maxabs(H);
      double asym = 0, emax, lmin = min_eigenvalue(H, &emax);
      for (size_t i = 0; i < H->size1; i++)
        for (size_t j = 0; j < i; j++) asym = fmax(asym, fabs(gsl_matrix_get(H, i, j) - gsl_matrix_get(H, j, i)));
      cr_expect(asym <= 1e-14 * hmax, "%s, %s: H_GN asymmetric by %.3g", t.name, state_names[sk], asym);
      cr_expect(lmin >= -1e-12 * emax, "%s, %s: H_GN eigenvalue %.3g (max %.3g)", t.name, state_names[sk], lmin, emax);
      /* the exact variant is the FD Hessian (the registry loop checks it too); GN differs from it */
      double dex = mat_diffabs(He, Hfd), dgn = mat_diffabs(H, Hfd), fdmax = mat_maxabs(Hfd);
      cr_expect(dex <= 1e-6 * fdmax, "%s, %s: |H_exact - FD| = %.3g", t.name, state_names[sk], dex);
      cr_expect(dgn >= 1e-3 * fdmax, "%s, %s: H_GN equals the exact Hessian (%.3g of %.3g) away from rest", t.name,
                state_names[sk], dgn, fdmax);
      if (mk == 1) { /* one hinge: H_GN = grad E grad E^T / (2E), grad E by central differences of E */
        double E = cb_system_energy(&sg, x, NULL, NULL), e2 = 0;
        cr_assert(E > 0);
        for (int i = 0; i < n3; i++) {
          double xi = x[i];
          x[i] = xi + FD_H;
          double Ep = cb_system_energy(&sg, x, NULL, NULL);
          x[i] = xi - FD_H;
          double Em = cb_system_energy(&sg, x, NULL, NULL);
          x[i] = xi;
          g[i] = (Ep - Em) / (2 * FD_H);
        }
        for (int i = 0; i < n3; i++)
          for (int j = 0; j < n3; j++)
            e2 = fmax(e2, fabs(gsl_matrix_get(H, (size_t)i, (size_t)j) - g[i] * g[j] / (2 * E)));
        cr_expect(e2 <= 1e-6 * hmax, "%s, %s: |H_GN - grad E grad E^T / 2E| = %.3g of %.3g", t.name, state_names[sk],
                  e2, hmax);
      }
      gsl_matrix_free(H);
      gsl_matrix_free(He);
      gsl_matrix_free(Hfd);
    }
    if (mk == 1) { /* the dropped term c d d2theta is linear in the fold d: wing x3 rotated by delta, 2 delta */
      int v[4];
      cb_hinge_vertices(&t.topo, v);
      double drop[2];
      for (int f = 0; f < 2; f++) {
        double dl = 0.02 * (f + 1);
        memcpy(x, t.mesh.x, (size_t)n3 * sizeof(double));
        const double *o = t.mesh.x + 3 * v[0], *p = t.mesh.x + 3 * v[1];
        double e[3], w[3], le = 0, we = 0;
        for (int a = 0; a < 3; a++) e[a] = p[a] - o[a], le += e[a] * e[a];
        for (int a = 0; a < 3; a++) w[a] = x[3 * v[3] + a] - o[a], we += w[a] * e[a] / le;
        double r[3], rr = 0;
        for (int a = 0; a < 3; a++) r[a] = w[a] - we * e[a], rr += r[a] * r[a];
        double ez[3] = {e[1] * r[2] - e[2] * r[1], e[2] * r[0] - e[0] * r[2], e[0] * r[1] - e[1] * r[0]}, ne = sqrt(le);
        for (int a = 0; a < 3; a++) /* rotate r about the edge by dl: r cos + (e^ x r) sin */
          x[3 * v[3] + a] = o[a] + we * e[a] + r[a] * cos(dl) + ez[a] / ne * sin(dl);
        H = assembled(&sg, x);
        gsl_matrix *He = assembled(&se, x);
        drop[f] = mat_diffabs(He, H);
        gsl_matrix_free(H);
        gsl_matrix_free(He);
      }
      cr_expect(drop[0] > 0 && fabs(drop[1] / drop[0] - 2) < 0.05, "dropped term at folds 0.02, 0.04 rad: %.4g, %.4g",
                drop[0], drop[1]);
    }
    free(x);
    free(g);
    cb_system_free(&sg);
    cb_system_free(&se);
    model_free(&t);
  }
}

/* ---- a constant-Hessian term, registered only here ------------------------------- */

/* E = k/2 sum_i |x_i - a_i|^2 (a zero-length spring from every vertex to a
 * fixed anchor a_i), dE/dx_i = k (x_i - a_i), H = k I: constant. */
typedef struct {
  cb_term base;
  double k;       /* N/m */
  double *anchor; /* 3 nv */
  int *verts;     /* nv: 1-vertex elements */
  cb_stencil st;
} anchor_term;

static int anchor_hessian_calls;

static double anchor_energy(const cb_term *t, const double *x, double *grad) {
  const anchor_term *s = (const anchor_term *)t;
  double E = 0;
  for (int i = 0; i < t->model->mesh->nv; i++) {
    double g[3];
    for (int a = 0; a < 3; a++) {
      double d = x[3 * i + a] - s->anchor[3 * i + a];
      E += 0.5 * s->k * d * d;
      g[a] = s->k * d;
    }
    if (grad) cb_stencil_add_gradient(&s->st, i, g, grad);
  }
  return E;
}

static int anchor_pattern(const cb_term *t, cb_pattern *p) {
  return cb_stencil_pattern(&((const anchor_term *)t)->st, p);
}
static int anchor_bind(cb_term *t, const cb_sparse *A) { return cb_stencil_bind(&((anchor_term *)t)->st, A, "anchor"); }

static void anchor_hessian(const cb_term *t, const double *x, cb_projection proj, double *val) {
  (void)x;
  (void)proj; /* k I is PSD */
  const anchor_term *s = (const anchor_term *)t;
  anchor_hessian_calls++;
  double H[9] = {s->k, 0, 0, 0, s->k, 0, 0, 0, s->k};
  for (int i = 0; i < t->model->mesh->nv; i++) cb_stencil_add_hessian(&s->st, i, H, val);
}

static void anchor_free(cb_term *t) {
  anchor_term *s = (anchor_term *)t;
  free(s->anchor);
  free(s->verts);
  cb_stencil_free(&s->st);
  free(s);
}

static int anchor_example(const cb_model *m, int i, cb_term **out);

static const cb_term_type anchor_type = {.name = "anchor",
                                         .flags = CB_TERM_CONSTANT_HESSIAN,
                                         .energy = anchor_energy,
                                         .pattern = anchor_pattern,
                                         .bind = anchor_bind,
                                         .hessian = anchor_hessian,
                                         .free = anchor_free,
                                         .nexamples = 1,
                                         .example = anchor_example};

/* Anchors at the rest positions shifted by (0.1, -0.2, 0.05), k = 50 N/m. */
static int anchor_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  int nv = m->mesh->nv;
  anchor_term *s = calloc(1, sizeof *s);
  cr_assert(s);
  s->base.type = &anchor_type;
  s->base.model = m;
  strcpy(s->base.label, "anchor");
  s->k = 50.0;
  s->anchor = malloc((size_t)3 * nv * sizeof(double));
  s->verts = malloc((size_t)nv * sizeof(int));
  cr_assert(s->anchor && s->verts);
  static const double off[3] = {0.1, -0.2, 0.05};
  for (int v = 0; v < nv; v++) {
    s->verts[v] = v;
    for (int a = 0; a < 3; a++) s->anchor[3 * v + a] = m->mesh->x[3 * v + a] + off[a];
  }
  cr_assert_eq(cb_stencil_init(&s->st, 1, nv, s->verts, m->free_index), CB_OK);
  *out = &s->base;
  return CB_OK;
}

Test(energy_conformance, constant_hessian_term_passes_the_same_checks) {
  int cases = check_type(&anchor_type);
  cr_expect_eq(cases, NMESHES * NSTATES);
}

Test(energy_conformance, constant_hessian_is_evaluated_once_and_added_at_every_assembly) {
  tmodel t;
  model_init(&t, 3, 9); /* vertices 0 and 5 pinned */
  cb_term *with[2], *without[1];
  cr_assert_eq(cb_term_spring->example(&t.model, 0, &with[0]), CB_OK);
  cr_assert_eq(cb_term_spring->example(&t.model, 0, &without[0]), CB_OK);
  anchor_hessian_calls = 0;
  cr_assert_eq(anchor_example(&t.model, 0, &with[1]), CB_OK);
  cb_system a, b;
  cr_assert_eq(cb_system_init(&a, &t.model, with, 2), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_system_init(&b, &t.model, without, 1), CB_OK);
  cr_expect_eq(anchor_hessian_calls, 1, "the constant Hessian is evaluated when the system is finalised");
  cr_assert_eq(a.A.nnz, b.A.nnz, "k I adds no block to the pattern");
  int n3 = 3 * t.mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double));
  cr_assert(x);
  for (int sk = 0; sk < NSTATES; sk++)
    for (int d = 0; d < CB_DEF_COUNT; d++) {
      state(&t, sk, 3 + (uint64_t)sk, x);
      double ms = 2.5, mu = 0.125;
      cb_system_assemble(&a, x, ms, (cb_definiteness)d, mu);
      cb_system_assemble(&b, x, ms, (cb_definiteness)d, mu);
      gsl_matrix *A = test_dense(&a.A), *B = test_dense(&b.A);
      for (size_t i = 0; i < B->size1; i++) gsl_matrix_set(B, i, i, gsl_matrix_get(B, i, i) + 50.0); /* + k I */
      double err = 0, scale = mat_maxabs(B);
      for (size_t i = 0; i < A->size1; i++)
        for (size_t j = 0; j < A->size2; j++) err = fmax(err, fabs(gsl_matrix_get(A, i, j) - gsl_matrix_get(B, i, j)));
      cr_expect(err <= 1e-13 * scale, "%s %s: |A - (A_spring + k I)| = %.3g", state_names[sk], cb_definiteness_names[d],
                err);
      gsl_matrix_free(A);
      gsl_matrix_free(B);
    }
  cr_expect_eq(anchor_hessian_calls, 1, "assembly never evaluates a constant Hessian again (%d calls)",
               anchor_hessian_calls);
  free(x);
  cb_system_free(&a);
  cb_system_free(&b);
  model_free(&t);
}

/* ---- the stencil helper on triangles ------------------------------------------- */

/* Every triangle gets a fixed dense symmetric 9x9 matrix; the assembled
 * matrix must equal the dense assembly done here by free indices (pinned
 * rows and columns dropped), and the gradient scatter must add g_e to every
 * vertex of e, pinned ones included. */
Test(energy_conformance, stencil_scatters_dense_triangle_elements) {
  tmodel t;
  model_init(&t, 3, 21); /* 4x3 grid, 12 triangles, vertices 0 and 5 pinned */
  int nt = t.mesh.nt, nf = t.model.nfree;
  cb_stencil st;
  cr_assert_eq(cb_stencil_init(&st, 3, nt, t.mesh.tri, t.free_index), CB_OK);
  cb_pattern p;
  cb_sparse A;
  cr_assert_eq(cb_pattern_init(&p, nf), CB_OK);
  cr_assert_eq(cb_stencil_pattern(&st, &p), CB_OK);
  cr_assert_eq(cb_sparse_from_pattern(&p, &A), CB_OK);
  cb_pattern_free(&p);
  cr_assert_eq(cb_stencil_bind(&st, &A, "triangle"), CB_OK, "%s", cb_error_message());
  double *He = malloc((size_t)nt * 81 * sizeof(double)), *ge = malloc((size_t)nt * 9 * sizeof(double));
  cr_assert(He && ge);
  cb_rng seed = cb_rng_raw(4);
  for (int e = 0; e < nt; e++) {
    for (int i = 0; i < 9; i++)
      for (int j = 0; j <= i; j++) He[81 * e + 9 * i + j] = He[81 * e + 9 * j + i] = 2 * cb_rng_uniform(&seed) - 1;
    for (int i = 0; i < 9; i++) ge[9 * e + i] = 2 * cb_rng_uniform(&seed) - 1;
  }
  gsl_matrix *D = gsl_matrix_calloc((size_t)3 * nf, (size_t)3 * nf);
  double *gd = calloc((size_t)3 * t.mesh.nv, sizeof(double)), *g = calloc((size_t)3 * t.mesh.nv, sizeof(double));
  cr_assert(D && gd && g);
  int active = 0;
  for (int e = 0; e < nt; e++) {
    const int *v = t.mesh.tri + 3 * e;
    int any = 0;
    for (int a = 0; a < 3; a++) {
      any |= t.free_index[v[a]] >= 0;
      for (int r = 0; r < 3; r++) gd[3 * v[a] + r] += ge[9 * e + 3 * a + r];
      for (int b = 0; b < 3; b++) {
        int fa = t.free_index[v[a]], fb = t.free_index[v[b]];
        if (fa < 0 || fb < 0) continue;
        for (int r = 0; r < 3; r++)
          for (int c = 0; c < 3; c++) {
            size_t i = (size_t)(3 * fa + r), j = (size_t)(3 * fb + c);
            gsl_matrix_set(D, i, j, gsl_matrix_get(D, i, j) + He[81 * e + 9 * (3 * a + r) + 3 * b + c]);
          }
      }
    }
    cr_expect_eq(cb_stencil_active(&st, e), any, "triangle %d", e);
    active += any;
    cb_stencil_add_hessian(&st, e, He + 81 * e, A.val);
    cb_stencil_add_gradient(&st, e, ge + 9 * e, g);
  }
  cr_expect_eq(active, nt, "every triangle of this mesh has a free vertex");
  gsl_matrix *S = test_dense(&A);
  for (size_t i = 0; i < S->size1; i++)
    for (size_t j = 0; j < S->size2; j++)
      cr_expect(fabs(gsl_matrix_get(S, i, j) - gsl_matrix_get(D, i, j)) <= 1e-15, "entry (%zu, %zu)", i, j);
  for (int i = 0; i < 3 * t.mesh.nv; i++) cr_expect(fabs(g[i] - gd[i]) <= 1e-15, "gradient %d", i);
  gsl_matrix_free(S);
  gsl_matrix_free(D);
  free(He);
  free(ge);
  free(g);
  free(gd);
  cb_sparse_free(&A);
  cb_stencil_free(&st);
  model_free(&t);
}
