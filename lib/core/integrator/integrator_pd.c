/* Projective dynamics for mass-spring systems (Liu, Bargteil, O'Brien and
 * Kavan 2013, "Fast simulation of mass-spring systems"), and its Chebyshev
 * acceleration (Wang 2015).
 *
 * The implicit-Euler objective with springs E_e = k/2 (|x_i - x_j| - L_e)^2
 * equals min over directions |d_e| = L_e of k/2 |x_i - x_j - d_e|^2, so
 *   F(x) = min_d  1/(2 dt^2)|x - xhat|_M^2 + sum_e k/2 |x_i - x_j - d_e|^2 - sum_i m_i g.x_i
 * and alternating minimisation over d and x is a descent method on F:
 *   local   d_e = L_e (x_i - x_j)/|x_i - x_j|                 (each spring, closed form)
 *   global  (M/dt^2 + L) y = M xhat/dt^2 + f_ext + J d         (one linear solve)
 * with L = sum_e k A_e A_e^T (x) I_3 the spring Laplacian, (J d)_i =
 * sum_{e = (i, j)} k d_e - sum_{e = (j, i)} k d_e, f_ext = m g, and a pinned
 * neighbour p of a free i moving k x_p to the right-hand side. The matrix is
 * constant and of the form P (x) I_3: with CHOLMOD (the default solver) the
 * n x n P is factorised once when the integrator is built (init) and each
 * global step solves x, y and z as one 3-column right-hand side (Liu et al.
 * 2013, sec. 4); with an iterative solver, or integrator.pd_matrix = block,
 * the 3n x 3n P (x) I_3 on a copy of the system's 3x3-block pattern
 * (pd_matrix.h). Each iteration is one local step and one back-solve; no
 * factorisation happens inside a step.
 *
 *   pd            x_{k+1} = y_k                                   (K = integrator.iters)
 *   pd-chebyshev  x_{k+1} = omega_k y_k + (1 - omega_k) x_{k-1}   (rho = integrator.rho or `auto`)
 * starting from x_0 = xhat; then v1 = (x_K - x0)/dt. Plain pd never raises F
 * (Liu's guarantee: each half-step minimises over its own variables). The
 * `auto` rho is Wang's estimate from the plain iterations of the first step,
 * once (cb_rho_from_updates, as in integrator_nljacobi.c): the decay rate of
 * the updates |x_{k+1} - x_k| over the second half of n = rho_iters
 * iterations, with n doubled (the iteration continued) while the estimate
 * still rises, i.e. while 1 - rho shrinks by more than 10% per doubling, up
 * to RHO_DOUBLINGS doublings, and cut where the updates reach round-off
 * (1e-12 of the first). PD's slowest modes are a dense cluster just below
 * rho (its iteration matrix I - P^-1 grad^2 F has no negative eigenvalues),
 * so the updates' decay rate approaches rho from below only slowly: 64
 * iterations gave 0.946, 0.954 and 0.967 on the lab cloth at 21^2, 64^2 and
 * 128^2, where plain pd's own rate was 0.962, 0.996 and higher.
 *
 * Scope: the stretch springs and gravity. A scene with any other energy
 * term, or with Choi-Ko springs, is refused at init. A spring of zero length
 * keeps its rest direction. Step stats as for jacobi-nl: newton_iters = K,
 * rel_grad = rel_grad_hat = |grad F(x_K)|/|grad F(xhat)| (two gradient
 * evaluations per step: at xhat and at x_K; one per iteration more when a
 * hook observes the iterates), linear_iters the solver's iterations,
 * global_path the matrix used. */
#include <cblas.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "integrator_keys.h"

#include "nl_kernel.h"
#include "pd_matrix.h"

enum { RHO_DOUBLINGS = 5 }; /* the auto estimate runs at most rho_iters << RHO_DOUBLINGS plain iterations */
#define RHO_ROUNDOFF 1e-12  /* updates below this fraction of the first are round-off */

static const cb_pd_params pd_defaults = {
    .cookie = CB_PARAMS_COOKIE, .iters = 32, .rho = 0.0, .rho_iters = 64, .matrix = CB_PD_MATRIX_AUTO};
static const cb_pd_params pdc_defaults = {
    .cookie = CB_PARAMS_COOKIE, .iters = 32, .rho = 0.995, .rho_iters = 64, .matrix = CB_PD_MATRIX_AUTO};

cb_pd_params cb_pd_params_default(void) { return pdc_defaults; }

