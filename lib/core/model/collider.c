/* The sphere collider (collider.h): the penalty term and the project response.
 *
 * Penalty, per vertex inside the shell, R = r + thickness, d = x - c, l = |d|,
 * u = d / l, phi = R - l > 0:
 *   E = k_c phi^2 / 2,   dE/dx = -k_c phi u,
 *   H = k_c u u^T - k_c (phi / l) (I - u u^T).
 * Its eigenvalues are k_c (along u) and -k_c phi / l (twice, across u), so the
 * projection acts on the transverse one in closed form, as the spring's does.
 * A vertex exactly at the centre (l = 0) has no direction and is skipped (no
 * energy, gradient or Hessian: a documented clamp, never a NaN).
 *
 * Project (the GAMES103 lab): the response advances the sphere to c(t) and
 * moves every free vertex with l < R to c + R u, v += (x_new - x)/dt; a vertex
 * exactly at the centre is pushed along +y. */
#include <clothbench/collider.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/response.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>
#include "vec.h"

/* The parameters of each collider's response, from the definition. */
static const void *sphere_params(const cb_sphere *sp, const cb_obstacle_params *ob) {
  (void)ob;
  return sp;
}
static const void *obstacle_params(const cb_sphere *sp, const cb_obstacle_params *ob) {
  (void)sp;
  return ob;
}

/* The colliders: X(name, its term's alloc, its post-step response, the
 * response's parameters), one line each, in the order of collider.type's
 * choices. */
#define CB_COLLIDERS(X) \
  X("none", NULL, NULL, NULL) \
  X("penalty", cb_sphere_term_alloc, NULL, NULL) \
  X("project", NULL, &cb_response_sphere_project, sphere_params) \
  X("mesh", NULL, &cb_response_obstacle_move, obstacle_params) \
  /* one X(...) line per collider, above this line */
#define CB_COLLIDER_ROW(name_, term_, response_, params_) \
  {.name = name_, .term_alloc = term_, .response = response_, .params = params_},
#define CB_COLLIDER_NAME(name_, term_, response_, params_) name_,
const cb_collider cb_colliders[] = {CB_COLLIDERS(CB_COLLIDER_ROW){.name = NULL}};
const char *const cb_collider_names[] = {CB_COLLIDERS(CB_COLLIDER_NAME) NULL};

const cb_collider *cb_collider_find(const char *name) {
  for (const cb_collider *c = cb_colliders; c->name; c++)
    if (strcmp(c->name, name) == 0) return c;
  return NULL;
}

extern const cb_term_type cb_term_sphere_type;

typedef struct {
  cb_term base;
  cb_sphere sp;
  int nv;
  int *vert; /* 0..nv-1, the stencil's elements */
  cb_stencil st;
} sphere_term;

static int sphere_check(const cb_sphere *sp) {
  if (!(sp->radius > 0) || !isfinite(sp->radius)) return cb_fail("collider.radius: must be > 0, got %g", sp->radius);
  if (!(sp->thickness >= 0) || !isfinite(sp->thickness))
    return cb_fail("collider.thickness: must be >= 0, got %g", sp->thickness);
  for (int a = 0; a < 3; a++)
    if (!isfinite(sp->centre[a]) || !isfinite(sp->velocity[a])) return cb_fail("collider.centre: not finite");
  return CB_OK;
}

