/* Shape matching (Müller, Heidelberger, Teschner & Gross 2005, "Meshless
 * deformations based on shape matching"), an explicit integrator of its own.
 *
 * Clusters: every vertex's one-ring (the vertex and its edge neighbours in
 * the scene's topology), so the clusters overlap and couple the cloth; a
 * vertex in n_i clusters carries the weight w_i = m_i / n_i in each. For a
 * cluster c with rest positions x0_i (the rest mesh) and current ones x_i:
 *   x0_cm = sum w x0 / sum w,   x_cm = sum w x / sum w,   q_i = x0_i - x0_cm
 *   A_pq  = sum_i w_i (x_i - x_cm) q_i^T,   R = polar rotation of A_pq (polar.h,
 *           a proper rotation; planar and collinear clusters are rank deficient
 *           and handled there)
 *   g_i^c = R q_i + x_cm
 * and vertex i's goal is the mean of its clusters' goals, g_i = (1/n_i) sum_c g_i^c.
 * The step is the paper's (its eq. 2):
 *   v_i <- v_i + alpha (g_i - x_i) / dt + dt f_ext,i / m_i,   x_i <- x_i + dt v_i
 * with alpha in (0, 1] (`integrator.shape_alpha`) and f_ext = m g (scene.gravity).
 * Shape matching replaces the scene's elastic terms: the stretch and bending
 * terms are not evaluated (CB_INTEGRATOR_OWN_ELASTICITY: a run's energy bound
 * counts kinetic + gravity; its elastic_j column still reports them, as a
 * measure of how far the cloth stretches).
 * Pinned vertices follow their prescribed velocity, as in the explicit
 * integrator.
 * The penalty collider (collider.type = penalty) is an energy term like the
 * elastic ones, so shape matching would skip it and the cloth would fall
 * through the sphere while the run reports contacts: init refuses it and
 * names collider.type = project, a response applied after every step (the
 * post-step responses, cb_scene_post_step in integrator.c), which shape matching honours.
 *
 * Conservation: the weights make sum_i m_i (g_i - x_i) = sum_c sum_{i in c}
 * w_i (g_i^c - x_i) = 0, and likewise the angular term (R A_pq^T is
 * symmetric for the polar R), so without external forces and pins the goal
 * impulses conserve linear and angular momentum up to round-off
 * (tests/test_locking_models.c). Goals lie on well-defined positions, which
 * is the paper's argument for unconditional stability (claim S1, experiment
 * locking). */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/contact.h>
#include <clothbench/integrator.h>
#include <clothbench/polar.h>
#include <clothbench/status.h>

static const cb_shape_matching_params sm_defaults = {.cookie = CB_PARAMS_COOKIE, .alpha = 1.0};
cb_shape_matching_params cb_shape_matching_params_default(void) { return sm_defaults; }

static const cb_param_key sm_keys[] = {
    {.name = "shape_alpha",
     .kind = CB_PARAM_DOUBLE,
     .offset = offsetof(cb_shape_matching_params, alpha),
     .def = "1",
     .unit = "-",
     .hi = 1,
     .lo_open = 1,
     .doc = "Shape matching (`integrator.method = shape_matching`): stiffness alpha in (0, 1] of the pull toward the "
            "goal positions, v += alpha (g - x)/dt; 1 moves every vertex onto its goal in one step."},
    {.name = NULL},
};

typedef struct {
  int nc;     /* clusters (= vertices) */
  int *start; /* nc + 1: cluster c is member[start[c] .. start[c+1]) */
  int *member;
  double *w;    /* per vertex: m_i / n_i */
  double *q;    /* 3 per membership: x0_i - x0_cm */
  double *goal; /* 3*nv: sum of cluster goals */
  int *count;   /* nv: n_i */
} sm_work;

static void sm_free(cb_integrator *it) {
  sm_work *w = it->state;
  free(w->start);
  free(w->member);
  free(w->w);
  free(w->q);
  free(w->goal);
  free(w->count);
}

