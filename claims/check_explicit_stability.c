/* Checkers for E1, E2 and I1 from results/explicit_stability.csv and its side
 * tables explicit_stability_boundary.csv (E1) and explicit_stability_timing.csv
 * (E2). Every number below is computed here from those files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"


enum { MAXS = 16, MAXPTS = 4096 };

/* The tolerances the claims state. */
#define E1_RATIO_TOL 0.15 /* |dt_meas / dt_pred - 1| */
#define E1_SLOPE 0.5      /* -d log dt_crit / d log k */
#define E1_SLOPE_TOL 0.05
#define E2_ERR_TOL 0.01  /* an implicit method counts when its step error is within 1% */
#define E2_N_EXP_TOL 0.2 /* |b - b_pred|: explicit cost ~ n^b against 1 + d log omega_max / d log n */
#define I1_MIN_EXP 0.25  /* energy lost per second ~ dt^p with p at least this: damping grows with dt */

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
  static const char *const bn[] = {
      "scene",         "k_n_per_m",           "dt_crit_pred_s",      "dt_crit_meas_s",
      "bisect_status", "dt_crit_pred_rest_s", "lambda_dense_per_s2", "lambda_lanczos_per_s2"};
  static const char *const mn[] = {"kind", "scene", "k_n_per_m", "dt_s", "method", "status", "dt_crit_pred_s"};
  int bc[8], mc[7], ceq = cb_table_col(&b, "equilibrium_status"); /* optional: which state the runs start from */
  if (cb_claim_columns(&b, bn, bc, 8, "explicit_stability_boundary.csv", out) ||
      cb_claim_columns(t, mn, mc, 7, "explicit_stability.csv", out)) {
    cb_table_free(&b);
    return;
  }
  char names[MAXS][32];
  int ns = 0, nrows = 0, within = 0, failed = 0, npts[MAXS] = {0};
  static double lk[MAXS][64], lm[MAXS][64], lp[MAXS][64];
  double worst = 1, lanczos_diff = 0, worst_rest = 1;
  int checked = 0, at_eq = 0, rest_rows = 0, rest_within = 0;
  cb_claim_numbers(out, "Per (scene, k): the largest stable explicit dt (bisection) against dt_pred = 2/omega_max at "
                        "the "
                        "hanging equilibrium, and against the prediction at the flat rest shape.\n\n"
                        "| scene | k (N/m) | dt_pred (s) | dt_meas (s) | meas/pred | meas/pred(rest) "
                        "|\n|---|---|---|---|---|---|\n");
  for (int r = 0; r < b.nrows; r++) {
    const char *sc = cb_table_str(&b, r, bc[0]);
    double k = cb_table_num(&b, r, bc[1]), pred = cb_table_num(&b, r, bc[2]), meas = cb_table_num(&b, r, bc[3]);
    double rest = cb_table_num(&b, r, bc[5]), ld = cb_table_num(&b, r, bc[6]), ll = cb_table_num(&b, r, bc[7]);
    double ratio = meas / pred;
    nrows++;
    if (strcmp(cb_table_str(&b, r, bc[4]), "ok") || !isfinite(ratio)) failed++;
    else if (fabs(ratio - 1) <= E1_RATIO_TOL) within++;
    if (isfinite(ratio) && fabs(ratio - 1) > fabs(worst - 1)) worst = ratio;
    at_eq += ceq >= 0 && !strcmp(cb_table_str(&b, r, ceq), "ok");
    double rr = meas / rest;
    if (isfinite(rr)) {
      rest_rows++;
      rest_within += fabs(rr - 1) <= E1_RATIO_TOL;
      if (fabs(rr - 1) > fabs(worst_rest - 1)) worst_rest = rr;
    }
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
  cb_claim_numbers(out, "\nFitted slope of log10 dt_crit against log10 k (target -%.2f +- %.2f):\n\n", E1_SLOPE,
                   E1_SLOPE_TOL);
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
    if (x < 1 - E1_RATIO_TOL) {
      below++;
      below_bad += !stable;
    }
    if (x > 1 + E1_RATIO_TOL) {
      above++;
      above_bad += stable;
    }
  }
  cb_claim_numbers(out,
                   "\nStability map (explicit sweep cells): %d not stable; %d of %d cells with dt < %.2f dt_pred are "
                   "not "
                   "stable, %d of %d cells with dt > %.2f dt_pred are stable.\n",
                   unstable, below_bad, below, 1 - E1_RATIO_TOL, above_bad, above, 1 + E1_RATIO_TOL);
  if (checked)
    cb_claim_numbers(out,
                     "\nLanczos against GSL's dense solver: largest relative difference of lambda_max %.2g "
                     "(%d scenes where both ran).\n",
                     lanczos_diff, checked);
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
  /* CLAIMS.md: omega_max at the state the runs start from, rest or the hanging equilibrium; say which */
  if (at_eq == nrows)
    cb_claim_reason(out, "Judged at the state every run starts from, the static hanging equilibrium (v = 0 "
                         "before the small start velocity), not the flat rest shape: ");
  else
    cb_claim_reason(out,
                    "Judged at the state every run starts from (the static hanging equilibrium in %d of %d rows, "
                    "the scene's own start in the others): ",
                    at_eq, nrows);
  cb_claim_reason(out,
                  "%d of %d measured boundaries lie within %.0f%% of 2/omega_max (worst ratio %.4f%s); %d of %d scenes "
                  "have a slope within -%.2f +- %.2f; the map has %d cells off the predicted side outside the +-%.0f%% "
                  "band",
                  within, nrows, 100 * E1_RATIO_TOL, worst, failed ? ", some bisections failed" : "", slopes_ok, slopes,
                  E1_SLOPE, E1_SLOPE_TOL, below_bad + above_bad, 100 * E1_RATIO_TOL);
  cb_claim_reason(out, unstable ? "." : " and no unstable cell at all.");
  if (!lanczos_ok) cb_claim_reason(out, " Lanczos and GSL disagree by %.2g.", lanczos_diff);
  if (rest_rows)
    cb_claim_reason(out,
                    " At the flat rest shape instead, %d of %d lie within %.0f%% (worst %.4f); that prediction does "
                    "not "
                    "decide.",
                    rest_within, rest_rows, 100 * E1_RATIO_TOL, worst_rest);
}