static double sphere_energy(const cb_term *t, const double *x, double *grad) {
  const sphere_term *s = (const sphere_term *)t;
  double R = s->sp.radius + s->sp.thickness, E = 0;
  for (int i = 0; i < s->nv; i++) {
    double d[3] = {x[3 * i] - s->sp.centre[0], x[3 * i + 1] - s->sp.centre[1], x[3 * i + 2] - s->sp.centre[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), phi = R - l;
    if (!(phi > 0)) continue;
    E += 0.5 * s->sp.stiffness * phi * phi; /* at the centre too: E is continuous there (its maximum, k R^2/2) */
    if (grad && l > 0)
      for (int a = 0; a < 3; a++) grad[3 * i + a] += -s->sp.stiffness * phi * d[a] / l;
  }
  return E;
}

static int sphere_pattern(const cb_term *t, cb_pattern *p) {
  return cb_stencil_pattern(&((const sphere_term *)t)->st, p);
}

static int sphere_bind(cb_term *t, const cb_sparse *A) {
  return cb_stencil_bind(&((sphere_term *)t)->st, A, "collider sphere");
}

static const cb_stencil *sphere_stencil(const cb_term *t) { return &((const sphere_term *)t)->st; }

/* Vertex i's penalty: E = k/2 phi^2, phi = R - |d| > 0, g = -k phi d/|d|,
 * H = k uu^T + proj(-k phi/|d|)(I - uu^T); all zero outside the sphere. */
static double sphere_element(const cb_term *t, int i, const double *x, cb_projection proj, double *g, double *H) {
  const sphere_term *s = (const sphere_term *)t;
  double R = s->sp.radius + s->sp.thickness, k = s->sp.stiffness;
  double d[3] = {x[3 * i] - s->sp.centre[0], x[3 * i + 1] - s->sp.centre[1], x[3 * i + 2] - s->sp.centre[2]};
  double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], l = sqrt(l2), phi = R - l;
  memset(g, 0, 3 * sizeof(double));
  memset(H, 0, 9 * sizeof(double));
  if (!(phi > 0)) return 0.0;
  if (!(l > 0)) return 0.5 * k * phi * phi; /* the centre: E's maximum; no direction, g = 0 (a subgradient), H = 0 */
  double tr = cb_projection_eigenvalue(proj, -k * phi / l);
  for (int a = 0; a < 3; a++) {
    g[a] = -k * phi * d[a] / l;
    for (int b = 0; b < 3; b++) {
      double uu = d[a] * d[b] / l2;
      H[3 * a + b] = k * uu + tr * ((a == b) - uu);
    }
  }
  return 0.5 * k * phi * phi;
}

static void sphere_hessian(const cb_term *t, const double *x, cb_projection proj, double *val) {
  const sphere_term *s = (const sphere_term *)t;
  for (int i = 0; i < s->nv; i++) {
    if (!cb_stencil_active(&s->st, i)) continue;
    double g[3], H[9];
    sphere_element(t, i, x, proj, g, H);
    cb_stencil_add_block(&s->st, i, 0, 0, H, 1.0, val);
  }
}

static void sphere_free(cb_term *t) {
  sphere_term *s = (sphere_term *)t;
  free(s->vert);
  cb_stencil_free(&s->st);
  free(s);
}

int cb_sphere_term_alloc(const cb_model *m, const cb_sphere *sp, cb_term **out) {
  *out = NULL;
  int st = sphere_check(sp);
  if (st) return st;
  if (!(sp->stiffness >= 0) || !isfinite(sp->stiffness))
    return cb_fail("collider.stiffness: must be >= 0, got %g", sp->stiffness);
  if (cb_v3_nonzero(sp->velocity))
    return cb_fail("collider.velocity: a moving sphere needs collider.type = project (the penalty energy has no time)");
  sphere_term *s = cb_calloc(1, sizeof *s);
  if (!s) return CB_ENOMEM;
  s->base.type = &cb_term_sphere_type;
  s->base.model = m;
  snprintf(s->base.label, sizeof s->base.label, "collider");
  s->sp = *sp;
  s->nv = m->mesh->nv;
  s->vert = cb_malloc((size_t)(s->nv > 0 ? s->nv : 1), sizeof(int));
  if (!s->vert || cb_stencil_init(&s->st, 1, s->nv, s->vert, m->free_index)) {
    sphere_free(&s->base);
    return CB_ENOMEM;
  }
  for (int i = 0; i < s->nv; i++) s->vert[i] = i;
  *out = &s->base;
  return CB_OK;
}

