/* Config (INI + --set), pins, scene contents and lumped masses.
 *
 * Defaults are the documented ones (the key table in lib/config/config.c and the
 * physical model in DESIGN.md). Error messages must read
 * "file:LINE: section.key: reason". Masses are checked against hand counts of
 * the triangles around each grid vertex: m_i = density * (sum of adjacent
 * triangle areas) / 3. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "support.h"

/* ---- helpers ---------------------------------------------------------------- */

static char ini_path[256];

/* Newton's parameters as the binding reads them from c. */
static cb_newton_params newton_of(const cb_config *c) {
  cb_newton_params p;
  cr_assert_eq(cb_newton_params_from_config(c, &p), CB_OK, "%s", cb_error_message());
  return p;
}

static int load_text(const char *text, cb_config *c) {
  snprintf(ini_path, sizeof ini_path, "%s", test_tmpfile(".ini", text));
  cb_error_clear();
  int st = cb_config_load(ini_path, c);
  unlink(ini_path);
  return st;
}

static void load_ok(const char *text, cb_config *c) {
  int st = load_text(text, c);
  cr_assert_eq(st, CB_OK, "cb_config_load: %s\n--- file ---\n%s", cb_error_message(), text);
}

/* Loading must fail with CB_EINVAL and a message that starts with
 * "path:line: key: " (or "path:line: " if key is NULL) and contains what. */
static void expect_load_error(const char *text, int line, const char *key, const char *what) {
  cb_config c;
  int st = load_text(text, &c);
  cr_expect_eq(st, CB_EINVAL, "status %d for\n%s", st, text);
  char prefix[512];
  if (key) snprintf(prefix, sizeof prefix, "%s:%d: %s: ", ini_path, line, key);
  else snprintf(prefix, sizeof prefix, "%s:%d: ", ini_path, line);
  const char *msg = cb_error_message();
  cr_expect(strncmp(msg, prefix, strlen(prefix)) == 0, "message '%s' does not start with '%s'", msg, prefix);
  if (what) cr_expect(strstr(msg, what) != NULL, "message '%s' does not mention '%s'", msg, what);
}

/* cb_config_set must fail and its message must contain each of the strings. */
static void expect_set_error(const char *assignment, const char *what1, const char *what2) {
  cb_config c;
  cb_config_defaults(&c);
  cb_config before = c;
  cb_error_clear();
  int st = cb_config_set(&c, assignment);
  cr_expect_lt(st, 0, "--set %s was accepted", assignment);
  const char *msg = cb_error_message();
  if (what1) cr_expect(strstr(msg, what1) != NULL, "--set %s: message '%s' lacks '%s'", assignment, msg, what1);
  if (what2) cr_expect(strstr(msg, what2) != NULL, "--set %s: message '%s' lacks '%s'", assignment, msg, what2);
  cr_expect(memcmp(&before, &c, sizeof c) == 0, "--set %s: a failed override changed the config", assignment);
}

static cb_scene *scene_of(const char *const *sets) { return test_scene(sets); }

static int term_index(const cb_scene *s, const char *label) {
  for (int k = 0; k < s->sys.nterms; k++)
    if (strcmp(s->sys.terms[k]->label, label) == 0) return k;
  return -1;
}

/* Builds a scene from sets and expects failure whose message contains what. */
static void expect_scene_error(const char *const *sets, const char *what1, const char *what2) {
  cb_config c;
  test_config(&c, sets);
  cb_scene *s = (cb_scene *)1;
  cb_error_clear();
  int st = cb_scene_from_config(&c, &s);
  cr_expect_lt(st, 0, "scene built, expected an error mentioning '%s'", what1);
  cr_expect_null(s, "a failed build must leave *out NULL");
  const char *msg = cb_error_message();
  if (what1) cr_expect(strstr(msg, what1) != NULL, "message '%s' lacks '%s'", msg, what1);
  if (what2) cr_expect(strstr(msg, what2) != NULL, "message '%s' lacks '%s'", msg, what2);
  if (st == CB_OK) cb_scene_free(s);
}

static void expect_pins(const cb_scene *s, const int *want, int n) {
  cr_expect_eq(s->npinned, n, "%d pins, expected %d", s->npinned, n);
  if (s->npinned != n) return; /* (no assert: the caller still frees the scene) */
  for (int k = 0; k < n; k++)
    cr_expect_eq(s->pinned[k], want[k], "pinned[%d] = %d, expected %d", k, s->pinned[k], want[k]);
  /* free_index / free_vertex agree with the pin list */
  int nfree = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    int pinned = 0;
    for (int k = 0; k < n; k++) pinned |= want[k] == i;
    if (pinned) cr_expect_eq(s->free_index[i], -1, "pinned vertex %d has a free index", i);
    else {
      cr_expect_eq(s->free_index[i], nfree, "free_index[%d]", i);
      cr_expect_eq(s->free_vertex[nfree], i);
      nfree++;
    }
  }
  cr_expect_eq(s->model.nfree, s->mesh.nv - n);
  cr_expect_eq(s->model.nfree, nfree);
}

static const double rel = 1e-13;
#define CLOSE(a, b) (fabs((a) - (b)) <= rel * fmax(1.0, fabs(b)))

/* ---- defaults ------------------------------------------------------------------- */

Test(defaults, documented_values) {
  cb_config c;
  memset(&c, 0x5a, sizeof c); /* defaults must set every field */
  cb_config_defaults(&c);
  cr_expect_str_eq(c.mesh_type, "grid");
  cr_expect_eq(c.mesh_n, 21);
  cr_expect_eq(c.mesh_m, 0);
  cr_expect_eq(c.mesh_size[0], 10.0);
  cr_expect_eq(c.mesh_size[1], 10.0);
  cr_expect_str_eq(c.mesh_plane, "xz");
  cr_expect_str_eq(c.mesh_diagonal, "regular");
  cr_expect_str_eq(c.mesh_file, "");
  cr_expect_eq(c.density, 1.0);
  cr_expect_eq(c.vertex_mass, 0.0);
  cr_expect_eq(c.stretch_k, 8000.0);
  cr_expect_str_eq(c.bend, "none");
  cr_expect_eq(c.bend_k, 100.0);
  cr_expect_eq(c.gravity[0], 0.0);
  cr_expect_eq(c.gravity[1], -9.8);
  cr_expect_eq(c.gravity[2], 0.0);
  cr_expect_str_eq(c.pins, "top-corners");
  cr_expect_eq(c.initial_scale, 1.0);
  cr_expect_str_eq(c.method, "newton");
  cr_expect_eq(c.dt, 1.0 / 30.0);
  cr_expect_eq(c.steps, 60);
  cr_expect_eq(newton_of(&c).max_iters, 50);
  cr_expect_eq(newton_of(&c).tol, 1e-8);
  cr_expect_eq(newton_of(&c).tol_dx, 0.0);
  cr_expect_str_eq(cb_config_choice(&c, "integrator.definiteness"), "drop");
  cr_expect_eq(newton_of(&c).definiteness, CB_DEF_DROP);
  cr_expect_str_eq(cb_config_choice(&c, "integrator.init"), "predict");
  cr_expect_eq(newton_of(&c).init_predict, 1);
  cr_expect_eq(newton_of(&c).line_search, 0);
  cr_expect_eq(c.diverge_ratio, 10.0);
  cr_expect_str_eq(c.solver, "cholmod");
  cr_expect_eq(c.solver_tol, 1e-8);
  cr_expect_eq(c.solver_max_iters, 1000);
  cr_expect_eq(c.solver_alpha, CB_AUTO, "alpha = auto is stored as CB_AUTO");
  cr_expect_eq(c.solver_rho, CB_AUTO, "rho = auto is stored as CB_AUTO");
  cr_expect_str_eq(c.solver_ordering, "nesdis");
  cr_expect(c.solver_nrelax[0] == 16 && c.solver_nrelax[1] == 64 && c.solver_nrelax[2] == 128);
  cr_expect_str_eq(c.solver_storage, "upper");
  cr_expect_str_eq(c.solver_denormals, "flush");
  cr_expect_str_eq(c.path, "");
  cr_expect_str_eq(c.overrides, "");
  cr_expect_eq(cb_config_validate(&c), CB_OK, "%s", cb_error_message());
}

Test(defaults, default_scene) {
  cb_scene *s = scene_of(NULL);
  /* 21 x 21 grid, top corners (j = 20, i = 0 and 20) pinned */
  cr_expect_eq(s->mesh.nv, 441);
  cr_expect_eq(s->mesh.nt, 800);
  const int pins[2] = {420, 440};
  expect_pins(s, pins, 2);
  cr_expect_eq(s->sys.nterms, 2);
  cr_expect_geq(term_index(s, "stretch"), 0);
  cr_expect_geq(term_index(s, "gravity"), 0);
  cr_expect_eq(term_index(s, "bend"), -1);
  cb_scene_free(s);
}

Test(defaults, where_without_file) {
  cb_config c;
  cb_config_defaults(&c);
  char buf[256];
  cr_expect_str_eq(cb_config_where(&c, "mesh.n", buf, sizeof buf), "config");
  cr_expect_eq(cb_config_set(&c, "mesh.n=5"), CB_OK);
  cr_expect_str_eq(cb_config_where(&c, "mesh.n", buf, sizeof buf), "--set");
}

/* ---- loading ---------------------------------------------------------------------- */

