/* A scene is built from a definition (cb_scene_def) and holds only what the
 * definition names: the mesh and its topology, masses, pins, the energy terms
 * (a scene with bending off has no bending term), the system over them, the
 * post-step responses (none unless named), and the initial state.
 *
 * The core knows nothing of configs: lib/config/bind.c fills a cb_scene_def
 * from an INI config (cb_scene_from_config) and says where a bad key was set. */
#ifndef CB_SCENE_H
#define CB_SCENE_H

#include <stddef.h>

#include "collider.h"
#include "contact.h"
#include "energy.h"
#include "material.h"
#include "mesh.h"
#include "obstacle.h"
#include "params.h"
#include "response.h"
#include "system.h"
#include "topology.h"

typedef struct cb_scene cb_scene;

/* The post-step responses (response.h): the scene owns them and runs them
 * after every step, in order, each seeing the scene through a
 * cb_response_view. */

/* ---- definition ------------------------------------------------------------ */
typedef enum { CB_MESH_GRID = 0, CB_MESH_CHAIN = 1, CB_MESH_OBJ = 2 } cb_mesh_kind;

/* Everything a scene is built from. Strings are read during cb_scene_build
 * only (the scene's copy, cb_scene.def, has them NULL). */
typedef struct cb_scene_def {
  int cookie;        /* CB_PARAMS_COOKIE, set by cb_scene_def_default() and checked by cb_scene_build (params.h) */
  cb_mesh_kind mesh; /* Default grid */
  cb_grid_params
      grid; /* grid: all fields; chain: n, size[0] (its length, m), plane. Default cb_grid_params_default() */
  const char *mesh_file;       /* OBJ path for CB_MESH_OBJ, as given to fopen. Default NULL */
  double density;              /* kg/m^2, for area-lumped masses. Default 1 */
  double vertex_mass;          /* kg per vertex; 0 = lumped from density. Default 0 */
  const char *stretch;         /* in-plane model, a name of cb_stretch_names: "spring" (one on every
                                  edge) or "fem" (co-rotational triangles). Default "spring" */
  double stretch_k;            /* N/m: the spring stiffness k, or FEM's mu (energy per rest area). Default 8000 */
  const char *fem_hessian;     /* FEM Hessian, a name of cb_fem_hessian_names ("exact", "frozen"). Default "exact" */
  const char *bend;            /* bending model, a name of cb_bend_names. Default "none" */
  double bend_k;               /* N/m for `spring`, N m for `dihedral` and `quadratic`. Default 100 */
  const char *bend_hessian;    /* dihedral Hessian, a name of cb_bend_hessian_names ("gauss-newton", "exact"); NULL
                                  = "gauss-newton". Default "gauss-newton" */
  const char *definiteness;    /* compressed-spring response of the springs, a name of
                                  cb_definiteness_names ("choi-ko" changes the energy). Default "drop" */
  double buckling_kb;          /* N m^2, Choi-Ko bending stiffness. Default 0.01 */
  double gravity[3];           /* m/s^2; 0 0 0 = no gravity term. Default 0 -9.8 0 */
  const char *pins;            /* named set, halfspace or index list (cb_pins_resolve). Default "top-corners" */
  double initial_scale;        /* x0 = rest positions scaled about their centroid. Default 1 */
  double pin_squeeze[3];       /* m/s, pinned vertices driven toward each other. Default 0 0 0 */
  double diverge_ratio;        /* energy-growth bound of a run (run.h). Default 10 */
  const char *collider;        /* a name of cb_collider_names: "penalty" adds a term, "project" and
                                  "mesh" a response (after the def's own responses). Default "none" */
  cb_sphere sphere;            /* the collider's sphere. Default centre 0 0 0, radius 1, thickness 0,
                                  stiffness 10000, velocity 0 0 0 */
  cb_obstacle_params obstacle; /* the `mesh` collider's obstacle (its file read during the build
                                  only). Default cb_obstacle_params_default() */
  const char *contact;         /* contact.method, a name of cb_contact_names: "penalty" and "ipc" add their
                                  energy term (contact.h). Default "none" */
  cb_contact_params contact_params; /* the response's parameters. Default cb_contact_params_default() */
  int nresponses;                   /* post-step responses, run in this order. Default 0 */
  struct {
    const cb_response_type *type;
    const void *params; /* handed to type->init; read during the build only */
  } responses[CB_MAX_RESPONSES];
} cb_scene_def;

