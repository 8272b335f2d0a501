/* Checkers for B1, B2 and B3 from results/bending.csv (experiments/bending).
 * Model names come from the CSV: in B1 the model called "spring" against
 * every other (hinge) model; in B2 "quadratic" against "dihedral". */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "claims.h"

void cb_check_B1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_B2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_B3(const cb_table *t, const char *results_dir, cb_claim_result *out);

enum { MAXM = 8, MAXP = 256 };

static int is(const cb_table *t, int r, int c, const char *s) { return c >= 0 && strcmp(cb_table_str(t, r, c), s) == 0; }

/* Distinct values of column c over rows with part == part, in order. */
static int distinct(const cb_table *t, const char *part, int c, const char *names[MAXM]) {
  int cp = cb_table_col(t, "part"), n = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (!is(t, r, cp, part)) continue;
    const char *s = cb_table_str(t, r, c);
    int seen = 0;
    for (int k = 0; k < n; k++) seen |= strcmp(names[k], s) == 0;
    if (!seen && n < MAXM) names[n++] = s;
  }
  return n;
}

/* force_n of model at angle deg (NaN if absent). */
static double force_at(const cb_table *t, const char *model, double deg) {
  int cp = cb_table_col(t, "part"), cm = cb_table_col(t, "model"), ca = cb_table_col(t, "angle_deg"),
      cf = cb_table_col(t, "force_n");
  for (int r = 0; r < t->nrows; r++)
    if (is(t, r, cp, "b1") && is(t, r, cm, model) && fabs(cb_table_num(t, r, ca) - deg) < 1e-9) return cb_table_num(t, r, cf);
  return NAN;
}

void cb_check_B1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  int cp = cb_table_col(t, "part"), cm = cb_table_col(t, "model"), ca = cb_table_col(t, "angle_deg"),
      cf = cb_table_col(t, "force_n");
  if (cp < 0 || cm < 0 || ca < 0 || cf < 0) {
    cb_claim_reason(out, "bending.csv lacks the part/model/angle_deg/force_n columns.");
    return;
  }
  const char *models[MAXM];
  int nm = distinct(t, "b1", cm, models), spring_ok = -1, hinges = 0, hinges_ok = 0;
  if (nm == 0) {
    cb_claim_reason(out, "No b1 rows in bending.csv.");
    return;
  }
  double slope[MAXM];
  cb_claim_numbers(out, "| model | slope of log F vs log theta, 1-10 deg | F(1 deg) | F(5 deg) | F(30 deg) |\n|---|---|---|---|---|\n");
  for (int m = 0; m < nm; m++) {
    double lx[MAXP], ly[MAXP];
    int n = 0, bad = 0;
    for (int r = 0; r < t->nrows && n < MAXP; r++) {
      if (!is(t, r, cp, "b1") || !is(t, r, cm, models[m])) continue;
      double a = cb_table_num(t, r, ca), f = cb_table_num(t, r, cf);
      if (a < 1 - 1e-9 || a > 10 + 1e-9) continue;
      if (!(f > 0)) bad = 1; /* a restoring force must be positive */
      else {
        lx[n] = log(a);
        ly[n++] = log(f);
      }
    }
    double b = NAN;
    if (n >= 3 && !bad) cb_fit_line(lx, ly, n, &slope[m], &b);
    else slope[m] = NAN;
    cb_claim_numbers(out, "| %s | %.3f | %.4g | %.4g | %.4g |\n", models[m], slope[m], force_at(t, models[m], 1),
                     force_at(t, models[m], 5), force_at(t, models[m], 30));
    if (strcmp(models[m], "spring") == 0) spring_ok = slope[m] >= 2.5;
    else {
      hinges++;
      hinges_ok += fabs(slope[m] - 1) <= 0.1;
    }
  }
  cb_claim_numbers(out, "\nForces in N with bend_k = 1 (N/m for the spring, N m for the hinges): the restoring component "
                        "at the wing tip, 0.8 m from the edge. Predicted slopes: 3 (spring), 1 (hinges).\n");
  if (spring_ok < 0 || hinges == 0) {
    cb_claim_reason(out, "B1 needs the spring and at least one hinge model in the data.");
    return;
  }
  out->verdict = spring_ok && hinges_ok == hinges ? CB_REPRODUCED : CB_NOT_REPRODUCED;
  /* the spring's slope, not the first model's */
  for (int m = 0; m < nm; m++)
    if (strcmp(models[m], "spring") == 0) {
      cb_claim_reason(out, "%s: near the flat state the spring's restoring force grows like theta^%.2f (criterion >= 2.5), "
                           "%d of %d hinge models like theta^(1 +- 0.1).",
                      out->verdict == CB_REPRODUCED ? "Reproduced" : "Not reproduced", slope[m], hinges_ok, hinges);
    }
}