Test(load, every_key) {
  const char *text = "; every key, none at its default\n" /* 1 */
                     "[mesh]\n"                           /* 2 */
                     "type = grid\n"                      /* 3 */
                     "n = 7\n"                            /* 4 */
                     "m = 5\n"                            /* 5 */
                     "size = 4 2\n"                       /* 6 */
                     "plane = yz\n"                       /* 7 */
                     "diagonal = alternating\n"           /* 8 */
                     "file = some/mesh.obj\n"             /* 9 */
                     "\n"                                 /* 10 */
                     "[material]\n"                       /* 11 */
                     "density = 0.25\n"                   /* 12 */
                     "vertex_mass = 1.5\n"                /* 13 */
                     "stretch_k = 1e5\n"                  /* 14 */
                     "bend = spring\n"                    /* 15 */
                     "bend_k = 12.5\n"                    /* 16 */
                     "[scene]\n"                          /* 17 */
                     "gravity = 0.5, -3, 1\n"             /* 18 */
                     "pins = 1, 2 3\n"                    /* 19 */
                     "initial_scale = 0.75\n"             /* 20 */
                     "[integrator]\n"                     /* 21 */
                     "method = explicit\n"                /* 22 */
                     "dt = 1/240\n"                       /* 23 */
                     "steps = 17\n"                       /* 24 */
                     "max_iters = 3\n"                    /* 25 */
                     "tol = 1e-6\n"                       /* 26 */
                     "tol_dx = 2.5e-4\n"                  /* 27 */
                     "definiteness = none\n"              /* 28 */
                     "init = x0\n"                        /* 29 */
                     "line_search = 1\n"                  /* 30 */
                     "diverge_ratio = 100\n"              /* 31 */
                     "[solver]\n"                         /* 32 */
                     "method = cholmod\n"                 /* 33 */
                     "tol = 1e-10\n"                      /* 34 */
                     "max_iters = 77\n"                   /* 35 */
                     "alpha = 0.5\n"                      /* 36 */
                     "rho = 0.9\n";                       /* 37 */
  cb_config c;
  load_ok(text, &c);
  cr_expect_str_eq(c.mesh_type, "grid");
  cr_expect_eq(c.mesh_n, 7);
  cr_expect_eq(c.mesh_m, 5);
  cr_expect_eq(c.mesh_size[0], 4.0);
  cr_expect_eq(c.mesh_size[1], 2.0);
  cr_expect_str_eq(c.mesh_plane, "yz");
  cr_expect_str_eq(c.mesh_diagonal, "alternating");
  cr_expect_str_eq(c.mesh_file, "some/mesh.obj");
  cr_expect_eq(c.density, 0.25);
  cr_expect_eq(c.vertex_mass, 1.5);
  cr_expect_eq(c.stretch_k, 1e5);
  cr_expect_str_eq(c.bend, "spring");
  cr_expect_eq(c.bend_k, 12.5);
  cr_expect_eq(c.gravity[0], 0.5);
  cr_expect_eq(c.gravity[1], -3.0);
  cr_expect_eq(c.gravity[2], 1.0);
  cr_expect_str_eq(c.pins, "1, 2 3");
  cr_expect_eq(c.initial_scale, 0.75);
  cr_expect_str_eq(c.method, "explicit");
  cr_expect_eq(c.dt, 1.0 / 240.0);
  cr_expect_eq(c.steps, 17);
  cr_expect_eq(newton_of(&c).max_iters, 3);
  cr_expect_eq(newton_of(&c).tol, 1e-6);
  cr_expect_eq(newton_of(&c).tol_dx, 2.5e-4);
  cr_expect_str_eq(cb_config_choice(&c, "integrator.definiteness"), "none");
  cr_expect_eq(newton_of(&c).definiteness, CB_DEF_NONE);
  cr_expect_str_eq(cb_config_choice(&c, "integrator.init"), "x0");
  cr_expect_eq(newton_of(&c).init_predict, 0);
  cr_expect_eq(newton_of(&c).line_search, 1);
  cr_expect_eq(c.diverge_ratio, 100.0);
  cr_expect_str_eq(c.solver, "cholmod");
  cr_expect_eq(c.solver_tol, 1e-10);
  cr_expect_eq(c.solver_max_iters, 77);
  cr_expect_eq(c.solver_alpha, 0.5);
  cr_expect_eq(c.solver_rho, 0.9);
  cr_expect_str_eq(c.path, ini_path);
  /* where each key came from */
  char buf[600], want[600];
  static const struct {
    const char *key;
    int line;
  } where[] = {{"mesh.n", 4},      {"mesh.size", 6},      {"material.bend", 15},
               {"scene.pins", 19}, {"integrator.dt", 23}, {"solver.rho", 37}};
  for (size_t k = 0; k < sizeof where / sizeof where[0]; k++) {
    snprintf(want, sizeof want, "%s:%d", ini_path, where[k].line);
    cr_expect_str_eq(cb_config_where(&c, where[k].key, buf, sizeof buf), want, "where(%s)", where[k].key);
  }
  /* a key the file does not set names the file without a line */
  cb_config d;
  load_ok("[mesh]\nn = 3\n", &d);
  cr_expect_str_eq(cb_config_where(&d, "integrator.dt", buf, sizeof buf), ini_path);
}

Test(load, unset_keys_keep_defaults) {
  cb_config c, def;
  cb_config_defaults(&def);
  load_ok("[integrator]\nsteps = 5\n", &c);
  cr_expect_eq(c.steps, 5);
  cr_expect_eq(c.mesh_n, def.mesh_n);
  cr_expect_eq(c.dt, def.dt);
  cr_expect_str_eq(c.pins, def.pins);
  load_ok("", &c);
  cr_expect_eq(c.steps, 60);
  load_ok("; only comments\n# and more\n\n", &c);
  cr_expect_eq(c.stretch_k, 8000.0);
}

Test(load, fractions) {
  cb_config c;
  load_ok("[integrator]\ndt = 1/30\n", &c);
  cr_expect_eq(c.dt, 1.0 / 30.0);
  load_ok("[integrator]\ndt = 1 / 60\n", &c);
  cr_expect_eq(c.dt, 1.0 / 60.0);
  load_ok("[integrator]\ndt = 0.5/100\n", &c);
  cr_expect_eq(c.dt, 0.5 / 100.0);
  load_ok("[integrator]\ndt = 0.004\n", &c);
  cr_expect_eq(c.dt, 0.004);
  load_ok("[integrator]\ndt = 2e-3\n", &c);
  cr_expect_eq(c.dt, 2e-3);
  load_ok("[material]\nstretch_k = 3/2\n", &c);
  cr_expect_eq(c.stretch_k, 1.5);
}

Test(load, size_one_or_two_numbers) {
  cb_config c;
  load_ok("[mesh]\nsize = 10\n", &c);
  cr_expect(c.mesh_size[0] == 10 && c.mesh_size[1] == 10);
  load_ok("[mesh]\nsize = 4 2\n", &c);
  cr_expect(c.mesh_size[0] == 4 && c.mesh_size[1] == 2);
  load_ok("[mesh]\nsize = 4, 2\n", &c);
  cr_expect(c.mesh_size[0] == 4 && c.mesh_size[1] == 2);
  load_ok("[mesh]\nsize = 0.5\n", &c);
  cr_expect(c.mesh_size[0] == 0.5 && c.mesh_size[1] == 0.5);
}

Test(load, gravity_forms) {
  cb_config c;
  load_ok("[scene]\ngravity = 0, -9.8, 0\n", &c);
  cr_expect(c.gravity[0] == 0 && c.gravity[1] == -9.8 && c.gravity[2] == 0);
  load_ok("[scene]\ngravity = 0 -9.81 0\n", &c);
  cr_expect(c.gravity[0] == 0 && c.gravity[1] == -9.81 && c.gravity[2] == 0);
  load_ok("[scene]\ngravity = 1,2,3\n", &c);
  cr_expect(c.gravity[0] == 1 && c.gravity[1] == 2 && c.gravity[2] == 3);
  load_ok("[scene]\ngravity = 0 0 0\n", &c);
  cr_expect(c.gravity[0] == 0 && c.gravity[1] == 0 && c.gravity[2] == 0);
}

Test(load, rho_auto_and_number) {
  cb_config c;
  load_ok("[solver]\nrho = auto\n", &c);
  cr_expect_eq(c.solver_rho, CB_AUTO);
  load_ok("[solver]\nrho = 0.25\n", &c);
  cr_expect_eq(c.solver_rho, 0.25);
  load_ok("[solver]\nrho = 99/100\n", &c);
  cr_expect_eq(c.solver_rho, 0.99);
}

Test(load, booleans) {
  static const char *const yes[] = {"1", "true", "yes", "on"}, *const no[] = {"0", "false", "no", "off"};
  char text[128];
  cb_config c;
  for (int k = 0; k < 4; k++) {
    snprintf(text, sizeof text, "[integrator]\nline_search = %s\n", yes[k]);
    load_ok(text, &c);
    cr_expect_eq(newton_of(&c).line_search, 1, "'%s'", yes[k]);
  }
  for (int k = 0; k < 4; k++) {
    snprintf(text, sizeof text, "[integrator]\nline_search = %s\n", no[k]);
    load_ok(text, &c);
    cr_expect_eq(newton_of(&c).line_search, 0, "'%s'", no[k]);
  }
}

Test(load, syntax_niceties) {
  cb_config c;
  load_ok("\xEF\xBB\xBF" /* UTF-8 byte-order mark */
          "# hash comment\n"
          "; semicolon comment\n"
          "[mesh]   \n"
          "   n=9\n"
          "size\t=\t3 ; inline comment\n"
          "plane : xy\n"
          "\r\n"
          "[integrator]\r\n"
          "steps = 4\r\n",
          &c);
  cr_expect_eq(c.mesh_n, 9);
  cr_expect(c.mesh_size[0] == 3 && c.mesh_size[1] == 3);
  cr_expect_str_eq(c.mesh_plane, "xy");
  cr_expect_eq(c.steps, 4);
}

