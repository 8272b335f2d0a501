/* bending: the three bending models of material.bend on one hinge and on the
 * drape (claims B1, B2, B3), and the quadratic model against the continuous
 * bending energy.
 *
 * B1 (part b1): one two-triangle hinge (edge (0,0,0)-(1,0,0), wings at
 *     distance 0.8 m), wing x3 rotated about the edge by the fold angle
 *     0.5..90 deg; the restoring force |dE/dx3| at the wing tip for spring,
 *     dihedral and quadratic, each with material.bend_k = 1 in its own unit:
 *     its component along dx3/dphi (the one that unfolds the hinge: the
 *     torque about the edge over the 0.8 m arm), and |dE/dx3|.
 * B3 (part b3): a strip (1 m x 0.25 m, interior vertices jittered in-plane
 *     so a hinge's two wings differ; column wing_ratio: the largest area ratio
 *     of a hinge's two triangles) bent onto a cylinder of radius 0.5 m and
 *     stretched in-plane by a non-uniform field before it is bent: the
 *     strain grows linearly along the strip from 0 to the peak s = 0..30%
 *     (column stretch), either along the arc (`arc`: the hinges fold further)
 *     or along the cylinder's axis (`axis`: the folds stay). The quadratic
 *     energy against the dihedral (hinge) energy of the same state, both
 *     with the flat strip as rest shape; no closed form gives their ratio.
 * conv (part conv): a flat n x n grid (1 m, regular diagonals) bent
 *     isometrically onto a cylinder of radius R (axis along the grid's second
 *     axis); each model's energy (k = 1) against the continuous
 *     1/2 int |Delta x|^2 dA = A / (2 R^2), as n is refined.
 * B2 (part b2): configs/drape.ini under Newton with CHOLMOD at two grid
 *     resolutions (and, in the full run, on configs/drape_irregular.ini),
 *     quadratic against the dihedral model with each of its Hessians
 *     (material.bend_hessian, column hessian: gauss-newton, the default, and
 *     exact, projected per element; --quick runs exact on the smaller grid
 *     only): per-step medians of the assembly, factorisation, solve and total
 *     wall times, Newton iterations (total, the most in a step, steps that
 *     hit max_iters), contacts, the final kinetic energy, hinges whose exact
 *     Hessian the projection changes at the end; part b2_rms: the RMS vertex
 *     distance between the quadratic and the Gauss-Newton dihedral final
 *     shapes, and between the two dihedral Hessians' (the same energy).
 *     --smoke: the 12^2 grid, 3 steps, one round. The final shapes of the
 *     finest grid (quadratic, Gauss-Newton dihedral) are written as
 *     gnuplot triangle blocks, results/bending_rest_<model>.dat. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/material.h>
#include <clothbench/mesh.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/topology.h>
#include <clothbench/collider.h>
#include "rng.h"
#include "csv.h"
#include "bind.h"
#include "stats.h"
#include "experiment.h"

static const double PI = 3.14159265358979323846;
static const char *const MODELS[] = {"spring", "dihedral", "quadratic"};

/* ---- a hinge ------------------------------------------------------------- */

typedef struct {
  cb_mesh mesh;
  cb_topology topo;
  double mass[4];
  int free_index[4];
  cb_model model;
  double x[12], tri_x[12];
  int tri[6];
} hinge;

static int hinge_init(hinge *h) {
  memset(h, 0, sizeof *h);
  static const double X[12] = {0, 0, 0, 1, 0, 0, 0.5, 0.8, 0, 0.5, -0.8, 0};
  static const int T[6] = {0, 1, 2, 1, 0, 3};
  memcpy(h->tri_x, X, sizeof X);
  memcpy(h->tri, T, sizeof T);
  h->mesh = (cb_mesh){.nv = 4, .nt = 2, .x = h->tri_x, .tri = h->tri};
  if (cb_topology_build(&h->mesh, &h->topo)) return -1;
  for (int i = 0; i < 4; i++) {
    h->mass[i] = 1;
    h->free_index[i] = i;
  }
  h->model = (cb_model){&h->mesh, &h->topo, h->mass, h->free_index, 4};
  return h->topo.np == 1 ? 0 : -1;
}

