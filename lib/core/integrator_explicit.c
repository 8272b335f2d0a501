/* Explicit symplectic Euler (lecture, "Explicit Integration of A Mass-Spring
 * System"):
 *   v_i <- v_i + dt f_i(x) / m_i,   f = -dE/dx
 *   x_i <- x_i + dt v_i
 * for free vertices; pinned ones keep their prescribed v (0 unless
 * scene.pin_squeeze drives them) and move by x <- x + dt v. It is stable only while
 * dt < 2 / omega_max, omega_max^2 = lambda_max(M^-1 K). */
#include <math.h>
#include <stdlib.h>

#include <clothbench/integrator.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

typedef struct {
  double *grad; /* 3*nv */
} explicit_work;

static int ex_alloc(cb_integrator *it) {
  explicit_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  w->grad = cb_malloc((size_t)3 * it->scene->mesh.nv, sizeof(double));
  if (!w->grad) { free(w); return CB_ENOMEM; }
  it->work = w;
  return CB_OK;
}

static int ex_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  explicit_work *w = it->work;
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
  explicit_work *w = it->work;
  if (!w) return;
  free(w->grad);
  free(w);
}

const cb_integrator_type cb_integrator_explicit = {"explicit", ex_alloc, ex_step, ex_free};
