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
 * B3 (part b3): the same hinge folded by 20 deg and stretched in-plane by
 *     0..30%: uniformly (every position scaled about x0, angles kept) and
 *     across the edge (the wings' distance from the edge scaled); quadratic
 *     energy against the dihedral (hinge) energy of the stretched state.
 * conv (part conv): a flat n x n grid (1 m, regular diagonals) bent
 *     isometrically onto a cylinder of radius R (axis along the grid's second
 *     axis); each model's energy (k = 1) against the continuous
 *     1/2 int |Delta x|^2 dA = A / (2 R^2), as n is refined.
 * B2 (part b2): configs/drape.ini under Newton with CHOLMOD at two grid
 *     resolutions (and, in the full run, on configs/drape_irregular.ini),
 *     quadratic against dihedral: per-step medians of the assembly,
 *     factorisation, solve and total wall times, Newton iterations, contacts,
 *     the final kinetic energy, hinges whose Hessian the projection changed at
 *     the end; part b2_rms: the RMS vertex distance between the two models'
 *     final shapes. The final shapes of the finest grid are written as
 *     gnuplot triangle blocks, results/bending_rest_<model>.dat. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include <clothbench/collider.h>
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

static int part_hinge(FILE *f, int quick) {
  hinge h;
  if (hinge_init(&h)) return -1;
  cb_term *t[3] = {NULL, NULL, NULL};
  for (int m = 0; m < 3; m++)
    if (cb_bend_term_alloc(MODELS[m], &h.model, 1.0, &t[m])) return -1;
  double x[12], g[12];
  /* B1: 1..10 deg by 1 (full: 0.5..10 by 0.5), then 20..90 by 10 (full: 15..90 by 5); 1, 5 and 30 included */
  double angles[64];
  int na = 0;
  for (double d = quick ? 1.0 : 0.5; d <= 10 + 1e-9; d += quick ? 1.0 : 0.5) angles[na++] = d;
  for (double d = quick ? 20.0 : 15.0; d <= 90 + 1e-9; d += quick ? 10.0 : 5.0) angles[na++] = d;
  for (int k = 0; k < na; k++) {
    double deg = angles[k];
    hinge_pose(deg * PI / 180, 1, 1, x);
    for (int m = 0; m < 3; m++) {
      double E = energy_grad(t[m], x, g, 12), F = sqrt(g[9] * g[9] + g[10] * g[10] + g[11] * g[11]);
      double ph = deg * PI / 180, Ft = g[10] * sin(ph) + g[11] * cos(ph); /* -(-dE/dx3) . dx3/dphi: > 0 unfolds */
      cb_csv_printf(f, "b1,%s,hinge,,%.17g,,,%.17g,%.17g,%.17g,,,,,,,,,,,,,,,,,,,,,,,,,,,,,ok\n", MODELS[m], deg, Ft, F, E);
    }
  }
  /* B3: fold 20 deg, stretch 0..30% */
  const double fold = 20.0;
  for (int mode = 0; mode < 2; mode++)
    for (int k = 0; k <= (quick ? 15 : 60); k++) {
      double s = 0.30 * k / (quick ? 15 : 60);
      hinge_pose(fold * PI / 180, mode ? 1 + s : 1, mode ? 1 : 1 + s, x);
      double Eq = energy_grad(t[2], x, g, 12), Ed = energy_grad(t[1], x, g, 12);
      cb_csv_printf(f, "b3,quadratic,%s,,%.17g,%.17g,,,,%.17g,%.17g,%.17g,,,,,,,,,,,,,,,,,,,,,,,,,,,ok\n", mode ? "across" : "uniform", fold, s,
                    Eq, Ed, Eq / Ed);
    }
  for (int m = 0; m < 3; m++) cb_term_free(t[m]);
  cb_topology_free(&h.topo);
  return 0;
}

/* ---- the cylinder ---------------------------------------------------------- */

static int part_cylinder(FILE *f, int quick) {
  const int ns[] = {4, 8, 16, 32, 64, 128};
  int nn = quick ? 4 : 6;
  const double Rs[] = {1.0, 0.5};
  for (int ri = 0; ri < 2; ri++)
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
        cb_csv_printf(f, "conv,%s,cylinder,%d,,,%.17g,,,%.17g,%.17g,%.17g,,,,,,,,,,,,,,,,,,,,,,,,,,,ok\n", MODELS[m], ns[k], R, E, cont, E / cont);
        cb_term_free(t);
      }
      free(mass); free(x); free(fi);
      cb_topology_free(&topo);
      cb_mesh_free(&mesh);
    }
  return 0;
}

