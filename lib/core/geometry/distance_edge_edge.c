/* The edge-edge pair (a0, a1, b0, b1), distance.h.
 *
 * Classification: with u = a1 - a0, w = b1 - b0, r = a0 - b0, the closest
 * points of the two lines, a0 + s u and b0 + t w, minimise |r + s u - t w|^2:
 *   s a - t b = -d,   s b - t c = -e,     a = u.u, b = u.w, c = w.w, d = u.r, e = w.r
 *   s = (b e - c d) / D,   t = (a e - b d) / D,   D = a c - b^2 = |u x w|^2.
 * If the edges are not parallel (D > CB_DIST_PARALLEL a c) and both s and t
 * lie in [0, 1], the segments' closest points are the lines': the
 * line-line case. Otherwise the minimum of |r + s u - t w|^2 over the square
 * [0,1]^2 lies on its boundary, where one parameter is 0 or 1: the nearest of
 * the four endpoint-to-segment cases (a0 and a1 against edge b, b0 and b1
 * against edge a), each point-line or point-point. For parallel (and
 * collinear) edges an endpoint is always among the closest points, so this
 * is exact there too, and the line-line formula, whose |u x w|^2 vanishes,
 * is never used. */
#include <clothbench/status.h>
#include "distance_classify.h"
#include "vec.h"

int cb_distance_edge_edge_case(const double *x, cb_distance_case *c) {
  *c = (cb_distance_case){.form = CB_DIST_POINT_POINT, .v = {0, 2}};
  int st = cb_distance_check_finite(x, 12, "edge-edge");
  if (st) return st;
  double u[3], w[3], r[3], n[3];
  cb_v3_sub(x + 3, x, u);
  cb_v3_sub(x + 9, x + 6, w);
  cb_v3_sub(x, x + 6, r);
  cb_v3_cross(u, w, n);
  double a = cb_v3_dot(u, u), b = cb_v3_dot(u, w), cc = cb_v3_dot(w, w), d = cb_v3_dot(u, r), e = cb_v3_dot(w, r);
  double D = cb_v3_dot(n, n); /* = a c - b^2, without its cancellation */
  if (D > CB_DIST_PARALLEL * a * cc) {
    double s = (b * e - cc * d) / D, t = (a * e - b * d) / D;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
      *c = (cb_distance_case){.form = CB_DIST_LINE_LINE, .v = {0, 1, 2, 3}};
      return CB_OK;
    }
  }
  static const int cand[4][3] = {{0, 2, 3}, {1, 2, 3}, {2, 0, 1}, {3, 0, 1}}; /* point, segment */
  double best = 0;
  for (int k = 0; k < 4; k++) {
    cb_distance_case ck;
    double dk = cb_point_segment_case(x, cand[k][0], cand[k][1], cand[k][2], &ck);
    if (k == 0 || dk < best) {
      best = dk;
      *c = ck;
    }
  }
  return CB_OK;
}

CB_DISTANCE_PAIR_FUNCTIONS(ee, cb_distance_edge_edge_case, 4)

const cb_distance_type cb_distance_edge_edge = {.name = "edge-edge",
                                                .nverts = 4,
                                                .na = 2,
                                                .classify = cb_distance_edge_edge_case,
                                                .distance = ee_distance,
                                                .gradient = ee_gradient,
                                                .hessian = ee_hessian};
