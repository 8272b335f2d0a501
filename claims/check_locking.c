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

/* max/min of energy_density over the ok rows of (model, mesh, family) (mesh or family NULL: any), over
 * every direction when dir is NaN, else at that direction only. */
static double ratio(const cb_table *a, const int *c, const char *model, const char *mesh, const char *family,
                    double dir) {
  double lo = INFINITY, hi = 0;
  for (int r = 0; r < a->nrows; r++) {
    if (!same(a, r, c[0], model) || (mesh && !same(a, r, c[1], mesh)) || (family && !same(a, r, c[2], family)))
      continue;
    if (!same(a, r, c[5], "ok") || (!isnan(dir) && cb_table_num(a, r, c[3]) != dir)) continue;
    double e = cb_table_num(a, r, c[4]);
    lo = fmin(lo, e);
    hi = fmax(hi, e);
  }
  return lo > 0 && isfinite(lo) ? hi / lo : NAN;
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
  int c[6];
  if (cb_claim_columns(&a, names, c, 6, "locking_aniso.csv", out)) {
    cb_table_free(&a);
    return;
  }
  static const char *const meshes[3] = {"regular", "alternating", "disk"}, *const fams[2] = {"stretch", "shear"};
  static const char *const models[2] = {"spring", "fem"};
  double dir_worst[2] = {0, 0},
         mesh_worst[2] = {0, 0}; /* per model: over meshes and loads / over loads and directions */
  int rows = 0, bad = 0, meshes_seen[2] = {0, 0};
  for (int r = 0; r < a.nrows; r++) bad += !same(&a, r, c[5], "ok");
  cb_claim_numbers(out, "Anisotropy of the response to non-affine loads (boundary of a disk held at X + u(X), 5%% "
                        "strain "
                        "at its largest): max/min of the energy per area over the load's directions, per mesh, and "
                        "across "
                        "the meshes at each direction (the largest over the directions).\n\n"
                        "| model | mesh | stretch: over directions | shear: over directions |\n|---|---|---|---|\n");
  for (int md = 0; md < 2; md++)
    for (int m = 0; m < 3; m++) {
      double rs = ratio(&a, c, models[md], meshes[m], fams[0], NAN),
             rh = ratio(&a, c, models[md], meshes[m], fams[1], NAN);
      if (!isfinite(rs) && !isfinite(rh)) continue;
      rows++;
      meshes_seen[md]++;
      cb_claim_numbers(out, "| %s | %s | %.4f | %.4f |\n", models[md], meshes[m], rs, rh);
      if (isfinite(rs)) dir_worst[md] = fmax(dir_worst[md], rs);
      if (isfinite(rh)) dir_worst[md] = fmax(dir_worst[md], rh);
    }
  cb_claim_numbers(out, "\n| model | stretch: across meshes | shear: across meshes |\n|---|---|---|\n");
  for (int md = 0; md < 2; md++) {
    double w[2] = {NAN, NAN};
    for (int fm = 0; fm < 2; fm++)
      for (int r = 0; r < a.nrows; r++) /* every direction of this model and load */
        if (same(&a, r, c[0], models[md]) && same(&a, r, c[2], fams[fm])) {
          double x = ratio(&a, c, models[md], NULL, fams[fm], cb_table_num(&a, r, c[3]));
          if (isfinite(x)) w[fm] = isnan(w[fm]) ? x : fmax(w[fm], x);
        }
    for (int fm = 0; fm < 2; fm++)
      if (isfinite(w[fm])) mesh_worst[md] = fmax(mesh_worst[md], w[fm]);
    cb_claim_numbers(out, "| %s | %.4f | %.4f |\n", models[md], w[0], w[1]);
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
  if (rows == 0 || meshes_seen[0] == 0 || meshes_seen[1] == 0) {
    cb_claim_reason(out, "locking_aniso.csv lacks spring or FEM rows.");
    return;
  }
  /* FEM isotropic and mesh-independent; springs mesh-dependent; FEM less anisotropic than springs */
  int fem_ok = dir_worst[1] <= F1_FEM_MAX && mesh_worst[1] <= F1_FEM_MESH_MAX,
      spring_aniso = dir_worst[0] >= F1_SPRING_MIN;
  int fem_better = dir_worst[1] < dir_worst[0];
  out->verdict = !fem_better ? CB_NOT_REPRODUCED : fem_ok && spring_aniso ? CB_REPRODUCED : CB_PARTLY;
  cb_claim_reason(out,
                  "Under non-affine loads on %d meshes, FEM's largest anisotropy over the directions is %.4f "
                  "(isotropic if <= %.2f) and its largest spread across the meshes %.4f (mesh-independent if <= %.2f); "
                  "springs' are %.4f (direction-dependent if >= %.1f) and %.4f.%s",
                  meshes_seen[1], dir_worst[1], F1_FEM_MAX, mesh_worst[1], F1_FEM_MESH_MAX, dir_worst[0], F1_SPRING_MIN,
                  mesh_worst[0], fem_better ? "" : " FEM is not less anisotropic than springs.");
  if (bad) cb_claim_reason(out, " %d static solves did not converge and are left out.", bad);
  if (summary[0])
    cb_claim_reason(out,
                    " One Newton step (median wall time, in brackets the fastest and slowest run; the "
                    "status says whether it converged to rel. |grad F| 1e-12): %s.",
                    summary);
}

/* ---- S1 ------------------------------------------------------------------------ */

/* A cell is stable only if its energy class is `stable` and its shape error at the end is bounded:
 * every edge within S1_MAX_STRAIN of its rest length ((l - L)/L, 1 = doubled) and the RMS distance to
 * the best-fit rigid motion of the rest shape within S1_MAX_RIGID of the rest shape's RMS radius. */
#define S1_MAX_STRAIN 1.0
#define S1_MAX_RIGID 0.5

void cb_check_S1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)t;
  cb_table s;
  if (cb_claim_side_table(results_dir, "locking", "shape", &s, out)) return;
  static const char *const names[] = {
      "scene", "method", "alpha", "dt_s", "class", "final_energy_ratio", "max_strain", "rigid_dist_over_size"};
  int c[8];
  if (cb_claim_columns(&s, names, c, 8, "locking_shape.csv", out)) {
    cb_table_free(&s);
    return;
  }
  int sm_cells = 0, sm_stable = 0, sm_energy = 0, sm_shape = 0, sm_div = 0, sp_cells = 0, sp_stable = 0;
  double sm_worst_strain = 0, sm_worst_rigid = 0;
  int *done = calloc((size_t)s.nrows + 1, sizeof(int));
  cb_claim_numbers(out,
                   "A cell is stable only if its energy stays bounded (class `stable`) and its shape error at the end "
                   "is bounded too: max edge strain <= %.0f and distance to the best-fit rigid motion <= %.1f of the "
                   "rest shape's RMS radius.\n\n"
                   "| scene | method | alpha | cells | stable | energy unstable | shape unbounded | diverged | energy "
                   "drift "
                   "(median final ratio) | max edge strain at the largest dt | rigid-fit distance / size at the "
                   "largest "
                   "dt |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
                   S1_MAX_STRAIN, S1_MAX_RIGID);
  for (int r = 0; r < s.nrows; r++) {
    if (done[r]) continue;
    int n = 0, st = 0, un = 0, sh = 0, dv = 0;
    double drift[64], dtmax = -1, strain = NAN, rigid = NAN;
    int sm = same(&s, r, c[1], "shape_matching");
    for (int q = r; q < s.nrows; q++) {
      if (!same(&s, q, c[0], cb_table_str(&s, r, c[0])) || !same(&s, q, c[1], cb_table_str(&s, r, c[1])) ||
          !same(&s, q, c[2], cb_table_str(&s, r, c[2])))
        continue;
      done[q] = 1;
      const char *cls = cb_table_str(&s, q, c[4]);
      double e = cb_table_num(&s, q, c[6]), g = cb_table_num(&s, q, c[7]);
      int bounded = e <= S1_MAX_STRAIN && g <= S1_MAX_RIGID; /* NaN is unbounded */
      if (!strcmp(cls, "stable")) {
        if (bounded) st++;
        else sh++;
      } else if (!strcmp(cls, "unstable")) {
        un++;
      } else {
        dv++; /* diverged, failed, or anything else: not stable */
      }
      if (sm && !strcmp(cls, "stable")) {
        sm_worst_strain = fmax(sm_worst_strain, isfinite(e) ? e : INFINITY);
        sm_worst_rigid = fmax(sm_worst_rigid, isfinite(g) ? g : INFINITY);
      }
      if (n < 64) drift[n] = cb_table_num(&s, q, c[5]);
      n++;
      if (cb_table_num(&s, q, c[3]) > dtmax) {
        dtmax = cb_table_num(&s, q, c[3]);
        strain = e;
        rigid = g;
      }
    }
    int nd = n < 64 ? n : 64;
    for (int i = 1; i < nd; i++)
      for (int j = i; j > 0 && drift[j] < drift[j - 1]; j--) {
        double x = drift[j];
        drift[j] = drift[j - 1];
        drift[j - 1] = x;
      }
    if (sm) {
      sm_cells += n;
      sm_stable += st;
      sm_energy += un;
      sm_shape += sh;
      sm_div += dv;
    } else {
      sp_cells += n;
      sp_stable += st;
    }
    char alpha[32];
    snprintf(alpha, sizeof alpha, sm ? "%.3g" : "-", cb_table_num(&s, r, c[2]));
    cb_claim_numbers(out, "| %s | %s | %s | %d | %d | %d | %d | %d | %.3g | %.3g | %.3g |\n", cb_table_str(&s, r, c[0]),
                     cb_table_str(&s, r, c[1]), alpha, n, st, un, sh, dv, nd ? drift[nd / 2] : NAN, strain, rigid);
  }
  free(done);
  cb_table_free(&s);
  if (sm_cells == 0) {
    cb_claim_reason(out, "locking_shape.csv has no shape-matching cells.");
    return;
  }
  double fsm = (double)sm_stable / sm_cells, fsp = sp_cells ? (double)sp_stable / sp_cells : NAN;
  out->verdict = sm_stable == sm_cells ? CB_REPRODUCED : sp_cells && fsm > fsp ? CB_PARTLY : CB_NOT_REPRODUCED;
  cb_claim_reason(out,
                  "Shape matching: %d of %d (alpha, dt) cells stable (energy and shape error bounded: max edge strain "
                  "<= %.0f, rigid-fit distance <= %.1f of the size); %d energy-unstable, %d with an unbounded shape "
                  "error although their energy stayed bounded, %d diverged. Among the energy-stable cells the largest "
                  "edge strain is %.3g and the largest rigid-fit distance %.3g of the size. Springs under the same "
                  "explicit integrator: %d of %d cells stable (fraction %.2f against shape matching's %.2f).",
                  sm_stable, sm_cells, S1_MAX_STRAIN, S1_MAX_RIGID, sm_energy, sm_shape, sm_div, sm_worst_strain,
                  sm_worst_rigid, sp_stable, sp_cells, fsp, fsm);
  if (out->verdict == CB_PARTLY) cb_claim_reason(out, " Partly: more stable than springs, not unconditionally.");
}
