/* Checkers for the linear_solvers experiment (claims J1-J4). Every number
 * comes from results/linear_solvers.csv (one row per scene, sweep, solver,
 * parameters and iteration) and results/linear_solvers_scenes.csv (the
 * spectra of D^-1 A per captured matrix). A run is a maximal block of
 * consecutive rows with the same scene, sweep, solver, alpha and rho. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"
#include "solve_trace.h"
#include "spectrum.h"
#include <clothbench/solver.h>
#include <clothbench/status.h>


typedef struct {
  const char *scene, *sweep, *solver, *status;
  double alpha, rho;
  int r0, r1; /* rows [r0, r1) */
  int last_iter;
  double last_rel, last_wall, last_err, wall0;
  int it6;                       /* first iteration with rel_residual <= 1e-6, or -1 */
  double wall6, rate, rate_prev; /* residual ratio per iteration over [3/4 N, N] and [N/2, 3/4 N] */
  int row6, row0;                /* rows of it6 and of iteration 0 (-1 if none) */
} run_t;

typedef struct {
  cb_table sc; /* the scenes CSV */
  int ok;
  run_t *runs;
  int nruns;
} data_t;

enum { C_SCENE, C_SWEEP, C_SOLVER, C_ALPHA, C_RHO, C_ITER, C_REL, C_WALL, C_STATUS, C_ERR, NCOL };
static const char *colnames[NCOL] = {"scene", "sweep",        "solver",  "alpha",  "rho",
                                     "iter",  "rel_residual", "wall_ms", "status", "error"};

static int load(const cb_table *csv, const char *dir, data_t *d, cb_claim_result *out) {
  memset(d, 0, sizeof *d);
  int c[NCOL];
  for (int i = 0; i < NCOL; i++)
    if ((c[i] = cb_table_col(csv, colnames[i])) < 0) {
      cb_claim_reason(out, "linear_solvers.csv has no column '%s'.", colnames[i]);
      return 0;
    }
  char path[4096];
  snprintf(path, sizeof path, "%s/linear_solvers_scenes.csv", dir);
  if (cb_table_read(path, &d->sc)) {
    cb_claim_reason(out, "%s is missing or unreadable: run build/linear_solvers.", path);
    return 0;
  }
  d->ok = 1;
  d->runs = calloc((size_t)csv->nrows + 1, sizeof *d->runs);
  cb_trace_row *rows = calloc((size_t)csv->nrows + 1, sizeof *rows);
  if (!d->runs || !rows) {
    free(rows);
    cb_claim_reason(out, "out of memory");
    return 0;
  }
  for (int r = 0; r < csv->nrows;) {
    run_t *u = &d->runs[d->nruns++];
    u->r0 = r;
    int e = r + 1;
    while (e < csv->nrows && cb_table_num(csv, e, c[C_ITER]) > cb_table_num(csv, e - 1, c[C_ITER])) {
      int same = 1;
      for (int k = C_SCENE; k <= C_RHO; k++)
        same = same && !strcmp(cb_table_str(csv, e, c[k]), cb_table_str(csv, r, c[k]));
      if (!same) break;
      e++;
    }
    u->r1 = e;
    u->scene = cb_table_str(csv, r, c[C_SCENE]);
    u->sweep = cb_table_str(csv, r, c[C_SWEEP]);
    u->solver = cb_table_str(csv, r, c[C_SOLVER]);
    u->status = cb_table_str(csv, r, c[C_STATUS]);
    u->alpha = cb_table_num(csv, r, c[C_ALPHA]);
    u->rho = cb_table_num(csv, r, c[C_RHO]);
    u->last_iter = cb_table_int(csv, e - 1, c[C_ITER]);
    u->last_rel = cb_table_num(csv, e - 1, c[C_REL]);
    u->last_wall = cb_table_num(csv, e - 1, c[C_WALL]);
    u->last_err = cb_table_num(csv, e - 1, c[C_ERR]);
    u->wall0 = cb_table_num(csv, r, c[C_ITER]) == 0 ? cb_table_num(csv, r, c[C_WALL]) : 0;
    u->row0 = cb_table_num(csv, r, c[C_ITER]) == 0 ? r : -1;
    u->row6 = -1;
    u->it6 = -1;
    u->wall6 = NAN;
    for (int k = r; k < e; k++) {
      rows[k - r] = (cb_trace_row){cb_table_int(csv, k, c[C_ITER]), cb_table_num(csv, k, c[C_REL]),
                                   cb_table_num(csv, k, c[C_WALL]), cb_table_num(csv, k, c[C_ERR])};
      if (u->it6 < 0 && rows[k - r].rel_residual <= 1e-6) {
        u->it6 = rows[k - r].iter;
        u->wall6 = rows[k - r].wall_ms;
        u->row6 = k;
      }
    }
    u->rate = cb_trace_rate(rows, e - r, 0.25);
    u->rate_prev = cb_trace_rate_window(rows, e - r, 0.5, 0.75);
    r = e;
  }
  free(rows);
  return 1;
}

static void unload(data_t *d) {
  if (d->ok) cb_table_free(&d->sc);
  free(d->runs);
}

/* Timings of a run with their spread over the repeats (main table rows): at a row, at 1e-6, at the
 * last row, and its set-up (the iteration-0 row; 0 if the run has none). */
static cb_claim_timing t_row(const cb_table *csv, int row) { return cb_claim_timing_at(csv, row, "wall_ms"); }
static cb_claim_timing t_6(const cb_table *csv, const run_t *u) {
  return u->row6 >= 0 ? t_row(csv, u->row6) : cb_claim_timing_value(NAN);
}
static cb_claim_timing t_last(const cb_table *csv, const run_t *u) { return t_row(csv, u->r1 - 1); }
static cb_claim_timing t_0(const cb_table *csv, const run_t *u) {
  return u->row0 >= 0 ? t_row(csv, u->row0) : cb_claim_timing_value(0);
}

