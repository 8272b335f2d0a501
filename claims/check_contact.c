/* Checker for C1 from results/contact.csv (experiments/contact/main.c).
 *
 * C1: ipc keeps the cloth free of intersections at every frame of every cell of the sweep, where the
 * penalty (no CCD) tunnels. Over the rows of contact.csv (one per frame; a cell that could not start or
 * run is one row with its status):
 *   not reproduced  some ipc frame has an intersecting triangle pair (cloth-cloth or cloth-obstacle);
 *   reproduced      no ipc frame does, every ipc cell ran to its end, and some penalty frame does;
 *   partly          no ipc frame does, but the penalty never intersects (the claim's contrast is not
 *                   shown), or some ipc cell stopped early (a failed step, a refused start: not every
 *                   frame was checked);
 *   not run         no ipc frame was checked, or no penalty frame.
 * A cell is (scene, response, dt, speed); its status is the last row's. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "claims.h"

enum { MAXR = 16, MAXS = 8 };

typedef struct {
  char scene[64], resp[32];
  long cells, failed, frames, hit_frames;
  double worst, worst_self, worst_obst, min_sep;
  long max_contacts;
} acc;

static acc *find(acc *a, int *n, const char *scene, const char *resp) {
  for (int i = 0; i < *n; i++)
    if (!strcmp(a[i].scene, scene) && !strcmp(a[i].resp, resp)) return &a[i];
  if (*n >= MAXR * MAXS) return NULL;
  acc *x = &a[(*n)++];
  memset(x, 0, sizeof *x);
  snprintf(x->scene, sizeof x->scene, "%s", scene);
  snprintf(x->resp, sizeof x->resp, "%s", resp);
  x->min_sep = INFINITY;
  return x;
}

static int fatal(const char *status) { return strcmp(status, "ok") && strcmp(status, "max_iters"); }

void cb_check_C1(const cb_table *t, const char *results_dir, cb_claim_result *out) {
  (void)results_dir;
  static const char *const names[] = {"scene",
                                      "response",
                                      "dt_s",
                                      "speed_m_per_s",
                                      "frame",
                                      "status",
                                      "self_intersections",
                                      "obstacle_intersections",
                                      "intersections",
                                      "min_separation_m",
                                      "contacts"};
  enum { NC = sizeof names / sizeof names[0] };
  int c[NC];
  if (cb_claim_columns(t, names, c, NC, "contact.csv", out)) return;
  static acc a[MAXR * MAXS];
  int na = 0;
  for (int r = 0; r < t->nrows; r++) {
    acc *x = find(a, &na, cb_table_str(t, r, c[0]), cb_table_str(t, r, c[1]));
    if (!x) continue;
    const char *status = cb_table_str(t, r, c[5]);
    /* a new cell starts at frame 0, or is a one-row cell (no frame) */
    int frame = cb_table_int(t, r, c[4]);
    int last = r + 1 >= t->nrows || strcmp(cb_table_str(t, r + 1, c[0]), x->scene) ||
               strcmp(cb_table_str(t, r + 1, c[1]), x->resp) || cb_table_int(t, r + 1, c[4]) <= 0;
    if (frame <= 0) x->cells++;
    if (last && fatal(status)) x->failed++;
    double n = cb_table_num(t, r, c[8]);
    if (isnan(n)) continue; /* no frame, or positions not finite */
    x->frames++;
    x->hit_frames += n > 0;
    x->worst = fmax(x->worst, n);
    x->worst_self = fmax(x->worst_self, cb_table_num(t, r, c[6]));
    x->worst_obst = fmax(x->worst_obst, cb_table_num(t, r, c[7]));
    double sep = cb_table_num(t, r, c[9]);
    if (!isnan(sep)) x->min_sep = fmin(x->min_sep, sep);
    int k = cb_table_int(t, r, c[10]);
    if (k > x->max_contacts) x->max_contacts = k;
  }
  cb_claim_numbers(out, "| scene | response | cells | failed or refused | frames checked | frames intersecting | "
                        "worst intersections (self / obstacle) | smallest separation (m) | most contacts |\n"
                        "|---|---|---|---|---|---|---|---|---|\n");
  long ipc_frames = 0, ipc_hits = 0, ipc_failed = 0, pen_frames = 0, pen_hits = 0;
  double ipc_worst = 0, pen_worst = 0;
  for (int i = 0; i < na; i++) {
    const acc *x = &a[i];
    cb_claim_numbers(out, "| %s | %s | %ld | %ld | %ld | %ld | %.0f (%.0f / %.0f) | ", x->scene, x->resp, x->cells,
                     x->failed, x->frames, x->hit_frames, x->worst, x->worst_self, x->worst_obst);
    if (isfinite(x->min_sep)) cb_claim_numbers(out, "%.3g | %ld |\n", x->min_sep, x->max_contacts);
    else cb_claim_numbers(out, "- | %ld |\n", x->max_contacts);
    if (!strcmp(x->resp, "ipc")) {
      ipc_frames += x->frames, ipc_hits += x->hit_frames, ipc_failed += x->failed;
      ipc_worst = fmax(ipc_worst, x->worst);
    } else if (!strcmp(x->resp, "penalty")) {
      pen_frames += x->frames, pen_hits += x->hit_frames;
      pen_worst = fmax(pen_worst, x->worst);
    }
  }
  if (ipc_frames == 0 || pen_frames == 0) {
    cb_claim_reason(out, "contact.csv has no checked frame of %s.",
                    ipc_frames == 0 && pen_frames == 0 ? "ipc or penalty"
                    : ipc_frames == 0                  ? "ipc"
                                                       : "penalty");
    return;
  }
  if (ipc_hits > 0) {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out, "ipc intersects: %ld of its %ld frames have intersecting triangle pairs (at worst %.0f).",
                    ipc_hits, ipc_frames, ipc_worst);
    return;
  }
  cb_claim_reason(out, "ipc has 0 intersecting pairs at all %ld frames checked", ipc_frames);
  if (pen_hits > 0)
    cb_claim_reason(out, "; the penalty intersects at %ld of its %ld frames (at worst %.0f pairs).", pen_hits,
                    pen_frames, pen_worst);
  else
    cb_claim_reason(out, "; the penalty never intersects at a frame (%ld frames): the contrast is not shown.",
                    pen_frames);
  if (ipc_failed > 0)
    cb_claim_reason(out, " %ld ipc cell%s stopped early (failed step or refused start): not every frame was checked.",
                    ipc_failed, ipc_failed == 1 ? "" : "s");
  out->verdict = pen_hits > 0 && ipc_failed == 0 ? CB_REPRODUCED : CB_PARTLY;
}

