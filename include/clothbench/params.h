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