Test(load, long_line_under_the_limit) {
  /* a comment of 150 characters is fine */
  char text[512];
  char pad[151];
  memset(pad, 'x', 150);
  pad[150] = '\0';
  snprintf(text, sizeof text, "[mesh]\n;%s\nn = 4\n", pad);
  cb_config c;
  load_ok(text, &c);
  cr_expect_eq(c.mesh_n, 4);
}

/* ---- load errors ----------------------------------------------------------------- */

Test(load_error, unknown_key) {
  expect_load_error("[mesh]\nn = 5\nsides = 4\n", 3, "mesh.sides", "unknown key");
  expect_load_error("; c\n\n[material]\nstretch_k = 1\nstiffness = 4\n", 5, "material.stiffness", "unknown key");
}

/* An unknown section is reported at its header line, even when it is empty. */
Test(load_error, unknown_section) {
  expect_load_error("[mesh]\nn = 5\n[meshes]\nn = 4\n", 3, NULL, "unknown section [meshes]");
  expect_load_error("[Mesh]\nn = 4\n", 1, NULL, "unknown section [Mesh]");
  expect_load_error("[mesh]\nn = 5\n[foo]\n", 3, NULL, "unknown section [foo]");
}

Test(load_error, key_outside_section) { expect_load_error("; top\nn = 4\n[mesh]\n", 2, "n", "outside"); }

Test(load_error, not_a_number) {
  expect_load_error("[material]\nstretch_k = abc\n", 2, "material.stretch_k", "abc");
  expect_load_error("[material]\n\nstretch_k = 12kN\n", 3, "material.stretch_k", "12kN");
  expect_load_error("[integrator]\ndt = 1/0\n", 2, "integrator.dt", NULL);
  expect_load_error("[integrator]\ndt = 1/30/2\n", 2, "integrator.dt", NULL);
  expect_load_error("[integrator]\ndt =\n", 2, "integrator.dt", NULL);
  expect_load_error("[mesh]\nn = 2.5\n", 2, "mesh.n", "integer");
  expect_load_error("[mesh]\nn = five\n", 2, "mesh.n", "integer");
}

Test(load_error, out_of_range) {
  expect_load_error("[mesh]\nn = 1\n", 2, "mesh.n", "out of range");
  expect_load_error("[mesh]\nn = 0\n", 2, "mesh.n", "out of range");
  expect_load_error("[mesh]\nn = -4\n", 2, "mesh.n", "out of range");
  expect_load_error("[integrator]\ndt = 0\n", 2, "integrator.dt", "out of range");
  expect_load_error("[integrator]\n\n\ndt = -1\n", 4, "integrator.dt", "out of range");
  expect_load_error("[integrator]\ndt = nan\n", 2, "integrator.dt", NULL);
  expect_load_error("[integrator]\ndt = inf\n", 2, "integrator.dt", NULL);
  expect_load_error("[integrator]\nmax_iters = 0\n", 2, "integrator.max_iters", "out of range");
  expect_load_error("[integrator]\ntol = 2\n", 2, "integrator.tol", "out of range");
  expect_load_error("[material]\ndensity = 0\n", 2, "material.density", "out of range");
  expect_load_error("[material]\nstretch_k = -1\n", 2, "material.stretch_k", "out of range");
  expect_load_error("[mesh]\nsize = 0\n", 2, "mesh.size", "out of range");
  expect_load_error("[mesh]\nsize = 4 -2\n", 2, "mesh.size", "out of range");
  expect_load_error("[scene]\ninitial_scale = 0\n", 2, "scene.initial_scale", "out of range");
  expect_load_error("[solver]\nalpha = 0\n", 2, "solver.alpha", "out of range");
  expect_load_error("[solver]\nalpha = fast\n", 2, "solver.alpha", "must be `auto` or a number");
  expect_load_error("[solver]\nordering = colamd\n", 2, "solver.ordering", "not one of");
  expect_load_error("[solver]\nstorage = lower\n", 2, "solver.storage", "not one of");
  expect_load_error("[solver]\ndenormals = zero\n", 2, "solver.denormals", "not one of");
  expect_load_error("[solver]\nrho = 1\n", 2, "solver.rho", "auto");
  expect_load_error("[solver]\nrho = 0\n", 2, "solver.rho", "auto");
}

Test(load_error, wrong_count_of_numbers) {
  expect_load_error("[mesh]\nsize = 1 2 3\n", 2, "mesh.size", NULL);
  expect_load_error("[scene]\ngravity = 0 -9.8\n", 2, "scene.gravity", "3 numbers");
  expect_load_error("[scene]\ngravity = 0 -9.8 0 1\n", 2, "scene.gravity", "3 numbers");
  expect_load_error("[scene]\ngravity = 0 down 0\n", 2, "scene.gravity", NULL);
}

Test(load_error, bad_enum_lists_choices) {
  expect_load_error("[mesh]\nplane = xw\n", 2, "mesh.plane", "xy xz yz");
  expect_load_error("[mesh]\ndiagonal = diagonal\n", 2, "mesh.diagonal", "regular alternating");
  expect_load_error("[material]\nbend = hinge\n", 2, "material.bend", "none spring");
  expect_load_error("[integrator]\ninit = zero\n", 2, "integrator.init", "predict x0");
  expect_load_error("[integrator]\ndefiniteness = clamp\n", 2, "integrator.definiteness", "none drop");
  /* registry-backed choices */
  cb_config c;
  int st = load_text("[integrator]\nmethod = rk4\n", &c);
  cr_expect_eq(st, CB_EINVAL);
  const char *msg = cb_error_message();
  cr_expect(strstr(msg, "integrator.method") && strstr(msg, "rk4"), "%s", msg);
  for (int i = 0; cb_integrator_name(i); i++)
    cr_expect(strstr(msg, cb_integrator_name(i)) != NULL, "'%s' does not list %s", msg, cb_integrator_name(i));
  cr_expect(strstr(msg, "explicit") && strstr(msg, "newton"), "%s", msg);
  st = load_text("[solver]\nmethod = lu\n", &c);
  cr_expect_eq(st, CB_EINVAL);
  msg = cb_error_message();
  for (int i = 0; cb_solver_name(i); i++)
    cr_expect(strstr(msg, cb_solver_name(i)) != NULL, "'%s' does not list %s", msg, cb_solver_name(i));
  cr_expect(strstr(msg, "cholmod") != NULL, "%s", msg);
}

Test(load_error, bad_boolean) {
  expect_load_error("[integrator]\nline_search = 2\n", 2, "integrator.line_search", "boolean");
  expect_load_error("[integrator]\nline_search = maybe\n", 2, "integrator.line_search", "boolean");
}

Test(load_error, duplicate_key) {
  expect_load_error("[mesh]\nn = 5\nsize = 3\nn = 6\n", 4, "mesh.n", "first at line 2");
  /* the same key in a repeated section is still a duplicate */
  expect_load_error("[mesh]\nn = 5\n[scene]\npins = none\n[mesh]\nn = 5\n", 6, "mesh.n", "first at line 2");
  /* an indented line continues the previous key (inih multi-line) */
  expect_load_error("[mesh]\nn = 5\n   6\n", 3, "mesh.n", NULL);
}

Test(load, long_lines_load) {
  /* inih's default 200-byte line made a scene.pins list of more than ~40
   * indices impossible ("line longer than 198 characters") */
  static char text[40000];
  size_t used = (size_t)snprintf(text, sizeof text, "[scene]\n; fine\npins =");
  for (int i = 0; i < 3000; i++) used += (size_t)snprintf(text + used, sizeof text - used, " %d", i);
  snprintf(text + used, sizeof text - used, "\ninitial_scale = 0.5\n;%0300d\n", 0);
  cb_config c;
  load_ok(text, &c);
  cr_expect_eq(strlen(c.pins), strlen(strstr(text, "pins = ") + 7) - strlen(strchr(strstr(text, "pins = "), '\n')));
  cr_expect(strncmp(c.pins, "0 1 2 3", 7) == 0 && strstr(c.pins, " 2999") != NULL, "pins '%.40s...'", c.pins);
  cr_expect_eq(c.initial_scale, 0.5);
}

Test(load_error, syntax_error) {
  expect_load_error("[mesh]\nn = 5\nthis line has no equals sign\n", 3, NULL, "syntax");
  expect_load_error("[mesh]\nn = 5\n[integrator\n", 3, NULL, "syntax");
}

Test(load_error, first_error_is_reported) {
  /* a syntax error must not be hidden by a later key error: the unclosed
   * "[mesh" on line 1 is the mistake, not "n" on line 2 */
  expect_load_error("[mesh\nn = 5\n", 1, NULL, "syntax");
  expect_load_error("[mesh]\nn = 5\nbad line\n[integrator]\ndt = 0\n", 3, NULL, "syntax");
}

Test(load_error, missing_file) {
  cb_config c;
  const char *path = "/nonexistent-clothbench/none.ini";
  cb_error_clear();
  int st = cb_config_load(path, &c);
  cr_expect_lt(st, 0);
  cr_expect(strstr(cb_error_message(), path) != NULL, "message '%s'", cb_error_message());
}

Test(load_error, first_key_error_wins) {
  expect_load_error("[mesh]\nn = 1\n[integrator]\ndt = 0\n", 2, "mesh.n", NULL);
}

/* ---- --set --------------------------------------------------------------------- */