/* ---- E2 ------------------------------------------------------------------- */

/* wall: wall_ms_per_s with its spread over the repeats (min, max, each); err: the implicit
 * method's largest step error against the converged minimiser (NaN: not measured) */
typedef struct {
  char scene[32], family[16];
  double n, k, wall, steps, not_conv, err, dtp;
  int method, stable, iters; /* iters: a fixed-iteration method's count a step (0: none recorded) */
  cb_claim_timing w;
} trow;

/* which: 0 the median, 1 the fastest repeat, 2 the slowest */
static double pick(const cb_claim_timing *t, int which) { return which == 0 ? t->med : which == 1 ? t->min : t->max; }

/* "a (lo / hi fitted to the fastest / slowest repeats)" for a fitted exponent, or "a" */
static const char *exp_text(char *buf, size_t n, double a, double lo, double hi) {
  if (isfinite(lo) && isfinite(hi))
    snprintf(buf, n, "%.3f (%.3f / %.3f fitted to the fastest / slowest repeats)", a, lo, hi);
  else snprintf(buf, n, "%.3f", a);
  return buf;
}

/* methods: explicit, converged Newton, Baraff-Witkin (drop, shift), Newton stopped after 2-5 iterations,
 * the lab's chebyshev-nl and projective dynamics (each at the smallest count of its ladder within 1%) */
enum { E2_NM = 10, E2_NEWTON_K = 4, E2_CHEB = 8, E2_PD = 9 };
static const char *const e2_method[E2_NM] = {"explicit", "newton",   "newton_bw", "newton_bw_shift", "newton_2",
                                             "newton_3", "newton_4", "newton_5",  "chebyshev_nl",    "pd"};
static const char *const e2_variant[E2_NM] = {"explicit (symplectic Euler)",
                                              "converged Newton (exact Hessian, shift where indefinite, line search, "
                                              "CHOLMOD)",
                                              "Baraff-Witkin (one Newton iteration, the lecture's drop fix, CHOLMOD)",
                                              "Baraff-Witkin on the exact Hessian (one Newton iteration, shift, "
                                              "CHOLMOD)",
                                              "Newton stopped after 2, 3, 4 or 5 iterations a step (converged Newton's "
                                              "variant)",
                                              NULL,
                                              NULL,
                                              NULL,
                                              "the lab's nonlinear Chebyshev-Jacobi (rho 0.995) at the smallest of 32, "
                                              "128, 512 iterations a step whose step "
                                              "error is within the tolerance",
                                              "projective dynamics (CHOLMOD) at the smallest of 10, 32, 128 iterations "
                                              "a step within the tolerance"};
