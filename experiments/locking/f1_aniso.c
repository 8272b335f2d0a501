/* locking, F1 (results/locking_aniso.csv): the energy of non-affine loads
 * over their directions, per mesh and model, on disks written before the
 * sweeps (main.c describes the sweep). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/mesh.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include <clothbench/topology.h>
#include "csv.h"
#include "rigidity.h"
#include "stability.h"

#include "locking.h"

/* ---- F1: anisotropy of the response to non-affine loads ----------------------------- */

/* F1's patches: disks of radius F1_R in plane xy. The grids (regular, alternating) are
 * clipped to the disk (the triangles with every vertex inside) and written as OBJs beside the CSV
 * before the sweeps, like the ring disk, so that every mesh has the same round domain and every
 * load direction meets the same boundary. */
#define F1_R 0.5
char aniso_obj[F1_MAXLEV][NMESH][2048];
int f1_levels[F1_MAXLEV], f1_nlev;

/* The ring disk of F1 at level n: (n - 1)/2 rings of radius F1_R, the grid's spacing 1/(n - 1), plane xy. */
static int f1_write_disk(int lev, int n) {
  cb_mesh m;
  int rings = (n - 1) / 2, st = cb_ring_disk(rings, &m);
  if (st) return st;
  double sc = F1_R / rings;
  for (int i = 0; i < m.nv; i++) {
    m.x[3 * i] *= sc;
    m.x[3 * i + 1] *= sc;
    m.x[3 * i + 2] = 0;
  }
  char name[64];
  snprintf(name, sizeof name, "aniso_disk_n%d.obj", n);
  cb_experiment_side_path(&E, name, aniso_obj[lev][MESH_DISK], sizeof aniso_obj[lev][MESH_DISK]);
  st = cb_mesh_write_obj(&m, NULL, aniso_obj[lev][MESH_DISK]);
  cb_mesh_free(&m);
  return st;
}

int lk_write_f1_meshes(const int *levels, int nlev) {
  f1_nlev = nlev;
  for (int l = 0; l < nlev; l++) {
    f1_levels[l] = levels[l];
    int st = lk_write_clipped_grid(l, MESH_REGULAR, levels[l]);
    if (!st) st = lk_write_clipped_grid(l, MESH_ALTERNATING, levels[l]);
    if (!st) st = f1_write_disk(l, levels[l]);
    if (st) return st;
  }
  return CB_OK;
}

int lk_write_clipped_grid(int lev, mesh_kind mk, int n) {
  cb_mesh g, m;
  int st = lk_rest_mesh(mk, n, 1, &g);
  if (st) return st;
  memset(&m, 0, sizeof m);
  int *map = malloc((size_t)g.nv * sizeof(int));
  m.tri = malloc(3 * (size_t)g.nt * sizeof(int));
  m.x = malloc(3 * (size_t)g.nv * sizeof(double));
  if (!map || !m.tri || !m.x) {
    free(map);
    cb_mesh_free(&m);
    cb_mesh_free(&g);
    return CB_ENOMEM;
  }
  for (int i = 0; i < g.nv; i++) map[i] = -1;
  for (int t = 0; t < g.nt; t++) {
    int in = 1;
    for (int a = 0; a < 3; a++) {
      const double *X = g.x + 3 * g.tri[3 * t + a];
      in &= X[0] * X[0] + X[1] * X[1] <= F1_R * F1_R * (1 + 1e-12);
    }
    if (!in) continue;
    for (int a = 0; a < 3; a++) {
      int v = g.tri[3 * t + a];
      if (map[v] < 0) {
        map[v] = m.nv++;
        memcpy(m.x + 3 * map[v], g.x + 3 * v, 3 * sizeof(double));
      }
      m.tri[3 * m.nt + a] = map[v];
    }
    m.nt++;
  }
  char name[64];
  snprintf(name, sizeof name, "aniso_%s_n%d.obj", mk == MESH_REGULAR ? "regular" : "alternating", n);
  cb_experiment_side_path(&E, name, aniso_obj[lev][mk], sizeof aniso_obj[lev][mk]);
  st = cb_mesh_write_obj(&m, NULL, aniso_obj[lev][mk]);
  free(map);
  cb_mesh_free(&m);
  cb_mesh_free(&g);
  return st;
}

/* Non-affine loads (an affine one passes the patch test by construction): along the unit
 * direction n at dir_deg, s = n.X, t = n rotated by +90 deg,
 *   stretch: u = eps (s + R)^2 / (4R) n  (stretch along n growing from 0 at s = -R to eps at s = R)
 *   shear:   u = eps s^2 / (2R) t        (shear growing from -eps to eps across the disk: in-plane bending)
 * with eps = F1_EPS. */
