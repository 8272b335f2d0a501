/* `penalty` (contact.h): a quadratic penalty on pairs closer than the
 * thickness h, without CCD (the baseline that can tunnel, issue 34 C1).
 *
 *   E = k/2 (h - d)^2 for d < h,  0 beyond,   d = sqrt(s), s the pair's squared distance.
 * As a function of s (the pair term differentiates through s, contact_term.c):
 *   f(s)   = k/2 (h - sqrt s)^2,
 *   f'(s)  = -k (h - sqrt s) / (2 sqrt s),
 *   f''(s) = k h / (4 s^(3/2)).
 * f and f' vanish at s = h^2 (E is C^1 across the thickness; f'' jumps). The
 * pair's Hessian f'' g_s g_s^T + f' H_s is indefinite (f' < 0) and is
 * projected per pair. At d = 0 (primitives touching) the direction is lost:
 * the pair adds k h^2 / 2 with no gradient (a documented clamp, as the
 * sphere collider's centre; never a NaN). */
#include <math.h>

#include "contact_keys.h"
#include "contact_term.h"
#include <clothbench/status.h>

extern const cb_term_type cb_term_contact_penalty_type;

static double penalty_f(const cb_contact_params *p, double s, double *ds, double *dss) {
  double h = p->thickness, k = p->stiffness;
  if (!(s > 0)) {
    *ds = *dss = 0;
    return 0.5 * k * h * h;
  }
  double d = sqrt(s);
  *ds = -k * (h - d) / (2 * d);
  *dss = k * h / (4 * s * d);
  return 0.5 * k * (h - d) * (h - d);
}

static int penalty_alloc(const cb_model *m, const cb_contact_params *p, cb_term **out) {
  *out = NULL;
  int st = cb_contact_params_check("penalty", p);
  if (st) return st;
  if (!(p->stiffness > 0) || !isfinite(p->stiffness))
    return cb_fail("contact.stiffness: must be > 0 (N/m), got %g", p->stiffness);
  if (p->friction > 0)
    return cb_fail("contact.friction: %g: the penalty has no friction (only 0 is accepted); contact.method = ipc has "
                   "lagged Coulomb friction",
                   p->friction);
  return cb_contact_term_alloc(m, &cb_term_contact_penalty_type, p, penalty_f, p->thickness, 0, 0, out);
}

static int penalty_example(const cb_model *m, int i, cb_term **out) {
  cb_contact_params p = cb_contact_params_default();
  p.thickness = 0.3;
  p.stiffness = 5000;
  return cb_contact_example(m, i, &cb_term_contact_penalty_type, penalty_f, 0, 0, &p, out);
}

const cb_term_type cb_term_contact_penalty_type = {.name = "contact_penalty",
                                                   .energy = cb_contact_energy,
                                                   .pattern = cb_contact_pattern,
                                                   .bind = cb_contact_bind,
                                                   .hessian = cb_contact_hessian,
                                                   .free = cb_contact_free,
                                                   .nexamples = 2,
                                                   .example = penalty_example,
                                                   .indefinite = cb_contact_indefinite,
                                                   .vertex_collect = cb_contact_vertex_collect,
                                                   .vertex_blocks = cb_contact_vertex_blocks,
                                                   .vertex_bound = cb_contact_vertex_bound,
                                                   .intersections = cb_contact_term_intersections};

static const cb_param_key penalty_keys[] = {
    CB_KEY_CONTACT_THICKNESS,
    CB_KEY_CONTACT_FRICTION,
    CB_KEY_CONTACT_STIFFNESS,
    CB_KEY_CONTACT_END,
};

const cb_contact_type cb_contact_penalty = {.name = "penalty", .keys = penalty_keys, .term_alloc = penalty_alloc};
