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
 * mass.
 *
 * Every term P holds is of the form P (x) I_3: the mass, the springs
 * (k A_e A_e^T (x) I_3), quadratic bending (k_b Q (x) I_3, energy_quadratic.c)
 * and frozen-rotation FEM (2 mu A_t (b_a . b_b) I_3, energy_fem.c). So P is
 * stored two ways:
 *   scalar  the n x n matrix of P's coefficients over the free vertices, one
 *           entry per vertex pair that a term couples (a scalar cb_sparse),
 *           solved for x, y and z at once as a 3-column right-hand side (Liu
 *           et al. 2013, sec. 4; 2017, sec. 3). Its factor has about 1/9 of
 *           the block one's nonzeros and a back-solve reads it once for the
 *           three columns.
 *   block   the 3n x 3n matrix P (x) I_3 on a copy of the system's 3x3-block
 *           pattern (Newton's, explicit zeros included), so Newton's matrix
 *           is untouched: the path every solver can read (the iterative ones
 *           are block methods), and the one a constant Hessian that is not
 *           s I_3 per block would need.
 * cb_pd_matrix_build_scalar checks the Kronecker form block by block on the
 * assembled constant Hessian (exactly: off-diagonal entries 0, the three
 * diagonal ones equal) and returns CB_PD_NOT_KRONECKER, building nothing,
 * when a block fails, so the caller keeps the block path. */
#ifndef CB_PD_MATRIX_H
#define CB_PD_MATRIX_H

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>
#include <clothbench/sparse.h>

/* Allocates the block P (free with cb_sparse_free) and fills its values. */
int cb_pd_matrix_build(const cb_scene *s, double dt, int with_constant, cb_sparse *P);

/* A status of cb_pd_matrix_build_scalar: a constant-Hessian block is not s I_3. */
enum { CB_PD_NOT_KRONECKER = 1 };

/* 1 if every 3x3 block of the block matrix A with values val is s I_3 for some s (exactly), else 0; *bad (if not
 * NULL) gets the first failing block column, or -1. */
int cb_pd_matrix_is_kronecker(const cb_sparse *A, const double *val, int *bad);

/* Allocates the scalar n x n P (nfree x nfree; free with cb_sparse_free) and fills its values; CB_PD_NOT_KRONECKER
 * (P left empty) if with_constant and the system's constant Hessian is not of the form P (x) I_3. */
int cb_pd_matrix_build_scalar(const cb_scene *s, double dt, int with_constant, cb_sparse *P);

/* The global solve of pd, pd-chebyshev and lbfgs with their constant P. */
typedef struct cb_pd_global {
  int path;      /* CB_GLOBAL_SCALAR or CB_GLOBAL_BLOCK (integrator.h) */
  int nf;        /* free vertices */
  cb_sparse P;   /* n x n (scalar) or 3n x 3n (block) */
  cb_solver *s;  /* the scalar path's own n x n solver; NULL on the block path (it uses the integrator's) */
  double *B, *X; /* scalar: 3 nf each, the right-hand sides and the solutions as 3 columns (x, y, z) */
} cb_pd_global;

/* Builds P and factorises it, once. The scalar path is taken when `matrix` is CB_PD_MATRIX_AUTO, the integrator's
 * solver is a direct one with a multi-column solve (CHOLMOD) and P is of the form P (x) I_3; otherwise the block
 * path on the integrator's solver. Neither path computes the solver's per-solve residual (solver.residual = 0):
 * nothing reads it, and it cost one product with P inside every timed solve. */
int cb_pd_global_init(cb_pd_global *g, cb_integrator *it, int with_constant, int matrix);
/* P X = B for X over the free DOFs, interleaved (x0 y0 z0 x1 ...) as the integrators hold them; x holds the initial
 * guess of an iterative solver. Adds the solve's time, iterations and status to st. Returns the solver's status. */
int cb_pd_global_solve(cb_pd_global *g, cb_integrator *it, const double *b, double *x, cb_step_stats *st);
void cb_pd_global_free(cb_pd_global *g);

#endif
