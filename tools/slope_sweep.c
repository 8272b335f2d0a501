/* slope-sweep: claim C2's measurement on the slope scene (issue 34 §2-3;
 * docs/contact.md, "Friction"): the slide after t seconds against mu for
 * several theta, and the stick-slip threshold mu* against tan theta, through
 * the slope instrument (lib/instruments/slope.h).
 *
 *   slope-sweep [CONFIG] [--theta LIST] [--mu-factors LIST] [--t T] [--s-tol S] [--rtol R]
 *               [--set section.key=value]... [-o OUT.csv]
 *
 * One CSV (provenance lines first), one row per run: kind `slide` (theta, mu
 * = factor tan theta, the slide and the sliding block's closed form) or kind
 * `threshold` (theta, mu* and its bracket, the runs it took). Exit: 0 ok, 1 a
 * run failed (its message), 2 usage, 3 the output could not be written. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

#include "config.h"
#include "csv.h"
#include "outfile.h"
#include "provenance.h"
#include "slope.h"

#define MAX_LIST 32

static void usage(FILE *f) {
  fprintf(f, "usage: slope-sweep [CONFIG] [--theta LIST] [--mu-factors LIST] [--t T] [--s-tol S] [--rtol R]\n"
             "                   [--set section.key=value]... [-o OUT.csv]\n"
             "Claim C2's measurement on a slope scene (default configs/slope.ini): the slide of the cloth's\n"
             "centre of mass after T seconds for mu = factor x tan(theta), and the stick-slip threshold mu*\n"
             "(bisection of mu on slide > S), for each theta.\n"
             "  --theta LIST        slope angles in degrees, comma-separated (default 10,20,30)\n"
             "  --mu-factors LIST   mu / tan(theta) of the slide rows (default 0,0.5,0.9,1.1,1.5,2)\n"
             "  --t T               seconds of each run (default 1)\n"
             "  --s-tol S           slide (m) above which the cloth slides, for mu* (default 0.01)\n"
             "  --rtol R            mu*'s bracket width, relative to tan(theta) (default 0.02)\n"
             "  --set k=v           override a config key (repeatable)\n"
             "  -o OUT.csv          output (default results/slope_sweep.csv; - for stdout)\n"
             "Exit: 0 ok, 1 a run failed, 2 usage, 3 i/o error.\n");
}

static int parse_list(const char *s, double *v, int *n) {
  *n = 0;
  while (*s) {
    char *end;
    if (*n == MAX_LIST) return 1;
    v[(*n)++] = strtod(s, &end);
    if (end == s || !isfinite(v[*n - 1])) return 1;
    s = end;
    if (*s == ',') s++;
    else if (*s) return 1;
  }
  return *n == 0;
}

static int parse_num(const char *s, double *v) {
  char *end;
  *v = strtod(s, &end);
  return end == s || *end || !isfinite(*v);
}

int main(int argc, char **argv) {
  if (cb_runtime_init()) {
    fprintf(stderr, "slope-sweep: %s\n", cb_error_message());
    return 2;
  }
  const char *cfg_path = "configs/slope.ini", *out = "results/slope_sweep.csv";
  double thetas[MAX_LIST] = {10, 20, 30}, factors[MAX_LIST] = {0, 0.5, 0.9, 1.1, 1.5, 2};
  int ntheta = 3, nfactor = 6;
  double t_end = 1, s_tol = 0.01, rtol = 0.02;
  const char *sets[64];
  int nsets = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
    int bad = 0;
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
      usage(stdout);
      return 0;
    } else if (!strcmp(a, "--theta") && val) bad = parse_list(val, thetas, &ntheta), i++;
    else if (!strcmp(a, "--mu-factors") && val) bad = parse_list(val, factors, &nfactor), i++;
    else if (!strcmp(a, "--t") && val) bad = parse_num(val, &t_end), i++;
    else if (!strcmp(a, "--s-tol") && val) bad = parse_num(val, &s_tol), i++;
    else if (!strcmp(a, "--rtol") && val) bad = parse_num(val, &rtol), i++;
    else if (!strcmp(a, "--set") && val && nsets < 64) sets[nsets++] = val, i++;
    else if (!strcmp(a, "-o") && val) out = val, i++;
    else if (a[0] != '-' && i == 1) cfg_path = a;
    else bad = 1;
    if (bad) {
      fprintf(stderr, "slope-sweep: bad argument '%s'%s%s\n", a, val ? " " : "", val ? val : "");
      usage(stderr);
      return 2;
    }
  }
  cb_config *c = malloc(sizeof *c);
  if (!c) return 1;
  int st = cb_config_load(cfg_path, c);
  for (int k = 0; k < nsets && !st; k++) st = cb_config_set(c, sets[k]);
  if (!st) st = cb_config_validate(c);
  if (st) {
    fprintf(stderr, "slope-sweep: %s\n", cb_error_message());
    free(c);
    return 1;
  }
  cb_outfile o = {0};
  if (cb_outfile_open(&o, out)) {
    fprintf(stderr, "slope-sweep: %s\n", cb_error_message());
    free(c);
    return 3;
  }
  cb_provenance_write(o.f, "slope-sweep", argc, argv, c);
  fprintf(o.f, "kind,theta_deg,tan_theta,mu,mu_over_tan,slide_m,closed_form_m,drift_m,steps,not_converged,"
               "friction_pairs,mu_star,mu_lo,mu_hi,slide_lo_m,slide_hi_m,runs,wall_ms\n");
  const double pi = 3.14159265358979323846, na = cb_csv_na();
  for (int ti = 0; ti < ntheta && !st; ti++) {
    double th = thetas[ti], tn = tan(th * pi / 180);
    for (int fi = 0; fi < nfactor && !st; fi++) {
      cb_slope_run r;
      double mu = factors[fi] * tn;
      if ((st = cb_slope_slide(c, th, mu, t_end, &r))) break;
      cb_csv_printf(o.f, "slide,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%d,%ld,%g,%g,%g,%g,%g,1,%.6f\n", th, tn,
                    mu, factors[fi], r.slide, r.closed_form, r.drift, r.steps, r.not_converged, r.friction_pairs, na,
                    na, na, na, na, r.wall_ms);
      fprintf(stderr, "theta %g mu %.4f (%.2f tan): slide %.6g m, block %.6g m\n", th, mu, factors[fi], r.slide,
              r.closed_form);
    }
    if (st) break;
    cb_slope_threshold m;
    if ((st = cb_slope_find_threshold(c, th, t_end, s_tol, 3 * tn, rtol, &m))) break;
    cb_csv_printf(o.f, "threshold,%.17g,%.17g,%g,%.17g,%g,%g,%g,%g,%g,%g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.6f\n", th,
                  tn, na, m.mu_star / tn, na, na, na, na, na, na, m.mu_star, m.lo, m.hi, m.slide_lo, m.slide_hi, m.runs,
                  m.wall_ms);
    fprintf(stderr, "theta %g: mu* = %.5g, tan theta = %.5g (mu*/tan %.4f), bracket [%.5g, %.5g], %d runs\n", th,
            m.mu_star, tn, m.mu_star / tn, m.lo, m.hi, m.runs);
  }
  if (st) {
    fprintf(stderr, "slope-sweep: %s\n", cb_error_message());
    cb_outfile_abort(&o);
    free(c);
    return 1;
  }
  free(c);
  if (cb_outfile_commit(&o)) {
    fprintf(stderr, "slope-sweep: %s\n", cb_error_message());
    return 3;
  }
  return 0;
}
