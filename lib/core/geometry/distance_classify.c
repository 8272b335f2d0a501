/* The helpers the pair files share (distance_classify.h). */
#include "distance_classify.h"

#include <math.h>

#include <clothbench/status.h>
#include "vec.h"

double cb_point_segment_case(const double *x, int p, int e0, int e1, cb_distance_case *c) {
  const double *P = x + 3 * p, *A = x + 3 * e0, *B = x + 3 * e1;
  double e[3], q[3];
  cb_v3_sub(B, A, e);
  cb_v3_sub(P, A, q);
  double L = cb_v3_dot(e, e), t = L > 0 ? cb_v3_dot(q, e) / L : 0; /* closest point A + t e on the line */
  if (!(t > 0)) {
    *c = (cb_distance_case){.form = CB_DIST_POINT_POINT, .v = {p, e0}};
    return cb_v3_dot(q, q);
  }
  if (!(t < 1)) {
    *c = (cb_distance_case){.form = CB_DIST_POINT_POINT, .v = {p, e1}};
    return cb_v3_dist2(P, B);
  }
  *c = (cb_distance_case){.form = CB_DIST_POINT_LINE, .v = {p, e0, e1}};
  double r[3] = {q[0] - t * e[0], q[1] - t * e[1], q[2] - t * e[2]}; /* P - (A + t e) */
  return cb_v3_dot(r, r);
}

int cb_distance_check_finite(const double *x, int n, const char *pair) {
  for (int i = 0; i < n; i++)
    if (!isfinite(x[i])) return cb_fail("distance %s: coordinate %d is %g, not finite", pair, i, x[i]);
  return CB_OK;
}

double cb_distance_pair_eval(int (*classify)(const double *, cb_distance_case *), int nverts, const double *x,
                             double *g, double *H) {
  cb_distance_case c;
  if (classify(x, &c)) {
    int n = 3 * nverts;
    if (g)
      for (int i = 0; i < n; i++) g[i] = NAN;
    if (H)
      for (int i = 0; i < n * n; i++) H[i] = NAN;
    return NAN;
  }
  return cb_distance_case_eval(&c, nverts, x, g, H);
}
