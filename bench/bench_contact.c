/* bench_contact: the cost of a step with contact, split into its phases, on
 * the rotating sphere (configs/rotating_sphere.ini; issue 34, "Performance";
 * make bench; docs/performance.md, "Contact").
 *
 * Per size (mesh.n = 32 and 64: 1024 and 4096 vertices), one scene with the
 * config's contact (ipc, Newton + CHOLMOD with its CCD-filtered line search)
 * and the same scene with contact.method = none. The ipc scene takes `warm`
 * steps from the config's start (the sheet falls 0.1 m and lands on the
 * sphere by about step 5), and that state (x, v and the sphere's time) is the
 * start of every timed repeat: `steps` steps with ipc, and the same steps
 * with none (same state, same dt; without contact the sheet falls freely
 * through the sphere, which is the cost of the step without contact, not a
 * physical run). The two run in interleaved rounds (ipc none, none ipc, ...:
 * docs/running.md, "Timings"); a repeat is the mean step time of its `steps`
 * steps, and a repeat shorter than CB_TIMING_WARM_MS is run twice and timed
 * the second time (cb_timing_warm). The ratio ipc / none is per round (paired
 * repeats): its median, min and max.
 *
 * The phase split of a step (cb_step_stats: the contact term's timers,
 * cb_contact_stats, taken as differences over the step by the integrator
 * wrapper):
 *   broad_ms    broad phase (refit, traversal, candidates) of every evaluation and step bound
 *   ccd_ms      the step bound's narrow phase (distance filter, additive CCD)
 *   barrier_ms  the contact pairs' value, gradient and Hessian (projection and scatter included)
 *   solve_ms    the linear solve: CHOLMOD's numeric factorisation and solve (factor_ms + solve_ms)
 *   rest_ms     wall_ms less the four: the elastic terms' assembly, the line search's other work, ...
 * The contact count of a step is the number of pairs within d-hat at its
 * last energy evaluation (cb_contact_stats.active: its end state).
 *
 * Output: results/bench_contact.csv, one row per (size, method) with the
 * medians over the repeats; results/bench_contact_steps.csv, every step
 * (the warm-up's, then the first round's), with its split and contact count,
 * for the figure of the split against the contacts (plots/bench_contact.gp).
 * --quick: 6 warm-up steps and 1 timed step a repeat (3 rounds); the full
 * run 8 and 3. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/contact.h>
#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "bind.h"
#include "csv.h"
#include "experiment.h"
#include "provenance.h"
#include "stats.h"

#define TARGET_RATIO 10.0 /* issue 34: ipc at 64^2 at most 10x the step without contact */

enum { IPC, NONE, NSIDE };
static const char *side_name[NSIDE] = {"ipc", "none"};

typedef struct side {
  cb_scene *s;
  cb_integrator *it;
  /* per repeat: the mean per step of the repeat's steps */
  cb_timing wall, broad, ccd, barrier, solve, assemble, rest;
  double iters, contacts, candidates; /* sums over every timed step */
  long nsteps;                        /* timed steps */
  int status;                         /* worst status of the timed steps (fatal first) */
} side;

enum { T_MAIN, T_STEPS };

static int load(cb_experiment *ex, int n, int none, cb_scene **s, cb_integrator **it) {
  char setn[32];
  snprintf(setn, sizeof setn, "mesh.n=%d", n);
  const char *sets[] = {setn, none ? "contact.method=none" : NULL, NULL};
  cb_config c;
  int st = cb_experiment_config(ex, "rotating_sphere.ini", sets, &c);
  if (!st) st = cb_config_validate(&c);
  if (!st) st = cb_scene_from_config(&c, s);
  if (!st) st = cb_integrator_from_config(&c, *s, NULL, it);
  return st;
}

/* The pairs within d-hat at the last energy evaluation (the step's end state), and the broad phase's candidates
 * there. */
