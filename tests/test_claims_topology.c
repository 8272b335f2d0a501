/* Verdict logic of claims/check_topology.c on small constructed CSVs. */
#define _DEFAULT_SOURCE
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "claims.h"
#include "support.h"


static const char *header = "# test\nkind,mesh,i,j,vertices,triangles,edges,boundary_edges,predicted_edges,"
                            "boundary_loops,components,free_dofs,predicted_dofs,status\n";

static cb_verdict decide(const char *rows, cb_claim_check check) {
  static cb_claim_result r;
  return test_decide_rows(check, header, rows, &r);
}

static const char *slide = "edge,lecture,0,1,,,,,,,,,,ok\nedge,lecture,0,3,,,,,,,,,,ok\nedge,lecture,0,4,,,,,,,,,,ok\n"
                           "edge,lecture,1,2,,,,,,,,,,ok\nedge,lecture,1,3,,,,,,,,,,ok\nedge,lecture,2,3,,,,,,,,,,ok\n"
                           "edge,lecture,3,4,,,,,,,,,,ok\npair,lecture,1,2,,,,,,,,,,ok\npair,lecture,0,1,,,,,,,,,,ok\n";

Test(claims_topology, T1_reproduced_on_the_slide_lists) { cr_assert_eq(decide(slide, cb_check_T1), CB_REPRODUCED); }

Test(claims_topology, T1_fails_on_wrong_order_or_missing_edge) {
  char rows[2048];
  snprintf(rows, sizeof rows, "%s", slide);
  char *p = strstr(rows, "pair,lecture,1,2");
  memcpy(p, "pair,lecture,0,1", 16); /* pairs now {0,1},{0,1} */
  cr_assert_eq(decide(rows, cb_check_T1), CB_NOT_REPRODUCED);
  const char *missing = "edge,lecture,0,1,,,,,,,,,,ok\nedge,lecture,0,3,,,,,,,,,,ok\npair,lecture,1,2,,,,,,,,,,ok\n"
                        "pair,lecture,0,1,,,,,,,,,,ok\n";
  cr_assert_eq(decide(missing, cb_check_T1), CB_NOT_REPRODUCED);
}

Test(claims_topology, T2_reproduced_when_counts_match_on_grids_and_irregular_disks) {
  const char *rows = "count,grid_3x3,,,9,8,16,8,16,1,1,11,11,ok\ncount,ring_disk_2,,,21,27,47,13,47,1,1,16,16,ok\n";
  cr_assert_eq(decide(rows, cb_check_T2), CB_REPRODUCED);
}

Test(claims_topology, T2_not_reproduced_when_euler_fails_and_partly_without_dofs) {
  const char *bad = "count,grid_3x3,,,9,8,17,8,16,1,1,11,11,ok\ncount,ring_disk_2,,,21,27,47,13,47,1,1,16,16,ok\n";
  cr_assert_eq(decide(bad, cb_check_T2), CB_NOT_REPRODUCED);
  const char *dofs = "count,grid_3x3,,,9,8,16,8,16,1,1,12,11,ok\ncount,ring_disk_2,,,21,27,47,13,47,1,1,16,16,ok\n";
  cr_assert_eq(decide(dofs, cb_check_T2), CB_PARTLY);
  const char *annulus_only = "count,annulus,,,16,16,32,16,29,2,1,16,19,ok\n"; /* not a disk: ignored */
  cr_assert_eq(decide(annulus_only, cb_check_T2), CB_NOT_RUN);
}
