/* How an experiment declares its scenes: every scene is a config file from
 * the --configs folder plus "section.key=value" overrides applied in order,
 * a label (its name in rows, file names and errors) and a role (what the
 * scene is for in that experiment: "map", "j3", "steps", "pair", ...; each
 * experiment's main.c lists its roles). An experiment keeps its scenes in one
 * table of these, and adding a scene to an experiment is one row there:
 *
 *   static const cb_scene_decl scenes[] = {
 *     {"lab", "hanging.ini", {NULL}, "steps"},
 *     {"stiff", "hanging.ini", {"material.stretch_k=1e6", NULL}, "steps"},
 *   };
 *
 * Experiment-specific plan data (step counts, strides) sits next to the
 * declaration, in a struct whose first member is the cb_scene_decl. */
#ifndef CB_SCENE_DECL_H
#define CB_SCENE_DECL_H

#include "config.h"
#include <clothbench/scene.h>
#include "experiment.h"

enum { CB_SCENE_DECL_MAX_SETS = 15 };

typedef struct cb_scene_decl {
  const char *label;                                 /* the scene's name in rows and errors */
  const char *config;                                /* INI file in the --configs folder, e.g. "hanging.ini" */
  const char *overrides[CB_SCENE_DECL_MAX_SETS + 1]; /* "section.key=value", applied in order; NULL-terminated */
  const char *role;                                  /* what the scene is for in its experiment */
} cb_scene_decl;

/* The scene's config: <configs>/<config>, then its overrides, then the
 * NULL-terminated `more` (a cell's own, e.g. "material.stretch_k=1e4"; may be
 * NULL), then cb_config_validate. An error names the scene:
 * "scene <label> (<config>): <file:line: key: reason>". */
int cb_scene_decl_config(const cb_experiment *e, const cb_scene_decl *d, const char *const *more, cb_config *out);

/* cb_scene_decl_config, then the scene built from that config; cfg (may be
 * NULL) receives the config. *out is NULL on error. */
int cb_scene_decl_build(const cb_experiment *e, const cb_scene_decl *d, const char *const *more, cb_config *cfg,
                        cb_scene **out);

/* The value the declaration's overrides give "section.key" (the last one
 * wins), or NULL if they do not set it. For plan data read off the table,
 * e.g. a cost hint from mesh.n. */
const char *cb_scene_decl_override(const cb_scene_decl *d, const char *key);

/* Vertices of the scene a config describes, for cost hints: n*m for a grid,
 * n for a chain, 0 for an OBJ mesh (not read here). */
long cb_scene_decl_vertices(const cb_config *c);

/* Whether d has this role. */
int cb_scene_decl_is(const cb_scene_decl *d, const char *role);

#endif