typedef struct {
  int found, n, steps, iters, contacts, indefinite, hinges;
  double asm_ms, fac_ms, sol_ms, wall_ms, wall_min, wall_max, kinetic; /* wall_min, wall_max: fastest, slowest step */
  cb_claim_timing t[4]; /* assembly, factor, solve, step: medians over the repeats with their spread */
  char status[32];
} b2row;

static b2row b2_get(const cb_table *t, const char *model, const char *mesh, int n) {
  b2row b;
  memset(&b, 0, sizeof b);
  int cp = cb_table_col(t, "part"), cm = cb_table_col(t, "model"), ce = cb_table_col(t, "mesh"), cn = cb_table_col(t, "n");
  /* step_min_ms, step_max_ms: the fastest and slowest step; wall_min_ms, wall_max_ms then the spread over
   * the repeats. An older table without them had the steps' range in wall_min_ms, wall_max_ms. */
  int cs = cb_table_col(t, "step_min_ms"), repeated = cs >= 0;
  for (int r = 0; r < t->nrows; r++) {
    if (!is(t, r, cp, "b2") || !is(t, r, cm, model) || !is(t, r, ce, mesh) || (int)cb_table_num(t, r, cn) != n) continue;
    b.found = 1;
    b.n = n;
    b.steps = (int)cb_table_num(t, r, cb_table_col(t, "steps"));
    b.iters = (int)cb_table_num(t, r, cb_table_col(t, "newton_iters"));
    static const char *const part[4] = {"assemble_ms", "factor_ms", "solve_ms", "wall_ms"};
    for (int q = 0; q < 4; q++)
      b.t[q] = repeated ? cb_claim_timing_at(t, r, part[q]) : cb_claim_timing_value(cb_table_num(t, r, cb_table_col(t, part[q])));
    if (!repeated)
      for (int q = 0; q < 4; q++) b.t[q].min = b.t[q].max = NAN; /* no spread recorded */
    b.asm_ms = b.t[0].med;
    b.fac_ms = b.t[1].med;
    b.sol_ms = b.t[2].med;
    b.wall_ms = b.t[3].med;
    int cl = repeated ? cs : cb_table_col(t, "wall_min_ms"), ch = cb_table_col(t, repeated ? "step_max_ms" : "wall_max_ms"); /* optional */
    b.wall_min = cl >= 0 ? cb_table_num(t, r, cl) : NAN;
    b.wall_max = ch >= 0 ? cb_table_num(t, r, ch) : NAN;
    b.kinetic = cb_table_num(t, r, cb_table_col(t, "kinetic_j"));
    b.contacts = (int)cb_table_num(t, r, cb_table_col(t, "contacts"));
    b.indefinite = (int)cb_table_num(t, r, cb_table_col(t, "indefinite"));
    b.hinges = (int)cb_table_num(t, r, cb_table_col(t, "hinges"));
    snprintf(b.status, sizeof b.status, "%s", cb_table_str(t, r, cb_table_col(t, "status")));
  }
  return b;
}

static double b2_rms(const cb_table *t, const char *mesh, int n) {
  int cp = cb_table_col(t, "part"), ce = cb_table_col(t, "mesh"), cn = cb_table_col(t, "n"), cr = cb_table_col(t, "rms_m");
  for (int r = 0; r < t->nrows; r++)
    if (is(t, r, cp, "b2_rms") && is(t, r, ce, mesh) && (int)cb_table_num(t, r, cn) == n) return cb_table_num(t, r, cr);
  return NAN;
}

