/* Explicit symplectic Euler (lecture, "Explicit Integration of A Mass-Spring
 * System"):
 *   v_i <- v_i + dt f_i(x) / m_i,   f = -dE/dx
 *   x_i <- x_i + dt v_i
 * for free vertices; pinned ones keep their prescribed v (0 unless
 * scene.pin_squeeze drives them) and move by x <- x + dt v. It is stable only while
 * dt < 2 / omega_max, omega_max^2 = lambda_max(M^-1 K).
 * It reads only the generic parameters (dt): no parameters of its own, no
 * linear solver, no Hessian. */
#include <math.h>
#include <stdlib.h>

#include <clothbench/integrator.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

typedef struct {
  double *grad; /* 3*nv */
} explicit_work;

static int ex_init(cb_integrator *it) {
  explicit_work *w = it->state;
  w->grad = cb_malloc((size_t)3 * it->scene->mesh.nv, sizeof(double));
  return w->grad ? CB_OK : CB_ENOMEM;
}

static int ex_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  explicit_work *w = it->state;
  const cb_scene *s = it->scene;
  double dt = it->params.dt, t0 = cb_now_ms();
  cb_system_energy(it->sys, x, w->grad, NULL);
  st->assemble_ms = cb_now_ms() - t0;
  int bad = 0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    double inv_m = 1.0 / s->mass[i];
    for (int a = 0; a < 3; a++) {
      v[3 * i + a] -= dt * inv_m * w->grad[3 * i + a]; /* v += dt M^-1 f */
      x[3 * i + a] += dt * v[3 * i + a];               /* x += dt v (new v) */
      bad |= !isfinite(x[3 * i + a]) || !isfinite(v[3 * i + a]);
    }
  }
  for (int k = 0; k < s->npinned; k++) /* prescribed pin motion: x += dt v */
    for (int a = 0; a < 3; a++) x[3 * s->pinned[k] + a] += dt * v[3 * s->pinned[k] + a];
  return bad ? CB_DIVERGED : CB_OK;
}

static void ex_free(cb_integrator *it) {
  explicit_work *w = it->state;
  free(w->grad);
}

const cb_integrator_type cb_integrator_explicit = {
    .name = "explicit",
    .flags = 0,
    .size = sizeof(explicit_work),
    .params_size = 0,
    .params_default = NULL,
    .keys = NULL,
    .init = ex_init,
    .step = ex_step,
    .free = ex_free,
};
