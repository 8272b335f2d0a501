/* Checkers for I2 and I3 (experiment newton_vs_bw). Every number comes from
 * results/newton_vs_bw*.csv; the definitions of the Pareto front, the
 * cheapest method and the convergence order are lib/instruments/pareto.c's, the same
 * ones the experiment's figures use.
 *
 * I2: for every step of the stretched hanging cloth, the order
 *     p = log(g_{k+1}/g_k) / log(g_k/g_{k-1}) of the last triple of Newton's
 *     |grad F| sequence that lies in the local regime (g_{k-1} <= 0.1 g_0),
 *     above round-off (g_{k+1} >= 1e-11 g_0) and whose two updates used the
 *     exact Hessian; runs "exact_or_shift" (the reference Newton: exact
 *     Hessian, shifted where A is indefinite, line search). Reproduced when
 *     the median over steps is >= 1.8 (at least 5 steps with an estimate);
 *     partly when the median is >= 1.5 or some step reaches 1.8; otherwise
 *     not reproduced.
 * I3: K = 1 "is fast": its median step time with CHOLMOD is at most half of
 *     the fastest converged Newton's on every scene (the fastest, by median
 *     step time, of every converged variant the scene ran: drop or exact
 *     Hessian, with or without line search, any inner solve, whose step error
 *     stays <= 1e-6 at every start state; the report names it); it "can fail": at least
 *     one cell of the regime map has one-step error > 1% or a diverging
 *     trajectory. Reproduced when both hold, partly when one does. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"
#include "pareto.h"
#include <clothbench/status.h>
#include "stats.h"

/* I2 and I3: their entries in claims_list.h */

#define I2_LOCAL 0.1
#define I2_FLOOR 1e-11
#define I2_TARGET 1.8
#define SPEEDUP_MIN 2.0
#define I3_CONVERGED_ERR 1e-6 /* a "converged" variant's step error at every start state */

static int side_table(const char *dir, const char *suffix, cb_table *t, cb_claim_result *out) {
  char path[4096];
  snprintf(path, sizeof path, "%s/newton_vs_bw_%s", dir, suffix);
  if (cb_table_read(path, t) == CB_OK) return 0;
  out->verdict = CB_NOT_RUN;
  cb_claim_reason(out, "%s is missing or unreadable: run build/newton_vs_bw.", path);
  return -1;
}

/* ---- I2 ------------------------------------------------------------------ */

enum { I2_VARIANTS = 16, I2_MAXIT = 512, I2_MAXSTEPS = 4096 };
/* The claim's subject: the reference Newton (exact Hessian, shifted where A
 * is indefinite, line search), and the lecture's fix it is contrasted with. */
#define I2_SUBJECT "exact_or_shift"
#define I2_FIX "drop"

/* The Newton variants of the CSV, (definiteness, line search), in its order of
 * definiteness treatments with line search first, the subject's first:
 * variant 0 is the subject. Returns how many (at most I2_VARIANTS). */
static int i2_variants(const cb_table *t, int cd, int cl, char def[][32], int *ls) {
  char names[I2_VARIANTS][32];
  int nn = 0, nv = 0;
  snprintf(names[nn++], 32, "%s", I2_SUBJECT);
  for (int r = 0; r < t->nrows && nn < I2_VARIANTS; r++) {
    int seen = 0;
    for (int k = 0; k < nn && !seen; k++) seen = !strcmp(names[k], cb_table_str(t, r, cd));
    if (!seen) snprintf(names[nn++], 32, "%s", cb_table_str(t, r, cd));
  }
  for (int k = 0; k < nn; k++)
    for (int l = 1; l >= 0; l--) {
      int found = 0;
      for (int r = 0; r < t->nrows && !found; r++)
        found = !strcmp(cb_table_str(t, r, cd), names[k]) && cb_table_int(t, r, cl) == l;
      if ((found || (k == 0 && l == 1)) && nv < I2_VARIANTS) { /* the subject's row even if it was not run */
        snprintf(def[nv], 32, "%s", names[k]);
        ls[nv++] = l;
      }
    }
  return nv;
}

