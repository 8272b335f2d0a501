/* Kinematic obstacle meshes (obstacle.c): a triangle mesh read from OBJ that
 * moves by a scripted rigid motion (issue 33 §5). It has no mass and no
 * energy of its own: a scene whose collider is `mesh` moves it every step
 * (the collider's post-step response), the contact term of contact.method
 * meets it (contact.h, static at its positions within a step), and programs
 * write it beside the cloth.
 *
 * Motion: the file's coordinates X_i are the obstacle's own frame, whose
 * origin is placed at the centre c at t = 0 and moves at the velocity v,
 * while the obstacle turns about the axis through that origin at angular
 * speed omega (right-handed about the unit axis a):
 *   x_i(t) = c + t v + R(a, omega t) X_i,
 *   R(a, th) r = r cos th + (a x r) sin th + a (a . r)(1 - cos th)   (Rodrigues),
 *   dx_i/dt = v + omega a x R(a, omega t) X_i.
 * A mesh modelled about its own origin (configs/cylinder.obj: its axis is
 * the z axis) thus turns about itself. A pure translation is omega = 0, a
 * pure rotation v = 0; c = 0 keeps the file's placement. */
#ifndef CB_OBSTACLE_H
#define CB_OBSTACLE_H

#include "mesh.h"
#include "params.h"

typedef struct cb_obstacle_params {
  int cookie;         /* CB_PARAMS_COOKIE, set by cb_obstacle_params_default() and checked by cb_obstacle_alloc */
  const char *file;   /* OBJ path (read by cb_obstacle_alloc only). Default NULL: required */
  double centre[3];   /* m, where the file's origin is at t = 0 (on the rotation axis). Default 0 0 0 */
  double axis[3];     /* rotation axis, any length > 0 (normalised); may be 0 0 0 if omega = 0. Default 0 1 0 */
  double omega;       /* rad/s, angular speed about axis (right-handed). Default 0 */
  double velocity[3]; /* m/s, velocity of the centre (and of the whole mesh if omega = 0). Default 0 0 0 */
} cb_obstacle_params;

cb_obstacle_params cb_obstacle_params_default(void);

typedef struct cb_obstacle {
  cb_mesh mesh;       /* the file's mesh, in the obstacle's frame (X_i), triangles only */
  double centre[3];   /* m, c */
  double axis[3];     /* unit axis a (0 0 0 when omega = 0) */
  double omega;       /* rad/s */
  double velocity[3]; /* m/s, v */
  double t;           /* s, the time of x */
  double *x;          /* 3 nv positions at t */
} cb_obstacle;

/* Reads p->file and checks the motion. Errors start with the config key they
 * are about: "collider.file: ..." (missing or unreadable file, broken OBJ,
 * zero-area triangles, no triangles, line elements), "collider.axis: ..."
 * (zero or not finite with omega != 0), "collider.angular_speed: ...",
 * "collider.centre: ...", "collider.velocity: ..." (not finite). */
int cb_obstacle_alloc(const cb_obstacle_params *p, cb_obstacle **out);
void cb_obstacle_free(cb_obstacle *o);

/* Positions x (3 nv) at time t, s; o is not changed and nothing allocated. */
void cb_obstacle_positions(const cb_obstacle *o, double t, double *x);
/* Velocities v (3 nv) at time t, m/s. */
void cb_obstacle_velocities(const cb_obstacle *o, double t, double *v);
/* Moves o to time t: o->x = positions at t, o->t = t. */
void cb_obstacle_advance(cb_obstacle *o, double t);

/* The `mesh` collider's post-step response (obstacle.c; its params a
 * cb_obstacle_params): it owns the obstacle and moves it to the run's time
 * after every step. cb_obstacle_of is its obstacle at the time of the last
 * step, or NULL if r is another response. */
struct cb_response;
struct cb_response_type;
extern const struct cb_response_type cb_response_obstacle_move;
const cb_obstacle *cb_obstacle_of(const struct cb_response *r);
/* The time of the obstacle's motion, s, if r is that response (else NaN); and
 * its reset: the obstacle moved to time t (returns 1, or 0 if r is another
 * response). The scene's cb_scene_obstacle_time / _set_time use them. */
double cb_obstacle_time_of(const struct cb_response *r);
int cb_obstacle_set_time_of(struct cb_response *r, double t);

#endif