static const char *const e2_short[E2_NM] = {"explicit",
                                            "converged Newton",
                                            "Baraff-Witkin (drop)",
                                            "Baraff-Witkin (shift)",
                                            "Newton, 2 iterations",
                                            "Newton, 3 iterations",
                                            "Newton, 4 iterations",
                                            "Newton, 5 iterations",
                                            "chebyshev-nl",
                                            "pd"};

/* The fastest implicit row of (scene, k) that stayed stable with a measured step error within E2_ERR_TOL. */
static const trow *e2_best(const trow *rows, int n, const trow *ex) {
  const trow *best = NULL;
  for (int j = 0; j < n; j++) {
    const trow *y = &rows[j];
    if (y->method < 1 || y->method >= E2_NM || strcmp(y->scene, ex->scene) || y->k != ex->k) continue;
    if (!y->stable || !(y->err <= E2_ERR_TOL) || !(y->wall > 0)) continue;
    if (!best || y->wall < best->wall) best = y;
  }
  return best;
}

static const trow *e2_row(const trow *rows, int n, const trow *ex, int method) {
  for (int j = 0; j < n; j++)
    if (rows[j].method == method && !strcmp(rows[j].scene, ex->scene) && rows[j].k == ex->k) return &rows[j];
  return NULL;
}

/* Where explicit stands against its baseline, over the paired spread of their ratio (cb_claim_timing_side
 * against 1): +1 slower, -1 faster, 0 undecided within the spread; -2 when there is nothing to compare (no
 * accurate implicit method, or explicit not stable). */
static int e2_side(const trow *ex, const trow *best, cb_claim_timing *ratio) {
  if (!best || !ex->stable) return -2;
  *ratio = cb_claim_timing_ratio(&ex->w, &best->w);
  return cb_claim_timing_side(ratio, 1.0);
}

/* "ms; step error" of an implicit row, with its flags */
static const char *e2_cell(char *buf, size_t n, const trow *y, int with_iters) {
  char s1[128], es[32], it[32] = "";
  cb_claim_spread(s1, sizeof s1, "%.4g", &y->w, "");
  if (isfinite(y->err) || isinf(y->err)) snprintf(es, sizeof es, "%.2g", y->err);
  else snprintf(es, sizeof es, "not measured");
  if (with_iters && y->iters > 0) snprintf(it, sizeof it, "%d it.: ", y->iters);
  snprintf(buf, n, "%s%s; %s%s%s", it, s1, es, y->stable ? "" : ", **not stable**",
           y->method == 1 && y->not_conv > 0 ? ", **not converged**" : "");
  return buf;
}