/* C2 from results/contact_c2.csv (experiments/contact/c2.c): ipc's lagged, smoothed friction reproduces
 * Coulomb's stick-slip threshold on the slope. Per angle theta, the threshold row's mu* against tan theta:
 *   reproduced      every angle's mu* within C2_TOL of tan theta (at least two angles);
 *   partly          some angles within, some not (or one angle alone, within);
 *   not reproduced  no angle within (or a threshold not bracketed: mu = 0 holds, or 3 tan theta slides);
 *   not run         no threshold row.
 * Reported beside it: the slides against the sliding block, the creep below the threshold (the slide at
 * mu = 1.5 tan theta, which the smoothing eps_v allows), and VBD's row (its contact has no friction yet). */
#define C2_TOL 0.10

void cb_check_C2(const cb_table *csv, const char *dir, cb_claim_result *out) {
  (void)csv;
  cb_table t;
  if (cb_claim_side_table(dir, "contact", "c2", &t, out)) return;
  static const char *const names[] = {"kind",          "integrator", "theta_deg", "tan_theta", "mu_over_tan", "slide_m",
                                      "closed_form_m", "mu_star",    "creep_m",   "note",      "status"};
  enum { NC = sizeof names / sizeof names[0] };
  int c[NC];
  if (cb_claim_columns(&t, names, c, NC, "contact_c2.csv", out)) {
    cb_table_free(&t);
    return;
  }
  int n = 0, within = 0, unbracketed = 0;
  double worst = 0;
  char vbd[160] = "";
  cb_claim_numbers(out, "| theta | tan theta | mu* | mu* / tan theta | slide at 0.5 tan (block) | slide at 0.9 tan "
                        "(block) | creep at 1.5 tan | creep at 2 tan |\n|---|---|---|---|---|---|---|---|\n");
  for (int r = 0; r < t.nrows; r++) {
    const char *kind = cb_table_str(&t, r, c[0]), *integ = cb_table_str(&t, r, c[1]);
    if (!strcmp(integ, "vbd")) {
      if (!vbd[0]) snprintf(vbd, sizeof vbd, "%s", cb_table_str(&t, r, c[10]));
      continue;
    }
    if (strcmp(kind, "threshold")) continue;
    double th = cb_table_num(&t, r, c[2]), tn = cb_table_num(&t, r, c[3]), ms = cb_table_num(&t, r, c[7]);
    double q = ms / tn;
    n++;
    if (!isfinite(q)) unbracketed++;
    else {
      within += fabs(q - 1) <= C2_TOL;
      worst = fmax(worst, fabs(q - 1));
    }
    /* the same angle's slide rows */
    double s05 = NAN, b05 = NAN, s09 = NAN, b09 = NAN, s15 = NAN, s20 = NAN;
    for (int k = 0; k < t.nrows; k++) {
      if (strcmp(cb_table_str(&t, k, c[0]), "slide") || strcmp(cb_table_str(&t, k, c[1]), integ) ||
          cb_table_num(&t, k, c[2]) != th)
        continue;
      double f = cb_table_num(&t, k, c[4]), s = cb_table_num(&t, k, c[5]), b = cb_table_num(&t, k, c[6]);
      if (fabs(f - 0.5) < 1e-9) s05 = s, b05 = b;
      if (fabs(f - 0.9) < 1e-9) s09 = s, b09 = b;
      if (fabs(f - 1.5) < 1e-9) s15 = s;
      if (fabs(f - 2.0) < 1e-9) s20 = s;
    }
    cb_claim_numbers(out, "| %g deg | %.4f | %.4f | %.3f | %.4g m (%.4g) | %.4g m (%.4g) | %.3g m | %.3g m |\n", th, tn,
                     ms, q, s05, b05, s09, b09, s15, s20);
  }
  cb_table_free(&t);
  if (n == 0) {
    cb_claim_reason(out, "contact_c2.csv has no threshold row.");
    return;
  }
  cb_claim_reason(out,
                  "The stick-slip threshold mu* of ipc's friction lies within %.0f%% of tan theta at %d of %d angles "
                  "(worst |mu*/tan theta - 1| = %.3f)",
                  100 * C2_TOL, within, n, worst);
  if (unbracketed) cb_claim_reason(out, "; at %d the threshold was not bracketed", unbracketed);
  cb_claim_reason(out, ". VBD: %s.",
                  vbd[0] ? (!strcmp(vbd, "refused") ? "refused (its contact blocks carry no friction "
                                                      "yet), so its half of C2 is not measured"
                                                    : vbd)
                         : "no row");
  out->verdict = within == n && n >= 2 ? CB_REPRODUCED : within > 0 ? CB_PARTLY : CB_NOT_REPRODUCED;
}

