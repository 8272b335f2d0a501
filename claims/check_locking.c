/* Checkers for L1, L2, F1 and S1 from results/locking.csv and its side tables
 * locking_dofs.csv (L2), locking_aniso.csv, locking_newton.csv and
 * locking_newton_steps.csv (F1) and locking_shape.csv (S1). The rules are in
 * docs/experiments/locking.md. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"


#define L1_MIN_FALL 20.0     /* deg: across mesh lines the fold angle falls at least this much over the sweep, */
                             /* and at every step of k */
#define L1_FREE_FOLD 90.0    /* deg: a free fold's angle, the flap hanging straight down (centroid below the line) */
#define L1_MAX_DEV 5.0       /* deg: along mesh edges the angle stays within this of the free fold's at every k */
#define L1_MIN_DECADES 4.0   /* converged k must span at least this many decades to judge a case */
#define L2_NC_MIN 2.5        /* nonconforming DoFs per vertex on the largest mesh of each family, at least */
#define L2_C_MAX 0.6         /* conforming DoFs per vertex on the largest mesh, at most */
#define F1_FEM_MAX 1.05      /* FEM: max/min energy over the directions of a non-affine load, at most */
#define F1_FEM_MESH_MAX 1.10 /* FEM: max/min energy across the three meshes at one direction, at most */
#define F1_SPRING_MIN 1.2    /* springs: anisotropy over the directions, on some mesh, at least */
#define F1_ROUNDOFF 1e-10    /* rel_grad above this counts for the convergence order */
#define F1_MIN_ORDER 0.5     /* FEM tends to 1: (anisotropy - 1) ~ h^q with q at least this over the ladder */
enum { F1_MAXLEV = 8 };      /* refinement levels read at most */

static int same(const cb_table *t, int r, int c, const char *s) { return strcmp(cb_table_str(t, r, c), s) == 0; }

/* ---- L1 ------------------------------------------------------------------------ */