/* Scene row and a number from it (NaN if missing). */
static int scene_row(const data_t *d, const char *scene) {
  int c = cb_table_col(&d->sc, "scene");
  for (int r = 0; r < d->sc.nrows; r++)
    if (!strcmp(cb_table_str(&d->sc, r, c), scene)) return r;
  return -1;
}
static double sc_num(const data_t *d, const char *scene, const char *col) {
  return cb_table_num(&d->sc, scene_row(d, scene), cb_table_col(&d->sc, col));
}
/* Extreme eigenvalues of D^-1 A: GSL dense where computed, else Lanczos. */
static void spectrum(const data_t *d, const char *scene, double *lmin, double *lmax, int *dense) {
  *lmin = sc_num(d, scene, "lmin_dense");
  *lmax = sc_num(d, scene, "lmax_dense");
  *dense = !isnan(*lmin) && !isnan(*lmax);
  if (!*dense) {
    *lmin = sc_num(d, scene, "lmin_lanczos");
    *lmax = sc_num(d, scene, "lmax_lanczos");
  }
}
static const run_t *find(const data_t *d, const char *scene, const char *sweep, const char *solver) {
  for (int i = 0; i < d->nruns; i++)
    if (!strcmp(d->runs[i].scene, scene) && !strcmp(d->runs[i].sweep, sweep) && !strcmp(d->runs[i].solver, solver))
      return &d->runs[i];
  return NULL;
}
/* The distinct solvers of the main sweep that the registry does not flag as
 * direct, in the CSV's order (a name the registry does not know, e.g. from
 * another build, counts as iterative). names has room for d->nruns. */
static int iterative_solvers(const data_t *d, const char **names) {
  int n = 0;
  for (int i = 0; i < d->nruns; i++) {
    const run_t *u = &d->runs[i];
    const cb_solver_type *t = cb_solver_type_find(u->solver);
    if (strcmp(u->sweep, "main") || (t && (t->flags & CB_SOLVER_DIRECT))) continue;
    int seen = 0;
    for (int k = 0; k < n && !seen; k++) seen = !strcmp(names[k], u->solver);
    if (!seen) names[n++] = u->solver;
  }
  return n;
}
static int diverged(const run_t *u) { return !strcmp(u->status, "diverged"); }
/* Converging: stopped at the tolerance, or still shrinking when cut at max_iters. */
static int converging(const run_t *u) {
  return !strcmp(u->status, "ok") || (!strcmp(u->status, "max_iters") && u->rate < 1);
}
/* Iteration exponent ratio ln(measured)/ln(predicted) - 1 (0 = perfect). */
static double rate_dev(double measured, double predicted) { return log(measured) / log(predicted) - 1; }

void cb_check_j1(const cb_table *csv, const char *dir, cb_claim_result *out) {
  data_t d;
  if (!load(csv, dir, &d, out)) {
    unload(&d);
    return;
  }
  int nsc = 0, vanilla_div = 0, disagree = 0, nrate = 0, bad_rate = 0, nshort = 0, dd_conv = 0;
  double worst = 0, spec_diff = 0;
  cb_claim_numbers(out, "| scene | non-DD rows / n | lambda(D^-1 A) dense | lambda Lanczos | 2/lambda_max | "
                        "rho(alpha=1) | alpha = 1 |\n|---|---|---|---|---|---|---|\n");
  for (int r = 0; r < d.sc.nrows; r++) {
    const char *s = cb_table_str(&d.sc, r, cb_table_col(&d.sc, "scene"));
    int has_runs = find(&d, s, "alpha", "jacobi") != NULL;
    nsc += has_runs;
    double lmin, lmax, ld = sc_num(&d, s, "lmin_dense"), hd = sc_num(&d, s, "lmax_dense");
    double ll = sc_num(&d, s, "lmin_lanczos"), hl = sc_num(&d, s, "lmax_lanczos");
    int dense, nondd = cb_table_int_of(sc_num(&d, s, "non_dd_rows"));
    spectrum(&d, s, &lmin, &lmax, &dense);
    if (dense) spec_diff = fmax(spec_diff, fmax(fabs(ld - ll) / ld, fabs(hd - hl) / hd));
    const run_t *v = NULL;
    for (int i = 0; i < d.nruns; i++)
      if (!strcmp(d.runs[i].scene, s) && !strcmp(d.runs[i].solver, "jacobi") && d.runs[i].alpha == 1.0) v = &d.runs[i];
    double rho1 = cb_jacobi_rho(lmin, lmax, 1.0);
    if (v && nondd > 0 && lmin > 0 && rho1 > 1 && diverged(v)) vanilla_div++;
    if (v && nondd == 0 && converging(v)) dd_conv++;
    char dz[64] = "-";
    if (dense) snprintf(dz, sizeof dz, "[%.6g, %.6g]", ld, hd);
    char van[64] = "spectrum only (no runs)";
    if (v) snprintf(van, sizeof van, "%s (rate %.4f)", v->status, v->rate);
    cb_claim_numbers(out, "| %s | %d / %d | %s | [%.6g, %.6g] | %.4g | %.4f | %s |\n", s, nondd,
                     cb_table_int_of(sc_num(&d, s, "n_dofs")), dz, ll, hl, 2 / lmax, rho1, van);
  }
  cb_claim_numbers(out, "\n| scene | alpha / (2/lambda_max) | predicted rho | measured rate, last quarter (exponent "
                        "deviation) | previous quarter | iterations | status | agrees "
                        "|\n|---|---|---|---|---|---|---|---|\n");
  for (int i = 0; i < d.nruns; i++) {
    const run_t *u = &d.runs[i];
    if (strcmp(u->solver, "jacobi") || isnan(u->alpha)) continue;
    double lmin, lmax;
    int dense;
    spectrum(&d, u->scene, &lmin, &lmax, &dense);
    double p = cb_jacobi_rho(lmin, lmax, u->alpha);
    int ok = p < 1 ? converging(u) : diverged(u);
    disagree += !ok;
    const char *rt = "";
    /* settled: the rate over the last quarter agrees with the previous quarter's (5% in the exponent) */
    int settled = isfinite(u->rate_prev) && fabs(rate_dev(u->rate, u->rate_prev)) <= 0.05;
    if (isfinite(u->rate) && !settled) {
      nshort++;
      rt = " (rate not settled)";
    }
    if (isfinite(u->rate) && settled) {
      double dev = rate_dev(u->rate, p);
      nrate++;
      if (fabs(dev) > 0.15) {
        bad_rate++;
        rt = " (rate off)";
      }
      worst = fmax(worst, fabs(dev));
    }
    cb_claim_numbers(out, "| %s | %.3f | %.5f | %.5f (%+.1f%%) | %.5f | %d | %s | %s%s |\n", u->scene,
                     u->alpha * lmax / 2, p, u->rate, 100 * rate_dev(u->rate, p), u->rate_prev, u->last_iter, u->status,
                     ok ? "yes" : "no", rt);
  }
  cb_claim_numbers(out,
                   "\nPredicted rho from GSL's dense eigenvalues where computed, else Lanczos (top) and shift-invert "
                   "Lanczos (bottom); "
                   "largest relative difference between the two: %.2g. Measured rate: geometric mean of the residual "
                   "ratios over the last quarter of the run; "
                   "compared with the prediction when the run has settled on its rate (the last and the previous "
                   "quarter agree within 5%% "
                   "in the exponent ln rate); the exponent deviation is ln(measured)/ln(predicted) - 1.\n",
                   spec_diff);
  if (nsc == 0) {
    cb_claim_reason(out, "No alpha sweep in the CSV.");
    unload(&d);
    return;
  }
  out->verdict = vanilla_div > 0 && disagree == 0 ? (bad_rate == 0 ? CB_REPRODUCED : CB_PARTLY) : CB_NOT_REPRODUCED;
  cb_claim_reason(out,
                  "Vanilla Jacobi diverged on %d non-diagonally-dominant SPD matrices where rho(I - D^-1 A) > 1; "
                  "%d of the Jacobi runs disagree with the prediction (converge iff alpha < 2/lambda_max); "
                  "the measured rate is within 15%% of the predicted rho in the iteration exponent "
                  "(ln rate / ln rho) on %d of %d runs that settled on their rate (worst deviation %.1f%%; %d runs "
                  "whose "
                  "rate had not settled by the end of the run are not compared).",
                  vanilla_div, disagree, nrate - bad_rate, nrate, 100 * worst, nshort);
  if (dd_conv)
    cb_claim_reason(out, " On %d diagonally dominant matrix(es) vanilla Jacobi converged, as dominance guarantees.",
                    dd_conv);
  unload(&d);
}

