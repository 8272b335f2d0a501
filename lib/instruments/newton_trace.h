/* A Newton hook that records every iteration of a step, with the
 * definiteness witnesses of spd_probe.h run on the matrix that was solved
 * and, optionally, on the lecture's exact matrix M/dt^2 + H_none(x) at the
 * same iterate (assembled in a reference system with linear springs).
 *
 * Rows are kept in a buffer allocated at set-up (max_iters + 1 per step) and
 * read by the caller after cb_newton_trace_end_step. Per-iteration wall time counts
 * the integrator's own work (gradient, assembly, factorisations, solve,
 * update) and excludes the probes, which are timed separately. */
#ifndef CB_NEWTON_TRACE_H
#define CB_NEWTON_TRACE_H

#include <clothbench/integrator.h>
#include <clothbench/scene.h>
#include "spd_probe.h"
#include <clothbench/system.h>

typedef struct cb_newton_trace_row {
  int iter;                   /* Newton iteration: x^(iter), 0 = initial guess */
  int system;                 /* 1 if A(x^(iter)) was assembled and solved */
  double rel_grad, grad_norm; /* |grad F(x)| / |grad F(x^(0))|, |grad F(x)| (N) */
  double F;                   /* F(x), J */
  double energy;              /* E(x): springs + gravity potential, J */
  double compressed_frac;     /* indefinite elements over all counted ones (springs: l < L), cb_compressed_fraction */
  int status;                 /* system row: the factor/solve status; last row: the step's status */
  double mu;                  /* shift in the matrix solved (`shift` policy), N/m */
  int linear_ok;              /* the integrator's factor/solve succeeded (CHOLMOD: A was SPD) */
  cb_spd_probe_result used;   /* witnesses on the matrix solved */
  int have_exact;
  cb_spd_probe_result exact; /* witnesses on the exact (none) matrix at x */
  double wall_ms;            /* the integrator's time for this iteration, probes excluded */
} cb_newton_trace_row;

typedef struct cb_newton_trace {
  const cb_scene *scene;
  cb_system *ref;                 /* reference system for the exact matrix, or NULL (the run is exact) */
  double mass_scale;              /* 1/dt^2 */
  unsigned what_used, what_exact; /* CB_PROBE_* bits */
  cb_spd_probe *probe, *probe_ref;
  cb_newton_trace_row *rows;
  int nrows, cap;
  double t_mark, probe_ms_mark; /* time accounting of the open row */
  double probe_ms;              /* probe time in this step */
  int open;                     /* a row is open (waiting for its wall time) */
  int error;                    /* first probe error (negative status), 0 if none */
} cb_newton_trace;

/* ref may be NULL. cap = max_iters + 1. Probes use params (NULL: defaults). */
int cb_newton_trace_init(cb_newton_trace *t, const cb_scene *scene, cb_system *ref, double dt, int cap,
                         unsigned what_used, unsigned what_exact, const cb_spd_probe_params *params);
void cb_newton_trace_free(cb_newton_trace *t);

/* Call right before cb_integrator_step, and right after it with its status. */
void cb_newton_trace_begin_step(cb_newton_trace *t);
void cb_newton_trace_end_step(cb_newton_trace *t, int status);

/* The hook: set params.hook = cb_newton_trace_hook, params.hook_ctx = &trace. */
void cb_newton_trace_hook(void *ctx, int event, const cb_newton_event *ev);

/* Fraction of the elements whose Hessian at x can be indefinite, over the
 * elements of every term of sys that counts them (cb_term_count_indefinite):
 * on a spring scene, the springs with l < L over all springs. */
double cb_compressed_fraction(const cb_system *sys, const double *x);

#endif
