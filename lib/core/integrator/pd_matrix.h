/* The projective-dynamics matrix of a scene (internal to lib/core):
 *
 *   P = M/dt^2 + sum over the spring terms of sum_e k A_e A_e^T (x) I_3   (+ H_const)
 *
 * over the free DOFs, A_e the incidence vector of spring e = (i, j), a pinned
 * end's column dropped (its k x_p goes to the right-hand side of whoever
 * solves with P). It is the constant matrix of projective dynamics for springs
 * (Liu et al. 2013; integrator_pd.c) and L-BFGS's initial Hessian (Liu,
 * Bouaziz and Kavan 2017; integrator_lbfgs.c). With_constant adds the
 * system's constant Hessians (quadratic bending, frozen-rotation FEM), which
 * are their own projective-dynamics matrices. P is SPD when every vertex has
 * mass. It is built on a copy of the system's 3x3-block pattern, so Newton's
 * matrix is untouched. */
#ifndef CB_PD_MATRIX_H
#define CB_PD_MATRIX_H

#include <clothbench/scene.h>
#include <clothbench/sparse.h>

/* Allocates P (free with cb_sparse_free) and fills its values. */
int cb_pd_matrix_build(const cb_scene *s, double dt, int with_constant, cb_sparse *P);

#endif
