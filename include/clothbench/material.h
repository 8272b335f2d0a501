/* Material models: what material.stretch and material.bend name. One table
 * (lib/core/model/material.c), a row per model: its name, its role (the in-plane
 * stretch term or the bending term of a scene), the registered term type it
 * builds (energy.h) and its alloc. The scene builds the row a definition
 * names; the config offers the names of each role as that key's choices. */
#ifndef CB_MATERIAL_H
#define CB_MATERIAL_H

#include "definiteness.h"
#include "energy.h"

typedef enum { CB_MATERIAL_STRETCH = 0, CB_MATERIAL_BEND = 1 } cb_material_role;

/* What a model reads from the scene's definition (cb_scene_def). */
typedef struct cb_material_params {
  double k;                     /* material.stretch_k (stretch) or material.bend_k (bend) */
  cb_fem_hessian fem_hessian;   /* material.fem_hessian (fem) */
  cb_bend_hessian bend_hessian; /* material.bend_hessian (dihedral) */
  cb_definiteness definiteness; /* integrator.definiteness: choi-ko changes a spring's energy */
  double buckling_kb;           /* material.buckling_kb, N m^2 (springs under choi-ko) */
} cb_material_params;

/* Defaults: k 0, exact FEM, Gauss-Newton dihedral, drop, buckling_kb 0.01. */
cb_material_params cb_material_params_default(void);

typedef struct cb_material {
  const char *name; /* the value of material.stretch or material.bend */
  cb_material_role role;
  const char *term;     /* name of the registered term type it builds (cb_term_type_find); NULL: none */
  const char *term_alt; /* the type it builds with its other Hessian (fem_frozen, dihedral_exact), or NULL */
  /* Builds the term on m (label "stretch" or "bend"); NULL: builds nothing
   * (bend = none). On failure *out is NULL, and *key is set to the config
   * key the error is about when the model knows it (material.buckling_kb for
   * a spring's Choi-Ko response). */
  int (*alloc)(const cb_model *m, const cb_material_params *p, cb_term **out, const char **key);
} cb_material;

/* The table, ended by a NULL name; and each role's names in table order,
 * NULL-terminated (the choices of material.stretch and material.bend). */
extern const cb_material cb_materials[];
extern const char *const cb_stretch_names[]; /* "spring", "fem" */
extern const char *const cb_bend_names[];    /* "none", "spring", "dihedral", "quadratic" */

/* The row of that role and name, or NULL. */
const cb_material *cb_material_find(cb_material_role role, const char *name);
/* Builds the term of material mat (*out NULL for a model that builds none),
 * and checks that it is of the row's type. */
int cb_material_term_alloc(const cb_material *mat, const cb_model *m, const cb_material_params *p, cb_term **out,
                           const char **key);
/* The bending model called name with stiffness bend_k and the other
 * parameters at their defaults (*out NULL for `none`). */
int cb_bend_term_alloc(const char *name, const cb_model *m, double bend_k, cb_term **out);

#endif