Test(set, overrides) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_eq(cb_config_set(&c, "mesh.n=7"), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_config_set(&c, "integrator.dt =  1/60 "), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_config_set(&c, "scene.gravity=0,0,-1"), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_config_set(&c, "scene.pins=0 3, 5"), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_config_set(&c, "mesh.size=3 1"), CB_OK);
  cr_assert_eq(cb_config_set(&c, "solver.rho=auto"), CB_OK);
  cr_assert_eq(cb_config_set(&c, "integrator.line_search=yes"), CB_OK);
  cr_expect_eq(c.mesh_n, 7);
  cr_expect_eq(c.dt, 1.0 / 60.0);
  cr_expect(c.gravity[0] == 0 && c.gravity[1] == 0 && c.gravity[2] == -1);
  cr_expect_str_eq(c.pins, "0 3, 5");
  cr_expect(c.mesh_size[0] == 3 && c.mesh_size[1] == 1);
  cr_expect_eq(newton_of(&c).line_search, 1);
  cr_expect(strstr(c.overrides, "mesh.n=7") != NULL, "overrides '%s'", c.overrides);
  cr_expect(strstr(c.overrides, "integrator.dt=1/60") != NULL, "overrides '%s'", c.overrides);
  /* the last --set wins */
  cr_assert_eq(cb_config_set(&c, "mesh.n=9"), CB_OK);
  cr_expect_eq(c.mesh_n, 9);
}

Test(set, whitespace_around_key_is_trimmed) {
  /* config.c trims "spaces around key and value" */
  cb_config c;
  cb_config_defaults(&c);
  cr_expect_eq(cb_config_set(&c, "  integrator.dt = 1/60"), CB_OK, "%s", cb_error_message());
  cr_expect_eq(c.dt, 1.0 / 60.0);
  cr_expect_eq(cb_config_set(&c, "\tmesh.n\t=\t5\t"), CB_OK, "%s", cb_error_message());
  cr_expect_eq(c.mesh_n, 5);
}

Test(set, after_load_overrides_file) {
  cb_config c;
  load_ok("[mesh]\nn = 5\n[integrator]\ndt = 1/30\n", &c);
  cr_assert_eq(cb_config_set(&c, "mesh.n=11"), CB_OK);
  cr_expect_eq(c.mesh_n, 11);
  cr_expect_eq(c.dt, 1.0 / 30.0);
  char buf[600], want[600];
  cr_expect_str_eq(cb_config_where(&c, "mesh.n", buf, sizeof buf), "--set");
  snprintf(want, sizeof want, "%s:4", ini_path);
  cr_expect_str_eq(cb_config_where(&c, "integrator.dt", buf, sizeof buf), want);
}

Test(set, errors) {
  expect_set_error("mesh.n", "mesh.n", NULL);                 /* no '=' */
  expect_set_error("material.nope=1", "material.nope", NULL); /* unknown key */
  expect_set_error("nope=1", "nope", NULL);
  expect_set_error("=5", NULL, NULL);
  expect_set_error("mesh.n=1", "mesh.n", "out of range");
  expect_set_error("mesh.n=", "mesh.n", NULL);
  expect_set_error("integrator.dt=0", "integrator.dt", "out of range");
  expect_set_error("integrator.dt=-1", "integrator.dt", "out of range");
  expect_set_error("integrator.dt=fast", "integrator.dt", "fast");
  expect_set_error("mesh.plane=xw", "mesh.plane", "xy xz yz");
  expect_set_error("scene.gravity=0 -9.8", "scene.gravity", NULL);
  expect_set_error("mesh.size=1 2 3", "mesh.size", NULL);
  expect_set_error("integrator.line_search=2", "integrator.line_search", NULL);
  expect_set_error("solver.rho=1.5", "solver.rho", NULL);
}

Test(set, write_then_set_round_trip) {
  /* every "key=value" written by cb_config_write is accepted by
   * cb_config_set and gives back the same values */
  cb_config a;
  load_ok("[mesh]\nn = 7\nsize = 4 2\nplane = yz\n[material]\nbend = spring\nvertex_mass = 0.1\n"
          "[scene]\ngravity = 0.1 -3 0\npins = 1, 5\n[integrator]\ndt = 1/240\nline_search = on\n"
          "[solver]\nrho = 0.3\n",
          &a);
  char *t1 = NULL, *t2 = NULL;
  size_t n1 = 0, n2 = 0;
  FILE *f = open_memstream(&t1, &n1);
  cb_config_write(&a, f, "\n");
  fclose(f);
  cb_config b;
  cb_config_defaults(&b);
  char *save = NULL;
  char *copy = strdup(t1);
  int count = 0;
  for (char *line = strtok_r(copy, "\n", &save); line; line = strtok_r(NULL, "\n", &save), count++)
    cr_expect_eq(cb_config_set(&b, line), CB_OK, "'%s': %s", line, cb_error_message());
  free(copy);
  cr_expect_geq(count, 30, "only %d keys written", count);
  f = open_memstream(&t2, &n2);
  cb_config_write(&b, f, "\n");
  fclose(f);
  cr_expect_str_eq(t2, t1);
  cr_expect_eq(b.dt, 1.0 / 240.0);
  cr_expect_eq(b.gravity[0], 0.1);
  cr_expect_str_eq(b.pins, "1, 5");
  cr_expect_eq(b.solver_rho, 0.3);
  free(t1);
  free(t2);
}

Test(set, reference_lists_every_key) {
  char *t = NULL;
  size_t n = 0;
  FILE *f = open_memstream(&t, &n);
  cb_config_write_reference(f);
  fclose(f);
  static const char *const keys[] = {"mesh.type",
                                     "mesh.n",
                                     "mesh.m",
                                     "mesh.size",
                                     "mesh.plane",
                                     "mesh.diagonal",
                                     "mesh.file",
                                     "material.density",
                                     "material.vertex_mass",
                                     "material.stretch_k",
                                     "material.bend",
                                     "material.bend_k",
                                     "scene.gravity",
                                     "scene.pins",
                                     "scene.initial_scale",
                                     "integrator.method",
                                     "integrator.dt",
                                     "integrator.steps",
                                     "integrator.max_iters",
                                     "integrator.tol",
                                     "integrator.tol_dx",
                                     "integrator.definiteness",
                                     "integrator.init",
                                     "integrator.line_search",
                                     "integrator.diverge_ratio",
                                     "solver.method",
                                     "solver.tol",
                                     "solver.max_iters",
                                     "solver.alpha",
                                     "solver.rho",
                                     "solver.ordering",
                                     "solver.nrelax",
                                     "solver.storage",
                                     "solver.denormals"};
  for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++) {
    char cell[64];
    snprintf(cell, sizeof cell, "| `%s` |", keys[k]);
    cr_expect(strstr(t, cell) != NULL, "reference lacks %s", keys[k]);
  }
  free(t);
}

Test(validate, obj_needs_file) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_eq(cb_config_set(&c, "mesh.type=obj"), CB_OK);
  cr_expect_eq(cb_config_validate(&c), CB_EINVAL);
  cr_expect(strstr(cb_error_message(), "mesh.file") != NULL, "%s", cb_error_message());
  cb_scene *s = NULL;
  cr_expect_eq(cb_scene_from_config(&c, &s), CB_EINVAL);
  cr_expect_null(s);
}

/* ---- pins ---------------------------------------------------------------------- */

Test(pins, named_sets) {
  /* 4 x 3 grid: rows j = 0 {0..3}, 1 {4..7}, 2 {8..11}; top edge is j = 2 */
  {
    const char *const sets[] = {"mesh.n=4", "mesh.m=3", "scene.pins=corners", NULL};
    cb_scene *s = scene_of(sets);
    const int want[4] = {0, 3, 8, 11};
    expect_pins(s, want, 4);
    cb_scene_free(s);
  }
  {
    const char *const sets[] = {"mesh.n=4", "mesh.m=3", "scene.pins=top-corners", NULL};
    cb_scene *s = scene_of(sets);
    const int want[2] = {8, 11};
    expect_pins(s, want, 2);
    cb_scene_free(s);
  }
  {
    const char *const sets[] = {"mesh.n=4", "mesh.m=3", "scene.pins=top-edge", NULL};
    cb_scene *s = scene_of(sets);
    const int want[4] = {8, 9, 10, 11};
    expect_pins(s, want, 4);
    cb_scene_free(s);
  }
  {
    const char *const sets[] = {"mesh.n=4", "mesh.m=3", "scene.pins=none", NULL};
    cb_scene *s = scene_of(sets);
    expect_pins(s, NULL, 0);
    cb_scene_free(s);
  }
  {
    /* m = 0 means m = n: 3 x 3, corners 0 2 6 8 */
    const char *const sets[] = {"mesh.n=3", "scene.pins=corners", NULL};
    cb_scene *s = scene_of(sets);
    const int want[4] = {0, 2, 6, 8};
    cr_expect_eq(s->mesh.nv, 9);
    expect_pins(s, want, 4);
    cb_scene_free(s);
  }
}

Test(pins, top_is_the_top_in_every_plane) {
  /* the top edge has the largest second coordinate */
  const char *const sets_xy[] = {"mesh.n=3", "mesh.m=4", "mesh.plane=xy", "scene.pins=top-edge", NULL};
  cb_scene *s = scene_of(sets_xy);
  for (int k = 0; k < s->npinned; k++)
    cr_expect(CLOSE(s->mesh.x[3 * s->pinned[k] + 1], 5.0), "y = %g", s->mesh.x[3 * s->pinned[k] + 1]);
  cb_scene_free(s);
  const char *const sets_yz[] = {"mesh.n=3", "mesh.m=4", "mesh.plane=yz", "scene.pins=top-edge", NULL};
  s = scene_of(sets_yz);
  for (int k = 0; k < s->npinned; k++) cr_expect(CLOSE(s->mesh.x[3 * s->pinned[k] + 2], 5.0));
  cb_scene_free(s);
}

