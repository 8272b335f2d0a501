/* locking: membrane locking, the DoF count behind it, co-rotational FEM
 * against springs, and shape matching under explicit integration (claims L1,
 * L2, F1, S1). docs/experiments/locking.md explains every choice.
 *
 * L1  results/locking.csv: a 1 m square cloth (grids, regular and
 *     alternating) or a 1 m disk (the irregular ring disk of T2), horizontal,
 *     bending off, pinned on one side of a straight fold line through its
 *     centre, hangs under gravity. Its rest state is a static solve: proximal
 *     Newton steps x <- argmin E(y) + |y - x|_M^2/(2h^2) (lib/instruments/
 *     stability.c, cb_stability_equilibrium: implicit Euler from rest, h
 *     doubling to 10 s) until max_i |dE/dx_i| <= 1e-5 max_i m_i g. The fold
 *     angle is atan2(drop, offset) of the free part's centroid below and
 *     beyond the fold line: 90 deg hangs straight down, 0 stays flat.
 *     Sweep: in-plane stiffness k (spring) or mu (FEM) 1e1..1e7 N/m, four
 *     fold lines (along grid edges, along and across the regular diagonal, at
 *     30 deg), three meshes, springs and FEM. Whether the line runs along mesh
 *     edges is measured: no triangle has vertices strictly on both sides.
 * L2  results/locking_dofs.csv: 3 #variables - rank(rigidity matrix)
 *     (lib/instruments/rigidity.c) with every edge hard (conforming, variables
 *     at the vertices) and with every triangle rigid on edge-midpoint
 *     variables (nonconforming, English & Bridson 2008), at jittered generic
 *     positions, per vertex against mesh size.
 * F1  results/locking_aniso.csv: disks of radius 0.5 m in the plane (the grids clipped
 *     to it, and the ring disk), boundary held at X + u(X) for a non-affine u (a
 *     non-uniform stretch, an in-plane-bending shear) in 8 directions, interior
 *     relaxed by the same static solve, elastic energy per area (an affine load is
 *     FEM's patch test and would decide nothing); results/locking_newton.csv: one
 *     implicit Euler step of the lab cloth at 64^2 (32^2 with --quick), springs, FEM
 *     exact and FEM frozen, |grad F| and wall time per Newton iteration.
 * S1  results/locking_shape.csv: shape matching (integrator.shape_alpha swept) on
 *     explicit_stability's chain and 21^2 cloth, hanging vertically from the
 *     rest shape with a small random velocity, over explicit_stability's dt
 *     range; cells classified as there (energy = kinetic + gravity, the only
 *     energy shape matching has), and the shape error at the end (max edge
 *     strain, distance to the best-fit rigid motion of the rest shape), against
 *     springs (the scene's k) under symplectic Euler from the same start.
 * --smoke: one small cell per sweep (docs/experiments/locking.md says which). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include <clothbench/rng.h>
#include <clothbench/polar.h>
#include "csv.h"
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "rigidity.h"
#include "scene_decl.h"
#include "stability.h"
#include "stats.h"
#include "sweep.h"

#define PI 3.14159265358979323846
static cb_experiment E;
static char disk_xz[2048], disk_xy[2048];

/* ---- scenes ---------------------------------------------------------------------- */

typedef enum { MESH_REGULAR = 0, MESH_ALTERNATING, MESH_DISK, NMESH } mesh_kind;
static const char *const mesh_names[NMESH] = {"regular", "alternating", "disk"};

/* Scenes. Roles: "fold" = L1's base (hanging.ini as a horizontal 1 m cloth;
 * each cell adds the mesh, model and k); "aniso" = F1's patch in its plane
 * (each cell adds the mesh and model); "step" = F1's timed Newton step on the
 * lab cloth (one cell each; plan: the definiteness of the timed step, mesh.n
 * and the lab's 441 kg are added per run mode); "shape" = S1's scenes (one
 * cell per method: springs under symplectic Euler, shape matching per alpha).
 * The disks of L1 and F1 are ring disks generated in code and written as OBJs
 * beside the CSV before the sweeps (every shard writes them), and L2's meshes
 * (grids and ring disks, no scene) stay in code, as in topology. */
