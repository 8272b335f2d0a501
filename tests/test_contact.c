/* The contact responses (contact.h, docs/contact.md): the seam's keys and
 * their errors; the penalty's and the barrier's energies and gradients
 * against closed forms on a sheet held flat above a large triangle; the step
 * bound (additive CCD) against the crossing time of a straight fall; the
 * conformance examples are not vacuous (contacts and mollified edge pairs
 * are active in them); and a sheet dropped on the shipped table
 * (configs/table.obj) under Newton: with `ipc` no frame intersects (exact
 * triangle-triangle tests, intersect.h, cloth against table and cloth against
 * itself), with `penalty` at the same large step the sheet tunnels through. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "intersections.h"
#include "support.h"

/* ---- the seam ----------------------------------------------------------------- */

Test(contact, bad_values_name_their_key) {
  test_expect_config_error((const char *const[]){"contact.method=ipc", "contact.thickness=0", NULL}, "contact."
                                                                                                     "thickness");
  test_expect_config_error((const char *const[]){"contact.method=penalty", "contact.thickness=-1e-3", NULL}, "contact."
                                                                                                             "thicknes"
                                                                                                             "s");
  test_expect_config_error((const char *const[]){"contact.method=ipc", "contact.friction=-0.1", NULL}, "contact."
                                                                                                       "friction");
  test_expect_config_error((const char *const[]){"contact.method=penalty", "contact.friction=0.4", NULL}, "contact."
                                                                                                          "friction");
  test_expect_config_error((const char *const[]){"contact.method=ipc", "contact.friction=0.4", "contact.epsv=0", NULL},
                           "contact."
                           "epsv");
  test_expect_config_error((const char *const[]){"contact.method=ipc", "contact.epsv=-1e-3", NULL}, "contact.epsv");
  test_expect_config_error((const char *const[]){"contact.method=vbd", NULL}, "contact.method");
  test_expect_config_error((const char *const[]){"contact.method=penalty", "contact.stiffness=0", NULL}, "contact."
                                                                                                         "stiffness");
  test_expect_config_error((const char *const[]){"contact.method=ipc", "contact.kappa=-1", NULL}, "contact.kappa");
  /* the core checks without a config too */
  cb_contact_params p = cb_contact_params_default();
  p.thickness = NAN;
  cr_expect_neq(cb_contact_params_check("ipc", &p), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.thickness"));
  p = cb_contact_params_default();
  p.epsv = NAN;
  cr_expect_neq(cb_contact_params_check("ipc", &p), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.epsv"));
  p = cb_contact_params_default();
  p.friction = INFINITY;
  cr_expect_neq(cb_contact_params_check("ipc", &p), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.friction"));
  p = cb_contact_params_default();
  p.friction = 0.4; /* ipc takes friction */
  cr_expect_eq(cb_contact_params_check("ipc", &p), CB_OK, "%s", cb_error_message());
  p = cb_contact_params_default();
  cr_expect_neq(cb_contact_params_check("nope", &p), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.method"));
  cr_expect_eq(cb_contact_params_check("none", &p), CB_OK);
}

Test(contact, registry_and_keys) {
  int n = 0;
  for (int i = 0; cb_contact_types[i]; i++, n++) {
    cr_expect(cb_contact_type_find(cb_contact_types[i]->name) == cb_contact_types[i]);
    cr_expect_str_eq(cb_contact_names[i], cb_contact_types[i]->name);
    if (!cb_contact_types[i]->term_alloc && !cb_contact_types[i]->response) continue;
    int thick = 0, fric = 0;
    for (const cb_param_key *k = cb_contact_types[i]->keys; k && k->name; k++) {
      thick += !strcmp(k->name, "thickness");
      fric += !strcmp(k->name, "friction");
    }
    cr_expect(thick == 1 && fric == 1, "%s: declares thickness and friction once each", cb_contact_types[i]->name);
  }
  cr_expect_eq(n, 4);
  cr_expect_null(cb_contact_type_find("vbd"));
  /* the keys' defaults give cb_contact_params_default */
  cb_config c;
  cb_config_defaults(&c);
  cb_contact_params p, d = cb_contact_params_default();
  cr_assert_eq(cb_contact_params_from_config(&c, &p), CB_OK, "%s", cb_error_message());
  cr_expect(p.thickness == d.thickness && p.friction == d.friction && p.stiffness == d.stiffness &&
            p.kappa == d.kappa && p.epsv == d.epsv && p.bridson_iters == d.bridson_iters);
  cr_assert_eq(cb_config_set(&c, "contact.thickness=2e-3"), CB_OK);
  cr_assert_eq(cb_contact_params_from_config(&c, &p), CB_OK);
  cr_expect_eq(p.thickness, 2e-3);
}

/* ---- closed forms ------------------------------------------------------------------ */

/* A 2x2 sheet (4 vertices, two triangles, all primitives adjacent: no self pairs) 0.1 m wide in the xz plane,
 * and a triangle 20 m wide in the plane y = 0: the sheet's vertices at height h see point-plane pairs at distance
 * h exactly, and no other pair is within reach. */
typedef struct {
  cb_scene *s;
  cb_obstacle o;
  double X[9];
  int tri[3];
} flat;

static void flat_init(flat *f) {
  f->s = test_scene((const char *const[]){"mesh.n=2", "mesh.size=0.1", "mesh.plane=xz", "scene.pins=none", NULL});
  memset(&f->o, 0, sizeof f->o);
  const double X[9] = {-10, 0, -10, 0, 0, 10, 10, 0, -10};
  memcpy(f->X, X, sizeof X);
  f->tri[0] = 0;
  f->tri[1] = 1;
  f->tri[2] = 2;
  f->o.mesh.nv = 3;
  f->o.mesh.nt = 1;
  f->o.mesh.x = f->X;
  f->o.mesh.tri = f->tri;
  f->o.x = f->X;
}

static cb_term *flat_term(flat *f, const char *method, const cb_contact_params *p) {
  cb_term *t = NULL;
  cr_assert_eq(cb_contact_type_find(method)->term_alloc(&f->s->model, p, &t), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_contact_term_set_obstacle(t, &f->o), CB_OK, "%s", cb_error_message());
  return t;
}

static void at_height(const flat *f, double h, double *x) {
  for (int i = 0; i < f->s->mesh.nv; i++) {
    x[3 * i] = f->s->x0[3 * i];
    x[3 * i + 1] = h;
    x[3 * i + 2] = f->s->x0[3 * i + 2];
  }
}

Test(contact, penalty_and_barrier_match_closed_forms) {
  flat f;
  flat_init(&f);
  cb_contact_params p = cb_contact_params_default();
  p.thickness = 0.01;
  p.stiffness = 300;
  p.kappa = 7;
  cb_term *pen = flat_term(&f, "penalty", &p), *ipc = flat_term(&f, "ipc", &p);
  double x[12], g[12];
  const double hs[] = {0.004, 0.0099, 0.002, 0.0101, 0.03};
  for (size_t k = 0; k < sizeof hs / sizeof hs[0]; k++) {
    double h = hs[k], H = p.thickness, s = h * h, sh = H * H;
    at_height(&f, h, x);
    /* penalty: 4 vertices x k/2 (H - h)^2, dE/dy = -k (H - h) */
    double Ep = h < H ? 4 * 0.5 * p.stiffness * (H - h) * (H - h) : 0, gp = h < H ? -p.stiffness * (H - h) : 0;
    memset(g, 0, sizeof g);
    double E = pen->type->energy(pen, x, g);
    cr_expect(fabs(E - Ep) <= 1e-12 * fmax(Ep, 1e-300) + 1e-300, "penalty h = %g: E %.17g, closed form %.17g", h, E,
              Ep);
    for (int i = 0; i < 4; i++)
      cr_expect(fabs(g[3 * i + 1] - gp) <= 1e-10 * fmax(fabs(gp), 1e-12) && g[3 * i] == 0 && g[3 * i + 2] == 0,
                "penalty h = %g: gradient %g, closed form %g", h, g[3 * i + 1], gp);
    /* ipc: 4 x kappa b(h^2), b(s) = -(s - sh)^2 ln(s/sh); dE/dy = kappa b'(s) 2h */
    double b = h < H ? -(s - sh) * (s - sh) * log(s / sh) : 0;
    double db = h < H ? -2 * (s - sh) * log(s / sh) - (s - sh) * (s - sh) / s : 0;
    double Ei = 4 * p.kappa * b, gi = p.kappa * db * 2 * h;
    memset(g, 0, sizeof g);
    E = ipc->type->energy(ipc, x, g);
    cr_expect(fabs(E - Ei) <= 1e-12 * fabs(Ei) + 1e-300, "ipc h = %g: E %.17g, closed form %.17g", h, E, Ei);
    for (int i = 0; i < 4; i++)
      cr_expect(fabs(g[3 * i + 1] - gi) <= 1e-10 * fabs(gi) + 1e-300, "ipc h = %g: gradient %g, closed form %g", h,
                g[3 * i + 1], gi);
    const cb_contact_stats *st = cb_contact_term_stats(ipc);
    cr_expect_eq(st->active, h < H ? 4 : 0, "h = %g: %ld active pairs", h, st->active);
  }
  /* touching: the barrier is infinite, the penalty its clamp k H^2 / 2 per vertex */
  at_height(&f, 0, x);
  cr_expect(isinf(ipc->type->energy(ipc, x, NULL)));
  cr_expect_eq(pen->type->energy(pen, x, NULL), 4 * 0.5 * p.stiffness * p.thickness * p.thickness);
  cb_term_free(pen);
  cb_term_free(ipc);
  cb_scene_free(f.s);
}

/* Friction (contact_term.c, "Friction") on the flat fixture: 4 point-plane pairs at height h, each with normal
 * force lam = -dE/dd = -2 h kappa b'(h^2) (b' of the barrier, above), frozen at x0. Moving the sheet by delta
 * in the plane gives every pair u = delta, so the term adds D = 4 mu lam f0(|delta|) and each vertex's tangential
 * gradient mu lam f1(|delta|) delta/|delta|, with c = eps_v dt:
 *   f0(y) = -y^3/(3c^2) + y^2/c + c/3, f1(y) = 2y/c - y^2/c^2 for y < c;  f0(y) = y, f1(y) = 1 beyond.
 * An obstacle moving at v: u = delta - dt v (the cloth's displacement against the obstacle's). */
Test(contact, friction_matches_closed_forms) {
  flat f;
  flat_init(&f);
  cb_contact_params p = cb_contact_params_default();
  p.thickness = 0.01;
  p.kappa = 7;
  p.friction = 0.3;
  p.epsv = 0.02;
  const double dt = 0.05, c = p.epsv * dt, h = 0.004, sh = p.thickness * p.thickness, s = h * h;
  double db = -2 * (s - sh) * log(s / sh) - (s - sh) * (s - sh) / s, lam = -2 * h * p.kappa * db;
  double Eb = 4 * p.kappa * -(s - sh) * (s - sh) * log(s / sh), ml = p.friction * lam;
  cr_assert_gt(lam, 0);
  cb_term *ipc = flat_term(&f, "ipc", &p);
  double x0[12], x[12], g[12];
  at_height(&f, h, x0);
  cr_assert_eq(cb_contact_term_begin_step(ipc, x0, dt), CB_OK, "%s", cb_error_message());
  cr_expect_eq(cb_contact_term_stats(ipc)->friction_pairs, 4);
  const double deltas[] = {0, 3e-4, 0.999e-3, 1.001e-3, 2e-3, 0.05}, phi = 0.7;
  for (size_t k = 0; k < sizeof deltas / sizeof deltas[0]; k++) {
    double y = deltas[k], dx = y * cos(phi), dz = y * sin(phi);
    for (int i = 0; i < 12; i++) x[i] = x0[i] + (i % 3 == 0 ? dx : i % 3 == 2 ? dz : 0);
    double f0 = y < c ? -y * y * y / (3 * c * c) + y * y / c + c / 3 : y, f1 = y < c ? 2 * y / c - y * y / (c * c) : 1;
    memset(g, 0, sizeof g);
    double E = ipc->type->energy(ipc, x, g), Ec = Eb + 4 * ml * f0;
    cr_expect(fabs(E - Ec) <= 1e-12 * fabs(Ec), "delta = %g: E %.17g, closed form %.17g", y, E, Ec);
    for (int i = 0; i < 4; i++) {
      double gx = ml * f1 * cos(phi), gz = ml * f1 * sin(phi);
      cr_expect(fabs(g[3 * i] - gx) <= 1e-10 * ml && fabs(g[3 * i + 2] - gz) <= 1e-10 * ml,
                "delta = %g: tangential gradient (%g, %g), closed form (%g, %g)", y, g[3 * i], g[3 * i + 2], gx, gz);
    }
    cr_expect_eq(cb_contact_term_stats(ipc)->sliding, y >= c ? 4 : 0, "delta = %g: %ld sliding", y,
                 cb_contact_term_stats(ipc)->sliding);
  }
  /* a moving obstacle: its displacement over the step enters u */
  const double v[3] = {0.4, 0, 0.1};
  memcpy(f.o.velocity, v, sizeof v);
  cr_assert_eq(cb_contact_term_begin_step(ipc, x0, dt), CB_OK, "%s", cb_error_message());
  for (int i = 0; i < 12; i++) x[i] = x0[i] + dt * v[i % 3]; /* carried along: u = 0, D = f0(0) */
  memset(g, 0, sizeof g);
  double E = ipc->type->energy(ipc, x, g);
  cr_expect(fabs(E - (Eb + 4 * ml * c / 3)) <= 1e-12 * E, "carried: E %.17g", E);
  for (int i = 0; i < 4; i++) /* the round-off of u (coordinates of 0.1 m: 1e-17 m) times f1/y = 2/c */
    cr_expect(fabs(g[3 * i]) <= 1e-15 * ml * 2 / c && fabs(g[3 * i + 2]) <= 1e-15 * ml * 2 / c,
              "carried: gradient (%g, %g) of %g", g[3 * i], g[3 * i + 2], ml);
  memset(g, 0, sizeof g); /* left behind: u = -dt v, sliding; the force -g drags the sheet along v */
  E = ipc->type->energy(ipc, x0, g);
  double vn = sqrt(v[0] * v[0] + v[2] * v[2]);
  cr_expect(fabs(E - (Eb + 4 * ml * dt * vn)) <= 1e-12 * E, "left behind: E %.17g", E);
  for (int i = 0; i < 4; i++)
    cr_expect(fabs(g[3 * i] + ml * v[0] / vn) <= 1e-10 * ml && fabs(g[3 * i + 2] + ml * v[2] / vn) <= 1e-10 * ml,
              "left behind: gradient (%g, %g)", g[3 * i], g[3 * i + 2]);
  /* bad dt; mu = 0 freezes nothing */
  cr_expect_neq(cb_contact_term_begin_step(ipc, x0, 0.0), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact.friction"));
  cb_term_free(ipc);
  p.friction = 0;
  ipc = flat_term(&f, "ipc", &p);
  cr_assert_eq(cb_contact_term_begin_step(ipc, x0, dt), CB_OK);
  cr_expect_eq(cb_contact_term_stats(ipc)->friction_pairs, 0);
  cr_expect(fabs(ipc->type->energy(ipc, x0, NULL) - Eb) <= 1e-12 * Eb);
  cb_term_free(ipc);
  cb_scene_free(f.s);
}

/* Self-friction: a 3x3 sheet without an obstacle, reach 0.4 m (a vertex is 0.354 m from a non-adjacent diagonal), mu
 * = 0.5, frozen at the rest shape with eps_v dt = 0.02 m: the frozen pairs are all self pairs, and the term's
 * gradient at a state 0.01-0.05 m from rest matches central differences of its energy. */
Test(contact, self_friction_has_pairs_and_its_gradient) {
  cb_scene *s = test_scene((const char *const[]){"mesh.n=3", "mesh.size=1", "mesh.plane=xy", "scene.pins=none", NULL});
  cb_contact_params p = cb_contact_params_default();
  p.thickness = 0.4;
  p.kappa = 1e4;
  p.friction = 0.5;
  p.epsv = 0.2;
  cb_term *t = NULL;
  cr_assert_eq(cb_contact_type_find("ipc")->term_alloc(&s->model, &p, &t), CB_OK, "%s", cb_error_message());
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *g = calloc((size_t)n3, sizeof(double));
  cr_assert(x && g);
  cr_assert_eq(cb_contact_term_begin_step(t, s->mesh.x, 0.1), CB_OK, "%s", cb_error_message());
  long nfr = cb_contact_term_stats(t)->friction_pairs;
  cr_expect_gt(nfr, 0, "no self-friction pair");
  for (int i = 0; i < n3; i++) x[i] = s->mesh.x[i] + 0.01 * (1 + i % 5) * (i % 2 ? 1 : -1);
  double E0 = t->type->energy(t, x, g), err = 0, gmax = 0, h = 1e-6;
  cr_expect_gt(cb_contact_term_stats(t)->friction_energy, 0);
  for (int i = 0; i < n3; i++) {
    double xi = x[i];
    x[i] = xi + h;
    double Ep = t->type->energy(t, x, NULL);
    x[i] = xi - h;
    double Em = t->type->energy(t, x, NULL);
    x[i] = xi;
    err = fmax(err, fabs((Ep - Em) / (2 * h) - g[i]));
    gmax = fmax(gmax, fabs(g[i]));
  }
  cr_expect(err <= 1e-6 * gmax, "self-friction: gradient - FD = %g of %g (E %g, %ld pairs)", err, gmax, E0, nfr);
  if (!getenv("CB_QUIET"))
    printf("self-friction: %ld pairs (%ld sliding), friction %.3g J of %.3g J, |grad - FD| %.2g of %.3g\n", nfr,
           cb_contact_term_stats(t)->sliding, cb_contact_term_stats(t)->friction_energy, E0, err, gmax);
  free(x);
  free(g);
  cb_term_free(t);
  cb_scene_free(s);
}

/* The step bound on a straight fall from h through the plane to -h: contact at t = 1/2. ACCD stops with a tenth
 * of the gap left: t in [0.45, 0.5). A fall that stops short, and a sideways slide, are not bounded. */
Test(contact, step_bound_stops_before_the_crossing) {
  flat f;
  flat_init(&f);
  cb_contact_params p = cb_contact_params_default();
  p.thickness = 0.01;
  cb_term *ipc = flat_term(&f, "ipc", &p), *pen = flat_term(&f, "penalty", &p);
  cb_system sys;
  cb_term *terms[1] = {ipc};
  cr_assert_eq(cb_system_init(&sys, &f.s->model, terms, 1), CB_OK);
  double x[12], x1[12], xa[12];
  at_height(&f, 0.005, x);
  at_height(&f, -0.005, x1);
  double a = cb_system_max_step(&sys, x, x1);
  cr_expect(a >= 0.45 && a < 0.5, "bound %.17g", a);
  for (int i = 0; i < 12; i++) xa[i] = x[i] + a * (x1[i] - x[i]);
  for (int i = 0; i < 4; i++) cr_expect_gt(xa[3 * i + 1], 0.0);
  cr_expect(isfinite(ipc->type->energy(ipc, xa, NULL)));
  at_height(&f, 0.001, x1);
  cr_expect_eq(cb_system_max_step(&sys, x, x1), 1.0);
  memcpy(x1, x, sizeof x);
  for (int i = 0; i < 4; i++) x1[3 * i] += 0.05;
  cr_expect_eq(cb_system_max_step(&sys, x, x1), 1.0);
  /* the penalty has no bound: it can tunnel */
  at_height(&f, -0.005, x1);
  cr_expect_null(pen->type->max_step);
  cb_system_free(&sys);
  cb_term_free(pen);
  cb_scene_free(f.s);
}

/* The conformance examples (tests/test_energy_conformance.c checks their derivatives) have active pairs, and
 * example 0 mollified edge-edge pairs, at a state of the test's kind (the 3x3 grid compressed to 0.7). */
Test(contact, conformance_examples_have_active_contacts) {
  cb_scene *s = test_scene((const char *const[]){"mesh.n=3", "mesh.size=1", "mesh.plane=xy", "scene.pins=none", NULL});
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double));
  cr_assert(x);
  for (int i = 0; i < n3; i++) x[i] = 0.7 * s->mesh.x[i];
  const char *const names[] = {"contact_penalty", "contact_ipc"};
  for (int k = 0; k < 2; k++) {
    const cb_term_type *type = cb_term_type_find(names[k]);
    cr_assert(type, "%s is not registered", names[k]);
    for (int ex = 0; ex < type->nexamples; ex++) {
      cb_term *t = NULL;
      cr_assert_eq(type->example(&s->model, ex, &t), CB_OK);
      type->energy(t, x, NULL);
      const cb_contact_stats *st = cb_contact_term_stats(t);
      cr_expect_gt(st->active, 0, "%s example %d: no active pair", names[k], ex);
      if (k == 1 && ex == 0) cr_expect_gt(st->mollified, 0, "ipc example 0: no mollified edge pair");
      if (k == 1 && ex == 2) /* friction: pairs on both sides of eps_v dt */
        cr_expect(st->friction_pairs > 0 && st->sliding > 0 && st->sliding < st->friction_pairs,
                  "ipc example 2: %ld friction pairs, %ld sliding", st->friction_pairs, st->sliding);
      cb_term_free(t);
    }
  }
  free(x);
  cb_scene_free(s);
}

/* ipc needs the line-search filter or vertex bounds: the types that keep neither refuse its scene, naming the key. */
Test(contact, ipc_needs_a_filtering_minimiser) {
  const char *const sets[] = {"mesh.n=3", "contact.method=ipc", NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator_params p = cb_integrator_params_default();
  for (int i = 0; cb_integrator_types[i]; i++) {
    const cb_integrator_type *t = cb_integrator_types[i];
    cb_integrator *it = NULL;
    int st = cb_integrator_alloc(t->name, s, &p, NULL, "cholmod", NULL, &it);
    if (t->flags & (CB_INTEGRATOR_STEP_FILTER | CB_INTEGRATOR_VERTEX_BOUNDS)) { /* the filter, or vbd's bounds */
      cr_expect_eq(st, CB_OK, "%s: %s", t->name, cb_error_message());
    } else {
      cr_expect_neq(st, CB_OK, "%s accepted an ipc scene", t->name);
      cr_expect(strstr(cb_error_message(), "integrator.method") || strstr(cb_error_message(), "contact"), "%s: %s",
                t->name, cb_error_message());
    }
    cb_integrator_free(it);
  }
  cb_scene_free(s);
  /* the penalty has no bound, but shape matching would ignore its energy: refused */
  s = test_scene((const char *const[]){"mesh.n=3", "contact.method=penalty", NULL});
  cb_integrator *it = NULL;
  cr_expect_neq(cb_integrator_alloc("shape_matching", s, &p, NULL, NULL, NULL, &it), CB_OK);
  cr_expect(strstr(cb_error_message(), "contact"), "%s", cb_error_message());
  cb_integrator_free(it);
  cb_scene_free(s);
}

/* A start state that intersects (a sheet 1 m wide inside the table's 0.8 m deep top crosses its sides): ipc refuses it,
 * naming contact.method; a start state at distance 0 (the sheet on the top's plane) too; the penalty starts from
 * either. */
Test(contact, ipc_refuses_an_intersecting_start) {
  const char *const heights[] = {"collider.centre=0 0.02 0", "collider.centre=0 0 0"};
  for (int h = 0; h < 2; h++)
    for (int m = 0; m < 2; m++) {
      const char *const sets[] = {"mesh.n=6",
                                  "mesh.size=1",
                                  "mesh.plane=xz",
                                  "scene.pins=none",
                                  "collider.type=mesh",
                                  "collider.file=configs/table.obj",
                                  heights[h],
                                  m ? "contact.method=penalty" : "contact.method=ipc",
                                  NULL};
      cb_config c;
      test_config(&c, sets);
      cb_scene *s = NULL;
      int st = cb_scene_from_config(&c, &s);
      if (m) {
        cr_expect_eq(st, CB_OK, "penalty, %s: %s", heights[h], cb_error_message());
      } else {
        cr_expect_neq(st, CB_OK, "ipc accepted the start state with %s", heights[h]);
        cr_expect(strstr(cb_error_message(), "contact.method"), "%s", cb_error_message());
      }
      cb_scene_free(s);
    }
}

/* ---- the drop ------------------------------------------------------------------------ */

typedef struct {
  long worst_cross, worst_self, frames_hit;
  double ymin_end, ymax_end;
  int failed_steps;
} drop_result;

/* A 10x10 sheet 0.8 m wide falls 0.5 m onto the table's top (y = -0.5, 0.04 m thick) at dt = 1/30 s (about
 * 0.1 m a step at impact: more than the top's thickness). */
static drop_result drop(const char *method, const char *integrator, int steps) {
  const char *const sets[] = {"mesh.n=10",
                              "mesh.size=0.8",
                              "mesh.plane=xz",
                              "material.density=0.2",
                              "material.stretch_k=500",
                              "scene.pins=none",
                              integrator,
                              "integrator.iters=100",
                              "integrator.dt=1/30",
                              "integrator.line_search=1",
                              "integrator.tol_dx=1e-7",
                              "collider.type=mesh",
                              "collider.file=configs/table.obj",
                              "collider.centre=0 -0.5 0",
                              method,
                              "contact.thickness=5e-3",
                              "contact.kappa=1e6",
                              "contact.stiffness=1e4",
                              NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  cb_intersections self;
  cr_assert_eq(cb_intersections_init(&self, &s->mesh), CB_OK);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = malloc((size_t)n3 * sizeof(double));
  cr_assert(x && v);
  memcpy(x, s->x0, (size_t)n3 * sizeof(double));
  memcpy(v, s->v0, (size_t)n3 * sizeof(double));
  drop_result r = {0};
  for (int k = 0; k < steps; k++) {
    cb_step_stats st;
    memset(&st, 0, sizeof st);
    int rc = cb_integrator_step(it, x, v, &st);
    r.failed_steps += rc != CB_OK && rc != CB_NOT_CONVERGED;
    long nself = 0, ncross = test_cross_intersections(s, x);
    cr_assert_eq(cb_intersections_count(&self, x, &nself), CB_OK);
    r.worst_cross = ncross > r.worst_cross ? ncross : r.worst_cross;
    r.worst_self = nself > r.worst_self ? nself : r.worst_self;
    r.frames_hit += ncross + nself > 0;
  }
  r.ymin_end = INFINITY;
  r.ymax_end = -INFINITY;
  for (int i = 0; i < s->mesh.nv; i++) {
    r.ymin_end = fmin(r.ymin_end, x[3 * i + 1]);
    r.ymax_end = fmax(r.ymax_end, x[3 * i + 1]);
  }
  free(x);
  free(v);
  cb_intersections_free(&self);
  cb_integrator_free(it);
  cb_scene_free(s);
  return r;
}

Test(contact, ipc_never_intersects_where_penalty_tunnels, .timeout = 600) {
  drop_result ipc = drop("contact.method=ipc", "integrator.method=newton", 24);
  cr_expect_eq(ipc.failed_steps, 0, "ipc: %d failed steps", ipc.failed_steps);
  cr_expect_eq(ipc.frames_hit, 0, "ipc: %ld frames intersect (worst: %ld with the table, %ld self)", ipc.frames_hit,
               ipc.worst_cross, ipc.worst_self);
  cr_expect(ipc.ymin_end > -0.5 && ipc.ymax_end < -0.5 + 5e-3,
            "ipc: the sheet ends at y in [%g, %g], not resting on "
            "the table (y = -0.5, within dhat)",
            ipc.ymin_end, ipc.ymax_end);
  drop_result pen = drop("contact.method=penalty", "integrator.method=newton", 24);
  /* tunnelled: a frame intersects the table, or the whole sheet ends below the table's top */
  cr_expect(pen.frames_hit > 0 || pen.ymax_end < -0.54, "penalty did not tunnel: ends at y in [%g, %g]", pen.ymin_end,
            pen.ymax_end);
  /* L-BFGS calls the same filter (its iterations may stop at integrator.iters: not converged, still apart) */
  drop_result lb = drop("contact.method=ipc", "integrator.method=lbfgs", 24);
  cr_expect_eq(lb.failed_steps, 0, "lbfgs: %d failed steps", lb.failed_steps);
  cr_expect_eq(lb.frames_hit, 0, "lbfgs: %ld frames intersect", lb.frames_hit);
  cr_expect(lb.ymin_end > -0.5, "lbfgs: the sheet ends at y = %g, below the table's top", lb.ymin_end);
  if (!getenv("CB_QUIET"))
    printf("drop: ipc (newton) ends at y in [%.5f, %.5f], 0 intersecting frames (lbfgs: [%.5f, %.5f], 0); penalty ends "
           "at y in [%.4f, %.4f], %ld "
           "intersecting frames (worst %ld table pairs)\n",
           ipc.ymin_end, ipc.ymax_end, lb.ymin_end, lb.ymax_end, pen.ymin_end, pen.ymax_end, pen.frames_hit,
           pen.worst_cross);
}

/* ---- the phase timers (cb_contact_stats' broad_ms, ccd_ms, barrier_ms; cb_step_stats' contact_*_ms) ---------- */

/* A 6x6 sheet 0.5 m wide falls onto the table from 5 cm above it (it lands within the 8 steps). Per step: the three
 * phase times are >= 0, and with the linear solve (factor + solve, disjoint from them) add up to no more than the
 * step's wall time (the phases are disjoint intervals inside the step: the 1e-9 ms allows the round-off of summing
 * doubles, not a timing margin); their sums over the steps are the term's running totals' growth over them (the
 * wrapper takes differences); ipc's pairs made the timers run (broad and barrier > 0 in some step, ccd > 0 in some
 * step); the penalty has no step bound: its ccd is exactly 0; without contact (contact.method = none) all three are
 * exactly 0. No timing threshold. */
static void timed_drop(const char *method, double *sum, double *grew, int *steps_with) {
  const char *const sets[] = {"mesh.n=6",
                              "mesh.size=0.5",
                              "mesh.plane=xz",
                              "material.density=0.2",
                              "material.stretch_k=500",
                              "scene.pins=none",
                              "integrator.method=newton",
                              "integrator.dt=1/30",
                              "integrator.line_search=1",
                              "integrator.tol_dx=1e-7",
                              "collider.type=mesh",
                              "collider.file=configs/table.obj",
                              "collider.centre=0 -0.05 0",
                              method,
                              "contact.thickness=5e-3",
                              "contact.kappa=1e6",
                              "contact.stiffness=1e4",
                              NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  const cb_term *term = cb_scene_contact_term(s);
  const cb_contact_stats *cs = term ? cb_contact_term_stats(term) : NULL;
  double before[3] = {0, 0, 0};
  if (cs) before[0] = cs->broad_ms, before[1] = cs->ccd_ms, before[2] = cs->barrier_ms;
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof(double)), *v = malloc((size_t)n3 * sizeof(double));
  cr_assert(x && v);
  memcpy(x, s->x0, (size_t)n3 * sizeof(double));
  memcpy(v, s->v0, (size_t)n3 * sizeof(double));
  for (int a = 0; a < 3; a++) sum[a] = 0, steps_with[a] = 0;
  for (int k = 0; k < 8; k++) {
    cb_step_stats st;
    int rc = cb_integrator_step(it, x, v, &st);
    cr_expect(rc == CB_OK || rc == CB_NOT_CONVERGED, "%s, step %d: %s", method, k, cb_status_name(rc));
    double ph[3] = {st.contact_broad_ms, st.contact_ccd_ms, st.contact_barrier_ms};
    for (int a = 0; a < 3; a++) {
      cr_expect_geq(ph[a], 0.0, "%s, step %d: phase %d took %g ms", method, k, a, ph[a]);
      sum[a] += ph[a];
      steps_with[a] += ph[a] > 0;
    }
    double parts = ph[0] + ph[1] + ph[2] + st.factor_ms + st.solve_ms;
    cr_expect_leq(parts, st.wall_ms + 1e-9,
                  "%s, step %d: broad %g + ccd %g + barrier %g + factor %g + solve %g ms > wall %g", method, k, ph[0],
                  ph[1], ph[2], st.factor_ms, st.solve_ms, st.wall_ms);
  }
  grew[0] = cs ? cs->broad_ms - before[0] : 0;
  grew[1] = cs ? cs->ccd_ms - before[1] : 0;
  grew[2] = cs ? cs->barrier_ms - before[2] : 0;
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}

Test(contact, phase_timers_add_up_within_the_step) {
  double sum[3], grew[3];
  int with[3];
  timed_drop("contact.method=ipc", sum, grew, with);
  for (int a = 0; a < 3; a++) {
    cr_expect(with[a] > 0, "ipc: phase %d never ran", a);
    cr_expect(fabs(sum[a] - grew[a]) <= 1e-9 * (1 + grew[a]), "ipc: phase %d: steps %.17g ms, term's total grew %.17g",
              a, sum[a], grew[a]);
  }
  timed_drop("contact.method=penalty", sum, grew, with);
  cr_expect(with[0] > 0 && with[2] > 0, "penalty: broad phase in %d steps, barrier in %d", with[0], with[2]);
  cr_expect_eq(sum[1], 0.0, "penalty: no step bound, yet ccd took %g ms", sum[1]);
  cr_expect_eq(grew[1], 0.0);
  timed_drop("contact.method=none", sum, grew, with);
  for (int a = 0; a < 3; a++) cr_expect_eq(sum[a], 0.0, "none: phase %d took %g ms", a, sum[a]);
}