Test(pins, index_lists) {
  const char *const sets[] = {"mesh.n=4", "mesh.m=3", "scene.pins= 7, 1 3,,3  1 ,0", NULL};
  cb_scene *s = scene_of(sets);
  const int want[4] = {0, 1, 3, 7};
  expect_pins(s, want, 4);
  cb_scene_free(s);
  const char *const sets2[] = {"mesh.n=4", "mesh.m=3", "scene.pins=11", NULL};
  s = scene_of(sets2);
  const int want2[1] = {11};
  expect_pins(s, want2, 1);
  cb_scene_free(s);
  const char *const sets3[] = {"mesh.n=4", "mesh.m=3", "scene.pins=2\t5", NULL};
  s = scene_of(sets3);
  const int want3[2] = {2, 5};
  expect_pins(s, want3, 2);
  cb_scene_free(s);
}

Test(pins, many_duplicates) {
  /* a list longer than the vertex count, made of repeats, still pins the
   * vertices it names: 20 times vertex 0, then vertex 3 (2 x 2 grid) */
  const char *const sets[] = {"mesh.n=2", "scene.pins=0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 3", NULL};
  cb_scene *s = scene_of(sets);
  const int want[2] = {0, 3};
  expect_pins(s, want, 2);
  cb_scene_free(s);
}

Test(pins, resolve_directly) {
  cb_grid_params p = cb_grid_params_default();
  p.n = 5;
  p.m = 2;
  cb_mesh g;
  cr_assert_eq(cb_mesh_grid(&p, &g), CB_OK);
  int *list = NULL, n = -1;
  cr_assert_eq(cb_pins_resolve("corners", &g, &list, &n), CB_OK);
  cr_expect_eq(n, 4);
  cr_expect(list[0] == 0 && list[1] == 4 && list[2] == 5 && list[3] == 9);
  free(list);
  cr_assert_eq(cb_pins_resolve("top-edge", &g, &list, &n), CB_OK);
  cr_expect_eq(n, 5);
  for (int k = 0; k < 5; k++) cr_expect_eq(list[k], 5 + k);
  free(list);
  cr_expect_lt(cb_pins_resolve("10", &g, &list, &n), 0);
  cr_expect(strstr(cb_error_message(), "scene.pins") != NULL);
  cb_mesh_free(&g);
}

/* `halfspace a b c d` pins the rest positions with a.p <= d, the plane included,
 * on grids and OBJ meshes alike; its numbers may be separated by commas. */
Test(pins, halfspace) {
  cb_grid_params p = cb_grid_params_default();
  p.n = p.m = 5; /* plane xz, 10 m: vertex (i, j) = j 5 + i at x = 10 (i/4 - 1/2), z = 10 (j/4 - 1/2) */
  cb_mesh g;
  cr_assert_eq(cb_mesh_grid(&p, &g), CB_OK);
  int *list = NULL, n = -1;
  cr_assert_eq(cb_pins_resolve("halfspace 1 0 0 0", &g, &list, &n), CB_OK, "%s", cb_error_message());
  cr_expect_eq(n, 15); /* columns i <= 2 */
  for (int k = 0; k < n; k++) cr_expect_leq(list[k] % 5, 2);
  free(list);
  cr_assert_eq(cb_pins_resolve("halfspace,1,0,-1,0", &g, &list, &n), CB_OK, "%s", cb_error_message());
  cr_expect_eq(n, 15); /* i <= j: the diagonal and above */
  for (int k = 0; k < n; k++) cr_expect_leq(list[k] % 5, list[k] / 5);
  free(list);
  cr_assert_eq(cb_pins_resolve("halfspace 0 0 -2 -5", &g, &list, &n), CB_OK); /* z >= 2.5: the rows j >= 3 */
  cr_expect_eq(n, 10);
  cr_expect_eq(list[0], 15);
  free(list);
  cr_assert_eq(cb_pins_resolve("halfspace 1 0 0 -90", &g, &list, &n), CB_OK); /* nothing */
  cr_expect_eq(n, 0);
  free(list);
  static const char *const bad[] = {
      "halfspace",         "halfspace 1 0 0",     "halfspace 1 0 0 0 5",        "halfspace 0 0 0 1",
      "halfspace 1 0 x 0", "halfspace 1 0 0 inf", "halfspace 1e300 1e300 0 0 x"};
  for (int k = 0; k < 7; k++) {
    cr_expect_lt(cb_pins_resolve(bad[k], &g, &list, &n), 0, "'%s' was accepted", bad[k]);
    cr_expect(strstr(cb_error_message(), "halfspace a b c d") != NULL, "'%s': %s", bad[k], cb_error_message());
  }
  cr_expect_lt(cb_pins_resolve("halfspaces 1 0 0 0", &g, &list, &n), 0);
  cb_mesh_free(&g);
  const char *const sets[] = {"mesh.n=3", "scene.pins=halfspace 0 0 1 0", NULL}; /* z <= 0: the rows j <= 1 */
  cb_scene *s = scene_of(sets);
  const int want[6] = {0, 1, 2, 3, 4, 5};
  expect_pins(s, want, 6);
  cb_scene_free(s);
}

Test(pins, errors_name_scene_pins) {
  const char *const range[] = {"mesh.n=4", "mesh.m=3", "scene.pins=0 12", NULL};
  expect_scene_error(range, "scene.pins", "12");
  const char *const big[] = {"mesh.n=4", "mesh.m=3", "scene.pins=99999999999999999999999", NULL};
  expect_scene_error(big, "scene.pins", NULL);
  const char *const neg[] = {"mesh.n=4", "mesh.m=3", "scene.pins=-1", NULL};
  expect_scene_error(neg, "scene.pins", NULL);
  const char *const word[] = {"mesh.n=4", "mesh.m=3", "scene.pins=bottom-edge", NULL};
  expect_scene_error(word, "scene.pins", "bottom-edge");
  const char *const frac[] = {"mesh.n=4", "mesh.m=3", "scene.pins=1.5", NULL};
  expect_scene_error(frac, "scene.pins", NULL);
  const char *const junk[] = {"mesh.n=4", "mesh.m=3", "scene.pins=1 2x", NULL};
  expect_scene_error(junk, "scene.pins", NULL);
}

Test(pins, error_names_file_and_line) {
  cb_config c;
  load_ok("[mesh]\nn = 3\n\n[scene]\npins = 0 9\n", &c);
  cb_scene *s = NULL;
  cr_expect_eq(cb_scene_from_config(&c, &s), CB_EINVAL);
  char want[600];
  snprintf(want, sizeof want, "%s:5: scene.pins", ini_path);
  cr_expect(strstr(cb_error_message(), want) != NULL, "message '%s' lacks '%s'", cb_error_message(), want);
}

/* ---- OBJ meshes in scenes ------------------------------------------------------ */

static char dir[256];

static void make_dir(void) {
  snprintf(dir, sizeof dir, "/tmp/cbtest_cfgdir_XXXXXX");
  cr_assert(mkdtemp(dir) != NULL);
}

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  cr_assert(f, "cannot write %s", path);
  fputs(text, f);
  fclose(f);
}

#define UNIT_SQUARE_OBJ "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"

Test(obj_scene, relative_file_from_config_folder) {
  make_dir();
  char sub[512], meshes[600], obj[700], ini[700];
  snprintf(sub, sizeof sub, "%s/configs", dir);
  snprintf(meshes, sizeof meshes, "%s/meshes", sub);
  cr_assert(mkdir(sub, 0777) == 0 && mkdir(meshes, 0777) == 0);
  snprintf(obj, sizeof obj, "%s/square.obj", meshes);
  snprintf(ini, sizeof ini, "%s/scene.ini", sub);
  write_file(obj, UNIT_SQUARE_OBJ);
  write_file(ini, "[mesh]\ntype = obj\nfile = meshes/square.obj\n[material]\ndensity = 3\n[scene]\npins = 0\n");
  cb_config c;
  cr_assert_eq(cb_config_load(ini, &c), CB_OK, "%s", cb_error_message());
  cb_scene *s = NULL;
  cr_assert_eq(cb_scene_from_config(&c, &s), CB_OK, "%s", cb_error_message());
  cr_expect_eq(s->mesh.nv, 4);
  cr_expect_eq(s->mesh.nt, 2);
  /* fan (0,1,2), (0,2,3), areas 1/2 each, density 3:
   * m = 3 * (1/2 + 1/2)/3 = 1 for vertices 0 and 2, 3 * (1/2)/3 = 1/2 for 1 and 3 */
  cr_expect(CLOSE(s->mass[0], 1.0) && CLOSE(s->mass[2], 1.0), "%g %g", s->mass[0], s->mass[2]);
  cr_expect(CLOSE(s->mass[1], 0.5) && CLOSE(s->mass[3], 0.5), "%g %g", s->mass[1], s->mass[3]);
  const int want[1] = {0};
  expect_pins(s, want, 1);
  cb_scene_free(s);
  unlink(obj);
  unlink(ini);
  rmdir(meshes);
  rmdir(sub);
  rmdir(dir);
}