/* J2: reproduced when Chebyshev needs 10x fewer iterations and 10x less wall time on every scene; partly
 * when it needs fewer iterations everywhere and 10x fewer iterations or time somewhere. */
static cb_verdict j2_verdict(int n, int it10, int wall10, int faster_it) {
  return it10 == n && wall10 == n                     ? CB_REPRODUCED
         : faster_it == n && (it10 > 0 || wall10 > 0) ? CB_PARTLY
                                                      : CB_NOT_REPRODUCED;
}

void cb_check_j2(const cb_table *csv, const char *dir, cb_claim_result *out) {
  data_t d;
  if (!load(csv, dir, &d, out)) {
    unload(&d);
    return;
  }
  /* context: the other iterative solvers of the CSV */
  const char **ctx = calloc((size_t)d.nruns + 1, sizeof *ctx);
  if (!ctx) {
    cb_claim_reason(out, "out of memory");
    unload(&d);
    return;
  }
  int nctx = 0, nit = iterative_solvers(&d, ctx);
  for (int k = 0; k < nit; k++)
    if (strcmp(ctx[k], "jacobi") && strcmp(ctx[k], "chebyshev")) ctx[nctx++] = ctx[k];
  int n = 0, it10 = 0, wall10 = 0, wall10_undecided = 0, faster_it = 0, faster_wall = 0, solve10 = 0, paired = 0,
      bounded = 0;
  char undecided[4096] = "";
  cb_claim_repeats reps = {0};
  cb_claim_timing best = cb_claim_timing_value(NAN);
  double best_rw = -INFINITY;
  char best_scene[64] = "";
  cb_claim_numbers(out, "| scene | alpha | Jacobi iters | Jacobi ms | Chebyshev iters | Chebyshev ms; of it the rho "
                        "estimate | speed-up iters | speed-up wall | wall without set-up |");
  for (int k = 0; k < nctx; k++) cb_claim_numbers(out, " %s iters / ms |", ctx[k]);
  cb_claim_numbers(out, "\n|---|---|---|---|---|---|---|---|---|");
  for (int k = 0; k < nctx; k++) cb_claim_numbers(out, "---|");
  cb_claim_numbers(out, "\n");
  for (int r = 0; r < d.sc.nrows; r++) {
    const char *s = cb_table_str(&d.sc, r, cb_table_col(&d.sc, "scene"));
    const run_t *j = find(&d, s, "main", "jacobi"), *c = find(&d, s, "main", "chebyshev");
    if (!j || !c) continue;
    n++;
    if (c->it6 < 0) {
      cb_claim_numbers(out, "| %s | %.4g | %d | %.4g | not reached (%s) | | | |", s, j->alpha, j->it6, j->wall6,
                       c->status);
      for (int k = 0; k < nctx; k++) cb_claim_numbers(out, " |");
      cb_claim_numbers(out, "\n");
      continue;
    }
    int lb = j->it6 < 0; /* Jacobi did not reach 1e-6: the ratios are lower bounds */
    double ji = lb ? j->last_iter : j->it6, jw = lb ? j->last_wall : j->wall6;
    double ri = ji / c->it6, rw = jw / c->wall6, rs = (jw - j->wall0) / (c->wall6 - c->wall0);
    it10 += ri >= 10;
    solve10 += rs >= 10;
    faster_it += ri > 1;
    faster_wall += rw > 1;
    /* the same numbers with their spread over the repeats (paired: the solvers ran in interleaved rounds) */
    cb_claim_timing tj = lb ? t_last(csv, j) : t_6(csv, j), tc = t_6(csv, c), tj0 = t_0(csv, j), tc0 = t_0(csv, c);
    cb_claim_timing trw = cb_claim_timing_ratio(&tj, &tc), dj = cb_claim_timing_diff(&tj, &tj0),
                    dc = cb_claim_timing_diff(&tc, &tc0);
    cb_claim_timing trs = cb_claim_timing_ratio(&dj, &dc);
    cb_claim_repeats_add(&reps, &tj);
    cb_claim_repeats_add(&reps, &tc);
    /* at least 10x in wall time over the speed-up's whole spread, below it, or undecided */
    int side = cb_claim_timing_side_ge(&trw, 10, 1);
    wall10 += side > 0;
    if (side == 0) {
      wall10_undecided++;
      char u[1024], what[160];
      snprintf(what, sizeof what, "on %s the wall-time speed-up", s);
      cb_claim_undecided_text(u, sizeof u, what, "%.2f", &trw, "x", 10);
      if (strlen(undecided) + strlen(u) + 8 < sizeof undecided)
        snprintf(undecided + strlen(undecided), sizeof undecided - strlen(undecided), "%s%s", undecided[0] ? "; " : "",
                 u);
    }
    if (trw.paired) paired++;
    else if (cb_claim_timing_has_spread(&trw)) bounded++;
    char b1[96], b2[96], b3[96], b4[96], b5[96];
    cb_claim_numbers(out, "| %s | %.4g | %s%.0f | %s%s | %d | %s; %s | %s%.1f | %s%s | %s%s |", s, j->alpha,
                     lb ? ">" : "", ji, lb ? ">" : "", cb_claim_spread(b1, sizeof b1, "%.4g", &tj, ""), c->it6,
                     cb_claim_spread(b2, sizeof b2, "%.4g", &tc, ""), cb_claim_spread(b3, sizeof b3, "%.3g", &tc0, ""),
                     lb ? ">=" : "", ri, lb ? ">=" : "", cb_claim_spread(b4, sizeof b4, "%.2f", &trw, ""),
                     lb ? ">=" : "", cb_claim_spread(b5, sizeof b5, "%.1f", &trs, ""));
    if (rw > best_rw) {
      best_rw = rw;
      best = trw;
      snprintf(best_scene, sizeof best_scene, "%s", s);
    }
    for (int k = 0; k < nctx; k++) {
      const run_t *g = find(&d, s, "main", ctx[k]);
      cb_claim_timing tg = g ? t_6(csv, g) : cb_claim_timing_value(NAN);
      cb_claim_numbers(out, " %d / %s |", g ? g->it6 : -1, cb_claim_spread(b1, sizeof b1, "%.3g", &tg, ""));
    }
    cb_claim_numbers(out, "\n");
  }
  free(ctx);
  cb_claim_numbers(out, "\nTo a relative residual of 1e-6 from x = 0; both at the same alpha = alpha* = 2/(lambda_min "
                        "+ lambda_max) of D^-1 A "
                        "(Jacobi's best weight, given to it for free); Chebyshev's wall time includes its automatic "
                        "rho estimate "
                        "(after the semicolon: its set-up time, the estimate). 'Wall without set-up' compares the "
                        "iterations' time only, "
                        "as when rho is reused across Newton iterations. '>' : Jacobi stopped at max_iters above "
                        "1e-6.\n");
  char rt[64];
  if (cb_claim_repeats_text(rt, sizeof rt, &reps)[0])
    cb_claim_numbers(out,
                     "\nEvery time is the median of %s, in brackets the fastest and slowest; the solvers of a scene "
                     "ran in "
                     "interleaved rounds, and the speed-ups' spreads are %s.\n",
                     rt,
                     bounded == 0  ? "of paired repeats (repeat i of Jacobi over repeat i of Chebyshev)"
                     : paired == 0 ? "bounds (the fastest of one over the slowest of the other)"
                                   : "of paired repeats where both list their repeats, else bounds");
  if (n == 0) {
    cb_claim_reason(out, "No Jacobi/Chebyshev main runs in the CSV.");
    unload(&d);
    return;
  }
  /* the verdict with the undecided scenes' wall-time speed-ups all below 10x and all at or above it */
  cb_verdict vlo = j2_verdict(n, it10, wall10, faster_it),
             vhi = j2_verdict(n, it10, wall10 + wall10_undecided, faster_it);
  out->verdict = cb_claim_verdict_either(vlo, vhi);
  cb_claim_reason(out,
                  "Chebyshev needs fewer iterations than Jacobi on %d of %d scenes, at least 10x fewer on %d; "
                  "its wall time including the rho estimate is shorter on %d and at least 10x shorter on %d "
                  "(over the speed-up's whole spread)%s; "
                  "without the set-up (rho reused) at least 10x shorter on %d.",
                  faster_it, n, it10, faster_wall, wall10,
                  wall10_undecided ? ", undecided within the spread on more" : "", solve10);
  if (wall10_undecided)
    cb_claim_reason(out, " Undecided (within the spread): %s if those %d scene(s) are below 10x, %s if not: %s.",
                    cb_verdict_name(vlo), wall10_undecided, cb_verdict_name(vhi), undecided);
  if (best_scene[0]) {
    char b[128];
    cb_claim_reason(out, " The largest wall-time speed-up: %s on %s.",
                    cb_claim_spread_long(b, sizeof b, "%.2f", &best, "x"), best_scene);
  }
  unload(&d);
}

