/* Verdict logic of claims/check_locking.c (L1, L2, F1, S1) on small
 * constructed CSVs: a passing and a failing case per claim. */
#define _DEFAULT_SOURCE
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"
#include "support.h"


static char dir[64];

static void put(const char *name, const char *text) { test_put(dir, name, NULL, text); }

static void setup(void) {
  snprintf(dir, sizeof dir, "/tmp/cblockXXXXXX");
  cr_assert(mkdtemp(dir));
}
static void teardown(void) {
  static const char *const files[] = {"locking.csv",        "locking_dofs.csv",         "locking_aniso.csv",
                                      "locking_newton.csv", "locking_newton_steps.csv", "locking_shape.csv"};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
    char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, files[i]);
    unlink(path);
  }
  rmdir(dir);
}

static cb_claim_result last; /* the result of the last decide() */

static cb_verdict decide(cb_claim_check check) {
  char path[128];
  snprintf(path, sizeof path, "%s/locking.csv", dir);
  return test_decide_check(check, path, dir, &last);
}

static const char *l1_head = "# test\nmodel,mesh,fold,on_edges,k_n_per_m,fold_angle_deg,status\n";

TestSuite(claims_locking, .init = setup, .fini = teardown);

Test(claims_locking, L1_reproduced_when_across_falls_and_along_stays) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "spring,regular,edges,1,10,90,ok\nspring,regular,edges,1,1e4,89,ok\nspring,regular,edges,1,1e7,88,ok\n"
           "spring,regular,cross,0,10,85,ok\nspring,regular,cross,0,1e4,40,ok\nspring,regular,cross,0,1e7,5,ok\n"
           "spring,regular,cross,0,1e8,99,max_iters\n",
           l1_head); /* an unconverged row is left out */
  put("locking.csv", csv);
  cr_assert_eq(decide(cb_check_L1), CB_REPRODUCED);
}

Test(claims_locking, L1_not_reproduced_without_locking) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "fem,disk,angle30,0,10,90,ok\nfem,disk,angle30,0,1e7,80,ok\n"    /* falls only 10 deg */
           "fem,regular,edges,1,10,90,ok\nfem,regular,edges,1,1e7,60,ok\n", /* along edges, yet it locks */
           l1_head);
  put("locking.csv", csv);
  cr_assert_eq(decide(cb_check_L1), CB_NOT_REPRODUCED);
  /* a range shorter than 4 decades is not judged at all */
  snprintf(csv, sizeof csv, "%sfem,disk,angle30,0,10,90,ok\nfem,disk,angle30,0,1e3,10,ok\n", l1_head);
  put("locking.csv", csv);
  cr_assert_eq(decide(cb_check_L1), CB_NOT_RUN);
}

/* Failure mode 1 (issue 19 #9): a solver that never moved. The flap stays flat (0 deg) at every k:
 * constant along the edges, which the old rule (constancy) passed; it is 90 deg off the free fold. */
Test(claims_locking, L1_not_reproduced_when_nothing_moved) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "spring,regular,edges,1,10,0,ok\nspring,regular,edges,1,1e4,0,ok\nspring,regular,edges,1,1e7,0,ok\n"
           "spring,regular,cross,0,10,0,ok\nspring,regular,cross,0,1e4,0,ok\nspring,regular,cross,0,1e7,0,ok\n",
           l1_head);
  put("locking.csv", csv);
  cr_assert_eq(decide(cb_check_L1), CB_NOT_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.reason, "largest deviation from 90 deg is 90.0 deg"), "%s", last.reason);
  /* along the edges alone: hanging at 84 deg is more than 5 deg off even though it never changes */
  snprintf(csv, sizeof csv,
           "%sfem,regular,edges,1,10,84,ok\nfem,regular,edges,1,1e7,84,ok\n"
           "fem,regular,cross,0,10,85,ok\nfem,regular,cross,0,1e4,40,ok\nfem,regular,cross,0,1e7,5,ok\n",
           l1_head);
  put("locking.csv", csv);
  cr_assert_eq(decide(cb_check_L1), CB_PARTLY, "%s", last.reason);
}

