/* newton_vs_bw measurements, part 2: trajectories against the reference
 * trajectory, the time-discretisation error, and the K = 1 regime map. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "newton_study.h"
#include "csv.h"
#include <clothbench/run.h>
#include <clothbench/status.h>

const char *const cb_study_traj_header = "scene,n,dt_s,k_n_per_m,stretch,method,max_newton_iters,inner_solver,line_"
                                         "search,step,t_s,pos_error_m,energy_j,"
                                         "ref_energy_j,energy_drift_j,newton_iters,linear_iters,wall_ms,status";

/* ss NULL: the start state, where no step ran (its iterations and time are empty) */
static void traj_row(FILE *f, const cb_scene *s, const char *label, double dt, const char *method, int K,
                     const char *inner, int ls, int step, double err, double E, double Eref, double E0,
                     const cb_step_stats *ss, int status) {
  double na = cb_csv_na();
  cb_csv_printf(f, "%s,%d,%.17g,%.17g,%.17g,%s,%d,%s,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.6f,%s\n", label,
                s->def.grid.n, dt, s->def.stretch_k, s->def.initial_scale, method, K, inner, ls, step, step * dt, err,
                E, Eref, E - E0, ss ? ss->newton_iters : na, ss ? ss->linear_iters : na, ss ? ss->wall_ms : na,
                cb_status_name(status));
}

int cb_study_trajectories(cb_scene *s, const char *label, double dt, int nsteps, const cb_method *methods, int nmethods,
                          FILE *csv) {
  size_t n3 = (size_t)3 * s->mesh.nv;
  double rms = 1.0 / sqrt(cb_free_mass(s)); /* |.|_M / sqrt(M) is an RMS distance in m */
  cb_reference_params rp = cb_reference_params_default();
  rp.dt = dt;
  cb_reference *ref = NULL;
  double *xr = cb_malloc((size_t)(nsteps + 1) * n3, sizeof(double)); /* reference positions per step */
  double *Er = cb_malloc((size_t)nsteps + 1, sizeof(double));
  double *v = cb_malloc(n3, sizeof(double));
  int st = xr && Er && v ? cb_reference_alloc(s, &rp, &ref) : CB_ENOMEM;
  if (st) goto done;
  memcpy(xr, s->x0, n3 * sizeof(double));
  memcpy(v, s->v0, n3 * sizeof(double));
  Er[0] = cb_state_energy(s, xr, v);
  traj_row(csv, s, label, dt, "reference", rp.max_iters, "cholmod", 1, 0, 0.0, Er[0], Er[0], Er[0], NULL, CB_OK);
  for (int k = 1; k <= nsteps; k++) { /* the converged trajectory */
    double *x = xr + (size_t)k * n3;
    memcpy(x, x - n3, n3 * sizeof(double));
    cb_reference_stats rs;
    int rst = cb_reference_advance(ref, x, v, &rs);
    Er[k] = cb_state_energy(s, x, v);
    cb_step_stats ss = {.newton_iters = rs.iters, .wall_ms = rs.wall_ms};
    traj_row(csv, s, label, dt, "reference", rp.max_iters, "cholmod", 1, k, 0.0, Er[k], Er[k], Er[0], &ss, rst);
  }
  for (int m = 0; m < nmethods && st == CB_OK; m++) {
    const cb_method *me = &methods[m];
    cb_integrator *it = NULL;
    cb_run run;
    st = cb_method_integrator(me, s, dt, NULL, NULL, &it);
    if (st == CB_OK) st = cb_run_init(&run, s, it);
    if (st) {
      cb_integrator_free(it);
      break;
    }
    int K = me->K > 0 ? me->K : CB_METHOD_CONVERGED_ITERS;
    traj_row(csv, s, label, dt, me->name, K, me->inner, me->line_search, 0, 0.0, Er[0], Er[0], Er[0], NULL, CB_OK);
    for (int k = 1; k <= nsteps; k++) {
      int rst = cb_run_step(&run);
      double err = cb_mnorm_diff(s, run.x, xr + (size_t)k * n3) * rms;
      traj_row(csv, s, label, dt, me->name, K, me->inner, me->line_search, k, err, run.kinetic + run.potential, Er[k],
               Er[0], &run.last, rst);
      if (cb_status_is_fatal(rst)) break; /* the first diverging (or failing) step ends the run */
    }
    cb_run_free(&run);
    cb_integrator_free(it);
  }
done:
  cb_reference_free(ref);
  free(xr);
  free(Er);
  free(v);
  return st;
}

/* ---- time-discretisation error -------------------------------------------- */

const char *const cb_study_dt_header = "scene,n,dt_s,k_n_per_m,stretch,fine_dt_s,step,t_s,pos_error_m,energy_j,fine_"
                                       "energy_j,ref_status,fine_status";