Test(obj_scene, absolute_file) {
  make_dir();
  char obj[600];
  snprintf(obj, sizeof obj, "%s/square.obj", dir);
  write_file(obj, UNIT_SQUARE_OBJ);
  char set[700];
  snprintf(set, sizeof set, "mesh.file=%s", obj);
  const char *const sets[] = {"mesh.type=obj", set, "scene.pins=none", NULL};
  cb_scene *s = scene_of(sets);
  cr_expect_eq(s->mesh.nv, 4);
  cr_expect_eq(s->npinned, 0);
  cb_scene_free(s);
  unlink(obj);
  rmdir(dir);
}

Test(obj_scene, named_pins_need_a_grid) {
  make_dir();
  char obj[600];
  snprintf(obj, sizeof obj, "%s/square.obj", dir);
  write_file(obj, UNIT_SQUARE_OBJ);
  char set[700];
  snprintf(set, sizeof set, "mesh.file=%s", obj);
  static const char *const named[] = {"scene.pins=corners", "scene.pins=top-corners", "scene.pins=top-edge"};
  for (int k = 0; k < 3; k++) {
    const char *const sets[] = {"mesh.type=obj", set, named[k], NULL};
    expect_scene_error(sets, "scene.pins", "grid");
  }
  /* the default pins (top-corners) are an error on an OBJ mesh as well */
  const char *const dflt[] = {"mesh.type=obj", set, NULL};
  expect_scene_error(dflt, "scene.pins", NULL);
  const char *const list[] = {"mesh.type=obj", set, "scene.pins=1,2", NULL};
  cb_scene *s = scene_of(list);
  const int want[2] = {1, 2};
  expect_pins(s, want, 2);
  cb_scene_free(s);
  const char *const half[] = {"mesh.type=obj", set, "scene.pins=halfspace 0 1 0 0", NULL}; /* y <= 0: vertices 0, 1 */
  s = scene_of(half);
  const int want_half[2] = {0, 1};
  expect_pins(s, want_half, 2);
  cb_scene_free(s);
  unlink(obj);
  rmdir(dir);
}

Test(obj_scene, bad_obj_names_obj_line_and_key) {
  make_dir();
  char obj[600], ini[600];
  snprintf(obj, sizeof obj, "%s/bad.obj", dir);
  snprintf(ini, sizeof ini, "%s/scene.ini", dir);
  write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  write_file(ini, "[mesh]\ntype = obj\nfile = bad.obj\n[scene]\npins = none\n");
  cb_config c;
  cr_assert_eq(cb_config_load(ini, &c), CB_OK, "%s", cb_error_message());
  cb_scene *s = NULL;
  cr_expect_eq(cb_scene_from_config(&c, &s), CB_EINVAL);
  char want[700];
  snprintf(want, sizeof want, "%s:4", obj);
  cr_expect(strstr(cb_error_message(), want) != NULL, "message '%s' lacks '%s'", cb_error_message(), want);
  cr_expect(strstr(cb_error_message(), "mesh.file") != NULL, "%s", cb_error_message());
  /* a missing OBJ is an I/O error */
  write_file(ini, "[mesh]\ntype = obj\nfile = missing.obj\n[scene]\npins = none\n");
  cr_assert_eq(cb_config_load(ini, &c), CB_OK);
  cr_expect_eq(cb_scene_from_config(&c, &s), CB_EIO);
  cr_expect(strstr(cb_error_message(), "missing.obj") != NULL, "%s", cb_error_message());
  unlink(obj);
  unlink(ini);
  rmdir(dir);
}

/* ---- scene contents ---------------------------------------------------------- */

Test(scene_terms, follow_the_config) {
  struct {
    const char *bend, *gravity;
    int nterms;
    int has_bend, has_gravity;
  } cases[] = {
      {"material.bend=none", "scene.gravity=0 -9.8 0", 2, 0, 1},
      {"material.bend=spring", "scene.gravity=0 -9.8 0", 3, 1, 1},
      {"material.bend=none", "scene.gravity=0 0 0", 1, 0, 0},
      {"material.bend=spring", "scene.gravity=0,0,0", 2, 1, 0},
      {"material.bend=none", "scene.gravity=1 0 0", 2, 0, 1},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    const char *const sets[] = {"mesh.n=5", cases[k].bend, cases[k].gravity, NULL};
    cb_scene *s = scene_of(sets);
    cr_expect_eq(s->sys.nterms, cases[k].nterms, "case %zu: %d terms", k, s->sys.nterms);
    cr_expect_geq(term_index(s, "stretch"), 0, "case %zu: no stretch term", k);
    cr_expect_eq(term_index(s, "bend") >= 0, cases[k].has_bend, "case %zu: bend term", k);
    cr_expect_eq(term_index(s, "gravity") >= 0, cases[k].has_gravity, "case %zu: gravity term", k);
    for (int a = 0; a < 3; a++) cr_expect_eq(s->gravity[a], s->def.gravity[a]);
    cb_scene_free(s);
  }
}

Test(scene_terms, topology_of_the_grid) {
  const char *const sets[] = {"mesh.n=5", "mesh.m=4", NULL};
  cb_scene *s = scene_of(sets);
  /* 4*4 + 5*3 + 4*3 = 43 edges, 2*4 + 2*3 = 14 on the boundary */
  cr_expect_eq(s->topo.ne, 43);
  cr_expect_eq(s->topo.nb, 14);
  cr_expect_eq(s->topo.np, 29);
  cb_scene_free(s);
}

Test(scene_terms, initial_state) {
  /* x0 = centroid + s (x - centroid); the grid is centred, so x0 = s x; v0 = 0 */
  const char *const sets[] = {"mesh.n=4", "mesh.m=3", "mesh.plane=xy", "scene.initial_scale=0.5", NULL};
  cb_scene *s = scene_of(sets);
  for (int i = 0; i < 3 * s->mesh.nv; i++) {
    cr_expect(fabs(s->x0[i] - 0.5 * s->mesh.x[i]) < 1e-12, "x0[%d] = %g", i, s->x0[i]);
    cr_expect_eq(s->v0[i], 0.0);
  }
  cb_scene_free(s);
}

/* ---- lumped masses --------------------------------------------------------------- */

/* Triangles around vertex (i, j) of an n x m grid with regular diagonals
 * (v00-v11 in every cell): a cell contributes 2 triangles to its v00 and v11
 * corners and 1 to v10 and v01. */
static int regular_count(int i, int j, int n, int m) {
  int c = 0;
  if (i < n - 1 && j < m - 1) c += 2; /* (i,j) is v00 of cell (i,j) */
  if (i > 0 && j < m - 1) c += 1;     /* v10 of cell (i-1,j) */
  if (i < n - 1 && j > 0) c += 1;     /* v01 of cell (i,j-1) */
  if (i > 0 && j > 0) c += 2;         /* v11 of cell (i-1,j-1) */
  return c;
}

Test(mass, regular_grid_by_hand) {
  /* 5 x 4 vertices on 4 m x 3 m: 1 m cells, triangles of 1/2 m^2, density 2:
   * m_i = 2 * (1/2) * count / 3 = count / 3 */
  const char *const sets[] = {"mesh.n=5", "mesh.m=4", "mesh.size=4 3", "material.density=2", NULL};
  cb_scene *s = scene_of(sets);
  /* the corner and edge values, spelled out */
  cr_expect(CLOSE(s->mass[0], 2.0 / 3), "corner (0,0): %g", s->mass[0]);   /* 2 triangles */
  cr_expect(CLOSE(s->mass[4], 1.0 / 3), "corner (4,0): %g", s->mass[4]);   /* 1 triangle */
  cr_expect(CLOSE(s->mass[15], 1.0 / 3), "corner (0,3): %g", s->mass[15]); /* 1 triangle */
  cr_expect(CLOSE(s->mass[19], 2.0 / 3), "corner (4,3): %g", s->mass[19]); /* 2 triangles */
  cr_expect(CLOSE(s->mass[2], 1.0), "bottom edge: %g", s->mass[2]);        /* 3 triangles */
  cr_expect(CLOSE(s->mass[17], 1.0), "top edge: %g", s->mass[17]);
  cr_expect(CLOSE(s->mass[5], 1.0), "left edge: %g", s->mass[5]);
  cr_expect(CLOSE(s->mass[9], 1.0), "right edge: %g", s->mass[9]);
  cr_expect(CLOSE(s->mass[6], 2.0), "interior: %g", s->mass[6]); /* 6 triangles */
  double total = 0;
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 5; i++) {
      double want = regular_count(i, j, 5, 4) / 3.0;
      cr_expect(CLOSE(s->mass[j * 5 + i], want), "(%d,%d): %g, expected %g", i, j, s->mass[j * 5 + i], want);
      total += s->mass[j * 5 + i];
    }
  cr_expect(CLOSE(total, 2.0 * 12.0), "total %g, expected density * area = 24", total);
  cb_scene_free(s);
}

Test(mass, alternating_3x3) {
  /* 3 x 3 vertices on 2 m x 2 m, density 1.5, triangles of 1/2 m^2:
   * a checkerboard whose cell (0,0) is split along v00-v11 gives the
   * "union jack": corners 2 triangles, edge midpoints 2, centre 8; the other
   * parity gives corners 1, midpoints 4, centre 4. m = 1.5 * 0.5 * count / 3. */
  const char *const sets[] = {"mesh.n=3", "mesh.size=2", "mesh.diagonal=alternating", "material.density=1.5", NULL};
  cb_scene *s = scene_of(sets);
  const double u = 1.5 * 0.5 / 3;
  int corners[4] = {0, 2, 6, 8}, mids[4] = {1, 3, 5, 7};
  int jack = CLOSE(s->mass[4], 8 * u);
  int other = CLOSE(s->mass[4], 4 * u);
  cr_expect(jack || other, "centre mass %g is neither %g nor %g", s->mass[4], 8 * u, 4 * u);
  for (int k = 0; k < 4; k++) {
    cr_expect(CLOSE(s->mass[corners[k]], (jack ? 2 : 1) * u), "corner %d: %g", corners[k], s->mass[corners[k]]);
    cr_expect(CLOSE(s->mass[mids[k]], (jack ? 2 : 4) * u), "midpoint %d: %g", mids[k], s->mass[mids[k]]);
  }
  double total = 0;
  for (int i = 0; i < 9; i++) total += s->mass[i];
  cr_expect(CLOSE(total, 1.5 * 4.0), "total %g", total);
  cb_scene_free(s);
}

