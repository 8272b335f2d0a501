/* The nonlinear iterations' kernel as it was before the structure-of-arrays
 * kernel (lib/core/energy/nl_kernel.h): kept here, in the bench only, so that
 * bench_nonlinear can time the old and the new kernel in the same run,
 * interleaved, and check that they agree. */
#ifndef CB_BENCH_NL_OLD_H
#define CB_BENCH_NL_OLD_H

#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>
#include <clothbench/system.h>
#include <clothbench/timer.h>

typedef struct {
  const cb_scene *s;
  cb_objective obj;
  double *grad, *gF, *xprev, *dinv; /* 3nv, 3nf, 3nv, nf */
  double dt, alpha, rho, damping;
  int iters;
} cb_old_lab;

/* The lab frame's integrator (chebyshev-nl, diagonal lab, fixed rho) of
 * scene s with its config's dt, damping, iters, alpha and rho. The scene may
 * hold linear spring terms and gravity only. 0 or -1 (cb_error_message). */
int cb_old_lab_init(cb_old_lab *o, const cb_scene *s, double dt, double damping, int iters, double alpha, double rho);
/* One step, the old way: what cb_integrator_step did, its F and |grad F(x_K)|/|grad F(xhat)| out. */
int cb_old_lab_step(cb_old_lab *o, double *x, double *v, double *F, double *rel_grad);
void cb_old_lab_free(cb_old_lab *o);

#endif
