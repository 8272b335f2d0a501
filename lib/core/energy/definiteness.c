/* Definiteness policies for compressed springs, in one place.
 *
 * Spring Hessian (lecture, "Spring Hessian"):
 *   H_e = k uu^T + k (1 - L/l) (I - uu^T),  u = x_ij / l,  l = |x_ij|.
 * Its eigenvalues are k (along u) and k(1 - L/l) (twice, across u). When the
 * spring is compressed (l < L) the transverse one is negative, so H_e, H and
 * A = M/dt^2 + H may be indefinite (lecture, "Positive Definiteness of
 * Hessian"). In 1D there is no transverse direction: E = k/2 (x - L)^2 and
 * E'' = k > 0.
 *
 *   none     keeps t = k(1 - L/l).
 *   drop     drops the second term when l < L ("Enforcement of Positive
 *            Definiteness"); since the term is negative exactly when l < L,
 *            this is max(t, 0): the transverse eigenvalue clamped at 0.
 *   mirror   |t|: the eigenvalue replaced by its absolute value (H_e becomes
 *            V |Lambda| V^T, the nearest SPD-like matrix with the same
 *            eigenvectors and curvature magnitudes).
 *   shift    exact Hessian; the solve adds mu I to A and raises mu until
 *            Cholesky succeeds (cb_shift_solve, solver_shift.c).
 *   choi-ko  a different model of the compressed spring: Choi & Ko's
 *            immediate-buckling response (energy_spring_choi_ko.c), built
 *            into the springs when the scene is built; its Hessian is the
 *            exact one of that model.
 *
 * So a policy is three independent choices, and each lives where it acts:
 *   the element projection (none, clamp, abs: projection.c), applied by every
 *   term whose Hessian can be indefinite when the system is assembled;
 *   the solve-side shift (solver_shift.c), called by the Newton integrator;
 *   the spring's compressed response (energy_spring_choi_ko.c), fixed when
 *   the scene builds its terms.
 * drop and mirror are clamp and abs of the element's eigenvalues: for a
 * spring the only eigenvalue that can be negative is t, so the spring applies
 * them to t in closed form (cb_projection_eigenvalue). */
#include <clothbench/definiteness.h>

#include <string.h>

#include <clothbench/status.h>

const char *const cb_definiteness_names[] = {"none", "drop", "mirror", "shift", "choi-ko", NULL};

int cb_definiteness_from_name(const char *name, cb_definiteness *out) {
  for (int i = 0; cb_definiteness_names[i]; i++)
    if (strcmp(name, cb_definiteness_names[i]) == 0) {
      *out = (cb_definiteness)i;
      return CB_OK;
    }
  return cb_fail("unknown definiteness policy '%s'", name);
}

cb_projection cb_definiteness_projection(cb_definiteness d) {
  switch (d) {
  case CB_DEF_DROP: return CB_PROJ_CLAMP; /* t -> max(t, 0) */
  case CB_DEF_MIRROR: return CB_PROJ_ABS; /* t -> |t| */
  default: return CB_PROJ_NONE;           /* none, shift (A is shifted in the solve), choi-ko (exact for its model) */
  }
}

double cb_definiteness_transverse(cb_definiteness d, double coef) {
  return cb_projection_eigenvalue(cb_definiteness_projection(d), coef);
}
