/* The point-triangle pair (p, t0, t1, t2), distance.h.
 *
 * Classification: with u = t1 - t0, w = t2 - t0, n = u x w, N = |n|^2 and
 * q = p - t0, the projection of p onto the plane is t0 + b1 u + b2 w with
 *   b1 = ((q x w) . n) / N,   b2 = ((u x q) . n) / N
 * (q x w = b1 n + (q.n/N) n x w, and (n x w) . n = 0; likewise for b2).
 * If b1 >= 0, b2 >= 0 and b1 + b2 <= 1 the closest point is that projection:
 * the point-plane case. Otherwise the closest point lies on the boundary,
 * the nearest of the three edges' point-segment cases (vertex or edge
 * region). A triangle with N <= CB_DIST_DEGENERATE |u|^2 |w|^2 (sin^2 of its
 * angle at t0) has no face: boundary only. */
#include <clothbench/status.h>
#include "distance_classify.h"
#include "vec.h"

int cb_distance_point_triangle_case(const double *x, cb_distance_case *c) {
  *c = (cb_distance_case){.form = CB_DIST_POINT_POINT, .v = {0, 1}};
  int st = cb_distance_check_finite(x, 12, "point-triangle");
  if (st) return st;
  double u[3], w[3], q[3], n[3], qw[3], uq[3];
  cb_v3_sub(x + 6, x + 3, u);
  cb_v3_sub(x + 9, x + 3, w);
  cb_v3_sub(x, x + 3, q);
  cb_v3_cross(u, w, n);
  double N = cb_v3_dot(n, n);
  if (N > CB_DIST_DEGENERATE * cb_v3_dot(u, u) * cb_v3_dot(w, w)) {
    cb_v3_cross(q, w, qw);
    cb_v3_cross(u, q, uq);
    double b1 = cb_v3_dot(qw, n) / N, b2 = cb_v3_dot(uq, n) / N; /* barycentrics of the projection */
    if (b1 >= 0 && b2 >= 0 && b1 + b2 <= 1) {
      *c = (cb_distance_case){.form = CB_DIST_POINT_PLANE, .v = {0, 1, 2, 3}};
      return CB_OK;
    }
  }
  static const int edges[3][2] = {{1, 2}, {2, 3}, {3, 1}};
  double best = 0;
  for (int k = 0; k < 3; k++) {
    cb_distance_case e;
    double d = cb_point_segment_case(x, 0, edges[k][0], edges[k][1], &e);
    if (k == 0 || d < best) {
      best = d;
      *c = e;
    }
  }
  return CB_OK;
}

CB_DISTANCE_PAIR_FUNCTIONS(pt, cb_distance_point_triangle_case, 4)

const cb_distance_type cb_distance_point_triangle = {.name = "point-triangle",
                                                     .nverts = 4,
                                                     .na = 1,
                                                     .classify = cb_distance_point_triangle_case,
                                                     .distance = pt_distance,
                                                     .gradient = pt_gradient,
                                                     .hessian = pt_hessian};
