/* The locking experiment's pieces (main.c runs them): the scene table and
 * the helpers its cells share, and one file per cell kind:
 *   scenes.c    the scene table, the ring disks and meshes written before the
 *               sweeps, building a cell's scene, edge strain
 *   l1_fold.c   L1: fold angle at rest against in-plane stiffness
 *   l2_dofs.c   L2: DoFs per vertex, conforming against nonconforming
 *   f1_aniso.c  F1: anisotropy of the response to non-affine loads
 *   f1_newton.c F1: one timed implicit Euler step of the lab cloth
 *   s1_shape.c  S1: shape matching under explicit integration
 * Each cell is a cb_sweep cell (ctx: the int quick) writing rows into its
 * table out[T_*]. */
#ifndef LOCKING_H
#define LOCKING_H

#include <stdio.h>

#include <clothbench/scene.h>
#include "experiment.h"
#include "scene_decl.h"

#define PI 3.14159265358979323846
extern cb_experiment E; /* the experiment (main.c) */

typedef enum { MESH_REGULAR = 0, MESH_ALTERNATING, MESH_DISK, NMESH } mesh_kind;
extern const char *const mesh_names[NMESH];

/* Scenes. Roles: "fold" = L1's base (hanging.ini as a horizontal 1 m cloth;
 * each cell adds the mesh, model and k); "aniso" = F1's patch in its plane
 * (each cell adds the mesh and model); "step" = F1's timed Newton step on the
 * lab cloth (one cell each; plan: the definiteness of the timed step, mesh.n
 * and the lab's 441 kg are added per run mode); "shape" = S1's scenes (one
 * cell per method: springs under symplectic Euler, shape matching per alpha).
 * The disk of L1 and F1's meshes (clipped grids and ring disks, per level) are
 * generated in code and written as OBJs beside the CSV before the sweeps (every
 * shard writes them), and L2's meshes
 * (grids and ring disks, no scene) stay in code, as in topology. */
typedef struct {
  cb_scene_decl scene;
  const char *definiteness;
} scene_plan;
enum { NSCENES = 9 };
extern const scene_plan SCENES[NSCENES];
enum { T_MAIN, T_DOFS, T_ANISO, T_NEWTON, T_STEPS, T_SHAPE }; /* tables, in the order opened */
/* the scenes of a role, in table order (main.c) */
extern int nsteps, step_idx[NSCENES], nshape, shape_idx[NSCENES];

/* the first scene of a role */
const cb_scene_decl *lk_scene_of(const char *role);

/* ---- meshes written before the sweeps (every shard writes them) ---- */
extern char disk_xz[2048], disk_xy[2048];      /* the ring disks of L1 (horizontal) and in plane xy (lk_write_disk) */
enum { F1_MAXLEV = 3 };                        /* F1's refinement ladder: n = 15, 31, 63 */
extern char aniso_obj[F1_MAXLEV][NMESH][2048]; /* F1's patches per level: the clipped grids, the ring disk */
extern int f1_levels[F1_MAXLEV], f1_nlev;      /* grid vertices per side of each level, and how many */
/* The ring disk scaled to radius 0.5 m in plane xz (horizontal) or xy, as an OBJ beside the CSV. */
int lk_write_disk(int rings, int plane_xy);
/* The n^2 grid of kind mk on [-0.5, 0.5]^2 (plane xy), clipped to the disk of radius F1_R, as an OBJ
 * (aniso_obj[lev][mk]). */
int lk_write_clipped_grid(int lev, mesh_kind mk, int n);
/* F1's meshes at every level: the clipped grids and the ring disk of (n - 1)/2 rings (the same spacing
 * 1/(n - 1) m), written beside the CSV. */
int lk_write_f1_meshes(const int *levels, int nlev);

/* ---- shared by the cells ---- */
/* The scene d with the cell's sets on grid n of kind mk, or on the OBJ obj when it is not NULL
 * (a mesh written before the sweeps), pins = pins. */
int lk_build(const cb_scene_decl *dl, const char *const *sets, mesh_kind mk, int n, const char *obj, const char *pins,
             cb_scene **out);
/* Rest positions of the mesh kind without building a scene (for pin lists). */
int lk_rest_mesh(mesh_kind mk, int n, int plane_xy, cb_mesh *m);
/* Edge strain (l - L)/L: max |.| and RMS over the scene's edges at x. */
void lk_edge_strain(const cb_scene *s, const double *x, double *mx, double *rms);

/* ---- the cells ---- */
enum { NFOLD = 4 }; /* L1's fold lines */
int lk_l1_cell(long ci, void *ctx, FILE *const *out);
int lk_l2_cell(long i, void *ctx, FILE *const *out);
int lk_f1_aniso_cell(long ci, void *ctx, FILE *const *out);
int lk_f1_newton_cell(long i, void *ctx, FILE *const *out);
int lk_s1_cell(long i, void *ctx, FILE *const *out);

#endif
