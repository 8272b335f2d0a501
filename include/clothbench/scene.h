/* A scene is built from a config and holds only what the config names: the
 * mesh and its topology, masses, pins, the energy terms (a scene with bending
 * off has no bending term), the system over them, and the initial state. */
#ifndef CB_SCENE_H
#define CB_SCENE_H

#include "config.h"
#include "energy.h"
#include "mesh.h"
#include "system.h"
#include "topology.h"

typedef struct cb_scene {
  cb_config cfg;
  cb_mesh mesh;          /* rest shape */
  cb_topology topo;
  double *mass;          /* nv, kg */
  int npinned;
  int *pinned;           /* npinned vertex indices, ascending */
  int *free_index;       /* nv: free block index or -1 */
  int *free_vertex;      /* nfree: vertex of each free block */
  cb_model model;
  cb_system sys;
  double *x0, *v0;       /* initial state, 3*nv each */
  double gravity[3];     /* m/s^2 (also inside the gravity term, if any) */
  double energy_scale;   /* divergence scale S of integrator.diverge_ratio, less the initial kinetic energy, J */
} cb_scene;

int cb_scene_build(const cb_config *cfg, cb_scene **out);
void cb_scene_free(cb_scene *s);

/* Sum of the vertex masses, kg. */
double cb_scene_total_mass(const cb_scene *s);

/* Kinetic energy 1/2 sum m_i |v_i|^2, J. */
double cb_scene_kinetic(const cb_scene *s, const double *v);

/* Resolves scene.pins for a mesh into a sorted, duplicate-free list. */
int cb_pins_resolve(const char *spec, const cb_mesh *m, int **out, int *n);

#endif
