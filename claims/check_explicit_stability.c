/* Checkers for E1, E2 and I1 from results/explicit_stability.csv and its side
 * tables explicit_stability_boundary.csv (E1) and explicit_stability_timing.csv
 * (E2). Every number below is computed here from those files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"

void cb_check_E1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_E2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_I1(const cb_table *t, const char *results_dir, cb_claim_result *out);

enum { MAXS = 16, MAXPTS = 4096 };

/* The tolerances the claims state. */
#define E1_RATIO_TOL 0.15  /* |dt_meas / dt_pred - 1| */
#define E1_SLOPE 0.5       /* -d log dt_crit / d log k */
#define E1_SLOPE_TOL 0.05
#define E2_K_EXP 0.5       /* explicit cost ~ k^(1/2): steps ~ 1/dt_crit */
#define E2_K_EXP_TOL 0.15
#define E2_N_EXP 2.0       /* Baraff-Witkin: explicit cost ~ n^2 */
#define E2_N_EXP_TOL 0.25
#define I1_MIN_EXP 0.25    /* energy lost per second ~ dt^p with p at least this: damping grows with dt */

static int find_name(char names[][32], int *n, const char *s) {
  for (int i = 0; i < *n; i++)
    if (!strcmp(names[i], s)) return i;
  if (*n == MAXS) return -1;
  snprintf(names[*n], 32, "%s", s);
  return (*n)++;
}

/* ---- E1 ------------------------------------------------------------------- */

