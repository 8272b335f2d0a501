/* Checkers for the definiteness experiment (claims H1, H2). Every number
 * comes from results/definiteness.csv (one row per Newton iterate of every
 * scene x policy run), results/definiteness_runs.csv (one row per run) and
 * results/definiteness_pair.csv (the spring pair held still, in 1D/2D/3D).
 *
 * A Newton matrix counts as indefinite when CHOLMOD's LL' met a non-positive
 * pivot or when its smallest eigenvalue estimate is below 0 (a Lanczos Ritz
 * value is never below the true lambda_min, so min_eig < 0 proves it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "claims.h"
#include <clothbench/status.h>

enum { MAXS = 16, MAXP = 8 };
/* The claims' subjects: the exact Hessian (no fix) and the lecture's fix.
 * Every other policy of the CSV is another fix. */
#define POLICY_EXACT "none"
#define POLICY_LECTURE "drop"

enum { C_SCENE, C_POLICY, C_STEP, C_SYSTEM, C_SPD, C_MINEIG, C_SPDX, C_MINEIGX, C_COMP, C_CGBD, C_STATUS, NCOL };
static const char *const colnames[NCOL] = {"scene",
                                           "policy",
                                           "step",
                                           "system",
                                           "spd",
                                           "min_eig_n_per_m",
                                           "spd_exact",
                                           "min_eig_exact_n_per_m",
                                           "compressed_frac",
                                           "cg_breakdown",
                                           "status"};

typedef struct {
  char scene[64];
  /* none run */
  int none_sys, none_indef, none_fail_step;
  double none_comp_max;
  /* exact matrix at every iterate of every run */
  int ex_sys, ex_indef, stretched_sys, stretched_indef, contradictions, unresolved;
  double comp_sum_indef; /* compressed fraction summed over exact-indefinite iterates */
  /* per policy (index into policies seen) */
  int sys[MAXP], spd_fail[MAXP], cg_bd[MAXP], ex_indef_p[MAXP];
} scene_t;

typedef struct {
  int c[NCOL];
  int nscene, npol;
  char pol[MAXP][32];
  scene_t sc[MAXS];
} data_t;

static int index_of(char names[][32], int *n, int cap, const char *s) {
  for (int i = 0; i < *n; i++)
    if (!strcmp(names[i], s)) return i;
  if (*n == cap) return -1;
  snprintf(names[*n], 32, "%s", s);
  return (*n)++;
}

static int load(const cb_table *csv, data_t *d, cb_claim_result *out) {
  memset(d, 0, sizeof *d);
  for (int i = 0; i < NCOL; i++)
    if ((d->c[i] = cb_table_col(csv, colnames[i])) < 0) {
      cb_claim_reason(out, "definiteness.csv has no column '%s'.", colnames[i]);
      return 0;
    }
  const int *c = d->c;
  for (int r = 0; r < csv->nrows; r++) {
    const char *sn = cb_table_str(csv, r, c[C_SCENE]), *pn = cb_table_str(csv, r, c[C_POLICY]);
    int si = -1;
    for (int k = 0; k < d->nscene; k++)
      if (!strcmp(d->sc[k].scene, sn)) si = k;
    if (si < 0 && d->nscene < MAXS) {
      si = d->nscene++;
      snprintf(d->sc[si].scene, sizeof d->sc[si].scene, "%s", sn);
      d->sc[si].none_fail_step = -1;
    }
    int pi = index_of(d->pol, &d->npol, MAXP, pn);
    if (si < 0 || pi < 0 || cb_table_num(csv, r, c[C_SYSTEM]) != 1) continue;
    scene_t *s = &d->sc[si];
    int spd = cb_table_num(csv, r, c[C_SPD]) == 1, spdx = cb_table_num(csv, r, c[C_SPDX]) == 1;
    double me = cb_table_num(csv, r, c[C_MINEIG]), mex = cb_table_num(csv, r, c[C_MINEIGX]);
    double comp = cb_table_num(csv, r, c[C_COMP]);
    s->sys[pi]++;
    s->spd_fail[pi] += !spd;
    s->cg_bd[pi] += cb_table_num(csv, r, c[C_CGBD]) == 1;
    if (!strcmp(pn, POLICY_EXACT)) {
      s->none_sys++;
      s->none_indef += !spd || me < 0;
      s->none_comp_max = fmax(s->none_comp_max, comp);
      if (!spd && s->none_fail_step < 0) s->none_fail_step = cb_table_int(csv, r, c[C_STEP]);
    }
    int indef = !spdx || mex < 0;
    s->ex_sys++;
    s->ex_indef += indef;
    s->ex_indef_p[pi] += indef;
    s->contradictions += spdx && mex < 0; /* CHOLMOD succeeded but a Ritz value < 0: impossible */
    s->unresolved += !spdx && !(mex < 0); /* CHOLMOD failed, Lanczos did not reach the negative eigenvalue */
    if (indef) s->comp_sum_indef += comp;
    if (comp == 0) {
      s->stretched_sys++;
      s->stretched_indef += indef;
    }
  }
  if (d->nscene == 0) {
    cb_claim_reason(out, "definiteness.csv has no Newton systems.");
    return 0;
  }
  return 1;
}