typedef struct {
  int runs, ok, reach8, with_order, ls_steps, ls_iters, shifted_iters;
  double orders[I2_MAXSTEPS];
  char fails[1024], ls_where[1024];
} i2_stat;

void cb_check_newton_vs_bw_i2(const cb_table *main_csv, const char *dir, cb_claim_result *out) {
  (void)main_csv;
  cb_table t;
  if (side_table(dir, "i2.csv", &t, out)) return;
  int cd = cb_table_col(&t, "definiteness"), cl = cb_table_col(&t, "line_search"), cs = cb_table_col(&t, "step"),
      ci = cb_table_col(&t, "iter"), cg = cb_table_col(&t, "grad_norm_n"), ca = cb_table_col(&t, "alpha"),
      ch = cb_table_col(&t, "hessian"), cst = cb_table_col(&t, "step_status");
  if (cd < 0 || cl < 0 || cs < 0 || ci < 0 || cg < 0 || ca < 0 || ch < 0 || cst < 0) {
    cb_claim_reason(out, "newton_vs_bw_i2.csv lacks a needed column.");
    cb_table_free(&t);
    return;
  }
  static i2_stat S[I2_VARIANTS];
  memset(S, 0, sizeof S);
  char var_def[I2_VARIANTS][32];
  int var_ls[I2_VARIANTS], nvar = i2_variants(&t, cd, cl, var_def, var_ls), fix = -1;
  for (int v = 0; v < nvar; v++)
    if (fix < 0 && !strcmp(var_def[v], I2_FIX) && var_ls[v] == 1) fix = v;
  double g[I2_MAXIT];
  int use[I2_MAXIT];
  for (int r = 0; r < t.nrows;) { /* one run = consecutive rows from iter 0 */
    int end = r + 1;
    while (end < t.nrows && cb_table_num(&t, end, ci) > 0) end++;
    int v = -1;
    for (int k = 0; k < nvar; k++)
      if (!strcmp(cb_table_str(&t, r, cd), var_def[k]) && cb_table_int(&t, r, cl) == var_ls[k]) v = k;
    if (v >= 0) {
      i2_stat *s = &S[v];
      int n = end - r < I2_MAXIT ? end - r : I2_MAXIT, reduced = 0, r8 = 0, own = 1;
      for (int i = 0; i < n; i++) {
        g[i] = cb_table_num(&t, r + i, cg);
        if (g[i] <= 1e-8 * g[0]) r8 = 1;
        const char *hs = cb_table_str(&t, r + i, ch);
        use[i] = !strcmp(hs, "exact");
        if (strcmp(hs, "-") && strcmp(hs, var_def[v])) own = 0; /* a Hessian other than the treatment's own */
        if (cb_table_num(&t, r + i, ca) < 1) reduced++;
        if (!strcmp(cb_table_str(&t, r + i, ch), "shifted")) s->shifted_iters++;
      }
      s->runs++;
      s->reach8 += r8;
      const char *status = cb_table_str(&t, r, cst);
      if (!strcmp(status, "ok")) s->ok++;
      else if (strlen(s->fails) < sizeof s->fails - 32)
        snprintf(s->fails + strlen(s->fails), sizeof s->fails - strlen(s->fails), "%s%s at step %s",
                 s->fails[0] ? "; " : "", status, cb_table_str(&t, r, cs));
      s->ls_iters += reduced;
      s->ls_steps += reduced > 0;
      if (reduced && strlen(s->ls_where) < sizeof s->ls_where - 24)
        snprintf(s->ls_where + strlen(s->ls_where), sizeof s->ls_where - strlen(s->ls_where), "%s%s (%d)",
                 s->ls_where[0] ? ", " : "", cb_table_str(&t, r, cs), reduced);
      double p;
      if (s->with_order < I2_MAXSTEPS && cb_convergence_order(g, use, n, I2_LOCAL, I2_FLOOR, &p, NULL) == 0)
        s->orders[s->with_order++] = p;
      else if (own && s->with_order < I2_MAXSTEPS && /* e.g. drop: any Hessian (it is the run's only one) */
               cb_convergence_order(g, NULL, n, I2_LOCAL, I2_FLOOR, &p, NULL) == 0)
        s->orders[s->with_order++] = p;
    }
    r = end;
  }
  cb_table_free(&t);
  cb_claim_numbers(out, "Each run: Newton with CHOLMOD from one state of the stretched trajectory, to relative |grad "
                        "F| "
                        "1e-14 or the round-off floor (max|dx| <= 1e-12 x mesh size), at most 60 iterations "
                        "(exact_or_shift: 500).\n\n"
                        "| Newton variant | line search | steps | reached the tolerance | reached 1e-8 | steps with an "
                        "order estimate | median order | min | max | steps with alpha < 1 | iterations with alpha < 1 "
                        "| "
                        "shifted iterations |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  double med[I2_VARIANTS];
  int reach[I2_VARIANTS];
  for (int v = 0; v < nvar; v++) {
    i2_stat *s = &S[v];
    reach[v] = 0;
    for (int i = 0; i < s->with_order; i++) reach[v] += s->orders[i] >= I2_TARGET;
    med[v] = cb_median(s->orders, s->with_order); /* sorts */
    cb_claim_numbers(out, "| %s | %s | %d | %d | %d | %d | %.3g | %.3g | %.3g | %d | %d | %d |\n", var_def[v],
                     var_ls[v] ? "yes" : "no", s->runs, s->ok, s->reach8, s->with_order, med[v],
                     s->with_order ? s->orders[0] : NAN, s->with_order ? s->orders[s->with_order - 1] : NAN,
                     s->ls_steps, s->ls_iters, s->shifted_iters);
  }
  for (int v = 0; v < nvar; v++)
    if (S[v].ls_where[0])
      cb_claim_numbers(out, "\n%s, line search: alpha < 1 at steps (iterations): %s.\n", var_def[v], S[v].ls_where);
  for (int v = 1; v < nvar; v++)
    if (S[v].fails[0])
      cb_claim_numbers(out, "\n%s Hessian, line search %s, did not reach the tolerance: %s.\n", var_def[v],
                       var_ls[v] ? "on" : "off", S[v].fails);
  int n = S[0].with_order;
  if (S[0].runs == 0) {
    out->verdict = CB_NOT_RUN;
    cb_claim_reason(out, "No exact_or_shift runs in newton_vs_bw_i2.csv.");
  } else if (n >= 5 && med[0] >= I2_TARGET) {
    out->verdict = CB_REPRODUCED;
    cb_claim_reason(out,
                    "Newton with the exact Hessian converges with median order %.2f (>= %.1f) over %d steps of the "
                    "stretched hanging cloth; %d of %d steps reach %.1f.",
                    med[0], I2_TARGET, n, reach[0], n, I2_TARGET);
  } else if (n >= 1 && (med[0] >= 1.5 || reach[0] > 0)) {
    out->verdict = CB_PARTLY;
    cb_claim_reason(out, "Median order %.2f over %d steps (target %.1f); %d steps reach it.", med[0], n, I2_TARGET,
                    reach[0]);
  } else {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out, "Median order %.2f over %d steps with an estimate (target %.1f).", med[0], n, I2_TARGET);
  }
  if (fix >= 0 && S[fix].with_order)
    cb_claim_reason(out,
                    " With the lecture's drop fix the order is %.2f (median): the modified Hessian converges "
                    "linearly once springs are compressed.",
                    med[fix]);
}