void cb_check_E1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  cb_table b;
  if (cb_claim_side_table(results_dir, "explicit_stability", "boundary", &b, out)) return;
  static const char *const bn[] = {"scene", "k_n_per_m", "dt_crit_pred_s", "dt_crit_meas_s", "bisect_status", "dt_crit_pred_rest_s",
                                   "lambda_dense_per_s2", "lambda_lanczos_per_s2"};
  static const char *const mn[] = {"kind", "scene", "k_n_per_m", "dt_s", "method", "status", "dt_crit_pred_s"};
  int bc[8], mc[7];
  if (cb_claim_columns(&b, bn, bc, 8, "explicit_stability_boundary.csv", out) || cb_claim_columns(t, mn, mc, 7, "explicit_stability.csv", out)) {
    cb_table_free(&b);
    return;
  }
  char names[MAXS][32];
  int ns = 0, nrows = 0, within = 0, failed = 0, npts[MAXS] = {0};
  static double lk[MAXS][64], lm[MAXS][64], lp[MAXS][64];
  double worst = 1, lanczos_diff = 0;
  int checked = 0;
  cb_claim_numbers(out, "Per (scene, k): the largest stable explicit dt (bisection) against dt_pred = 2/omega_max at the "
                        "hanging equilibrium, and against the prediction at the flat rest shape.\n\n"
                        "| scene | k (N/m) | dt_pred (s) | dt_meas (s) | meas/pred | meas/pred(rest) |\n|---|---|---|---|---|---|\n");
  for (int r = 0; r < b.nrows; r++) {
    const char *sc = cb_table_str(&b, r, bc[0]);
    double k = cb_table_num(&b, r, bc[1]), pred = cb_table_num(&b, r, bc[2]), meas = cb_table_num(&b, r, bc[3]);
    double rest = cb_table_num(&b, r, bc[5]), ld = cb_table_num(&b, r, bc[6]), ll = cb_table_num(&b, r, bc[7]);
    double ratio = meas / pred;
    nrows++;
    if (strcmp(cb_table_str(&b, r, bc[4]), "ok") || !isfinite(ratio)) failed++;
    else if (fabs(ratio - 1) <= E1_RATIO_TOL) within++;
    if (isfinite(ratio) && fabs(ratio - 1) > fabs(worst - 1)) worst = ratio;
    if (isfinite(ld) && isfinite(ll)) {
      checked++;
      lanczos_diff = fmax(lanczos_diff, fabs(ll - ld) / fabs(ld));
    }
    cb_claim_numbers(out, "| %s | %.3g | %.4g | %.4g | %.4f | %.4f |\n", sc, k, pred, meas, ratio, meas / rest);
    int s = find_name(names, &ns, sc);
    if (s >= 0 && npts[s] < 64 && k > 0 && meas > 0 && pred > 0) {
      lk[s][npts[s]] = log10(k);
      lm[s][npts[s]] = log10(meas);
      lp[s][npts[s]++] = log10(pred);
    }
  }
  /* slopes of log dt_crit against log k, per scene with at least 3 stiffnesses */
  int slopes = 0, slopes_ok = 0;
  cb_claim_numbers(out, "\nFitted slope of log10 dt_crit against log10 k (target -%.2f +- %.2f):\n\n", E1_SLOPE, E1_SLOPE_TOL);
  for (int s = 0; s < ns; s++) {
    if (npts[s] < 3) continue;
    double a, c, ap;
    cb_fit_line(lk[s], lm[s], npts[s], &a, &c);
    cb_fit_line(lk[s], lp[s], npts[s], &ap, &c);
    slopes++;
    slopes_ok += fabs(a + E1_SLOPE) <= E1_SLOPE_TOL;
    cb_claim_numbers(out, "- %s: measured %.4f, predicted %.4f (%d stiffnesses)\n", names[s], a, ap, npts[s]);
  }
  /* the map: explicit sweep cells well inside / outside the predicted boundary */
  int below = 0, below_bad = 0, above = 0, above_bad = 0, unstable = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, mc[0]), "sweep") || strcmp(cb_table_str(t, r, mc[4]), "explicit")) continue;
    double x = cb_table_num(t, r, mc[3]) / cb_table_num(t, r, mc[6]);
    int stable = !strcmp(cb_table_str(t, r, mc[5]), "stable");
    unstable += !stable;
    if (x < 1 - E1_RATIO_TOL) { below++; below_bad += !stable; }
    if (x > 1 + E1_RATIO_TOL) { above++; above_bad += stable; }
  }
  cb_claim_numbers(out, "\nStability map (explicit sweep cells): %d not stable; %d of %d cells with dt < %.2f dt_pred are not "
                        "stable, %d of %d cells with dt > %.2f dt_pred are stable.\n", unstable, below_bad, below,
                   1 - E1_RATIO_TOL, above_bad, above, 1 + E1_RATIO_TOL);
  if (checked) cb_claim_numbers(out, "\nLanczos against GSL's dense solver: largest relative difference of lambda_max %.2g "
                                     "(%d scenes where both ran).\n", lanczos_diff, checked);
  cb_table_free(&b);
  if (nrows == 0) {
    cb_claim_reason(out, "The boundary table has no rows.");
    return;
  }
  int ratios_ok = within == nrows, map_ok = below_bad == 0 && above_bad == 0 && unstable > 0;
  int slope_all = slopes > 0 && slopes_ok == slopes, lanczos_ok = checked == 0 || lanczos_diff <= 1e-6;
  if (ratios_ok && slope_all && map_ok && lanczos_ok) out->verdict = CB_REPRODUCED;
  else if (2 * within >= nrows && unstable > 0) out->verdict = CB_PARTLY;
  else out->verdict = CB_NOT_REPRODUCED;
  cb_claim_reason(out, "%d of %d measured boundaries lie within %.0f%% of 2/omega_max (worst ratio %.4f%s); %d of %d scenes "
                       "have a slope within -%.2f +- %.2f; the map has %d cells off the predicted side outside the +-%.0f%% band",
                  within, nrows, 100 * E1_RATIO_TOL, worst, failed ? ", some bisections failed" : "", slopes_ok, slopes,
                  E1_SLOPE, E1_SLOPE_TOL, below_bad + above_bad, 100 * E1_RATIO_TOL);
  cb_claim_reason(out, unstable ? "." : " and no unstable cell at all.");
  if (!lanczos_ok) cb_claim_reason(out, " Lanczos and GSL disagree by %.2g.", lanczos_diff);
}

/* ---- E2 ------------------------------------------------------------------- */

/* wall: wall_ms_per_s with its spread over the repeats (min, max, each) */
typedef struct { char scene[32]; double n, k, wall, steps, not_conv; int method, stable; cb_claim_timing w; } trow;

/* which: 0 the median, 1 the fastest repeat, 2 the slowest */
static double pick(const cb_claim_timing *t, int which) { return which == 0 ? t->med : which == 1 ? t->min : t->max; }

/* "a (lo / hi fitted to the fastest / slowest repeats)" for a fitted exponent, or "a" */
static const char *exp_text(char *buf, size_t n, double a, double lo, double hi) {
  if (isfinite(lo) && isfinite(hi)) snprintf(buf, n, "%.3f (%.3f / %.3f fitted to the fastest / slowest repeats)", a, lo, hi);
  else snprintf(buf, n, "%.3f", a);
  return buf;
}