/* Failure mode 2: across mesh lines the angle falls from the first to the last k by more than 20 deg
 * but rises on the way (the quick run's spring, regular, angle30: 91.3 -> 76.6 -> 52.7 -> 67.0), which
 * the old endpoint rule passed. */
Test(claims_locking, L1_not_as_predicted_when_the_angle_rises_at_a_step) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "spring,regular,edges,1,10,90,ok\nspring,regular,edges,1,1e7,90,ok\n"
           "spring,regular,angle30,0,10,91.3,ok\nspring,regular,angle30,0,1e3,76.6,ok\nspring,regular,angle30,0,1e5,52."
           "7,ok\n"
           "spring,regular,angle30,0,1e7,67.0,ok\n",
           l1_head);
  put("locking.csv", csv);
  cr_assert_eq(decide(cb_check_L1), CB_PARTLY, "%s", last.reason); /* 1 of 2 cases */
  cr_expect(strstr(last.numbers, "fall 24.3, smallest step -14.3 | not as predicted"), "%s", last.numbers);
  cr_expect(strstr(last.reason, "1 cases rise at some step"), "%s", last.reason);
}

static const char *dofs_head = "# "
                               "test\nmesh,vertices,boundary_edges,conforming_dofs,conforming_predicted,conforming_per_"
                               "vertex,"
                               "nonconforming_dofs,nonconforming_predicted,nonconforming_per_vertex\n";

Test(claims_locking, L2_reproduced_when_conforming_vanishes_and_nonconforming_keeps_three) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "grid_3x3_regular,9,8,11,11,1.222,24,24,2.667\ngrid_8x8_regular,64,28,31,31,0.484,189,189,2.953\n"
           "ring_disk_1,8,7,10,10,1.25,21,21,2.625\nring_disk_3,41,20,23,23,0.561,120,120,2.927\n",
           dofs_head);
  put("locking.csv", l1_head);
  put("locking_dofs.csv", csv);
  cr_assert_eq(decide(cb_check_L2), CB_REPRODUCED);
}

Test(claims_locking, L2_not_reproduced_when_nonconforming_loses_its_dofs) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "grid_3x3_regular,9,8,11,11,1.222,12,24,1.333\ngrid_8x8_regular,64,28,31,31,0.484,40,189,0.625\n",
           dofs_head);
  put("locking.csv", l1_head);
  put("locking_dofs.csv", csv);
  cr_assert_eq(decide(cb_check_L2), CB_NOT_REPRODUCED);
}

static const char *aniso_head = "# test\nmodel,mesh,family,dir_deg,energy_density_j_per_m2,status\n";

/* rows of one model on one mesh: the energies of the stretch load at 0, 45, 90, 135 deg and of the shear load (all ok)
 */
static void aniso_rows(char *buf, size_t n, const char *model, const char *mesh, const double *st, const double *sh) {
  size_t u = strlen(buf);
  for (int d = 0; d < 4; d++)
    u += (size_t)snprintf(buf + u, n - u, "%s,%s,stretch,%d,%g,ok\n%s,%s,shear,%d,%g,ok\n", model, mesh, 45 * d, st[d],
                          model, mesh, 45 * d, sh[d]);
}

static void put_newton(void) {
  put("locking_newton.csv", "# t\nmodel,rep,iter,rel_grad\nfem,0,0,1\nfem,0,1,1e-2\nfem,0,2,1e-4\nfem,0,3,1e-8\n"
                            "fem_frozen,0,0,1\nfem_frozen,0,1,0.5\nfem_frozen,0,2,0.25\nfem_frozen,0,3,0.125\n");
  /* three interleaved rounds: fem 10, 12, 9 ms and spring 5, 4, 6 ms: medians 10 and 5, spreads 9-12 and 4-6;
   * fem_frozen stops at its iteration cap */
  put("locking_newton_steps.csv", "# t\nmodel,n,rep,newton_iters,factorizations,rel_grad,step_wall_ms,status\n"
                                  "fem,64,0,3,3,1e-8,10,ok\nspring,64,0,3,3,1e-8,5,ok\nfem_frozen,64,0,300,0,3e-3,90,"
                                  "max_iters\n"
                                  "fem,64,1,3,3,1e-8,12,ok\nspring,64,1,3,3,1e-8,4,ok\nfem_frozen,64,1,300,0,3e-3,91,"
                                  "max_iters\n"
                                  "fem,64,2,3,3,1e-8,9,ok\nspring,64,2,3,3,1e-8,6,ok\nfem_frozen,64,2,300,0,3e-3,92,"
                                  "max_iters\n");
}

