/* C2's sweep of the contact experiment (c2.c): the stick-slip threshold of ipc's friction on the slope. */
#ifndef CONTACT_C2_H
#define CONTACT_C2_H

#include <stdio.h>

#include "experiment.h"

typedef struct {
  cb_experiment *e;
  const double *theta; /* degrees */
  int ntheta;
  double t_end; /* s: each run's simulated time */
} contact_c2_plan;

#define CONTACT_C2_COLUMNS \
  "kind,integrator,theta_deg,tan_theta,mu,mu_over_tan,slide_m,closed_form_m,drift_m,steps,not_converged,mu_star," \
  "mu_lo,mu_hi,creep_m,runs,wall_ms,note,status"

/* Cell i: theta[i]; rows into out[table]. */
int contact_c2_cell(const contact_c2_plan *p, long i, FILE *f);

#endif
