/* Every default is written once: the C `_default()` functions are the truth,
 * and every key table must give the same values (params.h).
 *
 * - config.c's key table: its defaults, bound into the core structs by
 *   lib/config/bind.c, equal cb_scene_def_default(), cb_grid_params_default(),
 *   cb_integrator_params_default() and cb_solver_params_default() field by
 *   field; every key of the table is checked here, or through a plug-in's
 *   cb_param_key table, or named as a key with no struct behind it (a new key
 *   fails until it is one of the three).
 * - every plug-in's cb_param_key table (the integrator types', the contact
 *   responses'): each key's default text, parsed here by the key's kind
 *   (independently of the config layer's parser), equals the field at its
 *   offset in the plug-in's params_default.
 * - `auto` is one value: CB_AUTO, in the C structs and from the config. */
#define _DEFAULT_SOURCE
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "support.h"

#include <clothbench/contact.h>
#include <clothbench/params.h>

/* ---- the keys this file has checked ----------------------------------------- */

static const char *checked[256];
static int nchecked;

static void mark(const char *key) {
  cr_assert_lt(nchecked, (int)(sizeof checked / sizeof checked[0]));
  checked[nchecked++] = key;
}

static int was_checked(const char *key) {
  for (int i = 0; i < nchecked; i++)
    if (strcmp(checked[i], key) == 0) return 1;
  return 0;
}

static void same_num(const char *key, double table, double c) {
  mark(key);
  cr_expect(table == c || (isnan(table) && isnan(c)), "%s: the key table's default is %.17g, the C _default()'s %.17g",
            key, table, c);
}

static void same_vec(const char *key, const double *table, const double *c, int n) {
  mark(key);
  for (int a = 0; a < n; a++)
    cr_expect_eq(table[a], c[a], "%s[%d]: the key table's default is %.17g, the C _default()'s %.17g", key, a, table[a],
                 c[a]);
}

static void same_str(const char *key, const char *table, const char *c) {
  mark(key);
  int same = table == c || (table && c && strcmp(table, c) == 0);
  cr_expect(same, "%s: the key table's default is '%s', the C _default()'s '%s'", key, table ? table : "(null)",
            c ? c : "(null)");
}

/* ---- a cb_param_key's default text, parsed by its kind -------------------------- */

/* The value key k's default text gives its field: a number, CB_AUTO, a
 * boolean, or a choice's value. Returns 0, or -1 if the text is none of its
 * kind's forms. */
static int key_default(const cb_param_key *k, double *v) {
  const char *d = k->def;
  if (!d) return -1;
  if (k->kind == CB_PARAM_DOUBLE_AUTO && strcmp(d, "auto") == 0) {
    *v = CB_AUTO;
    return 0;
  }
  switch (k->kind) {
  case CB_PARAM_CHOICE:
    for (int i = 0; k->choices && k->choices[i]; i++)
      if (strcmp(d, k->choices[i]) == 0) {
        *v = k->values ? k->values[i] : i;
        return 0;
      }
    return -1;
  case CB_PARAM_BOOL:
    if (!strcasecmp(d, "1") || !strcasecmp(d, "true") || !strcasecmp(d, "yes") || !strcasecmp(d, "on")) *v = 1;
    else if (!strcasecmp(d, "0") || !strcasecmp(d, "false") || !strcasecmp(d, "no") || !strcasecmp(d, "off")) *v = 0;
    else return -1;
    return 0;
  case CB_PARAM_DOUBLE_AUTO:
  case CB_PARAM_INT:
  case CB_PARAM_DOUBLE: {
    char *end;
    double x = strtod(d, &end);
    if (end == d) return -1;
    if (*end == '/') { /* a fraction, 1/30 */
      const char *den = end + 1;
      double y = strtod(den, &end);
      if (end == den || y == 0) return -1;
      x /= y;
    }
    if (*end) return -1;
    *v = x;
    return 0;
  }
  }
  return -1;
}

/* The field of key k in the struct at p, as a double. */
static double field_value(const cb_param_key *k, const void *p) {
  const char *f = (const char *)p + k->offset;
  if (k->kind == CB_PARAM_DOUBLE || k->kind == CB_PARAM_DOUBLE_AUTO) {
    double v;
    memcpy(&v, f, sizeof v);
    return v;
  }
  int i;
  memcpy(&i, f, sizeof i);
  return i;
}