void cb_check_L1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  static const char *const names[] = {"model", "mesh", "fold", "on_edges", "k_n_per_m", "fold_angle_deg", "status"};
  int c[7];
  if (cb_claim_columns(t, names, c, 7, "locking.csv", out)) return;
  int *done = calloc((size_t)t->nrows + 1, sizeof(int));
  double *ks = malloc(((size_t)t->nrows + 1) * sizeof(double)), *as = malloc(((size_t)t->nrows + 1) * sizeof(double));
  int judged = 0, pass = 0, across = 0, along = 0, unconverged = 0, skipped = 0, rises = 0, stuck = 0;
  double min_fall = INFINITY, min_step = INFINITY, max_dev = 0; /* over the judged cases across / along mesh lines */
  cb_claim_numbers(out, "| model | mesh | fold line | along mesh edges | k range (N/m) | angle by k, low to high (deg) "
                        "| "
                        "deciding number | verdict |\n|---|---|---|---|---|---|---|---|\n");
  for (int r = 0; r < t->nrows; r++) {
    if (done[r]) continue;
    int on = cb_table_int(t, r, c[3]), n = 0;
    for (int q = r; q < t->nrows; q++) { /* the case: same model, mesh, fold; its converged (k, angle), sorted by k */
      if (!same(t, q, c[0], cb_table_str(t, r, c[0])) || !same(t, q, c[1], cb_table_str(t, r, c[1])) ||
          !same(t, q, c[2], cb_table_str(t, r, c[2])))
        continue;
      done[q] = 1;
      if (!same(t, q, c[6], "ok")) {
        unconverged++;
        continue;
      }
      double k = cb_table_num(t, q, c[4]), a = cb_table_num(t, q, c[5]);
      int p = n++;
      for (; p > 0 && ks[p - 1] > k; p--) {
        ks[p] = ks[p - 1];
        as[p] = as[p - 1];
      }
      ks[p] = k;
      as[p] = a;
    }
    char angles[256] = "";
    for (int q = 0; q < n; q++) {
      size_t u = strlen(angles);
      if (u < sizeof angles - 1) snprintf(angles + u, sizeof angles - u, "%s%.1f", q ? ", " : "", as[q]);
    }
    double dev = 0, step = INFINITY; /* along: max |angle - free fold|; across: smallest fall between neighbouring k */
    for (int q = 0; q < n; q++) dev = fmax(dev, fabs(as[q] - L1_FREE_FOLD));
    for (int q = 1; q < n; q++) step = fmin(step, as[q - 1] - as[q]);
    int ok_range = n >= 2 && ks[n - 1] / ks[0] >= pow(10.0, L1_MIN_DECADES);
    const char *v = "not judged";
    char decide[96] = "-";
    if (ok_range) {
      judged++;
      double fall = as[0] - as[n - 1];
      int p = on ? dev <= L1_MAX_DEV : fall >= L1_MIN_FALL && step > 0;
      if (on) {
        max_dev = fmax(max_dev, dev);
        stuck += !p;
        snprintf(decide, sizeof decide, "largest deviation from %.0f: %.1f", L1_FREE_FOLD, dev);
      } else {
        min_fall = fmin(min_fall, fall);
        min_step = fmin(min_step, step);
        rises += step <= 0;
        snprintf(decide, sizeof decide, "fall %.1f, smallest step %.1f", fall, step);
      }
      pass += p;
      across += !on;
      along += on;
      v = p ? "as predicted" : "not as predicted";
    } else {
      skipped++;
    }
    cb_claim_numbers(out, "| %s | %s | %s | %s | %.0e-%.0e | %s | %s | %s |\n", cb_table_str(t, r, c[0]),
                     cb_table_str(t, r, c[1]), cb_table_str(t, r, c[2]), on ? "yes" : "no", n ? ks[0] : NAN,
                     n ? ks[n - 1] : NAN, angles, decide, v);
  }
  free(done);
  free(ks);
  free(as);
  if (judged == 0) {
    cb_claim_reason(out, "No case has converged rest states over %.0f decades of stiffness.", L1_MIN_DECADES);
    return;
  }
  out->verdict = pass == judged && across > 0 && along > 0 ? CB_REPRODUCED
                 : 2 * pass >= judged                      ? CB_PARTLY
                                                           : CB_NOT_REPRODUCED;
  cb_claim_reason(out,
                  "%d of %d cases as predicted: across mesh lines (%d cases) the fold angle must fall at every step of "
                  "stiffness and by at least %.0f deg in all; along mesh edges (%d cases) it must stay within %.0f deg "
                  "of the free fold's %.0f deg (the flap hangs straight down) at every stiffness. Across mesh lines "
                  "the "
                  "smallest total fall is %.1f deg and the smallest single step %.1f deg (%d cases rise at some step); "
                  "along mesh edges the largest deviation from %.0f deg is %.1f deg (%d cases off).",
                  pass, judged, across, L1_MIN_FALL, along, L1_MAX_DEV, L1_FREE_FOLD, across ? min_fall : NAN,
                  across ? min_step : NAN, rises, L1_FREE_FOLD, max_dev, stuck);
  if (unconverged) cb_claim_reason(out, " %d static solves did not converge and are left out.", unconverged);
  if (skipped) cb_claim_reason(out, " %d cases lacked converged solves over %.0f decades.", skipped, L1_MIN_DECADES);
}

/* ---- L2 ------------------------------------------------------------------------ */

