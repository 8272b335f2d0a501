/* nonlinear: the GAMES103 lab's own iteration and the other nonlinear
 * iterations on the implicit-Euler objective F (claims J3 panel a, W1, P1),
 * and error against run time for every implicit method.
 *
 * Outputs (results/):
 *   nonlinear.csv             J3, the lab's iteration: per rho, a trajectory of the lab scene
 *                             (chebyshev-nl, 32 iterations, d = m/dt^2 + 4k, damping 0.99):
 *                             whether and at which frame it diverged, the median relative
 *                             |grad F| after the 32 iterations, the linearised rho along the run
 *   nonlinear_spectrum.csv    rho(I - D^-1 A(x)) at sampled frames of each run (A = M/dt^2 + H(x),
 *                             exact Hessian, D the lab's diagonal; Lanczos)
 *   nonlinear_w1.csv          W1: iterations and wall time to relative |grad F| 1e-2 and 1e-4,
 *                             jacobi-nl vs chebyshev-nl and pd vs pd-chebyshev, at 21^2, 64^2, 128^2
 *                             (each traced run rerun with a larger cap until it reaches 1e-4)
 *   nonlinear_w1_trace.csv    the relative |grad F| per iteration of those steps (the figure)
 *   nonlinear_p1.csv          P1: per frame of an 81^2 cloth (and a stiff one), wall time and
 *                             step error against the converged step, for pd (10 iterations),
 *                             converged Newton (exact Hessian with line search, and drop) and
 *                             Baraff-Witkin
 *   nonlinear_p1_error.csv    P1: per frame, the iterations and wall time pd and exact Newton
 *                             need to reach step error 1e-2 and 1e-3
 *   nonlinear_error_time.csv  one step of every implicit method at several iteration counts:
 *                             step error and relative |grad F| against wall time
 * The scenes are the table SCENES below, the work four sweeps of cells (one
 * per phase), run by the shared sweep runner; --shard I/N splits them.
 * --smoke runs the lab scene's cells alone, short. Each cell kind is
 * its own file (nonlinear.h); one step from a start state against the
 * converged step is lib/instruments/step_bench.h, shared with field. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nonlinear.h"
#include "provenance.h"
#include "sweep.h"

static const char *const ABOUT =
    "Decides J3 on the lab's own iteration (panel a; panel b is linear_solvers' linear-solve rows),\n"
    "W1 (Wang 2015: Chebyshev accelerates the nonlinear iteration >= 10x) and P1 (Liu 2013:\n"
    "projective dynamics reaches a visually converged step much faster than exact Newton), and\n"
    "measures error against run time for every implicit method on the same steps.";

/* Scenes: configs/lab.ini (the lab's cloth and method) with these overrides.
 * Roles: "j3" = one trajectory per rho of nl_rhos (j3.c) (tables main and spectrum; one
 * cell per (scene, rho)); "w1" = one step of the W1 methods from a start
 * state (tables w1 and w1_trace); "p1" = one step of the P1 methods from
 * each of P1's start states (table p1; one cell per (scene, start state));
 * "error_time" = one step of every implicit method at 1, 2, 4, ... iterations
 * (table error_time). A "w1" scene is one cell per pair of methods (the
 * plain and the accelerated iteration, timed together), an "error_time"
 * scene one cell per method: the cells of a scene each compute the same start
 * state and reference step, so that no cell is most of the run and the
 * shards finish together. quick: the scene runs in --quick too.
 *
 * The lab cloth at 21^2, and the same cloth (441 kg, k, 10 m) at 64^2, 128^2
 * quads (129^2 = 16 641 vertices, Wang's dress size) and 81^2 (6561 vertices,
 * Liu's cloth, P1), pinned at the lab's corners 0 and n-1; P1's stiff variant. */
