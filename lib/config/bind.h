/* The binding of configs to the core: every place where a cb_config
 * (config.h) becomes a core struct, and where a core error about one field
 * gets the location (file:line, or --set) of the key that set it.
 *
 *   config keys --cb_scene_from_config-------> cb_scene_def -> cb_scene_build
 *               --cb_integrator_from_config--> cb_integrator_params + the
 *                                              type's own params + solver
 *
 * An integrator type's own keys are declared in its type table
 * (cb_integrator_type.keys, in the type's file); config.c adds them to its
 * key table and cb_integrator_type_params_from_config copies their values
 * into the type's parameter struct, so no line here names a type. */
#ifndef CB_BIND_H
#define CB_BIND_H

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>

#include "config.h"

/* The scene the config describes (cb_config_validate, then cb_scene_build).
 * Errors: "file:line: key: reason" as for the parser. */
int cb_scene_from_config(const cb_config *c, cb_scene **out);

/* Fills def from c. Its strings point into c (and into path, whose first
 * half receives mesh.file and whose second half collider.file, each resolved
 * against the config file's folder; 4 CB_PATH_LEN is room for both), so def
 * is valid while c and path are. */
int cb_scene_def_from_config(const cb_config *c, cb_scene_def *def, char *path, size_t npath);

/* The generic integrator parameters (integrator.dt; no hook). */
int cb_integrator_params_from_config(const cb_config *c, cb_integrator_params *p);

/* The parameters of type t from its keys (t->keys), starting from the
 * type's defaults; params has t->params_size bytes. */
/* The contact responses' keys (contact.thickness, contact.friction and each response's own, contact.h) into p. */
int cb_contact_params_from_config(const cb_config *c, cb_contact_params *p);
int cb_integrator_type_params_from_config(const cb_config *c, const cb_integrator_type *t, void *params);

/* The same for Newton (integrator.max_iters, tol, tol_dx, definiteness,
 * init, line_search), typed. */
int cb_newton_params_from_config(const cb_config *c, cb_newton_params *p);

/* solver.tol, max_iters, alpha, rho. */
cb_solver_params cb_solver_params_from_config(const cb_config *c);

/* The integrator integrator.method names for the scene, with its own keys,
 * the generic ones and the solver.* keys. p replaces the generic parameters
 * read from c when not NULL (e.g. to add a hook). */
int cb_integrator_from_config(const cb_config *c, cb_scene *s, const cb_integrator_params *p, cb_integrator **out);

#endif
