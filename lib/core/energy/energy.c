/* The term registry: every energy term type, one X(id) line each.
 *
 * A new term is one file, lib/core/energy/energy_<name>.c, ending with its table
 *   const cb_term_type cb_term_<id>_type = {.name = "<name>", ...};
 * plus its one X(id) line in CB_TERM_REGISTRY below. Registration is what
 * gets it checked: tests/test_energy_conformance.c runs the
 * finite-difference, symmetry and projection checks on every entry. The
 * material models that build terms for a scene are in material.c. */
#include <clothbench/energy.h>

#include <string.h>

#define CB_TERM_REGISTRY(X) \
  X(spring)          /* energy_spring.c */ \
  X(gravity)         /* energy_gravity.c */ \
  X(fem)             /* energy_fem.c: exact Hessian */ \
  X(fem_frozen)      /* energy_fem.c: frozen-R constant Hessian */ \
  X(dihedral)        /* energy_dihedral.c: Gauss-Newton Hessian */ \
  X(dihedral_exact)  /* energy_dihedral.c: exact Hessian, projected */ \
  X(quadratic)       /* energy_quadratic.c */ \
  X(sphere)          /* collider.c: the penalty collider */ \
  X(contact_penalty) /* contact/contact_penalty.c: contact.method = penalty */ \
  X(contact_ipc)     /* contact/contact_ipc.c: contact.method = ipc */ \
  /* one X(id) line per term type, above this line */
#define CB_TERM_DECLARE(id) extern const cb_term_type cb_term_##id##_type;
#define CB_TERM_ENTRY(id) &cb_term_##id##_type,
CB_TERM_REGISTRY(CB_TERM_DECLARE)
const cb_term_type *const cb_term_types[] = {CB_TERM_REGISTRY(CB_TERM_ENTRY) NULL};

const cb_term_type *cb_term_type_find(const char *name) {
  for (int i = 0; cb_term_types[i]; i++)
    if (strcmp(cb_term_types[i]->name, name) == 0) return cb_term_types[i];
  return NULL;
}

void cb_term_free(cb_term *t) {
  if (t) t->type->free(t);
}

int cb_term_count_indefinite(const cb_term *t, const double *x, int *nelements) {
  *nelements = 0;
  if (!t || !t->type->indefinite) return 0;
  return t->type->indefinite(t, x, nelements);
}