typedef struct {
  cb_scene_decl scene;
  int quick; /* 1: in --quick too; 2: in --smoke too; 3: in --smoke only */
} scene_plan;
#define G64 "mesh.n=64", "material.vertex_mass=441/4096", "scene.pins=0 63"
#define G128 "mesh.n=129", "material.vertex_mass=441/16641", "scene.pins=0 128" /* 128^2 quads */
#define G81 "mesh.n=81", "material.vertex_mass=441/6561", "scene.pins=0 80"
static const scene_plan SCENES[] = {
    {{"lab", "lab.ini", {NULL}, "j3"}, 2},
    {{"lab", "lab.ini", {NULL}, "w1"}, 2},
    {{"grid64", "lab.ini", {G64, NULL}, "w1"}, 1},
    {{"grid128", "lab.ini", {G128, NULL}, "w1"}, 0},
    {{"grid81", "lab.ini", {G81, NULL}, "p1"}, 1},
    {{"grid81_stiff", "lab.ini", {G81, "material.stretch_k=1e6", NULL}, "p1"}, 1},
    {{"lab", "lab.ini", {NULL}, "p1"}, 3},
    /* P1's size sweep (issue 31 §3): 441 kg in total (k dt^2/m grows as n^2), and 81^2's mass per vertex (_vm81) */
    {{"grid41", "lab.ini", {"mesh.n=41", "material.vertex_mass=441/1681", "scene.pins=0 40", NULL}, "p1"}, 1},
    {{"grid41_vm81", "lab.ini", {"mesh.n=41", "material.vertex_mass=441/6561", "scene.pins=0 40", NULL}, "p1"}, 1},
    {{"grid161", "lab.ini", {"mesh.n=161", "material.vertex_mass=441/25921", "scene.pins=0 160", NULL}, "p1"}, 0},
    {{"grid161_vm81", "lab.ini", {"mesh.n=161", "material.vertex_mass=441/6561", "scene.pins=0 160", NULL}, "p1"}, 0},
    {{"lab", "lab.ini", {NULL}, "error_time"}, 2},
    {{"grid64", "lab.ini", {G64, NULL}, "error_time"}, 0},
};
enum { NSCENES = sizeof SCENES / sizeof SCENES[0] };
_Static_assert((int)NSCENES <= (int)NL_MAXSCENES, "nonlinear.h: NL_MAXSCENES");

const cb_scene_decl *nl_scene_of(int i) { return &SCENES[i].scene; }

int nl_state(const cb_experiment *e, const cb_scene_decl *d, int frames, cb_step_state *S) {
  static cb_config c; /* large: not on the stack */
  cb_scene *s = NULL;
  int st = cb_scene_decl_build(e, d, NULL, &c, &s);
  return st ? st : cb_step_state_init(S, d->label, &c, s, frames);
}

/* the plan's vertex counts and grid sizes, from the scenes' configs (so a bad
 * declaration fails here, naming the scene, before any cell runs) */
static int scene_sizes(plan *p) {
  for (int i = 0; i < NSCENES; i++) {
    cb_scene_size z;
    int st = cb_sweep_scene_size(p->e, nl_scene_of(i), &z);
    if (st) return st;
    p->nv[i] = z.nv;
    p->mesh_n[i] = z.mesh_n;
  }
  return CB_OK;
}