/* x: the hinge folded by phi (rad), wing distance scaled by a, all scaled by u. */
static void hinge_pose(double phi, double a, double u, double *x) {
  const double X[12] = {0, 0, 0, 1, 0, 0, 0.5, 0.8 * a, 0, 0.5, -0.8 * a * cos(phi), 0.8 * a * sin(phi)};
  for (int i = 0; i < 12; i++) x[i] = u * X[i];
}

static double energy_grad(const cb_term *t, const double *x, double *g, int n3) {
  memset(g, 0, (size_t)n3 * sizeof *g);
  return t->type->energy(t, x, g);
}

static int part_hinge(FILE *f, int quick, int smoke) {
  hinge h;
  if (hinge_init(&h)) return -1;
  cb_term *t[3] = {NULL, NULL, NULL};
  for (int m = 0; m < 3; m++)
    if (cb_bend_term_alloc(MODELS[m], &h.model, 1.0, &t[m])) return -1;
  double x[12], g[12];
  /* B1: 1..10 deg by 1 (full: 0.5..10 by 0.5), then 20..90 by 10 (full: 15..90 by 5); 1, 5 and 30 included;
   * smoke: 1, 5, 10 and 30 deg */
  double angles[64];
  int na = 0;
  if (smoke) {
    static const double sm[] = {1, 5, 10, 30};
    for (int k = 0; k < 4; k++) angles[na++] = sm[k];
  } else {
    for (double d = quick ? 1.0 : 0.5; d <= 10 + 1e-9; d += quick ? 1.0 : 0.5) angles[na++] = d;
    for (double d = quick ? 20.0 : 15.0; d <= 90 + 1e-9; d += quick ? 10.0 : 5.0) angles[na++] = d;
  }
  for (int k = 0; k < na; k++) {
    double deg = angles[k];
    hinge_pose(deg * PI / 180, 1, 1, x);
    for (int m = 0; m < 3; m++) {
      double E = energy_grad(t[m], x, g, 12), F = sqrt(g[9] * g[9] + g[10] * g[10] + g[11] * g[11]);
      double ph = deg * PI / 180, Ft = g[10] * sin(ph) + g[11] * cos(ph); /* -(-dE/dx3) . dx3/dphi: > 0 unfolds */
      cb_csv_printf(f, "b1,%s,hinge,,%.17g,,,%.17g,%.17g,%.17g,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,ok\n", MODELS[m], deg,
                    Ft, F, E);
    }
  }
  for (int m = 0; m < 3; m++) cb_term_free(t[m]);
  cb_topology_free(&h.topo);
  return 0;
}

/* ---- B3: the stretched, curved strip ------------------------------------------- */

/* Area of the triangle (a, b, c). */
static double tri_area(const double *a, const double *b, const double *c) {
  double u[3], v[3];
  for (int k = 0; k < 3; k++) {
    u[k] = b[k] - a[k];
    v[k] = c[k] - a[k];
  }
  double n0 = u[1] * v[2] - u[2] * v[1], n1 = u[2] * v[0] - u[0] * v[2], n2 = u[0] * v[1] - u[1] * v[0];
  return 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
}

/* The strip: n x m vertices over 1 m x 0.25 m (plane xy, centred), interior vertices moved in-plane
 * by up to 0.25 h in each direction (fixed seed); flat rest shape. Its state at peak strain s:
 * with t = (u - u_min) / L in [0, 1], the in-plane map (arc) u' = u_min + L (t + s t^2 / 2), strain
 * s t along the strip, or (axis) v' = v (1 + s t), strain s t across it; then bent onto the cylinder
 * (u', v') -> (R sin(u'/R), v', R (1 - cos(u'/R))), which keeps lengths. */
