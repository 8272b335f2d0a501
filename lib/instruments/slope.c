/* The slope measurement (slope.h). The centre of mass is the mass-weighted
 * mean of the vertices, c = sum m_i x_i / sum m_i; the slide is c_x(t_end) -
 * c_x(0) (downhill is +x in the slope's frame, scene.slope). The sliding
 * block's closed form: a = g (sin theta - mu cos theta) with g = |gravity|,
 * s = a t^2 / 2 for a > 0, else 0. The threshold: bisection of mu on the
 * predicate slide(mu) > s_tol, which is monotone for Coulomb friction (more
 * friction, less slide). */
#include "slope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

#include "bind.h"

static void centre(const cb_scene *s, const double *x, double *c) {
  double m = 0;
  c[0] = c[1] = c[2] = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    m += s->model.mass[i];
    for (int a = 0; a < 3; a++) c[a] += s->model.mass[i] * x[3 * i + a];
  }
  for (int a = 0; a < 3; a++) c[a] /= m > 0 ? m : 1;
}

static int set_number(cb_config *c, const char *key, double v) {
  char buf[128];
  int n = snprintf(buf, sizeof buf, "%s=%.17g", key, v);
  if (n < 0 || (size_t)n >= sizeof buf) return cb_fail("slope: %s: the assignment does not fit", key);
  return cb_config_set(c, buf);
}

int cb_slope_slide(const cb_config *c0, double theta_deg, double mu, double t_end, cb_slope_run *r) {
  memset(r, 0, sizeof *r);
  if (!(theta_deg >= 0 && theta_deg < 90)) return cb_fail("slope: theta = %g degrees, not in [0, 90)", theta_deg);
  if (!(mu >= 0) || !isfinite(mu)) return cb_fail("slope: mu = %g, not >= 0", mu);
  if (!(t_end > 0) || !isfinite(t_end)) return cb_fail("slope: t_end = %g s, not > 0", t_end);
  cb_config *c = malloc(sizeof *c);
  if (!c) return cb_fail_status(CB_ENOMEM, "slope: out of memory");
  *c = *c0;
  int st = set_number(c, "scene.slope", theta_deg);
  if (!st) st = set_number(c, "contact.friction", mu);
  cb_scene *s = NULL;
  cb_integrator *it = NULL;
  double *x = NULL, *v = NULL;
  if (!st) st = cb_scene_from_config(c, &s);
  if (!st) st = cb_integrator_from_config(c, s, NULL, &it);
  if (!st) {
    x = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
    v = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
    if (!x || !v) st = CB_ENOMEM;
  }
  if (!st) {
    memcpy(x, s->x0, (size_t)3 * s->mesh.nv * sizeof(double));
    memcpy(v, s->v0, (size_t)3 * s->mesh.nv * sizeof(double));
    double c0x[3], c1x[3], dt = it->params.dt;
    centre(s, x, c0x);
    int steps = (int)ceil(t_end / dt - 1e-9);
    double t0 = cb_now_ms();
    for (int k = 0; k < steps && !st; k++) {
      cb_step_stats ss;
      int rs = cb_integrator_step(it, x, v, &ss);
      r->steps++;
      r->newton_iters += ss.newton_iters;
      if (rs == CB_NOT_CONVERGED) r->not_converged++;
      else if (rs != CB_OK) st = rs;
      const cb_term *ct = cb_scene_contact_term(s);
      r->friction_pairs = ct ? cb_contact_term_stats(ct)->friction_pairs : 0;
    }
    r->wall_ms = cb_now_ms() - t0;
    centre(s, x, c1x);
    r->slide = c1x[0] - c0x[0];
    r->drift = c1x[1] - c0x[1];
    double g = sqrt(s->gravity[0] * s->gravity[0] + s->gravity[1] * s->gravity[1] + s->gravity[2] * s->gravity[2]);
    double th = theta_deg * 3.14159265358979323846 / 180, a = g * (sin(th) - mu * cos(th)), T = r->steps * dt;
    r->closed_form = a > 0 ? 0.5 * a * T * T : 0;
  }
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
  free(c);
  return st;
}

int cb_slope_find_threshold(const cb_config *c, double theta_deg, double t_end, double s_tol, double mu_max,
                            double rtol, cb_slope_threshold *out) {
  memset(out, 0, sizeof *out);
  out->mu_star = NAN;
  if (!(theta_deg > 0 && theta_deg < 90)) return cb_fail("slope: theta = %g degrees, not in (0, 90)", theta_deg);
  if (!(s_tol > 0) || !isfinite(s_tol)) return cb_fail("slope: s_tol = %g m, not > 0", s_tol);
  if (!(mu_max > 0) || !isfinite(mu_max)) return cb_fail("slope: mu_max = %g, not > 0", mu_max);
  if (!(rtol > 0 && rtol < 1)) return cb_fail("slope: rtol = %g, not in (0, 1)", rtol);
  double width = rtol * tan(theta_deg * 3.14159265358979323846 / 180);
  cb_slope_run r;
  double lo = 0, hi = mu_max;
  int st = cb_slope_slide(c, theta_deg, lo, t_end, &r);
  out->runs++;
  out->wall_ms += r.wall_ms;
  if (st) return st;
  out->slide_lo = r.slide;
  if (!(r.slide > s_tol)) return CB_OK; /* no slide without friction: not bracketed */
  if ((st = cb_slope_slide(c, theta_deg, hi, t_end, &r))) return st;
  out->runs++;
  out->wall_ms += r.wall_ms;
  out->slide_hi = r.slide;
  if (r.slide > s_tol) { /* mu_max does not hold it */
    out->lo = out->hi = hi;
    return CB_OK;
  }
  while (hi - lo > width) {
    double mid = 0.5 * (lo + hi);
    if ((st = cb_slope_slide(c, theta_deg, mid, t_end, &r))) return st;
    out->runs++;
    out->wall_ms += r.wall_ms;
    if (r.slide > s_tol) {
      lo = mid;
      out->slide_lo = r.slide;
    } else {
      hi = mid;
      out->slide_hi = r.slide;
    }
  }
  out->lo = lo;
  out->hi = hi;
  out->bracketed = 1;
  out->mu_star = 0.5 * (lo + hi);
  return CB_OK;
}
