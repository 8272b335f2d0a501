/* One projection of a symmetric element Hessian onto (approximately) the
 * positive semidefinite cone, shared by every energy term whose Hessian can
 * be indefinite (springs today; dihedral hinges, FEM triangles later).
 *
 * A term computes its dense 3k x 3k element matrix H_e for a k-vertex
 * stencil, and cb_projection_apply replaces it by
 *   H_e = V diag(lambda) V^T  ->  V diag(f(lambda)) V^T,
 *   f = identity (none), max(lambda, 0) (clamp), |lambda| (abs),
 * by a symmetric eigendecomposition (GSL's gsl_eigen_symmv). A term whose
 * element has a known spectrum may apply f to its eigenvalues in closed form
 * instead (cb_projection_eigenvalue), as the spring does; the two agree, and
 * tests/test_energy_projection.c checks it.
 *
 * The projection is chosen per assembly (cb_system_assemble maps the
 * integrator.definiteness policy to it, definiteness.h), not stored in the
 * term: one scene's system is assembled with the exact Hessian and with a
 * projected one in the same run (a Newton integrator with `drop` next to
 * exact-Hessian witnesses and references), and a stored policy would make
 * them race on shared term state. */
#ifndef CB_PROJECTION_H
#define CB_PROJECTION_H

typedef enum {
  CB_PROJ_NONE = 0, /* exact Hessian */
  CB_PROJ_CLAMP,    /* negative eigenvalues clamped at 0 */
  CB_PROJ_ABS,      /* negative eigenvalues replaced by their absolute value */
  CB_PROJ_COUNT
} cb_projection;

extern const char *const cb_projection_names[]; /* NULL-terminated, by enum value */

/* f(lambda) of the projection: lambda, max(lambda, 0) or |lambda|. */
double cb_projection_eigenvalue(cb_projection p, double lambda);

/* Workspace for n x n matrices (allocated at set-up, so a projection
 * inside a time step never allocates). */
typedef struct cb_projection_work cb_projection_work;
int cb_projection_work_alloc(int n, cb_projection_work **out);
void cb_projection_work_free(cb_projection_work *w);

/* Projects the symmetric row-major n x n matrix H in place (only its lower
 * triangle is read). Eigenvalues above -n eps max|lambda| count as
 * nonnegative (the round-off of a zero one), so CB_PROJ_NONE, and a PSD
 * matrix with a null space, leave H untouched bit for bit. Returns the number
 * of negative eigenvalues (>= 0; the ones changed), or a negative status (n
 * not the workspace size, GSL failure). */
int cb_projection_apply(cb_projection p, int n, double *H, cb_projection_work *w);

#endif
