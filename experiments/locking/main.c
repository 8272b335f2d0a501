/* locking: membrane locking, the DoF count behind it, co-rotational FEM
 * against springs, and shape matching under explicit integration (claims L1,
 * L2, F1, S1). docs/experiments/locking.md explains every choice.
 *
 * L1  results/locking.csv: a 1 m square cloth (grids, regular and
 *     alternating) or a 1 m disk (the irregular ring disk of T2), horizontal,
 *     bending off, pinned on one side of a straight fold line through its
 *     centre, hangs under gravity. Its rest state is a static solve: proximal
 *     Newton steps x <- argmin E(y) + |y - x|_M^2/(2h^2) (lib/instruments/
 *     stability.c, cb_stability_equilibrium: implicit Euler from rest, h
 *     doubling to 10 s) until max_i |dE/dx_i| <= 1e-5 max_i m_i g. The fold
 *     angle is atan2(drop, offset) of the free part's centroid below and
 *     beyond the fold line: 90 deg hangs straight down, 0 stays flat.
 *     Sweep: in-plane stiffness k (spring) or mu (FEM) 1e1..1e7 N/m, four
 *     fold lines (along grid edges, along and across the regular diagonal, at
 *     30 deg), three meshes, springs and FEM. Whether the line runs along mesh
 *     edges is measured: no triangle has vertices strictly on both sides.
 * L2  results/locking_dofs.csv: 3 #variables - rank(rigidity matrix)
 *     (lib/instruments/rigidity.c) with every edge hard (conforming, variables
 *     at the vertices) and with every triangle rigid on edge-midpoint
 *     variables (nonconforming, English & Bridson 2008), at jittered generic
 *     positions, per vertex against mesh size.
 * F1  results/locking_aniso.csv: disks of radius 0.5 m in the plane (the n^2 grids clipped
 *     to it, and the ring disk of (n - 1)/2 rings) on a refinement ladder n = 15, 31, 63
 *     (15, 31 with --quick), boundary held at X + u(X) for a non-affine u (a
 *     non-uniform stretch, an in-plane-bending shear) in 8 directions, interior
 *     relaxed by the same static solve, elastic energy per area (an affine load is
 *     FEM's patch test and would decide nothing); results/locking_newton.csv: one
 *     implicit Euler step of the lab cloth at 64^2 (32^2 with --quick), springs, FEM
 *     exact and FEM frozen, |grad F| and wall time per Newton iteration.
 * S1  results/locking_shape.csv: shape matching (integrator.shape_alpha swept) on
 *     explicit_stability's chain and 21^2 cloth, hanging vertically from the
 *     rest shape with a small random velocity, over the upper three decades of
 *     explicit_stability's dt range, every cell the same simulated time (2 s);
 *     cells classified by the growth rate of their energy and shape error
 *     (s1_shape.c: stable, falling, unstable, diverged), with the shape error at
 *     the end (max edge strain, distance to the best-fit rigid motion of the rest
 *     shape), against springs (the scene's k) under symplectic Euler from the
 *     same start.
 * --smoke: one small cell per sweep (docs/experiments/locking.md says which). */
#include <string.h>

#include <clothbench/status.h>
#include "sweep.h"

#include "locking.h"

cb_experiment E;
int nsteps, step_idx[NSCENES], nshape, shape_idx[NSCENES];

