/* Definiteness policies for compressed springs, in one place.
 *
 * Spring Hessian (lecture, "Spring Hessian"):
 *   H_e = k uu^T + k (1 - L/l) (I - uu^T),  u = x_ij / l,  l = |x_ij|.
 * Its eigenvalues are k (along u) and k(1 - L/l) (twice, across u). When the
 * spring is compressed (l < L) the transverse one is negative, so H_e, H and
 * A = M/dt^2 + H may be indefinite (lecture, "Positive Definiteness of
 * Hessian").
 *
 *   none  keeps k(1 - L/l).
 *   drop  drops the second term when l < L ("Enforcement of Positive
 *         Definiteness"); since the term is negative exactly when l < L, this
 *         is max(k(1 - L/l), 0): the transverse eigenvalue clamped at 0. */
#include <string.h>

#include "energy.h"
#include "status.h"

const char *const cb_definiteness_names[] = {"none", "drop", NULL};

int cb_definiteness_from_name(const char *name, cb_definiteness *out) {
  for (int i = 0; cb_definiteness_names[i]; i++)
    if (strcmp(name, cb_definiteness_names[i]) == 0) {
      *out = (cb_definiteness)i;
      return CB_OK;
    }
  return cb_fail("unknown definiteness policy '%s'", name);
}

double cb_definiteness_transverse(cb_definiteness d, double coef) {
  switch (d) {
  case CB_DEF_DROP: return coef < 0 ? 0.0 : coef;
  default: return coef;
  }
}