/* Checks every key of a plug-in's table against its params_default; returns the keys checked. */
static int check_keys(const char *section, const char *owner, const cb_param_key *keys, const void *params_default) {
  int n = 0;
  for (const cb_param_key *k = keys; k && k->name; k++, n++) {
    double def;
    cr_expect_eq(key_default(k, &def), 0, "%s.%s (%s): default text '%s' is not a value of its kind", section, k->name,
                 owner, k->def ? k->def : "(null)");
    if (key_default(k, &def)) continue;
    double c = field_value(k, params_default);
    cr_expect_eq(def, c, "%s.%s (%s): the key's default '%s' gives %.17g, the C params_default %.17g", section, k->name,
                 owner, k->def, def, c);
  }
  return n;
}

/* ---- the tests ------------------------------------------------------------------ */

/* Every integrator type's and contact response's keys give its C defaults. */
Test(params, every_plugin_key_table_gives_its_params_default) {
  int n = 0;
  for (int i = 0; cb_integrator_types[i]; i++) {
    const cb_integrator_type *t = cb_integrator_types[i];
    if (!t->keys) continue;
    cr_assert_not_null(t->params_default, "%s declares keys but no params_default", t->name);
    n += check_keys("integrator", t->name, t->keys, t->params_default);
  }
  cr_expect_gt(n, 0);
  cb_contact_params cd = cb_contact_params_default();
  int nc = 0;
  for (int i = 0; cb_contact_types[i]; i++)
    nc += check_keys("contact", cb_contact_types[i]->name, cb_contact_types[i]->keys, &cd);
  cr_expect_gt(nc, 0);
}

/* Keys of config.c's table with no core struct behind them: the program's
 * choices and the binding's own transforms. */
static const char *const no_struct[] = {"integrator.method", /* the type's name, given to cb_integrator_alloc */
                                        "integrator.steps",  /* simulate's step count */
                                        "solver.method",     /* the solver's name, given to cb_integrator_alloc */
                                        "scene.slope", /* turns scene.gravity: checked below as the default gravity */
                                        NULL};

/* config.c's table: its defaults, bound into the core structs, are the C
 * _default()s, key by key. */