static long active_pairs(const cb_scene *s, long *candidates) {
  const cb_term *t = cb_scene_contact_term(s);
  const cb_contact_stats *cs = t ? cb_contact_term_stats(t) : NULL;
  *candidates = cs ? cs->candidates : 0;
  return cs ? cs->active : 0;
}

static double solve_ms(const cb_step_stats *st) { return st->factor_ms + st->solve_ms; }
static double rest_ms(const cb_step_stats *st) {
  return st->wall_ms - st->contact_broad_ms - st->contact_ccd_ms - st->contact_barrier_ms - solve_ms(st);
}

static void step_row(FILE *f, int n, int nv, const char *method, const char *kind, int rep, int step, double t,
                     const cb_scene *s, const cb_step_stats *st, int status) {
  long cand, a = active_pairs(s, &cand);
  cb_csv_printf(f, "%d,%d,%s,%s,%d,%d,%.17g,%ld,%ld,%d,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%s\n", n, nv, method, kind,
                rep, step, t, a, cand, st->newton_iters, st->wall_ms, st->contact_broad_ms, st->contact_ccd_ms,
                st->contact_barrier_ms, solve_ms(st), st->assemble_ms, rest_ms(st), cb_status_name(status));
}

/* worse of two step statuses: a fatal one first, else a nonzero one */
static int worse(int a, int b) {
  if (cb_status_is_fatal(a)) return a;
  if (cb_status_is_fatal(b)) return b;
  return a ? a : b;
}

/* One repeat of side k: `steps` steps from (xs, vs) at obstacle time ts; appends the per-step means to k's timings.
 * rows: write each step to the steps table. Returns the repeat's total wall time, ms. */
static double repeat(side *k, const char *method, int n, int rep, const double *xs, const double *vs, double ts,
                     double *x, double *v, int steps, int warm_steps, double dt, FILE *rows) {
  int nv3 = 3 * k->s->mesh.nv;
  double sum[7] = {0}, total = 0;
  for (int again = 0; again < 2; again++) { /* a short repeat is the warm-up of its own second run */
    memset(sum, 0, sizeof sum);
    memcpy(x, xs, (size_t)nv3 * sizeof *x);
    memcpy(v, vs, (size_t)nv3 * sizeof *v);
    cb_scene_obstacle_set_time(k->s, ts);
    double it = 0, ct = 0, cd = 0;
    int status = CB_OK;
    for (int j = 0; j < steps; j++) {
      cb_step_stats st;
      int r = cb_integrator_step(k->it, x, v, &st);
      status = worse(status, r);
      sum[0] += st.wall_ms, sum[1] += st.contact_broad_ms, sum[2] += st.contact_ccd_ms;
      sum[3] += st.contact_barrier_ms, sum[4] += solve_ms(&st), sum[5] += st.assemble_ms, sum[6] += rest_ms(&st);
      long cand, a = active_pairs(k->s, &cand);
      it += st.newton_iters, ct += (double)a, cd += (double)cand;
      if (rows && !again)
        step_row(rows, n, k->s->mesh.nv, method, "timed", rep, warm_steps + j + 1, ts + (j + 1) * dt, k->s, &st, r);
      if (cb_status_is_fatal(r)) break;
    }
    total = sum[0];
    if (again == 1 || !cb_timing_warm(total)) {
      cb_timing_add(&k->wall, sum[0] / steps);
      cb_timing_add(&k->broad, sum[1] / steps);
      cb_timing_add(&k->ccd, sum[2] / steps);
      cb_timing_add(&k->barrier, sum[3] / steps);
      cb_timing_add(&k->solve, sum[4] / steps);
      cb_timing_add(&k->assemble, sum[5] / steps);
      cb_timing_add(&k->rest, sum[6] / steps);
      k->iters += it, k->contacts += ct, k->candidates += cd;
      k->nsteps += steps;
      k->status = worse(k->status, status);
      break;
    }
  }
  return total;
}