typedef struct { cb_scene_decl scene; const char *definiteness; } scene_plan;
static const scene_plan SCENES[] = {
    {{"fold", "hanging.ini", {"mesh.size=1", "mesh.plane=xz", "material.vertex_mass=0", "material.density=0.1", NULL}, "fold"}, NULL},
    {{"aniso", "hanging.ini", {"mesh.size=1", "mesh.plane=xy", "material.vertex_mass=0", "material.density=1",
                               "scene.gravity=0 0 0", "material.stretch_k=1000", NULL}, "aniso"}, NULL},
#define STEP(s, h) {"material.stretch=" s, "material.fem_hessian=" h, "integrator.definiteness=drop", "integrator.tol=1e-8", "integrator.max_iters=300", NULL}
    {{"spring_drop", "hanging.ini", STEP("spring", "exact"), "step"}, "drop"},
    {{"spring_none", "hanging.ini", STEP("spring", "exact"), "step"}, "none"},
    {{"fem_exact_drop", "hanging.ini", STEP("fem", "exact"), "step"}, "drop"},
    {{"fem_exact_none", "hanging.ini", STEP("fem", "exact"), "step"}, "none"},
    {{"fem_frozen", "hanging.ini", STEP("fem", "frozen"), "step"}, "drop"},
#undef STEP
    {{"chain20", "chain20.ini", {NULL}, "shape"}, NULL},
    {{"cloth21", "hanging.ini", {"mesh.plane=xy", NULL}, "shape"}, NULL}, /* hanging vertically, as explicit_stability */
};
enum { NSCENES = sizeof SCENES / sizeof SCENES[0] };
enum { T_MAIN, T_DOFS, T_ANISO, T_NEWTON, T_STEPS, T_SHAPE }; /* tables, in the order opened */

/* the first scene of a role */
static const cb_scene_decl *scene_of(const char *role) {
  for (int i = 0; i < NSCENES; i++)
    if (cb_scene_decl_is(&SCENES[i].scene, role)) return &SCENES[i].scene;
  return NULL;
}

