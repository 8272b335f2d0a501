#include <clothbench/run.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

/* Energies of the current state; with driven pins also the power they put
 * in, P = sum over pinned i of dE/dx_i . v_i (the force a pin exerts on the
 * cloth balances the internal force there, -dE/dx_i, since a driven pin does
 * not accelerate). */
static void energies(cb_run *r, double *power) {
  double per[CB_MAX_TERMS];
  r->potential = cb_system_energy(&r->scene->sys, r->x, r->driven ? r->grad : NULL, per);
  r->elastic = r->gravity = 0;
  for (int k = 0; k < r->scene->sys.nterms; k++) {
    if (r->scene->sys.terms[k]->type->hessian) r->elastic += per[k];
    else r->gravity += per[k];
  }
  r->kinetic = cb_scene_kinetic(r->scene, r->v);
  *power = 0;
  if (r->driven)
    for (int k = 0; k < r->scene->npinned; k++) {
      int i = r->scene->pinned[k];
      for (int a = 0; a < 3; a++) *power += r->grad[3 * i + a] * r->v[3 * i + a];
    }
}

/* The status of the current state: CB_DIVERGED (with the reason as the
 * error message) if a position, velocity or energy is not finite, else CB_OK. */
static int finite_state(const cb_run *r) {
  int n = r->scene->mesh.nv;
  for (int i = 0; i < 3 * n; i++)
    if (!isfinite(r->x[i]) || !isfinite(r->v[i]))
      return cb_fail_status(CB_DIVERGED, "vertex %d's %s is %g, not finite", i / 3,
                            isfinite(r->x[i]) ? "velocity" : "position", isfinite(r->x[i]) ? r->v[i] : r->x[i]);
  double total = r->kinetic + r->potential;
  if (!isfinite(total))
    return cb_fail_status(CB_DIVERGED, "the total energy is %g J (kinetic %g, elastic %g, gravity %g), not finite",
                          total, r->kinetic, r->elastic, r->gravity);
  return CB_OK;
}

/* The energy the divergence bound follows: kinetic + potential, less the
 * elastic terms for an integrator that replaces them (shape matching). */
static double tracked(const cb_run *r) {
  int own = (r->integ->type->flags & CB_INTEGRATOR_OWN_ELASTICITY) != 0;
  return r->kinetic + r->potential - (own ? r->elastic : 0.0);
}

int cb_run_init(cb_run *r, cb_scene *s, cb_integrator *it) {
  memset(r, 0, sizeof *r);
  size_t n3 = (size_t)3 * s->mesh.nv;
  r->scene = s;
  r->integ = it;
  for (int k = 0; k < s->npinned; k++)
    for (int a = 0; a < 3; a++) r->driven |= s->v0[3 * s->pinned[k] + a] != 0;
  r->x = cb_malloc(n3, sizeof(double));
  r->v = cb_malloc(n3, sizeof(double));
  if (r->driven) r->grad = cb_malloc(n3, sizeof(double));
  if (!r->x || !r->v || (r->driven && !r->grad)) {
    cb_run_free(r);
    return CB_ENOMEM;
  }
  memcpy(r->x, s->x0, n3 * sizeof(double));
  memcpy(r->v, s->v0, n3 * sizeof(double));
  energies(r, &r->power);
  r->total0 = tracked(r);
  r->bound = s->diverge_ratio * (s->energy_scale + r->kinetic);
  r->last.status = finite_state(r); /* row 0 is ok only if it is finite */
  return CB_OK;
}

void cb_run_free(cb_run *r) {
  free(r->x);
  free(r->v);
  free(r->grad);
  r->x = r->v = r->grad = NULL;
}

int cb_run_step(cb_run *r) {
  cb_error_clear(); /* so that a status without a reason can be told apart */
  int st = cb_integrator_step(r->integ, r->x, r->v, &r->last);
  r->step++;
  r->t = r->step * r->integ->params.dt;
  double p0 = r->power;
  energies(r, &r->power);
  r->work += 0.5 * r->integ->params.dt * (p0 + r->power); /* trapezoid rule for the pins' work */
  /* The integrator's own status wins: after a failed solve the state is
   * whatever the failure left, and testing it would call the failure a
   * divergence. */
  if (st == CB_DIVERGED && !cb_error_message()[0]) { /* an integrator's NaN test: name what is not finite */
    int fs = finite_state(r);
    if (fs == CB_OK)
      cb_fail_status(CB_DIVERGED,
                     "%s: a value inside the step (objective, gradient or update) is not finite, "
                     "although the state is",
                     r->integ->type->name);
  }
  if (!cb_status_is_fatal(st)) {
    int fs = finite_state(r);
    double gain = tracked(r) - r->total0 - r->work;
    if (fs) st = fs;
    else if (gain > r->bound)
      st = cb_fail_status(CB_DIVERGED,
                          "energy bound: the total energy rose by %.6g J above its initial "
                          "value%s, more than integrator.diverge_ratio x S = %g x %.6g J = %.6g J",
                          gain, r->driven ? " less the driven pins' work" : "", r->scene->diverge_ratio,
                          r->bound / r->scene->diverge_ratio, r->bound);
  }
  r->last.status = st;
  return st;
}