void cb_check_L2(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)t;
  cb_table d;
  if (cb_claim_side_table(results_dir, "locking", "dofs", &d, out)) return;
  static const char *const names[] = {"mesh",
                                      "vertices",
                                      "boundary_edges",
                                      "conforming_dofs",
                                      "conforming_predicted",
                                      "conforming_per_vertex",
                                      "nonconforming_dofs",
                                      "nonconforming_predicted",
                                      "nonconforming_per_vertex"};
  int c[9];
  if (cb_claim_columns(&d, names, c, 9, "locking_dofs.csv", out)) {
    cb_table_free(&d);
    return;
  }
  static const char *const fam[3] = {"_regular", "_alternating", "ring_disk"};
  int exact_c = 0, exact_nc = 0, n = 0, fam_ok = 0, fams = 0;
  double worst_c = 0, worst_nc = INFINITY; /* on the largest mesh of each family */
  cb_claim_numbers(out, "| mesh | #V | #B | conforming DoFs (3+#B) | per vertex | nonconforming DoFs (3#V-3) | per "
                        "vertex |\n"
                        "|---|---|---|---|---|---|---|\n");
  for (int r = 0; r < d.nrows; r++) {
    n++;
    exact_c += cb_table_num(&d, r, c[3]) == cb_table_num(&d, r, c[4]);
    exact_nc += cb_table_num(&d, r, c[6]) == cb_table_num(&d, r, c[7]);
    cb_claim_numbers(out, "| %s | %.0f | %.0f | %.0f (%.0f) | %.3f | %.0f (%.0f) | %.3f |\n", cb_table_str(&d, r, c[0]),
                     cb_table_num(&d, r, c[1]), cb_table_num(&d, r, c[2]), cb_table_num(&d, r, c[3]),
                     cb_table_num(&d, r, c[4]), cb_table_num(&d, r, c[5]), cb_table_num(&d, r, c[6]),
                     cb_table_num(&d, r, c[7]), cb_table_num(&d, r, c[8]));
  }
  for (int f = 0; f < 3; f++) { /* per family: conforming per vertex falls with size; on the largest, the limits */
    double prev_v = -1, prev_c = INFINITY, last_c = NAN, last_nc = NAN;
    int mono = 1, rows = 0;
    for (int r = 0; r < d.nrows; r++) {
      if (!strstr(cb_table_str(&d, r, c[0]), fam[f])) continue;
      double v = cb_table_num(&d, r, c[1]), cp = cb_table_num(&d, r, c[5]);
      if (v <= prev_v) continue;
      mono &= cp < prev_c;
      prev_v = v;
      prev_c = cp;
      last_c = cp;
      last_nc = cb_table_num(&d, r, c[8]);
      rows++;
    }
    if (rows < 2) continue;
    fams++;
    int ok = mono && last_c <= L2_C_MAX && last_nc >= L2_NC_MIN;
    worst_c = fmax(worst_c, last_c);
    worst_nc = fmin(worst_nc, last_nc);
    fam_ok += ok;
    cb_claim_numbers(out,
                     "\n- %s meshes: conforming DoFs per vertex %s with size, %.3f on the largest; nonconforming %.3f.",
                     f == 2 ? "ring disk" : fam[f] + 1, mono ? "fall" : "do not fall", last_c, last_nc);
  }
  cb_claim_numbers(out, "\n");
  cb_table_free(&d);
  if (n == 0 || fams == 0) {
    cb_claim_reason(out, "locking_dofs.csv has no mesh families to compare.");
    return;
  }
  out->verdict = fam_ok == fams ? CB_REPRODUCED : fam_ok > 0 ? CB_PARTLY : CB_NOT_REPRODUCED;
  cb_claim_reason(out,
                  "Conforming DoFs equal 3 + #B on %d of %d meshes and nonconforming ones 3#V - 3 on %d of %d; in %d "
                  "of %d "
                  "mesh families the conforming DoFs per vertex fall with size to at most %.1f while the nonconforming "
                  "ones reach at least %.1f (on the largest meshes: conforming at most %.3f, nonconforming at least "
                  "%.3f per vertex).",
                  exact_c, n, exact_nc, n, fam_ok, fams, L2_C_MAX, L2_NC_MIN, worst_c, worst_nc);
}

/* ---- F1 ------------------------------------------------------------------------ */

/* max/min of energy_density over the ok rows of (model, mesh, family) (mesh or family NULL: any) at level n
 * (column c[6], the grid's vertices per side; NaN or no column: any), over every direction when dir is NaN,
 * else at that direction only. */
static double ratio(const cb_table *a, const int *c, const char *model, const char *mesh, const char *family,
                    double dir, double n) {
  double lo = INFINITY, hi = 0;
  for (int r = 0; r < a->nrows; r++) {
    if (!same(a, r, c[0], model) || (mesh && !same(a, r, c[1], mesh)) || (family && !same(a, r, c[2], family)))
      continue;
    if (!same(a, r, c[5], "ok") || (!isnan(dir) && cb_table_num(a, r, c[3]) != dir)) continue;
    if (c[6] >= 0 && !isnan(n) && cb_table_num(a, r, c[6]) != n) continue;
    double e = cb_table_num(a, r, c[4]);
    lo = fmin(lo, e);
    hi = fmax(hi, e);
  }
  return lo > 0 && isfinite(lo) ? hi / lo : NAN;
}

/* The anisotropy of (model, mesh) at level n: the larger over the two loads of max/min over the directions. */
static double aniso_at(const cb_table *a, const int *c, const char *model, const char *mesh, double n) {
  double x = ratio(a, c, model, mesh, "stretch", NAN, n), y = ratio(a, c, model, mesh, "shear", NAN, n);
  return isnan(x) ? y : isnan(y) ? x : fmax(x, y);
}

/* The spread of model across the meshes at level n: max/min over the meshes at one direction and load, the
 * largest over the directions and loads. */