/* ---- I3 ------------------------------------------------------------------ */

enum { I3_MAXM = 256 };
typedef struct {
  char key[96], method[32], inner[24];
  int ls, n, failed;
  cb_claim_timing wall[64]; /* per start state: its median, spread and repeats */
  double err_max;
} i3_point;

static int is_failure(const char *status) { /* fixed-K methods end at max_iters by design */
  return strcmp(status, "ok") && strcmp(status, "max_iters");
}

/* Aggregates the rows of one scene: median wall_ms over start states, max step_error (Inf if a step failed). */
static int i3_points(const cb_table *t, const char *scene, i3_point *P) {
  int csc = cb_table_col(t, "scene"), cm = cb_table_col(t, "method"), cin = cb_table_col(t, "inner_solver"),
      cl = cb_table_col(t, "line_search"), ce = cb_table_col(t, "step_error"), cw = cb_table_col(t, "wall_ms"),
      cst = cb_table_col(t, "status");
  if (csc < 0 || cm < 0 || cin < 0 || cl < 0 || ce < 0 || cw < 0 || cst < 0) return -1;
  int np = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (strcmp(cb_table_str(t, r, csc), scene)) continue;
    char key[96];
    snprintf(key, sizeof key, "%s/%s/%s", cb_table_str(t, r, cm), cb_table_str(t, r, cin), cb_table_str(t, r, cl));
    int p = 0;
    while (p < np && strcmp(P[p].key, key)) p++;
    if (p == np) {
      if (np == I3_MAXM) continue;
      memset(&P[np], 0, sizeof P[np]);
      snprintf(P[np].key, sizeof P[np].key, "%s", key);
      snprintf(P[np].method, sizeof P[np].method, "%s", cb_table_str(t, r, cm));
      snprintf(P[np].inner, sizeof P[np].inner, "%s", cb_table_str(t, r, cin));
      P[np].ls = cb_table_int(t, r, cl);
      np++;
    }
    double e = cb_table_num(t, r, ce);
    if (is_failure(cb_table_str(t, r, cst)) || !isfinite(e)) e = INFINITY, P[p].failed = 1;
    if (P[p].n == 0 || e > P[p].err_max) P[p].err_max = e;
    if (P[p].n < 64) P[p].wall[P[p].n++] = cb_claim_timing_at(t, r, "wall_ms");
  }
  return np;
}


