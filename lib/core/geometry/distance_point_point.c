/* The point-point pair (p, q): one case, d^2 = |p - q|^2 (distance.h). */
#include <math.h>

#include <clothbench/status.h>
#include "distance_classify.h"

static int pp_classify(const double *x, cb_distance_case *c) {
  *c = (cb_distance_case){.form = CB_DIST_POINT_POINT, .v = {0, 1}};
  return cb_distance_check_finite(x, 6, "point-point");
}
CB_DISTANCE_PAIR_FUNCTIONS(pp, pp_classify, 2)

const cb_distance_type cb_distance_point_point = {.name = "point-point",
                                                  .nverts = 2,
                                                  .na = 1,
                                                  .classify = pp_classify,
                                                  .distance = pp_distance,
                                                  .gradient = pp_gradient,
                                                  .hessian = pp_hessian};
