/* The nonlinear experiment's pieces: main.c declares the scenes and the plan
 * and runs the sweeps; each cell kind lives in its own file:
 *   j3.c          J3 panel a: the lab's iteration over 2000 frames, rho swept
 *   w1.c          W1: iterations and wall time to relative |grad F| 1e-2 and 1e-4
 *   p1.c          P1: pd (10 iterations) against the fastest Newton and Baraff-Witkin
 *   error_time.c  one step of every implicit method at 1, 2, 4, ... iterations
 * The steps from a start state against the converged step are the shared
 * module lib/instruments/step_bench.h. */
#ifndef NONLINEAR_H
#define NONLINEAR_H

#include <stdio.h>

#include <clothbench/definiteness.h>
#include <clothbench/eigen.h>
#include <clothbench/integrator.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include <clothbench/system.h>
#include "bind.h"
#include "experiment.h"
#include "reference.h"
#include "scene_decl.h"
#include "spectrum.h"
#include "stats.h"
#include "step_bench.h"

enum { T_J3, T_SPECTRUM, T_W1, T_W1_TRACE, T_P1, T_P1_ERROR, T_ERROR_TIME }; /* tables, in the order opened */
enum { NL_MAXSCENES = 16 };
/* cells per scene: W1 one per pair of methods (plain and accelerated, timed together), error-time one per
 * method */
enum { NL_W1_PAIRS = 2, NL_ET_METHODS = 12 };

/* J3's rho values */
enum { NL_NRHO = 10 };
extern const char *const nl_rhos[NL_NRHO];

/* The plan: the scenes of each role this run (--quick or not) and its sizes. */
typedef struct {
  const cb_experiment *e;
  int quick, smoke;
  int rho0, nrho;   /* J3's rho values: nl_rhos[rho0 .. rho0 + nrho) */
  int frames;       /* J3 frames per trajectory */
  int state_frames; /* frames of the lab's method before the W1 and error-time step */
  int p1_states;    /* P1 start states per scene: frames 5, 10, ... */
  int j3[NL_MAXSCENES], nj3, w1[NL_MAXSCENES], nw1, p1[NL_MAXSCENES], np1, et[NL_MAXSCENES],
      net;               /* scene indices by role */
  long nv[NL_MAXSCENES]; /* vertices of each scene (cost hints) */
  int mesh_n[NL_MAXSCENES];
} plan;

/* scene i of main.c's table */
const cb_scene_decl *nl_scene_of(int i);
/* scene d's start state after `frames` frames of the lab's method, and the reference step from it */
int nl_state(const cb_experiment *e, const cb_scene_decl *d, int frames, cb_step_state *S);

/* the sweeps' cells and cost hints (estimated ms, from a --quick run with one BLAS thread and the full
 * run's phase times) */
int nl_j3_cell(long i, void *ctx, FILE *const *out);
double nl_j3_cost(long i, void *ctx);
int nl_w1_cell(long i, void *ctx, FILE *const *out);
double nl_w1_cost(long i, void *ctx);
int nl_p1_cell(long i, void *ctx, FILE *const *out);
double nl_p1_cost(long i, void *ctx);
int nl_et_cell(long i, void *ctx, FILE *const *out);
double nl_et_cost(long i, void *ctx);

#endif
