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
 * constant: it is assembled on the system's 3x3-block pattern (a copy, so
 * Newton's matrix is untouched), factorised once when the integrator is built
 * (init) with the linear solver named by solver.method (CHOLMOD by
 * default), and each iteration is one local step and one back-solve; no
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
 * hook observes the iterates), linear_iters the solver's iterations. */
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

#include "pd_matrix.h"

enum { RHO_DOUBLINGS = 5 }; /* the auto estimate runs at most rho_iters << RHO_DOUBLINGS plain iterations */
#define RHO_ROUNDOFF 1e-12   /* updates below this fraction of the first are round-off */

static const cb_pd_params pd_defaults = {.iters = 32, .rho = 0.0, .rho_iters = 64};
static const cb_pd_params pdc_defaults = {.iters = 32, .rho = 0.995, .rho_iters = 64};

cb_pd_params cb_pd_params_default(void) { return pdc_defaults; }

/* The same keys (names and definitions) as integrator_nljacobi.c's. */
#define PP(f) offsetof(cb_pd_params, f)
static const cb_param_key pd_keys[] = {
    CB_KEY_ITERS(PP(iters)),
    CB_KEY_END,
};
static const cb_param_key pdc_keys[] = {
    CB_KEY_ITERS(PP(iters)),
    CB_KEY_RHO(PP(rho)),
    CB_KEY_RHO_ITERS(PP(rho_iters)),
    CB_KEY_END,
};
#undef PP

typedef struct {
  cb_objective obj;
  cb_sparse P;          /* M/dt^2 + L on the system's pattern (free DOFs) */
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
  double rho;           /* in use; CB_PARAM_AUTO until estimated */
} pd_work;

static void pd_free(cb_integrator *it) {
  pd_work *w = it->state;
  cb_objective_free(&w->obj);
  cb_sparse_free(&w->P);
  free(w->c); free(w->b); free(w->y); free(w->gF); free(w->xprev); free(w->dnorm);
}

static int pd_init(cb_integrator *it) {
  const cb_pd_params *p = it->type_params;
  pd_work *w = it->state;
  const cb_scene *s = it->scene;
  const char *name = it->type->name;
  if (p->iters < 1) return cb_fail("%s: iters must be >= 1, got %d", name, p->iters);
  if (!(p->rho == CB_PARAM_AUTO || (p->rho >= 0 && p->rho < 1))) return cb_fail("%s: rho must be in [0, 1) or auto, got %g", name, p->rho);
  if (p->rho == CB_PARAM_AUTO && p->rho_iters < 4) return cb_fail("%s: rho_iters must be >= 4", name);
  for (int t = 0; t < s->sys.nterms; t++) {
    const cb_term *term = s->sys.terms[t];
    if (term->type == cb_term_gravity) {
      memcpy(w->grav, s->gravity, sizeof w->grav);
      continue;
    }
    if (term->type == cb_term_spring && strcmp(term->label, "stretch") == 0 && !cb_spring_term_is_choi_ko(term)) {
      cb_spring_term_springs(term, &w->ns, &w->ends, &w->rest, &w->k); /* the local step's springs */
      continue;
    }
    /* the advice names the key that removes this term */
    const char *fix = cb_spring_term_is_choi_ko(term) ? "set integrator.definiteness to none, drop, mirror or shift"
                      : strcmp(term->label, "stretch") == 0 ? "set material.stretch = spring"
                      : strcmp(term->label, "collider") == 0 ? "set collider.type = project (a post-step projection) or none"
                      : strncmp(term->label, "bend", 4) == 0 ? "set material.bend = none"
                                                            : "remove that term from the scene";
    return cb_fail("%s: projective dynamics here covers the stretch springs and gravity; the scene has the term '%s'%s (%s)",
                   name, term->label, cb_spring_term_is_choi_ko(term) ? " with the Choi-Ko response" : "", fix);
  }
  int nf = s->model.nfree, nv = s->mesh.nv;
  int st = cb_objective_init(&w->obj, s);
  if (st == CB_OK) st = cb_pd_matrix_build(s, it->params.dt, 0, &w->P); /* P = M/dt^2 + sum_e k A_e A_e^T (x) I_3 */
  if (st) return st;
  w->c = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->b = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->y = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->gF = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->xprev = cb_malloc((size_t)3 * nv, sizeof(double));
  if (!w->c || !w->b || !w->y || !w->gF || !w->xprev) return CB_ENOMEM;
  if (p->rho == CB_PARAM_AUTO && !(w->dnorm = cb_malloc((size_t)p->rho_iters << RHO_DOUBLINGS, sizeof(double)))) return CB_ENOMEM;
  w->rho = p->rho;
  if (nf == 0) return CB_OK;
  st = cb_solver_factor(it->solver, &w->P); /* once per scene */
  if (st) return cb_fail_status(st, "%s: factorising M/dt^2 + L failed (%s)", name, cb_status_name(st));
  return CB_OK;
}