static int part_strip(FILE *f, int quick, int smoke) {
  const int n = smoke ? 9 : quick ? 17 : 33, m = smoke ? 3 : quick ? 5 : 9, nstretch = smoke ? 3 : quick ? 16 : 61;
  const double L = 1.0, W = 0.25, R = 0.5;
  cb_grid_params gp = cb_grid_params_default();
  gp.n = n;
  gp.m = m;
  gp.size[0] = L;
  gp.size[1] = W;
  gp.plane = CB_PLANE_XY;
  cb_mesh mesh;
  cb_topology topo;
  if (cb_mesh_grid(&gp, &mesh)) return -1;
  double h = fmin(L / (n - 1), W / (m - 1));
  cb_rng rng = cb_rng_seed(19);
  for (int j = 1; j < m - 1; j++)
    for (int i = 1; i < n - 1; i++)
      for (int a = 0; a < 2; a++) mesh.x[3 * (j * n + i) + a] += 0.25 * h * (2 * cb_rng_uniform(&rng) - 1);
  if (cb_topology_build(&mesh, &topo)) return -1;
  int nv = mesh.nv, np = topo.np;
  double *mass = malloc((size_t)nv * sizeof *mass), *x = malloc((size_t)3 * nv * sizeof *x);
  int *fi = malloc((size_t)nv * sizeof *fi), *hv = malloc((size_t)4 * (np > 0 ? np : 1) * sizeof *hv);
  if (!mass || !x || !fi || !hv) return -1;
  for (int i = 0; i < nv; i++) {
    mass[i] = 1;
    fi[i] = i;
  }
  cb_model model = {&mesh, &topo, mass, fi, nv};
  cb_hinge_vertices(&topo, hv);
  double wing = 1; /* the largest area ratio of a hinge's two triangles */
  for (int p = 0; p < np; p++) {
    const double *x0 = mesh.x + 3 * hv[4 * p], *x1 = mesh.x + 3 * hv[4 * p + 1];
    double a = tri_area(x0, x1, mesh.x + 3 * hv[4 * p + 2]), b = tri_area(x0, x1, mesh.x + 3 * hv[4 * p + 3]);
    wing = fmax(wing, fmax(a / b, b / a));
  }
  free(hv);
  cb_term *tq, *td;
  if (cb_bend_term_alloc("quadratic", &model, 1.0, &tq) || cb_bend_term_alloc("dihedral", &model, 1.0, &td)) return -1;
  double umin = INFINITY, umax = -INFINITY;
  for (int i = 0; i < nv; i++) {
    umin = fmin(umin, mesh.x[3 * i]);
    umax = fmax(umax, mesh.x[3 * i]);
  }
  static const char *const modes[] = {"arc", "axis"};
  for (int mode = 0; mode < 2; mode++)
    for (int k = 0; k < nstretch; k++) {
      double s = 0.30 * k / (nstretch - 1);
      for (int i = 0; i < nv; i++) {
        double u = mesh.x[3 * i], v = mesh.x[3 * i + 1], t = (u - umin) / (umax - umin);
        if (mode == 0) u = umin + (umax - umin) * (t + 0.5 * s * t * t);
        else v *= 1 + s * t;
        x[3 * i] = R * sin(u / R);
        x[3 * i + 1] = v;
        x[3 * i + 2] = R * (1 - cos(u / R));
      }
      double Eq = tq->type->energy(tq, x, NULL), Ed = td->type->energy(td, x, NULL);
      cb_csv_printf(f,
                    "b3,quadratic,%s,%d,%.17g,%.17g,%.17g,,,%.17g,%.17g,%.17g,,,,,,,,,,,,,,,,,,,,,,,,,,%d,,,,%.17g,"
                    "ok\n",
                    modes[mode], n, h / R * 180 / PI, s, R, Eq, Ed, Eq / Ed, np, wing);
    }
  cb_term_free(tq);
  cb_term_free(td);
  free(mass);
  free(x);
  free(fi);
  cb_topology_free(&topo);
  cb_mesh_free(&mesh);
  return 0;
}

/* ---- the cylinder ---------------------------------------------------------- */

