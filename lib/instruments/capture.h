/* Capture of a real Newton system from a running simulation.
 *
 * The linear-solver experiments need the matrices Newton actually meets:
 * A = M/dt^2 + H(x) and b = -grad F(x) at some iterate x of some time step,
 * not only at rest. cb_capture_newton_system simulates a scene with its
 * configured integrator (implicit Euler by Newton) and, through the Newton
 * hook (CB_NEWTON_SYSTEM), copies the values of A and b assembled in Newton
 * iteration `iter` of time step `step`. The sparsity pattern is fixed per
 * scene, so a copy of the values suffices: the captured matrix borrows its
 * pattern from the scene, which the capture keeps alive. */
#ifndef CB_CAPTURE_H
#define CB_CAPTURE_H

#include "config.h"
#include <clothbench/scene.h>
#include <clothbench/sparse.h>

typedef struct cb_capture {
  cb_scene *scene; /* owned; A's pattern arrays belong to scene->sys.A */
  cb_sparse A;     /* the captured matrix: scene's pattern, own values (A.val) */
  double *b;       /* right-hand side -grad F over the free DOFs, A.n */
  double *x;       /* positions of the captured Newton iterate, 3*nv, m */
  int step;        /* time step captured (0-based: step s runs from t = s dt) */
  int iter;        /* Newton iteration captured (0 = the first system of the step) */
  double t_s;      /* simulated time at the start of the captured step, s */
  double sim_ms;   /* wall time of the simulation up to the capture, ms */
} cb_capture;

/* Builds cfg's scene and integrator, steps until the system of Newton
 * iteration `iter` of step `step` has been assembled, copies it, and stops.
 * Returns CB_OK; a positive status if the run failed before the capture
 * (diverged, not SPD, ...) or the step ended before iteration `iter`
 * (CB_NOT_CONVERGED); negative on bad input or memory. */
int cb_capture_newton_system(const cb_config *cfg, int step, int iter, cb_capture *out);
void cb_capture_free(cb_capture *c);

/* Diagonal dominance of a symmetric matrix: the number of rows with
 * a_ii < sum_{j != i} |a_ij| (not weakly dominant), and the largest
 * ratio sum_{j != i} |a_ij| / a_ii over the rows. */
void cb_diag_dominance(const cb_sparse *A, int *violating_rows, double *max_ratio);

#endif