/* C3 from results/contact_c3.csv (experiments/contact/main.c, c3_cell): VBD with its per-vertex contact bounds
 * (Chen et al. 2024) reaches a given accuracy on contact-rich scenes faster than IPC's Newton, free of intersections.
 * Per scene, one step from the same warm state by each method at a ladder of iteration caps, each row with its
 * step_error against IPC's converged step, its wall time (median of interleaved repeats, with the spread) and the
 * exact intersection count of its result. For each scene and target error (C3_TARGETS), each method's time to reach
 * it is its fastest row (least median) with step_error <= target and a valid status (ok or max_iters), or "not
 * reached". A comparison (scene, target) is won by VBD when it reaches the target and Newton does not, or both do
 * and the paired spread of VBD's time over Newton's lies below 1 (cb_claim_timing_side, the shared timing rule);
 * lost when VBD does not reach it, or the spread lies above 1; undecided when the spread straddles 1.
 *   not reproduced  some VBD row intersects, or VBD wins no comparison;
 *   reproduced      VBD wins every comparison, on both claim scenes (the rotating sphere and the fold), and none of
 *                   its rows intersects;
 *   partly          VBD wins some comparisons and not others (the reason names which), or every comparison but a
 *                   claim scene has no rows;
 *   undecided       the verdict turns on a comparison whose spread straddles 1;
 *   not run         no contact_c3.csv, a column missing, or no VBD or Newton row.
 * L-BFGS with the barrier is reported beside (VBD's time over its own where both reach). */
