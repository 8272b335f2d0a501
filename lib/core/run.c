#include <clothbench/run.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

static void energies(cb_run *r) {
  double per[CB_MAX_TERMS];
  r->potential = cb_system_energy(&r->scene->sys, r->x, NULL, per);
  r->elastic = 0;
  for (int k = 0; k < r->scene->sys.nterms; k++)
    if (r->scene->sys.terms[k]->type->hessian) r->elastic += per[k];
  r->kinetic = cb_scene_kinetic(r->scene, r->v);
}

int cb_run_init(cb_run *r, cb_scene *s, cb_integrator *it) {
  memset(r, 0, sizeof *r);
  size_t n3 = (size_t)3 * s->mesh.nv;
  r->scene = s;
  r->integ = it;
  r->x = cb_malloc(n3, sizeof(double));
  r->v = cb_malloc(n3, sizeof(double));
  if (!r->x || !r->v) { cb_run_free(r); return CB_ENOMEM; }
  memcpy(r->x, s->x0, n3 * sizeof(double));
  memcpy(r->v, s->v0, n3 * sizeof(double));
  energies(r);
  r->total0 = r->kinetic + r->potential;
  r->bound = s->diverge_ratio * (s->energy_scale + r->kinetic);
  return CB_OK;
}

void cb_run_free(cb_run *r) {
  free(r->x);
  free(r->v);
  r->x = r->v = NULL;
}

int cb_run_step(cb_run *r) {
  int st = cb_integrator_step(r->integ, r->x, r->v, &r->last);
  r->step++;
  r->t = r->step * r->integ->params.dt;
  energies(r);
  double total = r->kinetic + r->potential;
  if (!isfinite(total)) st = CB_DIVERGED;
  for (int i = 0; st != CB_DIVERGED && i < 3 * r->scene->mesh.nv; i++)
    if (!isfinite(r->x[i]) || !isfinite(r->v[i])) st = CB_DIVERGED;
  if (st != CB_DIVERGED && total - r->total0 > r->bound) st = CB_DIVERGED;
  r->last.status = st;
  return st;
}

void cb_run_csv_header(FILE *f) {
  fputs("step,t_s,kinetic_j,potential_j,elastic_j,total_j,newton_iters,rel_grad,linear_iters,"
        "assemble_ms,factor_ms,solve_ms,wall_ms,status,contacts\n", f);
}

void cb_run_csv_row(FILE *f, const cb_run *r, int status) {
  const cb_step_stats *s = &r->last;
  fprintf(f, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%d,%.6f,%.6f,%.6f,%.6f,%s,%d\n", r->step, r->t, r->kinetic,
          r->potential, r->elastic, r->kinetic + r->potential, s->newton_iters, s->rel_grad, s->linear_iters,
          s->assemble_ms, s->factor_ms, s->solve_ms, s->wall_ms, cb_status_name(status), cb_scene_contacts(r->scene, r->x));
}