int cb_study_dt_error(cb_scene *s, const char *label, double dt, int refine, int nsteps, FILE *csv) {
  size_t n3 = (size_t)3 * s->mesh.nv;
  double rms = 1.0 / sqrt(cb_free_mass(s));
  cb_reference_params rp = cb_reference_params_default(), fp;
  rp.dt = dt;
  fp = rp;
  fp.dt = dt / refine;
  cb_reference *rc = NULL, *rf = NULL;
  double *xc = cb_malloc(n3, sizeof(double)), *vc = cb_malloc(n3, sizeof(double));
  double *xf = cb_malloc(n3, sizeof(double)), *vf = cb_malloc(n3, sizeof(double));
  int st = xc && vc && xf && vf ? cb_reference_alloc(s, &rp, &rc) : CB_ENOMEM;
  if (st == CB_OK) st = cb_reference_alloc(s, &fp, &rf);
  if (st == CB_OK) {
    memcpy(xc, s->x0, n3 * sizeof(double));
    memcpy(xf, s->x0, n3 * sizeof(double));
    memcpy(vc, s->v0, n3 * sizeof(double));
    memcpy(vf, s->v0, n3 * sizeof(double));
  }
  for (int k = 1; st == CB_OK && k <= nsteps; k++) {
    cb_reference_stats rs;
    int cst = cb_reference_advance(rc, xc, vc, &rs), fst = CB_OK;
    for (int j = 0; j < refine; j++) {
      int t = cb_reference_advance(rf, xf, vf, &rs);
      if (t != CB_OK) fst = t;
    }
    cb_csv_printf(csv, "%s,%d,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%s,%s\n", label, s->def.grid.n, dt,
                  s->def.stretch_k, s->def.initial_scale, fp.dt, k, k * dt, cb_mnorm_diff(s, xc, xf) * rms,
                  cb_state_energy(s, xc, vc), cb_state_energy(s, xf, vf), cb_status_name(cst), cb_status_name(fst));
  }
  cb_reference_free(rc);
  cb_reference_free(rf);
  free(xc);
  free(vc);
  free(xf);
  free(vf);
  return st;
}

/* ---- the K = 1 regime map -------------------------------------------------- */

const char *const cb_study_regime_header = "scene,n,dt_s,k_n_per_m,stretch,dt_index,k_index,stretch_index,steps,"
                                           "duration_s,first_diverged_step,traj_status,"
                                           "step_error_0,step_error_max,worst_step,worst_f_minus_fstar_j,samples,ref_"
                                           "status,ref_iters_max,k1_fails,wall_ms";

int cb_study_regime_cell(cb_scene *s, const char *label, double dt, double duration_s, int nsamples, double fail_level,
                         int dt_index, int k_index, int stretch_index, FILE *csv) {
  size_t n3 = (size_t)3 * s->mesh.nv;
  int nsteps = (int)lround(duration_s / dt);
  if (nsteps < 1) nsteps = 1;
  if (nsamples < 1) nsamples = 1;
  cb_reference_params rp = cb_reference_params_default();
  rp.dt = dt;
  cb_reference *ref = NULL;
  cb_integrator *it = NULL;
  cb_method bw;
  cb_run run;
  int have_run = 0;
  double *x0 = cb_malloc(n3, sizeof(double)), *v0 = cb_malloc(n3, sizeof(double)), *xs = cb_malloc(n3, sizeof(double));
  int st = x0 && v0 && xs ? cb_method_make(1, 0, "cholmod", &bw) : CB_ENOMEM;
  if (st == CB_OK) st = cb_reference_alloc(s, &rp, &ref);
  if (st == CB_OK) st = cb_method_integrator(&bw, s, dt, NULL, NULL, &it);
  if (st == CB_OK) st = cb_run_init(&run, s, it);
  have_run = st == CB_OK;
  int first_div = -1, traj_status = CB_OK, worst = -1, samples = 0, ref_bad = CB_OK, ref_iters = 0;
  double err0 = NAN, errmax = NAN, dfmax = NAN, wall = 0, Fs = 0;
  for (int k = 0, j = 0; st == CB_OK && k < nsteps; k++) {
    /* sampled steps k_j = j N / nsamples: x* from the current state */
    int sample = j < nsamples && k == (int)((long)j * nsteps / nsamples);
    if (sample) {
      while (j < nsamples && k == (int)((long)j * nsteps / nsamples)) j++;
      cb_reference_stats rs;
      int rst = cb_reference_step(ref, run.x, run.v, xs, &rs);
      if (rst != CB_OK) ref_bad = rst;
      if (rs.iters > ref_iters) ref_iters = rs.iters;
      memcpy(x0, run.x, n3 * sizeof(double));
      memcpy(v0, run.v, n3 * sizeof(double));
      Fs = cb_reference_objective(ref, x0, v0, xs, NULL);
    }
    int sst = cb_run_step(&run);
    wall += run.last.wall_ms;
    if (sample) {
      double e = cb_step_error(s, run.x, xs, x0);
      if (!isfinite(e)) e = INFINITY;
      if (k == 0) err0 = e;
      if (samples == 0 || e > errmax) {
        errmax = e;
        worst = k;
        dfmax = cb_reference_objective(ref, x0, v0, run.x, NULL) - Fs; /* < 0: K = 1 found a lower minimum */
      }
      samples++;
    }
    if (cb_status_is_fatal(sst)) {
      traj_status = sst;
      first_div = k + 1;
      break;
    }
  }
  if (st == CB_OK) {
    /* not applicable, written empty: the first diverged step of a trajectory that did not diverge (-1), and
     * the errors and worst step when no state was sampled */
    int fails = first_div >= 0 || !(errmax <= fail_level);
    double na = cb_csv_na();
    cb_csv_printf(csv, "%s,%d,%.17g,%.17g,%.17g,%d,%d,%d,%d,%.17g,%.17g,%s,%.17g,%.17g,%.17g,%.17g,%d,%s,%d,%d,%.6f\n",
                  label, s->def.grid.n, dt, s->def.stretch_k, s->def.initial_scale, dt_index, k_index, stretch_index,
                  nsteps, nsteps * dt, first_div >= 0 ? first_div : na, cb_status_name(traj_status),
                  samples ? err0 : na, samples ? errmax : na, samples ? worst : na, samples ? dfmax : na, samples,
                  cb_status_name(ref_bad), ref_iters, fails, wall);
  }
  if (have_run) cb_run_free(&run);
  cb_integrator_free(it);
  cb_reference_free(ref);
  free(x0);
  free(v0);
  free(xs);
  return st;
}