/* The same keys (names and definitions) as integrator_nljacobi.c's. */
#define PP(f) offsetof(cb_pd_params, f)
static const cb_param_key pd_keys[] = {
    CB_KEY_ITERS(PP(iters)),
    CB_KEY_PD_MATRIX(PP(matrix)),
    CB_KEY_END,
};
static const cb_param_key pdc_keys[] = {
    CB_KEY_ITERS(PP(iters)),      CB_KEY_RHO(PP(rho)), CB_KEY_RHO_ITERS(PP(rho_iters)),
    CB_KEY_PD_MATRIX(PP(matrix)), CB_KEY_END,
};
#undef PP

typedef struct {
  cb_objective obj;
  cb_pd_global g;       /* P = M/dt^2 + L over the free DOFs, factorised (n x n, or 3n x 3n blocks) */
  int ns;               /* springs */
  const int *ends;      /* 2*ns: the stretch springs, the mesh's edges (the spring term's arrays) */
  const double *rest;   /* ns: rest lengths L_e, m */
  double k;             /* N/m */
  double grav[3];       /* m/s^2, zero without a gravity term */
  double *c;            /* 3*nfree: M xhat/dt^2 + m g of the step */
  double *b, *y;        /* 3*nfree: right-hand side, global solution */
  double *gF;           /* 3*nfree */
  double *xprev;        /* 3*nv */
  double *dnorm;        /* rho_iters << RHO_DOUBLINGS */
  cb_spring_layout lay; /* the springs as structure of arrays, and each vertex's springs */
  double *p;            /* 4*ns: the local step's d_e (x, y, z blocks), then |x_ij|^2 */
  double rho;           /* in use; CB_AUTO until estimated */
} pd_work;

static void pd_free(cb_integrator *it) {
  pd_work *w = it->state;
  cb_objective_free(&w->obj);
  cb_pd_global_free(&w->g);
  free(w->c);
  free(w->b);
  free(w->y);
  free(w->gF);
  free(w->xprev);
  free(w->dnorm);
  free(w->p);
}

/* The local step, b = c + J d (+ pinned neighbours), in two loops with the
 * old one's arithmetic: d_e = L_e x_ij/|x_ij| of every spring (independent:
 * vectorised; the rare spring of zero or non-finite length redone with its
 * rest direction), then each free vertex gathers its springs' terms in
 * spring order, which is the order the scatter b_i += k(d_e + ...),
 * b_j += k(-d_e + ...) added them in: b is bit for bit the same. */
static void pd_local(pd_work *w, const cb_scene *s, const double *restrict x) {
  const cb_spring_layout *L = &w->lay;
  const int ns = L->ns, *restrict ei = L->ei, *restrict ej = L->ej, *restrict fi = s->free_index;
  const double *restrict rest = L->rest;
  double *restrict px = w->p, *restrict py = w->p + ns, *restrict pz = w->p + 2 * (size_t)ns;
  double *restrict len2 =
      w->p + 3 * (size_t)ns; /* |x_ij|^2, for the check below (a reduction here would stop the vectoriser) */
  for (int e = 0; e < ns; e++) {
    int i = ei[e], j = ej[e];
    double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
    double l2 = dx * dx + dy * dy + dz * dz, r = rest[e] / sqrt(l2);
    px[e] = dx * r; /* d_e = L_e (x_i - x_j)/|x_i - x_j| */
    py[e] = dy * r;
    pz[e] = dz * r;
    len2[e] = l2;
  }
  for (int e = 0; e < ns; e++) {
    if (len2[e] > 0) continue; /* no direction (|x_ij| = 0 or not a number): keep the rest one */
    const double *X = s->mesh.x;
    int i = ei[e], j = ej[e];
    px[e] = X[3 * i] - X[3 * j];
    py[e] = X[3 * i + 1] - X[3 * j + 1];
    pz[e] = X[3 * i + 2] - X[3 * j + 2];
  }
  const double k = w->k;
  for (int bb = 0; bb < s->model.nfree; bb++) {
    int v = s->free_vertex[bb];
    double b0 = w->c[3 * bb], b1 = w->c[3 * bb + 1], b2 = w->c[3 * bb + 2];
    for (int q = L->off[v]; q < L->off[v + 1]; q++) {
      int e = L->inc[q] >> 1, side = L->inc[q] & 1, o = side ? ei[e] : ej[e];
      double d0 = side ? -px[e] : px[e], d1 = side ? -py[e] : py[e], d2 = side ? -pz[e] : pz[e];
      int pinned = fi[o] < 0; /* a pinned neighbour moves k x_o to the right-hand side */
      b0 += k * (d0 + (pinned ? x[3 * o] : 0.0));
      b1 += k * (d1 + (pinned ? x[3 * o + 1] : 0.0));
      b2 += k * (d2 + (pinned ? x[3 * o + 2] : 0.0));
    }
    w->b[3 * bb] = b0;
    w->b[3 * bb + 1] = b1;
    w->b[3 * bb + 2] = b2;
  }
}