void cb_check_j3(const cb_table *csv, const char *dir, cb_claim_result *out) {
  data_t d;
  if (!load(csv, dir, &d, out)) {
    unload(&d);
    return;
  }
  int div_over = 0, div_under = 0, nover = 0, nunder = 0, div_true1 = 0, ntrue1 = 0;
  int d995 = -1, d95 = -1;
  cb_claim_repeats reps = {0};
  cb_claim_numbers(out, "| scene | alpha | true rho(I - alpha D^-1 A) | rho given | iterations to 1e-6 | status "
                        "|\n|---|---|---|---|---|---|\n");
  for (int i = 0; i < d.nruns; i++) {
    const run_t *u = &d.runs[i];
    if (strcmp(u->sweep, "rho")) continue;
    double lmin, lmax;
    int dense;
    spectrum(&d, u->scene, &lmin, &lmax, &dense);
    double t = cb_jacobi_rho(lmin, lmax, u->alpha), astar = 2 / (lmin + lmax);
    int dv = diverged(u), is_star = fabs(u->alpha - astar) <= 1e-9 * astar;
    if (t >= 1) {
      ntrue1++;
      div_true1 += dv;
    } else if (u->rho > t) {
      nover++;
      div_over += dv;
    } else {
      nunder++;
      div_under += dv;
    }
    if (t < 1 && is_star && fabs(u->rho - 0.995) < 1e-9) d995 = dv;
    if (t < 1 && is_star && fabs(u->rho - 0.95) < 1e-9) d95 = dv;
    char it[32] = "-";
    if (u->it6 >= 0) snprintf(it, sizeof it, "%d", u->it6);
    cb_claim_numbers(out, "| %s | %.4f%s | %.6f | %.6g | %s | %s |\n", u->scene, u->alpha, is_star ? " (alpha*)" : "",
                     t, u->rho, it, u->status);
  }
  cb_claim_numbers(out, "\nAutomatic rho (Lanczos, widened by its Ritz residuals) against the true rho(I - alpha D^-1 "
                        "A):\n\n| scene | alpha | auto rho | true rho | status | rho estimate ms "
                        "|\n|---|---|---|---|---|---|\n");
  for (int i = 0; i < d.nruns; i++) {
    const run_t *u = &d.runs[i];
    if (!(!strcmp(u->sweep, "main") && !strcmp(u->solver, "chebyshev")) && strcmp(u->sweep, "rho_auto")) continue;
    double lmin, lmax;
    int dense;
    spectrum(&d, u->scene, &lmin, &lmax, &dense);
    cb_claim_timing t0 = t_0(csv, u);
    char b[96];
    cb_claim_repeats_add(&reps, &t0);
    cb_claim_numbers(out, "| %s | %.4f | %.6f | %.6f | %s | %s |\n", u->scene, u->alpha, u->rho,
                     cb_jacobi_rho(lmin, lmax, u->alpha), u->status, cb_claim_spread(b, sizeof b, "%.3g", &t0, ""));
  }
  char rt[64];
  if (cb_claim_repeats_text(rt, sizeof rt, &reps)[0])
    cb_claim_numbers(out, "\nThe estimate's time is the median of %s, in brackets the fastest and slowest.\n", rt);
  double rl = sc_num(&d, "lab", "rho_lab");
  if (!isnan(rl))
    cb_claim_numbers(out,
                     "\nThe lab's own iteration (alpha = 1 with the constant diagonal m/dt^2 + 4k) has the true "
                     "spectral radius "
                     "rho(I - A/(m/dt^2 + 4k)) = %.4f on the lab matrix: there 0.995 is an overestimate and 0.95 an "
                     "underestimate.\n",
                     rl);
  if (nover + nunder == 0) {
    cb_claim_reason(out, "No rho sweep at a convergent alpha in the CSV.");
    unload(&d);
    return;
  }
  if (div_over == nover && d995 == 1 && d95 == 0) out->verdict = CB_REPRODUCED;
  else if (div_over + div_under == 0) out->verdict = CB_NOT_REPRODUCED;
  else out->verdict = CB_PARTLY;
  cb_claim_reason(out,
                  "Where the true rho(I - alpha D^-1 A) < 1, %d of %d overestimates and %d of %d underestimates "
                  "diverged; "
                  "rho = 0.995 at alpha* %s and 0.95 %s. Where the true rho >= 1 (alpha past 2/lambda_max), %d of %d "
                  "runs "
                  "diverged whatever rho was given: divergence is decided by the true spectral radius, not by the "
                  "estimate. ",
                  div_over, nover, div_under, nunder,
                  d995 < 0 ? "was not run"
                  : d995   ? "diverged"
                           : "converged",
                  d95 < 0 ? "was not run"
                  : d95   ? "diverged"
                          : "converged",
                  div_true1, ntrue1);
  if (out->verdict == CB_NOT_REPRODUCED)
    cb_claim_reason(out, "In these linear solves a wrong rho only slows Chebyshev down (see the iterations); the lab's "
                         "0.995 does not diverge on these systems (the lab's own nonlinear iteration is panel (a), "
                         "experiment nonlinear).");
  unload(&d);
}

