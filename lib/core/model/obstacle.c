/* Kinematic obstacle meshes (obstacle.h).
 *
 *   x_i(t) = c + t v + R(a, omega t) X_i
 *   R(a, th) r = r cos th + (a x r) sin th + a (a . r)(1 - cos th)   (Rodrigues' formula)
 *   dx_i/dt = v + omega a x R(a, omega t) X_i                        (dR/dth r = a x R r)
 * The rotation is evaluated afresh from t each time (no accumulated
 * increments), so the positions at any t are the closed form to rounding. */
#include <clothbench/obstacle.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/response.h>
#include <clothbench/status.h>
#include "vec.h"

cb_obstacle_params cb_obstacle_params_default(void) {
  return (cb_obstacle_params){.cookie = CB_PARAMS_COOKIE,
                              .file = NULL,
                              .centre = {0, 0, 0},
                              .axis = {0, 1, 0},
                              .omega = 0,
                              .velocity = {0, 0, 0}};
}

static int check_vec(const double *a, const char *key) {
  for (int k = 0; k < 3; k++)
    if (!isfinite(a[k])) return cb_fail("%s: component %d is %g, not finite", key, k + 1, a[k]);
  return CB_OK;
}

static int check_params(const cb_obstacle_params *p) {
  if (!p->file || !p->file[0]) return cb_fail("collider.file: required for collider.type = mesh (an OBJ file)");
  int st = check_vec(p->centre, "collider.centre");
  if (!st) st = check_vec(p->velocity, "collider.velocity");
  if (!st) st = check_vec(p->axis, "collider.axis");
  if (st) return st;
  if (!isfinite(p->omega)) return cb_fail("collider.angular_speed: %g, not finite", p->omega);
  if (p->omega != 0 && !(cb_v3_norm(p->axis) > 0))
    return cb_fail("collider.axis: the zero vector, but collider.angular_speed = %g rad/s needs an axis", p->omega);
  if (p->omega != 0 && !isfinite(cb_v3_norm(p->axis))) return cb_fail("collider.axis: its length overflows");
  return CB_OK;
}

void cb_obstacle_free(cb_obstacle *o) {
  if (!o) return;
  cb_mesh_free(&o->mesh);
  free(o->x);
  free(o);
}

int cb_obstacle_alloc(const cb_obstacle_params *p, cb_obstacle **out) {
  *out = NULL;
  int st = cb_params_check(p->cookie, "collider: obstacle", "cb_obstacle_params_default");
  if (st) return st;
  st = check_params(p);
  if (st) return st;
  cb_obstacle *o = cb_calloc(1, sizeof *o);
  if (!o) return CB_ENOMEM;
  st = cb_mesh_read_obj(p->file, &o->mesh);
  if (st) {
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", cb_error_message());
    cb_obstacle_free(o);
    return cb_fail_status(st, "collider.file: %s", msg);
  }
  if (o->mesh.nt == 0 || o->mesh.nl > 0) {
    st = cb_fail("collider.file: %s: an obstacle is a triangle mesh; the file has %d triangles and %d line elements",
                 p->file, o->mesh.nt, o->mesh.nl);
    cb_obstacle_free(o);
    return st;
  }
  memcpy(o->centre, p->centre, sizeof o->centre);
  memcpy(o->velocity, p->velocity, sizeof o->velocity);
  o->omega = p->omega;
  if (p->omega != 0) {
    double l = cb_v3_norm(p->axis);
    for (int k = 0; k < 3; k++) o->axis[k] = p->axis[k] / l;
  }
  o->x = cb_malloc((size_t)o->mesh.nv * 3, sizeof(double));
  if (!o->x) {
    cb_obstacle_free(o);
    return CB_ENOMEM;
  }
  cb_obstacle_advance(o, 0.0);
  *out = o;
  return CB_OK;
}

/* R(a, th) r, Rodrigues' formula */
static void rotate(const double *a, double c, double s, const double *r, double *out) {
  double ar[3], ad = cb_v3_dot(a, r);
  cb_v3_cross(a, r, ar);
  for (int k = 0; k < 3; k++) out[k] = r[k] * c + ar[k] * s + a[k] * ad * (1 - c);
}

void cb_obstacle_positions(const cb_obstacle *o, double t, double *x) {
  double th = o->omega * t, c = cos(th), s = sin(th);
  double ct[3] = {o->centre[0] + t * o->velocity[0], o->centre[1] + t * o->velocity[1],
                  o->centre[2] + t * o->velocity[2]}; /* c + t v */
  for (int i = 0; i < o->mesh.nv; i++) {
    const double *X = o->mesh.x + 3 * i;
    double Rr[3];
    if (o->omega != 0) rotate(o->axis, c, s, X, Rr);
    else memcpy(Rr, X, sizeof Rr);
    for (int k = 0; k < 3; k++) x[3 * i + k] = ct[k] + Rr[k]; /* c + t v + R X_i */
  }
}

void cb_obstacle_velocities(const cb_obstacle *o, double t, double *v) {
  double th = o->omega * t, c = cos(th), s = sin(th);
  for (int i = 0; i < o->mesh.nv; i++) {
    double Rr[3], w[3] = {0, 0, 0};
    if (o->omega != 0) {
      rotate(o->axis, c, s, o->mesh.x + 3 * i, Rr);
      cb_v3_cross(o->axis, Rr, w); /* a x R X_i */
    }
    for (int k = 0; k < 3; k++) v[3 * i + k] = o->velocity[k] + o->omega * w[k];
  }
}

void cb_obstacle_advance(cb_obstacle *o, double t) {
  cb_obstacle_positions(o, t, o->x);
  o->t = t;
}

/* ---- the `mesh` collider's response: the obstacle's motion ----------------- */

typedef struct {
  cb_obstacle *ob;
  double t; /* s, time reached */
} move_state;

static int move_init(cb_response *r, const cb_response_view *s, const void *params) {
  (void)s;
  if (!params) return cb_fail("collider: the mesh response needs its obstacle's parameters");
  move_state *m = r->state;
  return cb_obstacle_alloc(params, &m->ob);
}

static int move_apply(cb_response *r, const cb_response_view *s, const double *x_start, double *x, double *v,
                      double dt) {
  (void)s, (void)x_start, (void)x, (void)v;
  move_state *m = r->state;
  m->t += dt;
  cb_obstacle_advance(m->ob, m->t);
  return CB_OK;
}

static void move_free(cb_response *r) {
  move_state *m = r->state;
  if (m) cb_obstacle_free(m->ob);
}

const cb_response_type cb_response_obstacle_move = {
    .name = "obstacle-move", .size = sizeof(move_state), .init = move_init, .apply = move_apply, .free = move_free};

const cb_obstacle *cb_obstacle_of(const cb_response *r) {
  return r->type == &cb_response_obstacle_move ? ((const move_state *)r->state)->ob : NULL;
}

double cb_obstacle_time_of(const cb_response *r) {
  return r->type == &cb_response_obstacle_move ? ((const move_state *)r->state)->t : NAN;
}

int cb_obstacle_set_time_of(cb_response *r, double t) {
  if (r->type != &cb_response_obstacle_move) return 0;
  move_state *m = r->state;
  m->t = t;
  cb_obstacle_advance(m->ob, t);
  return 1;
}
