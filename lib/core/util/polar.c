/* Polar decomposition by GSL's SVD; the degenerate cases are documented in
 * polar.h. */
#include <clothbench/polar.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <math.h>
#include <string.h>

#include "vec.h"

/* A unit vector normal to the unit vector u: the coordinate axis on which u
 * is smallest, made orthogonal to u. */
static void normal_to(const double u[3], double n[3]) {
  int k = 0;
  for (int a = 1; a < 3; a++)
    if (fabs(u[a]) < fabs(u[k])) k = a;
  double e[3] = {0, 0, 0};
  e[k] = 1;
  double d = u[k], s = 0;
  for (int a = 0; a < 3; a++) {
    n[a] = e[a] - d * u[a];
    s += n[a] * n[a];
  }
  s = sqrt(s);
  for (int a = 0; a < 3; a++) n[a] /= s;
}

/* Thin SVD of the row-major rows x cols (cols <= 3) matrix M: U (rows x cols,
 * row-major), sigma, V (cols x cols, row-major). Returns 0, or -1 if GSL fails
 * or M is not finite. */
static int svd(const double *M, int rows, int cols, double *U, double *sigma, double *V) {
  for (int i = 0; i < rows * cols; i++)
    if (!isfinite(M[i])) return -1;
  memcpy(U, M, (size_t)rows * cols * sizeof(double));
  double work[3];
  gsl_matrix_view Uv = gsl_matrix_view_array(U, (size_t)rows, (size_t)cols);
  gsl_matrix_view Vv = gsl_matrix_view_array(V, (size_t)cols, (size_t)cols);
  gsl_vector_view Sv = gsl_vector_view_array(sigma, (size_t)cols), Wv = gsl_vector_view_array(work, (size_t)cols);
  gsl_error_handler_t *old = gsl_set_error_handler_off();
  int st = gsl_linalg_SV_decomp(&Uv.matrix, &Vv.matrix, &Sv.vector, &Wv.vector);
  gsl_set_error_handler(old);
  return st ? -1 : 0;
}

unsigned cb_polar32(const double F[6], double R[6], double sigma[2]) {
  double U[6], s[2] = {0, 0}, V[4];
  unsigned flags = 0;
  if (svd(F, 3, 2, U, s, V) || !(s[0] > 0)) { /* F = 0 or not finite */
    static const double E[6] = {1, 0, 0, 1, 0, 0};
    memcpy(R, E, sizeof E);
    if (sigma) sigma[0] = sigma[1] = 0;
    return CB_POLAR_RANK_DEFICIENT;
  }
  double u1[3] = {U[0], U[2], U[4]}, u2[3] = {U[1], U[3], U[5]}, v1[2] = {V[0], V[2]}, v2[2] = {V[1], V[3]};
  if (s[1] <= CB_POLAR_RANK_TOL * s[0]) { /* collapsed to a segment */
    flags |= CB_POLAR_RANK_DEFICIENT;
    normal_to(u1, u2);
    v2[0] = -v1[1];
    v2[1] = v1[0];
  }
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 2; c++) R[2 * r + c] = u1[r] * v1[c] + u2[r] * v2[c];
  if (sigma) {
    sigma[0] = s[0];
    sigma[1] = s[1];
  }
  return flags;
}

unsigned cb_polar33(const double A[9], double R[9], double sigma[3]) {
  double U[9], s[3] = {0, 0, 0}, V[9];
  unsigned flags = 0;
  if (svd(A, 3, 3, U, s, V) || !(s[0] > 0)) {
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(R, I, sizeof I);
    if (sigma) sigma[0] = sigma[1] = sigma[2] = 0;
    return CB_POLAR_RANK_DEFICIENT;
  }
  double u[3][3], v[3][3]; /* columns */
  for (int c = 0; c < 3; c++)
    for (int r = 0; r < 3; r++) {
      u[c][r] = U[3 * r + c];
      v[c][r] = V[3 * r + c];
    }
  double tol = CB_POLAR_RANK_TOL * s[0];
  if (s[1] <= tol) { /* rank 1: complete both bases */
    flags |= CB_POLAR_RANK_DEFICIENT;
    normal_to(u[0], u[1]);
    normal_to(v[0], v[1]);
  }
  if (s[2] <= tol) { /* rank <= 2: right-handed completion, det R = +1 */
    flags |= CB_POLAR_RANK_DEFICIENT;
    cb_v3_cross(u[0], u[1], u[2]);
    cb_v3_cross(v[0], v[1], v[2]);
  } else {
    double cu[3], cv[3];
    cb_v3_cross(u[0], u[1], cu);
    cb_v3_cross(v[0], v[1], cv);
    double du = cu[0] * u[2][0] + cu[1] * u[2][1] + cu[2] * u[2][2];
    double dv = cv[0] * v[2][0] + cv[1] * v[2][1] + cv[2] * v[2][2];
    if (du * dv < 0) { /* det(U V^T) = -1: A is a reflection; flip the weakest direction */
      flags |= CB_POLAR_REFLECTED;
      for (int r = 0; r < 3; r++) u[2][r] = -u[2][r];
    }
  }
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) R[3 * r + c] = u[0][r] * v[0][c] + u[1][r] * v[1][c] + u[2][r] * v[2][c];
  if (sigma) memcpy(sigma, s, sizeof s);
  return flags;
}
