/* Helpers the pair files share (lib/core/geometry, internal). */
#ifndef CB_DISTANCE_CLASSIFY_H
#define CB_DISTANCE_CLASSIFY_H

#include <clothbench/distance.h>

/* The case of point x[3p] against the segment x[3e0]..x[3e1] (point-line if
 * the point projects into the open segment, else point-point to the nearer
 * end, or to e0 for a zero-length segment), and its squared distance
 * computed from the closest point (for comparing candidates). */
double cb_point_segment_case(const double *x, int p, int e0, int e1, cb_distance_case *c);
/* CB_OK if the n coordinates x are finite, else CB_EINVAL naming the pair. */
int cb_distance_check_finite(const double *x, int n, const char *pair);

/* The pair's squared distance by classify, with g (3 nverts) and H ((3
 * nverts)^2) unless NULL; NaN in all three when classify fails (a
 * non-finite coordinate). */
double cb_distance_pair_eval(int (*classify)(const double *, cb_distance_case *), int nverts, const double *x,
                             double *g, double *H);
/* The three functions of a pair's type table, from its classifier. */
#define CB_DISTANCE_PAIR_FUNCTIONS(prefix, classify, nverts) \
  static double prefix##_distance(const double *x) { return cb_distance_pair_eval(classify, nverts, x, NULL, NULL); } \
  static double prefix##_gradient(const double *x, double *g) { \
    return cb_distance_pair_eval(classify, nverts, x, g, NULL); \
  } \
  static double prefix##_hessian(const double *x, double *H) { \
    return cb_distance_pair_eval(classify, nverts, x, NULL, H); \
  }

#endif
