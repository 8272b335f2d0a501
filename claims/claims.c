#include "claims.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <clothbench/status.h>

/* Checkers live in claims/check_<experiment>.c; declare them here. */
void cb_check_T1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_T2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_E1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_E2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_I1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_h1(const cb_table *csv, const char *dir, cb_claim_result *out);
void cb_check_h2(const cb_table *csv, const char *dir, cb_claim_result *out);
void cb_check_newton_vs_bw_i2(const cb_table *csv, const char *results_dir, cb_claim_result *out);
void cb_check_newton_vs_bw_i3(const cb_table *csv, const char *results_dir, cb_claim_result *out);
void cb_check_j1(const cb_table *csv, const char *dir, cb_claim_result *out);
void cb_check_j2(const cb_table *csv, const char *dir, cb_claim_result *out);
void cb_check_j3(const cb_table *csv, const char *dir, cb_claim_result *out);
void cb_check_j4(const cb_table *csv, const char *dir, cb_claim_result *out);
void cb_check_B1(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_B2(const cb_table *t, const char *results_dir, cb_claim_result *out);
void cb_check_B3(const cb_table *t, const char *results_dir, cb_claim_result *out);

const cb_claim cb_claims[] = {
  {"T1", "topology", "Sorting edge triples (i<j, triangle) gives the unique edge list and the neighbouring-triangle pairs.",
   "On the lecture's 5-vertex example: edges {0,1},{0,3},{0,4},{1,2},{1,3},{2,3},{3,4}; neighbour pairs {1,2},{0,1}.",
   NULL, cb_check_T1},
  {"T2", "topology", "A manifold disk mesh has #edges = 3 #vertices - 3 - #boundary_edges; with every edge a hard constraint only 3 + #boundary_edges DoFs remain.",
   "Counted on grids and on unstructured meshes; the DoFs as 3#V - rank of the rigidity matrix at a generic embedding.", NULL, cb_check_T2},
  {"E1", "explicit_stability", "Explicit integration becomes unstable when k and/or dt are too large.",
   "(k, dt) stability map; measured critical dt within 15% of 2/omega_max; slope of log dt_crit vs log k is -1/2 +- 0.05.",
   "explicit_stability_map.png", cb_check_E1},
  {"E2", "explicit_stability", "Using a small dt makes explicit integration stable but slow.",
   "Wall time to simulate 1 s: explicit at its largest stable dt against implicit at dt = 1/30, against k and resolution; explicit cost about O(n^2).",
   "explicit_stability_cost.png", cb_check_E2},
  {"I1", "explicit_stability", "Implicit Euler (converged Newton) stays stable for every (k, dt) in the same sweep; its price is numerical damping.",
   "Same sweep: no divergence; energy lost per simulated second as a function of dt.", "explicit_stability_damping.png",
   cb_check_I1},
  {"I2", "newton_vs_bw", "Implicit Euler is x1 = argmin F(x), solved by Newton's method, which converges quadratically near the solution.",
   "Measured convergence order from the |grad F| sequence is at least 1.8.", "newton_vs_bw_convergence.png",
   cb_check_newton_vs_bw_i2},
  {"I3", "newton_vs_bw", "Baraff-Witkin's single Newton iteration is fast but can fail to converge.",
   "Step error and wall time for K = 1, 2, 3, 5, 10 and converged; the (dt, k, stretch) regime where K = 1 has error above 1% or diverges.",
   "newton_vs_bw_pareto.png", cb_check_newton_vs_bw_i3},
  {"H1", "definiteness", "A spring's Hessian is SPD when stretched and may be indefinite when compressed; A = M/dt^2 + H can then be indefinite.",
   "Fraction of Newton iterations with indefinite A on compression scenes.", "definiteness_h1.png", cb_check_h1},
  {"H2", "definiteness", "Dropping the (1 - L/|x|) term when |x| < L restores definiteness; other fixes work at different costs.",
   "Per fix: SPD rate, CG breakdowns, Newton iterations, wall time, final energy.", "definiteness_residual.png", cb_check_h2},
  {"J1", "linear_solvers", "Vanilla Jacobi needs A diagonally dominant; alpha < 2/lambda_max(D^-1 A) makes it converge for any SPD A.",
   "alpha sweep on a non-diagonally-dominant SPD A: divergence at alpha = 1 where predicted, convergence for small alpha, measured rate matches rho(I - alpha D^-1 A).",
   "linear_solvers_j1_alpha.png", cb_check_j1},
  {"J2", "linear_solvers", "Chebyshev acceleration makes Jacobi much faster (Wang 2015: at least an order of magnitude).",
   "Iterations and wall time to relative residual 1e-6, Jacobi against Chebyshev-Jacobi on the same A.", "linear_solvers_j2_speedup.png", cb_check_j2},
  {"J3", "linear_solvers", "Chebyshev needs an estimate of rho, and an overestimate diverges; the lab default 0.995 is reported to diverge where about 0.95 works.",
   "rho sweep 0.9 to 0.9999: divergence boundary, and the automatic estimate.", "linear_solvers_j3_rho.png", cb_check_j3},
  {"J4", "linear_solvers", "Direct solvers are one-shot, exact and expensive; iterative solvers are cheaper per iteration and their accuracy is controllable.",
   "Error against run time for CHOLMOD, Jacobi, Chebyshev, CG and PCG on the same Newton systems, at three mesh sizes.", "linear_solvers_j4_error_time.png", cb_check_j4},
  {"B1", "bending", "A bending spring offers little resistance when the cloth is nearly planar.",
   "Restoring force at the wing tip of one hinge against the fold angle 0-90 deg for spring, dihedral and quadratic: "
   "log-log slope over 1-10 deg >= 2.5 for the spring and within 1 +- 0.1 for both hinges.", "bending_b1_force.png",
   cb_check_B1},
  {"B2", "bending", "The quadratic bending model has a constant Hessian and makes simulation up to 3x faster than the nonlinear hinge model.",
   "Wall time per step under Newton with CHOLMOD on the sphere drape at two resolutions, quadratic against dihedral, with the "
   "assembly/factorisation/solve split and Newton iterations: 1.5x-3x reproduced, above 3x exceeded; RMS final-shape difference.",
   "bending_b2_rest.png", cb_check_B2},
  {"B3", "bending", "The quadratic bending model is no longer valid if cloth stretches much.",
   "A hinge folded by 20 deg and stretched in-plane by 0-30%: the stretch at which the quadratic energy differs from the hinge "
   "energy by more than 10% (reproduced if they agree within 10% unstretched and part within 30%).", "bending_b3_stretch.png",
   cb_check_B3},
  {"L1", NULL, "Locking: stiff in-plane edges resist folding even with zero bending stiffness.",
   "Fold angle reached under a fixed load against in-plane stiffness, with bending stiffness 0.", NULL, NULL},
};
const int cb_nclaims = (int)(sizeof cb_claims / sizeof cb_claims[0]);

const char *cb_verdict_name(cb_verdict v) {
  switch (v) {
  case CB_REPRODUCED: return "reproduced";
  case CB_PARTLY: return "partly reproduced";
  case CB_NOT_REPRODUCED: return "not reproduced";
  default: return "not run";
  }
}

static void vappend(char *buf, size_t cap, const char *fmt, va_list ap) {
  size_t n = strlen(buf);
  if (n + 1 < cap) vsnprintf(buf + n, cap - n, fmt, ap);
}

void cb_claim_numbers(cb_claim_result *r, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vappend(r->numbers, sizeof r->numbers, fmt, ap);
  va_end(ap);
}

void cb_claim_reason(cb_claim_result *r, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vappend(r->reason, sizeof r->reason, fmt, ap);
  va_end(ap);
}

void cb_claim_decide(const cb_claim *c, const char *results_dir, cb_claim_result *out) {
  memset(out, 0, sizeof *out);
  out->verdict = CB_NOT_RUN;
  if (!c->experiment || !c->check) {
    cb_claim_reason(out, "No experiment decides this claim yet.");
    return;
  }
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.csv", results_dir, c->experiment);
  cb_table t;
  int st = cb_table_read(path, &t);
  if (st == CB_EIO) {
    cb_claim_reason(out, "%s is missing: run `make experiments` (or build/%s).", path, c->experiment);
    return;
  }
  if (st) {
    cb_claim_reason(out, "%s could not be read: %s", path, cb_error_message());
    return;
  }
  c->check(&t, results_dir, out);
  cb_table_free(&t);
}

void cb_fit_line(const double *x, const double *y, int n, double *slope, double *intercept) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int i = 0; i < n; i++) {
    sx += x[i]; sy += y[i]; sxx += x[i] * x[i]; sxy += x[i] * y[i];
  }
  double d = n * sxx - sx * sx;
  *slope = d != 0 ? (n * sxy - sx * sy) / d : 0;
  *intercept = n > 0 ? (sy - *slope * sx) / n : 0;
}
