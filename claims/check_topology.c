/* Checkers for T1 and T2 from results/topology.csv. */
#include <math.h>
#include <string.h>

#include "claims.h"


/* The lecture's slide: edges and neighbouring-triangle pairs, in this order. */
static const int want_edges[][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 3}, {2, 3}, {3, 4}};
static const int want_pairs[][2] = {{1, 2}, {0, 1}};

static int match(const cb_table *t, const char *kind, const int (*want)[2], int n, cb_claim_result *out) {
  int ck = cb_table_col(t, "kind"), cm = cb_table_col(t, "mesh"), ci = cb_table_col(t, "i"), cj = cb_table_col(t, "j");
  int k = 0, ok = 1;
  cb_claim_numbers(out, "- %s list:", kind);
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, ck), kind) || strcmp(cb_table_str(t, r, cm), "lecture")) continue;
    int i = cb_table_int(t, r, ci), j = cb_table_int(t, r, cj);
    cb_claim_numbers(out, " {%d,%d}", i, j);
    if (k >= n || want[k][0] != i || want[k][1] != j) ok = 0;
    k++;
  }
  cb_claim_numbers(out, " (%d entries; the slide has %d)\n", k, n);
  return ok && k == n;
}

void cb_check_T1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  if (cb_table_col(t, "kind") < 0 || cb_table_col(t, "i") < 0) {
    cb_claim_reason(out, "topology.csv lacks the kind/i/j columns.");
    return;
  }
  int e = match(t, "edge", want_edges, 7, out), p = match(t, "pair", want_pairs, 2, out);
  out->verdict = e && p ? CB_REPRODUCED : CB_NOT_REPRODUCED;
  cb_claim_reason(out, e && p ? "Sorting the edge triples gives exactly the slide's edge list and neighbour pairs, in "
                                "order."
                              : "The computed lists differ from the slide's (see above).");
}

void cb_check_T2(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  int ck = cb_table_col(t, "kind"), cm = cb_table_col(t, "mesh"), cv = cb_table_col(t, "vertices"),
      ce = cb_table_col(t, "edges"), cb = cb_table_col(t, "boundary_edges"), cp = cb_table_col(t, "predicted_edges"),
      cl = cb_table_col(t, "boundary_loops"), cc = cb_table_col(t, "components"), cd = cb_table_col(t, "free_dofs"),
      cq = cb_table_col(t, "predicted_dofs");
  if (ck < 0 || ce < 0 || cp < 0 || cd < 0 || cq < 0) {
    cb_claim_reason(out, "topology.csv lacks the count columns.");
    return;
  }
  int disks = 0, euler_ok = 0, dofs_ok = 0, irregular = 0;
  cb_claim_numbers(out, "| mesh | #V | #E | #B | 3#V-3-#B | DoFs (3#V - rank) | 3+#B "
                        "|\n|---|---|---|---|---|---|---|\n");
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, ck), "count")) continue;
    if (cb_table_num(t, r, cl) != 1 || cb_table_num(t, r, cc) != 1) continue; /* disks only */
    disks++;
    irregular += strncmp(cb_table_str(t, r, cm), "ring_disk", 9) == 0;
    euler_ok += cb_table_num(t, r, ce) == cb_table_num(t, r, cp);
    dofs_ok += cb_table_num(t, r, cd) == cb_table_num(t, r, cq);
    cb_claim_numbers(out, "| %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f |\n", cb_table_str(t, r, cm),
                     cb_table_num(t, r, cv), cb_table_num(t, r, ce), cb_table_num(t, r, cb), cb_table_num(t, r, cp),
                     cb_table_num(t, r, cd), cb_table_num(t, r, cq));
  }
  if (disks == 0) {
    cb_claim_reason(out, "No disk meshes in the data.");
    return;
  }
  int all = euler_ok == disks && dofs_ok == disks;
  out->verdict = all && irregular > 0 ? CB_REPRODUCED : euler_ok == disks ? CB_PARTLY : CB_NOT_REPRODUCED;
  cb_claim_reason(out,
                  "Euler's count holds on %d of %d disk meshes (%d irregular); the DoFs left with every edge rigid "
                  "equal 3 + #B on %d of %d.",
                  euler_ok, disks, irregular, dofs_ok, disks);
  if (irregular == 0) cb_claim_reason(out, " No unstructured mesh was counted.");
}