static int part_cylinder(FILE *f, int quick, int smoke) {
  const int ns[] = {4, 8, 16, 32, 64, 128};
  int nn = smoke ? 1 : quick ? 4 : 6;
  const double Rs[] = {1.0, 0.5};
  for (int ri = 0; ri < (smoke ? 1 : 2); ri++)
    for (int k = 0; k < nn; k++) {
      cb_grid_params gp = cb_grid_params_default();
      gp.n = gp.m = ns[k];
      gp.size[0] = gp.size[1] = 1.0;
      gp.plane = CB_PLANE_XY;
      cb_mesh mesh;
      cb_topology topo;
      if (cb_mesh_grid(&gp, &mesh) || cb_topology_build(&mesh, &topo)) return -1;
      int nv = mesh.nv;
      double *mass = malloc((size_t)nv * sizeof *mass), *x = malloc((size_t)3 * nv * sizeof *x);
      int *fi = malloc((size_t)nv * sizeof *fi);
      if (!mass || !x || !fi) return -1;
      for (int i = 0; i < nv; i++) {
        mass[i] = 1;
        fi[i] = i;
      }
      cb_model model = {&mesh, &topo, mass, fi, nv};
      double R = Rs[ri];
      for (int i = 0; i < nv; i++) { /* (u, v) -> (R sin(u/R), v, R (1 - cos(u/R))) */
        double u = mesh.x[3 * i], v = mesh.x[3 * i + 1];
        x[3 * i] = R * sin(u / R);
        x[3 * i + 1] = v;
        x[3 * i + 2] = R * (1 - cos(u / R));
      }
      double cont = 1.0 / (2 * R * R); /* A = 1 m^2 */
      for (int m = 1; m < 3; m++) {
        cb_term *t;
        if (cb_bend_term_alloc(MODELS[m], &model, 1.0, &t)) return -1;
        double E = t->type->energy(t, x, NULL);
        cb_csv_printf(f, "conv,%s,cylinder,%d,,,%.17g,,,%.17g,%.17g,%.17g,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,,ok\n",
                      MODELS[m], ns[k], R, E, cont, E / cont);
        cb_term_free(t);
      }
      free(mass);
      free(x);
      free(fi);
      cb_topology_free(&topo);
      cb_mesh_free(&mesh);
    }
  return 0;
}

/* ---- the drape --------------------------------------------------------------- */

typedef struct {
  int steps, iters, iters_max, unconverged, contacts, indefinite, nhinges, nv;
  double assemble, factor, solve, wall; /* per-step medians, ms */
  double wall_min, wall_max;            /* the fastest and slowest step, ms */
  double kinetic;
  double *x; /* final positions */
  char status[32];
} drape_result;

/* A bending model of the drape: material.bend and, for the dihedral model, material.bend_hessian. */
typedef struct {
  const char *model, *hessian; /* hessian: "constant" for the quadratic model (no key) */
} drape_model;

