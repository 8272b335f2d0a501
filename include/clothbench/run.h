/* A trajectory: a scene, an integrator and the state, stepped with the
 * bookkeeping every program needs (energies, time, divergence detection).
 *
 * Divergence: after a step the integrator did not fail (ok or
 * not_converged), a NaN/Inf position, velocity or energy, or a total energy
 * (kinetic + elastic + gravity potential) above its initial value plus the
 * work W done by driven pins (scene.pin_squeeze) by more than
 * integrator.diverge_ratio x S, where S is the scene's energy scale
 * (cb_scene.energy_scale) plus the initial kinetic energy. Implicit Euler
 * only loses energy, and a stable explicit run oscillates well inside that
 * bound. An integrator flagged CB_INTEGRATOR_OWN_ELASTICITY (shape matching)
 * is held to kinetic + gravity only, the scene's elastic terms being no part
 * of its model. A step the integrator failed (not_spd, linear_failed, ...) keeps
 * its own status. The reason for `diverged` (which test, at which step) is
 * the error message (cb_error_message).
 *
 * The pins' work: a driven pin i moves at its constant velocity v_i, so the
 * force it exerts on the cloth balances the internal force there and its
 * power is P = sum_i dE/dx_i . v_i; W integrates P over the steps by the
 * trapezoid rule. */
#ifndef CB_RUN_H
#define CB_RUN_H

#include <stdio.h>

#include "integrator.h"
#include "scene.h"

typedef struct cb_run {
  cb_scene *scene;
  cb_integrator *integ;
  double *x, *v; /* current state, 3*nv */
  int step;
  double t;                                    /* s */
  double kinetic, potential, elastic, gravity; /* J, at the current state; potential = elastic + gravity */
  double total0;                               /* initial total energy, J */
  double bound;                                /* divergence bound on total - total0 - work, J */
  int driven;                                  /* some pinned vertex moves (scene.pin_squeeze) */
  double work;                                 /* work the driven pins did on the cloth so far, J */
  double power;                                /* their power at the current state, W */
  double *grad;                                /* 3*nv scratch for dE/dx (driven scenes only) */
  cb_step_stats last;                          /* of the last step */
} cb_run;

/* Starts from the scene's initial state. last.status is the status of
 * that state (row 0): CB_OK, or CB_DIVERGED if it is not finite. */
int cb_run_init(cb_run *r, cb_scene *s, cb_integrator *it);
void cb_run_free(cb_run *r);

/* One step; returns its status (CB_DIVERGED also for the energy bound). */
int cb_run_step(cb_run *r);

#endif