void cb_check_E2(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)t;
  cb_table b;
  if (cb_claim_side_table(results_dir, "explicit_stability", "timing", &b, out)) return;
  static const char *const tn[] = {"scene", "n_vertices", "k_n_per_m", "method", "wall_ms_per_s", "steps", "status"};
  int c[7];
  if (cb_claim_columns(&b, tn, c, 7, "explicit_stability_timing.csv", out)) { cb_table_free(&b); return; }
  int cnc = cb_table_col(&b, "not_converged_steps"); /* optional: older tables lack it */
  static trow rows[MAXPTS];
  int n = 0, unstable = 0;
  cb_claim_repeats reps = {0};
  for (int r = 0; r < b.nrows && n < MAXPTS; r++) {
    const char *m = cb_table_str(&b, r, c[3]);
    trow *x = &rows[n++];
    snprintf(x->scene, sizeof x->scene, "%s", cb_table_str(&b, r, c[0]));
    x->n = cb_table_num(&b, r, c[1]); x->k = cb_table_num(&b, r, c[2]);
    x->w = cb_claim_timing_at(&b, r, "wall_ms_per_s");
    x->wall = x->w.med; x->steps = cb_table_num(&b, r, c[5]);
    x->method = !strcmp(m, "explicit") ? 0 : !strcmp(m, "newton") ? 1 : !strcmp(m, "newton_bw") ? 2 : 3;
    x->stable = !strcmp(cb_table_str(&b, r, c[6]), "stable");
    x->not_conv = cnc >= 0 ? cb_table_num(&b, r, cnc) : NAN;
    unstable += !x->stable;
    cb_claim_repeats_add(&reps, &x->w);
  }
  cb_table_free(&b);
  /* against k: per scene, explicit wall ~ k^a; compared with Newton at the stiffest k */
  char names[MAXS][32];
  int ns = 0;
  for (int i = 0; i < n; i++) find_name(names, &ns, rows[i].scene);
  int kfits = 0, kfits_ok = 0, slower = 0, compared = 0;
  char rtxt[64], s1[96], s2[96];
  cb_claim_repeats_text(rtxt, sizeof rtxt, &reps);
  cb_claim_numbers(out, "Wall time to simulate 1 s (explicit at 0.9 x its measured dt_crit; Newton + CHOLMOD at dt = 1/30 s, "
                        "converged, and Baraff-Witkin's single iteration for reference).");
  if (rtxt[0])
    cb_claim_numbers(out, " Each time is the median of %s (in brackets the fastest and slowest); the methods of a row "
                          "ran in interleaved rounds, so ratios between them are paired repeat by repeat.", rtxt);
  cb_claim_numbers(out, "\n\n| scene | k (N/m) | explicit (ms) | explicit steps | Newton (ms) | Baraff-Witkin (ms) |\n|---|---|---|---|---|---|\n");
  int newton_rows = 0, newton_unconverged = 0;
  for (int i = 0; i < n; i++) {
    if (rows[i].method != 0) continue;
    const trow *nt = NULL, *bw = NULL;
    for (int j = 0; j < n; j++)
      if (!strcmp(rows[j].scene, rows[i].scene) && rows[j].k == rows[i].k) {
        if (rows[j].method == 1) nt = &rows[j];
        if (rows[j].method == 2) bw = &rows[j];
      }
    char ntxt[192] = "not timed", btxt[96] = "not timed";
    if (nt) {
      newton_rows++;
      newton_unconverged += nt->not_conv > 0;
      cb_claim_spread(s1, sizeof s1, "%.4g", &nt->w, "");
      if (nt->not_conv > 0)
        snprintf(ntxt, sizeof ntxt, "%s (**not converged**: %.0f of %.0f steps at max_iters)", s1, nt->not_conv, nt->steps);
      else snprintf(ntxt, sizeof ntxt, "%s%s", s1, isnan(nt->not_conv) ? " (convergence not recorded)" : "");
    }
    if (bw) cb_claim_spread(btxt, sizeof btxt, "%.4g", &bw->w, "");
    cb_claim_numbers(out, "| %s | %.3g | %s | %.0f | %s | %s |\n", rows[i].scene, rows[i].k,
                     cb_claim_spread(s1, sizeof s1, "%.4g", &rows[i].w, ""), rows[i].steps, ntxt, btxt);
  }
  if (newton_rows)
    cb_claim_numbers(out, "\nConverged Newton (to integrator.tol, at most 400 iterations a step) is timed on %d (scene, k) rows; "
                          "%d of them had steps that stopped at max_iters, marked **not converged** above. `not timed`: only "
                          "explicit and Baraff-Witkin were run there.\n", newton_rows, newton_unconverged);
  cb_claim_numbers(out, "\nAgainst stiffness (explicit wall time ~ k^a; where the fit reaches converged Newton's time):\n\n");
  for (int s = 0; s < ns; s++) {
    double lx[64], ly[3][64], kmax = -1;
    const trow *ex_at = NULL, *nt_at = NULL;
    int m = 0, spread = 1;
    for (int i = 0; i < n; i++) {
      if (strcmp(rows[i].scene, names[s]) || rows[i].method != 0) continue;
      const trow *nt = NULL;
      for (int j = 0; j < n; j++)
        if (!strcmp(rows[j].scene, names[s]) && rows[j].k == rows[i].k && rows[j].method == 1) nt = &rows[j];
      if (m < 64 && rows[i].wall > 0) {
        lx[m] = log10(rows[i].k);
        for (int w = 0; w < 3; w++) ly[w][m] = log10(pick(&rows[i].w, w));
        spread &= cb_claim_timing_has_spread(&rows[i].w);
        m++;
      }
      if (nt && isfinite(nt->wall) && rows[i].k > kmax) { kmax = rows[i].k; ex_at = &rows[i]; nt_at = nt; }
    }
    cb_claim_timing ratio = {0};
    if (ex_at) ratio = cb_claim_timing_ratio(&ex_at->w, &nt_at->w);
    if (m >= 3) {
      double a[3], b0[3];
      for (int w = 0; w < 3; w++) cb_fit_line(lx, ly[w], m, &a[w], &b0[w]);
      if (!spread) a[1] = a[2] = NAN;
      kfits++;
      kfits_ok += fabs(a[0] - E2_K_EXP) <= E2_K_EXP_TOL;
      cb_claim_numbers(out, "- %s: explicit ~ k^%s over %d stiffnesses", names[s], exp_text(s1, sizeof s1, a[0], a[1], a[2]), m);
      if (ex_at && a[0] > 0) {
        double kr = pow(10.0, (log10(nt_at->wall) - b0[0]) / a[0]);
        cb_claim_numbers(out, "; at k = %.3g explicit/Newton = %s; the fit reaches Newton's time at k ~ %.2g N/m", kmax,
                         cb_claim_spread_long(s2, sizeof s2, "%.3g", &ratio, ""), kr);
        if (spread && a[1] > 0 && a[2] > 0 && cb_claim_timing_has_spread(&nt_at->w))
          cb_claim_numbers(out, " (%.2g / %.2g from the fastest / slowest repeats)",
                           pow(10.0, (log10(nt_at->w.min) - b0[1]) / a[1]), pow(10.0, (log10(nt_at->w.max) - b0[2]) / a[2]));
      }
      cb_claim_numbers(out, "\n");
    } else if (ex_at)
      cb_claim_numbers(out, "- %s: at k = %.3g explicit/Newton = %s\n", names[s], kmax,
                       cb_claim_spread_long(s2, sizeof s2, "%.3g", &ratio, ""));
    if (ex_at) { compared++; slower += ex_at->wall > nt_at->wall; }
  }
  /* against resolution: per k with explicit rows at >= 3 sizes */
  int nfits = 0, nfits_ok = 0;
  double nexp_ex[3] = {NAN, NAN, NAN};
  cb_claim_numbers(out, "\nAgainst resolution n (vertices), fitted exponents of wall time (and of explicit steps and "
                        "time per step):\n\n");
  for (int i = 0; i < n; i++) {
    if (rows[i].method != 0) continue;
    int seen = 0;
    for (int j = 0; j < i; j++) seen |= rows[j].method == 0 && rows[j].k == rows[i].k;
    if (seen) continue;
    double ln[3][16], lw[3][3][16], ls[16], lp[16];
    int m[3] = {0, 0, 0}, spread[3] = {1, 1, 1};
    for (int j = 0; j < n; j++) {
      if (rows[j].k != rows[i].k || rows[j].method > 2 || !(rows[j].wall > 0)) continue;
      int q = rows[j].method, dup = 0;
      for (int u = 0; u < m[q]; u++) dup |= ln[q][u] == log10(rows[j].n);
      if (dup || m[q] == 16) continue;
      ln[q][m[q]] = log10(rows[j].n);
      for (int w = 0; w < 3; w++) lw[q][w][m[q]] = log10(pick(&rows[j].w, w));
      spread[q] &= cb_claim_timing_has_spread(&rows[j].w);
      if (q == 0) { ls[m[0]] = log10(rows[j].steps); lp[m[0]] = log10(rows[j].wall / rows[j].steps); }
      m[q]++;
    }
    if (m[0] < 3) continue;
    double a[3], b0, as, ap;
    for (int w = 0; w < 3; w++) cb_fit_line(ln[0], lw[0][w], m[0], &a[w], &b0);
    if (!spread[0]) a[1] = a[2] = NAN;
    cb_fit_line(ln[0], ls, m[0], &as, &b0);
    cb_fit_line(ln[0], lp, m[0], &ap, &b0);
    nfits++;
    nfits_ok += fabs(a[0] - E2_N_EXP) <= E2_N_EXP_TOL;
    memcpy(nexp_ex, a, sizeof a);
    cb_claim_numbers(out, "- k = %.3g: explicit ~ n^%s (steps ~ n^%.3f, time per step ~ n^%.3f; %d sizes)", rows[i].k,
                     exp_text(s1, sizeof s1, a[0], a[1], a[2]), as, ap, m[0]);
    for (int q = 1; q <= 2; q++)
      if (m[q] >= 3) {
        double aq[3];
        for (int w = 0; w < 3; w++) cb_fit_line(ln[q], lw[q][w], m[q], &aq[w], &b0);
        if (!spread[q]) aq[1] = aq[2] = NAN;
        cb_claim_numbers(out, "; %s ~ n^%s", q == 1 ? "Newton" : "Baraff-Witkin", exp_text(s1, sizeof s1, aq[0], aq[1], aq[2]));
      }
    cb_claim_numbers(out, "\n");
  }
  if (kfits == 0 && nfits == 0) {
    cb_claim_reason(out, "The timing table has too few rows to fit anything.");
    return;
  }
  int grows = kfits > 0 && kfits_ok == kfits, slow = compared > 0 && slower == compared, n2 = nfits > 0 && nfits_ok == nfits;
  out->verdict = grows && slow && n2 ? CB_REPRODUCED : grows ? CB_PARTLY : CB_NOT_REPRODUCED;
  cb_claim_reason(out, "Explicit cost grows like k^(1/2) (+-%.2f) in %d of %d scenes; at the stiffest k timed, explicit is "
                       "slower than converged Newton at 1/30 s in %d of %d scenes; explicit cost against resolution grows "
                       "like n^2 (+-%.2f) for %d of %d stiffnesses (last exponent %s).", E2_K_EXP_TOL, kfits_ok, kfits,
                  slower, compared, E2_N_EXP_TOL, nfits_ok, nfits, exp_text(s1, sizeof s1, nexp_ex[0], nexp_ex[1], nexp_ex[2]));
  if (rtxt[0]) cb_claim_reason(out, " Times are medians of %s.", rtxt);
  if (unstable) cb_claim_reason(out, " %d timed runs were not stable.", unstable);
}