/* Trajectory summary (reported, not part of the verdict): per method the RMS
 * position error against the converged trajectory at the end, the first
 * failing step, and the time-discretisation error at the same time. */
static void trajectories(const char *dir, cb_claim_result *out) {
  cb_table t, d;
  char path[4096];
  snprintf(path, sizeof path, "%s/newton_vs_bw_traj.csv", dir);
  if (cb_table_read(path, &t)) return;
  int cm = cb_table_col(&t, "method"), ci = cb_table_col(&t, "inner_solver"), cl = cb_table_col(&t, "line_search"),
      cs = cb_table_col(&t, "step"), ct = cb_table_col(&t, "t_s"), ce = cb_table_col(&t, "pos_error_m"),
      cst = cb_table_col(&t, "status"), cE = cb_table_col(&t, "energy_j"), cR = cb_table_col(&t, "ref_energy_j");
  if (cm < 0 || ci < 0 || cl < 0 || cs < 0 || ct < 0 || ce < 0 || cst < 0 || cE < 0 || cR < 0) {
    cb_table_free(&t);
    return;
  }
  cb_claim_numbers(out, "\nTrajectories of the lab scene against the converged trajectory at the same dt:\n\n"
                        "| method | inner | line search | t end (s) | RMS position error at the end (m) | max (m) | "
                        "E - E_ref at the end (J) | first failing step |\n|---|---|---|---|---|---|---|---|\n");
  double tend = 0;
  for (int r = 0; r < t.nrows; r++) {
    int last = r + 1 == t.nrows || cb_table_num(&t, r + 1, cs) == 0;
    if (!last || !strcmp(cb_table_str(&t, r, cm), "reference")) continue;
    int r0 = r;
    while (r0 > 0 && cb_table_num(&t, r0, cs) > 0) r0--;
    double emax = 0;
    for (int q = r0; q <= r; q++)
      if (cb_table_num(&t, q, ce) > emax) emax = cb_table_num(&t, q, ce);
    const char *st = cb_table_str(&t, r, cst);
    int failed = strcmp(st, "ok") && strcmp(st, "max_iters");
    if (cb_table_num(&t, r, ct) > tend) tend = cb_table_num(&t, r, ct);
    cb_claim_numbers(out, "| %s | %s | %s | %.3g | %.2e | %.2e | %.3g | %s%s%s |\n", cb_table_str(&t, r, cm),
                     cb_table_str(&t, r, ci), cb_table_num(&t, r, cl) > 0 ? "yes" : "no", cb_table_num(&t, r, ct),
                     cb_table_num(&t, r, ce), emax, cb_table_num(&t, r, cE) - cb_table_num(&t, r, cR),
                     failed ? cb_table_str(&t, r, cs) : "-", failed ? " " : "", failed ? st : "");
  }
  cb_table_free(&t);
  snprintf(path, sizeof path, "%s/newton_vs_bw_dt.csv", dir);
  if (cb_table_read(path, &d)) return;
  int dt_ = cb_table_col(&d, "t_s"), de = cb_table_col(&d, "pos_error_m");
  if (dt_ >= 0 && de >= 0 && d.nrows > 0)
    cb_claim_numbers(out,
                     "\nTime-discretisation error (converged implicit Euler at dt against dt/16), RMS position: "
                     "%.2e m at t = %.3g s.\n",
                     cb_table_num(&d, d.nrows - 1, de), cb_table_num(&d, d.nrows - 1, dt_));
  cb_table_free(&d);
}