static int pd_init(cb_integrator *it) {
  const cb_pd_params *p = it->type_params;
  pd_work *w = it->state;
  const cb_scene *s = it->scene;
  const char *name = it->type->name;
  if (p->iters < 1) return cb_fail("%s: iters must be >= 1, got %d", name, p->iters);
  if (!(p->rho == CB_AUTO || (p->rho >= 0 && p->rho < 1)))
    return cb_fail("%s: rho must be in [0, 1) or auto, got %g", name, p->rho);
  if (p->rho == CB_AUTO && p->rho_iters < 4) return cb_fail("%s: rho_iters must be >= 4", name);
  for (int t = 0; t < s->sys.nterms; t++) {
    const cb_term *term = s->sys.terms[t];
    if (term->type == cb_term_gravity) {
      memcpy(w->grav, s->gravity, sizeof w->grav);
      continue;
    }
    if (term->type == cb_term_spring && strcmp(term->label, "stretch") == 0 && !cb_spring_term_is_choi_ko(term)) {
      cb_spring_term_springs(term, &w->ns, &w->ends, &w->rest, &w->k); /* the local step's springs */
      cb_spring_term_layout(term, &w->lay);
      continue;
    }
    /* the advice names the key that removes this term */
    const char *fix = cb_spring_term_is_choi_ko(term) ? "set integrator.definiteness to none, drop, mirror or shift"
                      : strcmp(term->label, "stretch") == 0  ? "set material.stretch = spring"
                      : strcmp(term->label, "collider") == 0 ? "set collider.type = project (a post-step projection) "
                                                               "or none"
                      : strncmp(term->label, "bend", 4) == 0 ? "set material.bend = none"
                                                             : "remove that term from the scene";
    return cb_fail("%s: projective dynamics here covers the stretch springs and gravity; the scene has the term '%s'%s "
                   "(%s)",
                   name, term->label, cb_spring_term_is_choi_ko(term) ? " with the Choi-Ko response" : "", fix);
  }
  int nf = s->model.nfree, nv = s->mesh.nv;
  int st = cb_objective_init(&w->obj, s);
  if (st) return st;
  w->c = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->b = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->y = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->gF = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->xprev = cb_malloc((size_t)3 * nv, sizeof(double));
  w->p = cb_malloc((size_t)4 * w->ns + 1, sizeof(double));
  if (!w->c || !w->b || !w->y || !w->gF || !w->xprev || !w->p) return CB_ENOMEM;
  if (p->rho == CB_AUTO && !(w->dnorm = cb_malloc((size_t)p->rho_iters << RHO_DOUBLINGS, sizeof(double))))
    return CB_ENOMEM;
  w->rho = p->rho;
  st = cb_pd_global_init(&w->g, it, 0, p->matrix); /* P = M/dt^2 + sum_e k A_e A_e^T, factorised once per scene */
  if (st) return cb_fail_status(st, "%s: factorising M/dt^2 + L failed (%s)", name, cb_status_name(st));
  return CB_OK;
}

/* K local/global iterations from xhat (restart) or, plain (rho = 0), on from x; dnorm (if not NULL) gets
 * |x_{k+1} - x_k|. */
