/* definiteness (claims H1, H2): how often Newton's matrix A = M/dt^2 + H is
 * indefinite on scenes that compress springs, and what each fix of
 * integrator.definiteness (drop, mirror, shift, choi-ko) costs.
 * Physics and witnesses live in lib/ (definiteness.c, spd_probe.c,
 * newton_trace.c); this program sweeps scenes x policies and writes CSV. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/clothbench.h>
#include "bind.h"
#include "experiment.h"
#include "provenance.h"
#include "newton_trace.h"

enum { NPOL = 5, NSCENE = 4 };
static const char *const policies[NPOL] = {"none", "drop", "mirror", "shift", "choi-ko"};
typedef struct { const char *name; int steps, quick_steps; const char *sets[8]; } scene_def;
static char pins_lr[CB_PINS_LEN]; /* left and right edges of the 21x21 grid */
static const scene_def scenes[NSCENE] = {
  {"hanging", 20, 3, {NULL}},                          /* the lab cloth falling from two corners */
  {"scaled", 20, 3, {"scene.initial_scale=0.7", NULL}}, /* starts at 0.7x its rest shape (pins too) */
  {"driven", 30, 3, {pins_lr, "scene.pin_squeeze=2 0 0", NULL}}, /* two edges pushed together: buckling */
  {"pair", 30, 10, {"mesh.type=chain", "mesh.n=3", "mesh.size=2", "mesh.plane=xy", "scene.pins=0 2",
                    "scene.initial_scale=0.7", NULL}}, /* two springs compressed to 0.7 L between pins */
};

#define IT_HEAD "scene,policy,step,newton_iter,system,spd,min_eig,min_eig_res,mu,spd_exact,min_eig_exact," \
  "compressed_frac,cg_breakdown,cg_status,cg_iters,rel_grad,grad_norm,f_j,energy_j,wall_ms,status"
#define RUN_HEAD "scene,policy,steps,steps_done,steps_converged,newton_iters,systems,not_spd,indefinite_exact," \
  "cg_breakdowns,mu_max,factorizations,wall_ms,probe_ms,final_f_j,final_energy_j,final_rel_grad," \
  "shape_diff_none_m,shape_diff_drop_m,status"

static void put_row(FILE *f, const char *sc, const char *pol, int step, const cb_newton_trace_row *r, int exact_run) {
  fprintf(f, "%s,%s,%d,%d,%d,", sc, pol, step, r->iter, r->system);
  if (r->system) {
    const cb_spd_probe_result *u = &r->used, *x = exact_run ? &r->used : &r->exact;
    int spd_x = exact_run ? r->status != CB_NOT_SPD : x->cholmod_status == CB_OK;
    fprintf(f, "%d,%.17g,%.17g,%.17g,%d,%.17g,", r->status != CB_NOT_SPD, u->min_eig, u->min_eig_res, r->mu, spd_x,
            x->min_eig);
  } else {
    fputs(",,,,,,", f);
  }
  fprintf(f, "%.17g,", r->compressed_frac);
  if (r->system) fprintf(f, "%d,%s,%d,", r->used.cg_status == CB_INDEFINITE, cb_status_name(r->used.cg_status), r->used.cg_iters);
  else fputs(",,,", f);
  fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.6f,%s\n", r->rel_grad, r->grad_norm, r->F, r->energy, r->wall_ms,
          cb_status_name(r->status));
}

/* max_i |x_i - y_i| over vertices (Euclidean), or "" when y is missing */
static void put_diff(FILE *f, const double *x, const double *y, int nv) {
  if (!x || !y) { fputs(",", f); return; }
  double m = 0;
  for (int i = 0; i < nv; i++)
    m = fmax(m, hypot(hypot(x[3 * i] - y[3 * i], x[3 * i + 1] - y[3 * i + 1]), x[3 * i + 2] - y[3 * i + 2]));
  fprintf(f, "%.17g,", m);
}

typedef struct {
  int steps_done, converged, iters, systems, not_spd, indef_x, cg_bd, fact, status;
  double mu, wall, probe, F, energy, rel_grad, *x;
} tally;