static double mesh_spread_at(const cb_table *a, const int *c, const char *model, double n) {
  static const char *const fams[2] = {"stretch", "shear"};
  double w = NAN;
  for (int fm = 0; fm < 2; fm++)
    for (int r = 0; r < a->nrows; r++)
      if (same(a, r, c[0], model) && same(a, r, c[2], fams[fm]) &&
          (c[6] < 0 || isnan(n) || cb_table_num(a, r, c[6]) == n)) {
        double x = ratio(a, c, model, NULL, fams[fm], cb_table_num(a, r, c[3]), n);
        if (isfinite(x)) w = isnan(w) ? x : fmax(w, x);
      }
  return w;
}

/* Convergence order at the last triple of rel_grad above round-off in the rep-0 trace of method m. */
static double conv_order(const cb_table *nt, const int *c, const char *m, double *rate) {
  double e[3] = {NAN, NAN, NAN};
  int k = 0;
  *rate = NAN;
  double order = NAN;
  for (int r = 0; r < nt->nrows; r++) {
    if (!same(nt, r, c[0], m) || cb_table_num(nt, r, c[1]) != 0) continue;
    double g = cb_table_num(nt, r, c[3]);
    if (!(g > F1_ROUNDOFF) || cb_table_num(nt, r, c[2]) == 0) continue; /* skip the initial guess (rel_grad = 1) */
    e[0] = e[1];
    e[1] = e[2];
    e[2] = g;
    if (++k >= 3) {
      order = log(e[2] / e[1]) / log(e[1] / e[0]);
      *rate = e[2] / e[1];
    }
  }
  return order;
}

/* "converged" or "not converged (STATUS at rel. grad G)" for a step's status and final rel_grad. */
static const char *conv_status(const char *status, double rel_grad, char *buf, size_t n) {
  if (!strcmp(status, "ok")) snprintf(buf, n, "converged");
  else snprintf(buf, n, "not converged (%s at rel. grad %.1e)", status, rel_grad);
  return buf;
}

