/* Gravity term.
 *   E = -sum_i m_i g . x_i,   dE/dx_i = -m_i g,   Hessian = 0.
 * Source: DESIGN.md, "The physical model" (the force m_i g). */
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>

#include "nl_kernel.h"

typedef struct {
  cb_term base;
  double g[3]; /* m/s^2 */
} gravity_term;

static double gravity_energy(const cb_term *t, const double *x, double *grad) {
  const gravity_term *s = (const gravity_term *)t;
  const double *m = t->model->mass;
  double E = 0.0;
  for (int i = 0; i < t->model->mesh->nv; i++) {
    E -= m[i] * (s->g[0] * x[3 * i] + s->g[1] * x[3 * i + 1] + s->g[2] * x[3 * i + 2]);
    if (grad)
      for (int a = 0; a < 3; a++) grad[3 * i + a] -= m[i] * s->g[a]; /* dE/dx_i = -m_i g */
  }
  return E;
}

static void gravity_free(cb_term *t) { free(t); }

/* Example: a gravity that is not along an axis. */
static int gravity_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  return cb_gravity_term_alloc(m, (const double[3]){0.5, -9.8, 1.25}, out);
}

const cb_term_type cb_term_gravity_type = {
    .name = "gravity", .energy = gravity_energy, .free = gravity_free, .nexamples = 1, .example = gravity_example};
const cb_term_type *const cb_term_gravity = &cb_term_gravity_type;

int cb_gravity_term_alloc(const cb_model *m, const double g[3], cb_term **out) {
  gravity_term *s = cb_calloc(1, sizeof *s);
  *out = NULL;
  if (!s) return CB_ENOMEM;
  s->base.type = &cb_term_gravity_type;
  s->base.model = m;
  strcpy(s->base.label, "gravity");
  memcpy(s->g, g, sizeof s->g);
  *out = &s->base;
  return CB_OK;
}

int cb_gravity_term_vector(const cb_term *t, double g[3]) {
  if (!t || t->type != &cb_term_gravity_type)
    return cb_fail("term '%s' is not a gravity term", t ? t->label : "(null)");
  memcpy(g, ((const gravity_term *)t)->g, 3 * sizeof(double));
  return CB_OK;
}