static int run_policy(cb_experiment *e, const scene_def *sd, int p, FILE *it, FILE *stp, tally *t, int *nv) {
  char pol[64];
  snprintf(pol, sizeof pol, "integrator.definiteness=%s", policies[p]);
  const char *sets[12], *refsets[12];
  int n = 0, steps = e->quick ? sd->quick_steps : sd->steps;
  for (; sd->sets[n]; n++) sets[n] = refsets[n] = sd->sets[n];
  sets[n] = refsets[n] = "integrator.tol_dx=1e-9"; /* |grad F(x0)| can be tiny at rest: stop at round-off */
  sets[n + 1] = pol; refsets[n + 1] = "integrator.definiteness=none"; sets[n + 2] = refsets[n + 2] = NULL;
  cb_config cfg, rcfg;
  cb_scene *s = NULL, *ref = NULL; /* ref: linear springs, for the exact (none) matrix at our iterates */
  cb_integrator *integ = NULL;
  cb_newton_trace tr = {0};
  cb_run run = {0};
  cb_integrator_params ip;
  int st = cb_experiment_config(e, "hanging.ini", sets, &cfg);
  if (st == CB_OK) st = cb_scene_from_config(&cfg, &s);
  if (st == CB_OK && p > 0) st = cb_experiment_config(e, "hanging.ini", refsets, &rcfg);
  if (st == CB_OK && p > 0) st = cb_scene_from_config(&rcfg, &ref);
  cb_newton_params np;
  if (st == CB_OK) st = cb_integrator_params_from_config(&cfg, &ip);
  if (st == CB_OK) st = cb_newton_params_from_config(&cfg, &np);
  if (st == CB_OK) st = cb_newton_trace_init(&tr, s, ref ? &ref->sys : NULL, ip.dt, np.max_iters + 1,
                                      CB_PROBE_EIG | CB_PROBE_CG, CB_PROBE_CHOLMOD | CB_PROBE_EIG, NULL);
  ip.hook = cb_newton_trace_hook;
  ip.hook_ctx = &tr;
  if (st == CB_OK) st = cb_integrator_from_config(&cfg, s, &ip, &integ);
  if (st == CB_OK) st = cb_run_init(&run, s, integ);
  for (int k = 0; st == CB_OK && k < steps; k++) {
    cb_newton_trace_begin_step(&tr);
    t->status = cb_run_step(&run);
    cb_newton_trace_end_step(&tr, t->status);
    if ((st = tr.error)) break;
    const cb_step_stats *ss = &run.last;
    cb_newton_trace_row none_seen = {.energy = NAN, .compressed_frac = NAN}; /* F was NaN before any hook */
    const cb_newton_trace_row *fin = tr.nrows ? &tr.rows[tr.nrows - 1] : &none_seen;
    double wall = ss->wall_ms - tr.probe_ms; /* the integrator's time, probes excluded */
    for (int r = 0; r < tr.nrows; r++) {
      const cb_newton_trace_row *w = &tr.rows[r];
      put_row(it, sd->name, policies[p], run.step, w, p == 0);
      t->systems += w->system;
      t->not_spd += w->system && w->status == CB_NOT_SPD;
      t->indef_x += w->system && (p == 0 ? w->status == CB_NOT_SPD || w->used.min_eig < 0
                                         : w->exact.cholmod_status == CB_NOT_SPD || w->exact.min_eig < 0);
      t->cg_bd += w->system && w->used.cg_status == CB_INDEFINITE;
    }
    fprintf(stp, "%s,%s,%d,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.6f,%s\n", sd->name, policies[p], run.step,
            run.t, ss->newton_iters, ss->factorizations, ss->F, fin->energy, run.kinetic, ss->rel_grad,
            fin->compressed_frac, ss->shift_mu, wall, cb_status_name(t->status));
    t->steps_done++;
    t->converged += t->status == CB_OK;
    t->iters += ss->newton_iters;
    t->fact += ss->factorizations;
    t->mu = fmax(t->mu, ss->shift_mu);
    t->wall += wall;
    t->probe += tr.probe_ms;
    t->F = ss->F; t->energy = fin->energy; t->rel_grad = ss->rel_grad;
    cb_progress_update(&e->progress, e->progress.done + 1);
    if (cb_status_is_fatal(t->status)) break;
  }
  if (st == CB_OK) {
    *nv = s->mesh.nv;
    char obj[1024], suffix[128];
    snprintf(suffix, sizeof suffix, "%s_%s.obj", sd->name, policies[p]);
    cb_experiment_side_path(e, suffix, obj, sizeof obj);
    st = cb_mesh_write_obj(&s->mesh, run.x, obj); /* the final (or failing) state */
    if (t->steps_done == steps && !cb_status_is_fatal(t->status) && (t->x = malloc((size_t)3 * *nv * sizeof(double))))
      memcpy(t->x, run.x, (size_t)3 * *nv * sizeof(double)); /* a finished run is a reference */
  }
  cb_run_free(&run);
  cb_integrator_free(integ);
  cb_newton_trace_free(&tr);
  cb_scene_free(s);
  cb_scene_free(ref);
  return st;
}