void cb_check_F1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)t;
  cb_table a;
  if (cb_claim_side_table(results_dir, "locking", "aniso", &a, out)) return;
  static const char *const names[] = {"model", "mesh", "family", "dir_deg", "energy_density_j_per_m2", "status"};
  int c[7];
  if (cb_claim_columns(&a, names, c, 6, "locking_aniso.csv", out)) {
    cb_table_free(&a);
    return;
  }
  c[6] = cb_table_col(&a, "n"); /* the refinement level; a CSV without it has one level */
  static const char *const meshes[3] = {"regular", "alternating", "disk"};
  static const char *const models[2] = {"spring", "fem"};
  /* the levels, ascending */
  double lv[F1_MAXLEV];
  int nlev = 0, bad = 0;
  for (int r = 0; r < a.nrows; r++) {
    bad += !same(&a, r, c[5], "ok");
    double n = c[6] >= 0 ? cb_table_num(&a, r, c[6]) : NAN;
    int seen = 0;
    for (int l = 0; l < nlev; l++) seen |= lv[l] == n || (isnan(n) && isnan(lv[l]));
    if (seen || nlev == F1_MAXLEV) continue;
    int p = nlev++;
    for (; p > 0 && lv[p - 1] > n; p--) lv[p] = lv[p - 1];
    lv[p] = n;
  }
  /* per (model, mesh): anisotropy at every level, and the order q of (anisotropy - 1) ~ h^q (h ~ 1/(n - 1)) */
  double an[2][3][F1_MAXLEV], qh[2][3], fine_dir[2] = {0, 0}, fine_mesh[2] = {NAN, NAN};
  int seen[2][3], meshes_seen[2] = {0, 0}, fem_to1 = 0, fem_meshes = 0, spring_stays = 0;
  char lvtxt[64] = "";
  for (int l = 0; l < nlev; l++) {
    size_t u = strlen(lvtxt);
    snprintf(lvtxt + u, sizeof lvtxt - u, "%s%.0f", l ? ", " : "", lv[l]);
  }
  cb_claim_numbers(out,
                   "Anisotropy of the response to non-affine loads (boundary of a disk held at X + u(X), 5%% strain at "
                   "its largest): max/min of the energy per area over the load's directions, the larger of the two "
                   "loads, per mesh and refinement level n (grids of n^2 clipped to the disk, ring disks of (n - 1)/2 "
                   "rings: spacing h = 1/(n - 1) m); q is the fitted order of (anisotropy - 1) ~ h^q over the ladder "
                   "(n = %s).\n\n| model | mesh |",
                   nlev > 0 ? lvtxt : "-");
  for (int l = 0; l < nlev; l++) cb_claim_numbers(out, " n = %.0f |", lv[l]);
  cb_claim_numbers(out, " q | tends to 1 |\n|---|---|");
  for (int l = 0; l < nlev + 2; l++) cb_claim_numbers(out, "---|");
  cb_claim_numbers(out, "\n");
  for (int md = 0; md < 2; md++)
    for (int m = 0; m < 3; m++) {
      seen[md][m] = 0;
      int falls = 1, np = 0;
      double lx[F1_MAXLEV], ly[F1_MAXLEV];
      for (int l = 0; l < nlev; l++) {
        an[md][m][l] = aniso_at(&a, c, models[md], meshes[m], lv[l]);
        if (!isfinite(an[md][m][l])) continue;
        seen[md][m]++;
        if (l > 0 && isfinite(an[md][m][l - 1])) falls &= an[md][m][l] - 1 < an[md][m][l - 1] - 1;
        if (an[md][m][l] > 1 && lv[l] > 1) {
          lx[np] = log(1.0 / (lv[l] - 1));
          ly[np++] = log(an[md][m][l] - 1);
        }
      }
      if (!seen[md][m]) continue;
      meshes_seen[md]++;
      double b0;
      qh[md][m] = NAN;
      if (np >= 2) cb_fit_line(lx, ly, np, &qh[md][m], &b0);
      double fine = an[md][m][nlev - 1];
      if (!isfinite(fine)) continue;
      fine_dir[md] = fmax(fine_dir[md], fine);
      /* FEM tends to 1: the excess falls at every refinement, at least like h^F1_MIN_ORDER; springs stay: still
       * direction-dependent at the finest level with their excess not shrinking like that */
      int to1 = nlev >= 2 && seen[md][m] == nlev && falls && qh[md][m] >= F1_MIN_ORDER;
      if (md == 1) {
        fem_meshes++;
        fem_to1 += to1;
      } else spring_stays += nlev >= 2 && fine >= F1_SPRING_MIN && !(qh[md][m] >= F1_MIN_ORDER);
      cb_claim_numbers(out, "| %s | %s |", models[md], meshes[m]);
      for (int l = 0; l < nlev; l++) cb_claim_numbers(out, " %.4f |", an[md][m][l]);
      cb_claim_numbers(out, " %.2f | %s |\n", qh[md][m], nlev < 2 ? "-" : to1 ? "yes" : "no");
    }
  cb_claim_numbers(out, "\nSpread across the three meshes at one direction (max/min, the largest over directions and "
                        "loads), per level:\n\n| model |");
  for (int l = 0; l < nlev; l++) cb_claim_numbers(out, " n = %.0f |", lv[l]);
  cb_claim_numbers(out, "\n|---|");
  for (int l = 0; l < nlev; l++) cb_claim_numbers(out, "---|");
  cb_claim_numbers(out, "\n");
  for (int md = 0; md < 2; md++) {
    cb_claim_numbers(out, "| %s |", models[md]);
    for (int l = 0; l < nlev; l++) {
      double w = mesh_spread_at(&a, c, models[md], lv[l]);
      cb_claim_numbers(out, " %.4f |", w);
      if (l == nlev - 1) fine_mesh[md] = w;
    }
    cb_claim_numbers(out, "\n");
  }
  cb_table_free(&a);
  /* the Newton step: per method, iterations, time, convergence order */
  cb_table nt, ns;
  char summary[1024] = "";
  if (cb_claim_side_table(results_dir, "locking", "newton", &nt, out) == 0) {
    static const char *const nn[] = {"model", "rep", "iter", "rel_grad"};
    int cn[4];
    int have_steps = cb_claim_side_table(results_dir, "locking", "newton_steps", &ns, out) == 0;
    static const char *const sn[] = {"model", "newton_iters", "factorizations", "rel_grad", "step_wall_ms", "status",
                                     "n"};
    int cs[7];
    if (have_steps && cb_claim_columns(&ns, sn, cs, 7, "locking_newton_steps.csv", out)) {
      cb_table_free(&ns);
      have_steps = 0;
    }
    if (cb_claim_columns(&nt, nn, cn, 4, "locking_newton.csv", out) == 0 && have_steps) {
      int nrep = 0;
      for (int r = 0; r < ns.nrows; r++) nrep += same(&ns, r, cs[0], cb_table_str(&ns, 0, cs[0]));
      cb_claim_numbers(out,
                       "\nOne implicit Euler step of the lab cloth at %.0f^2 (to rel. |grad F| 1e-12 or 300 "
                       "iterations; "
                       "the methods timed in interleaved rounds, the step's wall time the median of %d runs, in "
                       "brackets "
                       "the fastest and slowest):\n\n| method | Newton iterations | factorisations | final rel. grad | "
                       "step wall "
                       "(ms) | order | last rate | status |\n|---|---|---|---|---|---|---|---|\n",
                       cb_table_num(&ns, 0, cs[6]), nrep);
      for (int r = 0; r < ns.nrows; r++) {
        if (cb_table_num(&ns, r, cb_table_col(&ns, "rep")) != 0) continue;
        const char *m = cb_table_str(&ns, r, cs[0]);
        cb_claim_timing w = cb_claim_timing_value(NAN); /* the repeats are the model's rows, in round order */
        w.n = 0;
        for (int q = 0; q < ns.nrows; q++)
          if (same(&ns, q, cs[0], m)) cb_timing_add(&w.each, cb_table_num(&ns, q, cs[4]));
        w.med = cb_timing_median(&w.each);
        w.min = cb_timing_min(&w.each);
        w.max = cb_timing_max(&w.each);
        w.n = w.each.n;
        char wt[96], st[96];
        double rate, order = conv_order(&nt, cn, m, &rate);
        size_t used = strlen(summary);
        if (used < sizeof summary - 1)
          snprintf(summary + used, sizeof summary - used,
                   "%s%s %.0f iterations, %.0f factorisations, order %.2f, %s ms, %s", used ? "; " : "", m,
                   cb_table_num(&ns, r, cs[1]), cb_table_num(&ns, r, cs[2]), order,
                   cb_claim_spread(wt, sizeof wt, "%.0f", &w, ""),
                   conv_status(cb_table_str(&ns, r, cs[5]), cb_table_num(&ns, r, cs[3]), st, sizeof st));
        cb_claim_numbers(out, "| %s | %.0f | %.0f | %.2e | %s | %.2f | %.3g | %s |\n", m, cb_table_num(&ns, r, cs[1]),
                         cb_table_num(&ns, r, cs[2]), cb_table_num(&ns, r, cs[3]),
                         cb_claim_spread(wt, sizeof wt, "%.0f", &w, ""), order, rate, cb_table_str(&ns, r, cs[5]));
      }
    }
    if (have_steps) cb_table_free(&ns);
    cb_table_free(&nt);
  }
  if (nlev == 0 || meshes_seen[0] == 0 || meshes_seen[1] == 0) {
    cb_claim_reason(out, "locking_aniso.csv lacks spring or FEM rows.");
    return;
  }
  int fem_better = fine_dir[1] < fine_dir[0];
  int fem_fine_ok = fine_dir[1] <= F1_FEM_MAX && fine_mesh[1] <= F1_FEM_MESH_MAX;
  if (nlev >= 2) {
    /* the ladder: FEM tends to 1 on every mesh and is isotropic and mesh-independent at the finest level,
     * springs do not on some mesh */
    out->verdict = !fem_better || fem_to1 == 0                                ? CB_NOT_REPRODUCED
                   : fem_to1 == fem_meshes && fem_fine_ok && spring_stays > 0 ? CB_REPRODUCED
                                                                              : CB_PARTLY;
    cb_claim_reason(out,
                    "On the refinement ladder n = %s (mesh spacing halved at each step), FEM's anisotropy tends to 1 "
                    "(its excess falls at every step, at least like h^%.1f) on %d of %d meshes, and at n = %.0f it is "
                    "%.4f at most (isotropic if <= %.2f) with a spread across the meshes of %.4f (mesh-independent if "
                    "<= %.2f); springs stay direction-dependent (>= %.1f at the finest level, excess not shrinking "
                    "like h^%.1f) on %d of %d meshes, %.4f at most at n = %.0f, spread across the meshes %.4f.%s",
                    lvtxt, F1_MIN_ORDER, fem_to1, fem_meshes, lv[nlev - 1], fine_dir[1], F1_FEM_MAX, fine_mesh[1],
                    F1_FEM_MESH_MAX, F1_SPRING_MIN, F1_MIN_ORDER, spring_stays, meshes_seen[0], fine_dir[0],
                    lv[nlev - 1], fine_mesh[0], fem_better ? "" : " FEM is not less anisotropic than springs.");
  } else {
    /* one level: no ladder, judged at that level */
    int spring_aniso = fine_dir[0] >= F1_SPRING_MIN;
    out->verdict = !fem_better ? CB_NOT_REPRODUCED : fem_fine_ok && spring_aniso ? CB_REPRODUCED : CB_PARTLY;
    cb_claim_reason(out,
                    "One refinement level only (no ladder: judged at that level). Under non-affine loads on %d "
                    "meshes, FEM's largest anisotropy over the directions is %.4f (isotropic if <= %.2f) and its "
                    "largest spread across the meshes %.4f (mesh-independent if <= %.2f); springs' are %.4f "
                    "(direction-dependent if >= %.1f) and %.4f.%s",
                    meshes_seen[1], fine_dir[1], F1_FEM_MAX, fine_mesh[1], F1_FEM_MESH_MAX, fine_dir[0], F1_SPRING_MIN,
                    fine_mesh[0], fem_better ? "" : " FEM is not less anisotropic than springs.");
  }
  if (bad) cb_claim_reason(out, " %d static solves did not converge and are left out.", bad);
  if (summary[0])
    cb_claim_reason(out,
                    " One Newton step (median wall time, in brackets the fastest and slowest run; the "
                    "status says whether it converged to rel. |grad F| 1e-12): %s.",
                    summary);
}