int main(int argc, char **argv) {
  cb_experiment ex;
  int r = cb_experiment_begin(&ex, "bench_contact",
                              "The cost of a step with IPC contact against the same step without contact on the "
                              "rotating sphere (32^2, 64^2), split into broad phase, CCD, barrier, linear solve and "
                              "the rest, with the contact count.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  cb_experiment_timed(&ex);
  cb_runtime_init();
  int warm = ex.quick ? 6 : 8, steps = ex.quick ? 1 : 3;
  char extra[1024];
  snprintf(extra, sizeof extra,
           "# scene: configs/rotating_sphere.ini at mesh.n = 32 and 64 (ipc, newton + cholmod, CCD-filtered line "
           "search); none: the same with contact.method = none, from the same state\n"
           "# warm-up: %d ipc steps from the config's start (the sheet lands on the sphere); each repeat: %d steps "
           "from that state (cloth and sphere), per side, in interleaved rounds; *_ms: medians over the repeats of "
           "the mean per step (min, max: the repeats' extremes)\n"
           "# broad: broad phase; ccd: the step bound's narrow phase; barrier: the contact pairs' value, gradient, "
           "Hessian; solve: factor + solve; rest: wall - the four (elastic assembly, line search, ...); assemble: "
           "Newton's assembly time (includes broad and barrier of its calls)\n"
           "# ratio: ipc / none wall per round (paired), median (min_ratio, max_ratio); target_ratio: issue 34's 10x "
           "at 64^2\n",
           warm, steps);
  if (cb_experiment_table(&ex, NULL, extra,
                          "n,vertices,method,warmup_steps,steps_timed,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,"
                          "wall_repeats,broad_ms,ccd_ms,barrier_ms,solve_ms,rest_ms,assemble_ms,newton_iters,contacts,"
                          "n_candidates,ratio,min_ratio,max_ratio,target_ratio,status") != T_MAIN ||
      cb_experiment_table(&ex, "steps", NULL,
                          "n,vertices,method,kind,rep,step,t_s,contacts,n_candidates,newton_iters,"
                          "wall_ms,broad_ms,ccd_ms,barrier_ms,solve_ms,assemble_ms,rest_ms,status") != T_STEPS)
    return cb_experiment_end(&ex, CB_EIO), 2;
  FILE *fm = ex.table[T_MAIN].f, *fs = ex.table[T_STEPS].f;
  const int sizes[] = {32, 64};
  int rc = CB_OK;
  for (int si = 0; si < 2 && !rc; si++) {
    int n = sizes[si];
    side sd[NSIDE];
    memset(sd, 0, sizeof sd);
    for (int k = 0; k < NSIDE && !rc; k++)
      if ((rc = load(&ex, n, k == NONE, &sd[k].s, &sd[k].it)))
        fprintf(stderr, "bench_contact: n = %d (%s): %s\n", n, side_name[k], cb_error_message());
    if (rc) break;
    int nv = sd[IPC].s->mesh.nv, nv3 = 3 * nv;
    double dt = sd[IPC].it->params.dt;
    double *x = malloc((size_t)nv3 * sizeof *x), *v = malloc((size_t)nv3 * sizeof *v),
           *xs = malloc((size_t)nv3 * sizeof *xs), *vs = malloc((size_t)nv3 * sizeof *vs);
    if (!x || !v || !xs || !vs) {
      rc = CB_ENOMEM;
      break;
    }
    memcpy(x, sd[IPC].s->x0, (size_t)nv3 * sizeof *x);
    memcpy(v, sd[IPC].s->v0, (size_t)nv3 * sizeof *v);
    int wst = CB_OK;
    for (int j = 0; j < warm && !cb_status_is_fatal(wst); j++) {
      cb_step_stats st;
      wst = cb_integrator_step(sd[IPC].it, x, v, &st);
      step_row(fs, n, nv, "ipc", "warmup", 0, j + 1, (j + 1) * dt, sd[IPC].s, &st, wst);
      fprintf(stderr, "bench_contact: n = %d warm-up step %d: %.0f ms, %d Newton iterations, %s\n", n, j + 1,
              st.wall_ms, st.newton_iters, cb_status_name(wst));
    }
    fflush(fs);
    memcpy(xs, x, (size_t)nv3 * sizeof *x);
    memcpy(vs, v, (size_t)nv3 * sizeof *v);
    double ts = cb_scene_obstacle_time(sd[IPC].s);
    double ratio[CB_TIMING_MAX];
    int nratio = 0;
    if (!cb_status_is_fatal(wst)) {
      double spent = 0;
      for (int q = 0; cb_timing_more(ex.quick, q, spent); q++) {
        for (int j = 0; j < NSIDE; j++) {
          int k = (j + q) % NSIDE;
          spent += repeat(&sd[k], side_name[k], n, q, xs, vs, ts, x, v, steps, warm, dt, q == 0 ? fs : NULL);
        }
        if (sd[IPC].wall.n == q + 1 && sd[NONE].wall.n == q + 1 && nratio < CB_TIMING_MAX)
          ratio[nratio++] = sd[IPC].wall.ms[q] / sd[NONE].wall.ms[q];
        if (cb_status_is_fatal(sd[IPC].status) || cb_status_is_fatal(sd[NONE].status)) break;
      }
    }
    double rlo = NAN, rhi = NAN, rmed = NAN;
    for (int i = 0; i < nratio; i++) {
      rlo = i ? fmin(rlo, ratio[i]) : ratio[i];
      rhi = i ? fmax(rhi, ratio[i]) : ratio[i];
    }
    if (nratio > 0) rmed = cb_median(ratio, nratio);
    for (int k = 0; k < NSIDE; k++) {
      side *d = &sd[k];
      double ns = d->nsteps > 0 ? (double)d->nsteps : NAN;
      int status = cb_status_is_fatal(wst) ? wst : d->status;
      cb_csv_printf(fm, "%d,%d,%s,%d,%d,", n, nv, side_name[k], warm, steps);
      cb_timing_csv_repeats(fm, d->wall.n ? &d->wall : NULL);
      cb_csv_printf(fm, ",%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.17g,%.17g,%.17g,", cb_timing_median(&d->broad),
                    cb_timing_median(&d->ccd), cb_timing_median(&d->barrier), cb_timing_median(&d->solve),
                    cb_timing_median(&d->rest), cb_timing_median(&d->assemble), d->iters / ns, d->contacts / ns,
                    d->candidates / ns);
      if (k == IPC) cb_csv_printf(fm, "%.17g,%.17g,%.17g,%.17g", rmed, rlo, rhi, TARGET_RATIO);
      else fputs(",,,", fm);
      fprintf(fm, ",%s\n", cb_status_name(status));
      fprintf(stderr,
              "bench_contact: n = %d %-4s step %9.2f ms (broad %.2f, ccd %.2f, barrier %.2f, solve %.2f, rest %.2f) "
              "%.1f Newton iterations, %.0f contacts, %s\n",
              n, side_name[k], cb_timing_median(&d->wall), cb_timing_median(&d->broad), cb_timing_median(&d->ccd),
              cb_timing_median(&d->barrier), cb_timing_median(&d->solve), cb_timing_median(&d->rest), d->iters / ns,
              d->contacts / ns, cb_status_name(status));
    }
    fprintf(stderr, "bench_contact: n = %d ipc / none = %.3g (%.3g-%.3g over %d paired repeats); target %.0fx\n", n,
            rmed, rlo, rhi, nratio, TARGET_RATIO);
    fflush(fm);
    fflush(fs);
    for (int k = 0; k < NSIDE; k++) {
      cb_integrator_free(sd[k].it);
      cb_scene_free(sd[k].s);
    }
    free(x);
    free(v);
    free(xs);
    free(vs);
  }
  rc = cb_experiment_end(&ex, rc);
  return rc == CB_OK ? 0 : rc == CB_EIO ? 2 : 1;
}
