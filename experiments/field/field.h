/* The field experiment's pieces (issue 20): main.c declares the scenes and the
 * plan and runs the sweeps; each cell kind lives in its own file:
 *   front.c  the main figure: one step of every method at 1, 2, 4, ... iterations
 *            from a start state, step error against the converged step and wall
 *            time, each method's error-time front and the scene's; XPBD's gap
 *   x1.c     X1: effective stiffness of PBD and XPBD over iterations and dt
 *   x2.c     X2: XPBD n substeps x 1 iteration against 1 x n iterations
 *   tol.c    Q1 and V1's speed: iterations and wall time to relative |grad F|
 *            1e-3 and 1e-5, and the |grad F| traces (run by the front cell of
 *            its scene, on the same state and with the same rho estimates)
 *   v1.c     V1: objective rises over trajectories, and the scrambled start
 * The steps from a start state are lib/instruments/step_bench.h (shared with
 * the nonlinear experiment). */
#ifndef FIELD_H
#define FIELD_H

#include <stdio.h>

#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "bind.h"
#include "experiment.h"
#include "reference.h"
#include "scene_decl.h"
#include "stats.h"
#include "step_bench.h"

/* tables, in the order opened */
enum { T_FRONT, T_GAP, T_X1, T_X2, T_TOL, T_TOL_TRACE, T_RISES, T_SCRAMBLE };
enum { FD_MAXSCENES = 16 };

typedef struct {
  const cb_experiment *e;
  int quick, smoke;
  int state_frames; /* frames of the scene's own method before the measured step */
  int front[FD_MAXSCENES], nfront, x1[FD_MAXSCENES], nx1, x2[FD_MAXSCENES], nx2, tol[FD_MAXSCENES], ntol,
      v1[FD_MAXSCENES], nv1,               /* scene indices by role */
      tolsz[FD_MAXSCENES], ntolsz;         /* role "tolsize": Q1's size sweep (tol.c) */
  long nv[FD_MAXSCENES];                   /* vertices of each scene (cost hints) */
  const cb_scene_decl *decl[FD_MAXSCENES]; /* each scene's declaration (main.c's table) */
} fd_plan;

/* scene d's start state after `frames` frames of its own method, and the reference step from it */
int fd_state(const cb_experiment *e, const cb_scene_decl *d, int frames, cb_step_state *S);
/* 1 if the method `sets` can step S's scene (its integrator's init accepts it), 0 if not (why gets the
 * reason), < 0 on another error */
int fd_supported(cb_step_state *S, const char *const *sets, char *why, size_t nwhy);
/* |grad F(xhat)| of S's step (the relative |grad F| of every method is against it) */
double fd_grad_hat(const cb_step_state *S);
/* edge strain |x_i - x_j| / L - 1 over the stretch springs at x: the largest and the mean of |strain| */
void fd_strain(const cb_scene *s, const double *x, double *max_strain, double *mean_abs);
/* sets + "key=K" into out (NULL-terminated; at most 12 sets); buf holds the "key=K" */
void fd_with(const char *const *sets, const char *key, int K, char *buf, size_t nbuf, const char **out);

/* The auto rho estimates made on one start state (a cell's S), so that the main figure and the
 * tolerance runs of a scene estimate each method's rho once: cleared when the state changes. */
enum { FD_RHO_CACHE = 16 };
typedef struct {
  int n;
  char key[FD_RHO_CACHE][512], rho[FD_RHO_CACHE][64];
  double ms[FD_RHO_CACHE];
} fd_rho_cache;
void fd_rho_cache_clear(fd_rho_cache *rc);
/* sets with integrator.rho=auto replaced by the estimate of one run of it (the estimate is the same in
 * every run of the method on S's step; W1 in nonlinear does the same): out gets the sets (at most 12),
 * buf the "integrator.rho=<estimate>", *est_ms the estimate's time. Sets without auto are copied. With
 * rc (may be NULL), an estimate of the same sets on the same state is taken from the cache (its time
 * the one measured when it was made), and a new one is added to it. */
int fd_fix_rho(cb_step_state *S, fd_rho_cache *rc, const char *const *sets, const char **out, char *buf, size_t nbuf,
               double *est_ms);

int fd_front_cell(long i, void *ctx, FILE *const *out);
double fd_front_cost(long i, void *ctx);
long fd_x1_cells(const fd_plan *p);
int fd_x1_cell(long i, void *ctx, FILE *const *out);
double fd_x1_cost(long i, void *ctx);
int fd_x2_cell(long i, void *ctx, FILE *const *out);
double fd_x2_cost(long i, void *ctx);
/* Q1 and V1's speed on scene d from the front cell's state S (and its rho estimates, rc) */
int fd_tol_scene(const fd_plan *p, const cb_scene_decl *d, cb_step_state *S, fd_rho_cache *rc, FILE *const *out);
double fd_tol_cost(const fd_plan *p, int scene);
/* Q1's size sweep: Q1's methods to every tolerance on the "tolsize" scenes (41^2, 161^2; issue 31 §3) */
int fd_tolsize_cell(long i, void *ctx, FILE *const *out);
double fd_tolsize_cost(long i, void *ctx);
long fd_v1_cells(const fd_plan *p);
int fd_v1_cell(long i, void *ctx, FILE *const *out);
double fd_v1_cost(long i, void *ctx);

#endif