int main(int argc, char **argv) {
  int r = cb_experiment_begin(&E, "locking",
                              "L1, L2, F1 and S1: membrane locking of stiff in-plane edges, the DoF count "
                              "behind it (conforming against nonconforming elements), co-rotational FEM "
                              "against springs, and shape matching under explicit integration.",
                              argc, argv);
  if (r) return r > 0 ? 0 : 1;
  /* F1's Newton step is timed and runs alone; L2, F1's anisotropy, S1 and L1 compare no wall time (S1's
   * cell_wall_ms and L1's eq_wall_ms are recorded, decide nothing) and run beside other untimed work */
  cb_experiment_timed_cells(&E,
                            (const char *const[]){"L2 meshes", "F1 anisotropy", "S1 shape matching", "L1 fold", NULL});
  int quick = E.quick, st = CB_OK;
  for (int i = 0; i < NSCENES; i++) {
    if (cb_scene_decl_is(&SCENES[i].scene, "step")) step_idx[nsteps++] = i;
    if (cb_scene_decl_is(&SCENES[i].scene, "shape")) shape_idx[nshape++] = i;
  }
  if (cb_experiment_table(&E, NULL,
                          "# L1: static rest state by proximal Newton steps (cb_stability_equilibrium), tol max|dE/dx| "
                          "<= 1e-5 max m g; "
                          "fold_angle_deg = atan2(drop, offset) of the free part's centroid; on_edges = no triangle "
                          "straddles the fold line\n",
                          "model,mesh,fold,fold_dir_deg,on_edges,k_n_per_m,vertices,pinned,fold_angle_deg,offset_m,"
                          "drop_m,"
                          "max_strain,rms_strain,eq_steps,newton_iters,residual,degenerate,eq_wall_ms,status") !=
          T_MAIN ||
      cb_experiment_table(&E, "dofs",
                          "# L2: DoFs = 3 #variables - rank(rigidity matrix) at jittered generic positions (GSL SVD, "
                          "threshold 1e-9)\n",
                          "mesh,vertices,triangles,edges,boundary_edges,conforming_dofs,conforming_predicted,"
                          "conforming_per_vertex,nonconforming_variables,nonconforming_dofs,nonconforming_predicted,"
                          "nonconforming_per_vertex,status") != T_DOFS ||
      cb_experiment_table(&E, "aniso",
                          "# F1: disks of radius 0.5 m (n^2 grids clipped to it, ring disks of (n - 1)/2 rings; mesh "
                          "spacing h = 1/(n - 1) m, n = 15, 31, 63), boundary held at X + u(X) for a "
                          "non-affine u along "
                          "dir_deg (stretch: u = eps (s + R)^2/(4R) n; shear: u = eps s^2/(2R) t; s = n.X, eps = "
                          "strain), "
                          "interior relaxed; k = mu = 1000 N/m\n",
                          "model,mesh,n,h_m,family,test,dir_deg,vertices,strain,energy_j,energy_density_j_per_m2,area_"
                          "m2,"
                          "free_vertices,"
                          "residual,status") != T_ANISO ||
      cb_experiment_table(&E, "newton",
                          "# F1: one implicit Euler step of the lab cloth, |grad F| per Newton iteration; wall_ms "
                          "since the step began\n",
                          "model,rep,iter,f_j,grad_norm_n,rel_grad,wall_ms") != T_NEWTON ||
      cb_experiment_table(&E, "newton_steps", NULL,
                          "model,n,rep,newton_iters,factorizations,rel_grad,assemble_ms,factor_ms,solve_ms,step_wall_"
                          "ms,status") != T_STEPS ||
      cb_experiment_table(&E, "shape",
                          "# S1: cells as explicit_stability (energy = kinetic + elastic + gravity; shape matching "
                          "scenes have k = 0); "
                          "shape error at the end: edge strain (l - L)/L against the rest shape, and the mass-weighted "
                          "RMS distance "
                          "to the best-fit rigid motion of the rest shape (rigid_dist_m; over the rest shape's RMS "
                          "radius: "
                          "rigid_dist_over_size)\n",
                          "scene,method,alpha,dt_s,class,max_energy_ratio,final_energy_ratio,steps,t_end_s,sim_time_s,"
                          "max_strain,rms_strain,rigid_dist_m,rigid_dist_over_size,energy_growth_exponent,"
                          "shape_growth_exponent,shape_growth_per_s,cell_wall_ms,step_status") != T_SHAPE)
    return cb_experiment_end(&E, CB_EIO), 2;
  /* the disk of L1 (horizontal) and F1's meshes at every level of its ladder (clipped grids, ring disks):
   * inputs of cells, written by every shard. The ladder: n = 15, 31, 63 (15, 31 with --quick; 7 with --smoke) */
  static const int ladder[F1_MAXLEV] = {15, 31, 63}, smoke_ladder[1] = {7};
  if ((st = lk_write_disk(quick ? 4 : 6, 0)) ||
      (st = lk_write_f1_meshes(E.smoke ? smoke_ladder : ladder, E.smoke ? 1
                                                                : quick ? 2
                                                                        : F1_MAXLEV)))
    return cb_experiment_end(&E, st), 2;
  const cb_sweep sweeps[] = {
      /* --smoke: one small cell per sweep (the cells say which) */
      {"L2 meshes", E.smoke ? 1 : 2L * (quick ? 4 : 5) + (quick ? 3 : 5), lk_l2_cell, NULL, &quick, NULL},
      {"F1 anisotropy", E.smoke ? 1 : (long)NMESH * f1_nlev, lk_f1_aniso_cell, NULL, &quick, NULL},
      {"F1 Newton step", nsteps > 0, lk_f1_newton_cell, NULL, &quick, NULL},
      {"S1 shape matching", E.smoke ? 1 : nshape * ((quick ? 3L : 5L) + 1), lk_s1_cell, NULL, &quick, NULL},
      {"L1 fold", E.smoke ? 1 : (long)NMESH * NFOLD, lk_l1_cell, NULL, &quick, NULL},
  };
  st = cb_sweep_run(&E, sweeps, (int)(sizeof sweeps / sizeof sweeps[0]));
  st = cb_experiment_end(&E, st);
  return st == CB_OK ? 0 : st == CB_EIO ? 2 : 1;
}