#define F1_EPS 0.05
#define F1_NDIR \
  8 /* directions 0, 22.5, ..., 157.5 deg (dir + 180 is the same load for shear, its mirror for stretch) */
static const char *const f1_families[2] = {"stretch", "shear"};

static void f1_load(int fam, double deg, const double *X, double *x) {
  double th = deg * PI / 180, n[2] = {cos(th), sin(th)}, t[2] = {-sin(th), cos(th)};
  double sc = n[0] * X[0] + n[1] * X[1];
  double w = fam == 0 ? F1_EPS * (sc + F1_R) * (sc + F1_R) / (4 * F1_R) : F1_EPS * sc * sc / (2 * F1_R);
  const double *d = fam == 0 ? n : t;
  x[0] = X[0] + w * d[0];
  x[1] = X[1] + w * d[1];
  x[2] = X[2];
}

/* Cell ci: mesh kind ci % NMESH at level ci / NMESH, both models, both loads in every direction. */
int lk_f1_aniso_cell(long ci, void *ctx, FILE *const *out) {
  static const char *const models[2] = {"spring", "fem"};
  (void)ctx;
  FILE *f = out[T_ANISO];
  cb_equilibrium_params ep = cb_equilibrium_params_default();
  ep.tol = 1e-8;
  ep.max_steps = 200;
  int mk = (int)(ci % NMESH), lev = (int)(ci / NMESH), ndir = E.smoke ? 2 : F1_NDIR, nl = f1_levels[lev];
  const char *obj = aniso_obj[lev][mk];
  {
    cb_mesh rest;
    if (cb_mesh_read_obj(obj, &rest)) return CB_EIO;
    cb_topology tp;
    if (cb_topology_build(&rest, &tp)) {
      cb_mesh_free(&rest);
      return CB_EINVAL;
    }
    char *pins = malloc(12 * (size_t)rest.nv + 16), *p = pins;
    int npin = 0, *isb = calloc((size_t)rest.nv, sizeof(int));
    if (!pins || !isb) {
      free(pins);
      free(isb);
      cb_topology_free(&tp);
      cb_mesh_free(&rest);
      return CB_ENOMEM;
    }
    for (int b = 0; b < tp.nb; b++) {
      isb[tp.edge[2 * tp.boundary[b]]] = 1;
      isb[tp.edge[2 * tp.boundary[b] + 1]] = 1;
    }
    *p = 0;
    for (int i = 0; i < rest.nv; i++)
      if (isb[i]) p += sprintf(p, npin++ ? " %d" : "%d", i);
    double area = 0;
    for (int t = 0; t < rest.nt; t++) area += cb_mesh_triangle_area(&rest, rest.x, t);
    for (int md = 0; md < 2; md++) {
      const char *sets[] = {md ? "material.stretch=fem" : "material.stretch=spring", NULL};
      cb_scene *s = NULL;
      int bs = lk_build(lk_scene_of("aniso"), sets, (mesh_kind)mk, 3, obj, pins, &s);
      if (bs) {
        free(pins);
        free(isb);
        cb_topology_free(&tp);
        cb_mesh_free(&rest);
        return bs;
      }
      size_t n3 = 3 * (size_t)s->mesh.nv;
      double *x = malloc(n3 * sizeof(double));
      for (int fam = 0; fam < 2; fam++)
        for (int di = 0; di < ndir; di++) {
          double deg = 180.0 * di / F1_NDIR;
          for (int i = 0; i < s->mesh.nv; i++)
            f1_load(fam, deg, s->mesh.x + 3 * i, x + 3 * i); /* the start: x = X + u(X) */
          cb_equilibrium_stats es;
          int rc = cb_stability_equilibrium(s, x, &ep, &es);
          double En = cb_system_elastic_energy(&s->sys, x);
          char test[32];
          snprintf(test, sizeof test, "%s_%g", f1_families[fam], deg);
          cb_csv_printf(f, "%s,%s,%d,%.17g,%s,%s,%g,%d,%g,%.17g,%.17g,%.17g,%d,%.6g,%s\n", models[md], mesh_names[mk],
                        nl, 1.0 / (nl - 1), f1_families[fam], test, deg, s->mesh.nv, F1_EPS, En, En / area, area,
                        s->model.nfree, es.residual,
                        cb_status_name(rc                                                    ? rc
                                       : es.status == CB_NOT_CONVERGED && es.residual < 1e-6 ? CB_OK
                                                                                             : es.status));
        }
      free(x);
      cb_scene_free(s);
    }
    free(pins);
    free(isb);
    cb_topology_free(&tp);
    cb_mesh_free(&rest);
  }
  return 0;
}