/* The ring disk scaled to radius 0.5 m in plane xz (horizontal) or xy, as an OBJ beside the CSV. */
static int write_disk(int rings, int plane_xy) {
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
static int build(const cb_scene_decl *dl, const char *const *sets, mesh_kind mk, int n, const char *obj, const char *pins,
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
  char path[2 * CB_PATH_LEN];
  if ((st = cb_scene_def_from_config(&c, &d, path, sizeof path))) return st;
  if (obj) {
    d.mesh = CB_MESH_OBJ;
    d.mesh_file = obj;
  }
  if (pins) d.pins = pins;
  return cb_scene_build(&d, out, NULL);
}

/* Rest positions of the mesh kind without building a scene (for pin lists). */
static int rest_mesh(mesh_kind mk, int n, int plane_xy, cb_mesh *m) {
  if (mk == MESH_DISK) return cb_mesh_read_obj(plane_xy ? disk_xy : disk_xz, m);
  cb_grid_params g = cb_grid_params_default();
  g.n = g.m = n;
  g.size[0] = g.size[1] = 1.0;
  g.plane = plane_xy ? CB_PLANE_XY : CB_PLANE_XZ;
  g.diagonal = mk == MESH_ALTERNATING ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
  return cb_mesh_grid(&g, m);
}

/* Edge strain (l - L)/L: max |.| and RMS over the scene's edges at x. */
static void edge_strain(const cb_scene *s, const double *x, double *mx, double *rms) {
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

/* Distance to the best-fit rigid motion of the rest shape: min over rotations R and
 * translations t of sqrt(sum m_i |x_i - R X_i - t|^2 / sum m_i) (the mass-weighted
 * Procrustes fit: t from the centroids, R the polar rotation of sum m (x - c)(X - C)^T,
 * polar.h, planar and collinear shapes included), in m; *size the rest shape's RMS radius
 * sqrt(sum m |X - C|^2 / sum m) about its centroid C, in m. */
static double rigid_distance(const cb_scene *s, const double *x, double *size) {
  double c[3] = {0, 0, 0}, C[3] = {0, 0, 0}, M = 0, A[9] = {0}, R[9];
  const double *X = s->mesh.x;
  for (int i = 0; i < s->mesh.nv; i++) {
    M += s->mass[i];
    for (int a = 0; a < 3; a++) { c[a] += s->mass[i] * x[3 * i + a]; C[a] += s->mass[i] * X[3 * i + a]; }
  }
  if (!(M > 0)) { *size = NAN; return NAN; }
  for (int a = 0; a < 3; a++) { c[a] /= M; C[a] /= M; }
  double r2 = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    for (int a = 0; a < 3; a++) {
      r2 += s->mass[i] * (X[3 * i + a] - C[a]) * (X[3 * i + a] - C[a]);
      for (int b = 0; b < 3; b++) A[3 * a + b] += s->mass[i] * (x[3 * i + a] - c[a]) * (X[3 * i + b] - C[b]);
    }
  cb_polar33(A, R, NULL);
  double d2 = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    for (int a = 0; a < 3; a++) {
      double g = c[a];
      for (int b = 0; b < 3; b++) g += R[3 * a + b] * (X[3 * i + b] - C[b]);
      d2 += s->mass[i] * (x[3 * i + a] - g) * (x[3 * i + a] - g);
    }
  *size = sqrt(r2 / M);
  return sqrt(d2 / M);
}

static int degenerate(const cb_scene *s, const double *x) {
  int c = 0, nt;
  for (int k = 0; k < s->sys.nterms; k++) c += cb_fem_term_degenerate(s->sys.terms[k], x, &nt);
  return c;
}

/* ---- L1: fold angle at rest against in-plane stiffness ------------------------------ */

typedef struct { const char *name; double deg; } fold_line;
static const fold_line folds[] = {{"edges", 90}, {"diagonal", 45}, {"cross", 135}, {"angle30", 30}};
enum { NFOLD = 4 };

/* Cell ci: mesh kind ci / NFOLD, fold line ci % NFOLD, both models, every k. */
static int l1_cell(long ci, void *ctx, FILE *const *out) {
  static const char *const models[2] = {"spring", "fem"};
  int quick = *(const int *)ctx;
  FILE *f = out[T_MAIN];
  int nk = E.smoke ? 2 : quick ? 4 : 7, n = E.smoke ? 5 : quick ? 9 : 13;
  double ks[7];
  for (int j = 0; j < nk; j++) ks[j] = pow(10.0, 1.0 + 6.0 * j / (nk - 1));
  cb_equilibrium_params ep = cb_equilibrium_params_default();
  ep.tol = 1e-5;
  ep.max_steps = quick ? 300 : 400;
  int mk = (int)(ci / NFOLD), fl = E.smoke ? 2 : (int)(ci % NFOLD); /* smoke: the one cell is regular, cross */
  {
    cb_mesh rest;
    if (rest_mesh((mesh_kind)mk, n, 0, &rest)) return CB_EIO;
    {
      /* fold line through the centre with direction (cos, sin) in (x, z); pinned: side s <= 0 */
      double th = folds[fl].deg * PI / 180, nrm[2] = {sin(th), -cos(th)}; /* normal of the direction (cos, sin) */
      double tol = 1e-9;
      char *pins = malloc(16 * (size_t)rest.nv + 16), *p = pins, *end = pins + 16 * (size_t)rest.nv + 16;
      double *sd = malloc((size_t)rest.nv * sizeof(double));
      if (!pins || !sd) return CB_ENOMEM;
      *p = 0;
      int npin = 0;
      for (int i = 0; i < rest.nv; i++) {
        sd[i] = nrm[0] * rest.x[3 * i] + nrm[1] * rest.x[3 * i + 2];
        if (sd[i] <= tol) {
          int w = snprintf(p, (size_t)(end - p), npin ? " %d" : "%d", i);
          p += w;
          npin++;
        }
      }
      int on_edges = 1;
      for (int t = 0; t < rest.nt; t++) {
        int neg = 0, pos = 0;
        for (int a = 0; a < 3; a++) { neg |= sd[rest.tri[3 * t + a]] < -tol; pos |= sd[rest.tri[3 * t + a]] > tol; }
        if (neg && pos) on_edges = 0;
      }
      for (int md = 0; md < 2; md++)
        for (int ki = 0; ki < nk; ki++) {
          char sk[64];
          snprintf(sk, sizeof sk, "material.stretch_k=%.17g", ks[ki]);
          const char *sets[] = {md ? "material.stretch=fem" : "material.stretch=spring", sk, NULL};
          cb_scene *s = NULL;
          int bs = build(scene_of("fold"), sets, (mesh_kind)mk, n, mk == MESH_DISK ? disk_xz : NULL, pins, &s);
          if (bs) { free(pins); free(sd); cb_mesh_free(&rest); return bs; }
          size_t n3 = 3 * (size_t)s->mesh.nv;
          double *x = malloc(n3 * sizeof(double));
          memcpy(x, s->x0, n3 * sizeof(double));
          cb_equilibrium_stats es;
          int rc = cb_stability_equilibrium(s, x, &ep, &es);
          /* the free part's centroid against the fold line (through the origin, at y = 0) */
          double cm[3] = {0, 0, 0}, M = 0;
          for (int i = 0; i < s->mesh.nv; i++) {
            if (s->free_index[i] < 0) continue;
            for (int a = 0; a < 3; a++) cm[a] += s->mass[i] * x[3 * i + a];
            M += s->mass[i];
          }
          for (int a = 0; a < 3; a++) cm[a] /= M;
          double offset = nrm[0] * cm[0] + nrm[1] * cm[2], drop = -cm[1];
          double angle = atan2(drop, offset) * 180 / PI;
          double smax, srms;
          edge_strain(s, x, &smax, &srms);
          int st = rc ? rc : es.status;
          cb_csv_printf(f, "%s,%s,%s,%.0f,%d,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%ld,%.6g,%d,%.3f,%s\n", models[md],
                        mesh_names[mk], folds[fl].name, folds[fl].deg, on_edges, ks[ki], s->mesh.nv, npin, angle, offset, drop,
                        smax, srms, es.steps, es.newton_iters, es.residual, degenerate(s, x), es.ms, cb_status_name(st));
          free(x);
          cb_scene_free(s);
        }
      free(pins);
      free(sd);
    }
    cb_mesh_free(&rest);
  }
  return 0;
}

/* ---- L2: DoFs per vertex, conforming against nonconforming ------------------------- */

static void jitter(double *x, int n3, double h, unsigned seed) {
  cb_rng rng = cb_rng_seed(seed);
  for (int i = 0; i < n3; i++) x[i] += h * (cb_rng_uniform(&rng) - 0.5);
}

static void l2_row(FILE *f, const char *name, cb_mesh *m, unsigned seed) {
  cb_topology tp;
  if (cb_topology_build(m, &tp)) { cb_csv_printf(f, "%s,%d,%d,,,,,,,,,bad_input\n", name, m->nv, m->nt); return; }
  double h = 0.3 * sqrt(cb_mesh_triangle_area(m, m->x, 0));
  double *x = malloc((size_t)3 * m->nv * sizeof(double)), *mid = malloc((size_t)3 * tp.ne * sizeof(double));
  memcpy(x, m->x, (size_t)3 * m->nv * sizeof(double));
  jitter(x, 3 * m->nv, h, seed);
  int conf = cb_rigidity_dofs(m->nv, x, tp.ne, tp.edge);
  int *bar = NULL, nbars = 0, nonc = -1;
  if (cb_nonconforming_bars(m, m->x, tp.ne, tp.edge, mid, &bar, &nbars) == CB_OK) {
    jitter(mid, 3 * tp.ne, h, seed + 1000); /* generic midpoint positions */
    nonc = cb_rigidity_dofs(tp.ne, mid, nbars, bar);
  }
  /* a count the SVD (or the bar construction) did not give (-1) is written empty */
  cb_csv_printf(f, "%s,%d,%d,%d,%d,%.17g,%d,%.17g,%d,%.17g,%d,%.17g,%s\n", name, m->nv, m->nt, tp.ne, tp.nb,
                conf < 0 ? cb_csv_na() : conf, 3 + tp.nb, conf < 0 ? cb_csv_na() : (double)conf / m->nv, tp.ne,
                nonc < 0 ? cb_csv_na() : nonc, 3 * m->nv - 3, nonc < 0 ? cb_csv_na() : (double)nonc / m->nv,
                conf < 0 || nonc < 0 ? "svd_failed" : "ok");
  free(bar);
  free(x);
  free(mid);
  cb_topology_free(&tp);
}

/* Cells: the grids (size k = i / 2, diagonal pattern i % 2), then the ring disks. */
static int l2_cell(long i, void *ctx, FILE *const *out) {
  static const int sizes[] = {3, 4, 6, 8, 10};
  int quick = *(const int *)ctx, ns = quick ? 4 : 5;
  FILE *f = out[T_DOFS];
  if (i < 2L * ns) {
    int k = (int)i / 2, d = (int)i % 2;
    {
      cb_grid_params g = cb_grid_params_default();
      g.n = g.m = sizes[k];
      g.diagonal = d ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
      cb_mesh m;
      char name[64];
      snprintf(name, sizeof name, "grid_%dx%d_%s", g.n, g.m, d ? "alternating" : "regular");
      if (cb_mesh_grid(&g, &m) == CB_OK) l2_row(f, name, &m, 7 + (unsigned)k);
      cb_mesh_free(&m);
    }
  } else {
    int rings = (int)(i - 2L * ns) + 1;
    cb_mesh m;
    char name[64];
    snprintf(name, sizeof name, "ring_disk_%d", rings);
    if (cb_ring_disk(rings, &m) == CB_OK) l2_row(f, name, &m, 100 + (unsigned)rings);
    cb_mesh_free(&m);
  }
  return CB_OK;
}

/* ---- F1: anisotropy of the response, and one Newton step ---------------------------- */

/* F1's patches: disks of radius F1_R in plane xy. The grids (regular, alternating) are
 * clipped to the disk (the triangles with every vertex inside) and written as OBJs beside the CSV
 * before the sweeps, like the ring disk, so that every mesh has the same round domain and every
 * load direction meets the same boundary. */
#define F1_R 0.5
static char aniso_obj[NMESH][2048];

/* The n^2 grid of kind mk on [-0.5, 0.5]^2 (plane xy), clipped to the disk of radius F1_R, as an OBJ. */
static int write_clipped_grid(mesh_kind mk, int n) {
  cb_mesh g, m;
  int st = rest_mesh(mk, n, 1, &g);
  if (st) return st;
  memset(&m, 0, sizeof m);
  int *map = malloc((size_t)g.nv * sizeof(int));
  m.tri = malloc(3 * (size_t)g.nt * sizeof(int));
  m.x = malloc(3 * (size_t)g.nv * sizeof(double));
  if (!map || !m.tri || !m.x) { free(map); cb_mesh_free(&m); cb_mesh_free(&g); return CB_ENOMEM; }
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
  cb_experiment_side_path(&E, mk == MESH_REGULAR ? "grid_regular_xy.obj" : "grid_alternating_xy.obj", aniso_obj[mk],
                          sizeof aniso_obj[mk]);
  st = cb_mesh_write_obj(&m, NULL, aniso_obj[mk]);
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
#define F1_NDIR 8 /* directions 0, 22.5, ..., 157.5 deg (dir + 180 is the same load for shear, its mirror for stretch) */
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

/* Cell ci: mesh kind ci, both models, both loads in every direction. */
static int f1_aniso_cell(long ci, void *ctx, FILE *const *out) {
  static const char *const models[2] = {"spring", "fem"};
  (void)ctx;
  FILE *f = out[T_ANISO];
  cb_equilibrium_params ep = cb_equilibrium_params_default();
  ep.tol = 1e-8;
  ep.max_steps = 200;
  int mk = (int)ci, ndir = E.smoke ? 2 : F1_NDIR;
  {
    cb_mesh rest;
    if (cb_mesh_read_obj(aniso_obj[mk], &rest)) return CB_EIO;
    cb_topology tp;
    if (cb_topology_build(&rest, &tp)) { cb_mesh_free(&rest); return CB_EINVAL; }
    char *pins = malloc(12 * (size_t)rest.nv + 16), *p = pins;
    int npin = 0, *isb = calloc((size_t)rest.nv, sizeof(int));
    if (!pins || !isb) { free(pins); free(isb); cb_topology_free(&tp); cb_mesh_free(&rest); return CB_ENOMEM; }
    for (int b = 0; b < tp.nb; b++) { isb[tp.edge[2 * tp.boundary[b]]] = 1; isb[tp.edge[2 * tp.boundary[b] + 1]] = 1; }
    *p = 0;
    for (int i = 0; i < rest.nv; i++)
      if (isb[i]) p += sprintf(p, npin++ ? " %d" : "%d", i);
    double area = 0;
    for (int t = 0; t < rest.nt; t++) area += cb_mesh_triangle_area(&rest, rest.x, t);
    for (int md = 0; md < 2; md++) {
      const char *sets[] = {md ? "material.stretch=fem" : "material.stretch=spring", NULL};
      cb_scene *s = NULL;
      int bs = build(scene_of("aniso"), sets, (mesh_kind)mk, 3, aniso_obj[mk], pins, &s);
      if (bs) { free(pins); free(isb); cb_topology_free(&tp); cb_mesh_free(&rest); return bs; }
      size_t n3 = 3 * (size_t)s->mesh.nv;
      double *x = malloc(n3 * sizeof(double));
      for (int fam = 0; fam < 2; fam++)
        for (int di = 0; di < ndir; di++) {
          double deg = 180.0 * di / F1_NDIR;
          for (int i = 0; i < s->mesh.nv; i++) f1_load(fam, deg, s->mesh.x + 3 * i, x + 3 * i); /* the start: x = X + u(X) */
          cb_equilibrium_stats es;
          int rc = cb_stability_equilibrium(s, x, &ep, &es);
          double En = cb_system_elastic_energy(&s->sys, x);
          char test[32];
          snprintf(test, sizeof test, "%s_%g", f1_families[fam], deg);
          cb_csv_printf(f, "%s,%s,%s,%s,%g,%d,%g,%.17g,%.17g,%.17g,%d,%.6g,%s\n", models[md], mesh_names[mk], f1_families[fam],
                        test, deg, s->mesh.nv, F1_EPS, En, En / area, area, s->model.nfree, es.residual,
                        cb_status_name(rc ? rc : es.status == CB_NOT_CONVERGED && es.residual < 1e-6 ? CB_OK : es.status));
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

typedef struct { FILE *f; const char *model; int rep; double t0; } trace_ctx;
static void trace_hook(void *ctx, int event, const cb_newton_event *ev) {
  trace_ctx *c = ctx;
  if (event != CB_NEWTON_GRADIENT) return;
  cb_csv_printf(c->f, "%s,%d,%d,%.17g,%.17g,%.17g,%.4f\n", c->model, c->rep, ev->iter, ev->F, ev->grad_norm, ev->rel_grad,
                cb_now_ms() - c->t0);
}

/* the scenes of a role, in table order */
static int nsteps, step_idx[NSCENES], nshape, shape_idx[NSCENES];

/* One model's timed step: its scene and integrator, and the state after the warm-up steps. */
typedef struct {
  cb_scene *s;
  cb_integrator *it;
  double *x, *v, *xs, *vs;
  size_t n3;
} f1_model;

static void f1_model_free(f1_model *m) {
  free(m->x); free(m->v); free(m->xs); free(m->vs);
  cb_integrator_free(m->it);
  cb_scene_free(m->s);
  memset(m, 0, sizeof *m);
}

/* The "step" scene sm on the n^2 lab cloth: five steps to swing down (drop), then its own policy
 * for the timed step, to a tight tolerance. */
static int f1_model_init(const scene_plan *sm, int n, f1_model *m) {
  memset(m, 0, sizeof *m);
  char sn[32], sm_mass[64], sd[48];
  snprintf(sn, sizeof sn, "mesh.n=%d", n);
  snprintf(sm_mass, sizeof sm_mass, "material.vertex_mass=%.17g", 441.0 / ((double)n * n)); /* the lab's 441 kg */
  snprintf(sd, sizeof sd, "integrator.definiteness=%s", sm->definiteness);
  const char *sets[] = {sn, sm_mass, NULL};
  cb_config c;
  int bs = cb_scene_decl_build(&E, &sm->scene, sets, &c, &m->s);
  if (bs) return bs;
  cb_integrator_params ip;
  cb_integrator_params_from_config(&c, &ip);
  if ((bs = cb_integrator_from_config(&c, m->s, &ip, &m->it))) return bs;
  m->n3 = 3 * (size_t)m->s->mesh.nv;
  m->x = malloc(m->n3 * sizeof(double));
  m->v = calloc(m->n3, sizeof(double));
  m->xs = malloc(m->n3 * sizeof(double));
  m->vs = malloc(m->n3 * sizeof(double));
  if (!m->x || !m->v || !m->xs || !m->vs) return cb_fail_status(CB_ENOMEM, "out of memory");
  memcpy(m->x, m->s->x0, m->n3 * sizeof(double));
  cb_step_stats st;
  for (int k = 0; k < 5; k++) { memset(&st, 0, sizeof st); cb_integrator_step(m->it, m->x, m->v, &st); } /* swing down */
  cb_newton_params *np = m->it->type_params;
  cb_config cd = c; /* the method's policy for the timed step (the warm-up used drop) */
  if ((bs = cb_config_set(&cd, sd)) || (bs = cb_newton_params_from_config(&cd, np))) return bs;
  np->tol = 1e-12;
  np->tol_dx = 1e-12;
  np->max_iters = 300;
  return CB_OK;
}

/* One timed step of m from its state (traced into f with rep when f is not NULL); *ms its wall time. */
static int f1_model_step(f1_model *m, FILE *f, const char *model, int rep, cb_step_stats *st, double *ms) {
  memcpy(m->xs, m->x, m->n3 * sizeof(double));
  memcpy(m->vs, m->v, m->n3 * sizeof(double));
  trace_ctx tc = {f, model, rep, cb_now_ms()};
  m->it->params.hook = f ? trace_hook : NULL;
  m->it->params.hook_ctx = &tc;
  memset(st, 0, sizeof *st);
  int rc = cb_integrator_step(m->it, m->xs, m->vs, st);
  *ms = cb_now_ms() - tc.t0;
  m->it->params.hook = NULL;
  return rc;
}

/* The one cell of F1's timed step: every "step" scene (model, Hessian, definiteness of the timed
 * step) timed in interleaved rounds (stats.h: 3 with --quick, 2-5 in a full run by their cost; a
 * step under 25 ms timed right after an untimed one of its own); a row per model and round, rep
 * the round; the step's |grad F| per iteration traced at every round. */
static int f1_newton_cell(long i, void *ctx, FILE *const *out) {
  (void)i;
  int quick = *(const int *)ctx, n = E.smoke ? 8 : quick ? 32 : 64, st = CB_OK;
  FILE *f = out[T_NEWTON], *fs = out[T_STEPS];
  static f1_model M[NSCENES];
  for (int k = 0; k < nsteps; k++) memset(&M[k], 0, sizeof M[k]);
  for (int k = 0; st == CB_OK && k < nsteps; k++) st = f1_model_init(&SCENES[step_idx[k]], n, &M[k]);
  double spent = 0;
  for (int round = 0; st == CB_OK && cb_timing_more(quick, round, spent); round++)
    for (int k = 0; k < nsteps; k++) {
      const char *model = SCENES[step_idx[k]].scene.label;
      cb_step_stats ss;
      double ms;
      char *buf = NULL;
      size_t len = 0;
      FILE *tf = open_memstream(&buf, &len); /* the trace, kept if this run is the repeat */
      if (!tf) { st = cb_fail_status(CB_ENOMEM, "out of memory"); break; }
      int rc = f1_model_step(&M[k], tf, model, round, &ss, &ms);
      if (cb_timing_warm(ms)) { /* that was the warm-up: the repeat is the next run */
        fclose(tf);
        free(buf);
        buf = NULL;
        if (!(tf = open_memstream(&buf, &len))) { st = cb_fail_status(CB_ENOMEM, "out of memory"); break; }
        rc = f1_model_step(&M[k], tf, model, round, &ss, &ms);
      }
      fclose(tf);
      fwrite(buf, 1, len, f);
      free(buf);
      spent += ms;
      cb_csv_printf(fs, "%s,%d,%d,%d,%d,%.17g,%.4f,%.4f,%.4f,%.4f,%s\n", model, n, round, ss.newton_iters,
                    ss.factorizations, ss.rel_grad, ss.assemble_ms, ss.factor_ms, ss.solve_ms, ms, cb_status_name(rc));
    }
  for (int k = 0; k < nsteps; k++) f1_model_free(&M[k]);
  return st;
}

/* ---- S1: shape matching under explicit integration --------------------------------- */

/* Cell i: "shape" scene i / (na + 1), method i % (na + 1) - 1 (-1: springs under
 * symplectic Euler, else shape matching at alpha[m]), every dt (one start state). */
static int s1_cell(long i, void *ctx, FILE *const *out) {
  int quick = *(const int *)ctx;
  FILE *f = out[T_SHAPE];
  double alphas[5] = {0.01, 0.03, 0.1, 0.3, 1};
  int na = quick ? 3 : 5, ndt = E.smoke ? 2 : quick ? 7 : 13;
  if (quick) { alphas[1] = 0.1; alphas[2] = 1; }
  cb_stability_params sp = cb_stability_params_default();
  sp.sim_time = quick ? 1.0 : 2.0;
  sp.min_steps = E.smoke ? 20 : 200;
  sp.max_steps = quick ? 1000 : 2000;
  sp.energy_every = 4;
  const cb_scene_decl *sc = &SCENES[shape_idx[i / (na + 1)]].scene;
  {
    int m = E.smoke ? na - 1 : (int)(i % (na + 1)) - 1; /* smoke: the one cell is shape matching at alpha = 1 */
    {
      char sa[48];
      snprintf(sa, sizeof sa, "integrator.shape_alpha=%.17g", m >= 0 ? alphas[m] : 1.0);
      const char *sets[10] = {m >= 0 ? "integrator.method=shape_matching" : "integrator.method=explicit", sa};
      int k = 2;
      if (m >= 0) sets[k++] = "material.stretch_k=0"; /* shape matching has no elastic energy of its own */
      sets[k] = NULL;
      cb_config c;
      cb_scene *s = NULL;
      cb_integrator *it = NULL;
      int bs = cb_scene_decl_build(&E, sc, sets, &c, &s);
      if (bs) return bs;
      cb_integrator_params ip;
      cb_integrator_params_from_config(&c, &ip);
      if ((bs = cb_integrator_from_config(&c, s, &ip, &it))) { cb_scene_free(s); return bs; }
      size_t n3 = 3 * (size_t)s->mesh.nv;
      double *x0 = malloc(n3 * sizeof(double)), *v0 = calloc(n3, sizeof(double));
      memcpy(x0, s->mesh.x, n3 * sizeof(double)); /* the rest shape */
      double S0 = cb_stability_energy_scale(s, x0, v0);
      cb_stability_perturb(s, 1e-6 * S0, 1, v0);
      double S = cb_stability_energy_scale(s, x0, v0);
      cb_cell_work w;
      if ((bs = cb_cell_work_alloc(s, &w))) return bs;
      for (int j = 0; j < ndt; j++) {
        double dt = pow(10.0, -5.0 + 4.0 * j / (ndt - 1));
        cb_cell_result r;
        int rc = cb_stability_cell(it, dt, x0, v0, S, &sp, &w, &r);
        double smax, srms, size, none = cb_csv_na();
        edge_strain(s, w.x, &smax, &srms);
        double rd = rigid_distance(s, w.x, &size);
        /* springs have no alpha; a cell that failed to run (rc) measured nothing */
        cb_csv_printf(f, "%s,%s,%.6g,%.17g,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.3f,%s\n", sc->label,
                      m >= 0 ? "shape_matching" : "spring_explicit", m >= 0 ? alphas[m] : none, dt,
                      rc ? "failed" : cb_cell_class_name(r.cls), rc ? none : r.max_energy_ratio, rc ? none : r.final_energy_ratio,
                      rc ? none : (double)r.steps, rc ? none : r.t_end, rc ? none : isfinite(smax) ? smax : NAN,
                      rc ? none : isfinite(srms) ? srms : NAN, rc ? none : isfinite(rd) ? rd : NAN,
                      rc ? none : isfinite(rd) ? rd / size : NAN, rc ? none : r.wall_ms,
                      rc ? cb_status_name(rc) : cb_status_name(r.step_status));
      }
      cb_cell_work_free(&w);
      free(x0); free(v0);
      cb_integrator_free(it);
      cb_scene_free(s);
    }
  }
  return 0;
}

int main(int argc, char **argv) {
  int r = cb_experiment_begin(&E, "locking", "L1, L2, F1 and S1: membrane locking of stiff in-plane edges, the DoF count "
                                             "behind it (conforming against nonconforming elements), co-rotational FEM "
                                             "against springs, and shape matching under explicit integration.", argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&E); /* F1 times a Newton step: run alone */
  int quick = E.quick, st = CB_OK;
  for (int i = 0; i < NSCENES; i++) {
    if (cb_scene_decl_is(&SCENES[i].scene, "step")) step_idx[nsteps++] = i;
    if (cb_scene_decl_is(&SCENES[i].scene, "shape")) shape_idx[nshape++] = i;
  }
  if (cb_experiment_table(&E, NULL,
                          "# L1: static rest state by proximal Newton steps (cb_stability_equilibrium), tol max|dE/dx| <= 1e-5 max m g; "
                          "fold_angle_deg = atan2(drop, offset) of the free part's centroid; on_edges = no triangle straddles the fold line\n",
                          "model,mesh,fold,fold_dir_deg,on_edges,k_n_per_m,vertices,pinned,fold_angle_deg,offset_m,drop_m,"
                          "max_strain,rms_strain,eq_steps,newton_iters,residual,degenerate,eq_wall_ms,status") != T_MAIN ||
      cb_experiment_table(&E, "dofs", "# L2: DoFs = 3 #variables - rank(rigidity matrix) at jittered generic positions (GSL SVD, threshold 1e-9)\n",
                          "mesh,vertices,triangles,edges,boundary_edges,conforming_dofs,conforming_predicted,"
                          "conforming_per_vertex,nonconforming_variables,nonconforming_dofs,nonconforming_predicted,"
                          "nonconforming_per_vertex,status") != T_DOFS ||
      cb_experiment_table(&E, "aniso", "# F1: disks of radius 0.5 m (grids clipped to it), boundary held at X + u(X) for a non-affine u along "
                          "dir_deg (stretch: u = eps (s + R)^2/(4R) n; shear: u = eps s^2/(2R) t; s = n.X, eps = strain), "
                          "interior relaxed; k = mu = 1000 N/m\n",
                          "model,mesh,family,test,dir_deg,vertices,strain,energy_j,energy_density_j_per_m2,area_m2,free_vertices,"
                          "residual,status") != T_ANISO ||
      cb_experiment_table(&E, "newton", "# F1: one implicit Euler step of the lab cloth, |grad F| per Newton iteration; wall_ms since the step began\n",
                          "model,rep,iter,f_j,grad_norm_n,rel_grad,wall_ms") != T_NEWTON ||
      cb_experiment_table(&E, "newton_steps", NULL,
                          "model,n,rep,newton_iters,factorizations,rel_grad,assemble_ms,factor_ms,solve_ms,step_wall_ms,status") != T_STEPS ||
      cb_experiment_table(&E, "shape", "# S1: cells as explicit_stability (energy = kinetic + elastic + gravity; shape matching scenes have k = 0); "
                          "shape error at the end: edge strain (l - L)/L against the rest shape, and the mass-weighted RMS distance "
                          "to the best-fit rigid motion of the rest shape (rigid_dist_m; over the rest shape's RMS radius: "
                          "rigid_dist_over_size)\n",
                          "scene,method,alpha,dt_s,class,max_energy_ratio,final_energy_ratio,steps,t_end_s,"
                          "max_strain,rms_strain,rigid_dist_m,rigid_dist_over_size,cell_wall_ms,step_status") != T_SHAPE)
    return cb_experiment_end(&E, CB_EIO), 2;
  /* the disks of L1 (horizontal) and F1 (in plane xy): inputs of cells, written by every shard */
  /* and F1's clipped grids (the disk of F1 is disk_xy) */
  if ((st = write_disk(quick ? 4 : 6, 0)) || (st = write_disk(quick ? 5 : 7, 1)) ||
      (st = write_clipped_grid(MESH_REGULAR, E.smoke ? 7 : quick ? 11 : 15)) ||
      (st = write_clipped_grid(MESH_ALTERNATING, E.smoke ? 7 : quick ? 11 : 15)))
    return cb_experiment_end(&E, st), 2;
  memcpy(aniso_obj[MESH_DISK], disk_xy, sizeof disk_xy);
  const cb_sweep sweeps[] = {
      /* --smoke: one small cell per sweep (the cells say which) */
      {"L2 meshes", E.smoke ? 1 : 2L * (quick ? 4 : 5) + (quick ? 3 : 5), l2_cell, NULL, &quick},
      {"F1 anisotropy", E.smoke ? 1 : NMESH, f1_aniso_cell, NULL, &quick},
      {"F1 Newton step", nsteps > 0, f1_newton_cell, NULL, &quick},
      {"S1 shape matching", E.smoke ? 1 : nshape * ((quick ? 3L : 5L) + 1), s1_cell, NULL, &quick},
      {"L1 fold", E.smoke ? 1 : (long)NMESH * NFOLD, l1_cell, NULL, &quick},
  };
  st = cb_sweep_run(&E, sweeps, (int)(sizeof sweeps / sizeof sweeps[0]));
  st = cb_experiment_end(&E, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
