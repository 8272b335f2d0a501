/* make compare: this run's verdicts against a reference run's (report.h).
 *
 * Both directories are decided by the same checkers. Per claim:
 *   same          the two verdicts agree;
 *   within        they differ, but a timing number the verdict was decided on
 *                 (cb_claim_timing_side) lies on another side of its threshold
 *                 in the two runs while the two spreads [min, max] overlap:
 *                 the machines' noise, not a different result;
 *   differs       they differ and no deciding timing explains it (a
 *                 deterministic number moved, or the spreads are apart);
 *   not compared  either run lacks the claim's CSV, or either verdict is
 *                 undecided (a run that cannot decide contradicts nothing);
 *   new claim, no reference
 *                 this run decides a claim whose experiment's CSV the
 *                 reference run does not have (an experiment added since
 *                 the reference was stored, e.g. contact): not a difference.
 * Deciding numbers are paired in the order the checker decided them, which
 * is the same for two runs of the same sweep. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "claims.h"
#include "report.h"

static double lo_of(const cb_claim_deciding *d) { return isfinite(d->min) ? fmin(d->min, d->med) : d->med; }
static double hi_of(const cb_claim_deciding *d) { return isfinite(d->max) ? fmax(d->max, d->med) : d->med; }

static void put_number(FILE *f, const cb_claim_deciding *d) {
  if (isfinite(d->min) && isfinite(d->max)) fprintf(f, "%.3g (%.3g-%.3g)", d->med, d->min, d->max);
  else fprintf(f, "%.3g", d->med);
}

/* 1 if some deciding pair changed side while its spreads overlap. */
static int explained_by_spread(const cb_claim_result *a, const cb_claim_result *b) {
  int n = a->ndeciding < b->ndeciding ? a->ndeciding : b->ndeciding;
  for (int k = 0; k < n; k++) {
    const cb_claim_deciding *x = &a->deciding[k], *y = &b->deciding[k];
    if (x->thr != y->thr || x->side == y->side) continue;
    if (lo_of(x) <= hi_of(y) && lo_of(y) <= hi_of(x)) return 1;
  }
  return 0;
}

cb_compare_kind cb_report_compare_claim(const cb_claim_result *ours, const cb_claim_result *ref) {
  if (ours->verdict == CB_NOT_RUN || ref->verdict == CB_NOT_RUN) return CB_COMPARE_NOT_COMPARED;
  if (ours->verdict == ref->verdict) return CB_COMPARE_SAME;
  if (ours->verdict == CB_UNDECIDED || ref->verdict == CB_UNDECIDED) return CB_COMPARE_NOT_COMPARED;
  return explained_by_spread(ours, ref) ? CB_COMPARE_WITHIN : CB_COMPARE_DIFFERS;
}

static const char *kind_name(cb_compare_kind k) {
  switch (k) {
  case CB_COMPARE_SAME: return "same";
  case CB_COMPARE_WITHIN: return "differs within the spreads";
  case CB_COMPARE_DIFFERS: return "DIFFERS outside the spreads";
  case CB_COMPARE_NEW: return "new claim, no reference";
  default: return "not compared";
  }
}

int cb_report_compare(FILE *f, const char *ours_dir, const char *ref_dir) {
  cb_claim_result *ours = calloc((size_t)cb_nclaims, sizeof *ours);
  cb_claim_result *ref = calloc((size_t)cb_nclaims, sizeof *ref);
  if (!ours || !ref) {
    free(ours);
    free(ref);
    fprintf(stderr, "report: out of memory\n");
    return 2;
  }
  int count[5] = {0};
  fprintf(f, "# This run (%s/) against the reference (%s/)\n\n", ours_dir, ref_dir);
  fprintf(f, "| claim | reference | this run | comparison | deciding timings: this run / reference "
             "(threshold) |\n|---|---|---|---|---|\n");
  for (int i = 0; i < cb_nclaims; i++) {
    cb_claim_decide(&cb_claims[i], ours_dir, &ours[i]);
    cb_claim_decide(&cb_claims[i], ref_dir, &ref[i]);
    cb_compare_kind k = cb_report_compare_claim(&ours[i], &ref[i]);
    if (k == CB_COMPARE_NOT_COMPARED && ours[i].verdict != CB_NOT_RUN && cb_claims[i].experiment) {
      char path[4096];
      int w = snprintf(path, sizeof path, "%s/%s.csv", ref_dir, cb_claims[i].experiment);
      if (w > 0 && (size_t)w < sizeof path && access(path, F_OK) != 0) k = CB_COMPARE_NEW;
    }
    count[k]++;
    fprintf(f, "| %s | %s | %s | %s | ", cb_claims[i].id, cb_verdict_name(ref[i].verdict),
            cb_verdict_name(ours[i].verdict), kind_name(k));
    int n = ours[i].ndeciding > ref[i].ndeciding ? ours[i].ndeciding : ref[i].ndeciding;
    if (n == 0) fputs("-", f);
    for (int j = 0; j < n; j++) {
      if (j) fputs("; ", f);
      if (j < ours[i].ndeciding) put_number(f, &ours[i].deciding[j]);
      else fputs("-", f);
      fputs(" / ", f);
      if (j < ref[i].ndeciding) put_number(f, &ref[i].deciding[j]);
      else fputs("-", f);
      const cb_claim_deciding *d = j < ours[i].ndeciding ? &ours[i].deciding[j] : &ref[i].deciding[j];
      fprintf(f, " (%.3g)", d->thr);
    }
    fputs(" |\n", f);
  }
  fprintf(f, "\n%d same, %d differ within the spreads, %d differ outside them, %d not compared", count[CB_COMPARE_SAME],
          count[CB_COMPARE_WITHIN], count[CB_COMPARE_DIFFERS], count[CB_COMPARE_NOT_COMPARED]);
  if (count[CB_COMPARE_NEW]) fprintf(f, ", %d new (no reference)", count[CB_COMPARE_NEW]);
  fputs(".\n", f);
  free(ours);
  free(ref);
  return count[CB_COMPARE_DIFFERS] ? 1 : 0;
}