Test(claims_locking, F1_reproduced_when_fem_is_isotropic_and_springs_are_not) {
  static const double sp_st[4] = {2.0, 3.2, 2.0, 0.7}, sp_sh[4] = {1, 1.1, 1, 0.9}, fe_st[4] = {2.5, 2.51, 2.5, 2.49},
                      fe_sh[4] = {1.2, 1.21, 1.2, 1.19}, fe_st2[4] = {2.52, 2.53, 2.52, 2.51};
  char csv[4096] = "";
  aniso_rows(csv, sizeof csv, "spring", "regular", sp_st, sp_sh);
  aniso_rows(csv, sizeof csv, "fem", "regular", fe_st, fe_sh);
  aniso_rows(csv, sizeof csv, "fem", "disk", fe_st2, fe_sh);
  char all[5000];
  snprintf(all, sizeof all, "%s%sfem,disk,shear,10,99,max_iters\n", aniso_head,
           csv); /* an unconverged solve is left out */
  put("locking.csv", l1_head);
  put("locking_aniso.csv", all);
  put_newton();
  cr_assert_eq(decide(cb_check_F1), CB_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.numbers, "| spring | regular | 4.5714 | 1.2222 |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "median of 3 runs"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "| fem | 3 | 3 | 1.00e-08 | 10 (9-12) |"), "%s", last.numbers);
  cr_expect(strstr(last.numbers, "| spring | 3 | 3 | 1.00e-08 | 5 (4-6) |"), "%s", last.numbers);
  cr_expect(strstr(last.reason, "order 2.00, 10 (9-12) ms, converged"), "%s", last.reason);
  /* every run's convergence status is in the verdict text */
  cr_expect(strstr(last.reason, "fem_frozen 300 iterations, 0 factorisations, order 1.00, 91 (90-92) ms, not converged "
                                "(max_iters at rel. grad 3.0e-03)"),
            "%s", last.reason);
  cr_expect(strstr(last.reason, "1 static solves did not converge"), "%s", last.reason);
}

/* FEM as anisotropic as the springs (the same energies on the regular grid): not reproduced, although
 * the springs' ratio passes its own threshold. */
Test(claims_locking, F1_not_reproduced_when_fem_is_as_anisotropic_as_springs) {
  static const double st[4] = {2.0, 3.2, 2.0, 0.7}, sh[4] = {1, 1.1, 1, 0.9};
  char csv[4096] = "";
  aniso_rows(csv, sizeof csv, "spring", "regular", st, sh);
  aniso_rows(csv, sizeof csv, "fem", "regular", st, sh);
  char all[5000];
  snprintf(all, sizeof all, "%s%s", aniso_head, csv);
  put("locking.csv", l1_head);
  put("locking_aniso.csv", all);
  cr_assert_eq(decide(cb_check_F1), CB_NOT_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.reason, "FEM is not less anisotropic than springs"), "%s", last.reason);
  /* FEM isotropic over directions but 20% apart across meshes: only partly */
  static const double fa[4] = {2.5, 2.5, 2.5, 2.5}, fb[4] = {3.0, 3.0, 3.0, 3.0};
  csv[0] = 0;
  aniso_rows(csv, sizeof csv, "spring", "regular", st, sh);
  aniso_rows(csv, sizeof csv, "fem", "regular", fa, fa);
  aniso_rows(csv, sizeof csv, "fem", "disk", fb, fb);
  snprintf(all, sizeof all, "%s%s", aniso_head, csv);
  put("locking_aniso.csv", all);
  cr_assert_eq(decide(cb_check_F1), CB_PARTLY, "%s", last.reason);
  cr_expect(strstr(last.reason, "its largest spread across the meshes 1.2000"), "%s", last.reason);
}