int main(int argc, char **argv) {
  cb_experiment e;
  int b = cb_experiment_begin(&e, "nonlinear", ABOUT, argc, argv);
  if (b) return b > 0 ? 0 : 1;
  /* W1, P1 and the error-time figure are wall times and run alone; J3 compares none (its median_frame_ms is
   * recorded, decides nothing) and runs beside other untimed work */
  cb_experiment_timed_cells(&e, (const char *const[]){"J3", NULL});
  int q = e.quick, sm = e.smoke; /* smoke: the lab scene only, one rho, a few frames, one P1 state */
  plan p = {.e = &e,
            .quick = q,
            .smoke = sm,
            .rho0 = sm ? NL_NRHO - 1 : 0,
            .nrho = sm ? 1 : NL_NRHO,
            .frames = sm  ? 5
                      : q ? 300
                          : 2000,
            .state_frames = sm  ? 2
                            : q ? 10
                                : 20,
            .p1_states = sm  ? 1
                         : q ? 2
                             : 3};
  for (int i = 0; i < NSCENES; i++) {
    const cb_scene_decl *d = nl_scene_of(i);
    int level = SCENES[i].quick;
    if (sm ? level < 2 : level == 3 || (q && level < 1)) continue;
    if (cb_scene_decl_is(d, "j3")) p.j3[p.nj3++] = i;
    else if (cb_scene_decl_is(d, "w1")) p.w1[p.nw1++] = i;
    else if (cb_scene_decl_is(d, "p1")) p.p1[p.np1++] = i;
    else if (cb_scene_decl_is(d, "error_time")) p.et[p.net++] = i;
  }
  if ((b = scene_sizes(&p))) return cb_experiment_end(&e, b), 1;
  char j3_extra[256], p1_extra[256];
  snprintf(j3_extra, sizeof j3_extra,
           "# frames: %d (configs/lab.ini: chebyshev-nl, 32 iterations, damping 0.99; integrator.rho swept)\n",
           p.frames);
  snprintf(p1_extra, sizeof p1_extra,
           "# frames: %d (start states: frames 5, 10, ... of the lab's method; the step without damping)\n",
           p.p1_states);
  const char *state_extra = "# state: 20 frames of the lab's method (10 in --quick, 2 in --smoke); the step without "
                            "damping\n";
  if (cb_experiment_table(&e, NULL, j3_extra,
                          "panel,scene,method,rho_given,rho,frames,frames_run,diverged,diverge_frame,median_rel_grad,"
                          "p90_rel_grad,max_rel_grad,frames_grad_up,rho_lin_median,rho_lin_max,lmin_min,lmax_max,"
                          "median_frame_ms,status") != T_J3 ||
      cb_experiment_table(&e, "spectrum", j3_extra, "scene,rho_given,frame,lmin,lmax,rho_lin,lanczos_steps") !=
          T_SPECTRUM ||
      cb_experiment_table(&e, "w1", state_extra,
                          "scene,n,method,pair,rho,max_iters,tol,iters_to_tol,wall_to_tol_ms,wall_to_tol_min_ms,"
                          "wall_to_tol_max_ms,wall_to_tol_each_ms,wall_repeats,setup_ms,alloc_ms,"
                          "final_rel_grad,status") != T_W1 ||
      cb_experiment_table(&e, "w1_trace", NULL, "scene,n,method,iter,rel_grad") != T_W1_TRACE ||
      cb_experiment_table(&e, "p1", p1_extra,
                          "scene,n,k_n_per_m,method,frame,iters,wall_ms,wall_min_ms,wall_max_ms,wall_each_ms,wall_"
                          "repeats,"
                          "alloc_ms,step_error,obj_error,rel_grad,fallback,global_matrix,status") != T_P1 ||
      cb_experiment_table(&e, "p1_error", p1_extra,
                          "scene,n,k_n_per_m,method,frame,measure,tol,max_iters,iters_to_tol,wall_to_tol_ms,wall_to_"
                          "tol_"
                          "min_ms,wall_to_tol_max_ms,wall_to_tol_each_ms,wall_repeats,step_error,obj_error,rel_grad,"
                          "fallback,global_matrix,status") != T_P1_ERROR ||
      cb_experiment_table(&e, "error_time", state_extra,
                          "scene,n,method,family,iters,rho,wall_ms,setup_ms,step_error,rel_grad,status") !=
          T_ERROR_TIME)
    return cb_experiment_end(&e, CB_EIO), 2;
  const cb_sweep sweeps[] = {
      {"J3", (long)p.nj3 * p.nrho, nl_j3_cell, nl_j3_cost, &p, NULL},
      {"W1", (long)p.nw1 * NL_W1_PAIRS, nl_w1_cell, nl_w1_cost, &p, NULL},
      {"P1", (long)p.np1 * p.p1_states, nl_p1_cell, nl_p1_cost, &p, NULL},
      {"error-time", (long)p.net * NL_ET_METHODS, nl_et_cell, nl_et_cost, &p, NULL},
  };
  int st = cb_sweep_run(&e, sweeps, 4);
  st = cb_experiment_end(&e, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