void cb_check_B2(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  const char *need[] = {"part", "model", "mesh", "n", "steps", "newton_iters", "assemble_ms", "factor_ms", "solve_ms",
                        "wall_ms", "kinetic_j", "rms_m", "contacts", "indefinite", "hinges", "status"};
  for (size_t k = 0; k < sizeof need / sizeof need[0]; k++)
    if (cb_table_col(t, need[k]) < 0) {
      cb_claim_reason(out, "bending.csv lacks the column %s.", need[k]);
      return;
    }
  int cp = cb_table_col(t, "part"), ce = cb_table_col(t, "mesh"), cn = cb_table_col(t, "n");
  /* (mesh, n) pairs of the b2 rows, in order */
  const char *mesh[MAXM];
  int ns[MAXM], np = 0, nmax = -1;
  for (int r = 0; r < t->nrows; r++) {
    if (!is(t, r, cp, "b2")) continue;
    int n = (int)cb_table_num(t, r, cn), seen = 0;
    for (int k = 0; k < np; k++) seen |= ns[k] == n && strcmp(mesh[k], cb_table_str(t, r, ce)) == 0;
    if (!seen && np < MAXM) {
      mesh[np] = cb_table_str(t, r, ce);
      ns[np++] = n;
    }
    if (is(t, r, ce, "grid") && n > nmax) nmax = n;
  }
  if (nmax < 0) {
    cb_claim_reason(out, "No b2 grid rows in bending.csv.");
    return;
  }
  cb_claim_numbers(out, "| mesh | model | steps | Newton iters (per step) | assembly ms | factor ms | solve ms | total ms/step | "
                        "fastest-slowest step ms | indefinite hinges at rest | final kinetic J |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  double ratio_max = NAN;
  cb_claim_timing ratio_t = cb_claim_timing_value(NAN), asm_t = cb_claim_timing_value(NAN);
  cb_claim_repeats reps = {0};
  int failed = 0;
  char c[4][96], w[96];
  for (int k = 0; k < np; k++) {
    b2row q = b2_get(t, "quadratic", mesh[k], ns[k]), d = b2_get(t, "dihedral", mesh[k], ns[k]);
    for (int m = 0; m < 2; m++) {
      const b2row *b = m ? &d : &q;
      if (!b->found) continue;
      failed += strcmp(b->status, "ok") != 0;
      char ind[64] = "-";
      if (b->hinges > 0) snprintf(ind, sizeof ind, "%d of %d", b->indefinite, b->hinges);
      for (int p = 0; p < 4; p++) cb_claim_spread(c[p], sizeof c[p], "%.2f", &b->t[p], "");
      cb_claim_repeats_add(&reps, &b->t[3]);
      cb_claim_numbers(out, "| %s %d | %s | %d | %d (%.1f) | %s | %s | %s | %s | %.1f-%.1f | %s | %.3g |\n", mesh[k],
                       ns[k], m ? "dihedral" : "quadratic", b->steps, b->iters,
                       b->steps ? (double)b->iters / b->steps : 0.0, c[0], c[1], c[2], c[3], b->wall_min, b->wall_max, ind,
                       b->kinetic);
    }
    if (q.found && d.found && q.wall_ms > 0) {
      cb_claim_timing rr[4];
      for (int p = 0; p < 4; p++) {
        rr[p] = cb_claim_timing_ratio(&d.t[p], &q.t[p]);
        if (!(q.t[p].med > 0)) rr[p] = cb_claim_timing_value(NAN);
      }
      cb_claim_numbers(out, "| %s %d | **ratio** dihedral/quadratic | | iters %.2f | %s | %s | %s | **%s** | | "
                            "RMS shape difference %.4g m | |\n",
                       mesh[k], ns[k], q.iters ? (double)d.iters / q.iters : NAN, cb_claim_spread(c[0], sizeof c[0], "%.1f", &rr[0], "x"),
                       cb_claim_spread(c[1], sizeof c[1], "%.2f", &rr[1], "x"), cb_claim_spread(c[2], sizeof c[2], "%.2f", &rr[2], "x"),
                       cb_claim_spread(w, sizeof w, "%.2f", &rr[3], "x"), b2_rms(t, mesh[k], ns[k]));
      if (strcmp(mesh[k], "grid") == 0 && ns[k] == nmax) {
        ratio_max = d.wall_ms / q.wall_ms;
        ratio_t = rr[3];
        if (d.wall_ms > 0) {
          cb_claim_timing f = cb_claim_timing_ratio(&d.t[0], &d.t[3]);
          asm_t = cb_claim_timing_scale(&f, 100);
        }
      }
    }
  }
  char rt[64];
  cb_claim_repeats_text(rt, sizeof rt, &reps);
  if (rt[0])
    cb_claim_numbers(out, "\nTimes are per-step medians over the run (ms), each the median over %s of the run, in brackets the "
                          "fastest and slowest repeat; the two models ran in interleaved rounds and the ratios' spreads are "
                          "of paired repeats (repeat i of dihedral over repeat i of quadratic); the claim is decided on the "
                          "finest grid, by the ratio of the medians.\n", rt);
  else
    cb_claim_numbers(out, "\nTimes are per-step medians over the run (ms); ratios are of medians; the claim is decided on the "
                          "finest grid.\n");
  if (!(ratio_max == ratio_max)) {
    cb_claim_reason(out, "The finest grid lacks a quadratic or a dihedral run.");
    return;
  }
  if (failed) {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out, "%d drape run(s) did not finish with status ok; the timing ratio %.2fx is not a fair comparison.",
                    failed, ratio_max);
    return;
  }
  if (ratio_max > 3) {
    out->verdict = CB_REPRODUCED;
    char a[128];
    cb_claim_reason(out, "Exceeded: on the %d^2 drape the quadratic model's step is %s faster than the dihedral one's "
                         "(claim: up to 3x); %s of the dihedral step is the assembly of its changing, per-element "
                         "projected Hessian.", nmax, cb_claim_spread_long(w, sizeof w, "%.1f", &ratio_t, "x"),
                    cb_claim_spread(a, sizeof a, "%.0f", &asm_t, "%"));
  } else if (ratio_max >= 1.5) {
    out->verdict = CB_REPRODUCED;
    cb_claim_reason(out, "Reproduced: on the %d^2 drape the quadratic model's step is %s faster than the dihedral one's "
                         "(claim: up to 3x, reproduced from 1.5x).", nmax, cb_claim_spread_long(w, sizeof w, "%.2f", &ratio_t, "x"));
  } else {
    out->verdict = ratio_max > 1 ? CB_PARTLY : CB_NOT_REPRODUCED;
    cb_claim_reason(out, "On the %d^2 drape the quadratic model's step is only %s faster than the dihedral one's "
                         "(claim: up to 3x; 1.5x needed).", nmax, cb_claim_spread_long(w, sizeof w, "%.2f", &ratio_t, "x"));
  }
}