/* K local/global iterations from xhat (restart) or, plain (rho = 0), on from x; dnorm (if not NULL) gets
 * |x_{k+1} - x_k|. */
static int iterate(cb_integrator *it, double *x, int K, double rho, double *dnorm, cb_step_stats *st, int report, int restart) {
  pd_work *w = it->state;
  const cb_scene *s = it->scene;
  const int *fi = s->free_index;
  cb_newton_hook hook = report ? it->params.hook : NULL;
  int nf = s->model.nfree, nf3 = 3 * nf, nv3 = 3 * s->mesh.nv;
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
    memcpy(w->b, w->c, (size_t)nf3 * sizeof(double));
    for (int e = 0; e < w->ns; e++) { /* local: d_e = L_e (x_i - x_j)/|x_i - x_j|; b += J d (+ pinned neighbours) */
      int i = w->ends[2 * e], j = w->ends[2 * e + 1], bi = fi[i], bj = fi[j];
      if (bi < 0 && bj < 0) continue;
      const double *xi = x + 3 * i, *xj = x + 3 * j;
      double d[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
      double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (l > 0) {
        for (int a = 0; a < 3; a++) d[a] *= w->rest[e] / l;
      } else { /* no direction: keep the rest one */
        const double *X = s->mesh.x;
        for (int a = 0; a < 3; a++) d[a] = X[3 * i + a] - X[3 * j + a];
      }
      for (int a = 0; a < 3; a++) {
        if (bi >= 0) w->b[3 * bi + a] += w->k * (d[a] + (bj < 0 ? xj[a] : 0.0));
        if (bj >= 0) w->b[3 * bj + a] += w->k * (-d[a] + (bi < 0 ? xi[a] : 0.0));
      }
    }
    for (int b = 0; b < nf; b++) /* initial guess of an iterative solver: the current iterate */
      for (int a = 0; a < 3; a++) w->y[3 * b + a] = x[3 * s->free_vertex[b] + a];
    st->assemble_ms += cb_now_ms() - t0;
    int ls = cb_solver_solve(it->solver, &w->P, w->b, w->y); /* global: (M/dt^2 + L) y = b */
    st->solve_ms += it->solver->stats.solve_ms;
    st->linear_iters += it->solver->stats.iters;
    st->linear_status = ls;
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
  if (w->rho == CB_PARAM_AUTO) { /* Wang's estimate, once, from the first step's plain iterations (top of the file) */
    double t0 = cb_now_ms(), rho = 0.0, prev = -1.0;
    cb_step_stats scratch;
    memset(&scratch, 0, sizeof scratch);
    for (int n = p->rho_iters, done = 0, dbl = 0;; dbl++, n *= 2) {
      int es = iterate(it, x, n - done, 0.0, w->dnorm + done, &scratch, 0, done == 0);
      if (es < 0) return es; /* an error (out of memory in the solve), not an estimate of 0 */
      if (es != CB_OK) { rho = 0.0; break; }
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
