/* Polar decomposition F = R S (R with orthonormal columns, S symmetric
 * positive semidefinite), the rotation part of a deformation gradient
 * (co-rotational FEM, energy_fem.c) or of a shape-matching moment matrix
 * A_pq (integrator_shape_matching.c). By GSL's SVD (gsl_linalg_SV_decomp):
 * F = U diag(sigma) V^T, R = U V^T, on stack storage (never allocates).
 *
 * Degenerate input never gives NaN; the treatment (polar.c) is:
 *   3x2 (a triangle's F): no orientation exists in 3D (a flipped triangle is a
 *     rotated one), so only the rank matters. Rank 2: R = U V^T, unique.
 *     sigma_2 <= CB_POLAR_RANK_TOL sigma_1 (the triangle collapsed to a
 *     segment): R = u_1 v_1^T + u_2 v_2^T with v_2 = v_1 turned by +90 degrees
 *     and u_2 the unit vector normal to u_1 closest to the coordinate axis on
 *     which u_1 is smallest (deterministic; any u_2 normal to u_1 minimises
 *     |F - R|). F = 0 (or non-finite): R = [e_x e_y].
 *   3x3 (A_pq): R is the closest proper rotation, det R = +1: with
 *     d = sign(det U det V), R = U diag(1, 1, d) V^T, so a reflected A
 *     (det A < 0) gets the rotation that flips its weakest direction. Rank
 *     deficient A (planar or collinear clusters): the missing singular
 *     vectors are completed to right-handed bases (u_3 = u_1 x u_2, and for
 *     rank 1 u_2 as in the 3x2 case), which leaves R A^T's action on the
 *     cluster's span unchanged. A = 0 (or non-finite): R = I.
 * The return value says which case applied (CB_POLAR_* bits, 0 = regular). */
#ifndef CB_POLAR_H
#define CB_POLAR_H

#define CB_POLAR_RANK_TOL 1e-10

enum {
  CB_POLAR_RANK_DEFICIENT = 1u << 0, /* a singular value <= CB_POLAR_RANK_TOL x the largest (or F = 0) */
  CB_POLAR_REFLECTED = 1u << 1       /* 3x3 only: det < 0 (the closest rotation flipped a direction) */
};

/* F and R 3x2 row-major (F[2 r + c]); sigma (may be NULL) gets the singular
 * values, descending. */
unsigned cb_polar32(const double F[6], double R[6], double sigma[2]);

/* A and R 3x3 row-major; R is a proper rotation. sigma (may be NULL) gets the
 * singular values of A, descending. */
unsigned cb_polar33(const double A[9], double R[9], double sigma[3]);

#endif
