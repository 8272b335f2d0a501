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