static int iterate(cb_integrator *it, double *x, int K, double rho, double *dnorm, cb_step_stats *st, int report,
                   int restart) {
  pd_work *w = it->state;
  const cb_scene *s = it->scene;
  cb_newton_hook hook = report ? it->params.hook : NULL;
  int nf = s->model.nfree, nv3 = 3 * s->mesh.nv;
  double dt = it->params.dt, omega = 1.0, g0 = 0.0;
  if (restart) cb_objective_guess(&w->obj, x, 1); /* x_0 = xhat */
  memcpy(w->xprev, x, (size_t)nv3 * sizeof(double));
  for (int b = 0; b < nf; b++) { /* c = M xhat/dt^2 + m g */
    int i = s->free_vertex[b];
    for (int a = 0; a < 3; a++) w->c[3 * b + a] = s->mass[i] * (w->obj.xhat[3 * i + a] / (dt * dt) + w->grav[a]);
  }
  for (int k = 0;; k++) {
    if (report && (k == 0 || k == K || hook) && cb_integrator_measure(it, &w->obj, x, w->gF, k, &g0, -1.0, hook, st))
      return CB_DIVERGED;
    if (k == K || nf == 0) break;
    double t0 = cb_now_ms();
    pd_local(w, s, x);           /* local: d_e = L_e (x_i - x_j)/|x_i - x_j|; b = c + J d (+ pinned neighbours) */
    for (int b = 0; b < nf; b++) /* initial guess of an iterative solver: the current iterate */
      for (int a = 0; a < 3; a++) w->y[3 * b + a] = x[3 * s->free_vertex[b] + a];
    st->assemble_ms += cb_now_ms() - t0;
    int ls = cb_pd_global_solve(&w->g, it, w->b, w->y, st); /* global: (M/dt^2 + L) y = b */
    if (ls != CB_OK && ls != CB_NOT_CONVERGED) return ls == CB_ENOMEM ? CB_ENOMEM : CB_LINEAR_FAILED;
    omega = cb_chebyshev_omega(k, rho, omega);
    double d2 = 0.0;
    for (int b = 0; b < nf; b++) {
      double *xi = x + 3 * s->free_vertex[b], *xp = w->xprev + 3 * s->free_vertex[b];
      for (int a = 0; a < 3; a++) {
        double xk = xi[a], xn = omega * w->y[3 * b + a] + (1.0 - omega) * xp[a]; /* x_{k+1} = w y + (1-w) x_{k-1} */
        d2 += (xn - xk) * (xn - xk);
        xp[a] = xk;
        xi[a] = xn;
      }
    }
    if (!isfinite(d2)) return CB_DIVERGED;
    if (dnorm) dnorm[k] = sqrt(d2);
  }
  return CB_OK;
}

static int pd_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  pd_work *w = it->state;
  const cb_pd_params *p = it->type_params;
  cb_objective_begin(&w->obj, x, v, it->params.dt);
  if (w->rho == CB_AUTO) { /* Wang's estimate, once, from the first step's plain iterations (top of the file) */
    double t0 = cb_now_ms(), rho = 0.0, prev = -1.0;
    cb_step_stats scratch;
    memset(&scratch, 0, sizeof scratch);
    for (int n = p->rho_iters, done = 0, dbl = 0;; dbl++, n *= 2) {
      int es = iterate(it, x, n - done, 0.0, w->dnorm + done, &scratch, 0, done == 0);
      if (es < 0) return es; /* an error (out of memory in the solve), not an estimate of 0 */
      if (es != CB_OK) {
        rho = 0.0;
        break;
      }
      done = n;
      int m = n; /* the updates above round-off */
      while (m > 4 && !(w->dnorm[m - 1] > RHO_ROUNDOFF * w->dnorm[0])) m--;
      rho = cb_rho_from_updates(w->dnorm, m);
      if (m < n || dbl == RHO_DOUBLINGS || (prev >= 0 && 1.0 - rho >= 0.9 * (1.0 - prev))) break;
      prev = rho;
    }
    w->rho = rho;
    st->factor_ms += cb_now_ms() - t0;
  }
  st->rho = w->rho;
  int status = iterate(it, x, p->iters, w->rho, NULL, st, 1, 1);
  cb_objective_velocity(&w->obj, x, v);
  return status;
}

const cb_integrator_type cb_integrator_pd = {
    .name = "pd",
    .flags = CB_INTEGRATOR_LINEAR_SOLVER,
    .size = sizeof(pd_work),
    .params_size = sizeof(cb_pd_params),
    .params_default = &pd_defaults,
    .keys = pd_keys,
    .init = pd_init,
    .step = pd_step,
    .free = pd_free,
};

const cb_integrator_type cb_integrator_pd_chebyshev = {
    .name = "pd-chebyshev",
    .flags = CB_INTEGRATOR_LINEAR_SOLVER,
    .size = sizeof(pd_work),
    .params_size = sizeof(cb_pd_params),
    .params_default = &pdc_defaults,
    .keys = pdc_keys,
    .init = pd_init,
    .step = pd_step,
    .free = pd_free,
};