static const double C3_TARGETS[] = {1e-2, 1e-3};
enum { C3_NT = 2, C3_NM = 3, C3_MAXSC = 8 };
static const char *const C3_METHOD[C3_NM] = {"newton", "lbfgs", "vbd"};

typedef struct {
  int row;           /* the fastest row reaching the target, -1: not reached */
  int iters;         /* its iteration cap */
  cb_claim_timing t; /* its wall time */
} c3_best;

typedef struct {
  char name[64];
  int rows[C3_NM];         /* rows of each method */
  int hit_rows[C3_NM];     /* of them with intersections > 0 */
  double worst[C3_NM];     /* the largest intersection count */
  int unchecked[C3_NM];    /* rows whose intersections were not counted */
  double least_err[C3_NM]; /* the smallest step_error of a valid row (NaN: none) */
  int least_iters[C3_NM];  /* its iteration cap */
  c3_best best[C3_NT][C3_NM];
} c3_scene;

/* printf-style text appended to buf (cut at its end) */
static void c3_append(char *buf, size_t cap, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void c3_append(char *buf, size_t cap, const char *fmt, ...) {
  size_t u = strlen(buf);
  if (u + 1 >= cap) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf + u, cap - u, fmt, ap);
  va_end(ap);
}

static int c3_valid(const char *status) { return !strcmp(status, "ok") || !strcmp(status, "max_iters"); }