Test(mass, total_is_density_times_area) {
  static const char *const diags[] = {"mesh.diagonal=regular", "mesh.diagonal=alternating"};
  static const char *const planes[] = {"mesh.plane=xy", "mesh.plane=xz", "mesh.plane=yz"};
  for (int d = 0; d < 2; d++)
    for (int p = 0; p < 3; p++) {
      const char *const sets[] = {"mesh.n=7", "mesh.m=4", "mesh.size=3 0.75", "material.density=0.3", diags[d],
                                  planes[p],  NULL};
      cb_scene *s = scene_of(sets);
      double total = 0;
      for (int i = 0; i < s->mesh.nv; i++) {
        cr_expect_gt(s->mass[i], 0.0);
        total += s->mass[i];
      }
      cr_expect(fabs(total - 0.3 * 3 * 0.75) < 1e-13, "%s %s: total %.17g, expected 0.675", diags[d], planes[p], total);
      cb_scene_free(s);
    }
}

Test(mass, vertex_mass_overrides_density) {
  const char *const sets[] = {"mesh.n=4", "material.density=7", "material.vertex_mass=0.25", NULL};
  cb_scene *s = scene_of(sets);
  for (int i = 0; i < s->mesh.nv; i++) cr_expect_eq(s->mass[i], 0.25, "mass[%d] = %g", i, s->mass[i]);
  cb_scene_free(s);
}

Test(mass, kinetic_energy) {
  /* K = 1/2 sum m_i |v_i|^2 with the lumped masses; v = (1, 2, 2): |v|^2 = 9 */
  const char *const sets[] = {"mesh.n=3", "mesh.size=2", "material.density=2", NULL};
  cb_scene *s = scene_of(sets);
  double v[27];
  for (int i = 0; i < 9; i++) {
    v[3 * i] = 1;
    v[3 * i + 1] = 2;
    v[3 * i + 2] = 2;
  }
  /* total mass 2 * 4 = 8: K = 1/2 * 8 * 9 = 36 */
  cr_expect(CLOSE(cb_scene_kinetic(s, v), 36.0), "K = %g", cb_scene_kinetic(s, v));
  cb_scene_free(s);
}

Test(mass, chain_needs_vertex_mass) {
  const char *const no_mass[] = {"mesh.type=chain", "mesh.n=4", "scene.pins=none", NULL};
  expect_scene_error(no_mass, "vertex_mass", NULL);
  const char *const with_mass[] = {"mesh.type=chain", "mesh.n=4", "material.vertex_mass=0.5", "scene.pins=0", NULL};
  cb_scene *s = scene_of(with_mass);
  cr_expect_eq(s->mesh.nv, 4);
  cr_expect_eq(s->topo.ne, 3);
  for (int i = 0; i < 4; i++) cr_expect_eq(s->mass[i], 0.5);
  cb_scene_free(s);
}

/* ---- the binding ------------------------------------------------------------------ */

/* Every registered integrator type's keys are config keys
 * (integrator.<name>), and their default texts give the type's own
 * defaults, byte for byte. */
Test(bind, every_types_keys_are_config_keys_and_their_defaults_are_the_types) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_eq(cb_config_validate(&c), CB_OK, "%s", cb_error_message());
  int nkeys = 0;
  for (int i = 0; cb_integrator_types[i]; i++) {
    const cb_integrator_type *t = cb_integrator_types[i];
    for (const cb_param_key *k = t->keys; k && k->name; k++, nkeys++) {
      char key[64], set[128];
      snprintf(key, sizeof key, "integrator.%s", k->name);
      double v;
      cr_expect_eq(cb_config_type_value(&c, key, &v), 0, "%s is not a config key", key);
      snprintf(set, sizeof set, "%s=%s", key, k->def);
      cr_expect_eq(cb_config_set(&c, set), CB_OK, "%s", cb_error_message());
    }
    if (!t->params_size) continue;
    void *p = malloc(t->params_size);
    cr_assert_eq(cb_integrator_type_params_from_config(&c, t, p), CB_OK, "%s", cb_error_message());
    cr_expect(memcmp(p, t->params_default, t->params_size) == 0, "%s: key defaults differ from params_default",
              t->name);
    free(p);
  }
  cr_expect_eq(nkeys, 44); /* newton 6, jacobi-nl 4, chebyshev-nl 6, pd 2, pd-chebyshev 4, pbd 3, xpbd 2, lbfgs 6,
                              vbd 4, vbd-chebyshev 6, shape_matching 1 */
}

/* The binding reads a type's keys into its struct: Newton from a file. */
Test(bind, newton_reads_its_own_keys) {
  cb_config c;
  load_ok("[integrator]\nmax_iters = 7\ntol = 1e-5\ntol_dx = 1e-9\ndefiniteness = shift\ninit = x0\nline_search = on\n",
          &c);
  cb_newton_params p = newton_of(&c);
  cr_expect_eq(p.max_iters, 7);
  cr_expect_eq(p.tol, 1e-5);
  cr_expect_eq(p.tol_dx, 1e-9);
  cr_expect_eq(p.definiteness, CB_DEF_SHIFT);
  cr_expect_eq(p.init_predict, 0);
  cr_expect_eq(p.line_search, 1);
  cr_expect_eq(cb_config_type_value(&c, "integrator.dt", &(double){0}), -1); /* generic, not a type's */
  cr_expect_null(cb_config_choice(&c, "integrator.dt"));
}

/* The core names the field of a bad definition; the binding adds where the
 * key was set (here: the default, so the config's path). */
Test(bind, core_errors_name_the_key_and_the_binding_its_location) {
  cb_scene_def d = cb_scene_def_default();
  d.grid.n = 4;
  d.grid.m = 4;
  d.pins = "99";
  cb_scene *s = NULL;
  const char *key = "unset";
  cr_expect_eq(cb_scene_build(&d, &s, &key), CB_EINVAL);
  cr_expect_null(s);
  cr_expect_str_eq(key, "scene.pins");
  cr_expect(strncmp(cb_error_message(), "scene.pins: vertex 99 out of range", 34) == 0, "%s", cb_error_message());
  d.pins = "none";
  d.vertex_mass = 1;
  cr_assert_eq(cb_scene_build(&d, &s, &key), CB_OK, "%s", cb_error_message());
  cr_expect_null(key);
  cr_expect_null(s->def.pins); /* the scene's copy keeps no borrowed strings */
  cr_expect_eq(s->npinned, 0);
  cb_scene_def copy = s->def; /* ... so rebuilding from it is refused, not a crash */
  cb_scene_free(s);
  cr_expect_eq(cb_scene_build(&copy, &s, NULL), CB_EINVAL);
  cr_expect_null(s);
  cb_config c;
  test_config(&c, (const char *const[]){"scene.pins=99", "mesh.n=4", NULL});
  cr_expect_eq(cb_scene_from_config(&c, &s), CB_EINVAL);
  cr_expect(strncmp(cb_error_message(), "--set: scene.pins: vertex 99 out of range", 41) == 0, "%s",
            cb_error_message());
}

/* ---- non-text and endless input (issue 14, item 2) --------------------------------- */

static const char *write_bytes(const char *data, size_t n) {
  static char path[64];
  snprintf(path, sizeof path, "/tmp/cbtest_ini_XXXXXX");
  int fd = mkstemp(path);
  cr_assert(fd >= 0);
  cr_assert_eq(write(fd, data, n), (ssize_t)n);
  close(fd);
  return path;
}

Test(load_error, nul_byte_is_an_error_and_keeps_nothing_after_it) {
  /* inih's fgets reader dropped "garbage" after the NUL and took n = 5 */
  static const char text[] = "[mesh]\nn = 5\0garbage\nm = 4\n";
  const char *p = write_bytes(text, sizeof text - 1);
  cb_config c;
  cb_error_clear();
  int st = cb_config_load(p, &c);
  unlink(p);
  cr_expect_eq(st, CB_EINVAL);
  char where[100];
  snprintf(where, sizeof where, "%s:2: NUL byte", p);
  cr_expect(strstr(cb_error_message(), where) != NULL, "message '%s' lacks '%s'", cb_error_message(), where);
  /* a file of NUL bytes ran the default scene */
  char zeros[64] = {0};
  p = write_bytes(zeros, sizeof zeros);
  st = cb_config_load(p, &c);
  unlink(p);
  cr_expect_eq(st, CB_EINVAL, "a file of NULs loaded");
}