/* The spring pair held still: two springs (L = 1) compressed to l = ratio L
 * between pinned ends, the middle vertex free; H and A restricted to 1, 2 or
 * 3 dimensions. Prediction: A's eigenvalues are m/dt^2 + 2 (along) and
 * m/dt^2 + 2 (transverse, twice), the spring's eigenvalues doubled. */
static int pair_sweep(cb_experiment *e, FILE *f) {
  static const double ratios[] = {1.05, 1.0, 0.99, 0.97, 0.95, 0.94, 0.9, 0.8, 0.7, 0.5, 0.3, 0.1};
  static const char *const pols[] = {"none", "drop", "mirror", "choi-ko", "choi-ko", "choi-ko", "choi-ko"};
  static const char *const kbs[] = {"0.01", "0.01", "0.01", "0.01", "0.1", "1", "10"};
  int st = CB_OK;
  for (int p = 0; p < 7 && st == CB_OK; p++) {
    char pol[64], kb[64];
    snprintf(pol, sizeof pol, "integrator.definiteness=%s", pols[p]);
    snprintf(kb, sizeof kb, "material.buckling_kb=%s", kbs[p]);
    const char *sets[] = {"mesh.type=chain", "mesh.n=3", "mesh.size=2", "mesh.plane=xy", "scene.pins=0 2", pol, kb, NULL};
    cb_config cfg;
    cb_scene *s = NULL;
    cb_definiteness def = CB_DEF_NONE;
    st = cb_experiment_config(e, "hanging.ini", sets, &cfg);
    if (st == CB_OK) st = cb_scene_from_config(&cfg, &s);
    if (st == CB_OK) st = cb_definiteness_from_name(pols[p], &def);
    for (size_t r = 0; st == CB_OK && r < sizeof ratios / sizeof ratios[0]; r++) {
      double q = ratios[r], x[9] = {-q, 0, 0, 0, 0, 0, q, 0, 0}, m = s->mass[1], s2 = 1.0 / (cfg.dt * cfg.dt);
      double k = cfg.stretch_k, along = k, tr = k * (1 - 1 / q), Eb, dEb, d2Eb; /* one spring: k, k(1 - L/l) */
      cb_choi_ko ck;
      if (def == CB_DEF_CHOI_KO && (st = cb_choi_ko_init(&ck, k, 1.0, cfg.buckling_kb)) == CB_OK) {
        cb_choi_ko_eval(&ck, q, &Eb, &dEb, &d2Eb);
        along = d2Eb; /* E''(l) */
        tr = dEb / q; /* E'(l)/l */
      }
      tr = cb_definiteness_transverse(def, tr);
      for (int dim = 1; dim <= 3 && st == CB_OK; dim++) {
        int keep[3] = {1, dim >= 2, dim >= 3}, ok_h, ok_a;
        double lh, la;
        cb_system_assemble(&s->sys, x, 0.0, def, 0.0); /* H */
        st = cb_dense_restricted_spd(&s->sys.A, keep, &lh, &ok_h);
        cb_system_assemble(&s->sys, x, s2, def, 0.0); /* A = M/dt^2 + H */
        if (st == CB_OK) st = cb_dense_restricted_spd(&s->sys.A, keep, &la, &ok_a);
        double pred = m * s2 + 2 * (dim == 1 ? along : fmin(along, tr));
        if (st == CB_OK)
          fprintf(f, "%d,%s,%s,%.17g,%.17g,%.17g,%.17g,%d\n", dim, pols[p], def == CB_DEF_CHOI_KO ? kbs[p] : "", q, lh, la,
                  pred, ok_a);
      }
    }
    cb_scene_free(s);
  }
  return st;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int st = cb_experiment_begin(&e, "definiteness",
                               "Claims H1, H2: how often A = M/dt^2 + H is indefinite on scenes that compress springs "
                               "(hanging, scaled, driven, pair; and a static spring pair in 1D/2D/3D), and what the "
                               "fixes drop, mirror, shift and choi-ko cost (Newton iterations, time, shape).",
                               argc, argv);
  if (st) return st > 0 ? 0 : 1;
  size_t u = 0;
  for (int side = 0; side < 2; side++) /* vertex (i, j) is j*21 + i: columns i = 0 and i = 20 */
    for (int j = 0; j < 21; j++) u += (size_t)snprintf(pins_lr + u, sizeof pins_lr - u, "%s%d", u ? " " : "scene.pins=", j * 21 + 20 * side);
  cb_outfile it, stp, runs, pair;
  char path[3][1024];
  cb_experiment_side_path(&e, "steps.csv", path[0], sizeof path[0]);
  cb_experiment_side_path(&e, "runs.csv", path[1], sizeof path[1]);
  cb_experiment_side_path(&e, "pair.csv", path[2], sizeof path[2]);
  const char *extra = "# one row per Newton iterate x^(k); system = 1 if A(x^(k)) was assembled and solved there\n";
  st = cb_experiment_csv(&e, &it, NULL, extra, IT_HEAD);
  if (st == CB_OK) st = cb_experiment_csv(&e, &stp, path[0], NULL, "scene,policy,step,t_s,newton_iters,factorizations,"
                                          "f_j,energy_j,kinetic_j,rel_grad,compressed_frac,mu_max,wall_ms,status");
  if (st == CB_OK) st = cb_experiment_csv(&e, &runs, path[1], NULL, RUN_HEAD);
  if (st == CB_OK) st = cb_experiment_csv(&e, &pair, path[2], NULL, "dim,policy,buckling_kb,ratio,min_eig_h,min_eig_a,"
                                          "predicted_min_eig_a,spd");
  if (st) { fprintf(stderr, "definiteness: %s\n", cb_error_message()); return 2; }
  long total = 0;
  for (int si = 0; si < NSCENE; si++) total += (long)NPOL * (e.quick ? scenes[si].quick_steps : scenes[si].steps);
  cb_progress_start(&e.progress, "definiteness", total);
  for (int si = 0; si < NSCENE && st == CB_OK; si++) {
    tally t[NPOL];
    memset(t, 0, sizeof t);
    int nv = 0;
    for (int p = 0; p < NPOL && st == CB_OK; p++) st = run_policy(&e, &scenes[si], p, it.f, stp.f, &t[p], &nv);
    for (int p = 0; p < NPOL && st == CB_OK; p++) {
      const tally *a = &t[p];
      fprintf(runs.f, "%s,%s,%d,%d,%d,%d,%d,%d,%d,%d,%.17g,%d,%.6f,%.6f,%.17g,%.17g,%.17g,", scenes[si].name, policies[p],
              e.quick ? scenes[si].quick_steps : scenes[si].steps, a->steps_done, a->converged, a->iters, a->systems,
              a->not_spd, a->indef_x, a->cg_bd, a->mu, a->fact, a->wall, a->probe, a->F, a->energy, a->rel_grad);
      put_diff(runs.f, a->x, t[0].x, nv);
      put_diff(runs.f, a->x, t[1].x, nv);
      fprintf(runs.f, "%s\n", cb_status_name(a->status));
    }
    for (int p = 0; p < NPOL; p++) free(t[p].x);
  }
  if (st == CB_OK) st = pair_sweep(&e, pair.f);
  cb_progress_end(&e.progress);
  if (st) {
    fprintf(stderr, "definiteness: %s\n", cb_error_message());
    cb_outfile_abort(&it); cb_outfile_abort(&stp); cb_outfile_abort(&runs); cb_outfile_abort(&pair);
    return 1;
  }
  if (cb_outfile_commit(&it) || cb_outfile_commit(&stp) || cb_outfile_commit(&runs) || cb_outfile_commit(&pair)) {
    fprintf(stderr, "definiteness: %s\n", cb_error_message());
    return 2;
  }
  return 0;
}