void cb_check_E2(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)t;
  cb_table b;
  if (cb_claim_side_table(results_dir, "explicit_stability", "timing", &b, out)) return;
  static const char *const tn[] = {
      "scene",  "family",         "n_vertices",     "k_n_per_m",          "method", "wall_ms_per_s", "steps",
      "status", "dt_crit_pred_s", "step_error_max", "not_converged_steps"};
  int c[11];
  if (cb_claim_columns(&b, tn, c, 11, "explicit_stability_timing.csv", out)) {
    cb_table_free(&b);
    return;
  }
  static trow rows[MAXPTS];
  int n = 0, unstable = 0, ci = cb_table_col(&b, "iters_per_step"); /* optional (older CSVs lack it) */
  cb_claim_repeats reps = {0};
  for (int r = 0; r < b.nrows && n < MAXPTS; r++) {
    const char *m = cb_table_str(&b, r, c[4]);
    trow *x = &rows[n++];
    snprintf(x->scene, sizeof x->scene, "%s", cb_table_str(&b, r, c[0]));
    snprintf(x->family, sizeof x->family, "%s", cb_table_str(&b, r, c[1]));
    x->n = cb_table_num(&b, r, c[2]);
    x->k = cb_table_num(&b, r, c[3]);
    x->w = cb_claim_timing_at(&b, r, "wall_ms_per_s");
    x->wall = x->w.med;
    x->steps = cb_table_num(&b, r, c[6]);
    x->method = E2_NM;
    for (int q = 0; q < E2_NM; q++)
      if (!strcmp(m, e2_method[q])) x->method = q;
    x->stable = !strcmp(cb_table_str(&b, r, c[7]), "stable");
    x->dtp = cb_table_num(&b, r, c[8]);
    x->err = cb_table_num(&b, r, c[9]);
    x->not_conv = cb_table_num(&b, r, c[10]);
    x->iters = ci >= 0 && cb_table_int(&b, r, ci) > 0 ? cb_table_int(&b, r, ci) : 0;
    unstable += !x->stable;
    cb_claim_repeats_add(&reps, &x->w);
  }
  cb_table_free(&b);
  char rtxt[64], s1[128], s3[160];
  cb_claim_repeats_text(rtxt, sizeof rtxt, &reps);
  cb_claim_numbers(out,
                   "Wall time to simulate 1 s: explicit (symplectic Euler) at its measured largest stable dt, against "
                   "the fastest implicit method at dt = 1/30 s whose step error (|x - x*|_M / |x* - x0|_M against the "
                   "converged minimiser of each step, largest over the steps checked) is within %.0f%%. Implicit "
                   "variants: %s; %s; %s; %s; %s; %s. Explicit counts as slower (or faster) only when the paired "
                   "spread of the ratio lies above (below) 1; a spread that straddles 1 is undecided.",
                   100 * E2_ERR_TOL, e2_variant[1], e2_variant[2], e2_variant[3], e2_variant[4], e2_variant[E2_CHEB],
                   e2_variant[E2_PD]);
  if (rtxt[0])
    cb_claim_numbers(out,
                     " Each time is the median of %s (in brackets the fastest and slowest); the methods of a row "
                     "ran in interleaved rounds, so ratios between them are paired repeat by repeat.",
                     rtxt);
  cb_claim_numbers(out,
                   "\n\n| scene | family | k (N/m) | n | explicit (ms) | explicit steps | converged Newton (ms; step "
                   "error) "
                   "| Baraff-Witkin, drop (ms; step error) | Baraff-Witkin, shift (ms; step error) | Newton, 2 / 3 / "
                   "4 / 5 iterations (ms; step error) | chebyshev-nl (iterations: ms; step error) | pd (iterations: "
                   "ms; step error) | fastest implicit within %.0f%% | explicit / it "
                   "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
                   100 * E2_ERR_TOL);
  int compared = 0, slower = 0, faster = 0, undecided = 0, newton_unconverged = 0, no_best = 0;
  for (int i = 0; i < n; i++) {
    const trow *ex = &rows[i];
    if (ex->method != 0) continue;
    const trow *best = e2_best(rows, n, ex);
    char itxt[E2_NM][320], rat[160] = "-", nk[4 * 200] = "";
    for (int q = 1; q < E2_NM; q++) {
      const trow *y = e2_row(rows, n, ex, q);
      snprintf(itxt[q], sizeof itxt[q], "not timed");
      if (!y) continue;
      e2_cell(itxt[q], sizeof itxt[q], y, q >= E2_CHEB);
      if (q == 1 && y->not_conv > 0) newton_unconverged++;
    }
    for (int q = E2_NEWTON_K; q < E2_CHEB; q++) {
      size_t u = strlen(nk);
      snprintf(nk + u, sizeof nk - u, "%s%s", q > E2_NEWTON_K ? " / " : "", itxt[q]);
    }
    cb_claim_timing ratio;
    int side = e2_side(ex, best, &ratio);
    if (side != -2) {
      cb_claim_spread_long(rat, sizeof rat - 16, "%.3g", &ratio, "");
      if (side == 0) strcat(rat, ", undecided");
      compared++;
      slower += side > 0;
      faster += side < 0;
      undecided += side == 0;
    } else no_best++;
    cb_claim_numbers(out, "| %s | %s | %.3g | %.0f | %s%s | %.0f | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                     ex->scene, ex->family, ex->k, ex->n, cb_claim_spread(s1, sizeof s1, "%.4g", &ex->w, ""),
                     ex->stable ? "" : " (**not stable**)", ex->steps, itxt[1], itxt[2], itxt[3], nk, itxt[E2_CHEB],
                     itxt[E2_PD], best ? e2_short[best->method] : "none", rat);
  }
  if (newton_unconverged)
    cb_claim_numbers(out,
                     "\n%d converged-Newton rows had steps that stopped at max_iters (marked **not converged**).\n",
                     newton_unconverged);
  /* against stiffness: per scene, explicit wall ~ k^a against a = d log omega_max / d log k (steps ~ omega_max) */
  char names[MAXS][32];
  int ns = 0;
  for (int i = 0; i < n; i++) find_name(names, &ns, rows[i].scene);
  cb_claim_numbers(out, "\nAgainst stiffness (explicit wall time ~ k^a; predicted a = d log omega_max / d log k, "
                        "omega_max = 2/dt_crit_pred; the smallest k from which explicit is slower than the fastest "
                        "accurate implicit at every larger k timed):\n\n");
  int kfits = 0;
  double stiff_k = -1;
  const trow *stiff_ex = NULL;
  for (int s = 0; s < ns; s++) {
    double lx[64], ly[3][64], lo[64];
    int m = 0, spread = 1;
    double from = NAN;
    const trow *last = NULL;
    for (int i = 0; i < n; i++) {
      const trow *ex = &rows[i];
      if (strcmp(ex->scene, names[s]) || ex->method != 0 || m == 64 || !(ex->wall > 0) || !(ex->dtp > 0)) continue;
      lx[m] = log10(ex->k);
      lo[m] = log10(2 / ex->dtp);
      for (int w = 0; w < 3; w++) ly[w][m] = log10(pick(&ex->w, w));
      spread &= cb_claim_timing_has_spread(&ex->w);
      m++;
      cb_claim_timing rr;
      int slow = e2_side(ex, e2_best(rows, n, ex), &rr) > 0;
      if (slow && isnan(from)) from = ex->k;
      if (!slow) from = NAN; /* rows are in increasing k per scene */
      if (!last || ex->k > last->k) last = ex;
    }
    if (m < 3) continue;
    double a[3], b0, ap;
    for (int w = 0; w < 3; w++) cb_fit_line(lx, ly[w], m, &a[w], &b0);
    if (!spread) a[1] = a[2] = NAN;
    cb_fit_line(lx, lo, m, &ap, &b0);
    kfits++;
    if (last && last->k > stiff_k) {
      stiff_k = last->k;
      stiff_ex = last;
    }
    cb_claim_numbers(out, "- %s: explicit ~ k^%s over %d stiffnesses, predicted %.3f; explicit is slower ", names[s],
                     exp_text(s1, sizeof s1, a[0], a[1], a[2]), m, ap);
    if (isnan(from)) cb_claim_numbers(out, "at no k timed up to %.3g N/m\n", last ? last->k : NAN);
    else cb_claim_numbers(out, "from k = %.3g N/m on (timed up to %.3g)\n", from, last->k);
  }
  /* against resolution: per (family, k) with explicit rows at >= 3 sizes */
  cb_claim_numbers(out,
                   "\nAgainst resolution n (vertices): fitted exponent b of explicit wall time, against b_pred = 1 + "
                   "c, c = d log omega_max / d log n (steps ~ omega_max, work ~ n per step; target |b - b_pred| <= "
                   "%.2f); and the exponents of steps, of time per step and of the fastest accurate implicit time:\n\n",
                   E2_N_EXP_TOL);
  int nfits = 0, nfits_ok = 0, fam_fit[2] = {0, 0}, fam_slow[2] = {0, 0}, fam_fine[2] = {0, 0}, fam_undec[2] = {0, 0};
  double fam_c[2] = {NAN, NAN}, worst_dev = 0;
  char worst_txt[160] = "";
  for (int i = 0; i < n; i++) {
    const trow *r0 = &rows[i];
    if (r0->method != 0) continue;
    int seen = 0;
    for (int j = 0; j < i; j++)
      seen |= rows[j].method == 0 && rows[j].k == r0->k && !strcmp(rows[j].family, r0->family);
    if (seen) continue;
    double ln[16], lw[3][16], ls[16], lp[16], lo[16], li[16];
    int m = 0, mi = 0, spread = 1;
    const trow *fine = NULL;
    for (int j = 0; j < n && m < 16; j++) {
      const trow *ex = &rows[j];
      if (ex->method != 0 || ex->k != r0->k || strcmp(ex->family, r0->family) || !(ex->wall > 0) || !(ex->dtp > 0))
        continue;
      int dup = 0;
      for (int u = 0; u < m; u++) dup |= ln[u] == log10(ex->n);
      if (dup) continue;
      ln[m] = log10(ex->n);
      for (int w = 0; w < 3; w++) lw[w][m] = log10(pick(&ex->w, w));
      spread &= cb_claim_timing_has_spread(&ex->w);
      ls[m] = log10(ex->steps);
      lp[m] = log10(ex->wall / ex->steps);
      lo[m] = log10(2 / ex->dtp);
      const trow *best = e2_best(rows, n, ex);
      if (best) li[mi++] = log10(best->wall); /* fitted only if every size has one */
      if (!fine || ex->n > fine->n) fine = ex;
      m++;
    }
    if (m < 3) continue;
    double a[3], b0, as, ap, ac, ai = NAN;
    for (int w = 0; w < 3; w++) cb_fit_line(ln, lw[w], m, &a[w], &b0);
    if (!spread) a[1] = a[2] = NAN;
    cb_fit_line(ln, ls, m, &as, &b0);
    cb_fit_line(ln, lp, m, &ap, &b0);
    cb_fit_line(ln, lo, m, &ac, &b0);
    if (mi == m) cb_fit_line(ln, li, m, &ai, &b0);
    double dev = a[0] - (1 + ac);
    int ok = fabs(dev) <= E2_N_EXP_TOL, f = !strcmp(r0->family, "bending");
    nfits++;
    nfits_ok += ok;
    fam_fit[f]++;
    fam_c[f] = ac;
    const trow *best = e2_best(rows, n, fine);
    fam_fine[f]++;
    cb_claim_timing fr;
    int fside = e2_side(fine, best, &fr);
    fam_slow[f] += fside > 0;
    fam_undec[f] += fside == 0;
    if (fabs(dev) >= fabs(worst_dev)) {
      worst_dev = dev;
      snprintf(worst_txt, sizeof worst_txt, "%s family at k = %.3g: b = %.3f against b_pred = %.3f", r0->family, r0->k,
               a[0], 1 + ac);
    }
    char fine_rat[128] = "-";
    if (best && fine->stable) {
      cb_claim_timing r = cb_claim_timing_ratio(&fine->w, &best->w);
      cb_claim_spread_long(fine_rat, sizeof fine_rat, "%.3g", &r, "");
    }
    cb_claim_numbers(out,
                     "- %s family, k = %.3g: explicit ~ n^%s, b_pred = %.3f (omega_max ~ n^%.3f)%s; steps ~ n^%.3f, "
                     "time per step ~ n^%.3f; fastest accurate implicit ~ %s (%d sizes); at n = %.0f explicit / "
                     "fastest accurate implicit = %s\n",
                     r0->family, r0->k, exp_text(s1, sizeof s1, a[0], a[1], a[2]), 1 + ac, ac,
                     ok ? "" : " (**outside the tolerance**)", as, ap,
                     isfinite(ai) ? (snprintf(s3, sizeof s3, "n^%.3f", ai), s3) : "not fitted (a size without one)", m,
                     fine->n, fine_rat);
  }
  if (compared == 0 && nfits == 0) {
    cb_claim_reason(out, "The timing table has no explicit row with an accurate implicit one to compare, and too few "
                         "sizes "
                         "to fit anything.");
    return;
  }
  cb_claim_numbers(out,
                   "\nVerdict rule: reproduced when explicit is slower than the fastest accurate implicit method at "
                   "the stiffest k and at the finest mesh of every (family, k), and every resolution exponent is "
                   "within "
                   "%.2f of 1 + its omega_max exponent, with both families measured and the bending one's omega_max "
                   "growing faster; refuted (not reproduced) when explicit is faster than every accurate implicit "
                   "method in every timed row; undecided when a row that decides lies within the spread (the paired "
                   "spread of explicit / fastest accurate implicit straddles 1) and the others would reproduce it, or "
                   "when no row is slower outside the spread but some straddle 1; otherwise partly.\n",
                   E2_N_EXP_TOL);
  /* the verdict: "slow" at the stiffest k of the k-sweep and at the finest mesh of each family;
   * "as the physics predicts": every resolution exponent within tolerance of its omega_max prediction,
   * with both families measured and the bending family's omega_max growing faster */
  int stiff_side = -2;
  cb_claim_timing sr;
  if (stiff_ex) stiff_side = e2_side(stiff_ex, e2_best(rows, n, stiff_ex), &sr);
  int stiff_slow = stiff_side > 0;
  int both = fam_fit[0] > 0 && fam_fit[1] > 0, distinct = both && fam_c[1] > fam_c[0] + E2_N_EXP_TOL;
  int exps_ok = both && distinct && nfits_ok == nfits;
  int slow_all = stiff_ex && stiff_slow && both && fam_slow[0] == fam_fine[0] && fam_slow[1] == fam_fine[1];
  /* slow or within the spread at every deciding row, and within it at one at least */
  int slow_or_undec = stiff_ex && stiff_side >= 0 && both && fam_slow[0] + fam_undec[0] == fam_fine[0] &&
                      fam_slow[1] + fam_undec[1] == fam_fine[1];
  if (slower == 0) out->verdict = undecided ? CB_UNDECIDED : CB_NOT_REPRODUCED;
  else if (exps_ok && slow_all) out->verdict = CB_REPRODUCED;
  else if (exps_ok && slow_or_undec) out->verdict = CB_UNDECIDED;
  else out->verdict = CB_PARTLY;
  cb_claim_reason(out,
                  "Explicit at its largest stable dt is slower than the fastest implicit method at 1/30 s within "
                  "%.0f%% "
                  "step error in %d of %d timed rows, faster in %d, undecided within the spread in %d",
                  100 * E2_ERR_TOL, slower, compared, faster, undecided);
  if (stiff_ex)
    cb_claim_reason(out, ", %s at the stiffest k (%.3g N/m, %s%s)",
                    stiff_slow        ? "including"
                    : stiff_side == 0 ? "undecided"
                                      : "but not",
                    stiff_k, stiff_ex->scene,
                    stiff_side >= -1
                        ? (s3[0] = ':', s3[1] = ' ', cb_claim_spread_long(s3 + 2, sizeof s3 - 2, "%.3g", &sr, "x"), s3)
                        : "");
  cb_claim_reason(out,
                  "; at the finest mesh it is slower in %d of %d stretch-family and %d of %d bending-family "
                  "stiffnesses (undecided in %d). Explicit cost against resolution follows b_pred = 1 + d log "
                  "omega_max / d log n "
                  "within %.2f in %d of %d (family, k) fits (worst: %s); omega_max ~ n^%.3f (stretch) and n^%.3f "
                  "(bending).",
                  fam_slow[0], fam_fine[0], fam_slow[1], fam_fine[1], fam_undec[0] + fam_undec[1], E2_N_EXP_TOL,
                  nfits_ok, nfits, worst_txt[0] ? worst_txt : "none", fam_c[0], fam_c[1]);
  if (!both) cb_claim_reason(out, " Only one family was measured.");
  else if (!distinct)
    cb_claim_reason(out, " The bending family's omega_max does not grow faster than the stretch family's.");
  if (no_best)
    cb_claim_reason(out, " %d rows have no stable implicit method within %.0f%%.", no_best, 100 * E2_ERR_TOL);
  if (rtxt[0]) cb_claim_reason(out, " Times are medians of %s.", rtxt);
  if (unstable) cb_claim_reason(out, " %d timed runs were not stable.", unstable);
}

