/* Gravity term.
 *   E = -sum_i m_i g . x_i,   dE/dx_i = -m_i g,   Hessian = 0.
 * Source: DESIGN.md, "The physical model" (the force m_i g). */
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>

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

static const cb_term_type gravity_type = {"gravity", gravity_energy, NULL, NULL, NULL, gravity_free};
const cb_term_type *const cb_term_gravity = &gravity_type;

int cb_gravity_term_alloc(const cb_model *m, const double g[3], cb_term **out) {
  gravity_term *s = cb_calloc(1, sizeof *s);
  *out = NULL;
  if (!s) return CB_ENOMEM;
  s->base.type = &gravity_type;
  s->base.model = m;
  strcpy(s->base.label, "gravity");
  memcpy(s->g, g, sizeof s->g);
  *out = &s->base;
  return CB_OK;
}
