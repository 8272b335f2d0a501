/* `ipc` (contact.h): the log barrier of Li et al. 2020 (Incremental Potential
 * Contact, section 4) on the squared distance, with the edge-edge mollifier,
 * and CCD step bounds for the minimisers' line search.
 *
 * With s = d^2 and sh = dhat^2 (dhat = contact.thickness), per pair
 *   b(s)   = -(s - sh)^2 ln(s / sh)                            for 0 < s < sh, 0 beyond,
 *   b'(s)  = -2 (s - sh) ln(s / sh) - (s - sh)^2 / s,
 *   b''(s) = -2 ln(s / sh) - 4 (s - sh) / s + (s - sh)^2 / s^2,
 * and E = kappa sum_pairs e_p b(s_p), e_p the mollifier e_x(c) of nearly
 * parallel edges (distance.h; 1 for point-triangle pairs). b, b' vanish at s =
 * sh, so E is C^1 where pairs enter; b -> +inf as s -> 0, so no pair reaches
 * contact on a path of finite energy. This is IPC's barrier on the squared
 * distance as its code writes it (the paper's b(d) with d^2 and dhat^2 in
 * place of d and dhat). The pair Hessian is projected per pair (12 x 12).
 * At s <= 0 (touching, or a start that already intersects) E = +inf: the line
 * search never accepts such a point, and the CCD bound never leads to one.
 *
 * With contact.friction mu > 0 the term also carries lagged, smoothed
 * Coulomb friction (Li et al. 2020, section 5; contact.epsv the smoothing
 * velocity eps_v), frozen at every step's start by the type's begin_step:
 * the formulas are in contact_term.c ("Friction"). */
#include <math.h>

#include "contact_keys.h"
#include "contact_term.h"
#include <clothbench/status.h>

extern const cb_term_type cb_term_contact_ipc_type;

static double ipc_f(const cb_contact_params *p, double s, double *ds, double *dss) {
  double sh = p->thickness * p->thickness, k = p->kappa;
  if (!(s > 0)) {
    *ds = *dss = 0;
    return INFINITY;
  }
  double r = s - sh, l = log(s / sh);
  *ds = k * (-2 * r * l - r * r / s);
  *dss = k * (-2 * l - 4 * r / s + r * r / (s * s));
  return -k * r * r * l;
}

static int ipc_alloc(const cb_model *m, const cb_contact_params *p, cb_term **out) {
  *out = NULL;
  int st = cb_contact_params_check("ipc", p);
  if (st) return st;
  if (!(p->kappa > 0) || !isfinite(p->kappa)) return cb_fail("contact.kappa: must be > 0 (J/m^4), got %g", p->kappa);
  return cb_contact_term_alloc(m, &cb_term_contact_ipc_type, p, ipc_f, p->thickness, 1, 1, out);
}

/* Examples 0 and 1 are the pair term's (contact_term.h); 2 is example 0 with friction mu = 0.8, frozen at the
 * model's rest shape with eps_v dt = 0.1 m (eps_v = 1 m/s, dt = 0.1 s), so that the test's states (0.02-0.15 m
 * from rest) put pairs on both sides of the smoothing's eps_v dt. */
static int ipc_example(const cb_model *m, int i, cb_term **out) {
  cb_contact_params p = cb_contact_params_default();
  p.thickness = 0.3;
  p.kappa = 1e4;
  if (i < 2) return cb_contact_example(m, i, &cb_term_contact_ipc_type, ipc_f, 1, 1, &p, out);
  p.friction = 0.8;
  p.epsv = 1;
  int st = cb_contact_example(m, 0, &cb_term_contact_ipc_type, ipc_f, 1, 1, &p, out);
  if (!st) st = cb_contact_term_begin_step(*out, m->mesh->x, 0.1);
  if (st && *out) {
    cb_term_free(*out);
    *out = NULL;
  }
  return st;
}

const cb_term_type cb_term_contact_ipc_type = {.name = "contact_ipc",
                                               .energy = cb_contact_energy,
                                               .pattern = cb_contact_pattern,
                                               .bind = cb_contact_bind,
                                               .hessian = cb_contact_hessian,
                                               .free = cb_contact_free,
                                               .max_step = cb_contact_max_step,
                                               .nexamples = 3,
                                               .example = ipc_example,
                                               .indefinite = cb_contact_indefinite,
                                               .begin_step = cb_contact_term_begin_step,
                                               .vertex_collect = cb_contact_vertex_collect,
                                               .vertex_blocks = cb_contact_vertex_blocks,
                                               .vertex_bound = cb_contact_vertex_bound,
                                               .intersections = cb_contact_term_intersections};

static const cb_param_key ipc_keys[] = {
    CB_KEY_CONTACT_THICKNESS,
    CB_KEY_CONTACT_FRICTION,
    {.name = "kappa",
     .kind = CB_PARAM_DOUBLE,
     .offset = CB_CKEY(kappa),
     .def = "1e8",
     .unit = "J/m^4",
     .lo = 0,
     .hi = 1e30,
     .lo_open = 1,
     .doc = "Barrier stiffness kappa of contact.method = ipc: E = kappa b(d^2) per pair closer than the thickness "
            "dhat, b(s) = -(s - dhat^2)^2 ln(s / dhat^2)."},
    {.name = "epsv",
     .kind = CB_PARAM_DOUBLE,
     .offset = CB_CKEY(epsv),
     .def = "1e-3",
     .unit = "m/s",
     .lo = 0,
     .hi = 1e9,
     .lo_open = 1,
     .doc = "Friction's smoothing velocity eps_v of contact.method = ipc (Li et al. 2020, section 5): a contact whose "
            "tangential displacement over the step is below eps_v dt is in the smoothed, static-like branch of "
            "f1(y) = 2 y/(eps_v dt) - y^2/(eps_v dt)^2; above it, Coulomb's sliding force mu lambda."},
    CB_KEY_CONTACT_END,
};

const cb_contact_type cb_contact_ipc = {.name = "ipc", .keys = ipc_keys, .term_alloc = ipc_alloc, .friction = 1};