Test(params, config_table_defaults_are_the_c_defaults) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_eq(cb_config_validate(&c), CB_OK, "%s", cb_error_message());

  /* the scene */
  cb_scene_def d, e = cb_scene_def_default();
  char path[4 * CB_PATH_LEN];
  cr_assert_eq(cb_scene_def_from_config(&c, &d, path, sizeof path), CB_OK, "%s", cb_error_message());
  static const char *const mesh_kinds[] = {[CB_MESH_GRID] = "grid", [CB_MESH_CHAIN] = "chain", [CB_MESH_OBJ] = "obj"};
  same_str("mesh.type", c.mesh_type, mesh_kinds[e.mesh]);
  cr_expect_eq(d.mesh, e.mesh, "mesh.type: the bound kind is not cb_scene_def_default()'s");
  same_num("mesh.n", d.grid.n, e.grid.n);
  same_num("mesh.m", d.grid.m, e.grid.m);
  same_vec("mesh.size", d.grid.size, e.grid.size, 2);
  same_num("mesh.plane", d.grid.plane, e.grid.plane);
  same_num("mesh.diagonal", d.grid.diagonal, e.grid.diagonal);
  same_str("mesh.file", d.mesh_file, e.mesh_file);
  same_num("material.density", d.density, e.density);
  same_num("material.vertex_mass", d.vertex_mass, e.vertex_mass);
  same_str("material.stretch", d.stretch, e.stretch);
  same_num("material.stretch_k", d.stretch_k, e.stretch_k);
  same_str("material.fem_hessian", d.fem_hessian, e.fem_hessian);
  same_str("material.bend", d.bend, e.bend);
  same_str("material.bend_hessian", d.bend_hessian, e.bend_hessian);
  same_num("material.bend_k", d.bend_k, e.bend_k);
  same_num("material.buckling_kb", d.buckling_kb, e.buckling_kb);
  same_str("integrator.definiteness (the springs' response)", d.definiteness, e.definiteness);
  same_vec("scene.gravity", d.gravity, e.gravity, 3);
  same_str("scene.pins", d.pins, e.pins);
  same_num("scene.initial_scale", d.initial_scale, e.initial_scale);
  same_vec("scene.pin_squeeze", d.pin_squeeze, e.pin_squeeze, 3);
  same_num("integrator.diverge_ratio", d.diverge_ratio, e.diverge_ratio);
  same_str("collider.type", d.collider, e.collider);
  same_vec("collider.centre", d.sphere.centre, e.sphere.centre, 3);
  same_vec("collider.centre (obstacle)", d.obstacle.centre, e.obstacle.centre, 3);
  same_num("collider.radius", d.sphere.radius, e.sphere.radius);
  same_num("collider.thickness", d.sphere.thickness, e.sphere.thickness);
  same_num("collider.stiffness", d.sphere.stiffness, e.sphere.stiffness);
  same_vec("collider.velocity", d.sphere.velocity, e.sphere.velocity, 3);
  same_vec("collider.velocity (obstacle)", d.obstacle.velocity, e.obstacle.velocity, 3);
  same_str("collider.file", d.obstacle.file, e.obstacle.file);
  same_vec("collider.axis", d.obstacle.axis, e.obstacle.axis, 3);
  same_num("collider.angular_speed", d.obstacle.omega, e.obstacle.omega);
  same_str("contact.method", d.contact, e.contact);
  cr_expect_eq(d.nresponses, e.nresponses);

  /* the integrator's generic parameters */
  cb_integrator_params ip, ie = cb_integrator_params_default();
  cr_assert_eq(cb_integrator_params_from_config(&c, &ip), CB_OK, "%s", cb_error_message());
  same_num("integrator.dt", ip.dt, ie.dt);
  same_num("integrator.damping", ip.damping, ie.damping);

  /* the solver */
  cb_solver_params sp = cb_solver_params_from_config(&c), se = cb_solver_params_default();
  same_num("solver.tol", sp.tol, se.tol);
  same_num("solver.max_iters", sp.max_iters, se.max_iters);
  same_num("solver.alpha", sp.alpha, se.alpha);
  same_num("solver.rho", sp.rho, se.rho);
  same_num("solver.ordering", sp.ordering, se.ordering);
  double nr[3] = {sp.nrelax[0], sp.nrelax[1], sp.nrelax[2]}, ne[3] = {se.nrelax[0], se.nrelax[1], se.nrelax[2]};
  same_vec("solver.nrelax", nr, ne, 3);
  same_num("solver.storage", sp.upper, se.upper);
  same_num("solver.denormals", sp.flush_denormals, se.flush_denormals);
  same_str("solver.petsc", sp.petsc_options, se.petsc_options);
  same_num("solver.pc_reuse", sp.pc_reuse, se.pc_reuse);
  same_num("solver.pc_reuse_steps", sp.pc_reuse_steps, se.pc_reuse_steps);
  same_num("solver.rigid_modes", sp.rigid_modes, se.rigid_modes);

  /* every key of the table is accounted for: here, in a plug-in's table, or with no struct */
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len);
  cr_assert_not_null(f);
  cb_config_write(&c, f, "\n");
  fclose(f);
  int nkeys = 0;
  for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n"), nkeys++) {
    char *eq = strchr(line, '=');
    cr_assert_not_null(eq, "cb_config_write: '%s' has no '='", line);
    *eq = '\0';
    const char *key = line, *dot = strchr(key, '.');
    int plugin = 0;
    for (int i = 0; cb_integrator_types[i] && !plugin; i++)
      for (const cb_param_key *k = cb_integrator_types[i]->keys; k && k->name; k++)
        plugin |= !strncmp(key, "integrator.", 11) && !strcmp(dot + 1, k->name);
    for (int i = 0; cb_contact_types[i] && !plugin; i++)
      for (const cb_param_key *k = cb_contact_types[i]->keys; k && k->name; k++)
        plugin |= !strncmp(key, "contact.", 8) && !strcmp(dot + 1, k->name);
    int bare = 0;
    for (int i = 0; no_struct[i]; i++) bare |= !strcmp(key, no_struct[i]);
    cr_expect(plugin || bare || was_checked(key),
              "%s: a key of config.c's table whose default no test compares with a C _default() (add it to "
              "tests/test_params.c)",
              key);
  }
  cr_expect_gt(nkeys, 50);
  free(text);
}

/* `auto` is CB_AUTO wherever a key accepts it: the config stores it so, and
 * it lies outside every such key's range. */
