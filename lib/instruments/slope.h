/* The slope measurement (issue 34 §2-3, claim C2; docs/contact.md,
 * "Friction"): cloth resting on a plane tilted by theta, with Coulomb
 * friction mu, run for a given time; how far its centre of mass slid. On a
 * scene of configs/slope.ini's kind (a contact response with friction, the
 * slope's frame: scene.slope turns gravity about z, so downhill is +x).
 *
 * The reference is the sliding block: with mu < tan theta it slides with
 * a = g (sin theta - mu cos theta), s(t) = a t^2 / 2; with mu >= tan theta it
 * stays. The threshold finder bisects mu on "slid more than s_tol in t_end"
 * and gives mu*, to compare with tan theta. An instrument: it observes runs
 * and never steers one. */
#ifndef CB_SLOPE_H
#define CB_SLOPE_H

#include "config.h"

typedef struct cb_slope_run {
  double slide;        /* m: the centre of mass's displacement along the slope (+x) from t = 0 to t_end */
  double drift;        /* m: its displacement normal to the slope (y) */
  double closed_form;  /* m: the sliding block's a t^2 / 2 at t_end (0 when mu >= tan theta) */
  int steps;           /* steps taken */
  int not_converged;   /* steps whose minimiser stopped at its iteration limit (their state is kept) */
  long friction_pairs; /* friction pairs frozen at the last step's start (0 without friction) */
  long newton_iters;   /* iterations over all steps */
  double wall_ms;      /* wall time of the steps */
} cb_slope_run;

/* Runs c with scene.slope = theta_deg (degrees) and contact.friction = mu for
 * t_end seconds (ceil(t_end / integrator.dt) steps) from its start state.
 * Errors: the scene's or the integrator's (naming the key), a bad argument
 * ("slope: ..."), or the first step that fails (not converged is no failure:
 * counted). */
int cb_slope_slide(const cb_config *c, double theta_deg, double mu, double t_end, cb_slope_run *r);

typedef struct cb_slope_threshold {
  double mu_star;  /* the stick-slip threshold: the middle of the last bracket; NaN when not bracketed */
  double lo, hi;   /* the last bracket: slides at lo (slide > s_tol), holds at hi */
  double slide_lo; /* m: the slide at lo */
  double slide_hi; /* m: the slide at hi (the creep of a holding cloth) */
  int bracketed;   /* 0: mu = 0 did not slide or mu = mu_max did not hold (then mu_star is NaN) */
  int runs;        /* cb_slope_slide calls */
  double wall_ms;  /* their wall time */
} cb_slope_threshold;

/* The threshold mu* for theta_deg: bisects mu in [0, mu_max] on slide(mu) >
 * s_tol after t_end until hi - lo <= rtol tan theta. mu_max > 0, s_tol > 0,
 * 0 < rtol < 1, 0 < theta_deg < 90. */
int cb_slope_find_threshold(const cb_config *c, double theta_deg, double t_end, double s_tol, double mu_max,
                            double rtol, cb_slope_threshold *out);

#endif
