/* The point-edge pair (p, e0, e1): point-line when p projects into the open
 * segment, else point-point to the nearer end (distance.h). */
#include <clothbench/status.h>
#include "distance_classify.h"
#include "vec.h"

int cb_distance_point_edge_case(const double *x, cb_distance_case *c) {
  *c = (cb_distance_case){.form = CB_DIST_POINT_POINT, .v = {0, 1}};
  int st = cb_distance_check_finite(x, 9, "point-edge");
  if (st) return st;
  cb_point_segment_case(x, 0, 1, 2, c);
  return CB_OK;
}

CB_DISTANCE_PAIR_FUNCTIONS(pe, cb_distance_point_edge_case, 3)

const cb_distance_type cb_distance_point_edge = {.name = "point-edge",
                                                 .nverts = 3,
                                                 .na = 1,
                                                 .classify = cb_distance_point_edge_case,
                                                 .distance = pe_distance,
                                                 .gradient = pe_gradient,
                                                 .hessian = pe_hessian};
