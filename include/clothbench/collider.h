/* A sphere collider (the GAMES103 lab's ball), as an energy term (`penalty`)
 * or as a post-step response (`project`), collider.c; or a kinematic obstacle
 * mesh (`mesh`, obstacle.h: moved every step; contact.method's term meets it,
 * contact.h). A
 * scene has one only if its definition names one (cb_scene_def.collider).
 *
 * penalty: E = 1/2 k_c (r + thickness - |x_i - c|)^2 summed over the vertices
 *          inside the shell |x_i - c| < r + thickness; stackable with every
 *          other term, with its exact gradient and Hessian (the transverse
 *          part is negative; the assembly's projection acts on it in closed
 *          form). The sphere does not move (an energy has no time).
 * project: after every step, a free vertex inside the sphere of radius
 *          r + thickness around c(t) = c + t v is moved to its surface along
 *          x_i - c(t), and its velocity is corrected by (x_new - x)/dt. */
#ifndef CB_COLLIDER_H
#define CB_COLLIDER_H

#include "energy.h"
#include "obstacle.h"
#include "response.h"

typedef struct cb_sphere {
  double centre[3];   /* m, at t = 0 */
  double radius;      /* m, > 0 */
  double thickness;   /* m, >= 0: contact shell added to the radius */
  double stiffness;   /* N/m, penalty k_c */
  double velocity[3]; /* m/s, constant (project only) */
} cb_sphere;

/* The colliders collider.type names, one X line each in collider.c: what
 * each adds to a scene, an energy term or a post-step response (or
 * nothing); a scene builds what its definition's row gives. */
typedef struct cb_collider {
  const char *name;
  int (*term_alloc)(const cb_model *m, const cb_sphere *sp, cb_term **out); /* its term, or NULL */
  const cb_response_type *response;                                         /* its post-step response, or NULL */
  /* The parameters its response's init gets, from the definition's sphere and
   * obstacle (cb_scene_def.sphere, .obstacle): one of the two; NULL if no response. */
  const void *(*params)(const cb_sphere *sp, const cb_obstacle_params *ob);
} cb_collider;
extern const cb_collider cb_colliders[];      /* ended by a NULL name */
extern const char *const cb_collider_names[]; /* "none", "penalty", "project", "mesh"; NULL-terminated */
/* The collider called name, or NULL. */
const cb_collider *cb_collider_find(const char *name);

/* The sphere's projection (`project`; its params a cb_sphere), and the
 * vertices it moved in the last step: 0 if r is another response. */
extern const cb_response_type cb_response_sphere_project;
int cb_sphere_project_contacts(const cb_response *r);

/* The penalty term of sphere sp on every vertex of the model; fails on a
 * non-positive radius, negative thickness or stiffness, or a moving sphere. */
int cb_sphere_term_alloc(const cb_model *m, const cb_sphere *sp, cb_term **out);
/* Vertices strictly inside the shell at x (0 if t is no sphere term). */
int cb_sphere_term_count_contacts(const cb_term *t, const double *x);

#endif
