/* Parameters: one way to declare them, shared by every plug-in and struct.
 *
 * Each parameter struct has a _default() function that writes every default
 * once (cb_solver_params_default, cb_newton_params_default, ...); the config
 * layer's key tables (lib/config/config.c, and the cb_param_key tables the
 * plug-ins declare beside their structs) must give the same values, and
 * tests/test_params.c checks that they do, key by key.
 *
 * `auto`: a double parameter that the code can choose by itself (a weight,
 * a spectral radius) takes the one sentinel CB_AUTO, in the C API as in a
 * config file (`solver.alpha = auto`, `integrator.rho = auto`). Every such
 * parameter's valid range excludes it (they are all >= 0). */
#ifndef CB_PARAMS_H
#define CB_PARAMS_H

#include <stddef.h>

#define CB_AUTO (-1.0) /* `auto`: the code chooses the value (see each field's comment for how) */

/* The cookie (Box2D's habit: b2DefaultWorldDef() sets def.internalValue to
 * a secret cookie that b2CreateWorld checks). Every parameter struct of the
 * core's API has an int `cookie` that its _default() sets to
 * CB_PARAMS_COOKIE and its consumer checks, so a struct that skipped its
 * defaults (zeroed, or stack garbage) is refused with a message naming the
 * function to start from, instead of running on zeros. Start from the
 * _default() and change fields; never build one from nothing.
 *   cb_scene_def          cb_scene_def_default()          cb_scene_build
 *   cb_contact_params     cb_contact_params_default()     cb_scene_build, cb_contact_params_check
 *   cb_integrator_params  cb_integrator_params_default()  cb_integrator_alloc
 *   cb_<type>_params      cb_<type>_params_default()      cb_integrator_alloc (its first field)
 *   cb_solver_params      cb_solver_params_default()      cb_solver_alloc
 *   cb_grid_params        cb_grid_params_default()        cb_mesh_grid
 *   cb_obstacle_params    cb_obstacle_params_default()    cb_obstacle_alloc */
#define CB_PARAMS_COOKIE 0x63627031 /* "cbp1" */

/* CB_OK if cookie is CB_PARAMS_COOKIE; otherwise CB_EINVAL with "<what>:
 * not set up by <default_fn>() ...". */
int cb_params_check(int cookie, const char *what, const char *default_fn);

/* One of a plug-in's parameters as a config key, `<section>.<name>`. The
 * core only describes it; the config layer (lib/config/) parses, checks,
 * documents (`simulate --help-config`) and binds it into the plug-in's
 * parameter struct, so a plug-in's keys live in its file. Two plug-ins may
 * share a key by declaring the same name with the same definition. */
typedef enum {
  CB_PARAM_INT,
  CB_PARAM_DOUBLE,
  CB_PARAM_BOOL,
  CB_PARAM_CHOICE,
  CB_PARAM_DOUBLE_AUTO /* a double, or `auto`, stored as CB_AUTO (its range must exclude it) */
} cb_param_kind;
typedef struct cb_param_key {
  const char *name; /* key in its section; NULL ends a list */
  cb_param_kind kind;
  size_t offset;   /* of the field in the params struct: int (INT, BOOL, CHOICE; an enum is
                      int-sized) or double (DOUBLE, DOUBLE_AUTO) */
  const char *def; /* default, as a config writes it; must give the struct's _default() value */
  const char *unit;
  double lo, hi;              /* accepted range of INT and DOUBLE values (inclusive) ... */
  int lo_open;                /* ... but lo excluded when 1 */
  const char *const *choices; /* CHOICE: the names, NULL-terminated */
  const int *values;          /* CHOICE: the field's value for each name; NULL = the name's index */
  const char *doc;
} cb_param_key;

#endif