static int sm_init(cb_integrator *it) {
  const cb_shape_matching_params *p = it->type_params;
  if (!(p->alpha > 0 && p->alpha <= 1)) return cb_fail("integrator.shape_alpha: must be in (0, 1], got %g", p->alpha);
  sm_work *w = it->state;
  const cb_scene *s = it->scene;
  const cb_term_type *sphere = cb_term_type_find("sphere"); /* the penalty collider's term (collider.c) */
  for (int t = 0; t < s->sys.nterms; t++)
    if (s->sys.terms[t]->type == sphere)
      return cb_fail("shape matching replaces the scene's energy terms by goal positions, so it would ignore the "
                     "penalty collider's energy and the cloth would pass through the sphere: set collider.type = "
                     "project (or none) with integrator.method = shape_matching");
  for (int t = 0; t < s->sys.nterms; t++)
    if (cb_contact_term_is(s->sys.terms[t]))
      return cb_fail("shape matching replaces the scene's energy terms by goal positions, so it would ignore the "
                     "contact term (%s) and the cloth would pass through: contact.method must be none with "
                     "integrator.method = shape_matching",
                     s->sys.terms[t]->type->name);
  int nv = s->mesh.nv, ne = s->topo.ne;
  w->nc = nv;
  w->start = cb_calloc((size_t)nv + 1, sizeof(int));
  w->count = cb_calloc((size_t)nv, sizeof(int));
  w->member = cb_malloc((size_t)nv + 2 * (size_t)ne, sizeof(int));
  w->q = cb_malloc(3 * ((size_t)nv + 2 * (size_t)ne), sizeof(double));
  w->w = cb_malloc((size_t)nv, sizeof(double));
  w->goal = cb_malloc(3 * (size_t)nv, sizeof(double));
  if (!w->start || !w->count || !w->member || !w->q || !w->w || !w->goal) return CB_ENOMEM;
  /* one-ring sizes: 1 + degree */
  for (int i = 0; i < nv; i++) w->start[i + 1] = 1;
  for (int e = 0; e < ne; e++) {
    w->start[s->topo.edge[2 * e] + 1]++;
    w->start[s->topo.edge[2 * e + 1] + 1]++;
  }
  for (int i = 0; i < nv; i++) w->start[i + 1] += w->start[i];
  int *fill = w->count; /* reuse as a cursor, then as n_i */
  for (int i = 0; i < nv; i++) {
    w->member[w->start[i]] = i;
    fill[i] = 1;
  }
  for (int e = 0; e < ne; e++) {
    int a = s->topo.edge[2 * e], b = s->topo.edge[2 * e + 1];
    w->member[w->start[a] + fill[a]++] = b;
    w->member[w->start[b] + fill[b]++] = a;
  }
  for (int i = 0; i < nv; i++) { /* n_i = clusters containing i = size of its own one-ring */
    w->count[i] = w->start[i + 1] - w->start[i];
    w->w[i] = s->mass[i] / w->count[i];
  }
  const double *x0 = s->mesh.x;
  for (int c = 0; c < nv; c++) {
    double cm[3] = {0, 0, 0}, W = 0;
    for (int k = w->start[c]; k < w->start[c + 1]; k++) {
      int i = w->member[k];
      W += w->w[i];
      for (int a = 0; a < 3; a++) cm[a] += w->w[i] * x0[3 * i + a];
    }
    if (!(W > 0)) return cb_fail("shape matching: cluster of vertex %d has no mass", c);
    for (int k = w->start[c]; k < w->start[c + 1]; k++)
      for (int a = 0; a < 3; a++) w->q[3 * k + a] = x0[3 * w->member[k] + a] - cm[a] / W;
  }
  return CB_OK;
}

static int sm_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  (void)st;
  sm_work *w = it->state;
  const cb_scene *s = it->scene;
  const cb_shape_matching_params *p = it->type_params;
  double dt = it->params.dt, alpha = p->alpha;
  int nv = s->mesh.nv;
  memset(w->goal, 0, 3 * (size_t)nv * sizeof(double));
  for (int c = 0; c < w->nc; c++) {
    double cm[3] = {0, 0, 0}, W = 0, A[9] = {0}, R[9];
    for (int k = w->start[c]; k < w->start[c + 1]; k++) {
      int i = w->member[k];
      W += w->w[i];
      for (int a = 0; a < 3; a++) cm[a] += w->w[i] * x[3 * i + a];
    }
    for (int a = 0; a < 3; a++) cm[a] /= W;
    for (int k = w->start[c]; k < w->start[c + 1]; k++) {
      int i = w->member[k];
      const double *q = w->q + 3 * k;
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) A[3 * a + b] += w->w[i] * (x[3 * i + a] - cm[a]) * q[b];
    }
    cb_polar33(A, R, NULL);
    for (int k = w->start[c]; k < w->start[c + 1]; k++) {
      int i = w->member[k];
      const double *q = w->q + 3 * k;
      for (int a = 0; a < 3; a++)
        w->goal[3 * i + a] += R[3 * a] * q[0] + R[3 * a + 1] * q[1] + R[3 * a + 2] * q[2] + cm[a];
    }
  }
  int bad = 0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    double inv_n = 1.0 / w->count[i];
    for (int a = 0; a < 3; a++) {
      double g = w->goal[3 * i + a] * inv_n;
      v[3 * i + a] += alpha * (g - x[3 * i + a]) / dt + dt * s->gravity[a]; /* f_ext / m = g */
      x[3 * i + a] += dt * v[3 * i + a];
      bad |= !isfinite(x[3 * i + a]) || !isfinite(v[3 * i + a]);
    }
  }
  for (int k = 0; k < s->npinned; k++)
    for (int a = 0; a < 3; a++) x[3 * s->pinned[k] + a] += dt * v[3 * s->pinned[k] + a];
  return bad ? CB_DIVERGED : CB_OK;
}

const cb_integrator_type cb_integrator_shape_matching = {
    .name = "shape_matching",
    .flags = CB_INTEGRATOR_OWN_ELASTICITY,
    .size = sizeof(sm_work),
    .params_size = sizeof(cb_shape_matching_params),
    .params_default = &sm_defaults,
    .keys = sm_keys,
    .init = sm_init,
    .step = sm_step,
    .free = sm_free,
};
