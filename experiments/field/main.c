/* field: the field's baselines of 2016-2024 (PBD and XPBD with small steps,
 * vertex block descent, quasi-Newton L-BFGS) next to the lecture's methods,
 * on the same scenes, as error against the converged implicit-Euler step
 * against wall time (issue 20; claims X1, X2, Q1, V1).
 *
 * Outputs (results/):
 *   field.csv            the main figure: per scene, one step of every method at 1, 2, 4, ...
 *                        iterations from a start state: step error against the converged step,
 *                        relative |grad F|, wall time, and whether the point is on its method's
 *                        error-time front and on the scene's (front.c)
 *   field_gap.csv        XPBD's gap: relative |grad F| and step error at XPBD's fixed point (1 x n,
 *                        n large) against converged Newton's, per scene
 *   field_x1.csv         X1: effective stiffness of PBD and XPBD (static stretch of a hanging strip
 *                        and of the lab cloth against the converged static state) at the iteration
 *                        count where XPBD's constraint residual has converged (kind converged: X1's
 *                        verdict) and for 1-100 iterations (kind sweep), three dt (x1.c)
 *   field_x2.csv         X2: XPBD n x 1 against 1 x n, n = 1..64: largest edge stretch, step error
 *                        and wall time (x2.c)
 *   field_tol.csv        Q1 and V1: iterations and wall time of every minimiser to relative |grad F|
 *                        1e-3 and 1e-5, relative objective error and step error 1e-2 and 1e-3
 *                        (column measure), and the matrix pd and lbfgs solved with (tol.c)
 *   field_tol_trace.csv  the three measures per iteration of those steps, with the time
 *   field_rises.csv      V1: objective rises between VBD iterations over trajectories (v1.c)
 *   field_scramble.csv   V1: a scrambled start (vertices displaced at random by up to the cloth's
 *                        size): diverged, and the mean strain at the start, halfway and at the end of
 *                        the window, per method (recovery is decided in claims/check_field.c)
 * The scenes are the table SCENES below, the work four sweeps of cells run by
 * the shared sweep runner (a front scene's cell also runs its tolerance part, tol.c, on the same
 * state and rho estimates); --shard I/N splits them. --smoke runs one small
 * cell per sweep, on the lab scene (and the strip). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "field.h"
#include "provenance.h"
#include "sweep.h"

static const char *const ABOUT =
    "Puts the field's baselines (pbd, xpbd with substeps, vbd, vbd-chebyshev, lbfgs) and the lecture's\n"
    "minimisers (Newton, Baraff-Witkin, jacobi-nl, chebyshev-nl, pd, pd-chebyshev) on the same scenes as\n"
    "error against the converged implicit-Euler step against wall time, and decides X1 (XPBD's stiffness\n"
    "does not depend on iterations and dt, PBD's does), X2 (small steps: n x 1 beats 1 x n), Q1 (L-BFGS\n"
    "faster than PD and Newton) and V1 (VBD descends monotonically, survives a scrambled start, beats\n"
    "Jacobi-type iterations).";

/* Scenes. Roles: "front" = the main figure's step (one cell per scene: every method shares its start
 * state and reference step), also the scene of tol (Q1, V1's speed; run in the same cell) and v1 (rises, scrambled
 * start); "x2" = the X2 comparison; "x1" = X1's static stretch. The lab cloth (configs/lab.ini, 21^2), Liu's 81^2 cloth
 * (the same 441 kg, k and 10 m, pinned at two corners) and its stiff variant (nonlinear's P1 scenes), Q1's size sweep
 * ("tolsize": 41^2 and 161^2, full run only), the 32^2 drape
 * over the sphere (configs/drape.ini), the hanging strip (configs/chain20.ini). level: 1 in --quick too, 2 in --smoke
 * too (--quick leaves out the 81^2 scenes, and runs the drape in the main figure only). */
typedef struct {
  cb_scene_decl scene;
  int level;
  int tol, v1; /* levels of the front scene in the tol and v1 sweeps (as level; -1: not in them) */
} scene_plan;
#define G81 "mesh.n=81", "material.vertex_mass=441/6561", "scene.pins=0 80"
/* Q1's size sweep (issue 31 §3): Liu's cloth at 41^2 and 161^2 with its 441 kg (k dt^2/m grows as n^2), and with
 * 81^2's mass per vertex (_vm81: the same k dt^2/m as grid81) */
#define G41 "mesh.n=41", "scene.pins=0 40"
#define G161 "mesh.n=161", "scene.pins=0 160"
static const scene_plan SCENES[] = {
    {{"lab", "lab.ini", {NULL}, "front"}, 2, 2, 2},
    {{"grid81", "lab.ini", {G81, NULL}, "front"}, 0, 0, 0},
    {{"grid81_stiff", "lab.ini", {G81, "material.stretch_k=1e6", NULL}, "front"}, 0, 0, 0},
    {{"drape", "drape.ini", {NULL}, "front"}, 1, 0, 0}, /* tol and V1 in the full run only */
    {{"lab", "lab.ini", {NULL}, "x2"}, 2, -1, -1},
    {{"grid81_stiff", "lab.ini", {G81, "material.stretch_k=1e6", NULL}, "x2"}, 0, -1, -1},
    {{"strip", "chain20.ini", {NULL}, "x1"}, 2, -1, -1},
    {{"grid41", "lab.ini", {G41, "material.vertex_mass=441/1681", NULL}, "tolsize"}, 0, -1, -1},
    {{"grid41_vm81", "lab.ini", {G41, "material.vertex_mass=441/6561", NULL}, "tolsize"}, 0, -1, -1},
    {{"grid161", "lab.ini", {G161, "material.vertex_mass=441/25921", NULL}, "tolsize"}, 0, -1, -1},
    {{"grid161_vm81", "lab.ini", {G161, "material.vertex_mass=441/6561", NULL}, "tolsize"}, 0, -1, -1},
    {{"lab", "lab.ini", {NULL}, "x1"}, 1, -1, -1},
};
enum { NSCENES = sizeof SCENES / sizeof SCENES[0] };
_Static_assert((int)NSCENES <= (int)FD_MAXSCENES, "field.h: FD_MAXSCENES");