/* First stretch where |ratio - 1| > 0.1 in mode (linear interpolation between
 * samples); NaN if none. r0 gets the ratio at the smallest stretch. */
static double b3_threshold(const cb_table *t, const char *mode, double *r0, double *smax, int *npts) {
  int cp = cb_table_col(t, "part"), ce = cb_table_col(t, "mesh"), cs = cb_table_col(t, "stretch"), cr = cb_table_col(t, "ratio");
  double ps = NAN, pd = NAN, th = NAN;
  *r0 = NAN;
  *smax = NAN;
  *npts = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (!is(t, r, cp, "b3") || !is(t, r, ce, mode)) continue;
    double s = cb_table_num(t, r, cs), d = fabs(cb_table_num(t, r, cr) - 1);
    if (*npts == 0) *r0 = cb_table_num(t, r, cr);
    (*npts)++;
    *smax = s;
    if (th != th && d > 0.1) th = ps == ps && d != pd ? ps + (0.1 - pd) * (s - ps) / (d - pd) : s;
    ps = s;
    pd = d;
  }
  return th;
}

void cb_check_B3(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  if (cb_table_col(t, "part") < 0 || cb_table_col(t, "stretch") < 0 || cb_table_col(t, "ratio") < 0 ||
      cb_table_col(t, "mesh") < 0 || cb_table_col(t, "angle_deg") < 0) {
    cb_claim_reason(out, "bending.csv lacks the part/mesh/stretch/ratio columns.");
    return;
  }
  const char *modes[MAXM];
  int nmodes = distinct(t, "b3", cb_table_col(t, "mesh"), modes);
  if (nmodes == 0) {
    cb_claim_reason(out, "No b3 rows in bending.csv.");
    return;
  }
  int cp = cb_table_col(t, "part"), ca = cb_table_col(t, "angle_deg");
  double fold = NAN;
  for (int r = 0; r < t->nrows && fold != fold; r++)
    if (is(t, r, cp, "b3")) fold = cb_table_num(t, r, ca);
  cb_claim_numbers(out, "| in-plane stretch | E_quadratic / E_hinge unstretched | stretch where they differ by > 10%% |\n|---|---|---|\n");
  int ok = 0;
  double th_first = NAN, r0_first = NAN;
  for (int m = 0; m < nmodes; m++) {
    double r0, smax;
    int n;
    double th = b3_threshold(t, modes[m], &r0, &smax, &n);
    char ths[64];
    if (th == th) snprintf(ths, sizeof ths, "%.1f%%", 100 * th);
    else snprintf(ths, sizeof ths, "none up to %.0f%%", 100 * smax);
    cb_claim_numbers(out, "| %s | %.4f | %s |\n", modes[m], r0, ths);
    if (m == 0) {
      th_first = th;
      r0_first = r0;
    }
    ok += fabs(r0 - 1) <= 0.1 && th == th && th <= 0.30 + 1e-12;
  }
  cb_claim_numbers(out, "\nFold angle %.0f deg; `uniform` scales the whole hinge, `across` only the wings' distance from "
                        "the edge. The hinge (dihedral) energy depends on the angle alone, so it does not change.\n", fold);
  /* the quadratic energy against the continuous 1/2 int |Delta x|^2 on cylinders */
  int cm = cb_table_col(t, "model"), cn = cb_table_col(t, "n"), cs = cb_table_col(t, "radius_m"), cr = cb_table_col(t, "ratio");
  int header = 0;
  for (int r = 0; r < t->nrows; r++) {
    if (!is(t, r, cp, "conv")) continue;
    if (!header) {
      cb_claim_numbers(out, "\nBending energy of an isometric cylinder (radius R, 1 m^2 grid, k = 1) over the continuous "
                            "1/2 int |Delta x|^2 dA = A/(2R^2):\n\n| model | R (m) | grid n | ratio |\n|---|---|---|---|\n");
      header = 1;
    }
    cb_claim_numbers(out, "| %s | %g | %.0f | %.4f |\n", cb_table_str(t, r, cm), cb_table_num(t, r, cs), cb_table_num(t, r, cn),
                     cb_table_num(t, r, cr));
  }
  out->verdict = ok == nmodes ? CB_REPRODUCED : ok > 0 ? CB_PARTLY : CB_NOT_REPRODUCED;
  if (th_first == th_first)
    cb_claim_reason(out, "%s: at a %.0f deg fold the quadratic energy is %.3f x the hinge energy unstretched and differs "
                         "from it by more than 10%% from %.1f%% %s stretch (%d of %d stretch modes within 30%%).",
                    ok == nmodes ? "Reproduced" : "Not reproduced in every mode", fold, r0_first, 100 * th_first, modes[0],
                    ok, nmodes);
  else
    cb_claim_reason(out, "Not reproduced: the quadratic and hinge energies stay within 10%% up to the largest stretch "
                         "measured (or disagree already unstretched: ratio %.3f).", r0_first);
}