Test(params, auto_is_one_value) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_eq(cb_config_set(&c, "solver.alpha=auto"), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_config_set(&c, "solver.rho=auto"), CB_OK, "%s", cb_error_message());
  cb_solver_params sp = cb_solver_params_from_config(&c);
  cr_expect_eq(sp.alpha, CB_AUTO);
  cr_expect_eq(sp.rho, CB_AUTO);
  int nauto = 0;
  for (int i = 0; cb_integrator_types[i]; i++)
    for (const cb_param_key *k = cb_integrator_types[i]->keys; k && k->name; k++) {
      if (k->kind != CB_PARAM_DOUBLE_AUTO) continue;
      nauto++;
      cr_expect(k->lo > CB_AUTO || (k->lo == CB_AUTO && k->lo_open), "integrator.%s: its range includes CB_AUTO",
                k->name);
      char set[96];
      snprintf(set, sizeof set, "integrator.%s=auto", k->name);
      cr_assert_eq(cb_config_set(&c, set), CB_OK, "%s", cb_error_message());
      double v;
      char key[64];
      snprintf(key, sizeof key, "integrator.%s", k->name);
      cr_assert_eq(cb_config_type_value(&c, key, &v), 0);
      cr_expect_eq(v, CB_AUTO, "%s = auto is stored as %g", key, v);
    }
  cr_expect_gt(nauto, 0);
  /* the C API refuses the old sentinel 0 instead of reading it as auto */
  const char *names[] = {"jacobi", "chebyshev"};
  for (int i = 0; i < 2; i++) {
    cb_solver_params p = cb_solver_params_default();
    p.alpha = 0;
    cb_solver *s = NULL;
    cr_expect_eq(cb_solver_alloc(names[i], &p, 1, &s), CB_EINVAL, "%s accepted alpha = 0", names[i]);
    cb_solver_free(s);
  }
  cb_solver_params p = cb_solver_params_default();
  p.rho = 0;
  cb_solver *s = NULL;
  cr_expect_eq(cb_solver_alloc("chebyshev", &p, 1, &s), CB_EINVAL, "chebyshev accepted rho = 0");
  cb_solver_free(s);
}

/* ---- the cookie ------------------------------------------------------------------ */

/* A struct that skipped its _default() (zeroed, or the garbage of the
 * stack) is refused by its consumer with a message naming the function to
 * start from; the same struct from its _default() is accepted. */
Test(params, a_struct_without_its_defaults_is_refused) {
  unsigned char fills[] = {0x00, 0x5a, 0xff};
  for (size_t f = 0; f < sizeof fills; f++) {
    /* the scene */
    cb_scene_def d;
    memset(&d, fills[f], sizeof d);
    cb_scene *s = NULL;
    cr_expect_eq(cb_scene_build(&d, &s, NULL), CB_EINVAL, "fill %#x: a scene from no defaults was built", fills[f]);
    cr_expect_null(s);
    cr_expect(strstr(cb_error_message(), "cb_scene_def_default()") != NULL, "%s", cb_error_message());
    d = cb_scene_def_default();
    memset(&d.contact_params, fills[f], sizeof d.contact_params);
    cr_expect_eq(cb_scene_build(&d, &s, NULL), CB_EINVAL);
    cr_expect(strstr(cb_error_message(), "cb_contact_params_default()") != NULL, "%s", cb_error_message());
    cb_contact_params cp;
    memset(&cp, fills[f], sizeof cp);
    cr_expect_eq(cb_contact_params_check("penalty", &cp), CB_EINVAL);

    /* the solver */
    cb_solver_params sp;
    memset(&sp, fills[f], sizeof sp);
    cb_solver *sv = NULL;
    cr_expect_eq(cb_solver_alloc("cg", &sp, 3, &sv), CB_EINVAL);
    cr_expect_null(sv);
    cr_expect(strstr(cb_error_message(), "cb_solver_params_default()") != NULL, "%s", cb_error_message());
  }
  /* the same structs from their defaults are accepted */
  cb_scene_def d = cb_scene_def_default();
  d.grid.n = d.grid.m = 4;
  cb_scene *s = NULL;
  cr_assert_eq(cb_scene_build(&d, &s, NULL), CB_OK, "%s", cb_error_message());
  cb_contact_params cp = cb_contact_params_default();
  cr_expect_eq(cb_contact_params_check("penalty", &cp), CB_OK, "%s", cb_error_message());
  cb_solver_params sp = cb_solver_params_default();
  cb_solver *sv = NULL;
  cr_expect_eq(cb_solver_alloc("cg", &sp, 3, &sv), CB_OK, "%s", cb_error_message());
  cb_solver_free(sv);

  /* the integrator: its generic parameters, its type's, and the solver's it is given */
  cb_integrator_params ip = cb_integrator_params_default();
  cb_newton_params np = cb_newton_params_default();
  cb_integrator *it = NULL;
  cr_assert_eq(cb_integrator_alloc("newton", s, &ip, &np, "cholmod", &sp, &it), CB_OK, "%s", cb_error_message());
  cb_integrator_free(it);
  it = NULL;
  cb_integrator_params zip;
  memset(&zip, 0, sizeof zip);
  zip.dt = ip.dt;
  zip.damping = ip.damping; /* every field right but the cookie: still refused */
  cr_expect_eq(cb_integrator_alloc("newton", s, &zip, &np, "cholmod", &sp, &it), CB_EINVAL);
  cr_expect(strstr(cb_error_message(), "cb_integrator_params_default()") != NULL, "%s", cb_error_message());
  cr_expect_null(it);
  cb_newton_params znp;
  memset(&znp, 0, sizeof znp);
  cr_expect_eq(cb_integrator_alloc("newton", s, &ip, &znp, "cholmod", &sp, &it), CB_EINVAL);
  cr_expect(strstr(cb_error_message(), "newton:") != NULL, "%s", cb_error_message());
  cr_expect_null(it);
  cb_solver_params zsp;
  memset(&zsp, 0, sizeof zsp);
  cr_expect_eq(cb_integrator_alloc("newton", s, &ip, &np, "cholmod", &zsp, &it), CB_EINVAL);
  cr_expect_null(it);
  /* a NULL type or solver struct still means the defaults */
  cr_expect_eq(cb_integrator_alloc("newton", s, &ip, NULL, "cholmod", NULL, &it), CB_OK, "%s", cb_error_message());
  cb_integrator_free(it);
  cb_scene_free(s);
}