static int open_side(const char *dir, const char *name, cb_table *t, cb_claim_result *out) {
  char path[4096];
  snprintf(path, sizeof path, "%s/definiteness_%s.csv", dir, name);
  if (cb_table_read(path, t)) {
    cb_claim_reason(out, "%s is missing or unreadable: run build/definiteness.", path);
    return 0;
  }
  return 1;
}

void cb_check_h1(const cb_table *csv, const char *dir, cb_claim_result *out) {
  data_t *d = calloc(1, sizeof *d);
  cb_table pair;
  if (!d || !load(csv, d, out) || !open_side(dir, "pair", &pair, out)) {
    free(d);
    return;
  }
  cb_claim_numbers(out, "Newton systems per scene. `none`: the run with the exact Hessian, which stops at the first "
                        "CHOLMOD failure. `exact along <policy>`: the lecture's exact A = M/dt^2 + H_none evaluated at "
                        "every iterate of that policy's run (indefinite / systems).\n\n"
                        "| scene | none: indefinite / systems | none fails at step | none: max compressed fraction |");
  for (int p = 0; p < d->npol; p++)
    if (strcmp(d->pol[p], POLICY_EXACT)) cb_claim_numbers(out, " exact along %s |", d->pol[p]);
  cb_claim_numbers(out, " compressed fraction when indefinite (mean) | no spring compressed: systems (indefinite) "
                        "|\n|---|---|---|---|");
  for (int p = 0; p < d->npol; p++)
    if (strcmp(d->pol[p], POLICY_EXACT)) cb_claim_numbers(out, "---|");
  cb_claim_numbers(out, "---|---|\n");
  int scenes_indef = 0, scenes_exact = 0, stretched_indef = 0, contradictions = 0, unresolved = 0;
  for (int i = 0; i < d->nscene; i++) {
    const scene_t *s = &d->sc[i];
    char fail[32];
    snprintf(fail, sizeof fail, s->none_fail_step < 0 ? "-" : "%d", s->none_fail_step);
    cb_claim_numbers(out, "| %s | %d / %d | %s | %.3f |", s->scene, s->none_indef, s->none_sys, fail, s->none_comp_max);
    for (int p = 0; p < d->npol; p++)
      if (strcmp(d->pol[p], POLICY_EXACT)) cb_claim_numbers(out, " %d / %d |", s->ex_indef_p[p], s->sys[p]);
    cb_claim_numbers(out, " %.3f | %d (%d) |\n", s->ex_indef ? s->comp_sum_indef / s->ex_indef : 0.0, s->stretched_sys,
                     s->stretched_indef);
    scenes_indef += s->none_indef > 0;
    scenes_exact += s->ex_indef > 0;
    stretched_indef += s->stretched_indef;
    contradictions += s->contradictions;
    unresolved += s->unresolved;
  }
  /* the spring pair: 1D never indefinite; 2D/3D indefinite exactly where predicted */
  int cd = cb_table_col(&pair, "dim"), cp = cb_table_col(&pair, "policy"), cr = cb_table_col(&pair, "ratio"),
      ca = cb_table_col(&pair, "min_eig_a_n_per_m"), cq = cb_table_col(&pair, "predicted_min_eig_a_n_per_m"),
      cs = cb_table_col(&pair, "spd");
  int n1 = 0, n1_spd = 0, n23 = 0, n23_match = 0, n23_indef = 0;
  double worst = 0, thr = NAN;
  for (int r = 0; cd >= 0 && cp >= 0 && cr >= 0 && ca >= 0 && cq >= 0 && cs >= 0 && r < pair.nrows; r++) {
    if (strcmp(cb_table_str(&pair, r, cp), POLICY_EXACT) || !(cb_table_num(&pair, r, cr) < 1)) continue;
    int dim = cb_table_int(&pair, r, cd), spd = cb_table_num(&pair, r, cs) == 1;
    double a = cb_table_num(&pair, r, ca), q = cb_table_num(&pair, r, cq);
    worst = fmax(worst, fabs(a - q) / fmax(1.0, fabs(q)));
    if (dim == 1) {
      n1++;
      n1_spd += spd && a > 0;
      continue;
    }
    n23++;
    n23_match += spd == (q > 0);
    n23_indef += !spd;
    if (!spd && !(cb_table_num(&pair, r, cr) <= thr)) thr = cb_table_num(&pair, r, cr); /* largest indefinite ratio */
  }
  cb_claim_numbers(out,
                   "\nSpring pair held still (two springs compressed to l = ratio L between pins, `none`):\n\n"
                   "- 1D: A SPD at %d of %d compressions (E'' = k > 0).\n"
                   "- 2D/3D: A indefinite at %d of %d; a dense Cholesky (GSL) agrees with the sign of the predicted "
                   "lambda_min = "
                   "m/dt^2 + 2k(1 - L/l) at %d of %d; largest indefinite ratio %g; worst relative error of "
                   "lambda_min against the prediction %.2g.\n",
                   n1_spd, n1, n23_indef, n23, n23_match, n23, thr, worst);
  cb_claim_numbers(out,
                   "- Witness consistency: %d systems where CHOLMOD succeeded but a Ritz value was < 0 (must be 0); "
                   "%d where CHOLMOD failed and Lanczos had not yet reached a negative value.\n",
                   contradictions, unresolved);
  int pair_ok = n1 > 0 && n1_spd == n1 && n23 > 0 && n23_match == n23 && n23_indef > 0 && worst < 1e-6;
  if (scenes_exact == 0 && n23_indef == 0) {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out, "No indefinite A was found on any compression scene or in the spring pair.");
  } else if (pair_ok && stretched_indef == 0 && contradictions == 0 && scenes_indef > 0) {
    out->verdict = CB_REPRODUCED;
    cb_claim_reason(out,
                    "The exact A was indefinite on %d of %d scenes' `none` runs (CHOLMOD's non-positive pivot ends "
                    "them) and along the trajectories of the fixes on %d of %d scenes; never when no spring was "
                    "compressed; compression alone is not enough (see the scenes where `none` stays SPD). The spring "
                    "pair is indefinite in 2D/3D exactly below the predicted compression (largest indefinite ratio "
                    "%g) and SPD at every compression in 1D.",
                    scenes_indef, d->nscene, scenes_exact, d->nscene, thr);
  } else {
    out->verdict = CB_PARTLY;
    cb_claim_reason(out,
                    "Indefinite matrices were found (%d scenes; pair 2D/3D: %d), but a check failed: "
                    "pair prediction %s, %d indefinite systems without compressed springs, %d witness "
                    "contradictions.",
                    scenes_indef, n23_indef, pair_ok ? "ok" : "failed", stretched_indef, contradictions);
  }
  cb_table_free(&pair);
  free(d);
}

