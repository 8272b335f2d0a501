/* locking: the scene table, the meshes written before the sweeps, and the
 * helpers the cells share (locking.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <clothbench/mesh.h>
#include <clothbench/scene.h>
#include "bind.h"
#include "rigidity.h"

#include "locking.h"

const char *const mesh_names[NMESH] = {"regular", "alternating", "disk"};
char disk_xz[2048], disk_xy[2048];

const scene_plan SCENES[] = {
    {{"fold",
      "hanging.ini",
      {"mesh.size=1", "mesh.plane=xz", "material.vertex_mass=0", "material.density=0.1", NULL},
      "fold"},
     NULL},
    {{"aniso",
      "hanging.ini",
      {"mesh.size=1", "mesh.plane=xy", "material.vertex_mass=0", "material.density=1", "scene.gravity=0 0 0",
       "material.stretch_k=1000", NULL},
      "aniso"},
     NULL},
#define STEP(s, h) \
  { \
    "material.stretch=" s, "material.fem_hessian=" h, "integrator.definiteness=drop", "integrator.tol=1e-8", \
        "integrator.max_iters=300", NULL \
  }
    {{"spring_drop", "hanging.ini", STEP("spring", "exact"), "step"}, "drop"},
    {{"spring_none", "hanging.ini", STEP("spring", "exact"), "step"}, "none"},
    {{"fem_exact_drop", "hanging.ini", STEP("fem", "exact"), "step"}, "drop"},
    {{"fem_exact_none", "hanging.ini", STEP("fem", "exact"), "step"}, "none"},
    {{"fem_frozen", "hanging.ini", STEP("fem", "frozen"), "step"}, "drop"},
#undef STEP
    {{"chain20", "chain20.ini", {NULL}, "shape"}, NULL},
    {{"cloth21", "hanging.ini", {"mesh.plane=xy", NULL}, "shape"},
     NULL}, /* hanging vertically, as explicit_stability */
};
_Static_assert(sizeof SCENES / sizeof SCENES[0] == NSCENES, "NSCENES (locking.h) is the length of the scene table");

/* the first scene of a role */
const cb_scene_decl *lk_scene_of(const char *role) {
  for (int i = 0; i < NSCENES; i++)
    if (cb_scene_decl_is(&SCENES[i].scene, role)) return &SCENES[i].scene;
  return NULL;
}

/* The ring disk scaled to radius 0.5 m in plane xz (horizontal) or xy, as an OBJ beside the CSV. */
int lk_write_disk(int rings, int plane_xy) {
  cb_mesh m;
  int st = cb_ring_disk(rings, &m);
  if (st) return st;
  double s = 0.5 / rings;
  for (int i = 0; i < m.nv; i++) {
    double x = m.x[3 * i] * s, y = m.x[3 * i + 1] * s;
    m.x[3 * i] = x;
    m.x[3 * i + 1] = plane_xy ? y : 0;
    m.x[3 * i + 2] = plane_xy ? 0 : -y; /* xz: keep the orientation (normal +y) */
  }
  char *path = plane_xy ? disk_xy : disk_xz;
  cb_experiment_side_path(&E, plane_xy ? "disk_xy.obj" : "disk_xz.obj", path, sizeof disk_xy);
  st = cb_mesh_write_obj(&m, NULL, path);
  cb_mesh_free(&m);
  return st;
}

/* The scene d with the cell's sets on grid n of kind mk, or on the OBJ obj when it is not NULL
 * (a mesh written before the sweeps), pins = pins. */
int lk_build(const cb_scene_decl *dl, const char *const *sets, mesh_kind mk, int n, const char *obj, const char *pins,
             cb_scene **out) {
  const char *all[24];
  int k = 0;
  char sn[32];
  snprintf(sn, sizeof sn, "mesh.n=%d", n);
  all[k++] = sn;
  all[k++] = mk == MESH_ALTERNATING ? "mesh.diagonal=alternating" : "mesh.diagonal=regular";
  for (int i = 0; sets[i] && k < 23; i++) all[k++] = sets[i];
  all[k] = NULL;
  cb_config c;
  int st = cb_scene_decl_config(&E, dl, all, &c);
  if (st) return st;
  cb_scene_def d;
  char path[4 * CB_PATH_LEN];
  if ((st = cb_scene_def_from_config(&c, &d, path, sizeof path))) return st;
  if (obj) {
    d.mesh = CB_MESH_OBJ;
    d.mesh_file = obj;
  }
  if (pins) d.pins = pins;
  return cb_scene_build(&d, out, NULL);
}

/* Rest positions of the mesh kind without building a scene (for pin lists). */
int lk_rest_mesh(mesh_kind mk, int n, int plane_xy, cb_mesh *m) {
  if (mk == MESH_DISK) return cb_mesh_read_obj(plane_xy ? disk_xy : disk_xz, m);
  cb_grid_params g = cb_grid_params_default();
  g.n = g.m = n;
  g.size[0] = g.size[1] = 1.0;
  g.plane = plane_xy ? CB_PLANE_XY : CB_PLANE_XZ;
  g.diagonal = mk == MESH_ALTERNATING ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
  return cb_mesh_grid(&g, m);
}

/* Edge strain (l - L)/L: max |.| and RMS over the scene's edges at x. */
void lk_edge_strain(const cb_scene *s, const double *x, double *mx, double *rms) {
  double m = 0, q = 0;
  for (int e = 0; e < s->topo.ne; e++) {
    int i = s->topo.edge[2 * e], j = s->topo.edge[2 * e + 1];
    double l = 0, L = 0;
    for (int a = 0; a < 3; a++) {
      l += (x[3 * i + a] - x[3 * j + a]) * (x[3 * i + a] - x[3 * j + a]);
      L += (s->mesh.x[3 * i + a] - s->mesh.x[3 * j + a]) * (s->mesh.x[3 * i + a] - s->mesh.x[3 * j + a]);
    }
    double eps = (sqrt(l) - sqrt(L)) / sqrt(L);
    m = fmax(m, fabs(eps));
    q += eps * eps;
  }
  *mx = m;
  *rms = s->topo.ne ? sqrt(q / s->topo.ne) : 0;
}