int cb_sphere_term_count_contacts(const cb_term *t, const double *x) {
  if (!t || t->type != &cb_term_sphere_type) return 0;
  const sphere_term *s = (const sphere_term *)t;
  double R = s->sp.radius + s->sp.thickness;
  int n = 0;
  for (int i = 0; i < s->nv; i++) {
    double d[3] = {x[3 * i] - s->sp.centre[0], x[3 * i + 1] - s->sp.centre[1], x[3 * i + 2] - s->sp.centre[2]};
    n += d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < R * R;
  }
  return n;
}

/* The vertices inside the shell, off the centre: their transverse
 * eigenvalue -k_c phi / l is negative. */
static int sphere_indefinite(const cb_term *t, const double *x, int *nv) {
  const sphere_term *s = (const sphere_term *)t;
  double R = s->sp.radius + s->sp.thickness;
  int n = 0;
  for (int i = 0; i < s->nv; i++) {
    double d[3] = {x[3 * i] - s->sp.centre[0], x[3 * i + 1] - s->sp.centre[1], x[3 * i + 2] - s->sp.centre[2]};
    double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    n += l2 > 0 && l2 < R * R;
  }
  *nv = s->nv;
  return n;
}

/* Example: a sphere through the middle of the example meshes (about 1 x 0.8 m
 * around the origin), so some vertices of every state are inside. */
static int sphere_example(const cb_model *m, int i, cb_term **out) {
  (void)i;
  cb_sphere sp = {
      .centre = {0.1, 0.05, 0.2}, .radius = 0.35, .thickness = 0.05, .stiffness = 5000, .velocity = {0, 0, 0}};
  return cb_sphere_term_alloc(m, &sp, out);
}

const cb_term_type cb_term_sphere_type = {.name = "sphere",
                                          .energy = sphere_energy,
                                          .pattern = sphere_pattern,
                                          .bind = sphere_bind,
                                          .hessian = sphere_hessian,
                                          .free = sphere_free,
                                          .stencil = sphere_stencil,
                                          .element = sphere_element,
                                          .nexamples = 1,
                                          .example = sphere_example,
                                          .indefinite = sphere_indefinite};

/* ---- the project response --------------------------------------------------- */

typedef struct {
  cb_sphere sp;
  double t;     /* s, time reached */
  int contacts; /* vertices moved by the last step */
} project_state;

static int project_init(cb_response *r, const cb_response_view *s, const void *params) {
  (void)s;
  if (!params) return cb_fail("collider: the project response needs its sphere");
  int st = sphere_check(params);
  if (st) return st;
  project_state *p = r->state;
  p->sp = *(const cb_sphere *)params;
  return CB_OK;
}

static int project_apply(cb_response *r, const cb_response_view *s, const double *x_start, double *x, double *v,
                         double dt) {
  (void)x_start; /* the lab's projection reads the end of the step only */
  project_state *p = r->state;
  p->t += dt;
  double c[3], R = p->sp.radius + p->sp.thickness;
  for (int a = 0; a < 3; a++) c[a] = p->sp.centre[a] + p->t * p->sp.velocity[a];
  int n = 0;
  for (int i = 0; i < s->mesh->nv; i++) {
    if (s->free_index[i] < 0) continue; /* pins are prescribed */
    double *xi = x + 3 * i, d[3] = {xi[0] - c[0], xi[1] - c[1], xi[2] - c[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(l < R)) continue;
    double u[3] = {0, 1, 0};
    if (l > 0)
      for (int a = 0; a < 3; a++) u[a] = d[a] / l;
    for (int a = 0; a < 3; a++) {
      double xn = c[a] + R * u[a];
      if (dt > 0) v[3 * i + a] += (xn - xi[a]) / dt;
      xi[a] = xn;
    }
    n++;
  }
  p->contacts = n;
  return CB_OK;
}

const cb_response_type cb_response_sphere_project = {.name = "sphere-project",
                                                     .size = sizeof(project_state),
                                                     .init = project_init,
                                                     .apply = project_apply,
                                                     .free = NULL};

int cb_sphere_project_contacts(const cb_response *r) {
  return r->type == &cb_response_sphere_project ? ((const project_state *)r->state)->contacts : 0;
}
