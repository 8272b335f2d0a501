/* Small vector helpers: 3-vectors (a vertex's position, velocity or force,
 * stored as three consecutive doubles of a flat 3n array) and n-vectors.
 *
 * The sums run in index order, the same order as the expressions they
 * replace, so results are bit-for-bit those of the written-out formulas. For
 * long vectors where the order does not matter, CBLAS (cblas_ddot,
 * cblas_dnrm2) is the faster choice. */
#ifndef CB_VEC_H
#define CB_VEC_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/* a . b */
static inline double cb_v3_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
/* |a| */
static inline double cb_v3_norm(const double *a) { return sqrt(cb_v3_dot(a, a)); }
/* out = a - b */
static inline void cb_v3_sub(const double *a, const double *b, double *out) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}
/* |a - b|^2 */
static inline double cb_v3_dist2(const double *a, const double *b) {
  double d[3];
  cb_v3_sub(a, b, d);
  return cb_v3_dot(d, d);
}
/* out = a x b (out must not alias a or b) */
static inline void cb_v3_cross(const double *a, const double *b, double *out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
/* whether any component is nonzero */
static inline int cb_v3_nonzero(const double *a) { return a[0] != 0 || a[1] != 0 || a[2] != 0; }

/* sum_i a_i b_i, i = 0..n-1, in index order */
static inline double cb_vec_dot(int n, const double *a, const double *b) {
  double s = 0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* Finiteness on the bits, so that loops vectorise: a double is not finite iff its 11 exponent bits are all
 * ones, and then adding their lowest bit carries into bit 63. cb_nonfinite_bits(v) has bit 63 set iff v is
 * not finite; OR them together and test the result with cb_bits_finite. */
#define CB_DOUBLE_EXP_BITS 0x7ff0000000000000ull /* a double's exponent bits */
#define CB_DOUBLE_EXP_ONE 0x0010000000000000ull  /* their lowest */
static inline uint64_t cb_nonfinite_bits(double v) {
  uint64_t u;
  memcpy(&u, &v, sizeof u); /* the bits (no aliasing through a cast) */
  return (u & CB_DOUBLE_EXP_BITS) + CB_DOUBLE_EXP_ONE;
}
static inline int cb_bits_finite(uint64_t bad) { return !(bad >> 63); }

/* whether every x_i, i = 0..n-1, is finite (no inf, no NaN) */
static inline int cb_vec_all_finite(int n, const double *x) {
  uint64_t bad = 0;
  for (int i = 0; i < n; i++) bad |= cb_nonfinite_bits(x[i]);
  return cb_bits_finite(bad);
}

#endif
