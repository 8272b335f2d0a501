/* The material models of material.stretch and material.bend, one table.
 *
 * A new model is one row in CB_MATERIALS below: its role, its name, the
 * registered term type it builds (and the type of its other Hessian, if it
 * has one) and its alloc, a few lines here on the term's own constructor
 * (energy.h). The names each role offers (cb_stretch_names, cb_bend_names)
 * are generated from the same rows. A model on a new energy adds that term's
 * file and its line in the term registry (energy.c) first. */
#include <clothbench/material.h>

#include <stdio.h>
#include <string.h>

#include <clothbench/status.h>

cb_material_params cb_material_params_default(void) {
  cb_material_params p = {.k = 0,
                          .fem_hessian = CB_FEM_EXACT,
                          .bend_hessian = CB_BEND_GAUSS_NEWTON,
                          .definiteness = CB_DEF_DROP,
                          .buckling_kb = 0.01};
  return p;
}

/* Springs between ends[2s], ends[2s+1], with the compressed-spring response
 * the definiteness policy asks for (Choi-Ko changes the energy). */
static int springs(const cb_model *m, const char *label, int ns, const int *ends, const cb_material_params *p,
                   cb_term **out, const char **key) {
  int st = cb_spring_term_alloc(m, label, ns, ends, p->k, out);
  if (st) return st;
  st = cb_spring_term_set_response(*out, p->definiteness, p->buckling_kb);
  if (st) {
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", cb_error_message());
    cb_term_free(*out);
    *out = NULL;
    *key = "material.buckling_kb";
    return cb_fail_status(st == CB_ENOMEM ? st : CB_EINVAL, "material.buckling_kb: %s", msg);
  }
  return CB_OK;
}

/* stretch = spring: a spring on every mesh edge. */
static int stretch_spring(const cb_model *m, const cb_material_params *p, cb_term **out, const char **key) {
  return springs(m, "stretch", m->topo->ne, m->topo->edge, p, out, key);
}

/* stretch = fem: co-rotational FEM on every triangle (energy_fem.c). */
static int stretch_fem(const cb_model *m, const cb_material_params *p, cb_term **out, const char **key) {
  *key = "material.stretch"; /* each of its errors */
  if (m->mesh->nt == 0)
    return cb_fail("material.stretch: fem needs triangles; the mesh has none (use spring for chains and line "
                   "elements)");
  return cb_fem_term_alloc(m, "stretch", p->k, p->fem_hessian, out);
}

/* bend = spring: a spring across each pair of neighbouring triangles, between
 * the two vertices opposite their shared edge (topology pair_opp). */
static int bend_spring(const cb_model *m, const cb_material_params *p, cb_term **out, const char **key) {
  return springs(m, "bend", m->topo->np, m->topo->pair_opp, p, out, key);
}

/* bend = dihedral: the hinges of discrete shells, with material.bend_hessian. */
static int bend_dihedral(const cb_model *m, const cb_material_params *p, cb_term **out, const char **key) {
  (void)key;
  int st = cb_hinge_term_alloc(m, "bend", p->k, out);
  if (st == CB_OK) st = cb_hinge_term_set_hessian(*out, p->bend_hessian);
  if (st && *out) {
    cb_term_free(*out);
    *out = NULL;
  }
  return st;
}

/* bend = quadratic: Bergou et al.'s constant-Hessian bending (energy_quadratic.c). */
static int bend_quadratic(const cb_model *m, const cb_material_params *p, cb_term **out, const char **key) {
  (void)key;
  return cb_quadratic_bend_term_alloc(m, "bend", p->k, out);
}

/* The models: X(role, name, term type, its other Hessian's type, alloc), one
 * line each; within a role, the order of its config choices. */
#define CB_MATERIALS(X) \
  X(STRETCH, "spring", "spring", NULL, stretch_spring) \
  X(STRETCH, "fem", "fem", "fem_frozen", stretch_fem) \
  X(BEND, "none", NULL, NULL, NULL) \
  X(BEND, "spring", "spring", NULL, bend_spring) \
  X(BEND, "dihedral", "dihedral", "dihedral_exact", bend_dihedral) \
  X(BEND, "quadratic", "quadratic", NULL, bend_quadratic) \
  /* one X(...) line per material model, above this line */

#define CB_MATERIAL_ROW(role_, name_, term_, alt_, alloc_) \
  {.name = name_, .role = CB_MATERIAL_##role_, .term = term_, .term_alt = alt_, .alloc = alloc_},
const cb_material cb_materials[] = {CB_MATERIALS(CB_MATERIAL_ROW){.name = NULL}};

#define CB_MATERIAL_NAME_IF_STRETCH_STRETCH(name_) name_,
#define CB_MATERIAL_NAME_IF_STRETCH_BEND(name_)
#define CB_MATERIAL_NAME_IF_BEND_STRETCH(name_)
#define CB_MATERIAL_NAME_IF_BEND_BEND(name_) name_,
#define CB_MATERIAL_STRETCH_NAME(role_, name_, term_, alt_, alloc_) CB_MATERIAL_NAME_IF_STRETCH_##role_(name_)
#define CB_MATERIAL_BEND_NAME(role_, name_, term_, alt_, alloc_) CB_MATERIAL_NAME_IF_BEND_##role_(name_)
const char *const cb_stretch_names[] = {CB_MATERIALS(CB_MATERIAL_STRETCH_NAME) NULL};
const char *const cb_bend_names[] = {CB_MATERIALS(CB_MATERIAL_BEND_NAME) NULL};

const cb_material *cb_material_find(cb_material_role role, const char *name) {
  for (const cb_material *mat = cb_materials; mat->name; mat++)
    if (mat->role == role && strcmp(mat->name, name) == 0) return mat;
  return NULL;
}

int cb_material_term_alloc(const cb_material *mat, const cb_model *m, const cb_material_params *p, cb_term **out,
                           const char **key) {
  *out = NULL;
  if (!mat->alloc) return CB_OK;
  const char *dummy = NULL;
  int st = mat->alloc(m, p, out, key ? key : &dummy);
  if (st) {
    cb_term_free(*out);
    *out = NULL;
    return st;
  }
  const char *built = (*out)->type->name;
  if (cb_term_type_find(built) != (*out)->type ||
      !(strcmp(built, mat->term) == 0 || (mat->term_alt && strcmp(built, mat->term_alt) == 0))) {
    cb_term_free(*out);
    *out = NULL;
    return cb_fail("material '%s' built a term of type '%s', not its registered type '%s'", mat->name, built,
                   mat->term);
  }
  return CB_OK;
}

int cb_bend_term_alloc(const char *name, const cb_model *m, double bend_k, cb_term **out) {
  *out = NULL;
  const cb_material *mat = cb_material_find(CB_MATERIAL_BEND, name);
  if (!mat) return cb_fail("unknown bending model '%s'", name);
  cb_material_params p = cb_material_params_default();
  p.k = bend_k;
  return cb_material_term_alloc(mat, m, &p, out, NULL);
}