/* Every registered type's params_default carries the cookie (its first field), so the
 * wrapper accepts a copy of it. */
Test(params, every_types_defaults_carry_the_cookie) {
  for (int i = 0; cb_integrator_types[i]; i++) {
    const cb_integrator_type *t = cb_integrator_types[i];
    if (!t->params_size) continue;
    cr_assert_not_null(t->params_default, "%s", t->name);
    cr_expect_eq(*(const int *)t->params_default, CB_PARAMS_COOKIE, "%s: params_default has no cookie", t->name);
  }
  cr_expect_eq(cb_scene_def_default().cookie, CB_PARAMS_COOKIE);
  cr_expect_eq(cb_contact_params_default().cookie, CB_PARAMS_COOKIE);
  cr_expect_eq(cb_integrator_params_default().cookie, CB_PARAMS_COOKIE);
  cr_expect_eq(cb_solver_params_default().cookie, CB_PARAMS_COOKIE);
  cr_expect_eq(cb_grid_params_default().cookie, CB_PARAMS_COOKIE);
  cr_expect_eq(cb_obstacle_params_default().cookie, CB_PARAMS_COOKIE);
}

/* The mesh and obstacle parameters: a zeroed struct is refused, its default accepted. */
Test(params, grid_and_obstacle_without_their_defaults_are_refused) {
  cb_grid_params g;
  memset(&g, 0, sizeof g);
  g.n = g.m = 3;
  g.size[0] = g.size[1] = 1; /* every field valid but the cookie */
  cb_mesh m;
  cr_expect_eq(cb_mesh_grid(&g, &m), CB_EINVAL);
  cr_expect(strstr(cb_error_message(), "cb_grid_params_default()") != NULL, "%s", cb_error_message());
  g = cb_grid_params_default();
  g.n = g.m = 3;
  cr_assert_eq(cb_mesh_grid(&g, &m), CB_OK, "%s", cb_error_message());
  cb_mesh_free(&m);
  cb_scene_def d = cb_scene_def_default();
  memset(&d.grid, 0, sizeof d.grid);
  cb_scene *s = NULL;
  cr_expect_eq(cb_scene_build(&d, &s, NULL), CB_EINVAL);
  cr_expect_null(s);
  cb_obstacle_params op;
  memset(&op, 0, sizeof op);
  cb_obstacle *o = NULL;
  cr_expect_eq(cb_obstacle_alloc(&op, &o), CB_EINVAL);
  cr_expect_null(o);
  cr_expect(strstr(cb_error_message(), "cb_obstacle_params_default()") != NULL, "%s", cb_error_message());
}
