/* The term registry: every energy term type, one line each, and the bending
 * models of material.bend, which map names to term types on a stencil of the
 * topology.
 *
 * A new term is one file, lib/core/energy_<name>.c, ending with its table
 *   const cb_term_type cb_term_<name>_type = {.name = "<name>", ...};
 * plus its two lines here (the declaration and the entry in cb_term_types[]).
 * Registration is what gets it checked: tests/test_energy_conformance.c runs
 * the finite-difference, symmetry and projection checks on every entry. */
#include <clothbench/energy.h>

#include <string.h>

#include <clothbench/status.h>

extern const cb_term_type cb_term_spring_type;  /* energy_spring.c */
extern const cb_term_type cb_term_gravity_type; /* energy_gravity.c */
extern const cb_term_type cb_term_fem_type;        /* energy_fem.c: exact Hessian */
extern const cb_term_type cb_term_fem_frozen_type; /* energy_fem.c: frozen-R constant Hessian */
extern const cb_term_type cb_term_dihedral_type;       /* energy_dihedral.c: Gauss-Newton Hessian */
extern const cb_term_type cb_term_dihedral_exact_type; /* energy_dihedral.c: exact Hessian, projected */
extern const cb_term_type cb_term_quadratic_type; /* energy_quadratic.c */
extern const cb_term_type cb_term_sphere_type;    /* collider.c */

const cb_term_type *const cb_term_types[] = {
    &cb_term_spring_type,
    &cb_term_gravity_type,
    &cb_term_fem_type,
    &cb_term_fem_frozen_type,
    &cb_term_dihedral_type,
    &cb_term_dihedral_exact_type,
    &cb_term_quadratic_type,
    &cb_term_sphere_type,
    NULL,
};

const cb_term_type *cb_term_type_find(const char *name) {
  for (int i = 0; cb_term_types[i]; i++)
    if (strcmp(cb_term_types[i]->name, name) == 0) return cb_term_types[i];
  return NULL;
}

void cb_term_free(cb_term *t) {
  if (t) t->type->free(t);
}

/* ---- bending models (material.bend) -------------------------------------- */

/* A spring across each pair of neighbouring triangles: between the two
 * vertices opposite their shared edge (topology pair_opp). */
static int bend_springs(const cb_model *m, double k, cb_term **out) {
  return cb_spring_term_alloc(m, "bend", m->topo->np, m->topo->pair_opp, k, out);
}

static int bend_hinges(const cb_model *m, double k, cb_term **out) { return cb_hinge_term_alloc(m, "bend", k, out); }
static int bend_quadratic(const cb_model *m, double k, cb_term **out) {
  return cb_quadratic_bend_term_alloc(m, "bend", k, out);
}

typedef struct {
  const char *name;
  const cb_term_type *type; /* NULL: no bending term */
  int (*alloc)(const cb_model *m, double k, cb_term **out);
} bend_model;

/* One line per bending model; cb_bend_names lists the same names in order
 * (config.c offers them as the choices of material.bend; a test checks the two agree). */
static const bend_model bend_models[] = {
    {"none", NULL, NULL},
    {"spring", &cb_term_spring_type, bend_springs},
    {"dihedral", &cb_term_dihedral_type, bend_hinges},
    {"quadratic", &cb_term_quadratic_type, bend_quadratic},
};
const char *const cb_bend_names[] = {"none", "spring", "dihedral", "quadratic", NULL};
_Static_assert(sizeof bend_models / sizeof bend_models[0] + 1 == sizeof cb_bend_names / sizeof cb_bend_names[0],
               "cb_bend_names must list every bending model");

int cb_bend_term_alloc(const char *name, const cb_model *m, double bend_k, cb_term **out) {
  *out = NULL;
  for (size_t i = 0; i < sizeof bend_models / sizeof bend_models[0]; i++) {
    if (strcmp(name, bend_models[i].name) != 0) continue;
    if (strcmp(name, cb_bend_names[i]) != 0) return cb_fail("bending model %zu: name table out of order", i);
    if (!bend_models[i].alloc) return CB_OK;
    int st = bend_models[i].alloc(m, bend_k, out);
    if (st == CB_OK && (*out)->type != bend_models[i].type) {
      cb_term_free(*out);
      *out = NULL;
      return cb_fail("bending model '%s' built a term of the wrong type", name);
    }
    return st;
  }
  return cb_fail("unknown bending model '%s'", name);
}
