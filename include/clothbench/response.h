/* Post-step responses: a plug-in that changes the state after every step of
 * every integrator, in the order the scene lists them (cb_integrator_step runs
 * them): a collision projection, an obstacle's motion, a velocity filter.
 *
 * A response sees the part of the scene it needs through a cb_response_view,
 * not the scene itself, so the modules that define responses (collider.c,
 * obstacle.c, contact_bridson.c) sit below the scene that runs them: the
 * scene fills the view and owns the responses; a response never includes
 * scene.h.
 *
 * Plug-ins as a type table: the scene allocates each response's state from
 * the type's `size` (zeroed) and calls init with the parameters the
 * definition gives. */
#ifndef CB_RESPONSE_H
#define CB_RESPONSE_H

#include <stddef.h>

#include "mesh.h"

struct cb_obstacle; /* obstacle.h */

/* What a response sees of its scene. Every pointer is the scene's and lives
 * as long as it; a response reads them, never writes them. */
typedef struct cb_response_view {
  const cb_mesh *mesh;   /* the cloth's rest mesh (nv vertices, nt triangles) */
  const double *mass;    /* nv, kg */
  const int *free_index; /* nv: the vertex's free block index, or -1 for a pinned vertex */
  const double *x0;      /* 3 nv, the initial positions, m */
  const struct cb_obstacle
      *obstacle; /* the obstacle mesh moved by an earlier response (collider.type = mesh), or NULL */
} cb_response_view;

typedef struct cb_response cb_response;
typedef struct cb_response_type {
  const char *name;
  size_t size; /* bytes of state, allocated by the scene */
  int (*init)(cb_response *r, const cb_response_view *s, const void *params); /* may be NULL */
  /* Changes (x, v) (3*nv each) after a step of length dt that started at the
   * positions x_start (3*nv, read only: the collision responses sweep
   * x_start -> x); returns a status (a positive one becomes the step's status
   * if the step was ok). */
  int (*apply)(cb_response *r, const cb_response_view *s, const double *x_start, double *x, double *v, double dt);
  void (*free)(cb_response *r); /* frees what init allocated; may be NULL */
} cb_response_type;
struct cb_response {
  const cb_response_type *type;
  void *state;
};
enum { CB_MAX_RESPONSES = 8 };

/* Sets r->type = t and allocates its state from t->size (zeroed; NULL for a
 * size of 0); CB_ENOMEM leaves r->state NULL, and a type that is NULL or has
 * no apply is refused. The caller then runs t->init, if any. */
int cb_response_alloc(cb_response *r, const cb_response_type *t);
/* Runs r's type's free and frees its state. */
void cb_response_free(cb_response *r);
/* Runs rs[0..n) in order on (x, v) after a step x_start -> x of length dt;
 * returns the first nonzero status. */
int cb_response_apply_all(cb_response *rs, int n, const cb_response_view *view, const double *x_start, double *x,
                          double *v, double dt);

#endif
