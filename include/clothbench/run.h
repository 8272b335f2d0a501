/* A trajectory: a scene, an integrator and the state, stepped with the
 * bookkeeping every program needs (energies, time, divergence detection).
 *
 * Divergence: a NaN/Inf position or velocity, or a total energy
 * (kinetic + elastic + gravity potential) above its initial value by more
 * than integrator.diverge_ratio x S, where S is the scene's energy scale
 * (cb_scene.energy_scale). Implicit Euler only loses energy, and a stable
 * explicit run oscillates well inside that bound. An integrator flagged
 * CB_INTEGRATOR_OWN_ELASTICITY (shape matching) is held to kinetic + gravity
 * only, the scene's elastic terms being no part of its model. */
#ifndef CB_RUN_H
#define CB_RUN_H

#include <stdio.h>

#include "integrator.h"
#include "scene.h"

typedef struct cb_run {
  cb_scene *scene;
  cb_integrator *integ;
  double *x, *v;       /* current state, 3*nv */
  int step;
  double t;            /* s */
  double kinetic, potential, elastic; /* J, at the current state */
  double total0;       /* initial total energy, J */
  double bound;        /* divergence bound on total - total0, J */
  cb_step_stats last;  /* of the last step */
} cb_run;

/* Starts from the scene's initial state. */
int cb_run_init(cb_run *r, cb_scene *s, cb_integrator *it);
void cb_run_free(cb_run *r);

/* One step; returns its status (CB_DIVERGED also for the energy bound). */
int cb_run_step(cb_run *r);

/* Per-step CSV: the header row and one row of the current state. */
void cb_run_csv_header(FILE *f);
void cb_run_csv_row(FILE *f, const cb_run *r, int status);

#endif