/* ---- H2: the fixes' costs against `drop`, from the runs table ---------------------------------
 *
 * Per scene and working fix: Newton iterations, factorisations and wall time per step as ratios to
 * `drop` on the same scene (wall: paired repeats, the policies of a scene ran in interleaved rounds),
 * then per fix the median over the scenes of each ratio (cb_claim_timing_median: per repeat). The
 * fixes are ranked by that wall-time median. A fix's cost differs from drop's when its Newton
 * iterations per step differ by more than 5%, or its wall ratio's whole spread lies outside 1 +- 5%; it
 * is the same when both lie inside, and undecided when the wall ratio's spread straddles an edge of that
 * band (cb_claim_timing_side): "at different costs" is then undecided unless another fix differs. */
#define H2_BAND 1.05 /* a cost within 5% of drop's (wall time, Newton iterations) is the same cost */
typedef struct {
  int fix, nsc, differs; /* differs: 1 yes, 0 no, -1 undecided within the spread */
  double iters, facts;   /* medians over the scenes of the ratios to drop */
  double shape;          /* median over the scenes of the final shape's distance to drop's, m */
  cb_claim_timing wall;  /* median over the scenes of the paired wall ratios */
} h2_rank;

static double h2_median(double *v, int n) { /* sorts v */
  for (int i = 1; i < n; i++)
    for (int j = i; j > 0 && v[j] < v[j - 1]; j--) {
      double t = v[j];
      v[j] = v[j - 1];
      v[j - 1] = t;
    }
  return n == 0 ? NAN : n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

static int h2_costs(const cb_table *runs, const int *rc, const data_t *d, int row[][MAXP], char fixes[][32], int nfix,
                    int lec, const int *ok, h2_rank *rank, cb_claim_result *out) {
  int nrank = 0;
  cb_claim_numbers(out, "\nCosts against `drop` (the lecture's fix) on the same scene, per step: ratio of Newton "
                        "iterations, of "
                        "factorisations and of wall time (paired repeats, in brackets the fastest and slowest); per "
                        "fix the median "
                        "over the scenes, ranked by wall time; and the median distance of the final shape from drop's "
                        "(a fix that changes the energy, "
                        "as choi-ko does, or walks into another local minimum ends elsewhere):\n\n"
                        "| rank | fix | scenes | Newton iterations / drop's | factorisations / drop's | wall time / "
                        "drop's | differs | shape vs drop (m) |\n"
                        "|---|---|---|---|---|---|---|---|\n");
  for (int f = 0; f < nfix; f++) {
    if (!ok[f]) continue;
    h2_rank *k = &rank[nrank];
    memset(k, 0, sizeof *k);
    k->fix = f;
    double it[MAXS], fa[MAXS], sh[MAXS];
    int nsh = 0;
    cb_claim_timing w[MAXS];
    for (int si = 0; si < d->nscene; si++) {
      int a = row[si][f], b = row[si][lec];
      if (a < 0 || b < 0) continue;
      double da = cb_table_num(runs, a, rc[3]), db = cb_table_num(runs, b, rc[3]);
      if (!(da > 0 && db > 0)) continue;
      it[k->nsc] = cb_table_num(runs, a, rc[5]) / da / (cb_table_num(runs, b, rc[5]) / db);
      fa[k->nsc] = cb_table_num(runs, a, rc[6]) / da / (cb_table_num(runs, b, rc[6]) / db);
      cb_claim_timing wa = cb_claim_timing_at(runs, a, "wall_ms"), wb = cb_claim_timing_at(runs, b, "wall_ms");
      cb_claim_timing pa = cb_claim_timing_scale(&wa, 1 / da), pb = cb_claim_timing_scale(&wb, 1 / db);
      w[k->nsc++] = cb_claim_timing_ratio(&pa, &pb);
      double dd = cb_table_num(runs, a, rc[9]);
      if (!isnan(dd)) sh[nsh++] = dd;
    }
    if (k->nsc == 0) continue;
    k->iters = h2_median(it, k->nsc);
    k->facts = h2_median(fa, k->nsc);
    k->shape = h2_median(sh, nsh);
    k->wall = cb_claim_timing_median(w, k->nsc);
    /* wall time: differs when its spread lies outside 1 +- 5% (on either side), equal when inside,
       undecided when it straddles an edge of that band */
    int above = cb_claim_timing_side(&k->wall, H2_BAND), below = cb_claim_timing_side(&k->wall, 1 / H2_BAND);
    int wall_differs = above > 0 || below < 0 ? 1 : above < 0 && below > 0 ? 0 : -1;
    k->differs = f == lec ? 0 : fabs(k->iters - 1) > 0.05 ? 1 : wall_differs;
    nrank++;
  }
  for (int i = 1; i < nrank; i++) /* by the wall-time median, cheapest first */
    for (int j = i; j > 0 && rank[j].wall.med < rank[j - 1].wall.med; j--) {
      h2_rank t = rank[j];
      rank[j] = rank[j - 1];
      rank[j - 1] = t;
    }
  for (int i = 0; i < nrank; i++) {
    char b[128];
    cb_claim_numbers(out, "| %d | %s | %d | %.2f | %.2f | %s | %s | %.3g |\n", i + 1, fixes[rank[i].fix], rank[i].nsc,
                     rank[i].iters, rank[i].facts, cb_claim_spread_long(b, sizeof b, "%.2f", &rank[i].wall, "x"),
                     rank[i].fix == lec     ? "(baseline)"
                     : rank[i].differs > 0  ? "yes"
                     : rank[i].differs == 0 ? "no"
                                            : "undecided",
                     rank[i].shape);
  }
  return nrank;
}

/* The ranking in one sentence: each fix's wall time and Newton iterations per step against drop's. */
static void h2_rank_text(const h2_rank *rank, int nrank, char fixes[][32], int lec, cb_claim_result *out) {
  if (nrank == 0) return;
  cb_claim_reason(out, "Ranked by wall time per step against `drop` (median over the scenes, spread of paired "
                       "repeats): ");
  for (int i = 0; i < nrank; i++) {
    char b[96];
    if (rank[i].fix == lec) cb_claim_reason(out, "%s%d. drop (1x, the baseline)", i ? "; " : "", i + 1);
    else
      cb_claim_reason(out, "%s%d. %s %s, %.2fx the Newton iterations%s", i ? "; " : "", i + 1, fixes[rank[i].fix],
                      cb_claim_spread(b, sizeof b, "%.2f", &rank[i].wall, "x"), rank[i].iters,
                      rank[i].differs > 0    ? ""
                      : rank[i].differs == 0 ? " (the same cost, within 5%)"
                                             : " (undecided within the spread)");
  }
  cb_claim_reason(out, ".");
}


void cb_check_h2(const cb_table *csv, const char *dir, cb_claim_result *out) {
  data_t *d = calloc(1, sizeof *d);
  cb_table runs;
  if (!d || !load(csv, d, out) || !open_side(dir, "runs", &runs, out)) {
    free(d);
    return;
  }
  const char *need[] = {"scene",          "policy",         "steps",   "steps_done",        "steps_converged",
                        "newton_iters",   "factorizations", "wall_ms", "shape_diff_none_m", "shape_diff_drop_m",
                        "final_energy_j", "mu_max_n_per_m"};
  int rc[12];
  for (int k = 0; k < 12; k++)
    if ((rc[k] = cb_table_col(&runs, need[k])) < 0) {
      cb_claim_reason(out, "definiteness_runs.csv has no column '%s'.", need[k]);
      cb_table_free(&runs);
      free(d);
      return;
    }
  cb_claim_numbers(out, "| scene | policy | CHOLMOD failures / systems | CG breakdowns | steps done (converged) / "
                        "steps | "
                        "Newton iterations per step | factorisations per step | wall ms per step | max shift mu | "
                        "shape vs none (m) | shape vs drop (m) | final energy (J) |\n"
                        "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  char fixes[MAXP][32]; /* the fixes of the runs CSV, every policy but none, in its order */
  cb_claim_repeats reps = {0};
  int nfix = 0, ok[MAXP], seen[MAXP] = {0}, row[MAXS][MAXP]; /* row: the runs row of (scene, fix), or -1 */
  for (int k = 0; k < MAXP; k++) ok[k] = 1;
  for (int i = 0; i < MAXS; i++)
    for (int k = 0; k < MAXP; k++) row[i][k] = -1;
  for (int r = 0; r < runs.nrows; r++) {
    const char *sn = cb_table_str(&runs, r, rc[0]), *pn = cb_table_str(&runs, r, rc[1]);
    int si = -1, pi = -1, f = -1;
    for (int k = 0; k < d->nscene; k++)
      if (!strcmp(d->sc[k].scene, sn)) si = k;
    for (int k = 0; k < d->npol; k++)
      if (!strcmp(d->pol[k], pn)) pi = k;
    if (strcmp(pn, POLICY_EXACT)) f = index_of(fixes, &nfix, MAXP, pn);
    int sys = si >= 0 && pi >= 0 ? d->sc[si].sys[pi] : 0, fail = si >= 0 && pi >= 0 ? d->sc[si].spd_fail[pi] : 0;
    int bd = si >= 0 && pi >= 0 ? d->sc[si].cg_bd[pi] : 0;
    double steps = cb_table_num(&runs, r, rc[2]), done = cb_table_num(&runs, r, rc[3]),
           conv = cb_table_num(&runs, r, rc[4]);
    double per = done > 0 ? 1.0 / done : NAN;
    char dn[32] = "-", dd[32] = "-"; /* shape differences, when the reference run finished */
    if (!isnan(cb_table_num(&runs, r, rc[8]))) snprintf(dn, sizeof dn, "%.3g", cb_table_num(&runs, r, rc[8]));
    if (!isnan(cb_table_num(&runs, r, rc[9]))) snprintf(dd, sizeof dd, "%.3g", cb_table_num(&runs, r, rc[9]));
    cb_claim_timing w = cb_claim_timing_at(&runs, r, "wall_ms"), wps = cb_claim_timing_scale(&w, per); /* per step */
    char ws[96];
    cb_claim_repeats_add(&reps, &w);
    cb_claim_numbers(out,
                     "| %s | %s | %d / %d | %d | %.0f (%.0f) / %.0f | %.2f | %.2f | %s | %.3g | %s | %s | %.6g |\n", sn,
                     pn, fail, sys, bd, done, conv, steps, cb_table_num(&runs, r, rc[5]) * per,
                     cb_table_num(&runs, r, rc[6]) * per, cb_claim_spread(ws, sizeof ws, "%.1f", &wps, ""),
                     cb_table_num(&runs, r, rc[11]), dn, dd, cb_table_num(&runs, r, rc[10]));
    if (f < 0) continue;
    seen[f] = 1;
    if (si >= 0) row[si][f] = r;
    if (fail > 0 || bd > 0 || !(done == steps) || sys == 0) ok[f] = 0;
  }
  cb_claim_numbers(out, "\nA fix works here when, on every scene, CHOLMOD factorised every matrix it was given (for "
                        "`shift`: after raising mu), CG never broke down on it, and the run finished all its steps. "
                        "Steps that stop at max_iters are a cost, not a failure of definiteness.\n");
  char rt[64];
  if (cb_claim_repeats_text(rt, sizeof rt, &reps)[0])
    cb_claim_numbers(out,
                     "\nWall ms per step: the run's integrator time over its steps, the median of %s of the run "
                     "without "
                     "the probes, in brackets the fastest and slowest; a scene's policies ran in interleaved rounds.\n",
                     rt);
  int lec0 = -1;
  for (int k = 0; k < nfix; k++)
    if (!strcmp(fixes[k], POLICY_LECTURE)) lec0 = k;
  h2_rank rank[MAXP];
  int nrank = lec0 >= 0 ? h2_costs(&runs, rc, d, row, fixes, nfix, lec0, ok, rank, out) : 0;
  int nok = 0, nseen = 0, lec = -1;
  char bad[256] = "", others[256] = "";
  for (int k = 0; k < nfix; k++) {
    nseen += seen[k];
    nok += seen[k] && ok[k];
    if (seen[k] && !ok[k]) snprintf(bad + strlen(bad), sizeof bad - strlen(bad), "%s%s", bad[0] ? ", " : "", fixes[k]);
    if (!strcmp(fixes[k], POLICY_LECTURE)) lec = k;
    else snprintf(others + strlen(others), sizeof others - strlen(others), "%s%s", others[0] ? ", " : "", fixes[k]);
  }
  if (lec < 0 || !seen[lec] || !ok[lec]) {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out, "%s",
                    lec >= 0 && seen[lec] ? "`drop` did not restore definiteness everywhere: see the CHOLMOD failures, "
                                            "CG "
                                            "breakdowns or unfinished runs above."
                                          : "No `drop` run in the data.");
  } else if (nok == nfix) {
    int differ = 0, maybe = 0, first_maybe = -1;
    for (int k = 0; k < nrank; k++) {
      differ += rank[k].differs > 0;
      if (rank[k].differs < 0 && maybe++ == 0) first_maybe = k;
    }
    out->verdict = differ > 0 ? CB_REPRODUCED : maybe > 0 ? CB_UNDECIDED : CB_PARTLY;
    cb_claim_reason(out,
                    "`drop` and the %d other fixes (%s) gave CHOLMOD an SPD matrix at every "
                    "Newton iteration of every scene and CG never broke down (a fix with a non-SPD matrix, a CG "
                    "breakdown or an unfinished run on any scene would refute this). ",
                    nfix - 1, others);
    h2_rank_text(rank, nrank, fixes, lec0, out);
    if (!differ && maybe) {
      const h2_rank *k = &rank[first_maybe];
      double edge = k->wall.med >= 1 ? H2_BAND : 1 / H2_BAND;
      char u[1024], what[96];
      snprintf(what, sizeof what, "%s's wall time / drop's", fixes[k->fix]);
      cb_claim_reason(out,
                      " No fix's cost differs from `drop`'s by more than 5%% over its whole spread, and on %d fix(es) "
                      "the spread straddles the band's edge: undecided (within the spread), reproduced if one differs, "
                      "partly if none. First: %s.",
                      maybe, cb_claim_undecided_text(u, sizeof u, what, "%.3f", &k->wall, "x", edge));
    } else if (!differ)
      cb_claim_reason(out, " Every fix's cost is within 5%% of `drop`'s, in wall time over the whole spread of the "
                           "repeats and in Newton iterations: \"at different costs\" is not reproduced.");
  } else {
    out->verdict = CB_PARTLY;
    cb_claim_reason(out, "`drop` restored definiteness everywhere, but %s did not (%d of %d other fixes work).", bad,
                    nok - 1, nseen - 1);
  }
  cb_table_free(&runs);
  free(d);
}