Test(load_error, devices_directories_and_huge_files_are_refused, .timeout = 10) {
  /* /dev/zero and /dev/urandom hung at 100% CPU; a directory ran the default scene */
  const char *paths[] = {"/dev/zero", "/dev/urandom", "/tmp"};
  for (int k = 0; k < 3; k++) {
    cb_config c;
    cb_error_clear();
    int st = cb_config_load(paths[k], &c);
    cr_expect_eq(st, CB_EIO, "%s: status %d (%s)", paths[k], st, cb_error_message());
    cr_expect(strstr(cb_error_message(), paths[k]) != NULL, "message '%s'", cb_error_message());
  }
  size_t n = CB_CONFIG_MAX_BYTES + 1;
  char *big = malloc(n);
  cr_assert(big);
  memset(big, '\n', n);
  memcpy(big, "; a config of blank lines\n", 26);
  const char *p = write_bytes(big, n);
  free(big);
  cb_config c;
  int st = cb_config_load(p, &c);
  unlink(p);
  cr_expect_eq(st, CB_EIO, "a config over %d bytes loaded", CB_CONFIG_MAX_BYTES);
  cr_expect(strstr(cb_error_message(), "1 MiB") != NULL, "message '%s'", cb_error_message());
}

/* ---- did you mean (issue 14, item 7) ------------------------------------------------ */

Test(load_error, unknown_keys_suggest_the_nearest) {
  expect_load_error("[material]\nstrech_k = 4\n", 2, "material.strech_k", "did you mean material.stretch_k?");
  expect_load_error("[mesh]\nstretch_k = 4\n", 2, "mesh.stretch_k", "did you mean material.stretch_k?");
  expect_load_error("[integrator]\nmax_iter = 4\n", 2, "integrator.max_iter", "did you mean integrator.max_iters?");
  expect_load_error("[materal]\nk = 1\n", 1, NULL, "did you mean [material]?");
  /* nothing close: no suggestion */
  cb_config c;
  load_text("[mesh]\nfrobnicate = 1\n", &c);
  cr_expect(strstr(cb_error_message(), "did you mean") == NULL, "message '%s'", cb_error_message());
  expect_set_error("integrator.dtt=1", "integrator.dtt", "did you mean integrator.dt?");
}

/* ---- finite scene quantities, messages with a location (issue 14, items 1 and 7) ----- */

/* Builds the scene of ini (written to dir/scene.ini, with obj as dir/mesh.obj
 * if not NULL); expects an error whose message contains each string. */
static void expect_file_scene_error(const char *ini, const char *obj, const char *what1, const char *what2) {
  make_dir();
  char ip[600], op[600];
  snprintf(ip, sizeof ip, "%s/scene.ini", dir);
  snprintf(op, sizeof op, "%s/mesh.obj", dir);
  write_file(ip, ini);
  if (obj) write_file(op, obj);
  cb_config c;
  cr_assert_eq(cb_config_load(ip, &c), CB_OK, "%s", cb_error_message());
  cb_scene *s = NULL;
  cb_integrator *it = NULL;
  int st = cb_scene_from_config(&c, &s);
  if (st == CB_OK) st = cb_integrator_from_config(&c, s, NULL, &it);
  const char *msg = cb_error_message();
  cr_expect_neq(st, CB_OK, "scene built for\n%s", ini);
  if (what1) cr_expect(strstr(msg, what1) != NULL, "message '%s' lacks '%s'", msg, what1);
  if (what2) cr_expect(strstr(msg, what2) != NULL, "message '%s' lacks '%s'", msg, what2);
  cb_integrator_free(it);
  cb_scene_free(s);
  unlink(ip);
  unlink(op);
  rmdir(dir);
}

Test(scene_finite, huge_obj_mesh_is_refused_naming_the_quantity) {
  /* 1e150: finite areas (5e299 m^2) and masses, but the gravity potential
   * m g y ~ 5e299 x 9.8 x 1e150 overflows; row 0 was "-nan ... ok" */
  expect_file_scene_error("[mesh]\ntype = obj\nfile = mesh.obj\n[scene]\npins = 0\n",
                          "v 0 0 0\nv 1e150 0 0\nv 0 1e150 0\nf 1 2 3\n", "scene.gravity: the gravity energy", "inf");
  /* 1e200: the area itself is above DBL_MAX */
  expect_file_scene_error("[mesh]\ntype = obj\nfile = mesh.obj\n[scene]\npins = 0\n",
                          "v 0 0 0\nv 1e200 0 0\nv 0 1e200 0\nf 1 2 3\n", "scene.ini:3: mesh.file", "area inf");
  /* finite coordinates and area, but density x area overflows */
  expect_file_scene_error("[mesh]\ntype = obj\nfile = mesh.obj\n[material]\ndensity = 1e12\n[scene]\npins = 0\ngravity "
                          "= 0 0 0\n",
                          "v 0 0 0\nv 1e150 0 0\nv 0 1e150 0\nf 1 2 3\n", "scene.ini:5: material.density", "mass");
  /* vertex masses given: the stretch energy at a scaled start overflows */
  expect_file_scene_error("[mesh]\ntype = obj\nfile = mesh.obj\n[material]\nvertex_mass = 1\n[scene]\npins = 0\n"
                          "gravity = 0 0 0\ninitial_scale = 1e6\n",
                          "v 0 0 0\nv 1e150 0 0\nv 0 1e150 0\nf 1 2 3\n", "material.stretch_k: the stretch energy",
                          NULL);
}

Test(scene_finite, isolated_vertex_names_its_obj_line) {
  /* "vertex 4 has no mass" had no file:line */
  expect_file_scene_error("[mesh]\ntype = obj\nfile = mesh.obj\n[scene]\npins = 0\n",
                          "v 0 0 0\nv 1 0 0\n# an isolated vertex\nv 5 5 5\nv 0 1 0\nf 1 2 4\n",
                          "scene.ini:3: mesh.file: ", "mesh.obj:4: vertex 2 (0-based; 3 in the file's indices)");
  /* a chain without vertex masses: the key to set */
  expect_file_scene_error("[mesh]\ntype = chain\nn = 4\n[scene]\npins = top-corners\n", NULL,
                          "scene.ini: material.vertex_mass: the mesh has no triangles", NULL);
}

Test(scene_finite, all_pinned_chebyshev_names_scene_pins) {
  /* was "lanczos: empty operator" */
  expect_file_scene_error("[mesh]\nn = 2\n[scene]\npins = corners\n[solver]\nmethod = chebyshev\n", NULL,
                          "scene.ini:4: scene.pins: every vertex is pinned", "lanczos: empty operator");
}

Test(validate, nrelax_needs_non_decreasing_whole_numbers) {
  cb_config c;
  cb_config_defaults(&c);
  cr_assert_eq(cb_config_set(&c, "solver.nrelax=16 64 128"), CB_OK);
  cr_expect_eq(cb_config_validate(&c), CB_OK);
  cr_assert_eq(cb_config_set(&c, "solver.nrelax=16 8 128"), CB_OK);
  cr_expect_eq(cb_config_validate(&c), CB_EINVAL);
  cr_expect(strstr(cb_error_message(), "solver.nrelax") != NULL, "message: %s", cb_error_message());
  cr_assert_eq(cb_config_set(&c, "solver.nrelax=4 16.5 48"), CB_OK);
  cr_expect_eq(cb_config_validate(&c), CB_EINVAL);
}

/* A key two integrator types share has one definition: the config layer
 * refuses one name declared with two (here the same key with another help
 * text, another default, or declared twice by one type), naming the key, the
 * types and what differs; the same definition in two types is one key. */
#define SHARED_ITERS(doc_, def_) \
  { \
    .name = "iters", .kind = CB_PARAM_INT, .offset = 0, .def = def_, .unit = "iterations", .lo = 1, .hi = 100, \
    .doc = doc_ \
  }
static const cb_param_key keys_a[] = {SHARED_ITERS("Iterations per step.", "32"), {.name = NULL}};
static const cb_param_key keys_other_doc[] = {SHARED_ITERS("Sweeps per step.", "32"), {.name = NULL}};
static const cb_param_key keys_other_def[] = {SHARED_ITERS("Iterations per step.", "16"), {.name = NULL}};
static const cb_param_key keys_twice[] = {
    SHARED_ITERS("Iterations per step.", "32"), SHARED_ITERS("Iterations per step.", "32"), {.name = NULL}};

Test(config, shared_key_has_one_definition) {
  const cb_integrator_type a = {.name = "type-a", .keys = keys_a}, a2 = {.name = "type-a2", .keys = keys_a},
                           doc = {.name = "type-doc", .keys = keys_other_doc},
                           def = {.name = "type-def", .keys = keys_other_def},
                           twice = {.name = "type-twice", .keys = keys_twice};
  const cb_integrator_type *same[] = {&a, &a2, NULL};
  cr_expect_eq(cb_config_check_type_keys(same), CB_OK, "%s", cb_error_message());
  const cb_integrator_type *by_doc[] = {&a, &doc, NULL};
  cr_assert_neq(cb_config_check_type_keys(by_doc), CB_OK, "a shared key with another help text");
  const char *msg = cb_error_message();
  cr_expect(strstr(msg, "integrator.iters") && strstr(msg, "type-a") && strstr(msg, "type-doc") &&
                strstr(msg, "help text"),
            "%s", msg);
  const cb_integrator_type *by_def[] = {&a, &def, NULL};
  cr_assert_neq(cb_config_check_type_keys(by_def), CB_OK, "a shared key with another default");
  cr_expect(strstr(cb_error_message(), "default"), "%s", cb_error_message());
  const cb_integrator_type *dup[] = {&twice, NULL};
  cr_assert_neq(cb_config_check_type_keys(dup), CB_OK, "one type declaring a key twice");
  cr_expect(strstr(cb_error_message(), "twice"), "%s", cb_error_message());
  /* the registered types pass, so every config validates */
  cr_expect_eq(cb_config_check_type_keys(cb_integrator_types), CB_OK, "%s", cb_error_message());
}
#undef SHARED_ITERS