/* ---- I1 ------------------------------------------------------------------- */

void cb_check_I1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  static const char *const mn[] = {"kind",
                                   "scene",
                                   "k_n_per_m",
                                   "dt_s",
                                   "method",
                                   "status",
                                   "max_energy_ratio",
                                   "steps",
                                   "not_converged_steps",
                                   "t_mark_s",
                                   "energy_loss_w",
                                   "kinetic0_j",
                                   "window_s",
                                   "t_end_s"};
  int c[14];
  if (cb_claim_columns(t, mn, c, 14, "explicit_stability.csv", out)) return;
  char names[MAXS][32];
  int ns = 0, cells = 0, bad = 0, explicit_bad = 0;
  double max_gain = 0, steps = 0, nc = 0;
  static double dts[MAXS][MAXPTS], loss[MAXS][MAXPTS], ks[MAXS][MAXPTS];
  int np[MAXS] = {0};
  double tmark = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, c[0]), "sweep")) continue;
    int stable = !strcmp(cb_table_str(t, r, c[5]), "stable");
    if (strcmp(cb_table_str(t, r, c[4]), "newton")) {
      explicit_bad += !stable;
      continue;
    }
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
  /* the same simulated time: each Newton cell against the explicit sweep cell at its (scene, k, dt); an
   * explicit cell that diverged stopped early, so Newton must run at least as long, and exactly as long
   * where explicit ran to its end (stable) */
  int paired = 0, same = 0;
  double tmin = INFINITY, tmax = 0, smin = INFINITY, smax = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, c[0]), "sweep") || strcmp(cb_table_str(t, r, c[4]), "newton")) continue;
    double te = cb_table_num(t, r, c[13]), sn = cb_table_num(t, r, c[7]);
    tmin = fmin(tmin, te);
    tmax = fmax(tmax, te);
    smin = fmin(smin, sn);
    smax = fmax(smax, sn);
    for (int q = 0; q < t->nrows; q++) {
      if (strcmp(cb_table_str(t, q, c[0]), "sweep") || strcmp(cb_table_str(t, q, c[4]), "explicit") ||
          strcmp(cb_table_str(t, q, c[1]), cb_table_str(t, r, c[1])) ||
          cb_table_num(t, q, c[2]) != cb_table_num(t, r, c[2]) || cb_table_num(t, q, c[3]) != cb_table_num(t, r, c[3]))
        continue;
      double tx = cb_table_num(t, q, c[13]);
      int ex_full = !strcmp(cb_table_str(t, q, c[5]), "stable");
      paired++;
      same += ex_full ? fabs(te - tx) <= 1e-9 * tx : te >= tx * (1 - 1e-9);
      break;
    }
  }
  cb_claim_numbers(out,
                   "Converged Newton (CHOLMOD, |grad F| <= 1e-8 |grad F(x0)| or a step below 1e-10 m) on the sweep: "
                   "%d cells, %d not stable (explicit: %d of its sweep cells not stable); largest energy gain "
                   "(E - E0)/S = %.3g; %.0f of %.0f steps stopped at max_iters (%.2g%%).\n\n",
                   cells, bad, explicit_bad, max_gain, nc, steps, steps > 0 ? 100 * nc / steps : 0);
  cb_claim_numbers(out,
                   "Simulated time: %d of %d Newton cells ran as long as the explicit cell at the same (scene, k, dt) "
                   "(exactly, where that one ran to its end; at least as long where it diverged); %d have no explicit "
                   "cell to pair with. Newton cells ran %.0f to %.0f steps, %.3g to %.3g s simulated.\n\n",
                   same, paired, cells - paired, smin, smax, tmin, tmax);
  cb_claim_numbers(out,
                   "Energy lost per simulated second over the first %.3g s (cells that reached it), as a fraction of "
                   "the initial kinetic "
                   "energy: fitted exponent of dt (loss ~ dt^p) and the range over dt, per scene and k.\n\n"
                   "| scene | k (N/m) | cells | loss/s at smallest dt | loss/s at largest dt | p "
                   "|\n|---|---|---|---|---|---|\n",
                   tmark);
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
        if (dts[s][j] < dmin) {
          dmin = dts[s][j];
          lmin = loss[s][j];
        }
        if (dts[s][j] > dmax) {
          dmax = dts[s][j];
          lmax = loss[s][j];
        }
        gained += loss[s][j] < -1e-9;
        if (loss[s][j] > 0 && m < MAXPTS / 8) {
          lx[m] = log10(dts[s][j]);
          ly[m++] = log10(loss[s][j]);
        }
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
  int same_time = paired == cells && same == paired;
  if (bad) out->verdict = CB_NOT_REPRODUCED;
  else if (series > 0 && grows == series && gained == 0 && same_time) out->verdict = CB_REPRODUCED;
  else out->verdict = CB_PARTLY;
  cb_claim_reason(out,
                  "%s of %d Newton cells became unstable or diverged; the energy lost per simulated second grows "
                  "with dt (fitted exponent >= %.2f and more loss at the largest dt than at the smallest) in %d of %d "
                  "(scene, k) series, exponents %.2f to %.2f (1 is implicit Euler's h omega^2 damping of a slow "
                  "mode)%s.",
                  bad ? "Some" : "None", cells, I1_MIN_EXP, grows, series, pmin, pmax,
                  gained ? "; some cells gained energy" : "");
  if (bad) cb_claim_reason(out, " %d Newton cells were not stable.", bad);
  cb_claim_reason(out,
                  " %d of %d Newton cells ran the simulated time of the explicit cell at the same (scene, k, dt)%s.",
                  same, cells,
                  same_time ? ""
                            : " (the others ran shorter, or have no explicit cell: no-divergence is not shown over the "
                              "same time)");
}