static const char *shape_head = "# "
                                "test\nscene,method,alpha,dt_s,class,final_energy_ratio,max_strain,rigid_dist_over_"
                                "size\n";

Test(claims_locking, S1_reproduced_when_every_shape_matching_cell_keeps_energy_and_shape_bounded) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "cloth21,spring_explicit,,0.001,stable,0,0.01,0.001\ncloth21,spring_explicit,,0.1,diverged,1e9,1e6,nan\n"
           "cloth21,shape_matching,0.01,0.001,stable,-0.1,0.2,0.05\ncloth21,shape_matching,0.01,0.1,stable,-10,0.9,0."
           "4\n"
           "cloth21,shape_matching,1,0.1,stable,0,0.05,0.01\n",
           shape_head);
  put("locking.csv", l1_head);
  put("locking_shape.csv", csv);
  cr_assert_eq(decide(cb_check_S1), CB_REPRODUCED, "%s", last.reason);
  cr_expect(strstr(last.reason, "3 of 3 (alpha, dt) cells stable"), "%s", last.reason);
}

/* The old rule counted only diverged cells: energy-stable cells whose edges grew 5.3e3-fold (the
 * full run's chain at alpha = 0.01) and energy-unstable cells passed. Both now count against. */
Test(claims_locking, S1_not_reproduced_when_the_shape_error_is_unbounded_though_the_energy_is_not) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "chain20,spring_explicit,,0.001,stable,0,0.01,0.001\nchain20,spring_explicit,,0.1,diverged,1e9,1e10,nan\n"
           "chain20,shape_matching,0.01,0.001,stable,-0.1,0.3,0.1\nchain20,shape_matching,0.01,0.1,stable,-0.2,5.3e3,"
           "12\n",
           shape_head);
  put("locking.csv", l1_head);
  put("locking_shape.csv", csv);
  cr_assert_eq(decide(cb_check_S1), CB_NOT_REPRODUCED, "%s", last.reason); /* 1 of 2 stable, as springs */
  cr_expect(strstr(last.reason, "1 with an unbounded shape error"), "%s", last.reason);
  /* the rigid-fit distance alone decides too: edges at rest length, the shape far from any rigid motion */
  snprintf(csv, sizeof csv,
           "%schain20,spring_explicit,,0.1,stable,0,0.01,0.001\n"
           "chain20,shape_matching,1,0.1,stable,0,0.5,0.8\n",
           shape_head);
  put("locking_shape.csv", csv);
  cr_assert_eq(decide(cb_check_S1), CB_NOT_REPRODUCED, "%s", last.reason);
  /* an energy-unstable cell counts against; more stable than springs is only partly */
  snprintf(csv, sizeof csv,
           "%schain20,spring_explicit,,0.1,diverged,1e9,1e10,nan\nchain20,spring_explicit,,0.01,stable,0,0.01,0.01\n"
           "chain20,shape_matching,1,0.1,unstable,2,0.5,0.1\nchain20,shape_matching,1,0.01,stable,0,0.1,0.01\n"
           "chain20,shape_matching,1,0.001,stable,0,0.1,0.01\n",
           shape_head);
  put("locking_shape.csv", csv);
  cr_assert_eq(decide(cb_check_S1), CB_PARTLY, "%s", last.reason);
  cr_expect(strstr(last.reason, "1 energy-unstable"), "%s", last.reason);
}

Test(claims_locking, S1_not_reproduced_when_a_cell_diverges) {
  char csv[2048];
  snprintf(csv, sizeof csv,
           "%s"
           "cloth21,shape_matching,0.01,0.001,stable,-0.1,0.1,0.01\ncloth21,shape_matching,1,0.1,diverged,1e9,1e6,"
           "nan\n",
           shape_head);
  put("locking.csv", l1_head);
  put("locking_shape.csv", csv);
  cr_assert_eq(decide(cb_check_S1), CB_NOT_REPRODUCED);
  /* no shape matching cells at all: not run */
  snprintf(csv, sizeof csv, "%scloth21,spring_explicit,,0.1,diverged,1e9,1e6,nan\n", shape_head);
  put("locking_shape.csv", csv);
  cr_assert_eq(decide(cb_check_S1), CB_NOT_RUN);
}