/* One drape run; shapes: also write the final shape (results/bending_rest_<model>.dat); keep it in r->x. */
static int drape(const cb_experiment *e, const char *ini, int n, const drape_model *dm, int steps, int shapes,
                 drape_result *r) {
  char sn[64], sb[64], ss[64], sh[64];
  const char *model = dm->model;
  snprintf(sn, sizeof sn, "mesh.n=%d", n);
  snprintf(sb, sizeof sb, "material.bend=%s", model);
  snprintf(ss, sizeof ss, "integrator.steps=%d", steps);
  snprintf(sh, sizeof sh, "material.bend_hessian=%s", dm->hessian);
  int keyed = strcmp(model, "dihedral") == 0;
  const char *sets[] = {sb, ss, keyed ? sh : NULL, n > 0 ? sn : NULL, NULL};
  if (!keyed) sets[2] = sets[3], sets[3] = NULL;
  cb_config c;
  cb_scene *s = NULL;
  cb_integrator *it = NULL;
  int st = cb_experiment_config(e, ini, sets, &c);
  if (st == CB_OK) st = cb_scene_from_config(&c, &s);
  if (st == CB_OK) st = cb_integrator_from_config(&c, s, NULL, &it);
  cb_run run;
  if (st == CB_OK) st = cb_run_init(&run, s, it);
  if (st) {
    fprintf(stderr, "bending: %s: %s\n", ini, cb_error_message());
    cb_integrator_free(it);
    cb_scene_free(s);
    return -1;
  }
  memset(r, 0, sizeof *r);
  snprintf(r->status, sizeof r->status, "ok");
  double *tm = malloc((size_t)4 * (steps > 0 ? steps : 1) * sizeof *tm); /* assembly, factor, solve, wall per step */
  if (!tm) return -1;
  for (int k = 0; k < steps; k++) {
    int ss2 = cb_run_step(&run);
    r->steps++;
    r->iters += run.last.newton_iters;
    r->iters_max = run.last.newton_iters > r->iters_max ? run.last.newton_iters : r->iters_max;
    r->unconverged += ss2 == CB_NOT_CONVERGED;
    tm[k] = run.last.assemble_ms;
    tm[steps + k] = run.last.factor_ms;
    tm[2 * steps + k] = run.last.solve_ms;
    tm[3 * steps + k] = run.last.wall_ms;
    r->wall_min = k == 0 || run.last.wall_ms < r->wall_min ? run.last.wall_ms : r->wall_min;
    r->wall_max = k == 0 || run.last.wall_ms > r->wall_max ? run.last.wall_ms : r->wall_max;
    if (cb_status_is_fatal(ss2)) {
      snprintf(r->status, sizeof r->status, "%s", cb_status_name(ss2));
      break;
    }
  }
  if (r->steps > 0) {
    r->assemble = cb_median(tm, r->steps);
    r->factor = cb_median(tm + steps, r->steps);
    r->solve = cb_median(tm + 2 * steps, r->steps);
    r->wall = cb_median(tm + 3 * steps, r->steps);
  }
  free(tm);
  r->kinetic = run.kinetic;
  r->contacts = cb_scene_contacts(s, run.x);
  for (int k = 0; k < s->sys.nterms; k++)
    if (cb_hinge_term_is(s->sys.terms[k]))
      r->indefinite = cb_hinge_term_count_indefinite(s->sys.terms[k], run.x, &r->nhinges);
  r->nv = s->mesh.nv;
  r->x = malloc((size_t)3 * r->nv * sizeof *r->x); /* for the RMS distances */
  if (r->x) memcpy(r->x, run.x, (size_t)3 * r->nv * sizeof *r->x);
  /* the rest shape as gnuplot triangle blocks (p0 p1 / p2 p2), for pm3d */
  if (shapes) {
    char path[2200], suffix[64];
    snprintf(suffix, sizeof suffix, "rest_%s.dat", model);
    cb_experiment_side_path(e, suffix, path, sizeof path);
    FILE *f = fopen(path, "w");
    if (f) {
      fprintf(f, "# bending: final shape of %s, grid %d^2, after %d steps; x y z per line, one triangle per block\n",
              model, n, r->steps);
      for (int t = 0; t < s->mesh.nt; t++) {
        const int *v = s->mesh.tri + 3 * t;
        const double *p0 = run.x + 3 * v[0], *p1 = run.x + 3 * v[1], *p2 = run.x + 3 * v[2];
        fprintf(f, "%.6f %.6f %.6f\n%.6f %.6f %.6f\n\n%.6f %.6f %.6f\n%.6f %.6f %.6f\n\n\n", p0[0], p0[1], p0[2], p1[0],
                p1[1], p1[2], p2[0], p2[1], p2[2], p2[0], p2[1], p2[2]);
      }
      fclose(f);
    }
  }
  cb_run_free(&run);
  cb_integrator_free(it);
  cb_scene_free(s);
  return 0;
}

/* The RMS vertex distance (m) between two final shapes. */
static double rms_distance(const drape_result *a, const drape_result *b) {
  double s2 = 0;
  for (int i = 0; i < 3 * a->nv; i++) s2 += (a->x[i] - b->x[i]) * (a->x[i] - b->x[i]);
  return sqrt(s2 / a->nv);
}

/* B2: per mesh, the quadratic drape and the dihedral drape with each Hessian, in interleaved rounds
 * (quadratic, dihedral Gauss-Newton, dihedral exact, quadratic, ...; stats.h: 3 rounds with --quick,
 * 2-5 in a full run by their cost; --smoke: one). --quick runs the exact Hessian on its smaller grid
 * only (a step there costs about ten Gauss-Newton ones). Every repeat computes the same run; a row
 * holds the first run's results, and per time (assembly, factor, solve, step) the median over the
 * repeats of the run's per-step median, its min, max and every repeat; step_min_ms and step_max_ms
 * are the fastest and slowest single step of any repeat. */
