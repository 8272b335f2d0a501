/* Choi-Ko response of a compressed spring (cb_spring_term_set_response).
 *
 * Choi & Ko 2002, "Stable but Responsive Cloth", ACM TOG 21(3) (SIGGRAPH),
 * Section 4, the immediate buckling model of the post-buckling response: a
 * compressed spring does not shorten as a straight bar; it buckles at once
 * into a circular arc whose length stays L (the rest length) and whose chord
 * is l. The arc's curvature kappa follows from the chord,
 *     l = (2/kappa) sin(kappa L / 2) = L sinc(theta),   theta = kappa L / 2,
 * and its energy is the bending energy of the arc,
 *     E_b = 1/2 k_b Integral kappa^2 ds = 1/2 k_b L kappa^2 = 2 k_b theta^2 / L,
 * with k_b the bending stiffness (N m^2, material.buckling_kb). Differentiating
 * through l(theta) (s = sin theta - theta cos theta, r = 3 s - theta^2 sin theta):
 *     dl/dtheta  = -L s / theta^2
 *     dE/dl      = -k_b kappa^2 / (sinc theta - cos theta) = -4 k_b theta^3 / (L^2 s)
 *     d2E/dl^2   =  4 k_b theta^4 r / (L^3 s^3)
 * dE/dl is minus the paper's buckling force magnitude f_b = k_b kappa^2 /
 * (sinc(kappa L/2) - cos(kappa L/2)), which pushes the two ends apart along u.
 * Limits: f_b -> 12 k_b / L^2 and d2E/dl^2 -> 36 k_b / (5 L^3) as l -> L-, and
 * f_b -> 4 pi^2 k_b / L^2 as l -> 0. So E is continuous at l = L but its slope
 * jumps from -12 k_b/L^2 to 0 (the "immediate" buckling: no compression phase).
 * A stretched spring (l >= L) keeps E = k/2 (l - L)^2.
 *
 * The paper's response is discontinuous: the push jumps from 0 (l = L+) to
 * 12 k_b/L^2 (l = L-). Newton iterated to a tolerance cannot converge across
 * such a jump: with the pure response, the hanging scene (30 steps, k_b =
 * 0.01) hit max_iters = 50 in 29 of 30 steps, with |grad F| still up to 0.5
 * of its initial value (commit 7dd6abf, README). We therefore make the force
 * continuous, our one change to the model: the spring keeps its linear
 * response while its push k (L - l) is below f_b(l), and buckles beyond the
 * crossing l* where k (L - l*) = f_b(l*):
 *     E(l) = 1/2 k (l - L)^2                          for l >= l*
 *     E(l) = 1/2 k (L - l*)^2 + E_b(l) - E_b(l*)      for l <  l*
 * E is C^1 (its force is continuous) and piecewise C^2. For k = 8000 N/m,
 * L = 0.5 m, k_b = 0.01 N m^2, L - l* = 6e-5 m: the paper's response holds
 * for every compression beyond 0.012 %. The crossing is unique when the
 * buckled branch is softer than the spring, k > max E_b'' = 12 pi^2 k_b/L^3
 * (E_b'' grows from 36 k_b/(5 L^3) at l = L to 12 pi^2 k_b/L^3 at l = 0);
 * cb_choi_ko_init checks it.
 *
 * The spring Hessian of any E(l) is E'' uu^T + (E'/l)(I - uu^T). For the
 * buckled spring E'' > 0 on (0, L) (tested) and the transverse coefficient is
 * E'/l = -f_b / l < 0: still negative, but bounded by 4 pi^2 k_b / (L^2 l),
 * i.e. by the bending stiffness instead of k(L/l - 1) (on the linear part
 * before l*, |k(1 - L/l)| <= f_b(l*)/l: the same bound). That is the sense
 * in which the paper's response keeps the system well behaved ("stable");
 * we keep this exact Jacobian (no extra clamping) and measure whether A
 * stays SPD rather than assume it.
 *
 * What else we do differently from the paper, and why:
 *  - The paper approximates f_b(l) by a fitted polynomial because kappa has
 *    no closed form in l. We solve sinc(theta) = l/L for theta by safeguarded
 *    Newton to round-off instead, so the force is the exact gradient of E_b
 *    and the Hessian is exact (a fit of f_b alone would not be the gradient of
 *    any fitted energy, and Newton's convergence test on grad F needs one).
 *  - The paper applies the buckling response to its cloth's interaction
 *    springs with their own k_b; we apply it to every spring term of the
 *    scene (stretch and, if present, bending springs) with one k_b.
 *  - We did not have the paper's text at hand: the equations above are
 *    derived here from the model it states (circular arc of length L, bending
 *    energy 1/2 k_b Int kappa^2 ds), so no equation numbers are cited.
 *    tests/test_definiteness.c checks dE/dl and d2E/dl^2 against finite
 *    differences of E and the limits above. */
#include <math.h>

#include <clothbench/energy.h>
#include <clothbench/status.h>

/* q = 1 - sinc(theta), s = sin(theta) - theta cos(theta),
 * r = 3 s - theta^2 sin(theta), without cancellation for small theta:
 *   a_n = theta^(2n+1) / (2n+1)!
 *   q = sum_{n>=1} (-1)^(n+1) a_n / theta
 *   s = sum_{n>=1} (-1)^(n+1) 2n a_n
 *   r = sum_{n>=2} (-1)^n 4n(n-1) a_n */