cb_scene_def cb_scene_def_default(void);

struct cb_scene {
  cb_scene_def def; /* the definition it was built from (strings NULL) */
  cb_mesh mesh;     /* rest shape */
  cb_topology topo;
  double *mass; /* nv, kg */
  int npinned;
  int *pinned;      /* npinned vertex indices, ascending */
  int *free_index;  /* nv: free block index or -1 */
  int *free_vertex; /* nfree: vertex of each free block */
  cb_model model;
  cb_system sys;
  double *x0, *v0;      /* initial state, 3*nv each */
  double gravity[3];    /* m/s^2 (also inside the gravity term, if any) */
  double energy_scale;  /* divergence scale S of integrator.diverge_ratio, less the initial kinetic energy, J */
  double diverge_ratio; /* the run's energy-growth bound is diverge_ratio x S (run.h) */
  int nresponses;
  cb_response responses[CB_MAX_RESPONSES]; /* the post-step stage */
};

/* Builds the scene def names. On an error about one field, the message
 * starts with that field's key ("mesh: ", "scene.pins: ", ...) and *key (if
 * key is not NULL) is set to the config key whose location a caller should
 * prefix ("mesh.n", "mesh.file", "scene.pins", "material.bend",
 * "material.buckling_kb"); otherwise *key is NULL. */
int cb_scene_build(const cb_scene_def *def, cb_scene **out, const char **key);
void cb_scene_free(cb_scene *s);

/* Sum of the vertex masses, kg. */
double cb_scene_total_mass(const cb_scene *s);

/* Runs the post-step responses on (x, v) after a step x_start -> x of
 * length dt; returns the first nonzero status. */
int cb_scene_post_step(const cb_scene *s, const double *x_start, double *x, double *v, double dt);

/* The scene's obstacle mesh (collider.type = mesh) at the time of the last
 * step, or NULL without one. Contact code reads its positions at any time
 * with cb_obstacle_positions. */
const cb_obstacle *cb_scene_obstacle(const cb_scene *s);
/* The time of the obstacle's motion, s (the sum of the steps taken; 0 without an obstacle), and its reset: the
 * obstacle moved to time t as if the steps so far had summed to t, bit for bit (a program that repeats steps from a
 * saved cloth state, bench_contact and contact's C3, restores the obstacle with it). No-op without an obstacle. */
double cb_scene_obstacle_time(const cb_scene *s);
void cb_scene_obstacle_set_time(cb_scene *s, double t);
/* The scene's contact term (contact.method = penalty or ipc), or NULL. */
const cb_term *cb_scene_contact_term(const cb_scene *s);
/* What the last step's bridson filter did (contact.method = bridson), or NULL. */
const cb_bridson_stats *cb_scene_bridson_stats(const cb_scene *s);
/* Collider contacts: vertices inside a penalty sphere at x, plus the vertices
 * a project response moved in the last step (0 without a collider). */
int cb_scene_contacts(const cb_scene *s, const double *x);

/* Kinetic energy 1/2 sum m_i |v_i|^2, J. */
double cb_scene_kinetic(const cb_scene *s, const double *v);

/* Resolves scene.pins for a mesh into a sorted, duplicate-free list: `none`,
 * a named grid set, `halfspace a b c d` (rest positions with a.p <= d) or
 * 0-based indices. */
int cb_pins_resolve(const char *spec, const cb_mesh *m, int **out, int *n);

#endif