static int part_drape(cb_experiment *e, FILE *f) {
  static const drape_model models[] = {{"quadratic", "constant"}, {"dihedral", "gauss-newton"}, {"dihedral", "exact"}};
  enum { NMODELS = 3 };
  const int quick_n[] = {12, 16}, full_n[] = {16, 32};
  const int *ns = e->quick ? quick_n : full_n;
  int steps = e->smoke ? 3 : e->quick ? 30 : 90;
  int nmesh = e->smoke ? 1 : e->quick ? 2 : 3;
  int total = 0;
  for (int k = 0; k < nmesh; k++) total += e->quick && !e->smoke && k > 0 ? NMODELS - 1 : NMODELS;
  cb_progress_start(&e->progress, "drape", total);
  for (int k = 0; k < nmesh; k++) {
    const char *ini = k < 2 ? "drape.ini" : "drape_irregular.ini";
    int n = k < 2 ? ns[k] : 0;
    int nm = e->quick && !e->smoke && k > 0 ? NMODELS - 1 : NMODELS; /* quick: no exact Hessian on the larger grid */
    drape_result r[NMODELS];
    cb_timing tm[NMODELS][4]; /* per model: assembly, factor, solve, wall (per-step medians of each repeat) */
    double step_min[NMODELS], step_max[NMODELS], spent = 0;
    memset(tm, 0, sizeof tm);
    for (int m = 0; m < NMODELS; m++) {
      step_min[m] = INFINITY;
      step_max[m] = 0;
    }
    for (int round = 0; e->smoke ? round < 1 : cb_timing_more(e->quick, round, spent); round++)
      for (int m = 0; m < nm; m++) {
        drape_result x;
        if (drape(e, ini, n, &models[m], steps, round == 0 && m < 2 && k == (nmesh < 2 ? nmesh : 2) - 1, &x)) return -1;
        if (round == 0) r[m] = x;
        else free(x.x);
        const double part[4] = {x.assemble, x.factor, x.solve, x.wall};
        for (int q = 0; q < 4; q++) cb_timing_add(&tm[m][q], part[q]);
        step_min[m] = fmin(step_min[m], x.wall_min);
        step_max[m] = fmax(step_max[m], x.wall_max);
        spent += x.wall * x.steps;
        if (round == 0) cb_progress_update(&e->progress, e->progress.done + 1);
      }
    const char *mesh = k < 2 ? "grid" : "irregular";
    int size = k < 2 ? n : (int)lround(sqrt(r[0].nv));
    for (int m = 0; m < nm; m++) {
      drape_result *q = &r[m];
      const cb_timing *T = tm[m];
      cb_csv_printf(f, "b2,%s,%s,%d,,,,,,,,,%d,%d,%.6f,%.6f,%.6f,", models[m].model, mesh, size, q->steps, q->iters,
                    cb_timing_median(&T[0]), cb_timing_median(&T[1]), cb_timing_median(&T[2]));
      cb_timing_csv(f, &T[3], 1.0); /* wall_ms, wall_min_ms, wall_max_ms */
      fputc(',', f);
      cb_timing_csv_each(f, &T[3], 1.0);
      cb_csv_printf(f, ",%d,%.6f,%.6f", T[3].n, step_min[m], step_max[m]);
      for (int c = 0; c < 3; c++) { /* assemble, factor, solve: min, max, each */
        cb_csv_printf(f, ",%.6f,%.6f,", cb_timing_min(&T[c]), cb_timing_max(&T[c]));
        cb_timing_csv_each(f, &T[c], 1.0);
      }
      cb_csv_printf(f, ",%.17g,,%d,%d,%d,%s,%d,%d,,%s\n", q->kinetic, q->contacts, q->indefinite, q->nhinges,
                    models[m].hessian, q->iters_max, q->unconverged, q->status);
    }
    /* the quadratic against the default (Gauss-Newton) dihedral shape; the two dihedral Hessians' shapes */
    cb_csv_printf(f, "b2_rms,quadratic-dihedral,%s,%d,,,,,,,,,%d,,,,,,,,,,,,,,,,,,,,,,%.17g,,,,gauss-newton,,,,ok\n",
                  mesh, size, r[0].steps, rms_distance(&r[0], &r[1]));
    if (nm > 2 && r[2].x)
      cb_csv_printf(f,
                    "b2_rms,dihedral-dihedral,%s,%d,,,,,,,,,%d,,,,,,,,,,,,,,,,,,,,,,%.17g,,,,gauss-newton-exact,,,,"
                    "ok\n",
                    mesh, size, r[1].steps, rms_distance(&r[1], &r[2]));
    for (int m = 0; m < nm; m++) free(r[m].x);
  }
  cb_progress_end(&e->progress);
  return 0;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bending",
                              "B1, B2, B3: the restoring force of the spring, dihedral and quadratic bending models "
                              "against the fold angle; the drape under Newton, quadratic against dihedral with its "
                              "Gauss-Newton and exact Hessians (time split, Newton iterations, final-shape "
                              "difference); "
                              "the quadratic model on a curved strip under a non-uniform in-plane stretch; "
                              "the quadratic energy against 1/2 int |Delta x|^2 on refined cylinders.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* B2 is a wall-time ratio: run alone */
  cb_outfile o;
  if (cb_experiment_csv(
          &e, &o, NULL,
          "# b1: force_n = restoring force at the wing tip, the component of -dE/dx3 along -dx3/dphi (> 0 unfolds) "
          "(the torque over the 0.8 m arm), force_total_n = |dE/dx3|, bend_k = 1 (N/m spring, N m hinges); b3: the "
          "jittered strip (n vertices along it, hinges, wing_ratio = the largest area ratio of a hinge's two "
          "triangles) on a cylinder of radius_m, mesh = the stretch field (arc or axis), stretch = its peak strain, "
          "angle_deg = a grid step's fold h/R, energy_j quadratic, energy_ref_j dihedral; conv: energy_ref_j = "
          "A/(2R^2), radius_m = R; b2: per-step median times (ms), each the median over the repeats of the run "
          "(wall_min_ms, wall_max_ms, wall_each_ms and assemble_/factor_/solve_ likewise: its spread and every repeat; "
          "step_min_ms, step_max_ms: the fastest and slowest single step), newton_iters total, newton_iters_max "
          "the most in one step, unconverged_steps those that hit integrator.max_iters, hessian = the "
          "model's Hessian (material.bend_hessian; constant for the quadratic model), indefinite = hinges "
          "whose exact Hessian the projection changes at the final state; b2_rms: rms_m between the final "
          "shapes of model (quadratic-dihedral: the Gauss-Newton dihedral; dihedral-dihedral: its two Hessians)\n",
          "part,model,mesh,n,angle_deg,stretch,radius_m,force_n,force_total_n,energy_j,energy_ref_j,ratio,steps,"
          "newton_iters,assemble_ms,factor_ms,solve_ms,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,step_"
          "min_ms,"
          "step_max_ms,assemble_min_ms,assemble_max_ms,assemble_each_ms,factor_min_ms,factor_max_ms,factor_each_ms,"
          "solve_min_ms,solve_max_ms,solve_each_ms,kinetic_j,rms_m,contacts,"
          "indefinite,"
          "hinges,hessian,newton_iters_max,unconverged_steps,wing_ratio,status")) {
    fprintf(stderr, "bending: %s\n", cb_error_message());
    return 2;
  }
  if (part_hinge(o.f, e.quick, e.smoke) || part_strip(o.f, e.quick, e.smoke) || part_cylinder(o.f, e.quick, e.smoke) ||
      part_drape(&e, o.f)) {
    fprintf(stderr, "bending: %s\n", cb_error_message());
    return 2;
  }
  if (cb_outfile_commit(&o)) {
    fprintf(stderr, "bending: %s\n", cb_error_message());
    return 2;
  }
  return 0;
}