/* ---- J4: the scaling family (linear_solvers_scaling.csv) --------------------------------------
 *
 * Every solver solves A x = b with b = A x* for a manufactured x*, from x = 0, to an error
 * |x - x*|/|x*| <= 1e-6 (CHOLMOD in one shot); wall_ms is analyse + factor + solve, the solvers of a
 * size timed in interleaved rounds. Per size the best iterative solver is the one with the smallest
 * median time among those that reached 1e-6.
 *   exact:        CHOLMOD's error against x* <= J4_EXACT at every size (100x below the target);
 *   controllable: at every size some iterative solver reaches 1e-6 (its iteration count sets it);
 *   cheap:        an iteration of the best iterative solver costs less than a CHOLMOD solve;
 *   expensive:    a crossover: the smallest size from which, at every larger measured size too,
 *                 CHOLMOD's time exceeds the best iterative solver's time to 1e-6.
 * Reproduced: all four. Partly: exact and controllable, but no crossover up to the largest size
 * ("expensive" not reproduced) or iterations not cheaper. Not reproduced: CHOLMOD not exact or no
 * iterative solver reaches 1e-6 at some size. Each method's time is fitted as C n^p over the dofs n
 * (its largest three sizes that reached the target); a crossover beyond the sizes run is only
 * extrapolated from those fits, never counted. */
#define J4_EXACT 1e-8
#define J4_TARGET 1e-6
enum { J4_MAXS = 16, J4_MAXSOLV = 16 };

typedef struct {
  int grid, dofs, chol, best; /* rows of CHOLMOD and of the best iterative solver (-1: none) */
  double cond;
} j4_size;

static double j4_num(const cb_table *t, int r, const char *col) { return cb_table_num(t, r, cb_table_col(t, col)); }
static int j4_reached(const cb_table *t, int r) {
  return !strcmp(cb_table_str(t, r, cb_table_col(t, "status")), "ok") && j4_num(t, r, "error") <= J4_TARGET;
}