/* ---- the drape --------------------------------------------------------------- */

typedef struct {
  int steps, iters, contacts, indefinite, nhinges, nv;
  double assemble, factor, solve, wall; /* per-step medians, ms */
  double wall_min, wall_max;            /* the fastest and slowest step, ms */
  double kinetic;
  double *x; /* final positions */
  char status[32];
} drape_result;

/* One drape run; shapes: also write the final shape (results/bending_rest_<model>.dat) and keep it in r->x. */
static int drape(const cb_experiment *e, const char *ini, int n, const char *model, int steps, int shapes, drape_result *r) {
  char sn[64], sb[64], ss[64];
  snprintf(sn, sizeof sn, "mesh.n=%d", n);
  snprintf(sb, sizeof sb, "material.bend=%s", model);
  snprintf(ss, sizeof ss, "integrator.steps=%d", steps);
  const char *sets[] = {sb, ss, n > 0 ? sn : NULL, NULL};
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
    if (strcmp(s->sys.terms[k]->type->name, "dihedral") == 0)
      r->indefinite = cb_hinge_term_count_indefinite(s->sys.terms[k], run.x, &r->nhinges);
  r->nv = s->mesh.nv;
  r->x = shapes ? malloc((size_t)3 * r->nv * sizeof *r->x) : NULL;
  if (r->x) memcpy(r->x, run.x, (size_t)3 * r->nv * sizeof *r->x);
  /* the rest shape as gnuplot triangle blocks (p0 p1 / p2 p2), for pm3d */
  if (shapes && (n == 32 || (e->quick && n == 16))) {
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

/* B2: per mesh, the quadratic and the dihedral drape in interleaved rounds (quadratic, dihedral,
 * quadratic, ...; stats.h: 3 rounds with --quick, 2-5 in a full run by their cost). Every repeat
 * computes the same run; a row holds the first run's results, and per time (assembly, factor,
 * solve, step) the median over the repeats of the run's per-step median, its min, max and every
 * repeat; step_min_ms and step_max_ms are the fastest and slowest single step of any repeat. */
static int part_drape(cb_experiment *e, FILE *f) {
  const int quick_n[] = {12, 16}, full_n[] = {16, 32};
  const int *ns = e->quick ? quick_n : full_n;
  int steps = e->quick ? 30 : 90;
  int nmesh = e->quick ? 2 : 3;
  cb_progress_start(&e->progress, "drape", 2L * nmesh);
  for (int k = 0; k < nmesh; k++) {
    const char *ini = k < 2 ? "drape.ini" : "drape_irregular.ini";
    int n = k < 2 ? ns[k] : 0;
    drape_result r[2];
    cb_timing tm[2][4]; /* per model: assembly, factor, solve, wall (per-step medians of each repeat) */
    double step_min[2] = {INFINITY, INFINITY}, step_max[2] = {0, 0}, spent = 0;
    memset(tm, 0, sizeof tm);
    for (int round = 0; cb_timing_more(e->quick, round, spent); round++)
      for (int m = 0; m < 2; m++) { /* quadratic, then dihedral */
        drape_result x;
        if (drape(e, ini, n, MODELS[2 - m], steps, round == 0, &x)) return -1;
        if (round == 0) r[m] = x;
        const double part[4] = {x.assemble, x.factor, x.solve, x.wall};
        for (int q = 0; q < 4; q++) cb_timing_add(&tm[m][q], part[q]);
        step_min[m] = fmin(step_min[m], x.wall_min);
        step_max[m] = fmax(step_max[m], x.wall_max);
        spent += x.wall * x.steps;
        if (round == 0) cb_progress_update(&e->progress, e->progress.done + 1);
      }
    for (int m = 0; m < 2; m++) {
      drape_result *q = &r[m];
      const cb_timing *T = tm[m];
      cb_csv_printf(f, "b2,%s,%s,%d,,,,,,,,,%d,%d,%.6f,%.6f,%.6f,", MODELS[2 - m], k < 2 ? "grid" : "irregular",
              k < 2 ? n : (int)lround(sqrt(q->nv)), q->steps, q->iters, cb_timing_median(&T[0]), cb_timing_median(&T[1]),
              cb_timing_median(&T[2]));
      cb_timing_csv(f, &T[3], 1.0); /* wall_ms, wall_min_ms, wall_max_ms */
      fputc(',', f);
      cb_timing_csv_each(f, &T[3], 1.0);
      cb_csv_printf(f, ",%d,%.6f,%.6f", T[3].n, step_min[m], step_max[m]);
      for (int c = 0; c < 3; c++) { /* assemble, factor, solve: min, max, each */
        cb_csv_printf(f, ",%.6f,%.6f,", cb_timing_min(&T[c]), cb_timing_max(&T[c]));
        cb_timing_csv_each(f, &T[c], 1.0);
      }
      cb_csv_printf(f, ",%.17g,,%d,%d,%d,%s\n", q->kinetic, q->contacts, q->indefinite, q->nhinges, q->status);
    }
    double s2 = 0;
    for (int i = 0; i < 3 * r[0].nv; i++) s2 += (r[0].x[i] - r[1].x[i]) * (r[0].x[i] - r[1].x[i]);
    cb_csv_printf(f, "b2_rms,quadratic-dihedral,%s,%d,,,,,,,,,%d,,,,,,,,,,,,,,,,,,,,,,%.17g,,,,ok\n", k < 2 ? "grid" : "irregular",
            k < 2 ? n : (int)lround(sqrt(r[0].nv)), r[0].steps, sqrt(s2 / r[0].nv));
    free(r[0].x);
    free(r[1].x);
  }
  cb_progress_end(&e->progress);
  return 0;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int r = cb_experiment_begin(&e, "bending",
                              "B1, B2, B3: the restoring force of the spring, dihedral and quadratic bending models "
                              "against the fold angle; the drape under Newton, quadratic against dihedral (time split, "
                              "Newton iterations, final-shape difference); the quadratic model under in-plane stretch; "
                              "the quadratic energy against 1/2 int |Delta x|^2 on refined cylinders.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&e); /* B2 is a wall-time ratio: run alone */
  cb_outfile o;
  if (cb_experiment_csv(&e, &o, NULL,
                        "# b1: force_n = restoring force at the wing tip, the component of -dE/dx3 along -dx3/dphi (> 0 unfolds) "
                        "(the torque over the 0.8 m arm), force_total_n = |dE/dx3|, bend_k = 1 (N/m spring, N m hinges); b3: energy_j "
                        "quadratic, energy_ref_j dihedral, fold angle_deg, stretch fraction; conv: energy_ref_j = "
                        "A/(2R^2), radius_m = R; b2: per-step median times (ms), each the median over the repeats of the run "
                        "(wall_min_ms, wall_max_ms, wall_each_ms and assemble_/factor_/solve_ likewise: its spread and every repeat; "
                        "step_min_ms, step_max_ms: the fastest and slowest single step), newton_iters total, "
                        "indefinite = hinges whose exact Hessian the projection changes at the final state\n",
                        "part,model,mesh,n,angle_deg,stretch,radius_m,force_n,force_total_n,energy_j,energy_ref_j,ratio,steps,"
                        "newton_iters,assemble_ms,factor_ms,solve_ms,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_repeats,step_min_ms,"
                        "step_max_ms,assemble_min_ms,assemble_max_ms,assemble_each_ms,factor_min_ms,factor_max_ms,factor_each_ms,"
                        "solve_min_ms,solve_max_ms,solve_each_ms,kinetic_j,rms_m,contacts,"
                        "indefinite,"
                        "hinges,status")) {
    fprintf(stderr, "bending: %s\n", cb_error_message());
    return 2;
  }
  if (part_hinge(o.f, e.quick) || part_cylinder(o.f, e.quick) || part_drape(&e, o.f)) {
    fprintf(stderr, "bending: %s\n", cb_error_message());
    return 2;
  }
  if (cb_outfile_commit(&o)) {
    fprintf(stderr, "bending: %s\n", cb_error_message());
    return 2;
  }
  return 0;
}
