/* C2 (experiments/contact): Coulomb's stick-slip threshold on the slope (configs/slope.ini) under ipc's
 * lagged, smoothed friction, measured with lib/instruments/slope.h.
 *
 * Per angle theta, results/contact_c2.csv gets
 *   slide rows      the centre of mass's slide along the slope after t_end for mu = f tan theta,
 *                   f in {0.5, 0.9, 1.1, 1.5, 2}, beside the sliding block's closed form
 *                   (g (sin theta - mu cos theta) t^2 / 2, 0 when mu >= tan theta);
 *   a threshold row mu*: the bisection on "slid more than s_tol in t_end" (s_tol = 1 cm (t_end / 1 s)^2,
 *                   so the rule asks the same mean acceleration at every t_end; bracket to 2% of tan theta),
 *                   with the creep of the holding end of the last bracket;
 *   a vbd row       the same slide under integrator.method = vbd, which C2 names too: VBD's contact blocks
 *                   carry no friction, so the integrator refuses contact.friction > 0 (status refused, the
 *                   reason in note) until they do.
 * Newton with its line search is ipc's home (the scene's integrator). */
#include "c2.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>
#include "config.h"
#include "csv.h"
#include "scene_decl.h"
#include "slope.h"

static const double FACTORS[] = {0.5, 0.9, 1.1, 1.5, 2.0};

/* a message as one CSV field: no commas, quotes or line ends */
static void field(char *dst, size_t n, const char *src) {
  snprintf(dst, n, "%s", src);
  for (char *c = dst; *c; c++)
    if (*c == ',' || *c == '"' || *c == '\n' || *c == '\r') *c = ';';
}

int contact_c2_cell(const contact_c2_plan *p, long i, FILE *f) {
  const double pi = 3.14159265358979323846, na = cb_csv_na();
  double th = p->theta[i], tn = tan(th * pi / 180), t_end = p->t_end;
  double s_tol = 0.01 * t_end * t_end; /* m: 1 cm after 1 s */
  static const cb_scene_decl slope = {"slope", "slope.ini", {NULL}, "c2"};
  cb_config *cfg = malloc(sizeof *cfg);
  if (!cfg) return cb_fail_status(CB_ENOMEM, "contact: C2: no memory for a config");
  char note[256];
  int st = cb_scene_decl_config(p->e, &slope, NULL, cfg);
  if (st) { /* the scene's config: one row with its status */
    field(note, sizeof note, cb_error_message());
    cb_csv_printf(f, "slide,,%.17g,%.17g,,,,,,,,,,,,,,%s,%s\n", th, tn, note, cb_status_name(st));
    free(cfg);
    return st == CB_ENOMEM || st == CB_EIO ? st : CB_OK;
  }
  const char *integ = cfg->method;
  for (size_t k = 0; k < sizeof FACTORS / sizeof *FACTORS; k++) {
    cb_slope_run r;
    double mu = FACTORS[k] * tn;
    st = cb_slope_slide(cfg, th, mu, t_end, &r);
    if (st) {
      field(note, sizeof note, cb_error_message());
      cb_csv_printf(f, "slide,%s,%.17g,%.17g,%.17g,%.17g,,,,,,,,,,1,,%s,%s\n", integ, th, tn, mu, FACTORS[k], note,
                    cb_status_name(st));
      continue;
    }
    cb_csv_printf(f, "slide,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%d,,,,,1,%.6f,,%s\n", integ, th, tn, mu,
                  FACTORS[k], r.slide, r.closed_form, r.drift, r.steps, r.not_converged, r.wall_ms,
                  cb_status_name(r.not_converged ? CB_NOT_CONVERGED : CB_OK));
  }
  cb_slope_threshold m;
  st = cb_slope_find_threshold(cfg, th, t_end, s_tol, 3 * tn, 0.02, &m);
  if (st) {
    field(note, sizeof note, cb_error_message());
    cb_csv_printf(f, "threshold,%s,%.17g,%.17g,,,,,,,,,,,,,,%s,%s\n", integ, th, tn, note, cb_status_name(st));
  } else {
    snprintf(note, sizeof note, "s_tol %.3g m", s_tol);
    cb_csv_printf(f, "threshold,%s,%.17g,%.17g,,%.17g,%.17g,,,,,%.17g,%.17g,%.17g,%.17g,%d,%.6f,%s,%s\n", integ, th, tn,
                  m.bracketed ? m.mu_star / tn : na, m.slide_lo, m.bracketed ? m.mu_star : na, m.lo, m.hi, m.slide_hi,
                  m.runs, m.wall_ms, note, m.bracketed ? "ok" : "not_bracketed");
  }
  /* VBD, which C2 names beside ipc */
  if (cb_config_set(cfg, "integrator.method=vbd") == CB_OK) {
    cb_slope_run r;
    double mu = 0.5 * tn;
    st = cb_slope_slide(cfg, th, mu, t_end, &r);
    if (st) {
      field(note, sizeof note, cb_error_message());
      cb_csv_printf(f, "slide,vbd,%.17g,%.17g,%.17g,0.5,,,,,,,,,,1,,%s,%s\n", th, tn, mu, note,
                    strstr(note, "contact.friction") ? "refused" : cb_status_name(st));
    } else
      cb_csv_printf(f, "slide,vbd,%.17g,%.17g,%.17g,0.5,%.17g,%.17g,%.17g,%d,%d,,,,,1,%.6f,,%s\n", th, tn, mu, r.slide,
                    r.closed_form, r.drift, r.steps, r.not_converged, r.wall_ms,
                    cb_status_name(r.not_converged ? CB_NOT_CONVERGED : CB_OK));
  }
  free(cfg);
  return CB_OK;
}