/* ---- S1 ------------------------------------------------------------------------ */

/* The experiment classifies each cell (experiments/locking/s1_shape.c): every cell runs the same
 * simulated time; `unstable` = the energy rose by more than the scale S, or the energy or shape error
 * grew faster than any power t^4 (exponential growth); `diverged` as in explicit_stability; `falling`
 * = energy bounded and growth a power of t, but the shape error at the end beyond its bounds (the cloth
 * falls from its pin or sags): not an instability; `stable` otherwise. Here a shape-matching cell is
 * compared with springs under symplectic Euler at the same (scene, dt). */
static int s1_ok(const char *cls) { return !strcmp(cls, "stable") || !strcmp(cls, "falling"); }

void cb_check_S1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)t;
  cb_table s;
  if (cb_claim_side_table(results_dir, "locking", "shape", &s, out)) return;
  static const char *const names[] = {
      "scene",      "method", "alpha", "dt_s", "class", "final_energy_ratio", "shape_growth_exponent",
      "sim_time_s", "t_end_s"};
  int c[9];
  if (cb_claim_columns(&s, names, c, 9, "locking_shape.csv", out)) {
    cb_table_free(&s);
    return;
  }
  int sm_cells = 0, sm_stable = 0, sm_falling = 0, sm_unstable = 0, sm_div = 0, sp_cells = 0, sp_stable = 0;
  int both = 0, sm_only = 0, sp_only = 0, neither = 0, unpaired = 0, short_runs = 0;
  double worst_exp = -INFINITY, T0 = NAN, Tlo = INFINITY, Thi = -INFINITY;
  int *done = calloc((size_t)s.nrows + 1, sizeof(int));
  cb_claim_numbers(out, "Every cell runs the same simulated time and is classified by how it grows: unstable if its "
                        "energy rose by more than the scale S or its energy or shape error grew faster than any power "
                        "t^4 over the second half of the run (exponential growth); falling if its energy stayed "
                        "bounded "
                        "and its shape error grew like a power of t but ended beyond its bounds (the cloth falls or "
                        "sags "
                        "from its pin: not an instability); diverged as in explicit_stability. Each shape-matching "
                        "cell "
                        "is compared with springs under symplectic Euler at the same (scene, dt).\n\n"
                        "| scene | method | alpha | cells | stable | falling | unstable | diverged | stable where "
                        "springs "
                        "are not | not stable where springs are | largest shape-growth exponent |\n"
                        "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int r = 0; r < s.nrows; r++) {
    double T = cb_table_num(&s, r, c[7]);
    Tlo = fmin(Tlo, T);
    Thi = fmax(Thi, T);
    if (isnan(T0)) T0 = T;
    /* a cell that stopped early must have diverged or failed */
    if (cb_table_num(&s, r, c[8]) + cb_table_num(&s, r, c[3]) / 2 < T && s1_ok(cb_table_str(&s, r, c[4])))
      short_runs++; /* (t_end is a whole number of steps: within half a step of T is the whole run) */
  }
  for (int r = 0; r < s.nrows; r++) {
    if (done[r]) continue;
    int n = 0, st = 0, fa = 0, un = 0, dv = 0, better = 0, worse = 0;
    double gexp = -INFINITY;
    int sm = same(&s, r, c[1], "shape_matching");
    for (int q = r; q < s.nrows; q++) {
      if (!same(&s, q, c[0], cb_table_str(&s, r, c[0])) || !same(&s, q, c[1], cb_table_str(&s, r, c[1])) ||
          !same(&s, q, c[2], cb_table_str(&s, r, c[2])))
        continue;
      done[q] = 1;
      const char *cls = cb_table_str(&s, q, c[4]);
      int ok = s1_ok(cls);
      n++;
      st += !strcmp(cls, "stable");
      fa += !strcmp(cls, "falling");
      un += !strcmp(cls, "unstable");
      dv += !ok && strcmp(cls, "unstable"); /* diverged, failed, or anything else: not stable */
      double g = cb_table_num(&s, q, c[6]);
      if (isfinite(g)) gexp = fmax(gexp, g);
      if (!sm) continue;
      int sp = -1; /* springs at the same (scene, dt): 1 stable, 0 not, -1 none */
      for (int u = 0; u < s.nrows; u++)
        if (same(&s, u, c[1], "spring_explicit") && same(&s, u, c[0], cb_table_str(&s, q, c[0])) &&
            cb_table_num(&s, u, c[3]) == cb_table_num(&s, q, c[3]))
          sp = s1_ok(cb_table_str(&s, u, c[4]));
      if (sp < 0) unpaired++;
      else if (ok && sp) both++;
      else if (ok) sm_only++, better++;
      else if (sp) sp_only++, worse++;
      else neither++;
    }
    if (sm) {
      sm_cells += n;
      sm_stable += st;
      sm_falling += fa;
      sm_unstable += un;
      sm_div += dv;
      worst_exp = fmax(worst_exp, gexp);
    } else {
      sp_cells += n;
      sp_stable += st + fa;
    }
    char alpha[32];
    snprintf(alpha, sizeof alpha, sm ? "%.3g" : "-", cb_table_num(&s, r, c[2]));
    char b1[16] = "-", b2[16] = "-";
    if (sm) {
      snprintf(b1, sizeof b1, "%d", better);
      snprintf(b2, sizeof b2, "%d", worse);
    }
    cb_claim_numbers(out, "| %s | %s | %s | %d | %d | %d | %d | %d | %s | %s | %.2f |\n", cb_table_str(&s, r, c[0]),
                     cb_table_str(&s, r, c[1]), alpha, n, st, fa, un, dv, b1, b2, gexp);
  }
  free(done);
  cb_table_free(&s);
  if (sm_cells == 0) {
    cb_claim_reason(out, "locking_shape.csv has no shape-matching cells.");
    return;
  }
  int sm_bad = sm_unstable + sm_div, sp_fail = sp_cells - sp_stable;
  if (sm_bad == 0) out->verdict = sp_fail > 0 ? CB_REPRODUCED : CB_PARTLY;
  else if (sp_only == 0 && sm_only > 0) out->verdict = CB_PARTLY;
  else out->verdict = CB_NOT_REPRODUCED;
  cb_claim_reason(out,
                  "Every cell ran %.3g s of simulated time%s. Shape matching: %d of %d (alpha, dt) cells stable "
                  "(%d of them falling or sagging from the pin with their energy bounded and their shape error "
                  "growing like a power of t, not exponentially), %d unstable, %d diverged; the largest "
                  "shape-growth exponent is %.2f (unstable above 4). Cell by cell against springs under the same "
                  "integrator (%d of %d stable): shape matching stable where springs are not in %d cells, not stable "
                  "where springs are in %d, both stable in %d, neither in %d.",
                  T0, Thi > Tlo * (1 + 1e-9) ? " (**not the same in every cell**)" : "", sm_stable + sm_falling,
                  sm_cells, sm_falling, sm_unstable, sm_div, worst_exp, sp_stable, sp_cells, sm_only, sp_only, both,
                  neither);
  if (unpaired) cb_claim_reason(out, " %d cells have no springs cell at their (scene, dt).", unpaired);
  if (short_runs) cb_claim_reason(out, " %d stable cells stopped before the simulated time.", short_runs);
  if (sm_bad == 0 && sp_fail == 0)
    cb_claim_reason(out, " Partly: springs are stable over the same range too, so it does not reach the explicit "
                         "limit and cannot show the difference.");
  else if (out->verdict == CB_PARTLY)
    cb_claim_reason(out, " Partly: at least as stable as springs in every cell and more stable in some, not "
                         "unconditionally.");
}
