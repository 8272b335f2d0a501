/* Extreme eigenvalues of D^-1 A (lib/instruments/spectrum.c): Lanczos + shift-invert
 * Lanczos against GSL's dense eigensolver, and the rho formula. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "capture.h"
#include "spectrum.h"
#include "support.h"

Test(spectrum, lanczos_matches_dense_on_a_newton_matrix) {
  cb_config c;
  test_config(&c, (const char *const[]){"mesh.n=9", "material.vertex_mass=1", "material.stretch_k=1e5",
                                        "integrator.max_iters=5", NULL});
  cb_capture cap;
  cr_assert_eq(cb_capture_newton_system(&c, 8, 0, &cap), CB_OK, "%s", cb_error_message());
  double *d = malloc((size_t)cap.A.n * sizeof(double));
  cr_assert_eq(cb_jacobi_scaling(&cap.A, d), CB_OK);
  cb_spectrum lz, de;
  cr_assert_eq(cb_spectrum_lanczos(&cap.A, d, &lz), CB_OK);
  cr_assert_eq(cb_spectrum_dense(&cap.A, d, &de), CB_OK);
  cr_expect_lt(fabs(lz.lmin - de.lmin), 1e-8 * de.lmin, "lmin %.12g vs %.12g", lz.lmin, de.lmin);
  cr_expect_lt(fabs(lz.lmax - de.lmax), 1e-8 * de.lmax, "lmax %.12g vs %.12g", lz.lmax, de.lmax);
  cr_expect_lt(fabs(lz.lmin - de.lmin), lz.res_min + 1e-12, "the bound holds");
  cr_expect_gt(de.lmax / de.lmin, 100, "an ill-conditioned case (condition %g)", de.lmax / de.lmin);
  /* plain A (d = NULL): the mass term bounds lambda_min(A) from below by m/dt^2 */
  cr_assert_eq(cb_spectrum_lanczos(&cap.A, NULL, &lz), CB_OK);
  cr_assert_eq(cb_spectrum_dense(&cap.A, NULL, &de), CB_OK);
  cr_expect_lt(fabs(lz.lmin - de.lmin), 1e-8 * de.lmin);
  cr_expect_geq(de.lmin, 1 / (c.dt * c.dt) * (1 - 1e-9));
  free(d);
  cb_capture_free(&cap);
}

Test(spectrum, rho_of_the_weighted_jacobi_iteration) {
  /* eig(D^-1 A) in [0.1, 2.5]: rho(alpha) = max(|1 - 0.1 alpha|, |1 - 2.5 alpha|) */
  cr_expect_float_eq(cb_jacobi_rho(0.1, 2.5, 1.0), 1.5, 1e-15);
  cr_expect_float_eq(cb_jacobi_rho(0.1, 2.5, 0.5), 0.95, 1e-15);
  cr_expect_float_eq(cb_jacobi_rho(0.1, 2.5, 2 / 2.6), (2.5 - 0.1) / 2.6, 1e-15); /* alpha* */
}

Test(spectrum, non_positive_diagonal_is_not_spd) {
  cb_pattern p;
  cb_pattern_init(&p, 1);
  cb_pattern_add(&p, 0, 0);
  cb_sparse A;
  cb_sparse_from_pattern(&p, &A);
  cb_pattern_free(&p);
  double d[3];
  A.val[cb_sparse_diag_index(&A, 0)] = 1;
  A.val[cb_sparse_diag_index(&A, 1)] = -1;
  A.val[cb_sparse_diag_index(&A, 2)] = 1;
  cr_expect_eq(cb_jacobi_scaling(&A, d), CB_NOT_SPD);
  cb_spectrum s;
  cr_expect_eq(cb_spectrum_lanczos(&A, NULL, &s), CB_NOT_SPD);
  cb_sparse_free(&A);
}
