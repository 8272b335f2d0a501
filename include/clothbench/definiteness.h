/* The integrator.definiteness policy: what happens when a compressed spring
 * makes its Hessian indefinite (formulas and sources in definiteness.c).
 *
 * A policy is split into the three places where it acts:
 *   - the element projection (projection.h) that cb_system_assemble hands
 *     every term: none, clamp (drop) or abs (mirror);
 *   - the solve-side shift A + mu I (solver_shift.h), for `shift`;
 *   - the springs' compressed response (energy.h,
 *     cb_spring_term_set_response), for `choi-ko`: a different energy, fixed
 *     when the scene builds its terms. */
#ifndef CB_DEFINITENESS_H
#define CB_DEFINITENESS_H

#include "projection.h"

typedef enum {
  CB_DEF_NONE = 0, /* exact Hessian */
  CB_DEF_DROP,     /* drop k(1 - L/l)(I - uu^T) when l < L: clamps the eigenvalue at 0 */
  CB_DEF_MIRROR,   /* |k(1 - L/l)|: the eigenvalue mirrored to its absolute value */
  CB_DEF_SHIFT,    /* exact Hessian; the solve adds mu I, mu raised until Cholesky succeeds */
  CB_DEF_CHOI_KO,  /* Choi & Ko 2002: compressed springs buckle (a different energy), exact Hessian */
  CB_DEF_COUNT
} cb_definiteness;

extern const char *const cb_definiteness_names[]; /* NULL-terminated, by enum value */
int cb_definiteness_from_name(const char *name, cb_definiteness *out);

/* The element projection of a policy: clamp for drop, abs for mirror, none
 * for none, shift and choi-ko. */
cb_projection cb_definiteness_projection(cb_definiteness d);

/* The transverse coefficient t = E'(l)/l (k(1 - L/l) for a linear spring)
 * after the policy's projection: cb_projection_eigenvalue(projection(d), t). */
double cb_definiteness_transverse(cb_definiteness d, double coef);

#endif