void cb_check_newton_vs_bw_i3(const cb_table *t, const char *dir, cb_claim_result *out) {
  static i3_point P[I3_MAXM];
  static cb_claim_timing ct[I3_MAXM];
  double cost[I3_MAXM], err[I3_MAXM];
  int front[I3_MAXM], fast_all = 1, fast_undecided = 0, scenes = 0;
  char undecided[4096] = "";
  const double levels[3] = {1e-2, 1e-3, 1e-6};
  char speeds[1024] = "", b1[128], b2[128], b3[160];
  cb_claim_repeats reps = {0};
  cb_claim_numbers(out, "Step error = max over start states of |x - x*|_M / |x* - x0|_M; time = median wall_ms over "
                        "start states of each state's median over its repeats, in brackets the spread over the repeats "
                        "(per repeat the median over the states; the methods ran in interleaved rounds, so the "
                        "speed-up's "
                        "spread is of paired repeats); failed steps count as infinite error. The converged baseline is "
                        "the fastest converged Newton variant of the scene (step error <= 1e-6 at every state): "
                        "newton_converged is the drop fix, newton_converged_exact the exact Hessian (shifted where "
                        "A is not SPD).\n\n"
                        "| scene | K = 1 (CHOLMOD) ms | fastest converged Newton: ms | speed-up | K = 1 error | "
                        "cheapest at 1e-2 | cheapest at 1e-3 | cheapest at 1e-6 | Pareto front |\n"
                        "|---|---|---|---|---|---|---|---|---|\n");
  int cscene = cb_table_col(t, "scene");
  if (cscene < 0) {
    cb_claim_reason(out, "newton_vs_bw.csv lacks a needed column.");
    return;
  }
  enum { I3_MAXS = 64 };
  const char *done[I3_MAXS];
  int ndone = 0;
  for (int r = 0; r < t->nrows && ndone < I3_MAXS; r++) { /* every scene of the CSV, in its order */
    const char *scene = cb_table_str(t, r, cscene);
    int seen = 0;
    for (int q = 0; q < ndone && !seen; q++) seen = !strcmp(done[q], scene);
    if (seen) continue;
    done[ndone++] = scene;
    int np = i3_points(t, scene, P);
    if (np < 0) {
      cb_claim_reason(out, "newton_vs_bw.csv lacks a needed column.");
      return;
    }
    if (np == 0) continue;
    scenes++;
    int bw = -1, conv = -1;
    for (int p = 0; p < np; p++) {
      ct[p] = cb_claim_timing_median(P[p].wall, P[p].n);
      cost[p] = ct[p].med; /* the median over states of the states' medians: what the verdict uses */
      cb_claim_repeats_add(&reps, &ct[p]);
      err[p] = P[p].err_max;
      if (!strcmp(P[p].inner, "cholmod") && P[p].ls == 0 && !strcmp(P[p].method, "newton_k1")) bw = p;
      int converged = !strncmp(P[p].method, "newton_converged", 16) && !P[p].failed && err[p] <= I3_CONVERGED_ERR;
      if (converged && (conv < 0 || cost[p] < cost[conv])) conv = p; /* the fastest converged Newton */
    }
    cb_pareto_front(np, cost, err, front);
    double speed = bw >= 0 && conv >= 0 ? cost[conv] / cost[bw] : NAN;
    cb_claim_timing sp = cb_claim_timing_value(NAN);
    if (bw >= 0 && conv >= 0) sp = cb_claim_timing_ratio(&ct[conv], &ct[bw]);
    /* at least 2x over the speed-up's whole spread (paired repeats), below it, or undecided */
    int side = bw >= 0 && conv >= 0 ? cb_claim_timing_side_ge(&sp, SPEEDUP_MIN, 1) : -1;
    if (!(speed >= SPEEDUP_MIN) && side > 0) side = 0; /* a bound that does not hold the median */
    if (side < 0) fast_all = 0;
    if (side == 0) {
      fast_undecided++;
      char u[1024], what[160];
      snprintf(what, sizeof what, "on %s the speed-up", scene);
      cb_claim_undecided_text(u, sizeof u, what, "%.2f", &sp, "x", SPEEDUP_MIN);
      if (strlen(undecided) + strlen(u) + 8 < sizeof undecided)
        snprintf(undecided + strlen(undecided), sizeof undecided - strlen(undecided), "%s%s", undecided[0] ? "; " : "",
                 u);
    }
    if (bw >= 0 && conv >= 0 && strlen(speeds) < sizeof speeds - 200)
      snprintf(speeds + strlen(speeds), sizeof speeds - strlen(speeds), "%s%s %s against %s %s%s",
               speeds[0] ? "; " : "", scene, cb_claim_spread_long(b3, sizeof b3, "%.1f", &sp, "x"), P[conv].method,
               P[conv].inner, P[conv].ls ? " +LS" : "");
    cb_claim_numbers(out, "| %s | %s | %s%s%s%s%s%s | %s | %.2g |", scene,
                     bw >= 0 ? cb_claim_spread(b1, sizeof b1, "%.3g", &ct[bw], "") : "-",
                     conv >= 0 ? P[conv].method : "none", conv >= 0 ? " " : "", conv >= 0 ? P[conv].inner : "",
                     conv >= 0 && P[conv].ls ? " +LS" : "", conv >= 0 ? ": " : "",
                     conv >= 0 ? cb_claim_spread(b2, sizeof b2, "%.3g", &ct[conv], "") : "-",
                     cb_claim_spread(b3, sizeof b3, "%.1f", &sp, ""), bw >= 0 ? err[bw] : NAN);
    for (int l = 0; l < 3; l++) {
      int c = cb_cheapest_at(np, cost, err, levels[l]);
      if (c < 0) cb_claim_numbers(out, " none |");
      else
        cb_claim_numbers(out, " %s %s%s (%s ms, %.1e) |", P[c].method, P[c].inner, P[c].ls ? " +LS" : "",
                         cb_claim_spread(b1, sizeof b1, "%.3g", &ct[c], ""), err[c]);
    }
    int first = 1;
    for (int p = 0; p < np; p++)
      if (front[p]) {
        cb_claim_numbers(out, "%s%s %s%s", first ? " " : "; ", P[p].method, P[p].inner, P[p].ls ? " +LS" : "");
        first = 0;
      }
    cb_claim_numbers(out, " |\n");
  }
  if (reps.lo > 0) {
    char rt[64];
    cb_claim_numbers(out, "\nTimes are medians of %s per start state.\n", cb_claim_repeats_text(rt, sizeof rt, &reps));
  }
  /* the regime map */
  cb_table rg;
  if (side_table(dir, "regime.csv", &rg, out)) return;
  int cdt = cb_table_col(&rg, "dt_s"), ck = cb_table_col(&rg, "k_n_per_m"), cs = cb_table_col(&rg, "stretch"),
      cf = cb_table_col(&rg, "k1_fails"), cdv = cb_table_col(&rg, "first_diverged_step"),
      cem = cb_table_col(&rg, "step_error_max"), crs = cb_table_col(&rg, "ref_status");
  int cells = 0, fails = 0, diverged = 0, ref_bad = 0;
  if (cdt < 0 || ck < 0 || cs < 0 || cf < 0 || cdv < 0 || cem < 0 || crs < 0) {
    cb_claim_reason(out, "newton_vs_bw_regime.csv lacks a needed column.");
    cb_table_free(&rg);
    return;
  }
  cb_claim_numbers(out, "\nK = 1 regime map (one-step error: max over the sampled states of its own trajectory; D = "
                        "trajectory "
                        "diverged, E = error > 1%%, . = fine):\n\n| stretch | k (N/m) | dt (s): cells "
                        "|\n|---|---|---|\n");
  for (int r = 0; r < rg.nrows; r++) {
    cells++;
    int f = cb_table_int(&rg, r, cf), d = cb_table_num(&rg, r, cdv) >= 0;
    fails += f;
    diverged += d;
    ref_bad += strcmp(cb_table_str(&rg, r, crs), "ok") != 0;
    int newrow = r == 0 || cb_table_num(&rg, r, ck) != cb_table_num(&rg, r - 1, ck) ||
                 cb_table_num(&rg, r, cs) != cb_table_num(&rg, r - 1, cs);
    if (newrow)
      cb_claim_numbers(out, "%s| %g | %g |", r ? " |\n" : "", cb_table_num(&rg, r, cs), cb_table_num(&rg, r, ck));
    cb_claim_numbers(out, " 1/%.0f:%s", 1.0 / cb_table_num(&rg, r, cdt), d ? "D" : f ? "E" : ".");
  }
  if (cells) cb_claim_numbers(out, " |\n");
  cb_table_free(&rg);
  cb_claim_numbers(out, "\n%d of %d cells fail (%d diverge); the reference did not converge in %d cells.\n", fails,
                   cells, diverged, ref_bad);
  trajectories(dir, out);
  int can_fail = fails > 0;
  if (speeds[0] && scenes > 0 && cells > 0)
    cb_claim_reason(out, "Speed-up of K = 1 over the fastest converged Newton: %s. ", speeds);
  if (scenes > 0 && cells > 0 && fast_all && fast_undecided > 0) {
    /* some scene's speed-up straddles 2x and none lies below it: the verdict it would have either way */
    cb_verdict yes = can_fail ? CB_REPRODUCED : CB_PARTLY, no = can_fail ? CB_PARTLY : CB_NOT_REPRODUCED;
    out->verdict = cb_claim_verdict_either(yes, no);
    cb_claim_reason(out,
                    "Undecided (within the spread): %s with every speed-up at least %.0fx, %s without; K = 1 fails in "
                    "%d of %d regime cells. %s.",
                    cb_verdict_name(yes), SPEEDUP_MIN, cb_verdict_name(no), fails, cells, undecided);
  } else if (scenes == 0 || cells == 0) {
    out->verdict = CB_NOT_RUN;
    cb_claim_reason(out, "No step or regime rows.");
  } else if (fast_all && can_fail) {
    out->verdict = CB_REPRODUCED;
    cb_claim_reason(out,
                    "K = 1 is at least %.0fx faster than the fastest converged Newton on all %d scenes (over each "
                    "speed-up's whole spread), and it fails "
                    "(error > 1%% or divergence) in %d of %d (dt, k, stretch) cells.",
                    SPEEDUP_MIN, scenes, fails, cells);
  } else if (fast_all || can_fail) {
    out->verdict = CB_PARTLY;
    cb_claim_reason(out, "%s; K = 1 fails in %d of %d regime cells.",
                    fast_all ? "K = 1 is at least 2x faster than the fastest converged Newton on every scene"
                             : "K = 1 is not at least 2x faster on every scene",
                    fails, cells);
  } else {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out,
                    "K = 1 is neither at least %.0fx faster than the fastest converged Newton on every scene nor "
                    "failing in any "
                    "regime cell.",
                    SPEEDUP_MIN);
  }
}