static const cb_scene_decl *fd_scene_of(int i) { return &SCENES[i].scene; }

/* the plan's vertex counts, from the scenes' configs (so a bad declaration fails here, naming the
 * scene, before any cell runs) */
static int scene_sizes(fd_plan *p) {
  static cb_config c;
  for (int i = 0; i < NSCENES; i++) {
    int st = cb_scene_decl_config(p->e, fd_scene_of(i), NULL, &c);
    if (st) return st;
    p->nv[i] = cb_scene_decl_vertices(&c);
    if (!p->nv[i]) p->nv[i] = 1024;
  }
  return CB_OK;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "field", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  /* the front (the figure), X2 and Q1's sizes are wall times and run alone; X1's and V1's cells time nothing
   * and run beside other untimed work */
  cb_experiment_timed_cells(&e, (const char *const[]){"X1", "V1", NULL});
  int q = e.quick, sm = e.smoke;
  fd_plan p = {.e = &e, .quick = q, .smoke = sm, .state_frames = sm ? 2 : 10};
  for (int i = 0; i < NSCENES; i++) {
    const cb_scene_decl *d = p.decl[i] = fd_scene_of(i);
    int need = sm ? 2 : q ? 1 : 0;
    if (SCENES[i].level < need) continue;
    if (cb_scene_decl_is(d, "front")) {
      p.front[p.nfront++] = i;
      if (SCENES[i].tol >= need) p.tol[p.ntol++] = i;
      if (SCENES[i].v1 >= need) p.v1[p.nv1++] = i;
    } else if (cb_scene_decl_is(d, "x1")) p.x1[p.nx1++] = i;
    else if (cb_scene_decl_is(d, "x2")) p.x2[p.nx2++] = i;
    else if (cb_scene_decl_is(d, "tolsize")) p.tolsz[p.ntolsz++] = i;
  }
  if ((b = scene_sizes(&p))) return cb_experiment_end(&e, b), 1;
  const char *state_extra = "# state: 10 frames of the scene's own method (2 in --smoke); the step without damping\n";
  if (cb_experiment_table(&e, NULL, state_extra,
                          "scene,vertices,method,family,iters,substeps,rho,wall_ms,setup_ms,step_error,rel_grad,"
                          "on_method_front_by_wall,on_scene_front_by_wall,status") != T_FRONT ||
      cb_experiment_table(&e, "gap", state_extra,
                          "scene,vertices,method,iters,rel_grad,rel_grad_half,step_error,step_error_half,newton_method,"
                          "newton_rel_grad,step_error_newton,status") != T_GAP ||
      cb_experiment_table(&e, "x1", "# x1: static stretch after settling from the converged static state (see x1.c)\n",
                          "scene,method,kind,dt_s,iters,k_n_per_m,settle_s,ref_strain,strain,k_eff_n_per_m,"
                          "k_ratio,residual,status") != T_X1 ||
      cb_experiment_table(&e, "x2", state_extra,
                          "scene,vertices,n,variant,substeps,iters,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_"
                          "repeats,"
                          "step_error,max_strain,ref_max_strain,rel_grad,status") != T_X2 ||
      cb_experiment_table(&e, "tol", state_extra,
                          "scene,vertices,method,family,measure,tol,max_iters,iters_to_tol,wall_to_tol_ms,wall_to_tol_"
                          "min_ms,wall_to_tol_max_ms,wall_to_tol_each_ms,wall_repeats,alloc_ms,final_rel_grad,fallback,"
                          "global_matrix,status") != T_TOL ||
      cb_experiment_table(&e, "tol_trace", NULL, "scene,method,iter,rel_grad,rel_f,wall_ms,obj_error,step_error") !=
          T_TOL_TRACE ||
      cb_experiment_table(&e, "rises", NULL,
                          "scene,method,start,frames,frames_run,iters,rises,steps_with_rise,rel_max_rise,diverged,"
                          "diverge_frame,status") != T_RISES ||
      cb_experiment_table(&e, "scramble", NULL,
                          "scene,method,frames,frames_run,dt_s,displacement_m,start_strain,mid_strain,end_strain,"
                          "normal_strain,end_max_strain,diverged,diverge_frame,status") != T_SCRAMBLE)
    return cb_experiment_end(&e, CB_EIO), 2;
  const cb_sweep sweeps[] = {
      {"front", p.nfront, fd_front_cell, fd_front_cost, &p, NULL},
      {"X1", fd_x1_cells(&p), fd_x1_cell, fd_x1_cost, &p, NULL},
      {"X2", p.nx2, fd_x2_cell, fd_x2_cost, &p, NULL},
      {"V1", fd_v1_cells(&p), fd_v1_cell, fd_v1_cost, &p, NULL},
      {"Q1 sizes", p.ntolsz, fd_tolsize_cell, fd_tolsize_cost, &p, NULL},
  };
  int st = cb_sweep_run(&e, sweeps, 5);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
