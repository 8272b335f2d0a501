/* Counting degrees of freedom under hard constraints (claims T2 and L2;
 * experiments/topology and experiments/locking), and the irregular test
 * disk both count on.
 *
 * A bar framework: n points in 3D and bars (i, j) held at constant length.
 * Its infinitesimal motions are the null space of the rigidity matrix R
 * (row b = d/dx of |x_i - x_j| up to scale: x_ij^T at i, -x_ij^T at j), so
 *   DoFs = 3 n - rank(R),
 * computed by GSL's SVD (singular values above 1e-9 x the largest count),
 * at a generic embedding: callers jitter the positions out of the plane (a
 * flat framework has extra out-of-plane flexes). */
#ifndef CB_RIGIDITY_H
#define CB_RIGIDITY_H

#include <clothbench/mesh.h>

/* 3 n - rank of the rigidity matrix of bars bar[2b], bar[2b+1] (b < nbars)
 * between the n points x (3n); -1 if the SVD fails or is not possible
 * (GSL needs 3n >= nbars: more bars than coordinates are always dependent). */
int cb_rigidity_dofs(int n, const double *x, int nbars, const int *bar);

/* Irregular disk: a centre vertex and rings r = 1..rings of round(6.5 r)
 * vertices at radius r (m), each ring zipped to the previous one by angle,
 * so valences vary (5, 6, 7, ...). In the xy plane, counter-clockwise. */
int cb_ring_disk(int rings, cb_mesh *m);

/* English & Bridson's nonconforming discretisation of mesh m: one variable
 * per edge (its midpoint at positions x), and each triangle rigid, i.e. bars
 * between the three midpoints of its edges (3 per triangle). Fills *nbars and
 * a malloc'd bar list over edge indices of topology edges edge[2 ne]; the
 * midpoints go to mid (3 ne, caller's). */
int cb_nonconforming_bars(const cb_mesh *m, const double *x, int ne, const int *edge, double *mid, int **bar,
                          int *nbars);

#endif