static void buckle_terms(double th, double *q, double *s, double *r) {
  if (th >= 1.0) {
    double sn = sin(th), cs = cos(th);
    *q = 1.0 - sn / th;
    *s = sn - th * cs;
    *r = 3.0 * *s - th * th * sn;
    return;
  }
  double a = th, t2 = th * th, qs = 0, ss = 0, rs = 0;
  for (int n = 1; n < 40; n++) {
    a *= t2 / ((2.0 * n) * (2.0 * n + 1)); /* a_n = a_{n-1} theta^2 / ((2n)(2n+1)) */
    double sg = (n % 2) ? 1.0 : -1.0;      /* (-1)^(n+1) */
    qs += sg * a / th;
    ss += sg * 2.0 * n * a;
    rs -= sg * 4.0 * n * (n - 1) * a;
    if (a < 1e-18 * fabs(ss)) break;
  }
  *q = qs;
  *s = ss;
  *r = rs;
}

/* theta in (0, pi) with 1 - sinc(theta) = c, c = (L - l)/L in (0, 1):
 * Newton on q(theta) - c, q' = s / theta^2, kept inside a bisection bracket. */
static double buckle_theta(double c) {
  double lo = 0.0, hi = 3.14159265358979323846; /* pi: the arc closes into a circle at l = 0 */
  double th = sqrt(6.0 * c);                    /* q ~ theta^2/6 */
  if (!(th < hi)) th = 0.5 * (lo + hi);
  for (int it = 0; it < 100; it++) {
    double q, s, r;
    buckle_terms(th, &q, &s, &r);
    double f = q - c;
    if (f > 0) hi = th;
    else lo = th;
    double next = th - f * th * th / s; /* theta -= (q - c) / q' */
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (fabs(next - th) <= 1e-15 * th || hi - lo <= 1e-16 * hi) {
      th = next;
      break;
    }
    th = next;
  }
  return th;
}

double cb_choi_ko_response(double L, double l, double kb, double *E, double *dE, double *d2E) {
  double c = (L - l) / L; /* 1 - sinc(theta) */
  if (!(c > 0)) {         /* not compressed: no buckling energy */
    *E = 0;
    *dE = 0;
    *d2E = 0;
    return 0.0;
  }
  if (c > 1) c = 1; /* l < 0 cannot occur; guard */
  double th = buckle_theta(c), q, s, r;
  buckle_terms(th, &q, &s, &r);
  double th2 = th * th;
  *E = 2.0 * kb * th2 / L;                                   /* E_b = 2 k_b theta^2 / L */
  *dE = -4.0 * kb * th2 * th / (L * L * s);                  /* dE/dl = -4 k_b theta^3 / (L^2 s) */
  *d2E = 4.0 * kb * th2 * th2 * r / (L * L * L * s * s * s); /* d2E/dl2 = 4 k_b theta^4 r / (L^3 s^3) */
  return th;
}

/* Crossing of the linear push k L c with the buckling push f_b at compression
 * c = (L - l)/L: G(c) = k L c - f_b(c), G(0+) = -12 k_b/L^2 < 0,
 * dG/dc = L (k - E_b''). Newton kept inside a bisection bracket. */
int cb_choi_ko_init(cb_choi_ko *c, double k, double L, double kb) {
  c->k = k;
  c->L = L;
  c->kb = kb;
  c->lc = L;
  c->Ec = 0;
  if (!(k > 0 && L > 0 && kb > 0))
    return cb_fail("choi-ko: need k > 0, L > 0, k_b > 0 (k = %g, L = %g, k_b = %g)", k, L, kb);
  double emax = 12.0 * 3.14159265358979323846 * 3.14159265358979323846 * kb / (L * L * L); /* 12 pi^2 k_b / L^3 */
  if (!(k > emax))
    return cb_fail("choi-ko: k_b = %g N m^2 is too stiff for k = %g N/m and L = %g m (need k > 12 pi^2 k_b / L^3 = %g)",
                   kb, k, L, emax);
  double E, dE, d2E, lo = 0, hi = 1, cc = 12.0 * kb / (k * L * L * L); /* f_b ~ 12 k_b/L^2 near c = 0 */
  cb_choi_ko_response(L, 0.0, kb, &E, &dE, &d2E);
  if (k * L + dE <= 0) return CB_OK; /* G(1) <= 0: the linear push never reaches f_b (no buckling) */
  if (!(cc < 1)) cc = 0.5;
  for (int it = 0; it < 200; it++) {
    cb_choi_ko_response(L, L * (1 - cc), kb, &E, &dE, &d2E);
    double G = k * L * cc + dE; /* k L c - f_b */
    if (G > 0) hi = cc;
    else lo = cc;
    double next = cc - G / (L * (k - d2E));
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (fabs(next - cc) <= 1e-15 * cc || hi - lo <= 1e-16 * hi) {
      cc = next;
      break;
    }
    cc = next;
  }
  c->lc = cc * L;
  cb_choi_ko_response(L, L - c->lc, kb, &c->Ec, &dE, &d2E);
  return CB_OK;
}

void cb_choi_ko_eval(const cb_choi_ko *c, double l, double *E, double *dE, double *d2E) {
  if (l >= c->L - c->lc) { /* linear spring: E = k/2 (l - L)^2 */
    *E = 0.5 * c->k * (l - c->L) * (l - c->L);
    *dE = c->k * (l - c->L);
    *d2E = c->k;
    return;
  }
  cb_choi_ko_response(c->L, l, c->kb, E, dE, d2E); /* buckled: E_b(l) */
  *E += 0.5 * c->k * c->lc * c->lc - c->Ec;        /* + 1/2 k (L - l*)^2 - E_b(l*) */
}