/* exponent p of wall = C dofs^p over the largest (up to) three sizes where solver reached the target */
static int j4_fit(const cb_table *t, const char *solver, double *p, double *logc, int *g0, int *g1) {
  double x[J4_MAXS], y[J4_MAXS];
  int gs[J4_MAXS], m = 0;
  for (int r = 0; r < t->nrows && m < J4_MAXS; r++)
    if (!strcmp(cb_table_str(t, r, cb_table_col(t, "solver")), solver) && j4_reached(t, r) &&
        j4_num(t, r, "wall_ms") > 0) {
      x[m] = log(j4_num(t, r, "n_dofs"));
      y[m] = log(j4_num(t, r, "wall_ms"));
      gs[m++] = cb_table_int_of(j4_num(t, r, "grid_n"));
    }
  int k = m > 3 ? m - 3 : 0;
  if (m - k < 2) return 0;
  cb_fit_line(x + k, y + k, m - k, p, logc);
  *g0 = gs[k];
  *g1 = gs[m - 1];
  return 1;
}

void cb_check_j4(const cb_table *csv, const char *dir, cb_claim_result *out) {
  (void)csv;
  cb_table t;
  if (cb_claim_side_table(dir, "linear_solvers", "scaling", &t, out)) return;
  static const char *const need[] = {"scene",          "grid_n",         "n_dofs",    "solver",   "iters_to_err",
                                     "error",          "analyze_ms",     "factor_ms", "solve_ms", "wall_ms",
                                     "capped_wall_ms", "lmax_over_lmin", "status"};
  int idx[sizeof need / sizeof *need];
  if (cb_claim_columns(&t, need, idx, (int)(sizeof need / sizeof *need), "linear_solvers_scaling.csv", out)) {
    cb_table_free(&t);
    return;
  }
  j4_size sz[J4_MAXS];
  const char *solv[J4_MAXSOLV];
  int ns = 0, nsolv = 0, cs = cb_table_col(&t, "solver"), cg = cb_table_col(&t, "grid_n");
  for (int r = 0; r < t.nrows; r++) {
    const char *so = cb_table_str(&t, r, cs);
    const cb_solver_type *ty = cb_solver_type_find(so);
    int direct = ty && (ty->flags & CB_SOLVER_DIRECT), g = cb_table_int(&t, r, cg), k = 0;
    if (!so[0]) continue; /* a scene whose capture failed */
    while (k < ns && sz[k].grid != g) k++;
    if (k == ns) {
      if (ns == J4_MAXS) continue;
      sz[ns++] = (j4_size){g, cb_table_int_of(j4_num(&t, r, "n_dofs")), -1, -1, j4_num(&t, r, "lmax_over_lmin")};
    }
    if (direct) {
      if (!strcmp(so, "cholmod") || sz[k].chol < 0) sz[k].chol = r;
      continue;
    }
    int seen = 0;
    for (int q = 0; q < nsolv; q++) seen |= !strcmp(solv[q], so);
    if (!seen && nsolv < J4_MAXSOLV) solv[nsolv++] = so;
    if (j4_reached(&t, r) && (sz[k].best < 0 || j4_num(&t, r, "wall_ms") < j4_num(&t, sz[k].best, "wall_ms")))
      sz[k].best = r;
  }
  int exact = 0, control = 0, cheap = 0, cheap_undecided = 0, nchol = 0;
  cb_claim_repeats reps = {0};
  cb_claim_numbers(out, "| grid | dofs | cond(D^-1 A) | CHOLMOD ms (analyse + factor + solve), error | of it factor + "
                        "solve | best iterative to 1e-6: solver, iterations, ms | CHOLMOD / best |");
  for (int q = 0; q < nsolv; q++) cb_claim_numbers(out, " %s ms |", solv[q]);
  cb_claim_numbers(out, "\n|---|---|---|---|---|---|---|");
  for (int q = 0; q < nsolv; q++) cb_claim_numbers(out, "---|");
  cb_claim_numbers(out, "\n");
  int costly[J4_MAXS], costly_fs[J4_MAXS];
  for (int k = 0; k < ns; k++) {
    const j4_size *z = &sz[k];
    costly[k] = costly_fs[k] = 0;
    char b1[96], b2[96], b3[96];
    cb_claim_timing tc = z->chol >= 0 ? cb_claim_timing_at(&t, z->chol, "wall_ms") : cb_claim_timing_value(NAN);
    cb_claim_timing tb = z->best >= 0 ? cb_claim_timing_at(&t, z->best, "wall_ms") : cb_claim_timing_value(NAN);
    double ce = z->chol >= 0 ? j4_num(&t, z->chol, "error") : NAN;
    int chol_ok = z->chol >= 0 && !strcmp(cb_table_str(&t, z->chol, cb_table_col(&t, "status")), "ok");
    nchol += chol_ok;
    exact += chol_ok && ce <= J4_EXACT;
    control += z->best >= 0;
    if (chol_ok && z->best >= 0) {
      double it = j4_num(&t, z->best, "iters_to_err");
      double per = (j4_num(&t, z->best, "solve_ms")) / (it > 0 ? it : 1);
      /* an iteration cheaper than CHOLMOD (per / CHOLMOD below 1) and CHOLMOD costlier than the best
         iterative solver (CHOLMOD / best above 1), each over its ratio's whole spread, or undecided */
      cb_claim_timing tper = cb_claim_timing_value(per), rper = cb_claim_timing_ratio(&tper, &tc);
      int cs_side = cb_claim_timing_side_ge(&rper, 1, 1);
      cheap += cs_side < 0;
      cheap_undecided += cs_side == 0;
      cb_claim_timing rk = cb_claim_timing_ratio(&tc, &tb);
      costly[k] = cb_claim_timing_side_ge(&rk, 1, 0);
      costly_fs[k] = j4_num(&t, z->chol, "factor_ms") + j4_num(&t, z->chol, "solve_ms") > tb.med;
      cb_claim_repeats_add(&reps, &tc);
      cb_claim_repeats_add(&reps, &tb);
    }
    cb_claim_timing ratio = cb_claim_timing_ratio(&tc, &tb);
    cb_claim_numbers(out, "| %d^2 | %d | %.3g | %s, %.1e | %.3g | ", z->grid, z->dofs, z->cond,
                     cb_claim_spread(b1, sizeof b1, "%.3g", &tc, ""), ce,
                     z->chol >= 0 ? j4_num(&t, z->chol, "factor_ms") + j4_num(&t, z->chol, "solve_ms") : NAN);
    if (z->best >= 0)
      cb_claim_numbers(
          out, "%s, %d, %s | %s |", cb_table_str(&t, z->best, cs), cb_table_int_of(j4_num(&t, z->best, "iters_to_err")),
          cb_claim_spread(b2, sizeof b2, "%.3g", &tb, ""), cb_claim_spread(b3, sizeof b3, "%.3g", &ratio, "x"));
    else cb_claim_numbers(out, "none reached 1e-6 | - |");
    for (int q = 0; q < nsolv; q++) {
      int r = -1;
      for (int i = 0; i < t.nrows && r < 0; i++)
        if (cb_table_int(&t, i, cg) == z->grid && !strcmp(cb_table_str(&t, i, cs), solv[q])) r = i;
      if (r < 0) cb_claim_numbers(out, " - |");
      else if (j4_reached(&t, r)) cb_claim_numbers(out, " %.3g |", j4_num(&t, r, "wall_ms"));
      else
        cb_claim_numbers(out, " > %.3g (%s within its %.3g ms) |", j4_num(&t, r, "capped_wall_ms"),
                         cb_table_str(&t, r, cb_table_col(&t, "status")), j4_num(&t, r, "budget_ms"));
    }
    cb_claim_numbers(out, "\n");
  }
  /* crossover: the smallest size from which every larger size has CHOLMOD costlier too */
  int cross = -1, cross_fs = -1,
      cross_opt = -1; /* cross: undecided sizes counted as not costlier; cross_opt: as costlier */
  for (int k = ns - 1; k >= 0 && costly[k] > 0; k--) cross = k;
  for (int k = ns - 1; k >= 0 && costly[k] >= 0; k--) cross_opt = k;
  for (int k = ns - 1; k >= 0 && costly_fs[k]; k--) cross_fs = k; /* the same with CHOLMOD's analysis reused */
  /* growth exponents */
  double pc = NAN, lc = NAN;
  int g0, g1, have_c = j4_fit(&t, "cholmod", &pc, &lc, &g0, &g1);
  cb_claim_numbers(out, "\nGrowth of the time to error 1e-6 with the dofs n, fitted as C n^p over each method's "
                        "largest three sizes that reached it:\n\n| method | p | sizes |\n|---|---|---|\n");
  if (have_c) cb_claim_numbers(out, "| cholmod | %.2f | %d^2-%d^2 |\n", pc, g0, g1);
  double pbest = NAN, lbest = NAN;
  char bname_buf[64];
  const char *bname = ns > 0 && sz[ns - 1].best >= 0 ? cb_table_str(&t, sz[ns - 1].best, cs) : NULL;
  for (int q = 0; q < nsolv; q++) {
    double p, l;
    if (!j4_fit(&t, solv[q], &p, &l, &g0, &g1)) {
      cb_claim_numbers(out, "| %s | - | reached 1e-6 at fewer than 2 sizes |\n", solv[q]);
      continue;
    }
    cb_claim_numbers(out, "| %s | %.2f | %d^2-%d^2 |\n", solv[q], p, g0, g1);
    if (bname && !strcmp(bname, solv[q])) {
      pbest = p;
      lbest = l;
    }
  }
  /* memory (issue 36): each solver's peak resident memory beyond the captured system, in its first timed solve
     (a column that older runs lack: then the table is left out) */
  int cmem = cb_table_col(&t, "mem_peak_mib");
  if (cmem >= 0) {
    cb_claim_numbers(out, "\nPeak memory of one solve (MiB resident beyond the captured system; '-': not timed):\n\n"
                          "| grid | CHOLMOD | best iterative |");
    for (int q = 0; q < nsolv; q++) cb_claim_numbers(out, " %s |", solv[q]);
    cb_claim_numbers(out, "\n|---|---|---|");
    for (int q = 0; q < nsolv; q++) cb_claim_numbers(out, "---|");
    cb_claim_numbers(out, "\n");
    for (int k = 0; k < ns; k++) {
      const j4_size *z = &sz[k];
      double mc = z->chol >= 0 ? cb_table_num(&t, z->chol, cmem) : NAN;
      double mb = z->best >= 0 ? cb_table_num(&t, z->best, cmem) : NAN;
      char a[32] = "-", bb[32] = "-";
      if (!isnan(mc)) snprintf(a, sizeof a, "%.4g", mc);
      if (!isnan(mb)) snprintf(bb, sizeof bb, "%.4g", mb);
      cb_claim_numbers(out, "| %d^2 | %s | %s |", z->grid, a, bb);
      for (int q = 0; q < nsolv; q++) {
        double m = NAN;
        for (int i = 0; i < t.nrows; i++)
          if (cb_table_int(&t, i, cg) == z->grid && !strcmp(cb_table_str(&t, i, cs), solv[q]))
            m = cb_table_num(&t, i, cmem);
        if (isnan(m)) cb_claim_numbers(out, " - |");
        else cb_claim_numbers(out, " %.4g |", m);
      }
      cb_claim_numbers(out, "\n");
    }
  }
  char rt[64], last_ratio[128] = "-", margin[1024] = "";
  cb_claim_timing last = cb_claim_timing_value(NAN);
  if (ns > 0 && sz[ns - 1].chol >= 0 && sz[ns - 1].best >= 0) {
    cb_claim_timing a = cb_claim_timing_at(&t, sz[ns - 1].chol, "wall_ms"),
                    bb = cb_claim_timing_at(&t, sz[ns - 1].best, "wall_ms");
    last = cb_claim_timing_ratio(&a, &bb);
    cb_claim_spread_long(last_ratio, sizeof last_ratio, "%.2f", &last, "x");
    cb_claim_margin_text(margin, sizeof margin, "%.2f", &last, "x", 1);
  }
  /* what the timing part of the verdict depends on: the machine the scaling table was measured on */
  char hw[512];
  {
    const char *kern = cb_table_meta(&t, "blas_kernel");
    char kb[128];
    snprintf(kb, sizeof kb, "%s", kern ? kern : "not recorded");
    const char *cpu = cb_table_meta(&t, "cpu");
    snprintf(hw, sizeof hw, "the OpenBLAS kernel %s on %s", kb, cpu ? cpu : "an unrecorded CPU");
  }
  cb_claim_numbers(out,
                   "\nb = A x* for a manufactured x* (a smooth field plus 10%% noise), error |x - x*|/|x*|, never "
                   "against CHOLMOD; "
                   "every time is analyse + factor + solve from x = 0 with a fresh solver; an iterative solver runs "
                   "exactly its iterations "
                   "to 1e-6 (found by a traced run); '>': it did not get there within its budget (a multiple of "
                   "CHOLMOD's time), the time "
                   "is a lower bound. Jacobi-type solvers are given alpha* for free; Chebyshev's rho estimate is "
                   "counted. 'Of it factor + solve': "
                   "CHOLMOD with its symbolic analysis reused, as inside a Newton loop (medians of the parts; context, "
                   "not the verdict).%s%s%s\n",
                   cb_claim_repeats_text(rt, sizeof rt, &reps)[0] ? " Every time is the median of " : "", rt,
                   rt[0] ? ", in brackets the fastest and slowest, the solvers of a size in interleaved rounds "
                           "(ratios: paired repeats)."
                         : "");
  if (bname) { /* outlives the table */
    snprintf(bname_buf, sizeof bname_buf, "%s", bname);
    bname = bname_buf;
  }
  cb_table_free(&t);
  if (ns == 0 || nchol == 0) {
    cb_claim_reason(out, "No CHOLMOD rows in linear_solvers_scaling.csv.");
    return;
  }
  int base = exact == ns && control == ns;
  /* the verdict with every undecided comparison against the claim, and with every one for it */
  cb_verdict vlo = base && cheap == ns && cross >= 0 ? CB_REPRODUCED : base ? CB_PARTLY : CB_NOT_REPRODUCED;
  cb_verdict vhi = base && cheap + cheap_undecided == ns && cross_opt >= 0 ? CB_REPRODUCED
                   : base                                                  ? CB_PARTLY
                                                                           : CB_NOT_REPRODUCED;
  out->verdict = cb_claim_verdict_either(vlo, vhi);
  cb_claim_reason(out,
                  "Manufactured solutions at %d mesh sizes, %d^2 to %d^2: CHOLMOD is exact in one shot (error against "
                  "x* <= %.0e) on %d; "
                  "an iterative solver reaches error 1e-6 on %d (controllable), with an iteration cheaper than a "
                  "CHOLMOD solve on %d. ",
                  ns, sz[0].grid, sz[ns - 1].grid, J4_EXACT, exact, control, cheap);
  if (cheap_undecided)
    cb_claim_reason(out,
                    "On %d more sizes an iteration's cost against a CHOLMOD solve is undecided within the spread. ",
                    cheap_undecided);
  if (cross < 0 && cross_opt >= 0) {
    cb_claim_reason(out,
                    "Whether there is a crossover is undecided: at %d^2, the largest size, CHOLMOD / %s: %s. "
                    "Undecided (within the spread): %s with a crossover, %s without. ",
                    sz[ns - 1].grid, bname ? bname : "-", margin, cb_verdict_name(vhi), cb_verdict_name(vlo));
  } else if (cross >= 0) {
    cb_claim_reason(out,
                    "Crossover at %d^2 (%d dofs)%s: from there on CHOLMOD (analyse + factor + solve) costs more than "
                    "the best iterative "
                    "solver's time to 1e-6 (at %d^2: %s, against %s). ",
                    sz[cross].grid, sz[cross].dofs, cross == 0 ? ", the smallest size run, so at or below it" : "",
                    sz[ns - 1].grid, last_ratio, bname);
  } else {
    int nc = 0;
    for (int k = 0; k < ns; k++) nc += costly[k] > 0;
    cb_claim_reason(out,
                    "No crossover up to %d^2: CHOLMOD costs more than the best iterative solver's time to 1e-6 on %d "
                    "of %d sizes, "
                    "but not at %d^2, so there is no size from which it stays the costlier and \"expensive\" is not "
                    "reproduced "
                    "(at %d^2: CHOLMOD / %s = %s). ",
                    sz[ns - 1].grid, nc, ns, sz[ns - 1].grid, sz[ns - 1].grid, bname ? bname : "-", last_ratio);
  }
  if (cross_fs >= 0)
    cb_claim_reason(out, "With CHOLMOD's analysis reused (factor + solve only) the crossover is at %d^2. ",
                    sz[cross_fs].grid);
  else
    cb_claim_reason(out, "With CHOLMOD's analysis reused (factor + solve only) there is no crossover up to %d^2. ",
                    sz[ns - 1].grid);
  if (have_c && !isnan(pbest)) {
    cb_claim_reason(out, "Time grows as n^%.2f for CHOLMOD and n^%.2f for %s (the best iterative solver at %d^2)", pc,
                    pbest, bname, sz[ns - 1].grid);
    if (cross < 0 && pbest < pc) {
      double nx = exp((lbest - lc) / (pc - pbest)); /* C_c n^pc = C_b n^pb */
      cb_claim_reason(out, "; extrapolated, the two would cross near %.0f dofs (about %.0f^2 vertices), not measured",
                      nx, sqrt(nx / 3));
    } else if (cross < 0)
      cb_claim_reason(out, ": CHOLMOD's time grows the more slowly, so its advantage widens with n");
    else if (pbest > pc) {
      double nx = exp((lbest - lc) / (pc - pbest));
      cb_claim_reason(out,
                      ": the gap closes with n, and extrapolated CHOLMOD would be the cheaper again above about %.0f "
                      "dofs "
                      "(%.0f^2 vertices), not measured",
                      nx, sqrt(nx / 3));
    }
    cb_claim_reason(out, ".");
  }
  if (ns > 0 && sz[ns - 1].chol >= 0 && sz[ns - 1].best >= 0 && !(cross < 0 && cross_opt >= 0))
    cb_claim_reason(out, " The deciding ratio, CHOLMOD / %s at %d^2 (the largest size) against 1: %s.",
                    bname ? bname : "-", sz[ns - 1].grid, margin);
  cb_claim_reason(out,
                  " The crossover depends on the hardware: CHOLMOD's supernodal factorisation runs on dense BLAS "
                  "kernels, the iterative solvers on sparse products bound by memory bandwidth; measured with %s.",
                  hw);
}