/* ---- I1 ------------------------------------------------------------------- */

void cb_check_I1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  static const char *const mn[] = {"kind", "scene", "k_n_per_m", "dt_s", "method", "status", "max_energy_ratio", "steps",
                                   "not_converged_steps", "t_mark_s", "energy_loss_w", "kinetic0_j", "window_s"};
  int c[13];
  if (cb_claim_columns(t, mn, c, 13, "explicit_stability.csv", out)) return;
  char names[MAXS][32];
  int ns = 0, cells = 0, bad = 0, explicit_bad = 0;
  double max_gain = 0, steps = 0, nc = 0;
  static double dts[MAXS][MAXPTS], loss[MAXS][MAXPTS], ks[MAXS][MAXPTS];
  int np[MAXS] = {0};
  double tmark = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, c[0]), "sweep")) continue;
    int stable = !strcmp(cb_table_str(t, r, c[5]), "stable");
    if (strcmp(cb_table_str(t, r, c[4]), "newton")) { explicit_bad += !stable; continue; }
    cells++;
    bad += !stable;
    max_gain = fmax(max_gain, cb_table_num(t, r, c[6]));
    steps += cb_table_num(t, r, c[7]);
    nc += cb_table_num(t, r, c[8]);
    tmark = fmax(tmark, cb_table_num(t, r, c[12]));
  }
  for (int r = 0; r < t->nrows; r++) { /* energy lost over the common window [0, t_mark] */
    if (strcmp(cb_table_str(t, r, c[0]), "sweep") || strcmp(cb_table_str(t, r, c[4]), "newton")) continue;
    double w = cb_table_num(t, r, c[12]);
    if (!(w > 0) || cb_table_num(t, r, c[9]) < w * (1 - 1e-9)) continue; /* no window, or stopped before it */
    int s = find_name(names, &ns, cb_table_str(t, r, c[1]));
    if (s < 0 || np[s] == MAXPTS) continue;
    dts[s][np[s]] = cb_table_num(t, r, c[3]);
    ks[s][np[s]] = cb_table_num(t, r, c[2]);
    loss[s][np[s]++] = cb_table_num(t, r, c[10]) / cb_table_num(t, r, c[11]);
  }
  if (cells == 0) {
    cb_claim_reason(out, "The sweep has no Newton cells.");
    return;
  }
  cb_claim_numbers(out, "Converged Newton (CHOLMOD, |grad F| <= 1e-8 |grad F(x0)| or a step below 1e-10 m) on the sweep: "
                        "%d cells, %d not stable (explicit: %d of its sweep cells not stable); largest energy gain "
                        "(E - E0)/S = %.3g; %.0f of %.0f steps stopped at max_iters (%.2g%%).\n\n",
                   cells, bad, explicit_bad, max_gain, nc, steps, steps > 0 ? 100 * nc / steps : 0);
  cb_claim_numbers(out, "Energy lost per simulated second over the first %.3g s (cells that reached it), as a fraction of the initial kinetic "
                        "energy: fitted exponent of dt (loss ~ dt^p) and the range over dt, per scene and k.\n\n"
                        "| scene | k (N/m) | cells | loss/s at smallest dt | loss/s at largest dt | p |\n|---|---|---|---|---|---|\n", tmark);
  int series = 0, grows = 0, gained = 0;
  double pmin = INFINITY, pmax = -INFINITY;
  for (int s = 0; s < ns; s++)
    for (int i = 0; i < np[s]; i++) {
      int first = 1;
      for (int j = 0; j < i; j++) first &= ks[s][j] != ks[s][i];
      if (!first) continue;
      double lx[MAXPTS / 8], ly[MAXPTS / 8], dmin = INFINITY, dmax = 0, lmin = NAN, lmax = NAN;
      int m = 0;
      for (int j = 0; j < np[s]; j++) {
        if (ks[s][j] != ks[s][i]) continue;
        if (dts[s][j] < dmin) { dmin = dts[s][j]; lmin = loss[s][j]; }
        if (dts[s][j] > dmax) { dmax = dts[s][j]; lmax = loss[s][j]; }
        gained += loss[s][j] < -1e-9;
        if (loss[s][j] > 0 && m < MAXPTS / 8) { lx[m] = log10(dts[s][j]); ly[m++] = log10(loss[s][j]); }
      }
      if (m < 3) continue;
      double p, b0;
      cb_fit_line(lx, ly, m, &p, &b0);
      series++;
      grows += p >= I1_MIN_EXP && lmax > lmin; /* more damping at larger dt */
      pmin = fmin(pmin, p);
      pmax = fmax(pmax, p);
      cb_claim_numbers(out, "| %s | %.3g | %d | %.3g | %.3g | %.3f |\n", names[s], ks[s][i], m, lmin, lmax, p);
    }
  if (bad) out->verdict = CB_NOT_REPRODUCED;
  else if (series > 0 && grows == series && gained == 0) out->verdict = CB_REPRODUCED;
  else out->verdict = CB_PARTLY;
  cb_claim_reason(out, "%s of %d Newton cells became unstable or diverged; the energy lost per simulated second grows "
                       "with dt (fitted exponent >= %.2f and more loss at the largest dt than at the smallest) in %d of %d "
                       "(scene, k) series, exponents %.2f to %.2f (1 is implicit Euler's h omega^2 damping of a slow mode)%s.",
                  bad ? "Some" : "None", cells, I1_MIN_EXP, grows, series, pmin, pmax,
                  gained ? "; some cells gained energy" : "");
  if (bad) cb_claim_reason(out, " %d Newton cells were not stable.", bad);
}