void cb_check_C3(const cb_table *csv, const char *dir, cb_claim_result *out) {
  (void)csv;
  cb_table t;
  if (cb_claim_side_table(dir, "contact", "c3", &t, out)) return;
  static const char *const names[] = {"scene", "method", "iters", "step_error", "wall_ms", "intersections", "status"};
  enum { NC = sizeof names / sizeof names[0] };
  int c[NC];
  if (cb_claim_columns(&t, names, c, NC, "contact_c3.csv", out)) {
    cb_table_free(&t);
    return;
  }
  static c3_scene sc[C3_MAXSC];
  int ns = 0;
  memset(sc, 0, sizeof sc);
  for (int r = 0; r < t.nrows; r++) {
    const char *scene = cb_table_str(&t, r, c[0]), *method = cb_table_str(&t, r, c[1]);
    int m = -1;
    for (int k = 0; k < C3_NM; k++)
      if (!strcmp(method, C3_METHOD[k])) m = k;
    if (m < 0) continue; /* the reference row */
    int s = 0;
    while (s < ns && strcmp(sc[s].name, scene)) s++;
    if (s == ns) {
      if (ns == C3_MAXSC) continue;
      snprintf(sc[ns].name, sizeof sc[ns].name, "%s", scene);
      for (int k = 0; k < C3_NM; k++) {
        sc[ns].least_err[k] = NAN;
        for (int i = 0; i < C3_NT; i++) sc[ns].best[i][k].row = -1;
      }
      ns++;
    }
    c3_scene *x = &sc[s];
    x->rows[m]++;
    double nint = cb_table_num(&t, r, c[5]);
    if (isnan(nint)) x->unchecked[m]++;
    else {
      x->hit_rows[m] += nint > 0;
      x->worst[m] = fmax(x->worst[m], nint);
    }
    double err = cb_table_num(&t, r, c[3]);
    cb_claim_timing w = cb_claim_timing_at(&t, r, "wall_ms");
    if (!c3_valid(cb_table_str(&t, r, c[6])) || !isfinite(err) || !isfinite(w.med)) continue;
    if (!(x->least_err[m] <= err)) {
      x->least_err[m] = err;
      x->least_iters[m] = cb_table_int(&t, r, c[2]);
    }
    for (int i = 0; i < C3_NT; i++) {
      c3_best *b = &x->best[i][m];
      if (err <= C3_TARGETS[i] && (b->row < 0 || w.med < b->t.med)) {
        b->row = r;
        b->iters = cb_table_int(&t, r, c[2]);
        b->t = w;
      }
    }
  }
  cb_table_free(&t);
  int nv = 0, nn = 0, vbd_hits = 0, vbd_unchecked = 0;
  for (int s = 0; s < ns; s++) {
    nv += sc[s].rows[2], nn += sc[s].rows[0];
    vbd_hits += sc[s].hit_rows[2], vbd_unchecked += sc[s].unchecked[2];
  }
  if (nv == 0 || nn == 0) {
    cb_claim_reason(out, "contact_c3.csv has no %s row.",
                    nv == 0 && nn == 0 ? "VBD or Newton"
                    : nv == 0          ? "VBD"
                                       : "Newton");
    return;
  }
  cb_claim_numbers(out, "One step from the same contact-rich state, error against IPC's converged step: each method's "
                        "time "
                        "to reach the error is its fastest ladder row with step_error at or below it (in brackets the "
                        "fastest and slowest of the interleaved repeats; ratios paired repeat by repeat).\n\n"
                        "| scene | error | Newton | L-BFGS | VBD | VBD / Newton | VBD / L-BFGS |\n"
                        "|---|---|---|---|---|---|---|\n");
  int won = 0, lost = 0, undecided = 0;
  char wins[1024] = "", losses[2048] = "", undec[1024] = "";
  for (int s = 0; s < ns; s++)
    for (int i = 0; i < C3_NT; i++) {
      const c3_best *b = sc[s].best[i];
      char cell[C3_NM][160], rn[160] = "-", rl[160] = "-";
      for (int k = 0; k < C3_NM; k++) {
        if (b[k].row < 0) {
          if (!sc[s].rows[k]) snprintf(cell[k], sizeof cell[k], "no rows");
          else if (isnan(sc[s].least_err[k])) snprintf(cell[k], sizeof cell[k], "not reached (no valid row)");
          else
            snprintf(cell[k], sizeof cell[k], "not reached (least %.2g, %d it.)", sc[s].least_err[k],
                     sc[s].least_iters[k]);
          continue;
        }
        char sp[128];
        snprintf(cell[k], sizeof cell[k], "%d it.: %s", b[k].iters,
                 cb_claim_spread(sp, sizeof sp, "%.3g", &b[k].t, " ms"));
      }
      /* the comparison with Newton: -1 VBD faster, +1 slower, 0 undecided, 2 VBD not reached, -2 Newton not */
      int side;
      cb_claim_timing ratio;
      if (b[2].row < 0) side = 2;
      else if (b[0].row < 0) side = -2;
      else {
        ratio = cb_claim_timing_ratio(&b[2].t, &b[0].t);
        side = cb_claim_timing_side(&ratio, 1.0);
        cb_claim_spread_long(rn, sizeof rn, "%.3g", &ratio, "x");
      }
      if (b[2].row >= 0 && b[1].row >= 0) {
        cb_claim_timing rl_t = cb_claim_timing_ratio(&b[2].t, &b[1].t);
        cb_claim_spread_long(rl, sizeof rl, "%.3g", &rl_t, "x");
      }
      cb_claim_numbers(out, "| %s | %.0e | %s | %s | %s | %s | %s |\n", sc[s].name, C3_TARGETS[i], cell[0], cell[1],
                       cell[2], rn, rl);
      if (side < 0) {
        won++;
        c3_append(wins, sizeof wins, "%s%s %.0e (%s)", wins[0] ? "; " : "", sc[s].name, C3_TARGETS[i],
                  side == -2 ? "Newton does not reach it" : rn);
      } else if (side == 0) {
        undecided++;
        c3_append(undec, sizeof undec, "%s%s %.0e (VBD / Newton %s)", undec[0] ? "; " : "", sc[s].name, C3_TARGETS[i],
                  rn);
      } else {
        lost++;
        if (side == 2)
          c3_append(losses, sizeof losses, "%s%s %.0e: VBD does not reach it within %d rows (%s; Newton: %s)",
                    losses[0] ? "; " : "", sc[s].name, C3_TARGETS[i], sc[s].rows[2], cell[2], cell[0]);
        else
          c3_append(losses, sizeof losses, "%s%s %.0e: VBD %s against Newton's %s, VBD / Newton %s",
                    losses[0] ? "; " : "", sc[s].name, C3_TARGETS[i], cell[2], cell[0], rn);
      }
    }
  cb_claim_numbers(out, "\n| scene | method | rows | rows intersecting | worst intersections | rows not counted |\n"
                        "|---|---|---|---|---|---|\n");
  for (int s = 0; s < ns; s++)
    for (int k = 0; k < C3_NM; k++)
      if (sc[s].rows[k])
        cb_claim_numbers(out, "| %s | %s | %d | %d | %.0f | %d |\n", sc[s].name, C3_METHOD[k], sc[s].rows[k],
                         sc[s].hit_rows[k], sc[s].worst[k], sc[s].unchecked[k]);
  int have_sphere = 0, have_fold = 0;
  for (int s = 0; s < ns; s++) {
    have_sphere |= !strcmp(sc[s].name, "rotating_sphere") && sc[s].rows[2] > 0;
    have_fold |= !strcmp(sc[s].name, "sheet_on_table") && sc[s].rows[2] > 0;
  }
  if (vbd_hits > 0) {
    out->verdict = CB_NOT_REPRODUCED;
    cb_claim_reason(out, "VBD intersects: %d of its rows end with intersecting triangle pairs.", vbd_hits);
    if (won) cb_claim_reason(out, " (It is faster than Newton at: %s.)", wins);
    return;
  }
  cb_claim_reason(out, "VBD's rows have no intersecting pair%s. ", vbd_unchecked ? " where counted" : "");
  if (vbd_unchecked) cb_claim_reason(out, "(%d VBD rows not counted: no finite result.) ", vbd_unchecked);
  if (won) cb_claim_reason(out, "VBD reaches the error faster than Newton at: %s. ", wins);
  if (lost) cb_claim_reason(out, "Not at: %s. ", losses);
  if (undecided) cb_claim_reason(out, "Undecided within the spread at: %s. ", undec);
  if (!have_sphere || !have_fold)
    cb_claim_reason(out, "The %s has no VBD rows. ", !have_sphere ? "rotating sphere" : "fold (sheet_on_table)");
  /* the verdict with the undecided comparisons lost, and won: the same, or undecided */
  cb_verdict v[2];
  for (int e = 0; e < 2; e++) {
    int w = won + (e ? undecided : 0), l = lost + (e ? 0 : undecided);
    v[e] = w == 0 ? CB_NOT_REPRODUCED : l > 0 || !have_sphere || !have_fold ? CB_PARTLY : CB_REPRODUCED;
  }
  out->verdict = cb_claim_verdict_either(v[0], v[1]);
}
