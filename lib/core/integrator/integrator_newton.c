/* Implicit Euler by Newton's method (lecture, "Simulation by Newton's Method").
 *
 *   F(x)      = 1/(2 dt^2) |x - xhat|_M^2 + E(x),        xhat = x0 + dt v0
 *   grad F(x) = M (x - xhat) / dt^2 + dE/dx(x)            (E includes gravity)
 *   A         = M / dt^2 + H(x)
 *   repeat:  A dx = -grad F;  x += alpha dx
 *   until |grad F(x)| <= tol |grad F(x(0))|, or max|alpha dx| <= tol_dx, or
 *   max_iters linear solves. Then v1 = (x1 - x0) / dt.
 *
 * Initial guess x(0) = x0 + dt v0 ("predict") or x0. The optional line search
 * is backtracking with Armijo's condition
 *   F(x + alpha dx) <= F(x) + 1e-4 alpha grad F . dx,  alpha = 1, 1/2, 1/4, ...
 * and needs a descent direction (grad F . dx < 0); otherwise the step ends
 * with status line_search_failed. Near the minimiser the decrease that
 * Armijo's test must see, ~ |grad F . dx|, falls below the round-off of F
 * (F sums terms of size S = |x - xhat|_M^2/(2 dt^2) + sum_t |E_t|, each
 * carrying eps S), and the test then decides on noise: on the lab scene the
 * search stalled at rel_grad ~ 1e-7 with alpha -> 0. So when
 * |grad F . dx| <= LS_FLAT S the full step is taken without a test (there
 * the Newton step is tiny: |dx|_M^2 / dt^2 <= |grad F . dx|).
 * Only free DOFs move; pinned rows and columns are eliminated.
 * A pinned vertex is at its prescribed position x0 + dt v0 (its velocity v0
 * is prescribed: 0 for fixed pins, see scene.pin_squeeze) whatever the
 * initial guess, and keeps v0.
 *
 * The linear solve goes through cb_shift_solve (solver_shift.c), so
 * the `shift` policy's retries with A + mu I happen there, for every solver;
 * the largest mu of the step is reported in the step stats.
 *
 * A constant matrix is factorised once: when every term with a Hessian is
 * CB_TERM_CONSTANT_HESSIAN (frozen-R FEM, gravity), A = M/dt^2 + H does
 * not depend on x, so with a direct solver and any policy but `shift` the
 * factorisation of the first iteration serves every later iteration and
 * step at the same dt (A is still assembled, cheaply, for the hooks). This is
 * projective dynamics' prefactorisation.
 *
 * The line-search filter (system.h): when a term bounds the step (IPC's CCD,
 * contact.h), the predictor x0 + dt v0 is cut to x0 + a (xhat - x0) and every
 * update dx to alpha_max dx, alpha_max = cb_system_max_step(x, x + dx); the
 * line search then halves from alpha_max. No accepted iterate crosses a
 * contact the filter sees.
 *
 * F, grad F, the predictor and the velocity update are the shared objective
 * (objective.h). Newton's parameters are cb_newton_params (integrator.h). */
#include <cblas.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/solver_shift.h>
#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "integrator_keys.h"

enum { LS_MAX_HALVINGS = 40 };
#define LS_FLAT 1e-12 /* |grad F . dx| / S below which F cannot resolve the decrease */

typedef struct {
  cb_objective obj;    /* F, grad F, xhat, x0 */
  double *xtrial;      /* 3*nv */
  double *gF, *b, *dx; /* 3*nfree */
  cb_shift *shift;     /* workspace of the shift policy */
  int constant_A;      /* every Hessian term is constant and the solver direct */
  double factored_dt;  /* dt of the factorisation kept for a constant A; 0 = none */
  int filtered;        /* a term bounds the step (max_step, the line-search filter): the predictor and every
                          update are cut to the bound (cb_system_max_step) */
} newton_work;

static const cb_newton_params newton_defaults = {.cookie = CB_PARAMS_COOKIE,
                                                 .max_iters = 50,
                                                 .tol = 1e-8,
                                                 .tol_dx = 0,
                                                 .init_predict = 1,
                                                 .line_search = 0,
                                                 .definiteness = CB_DEF_DROP};

cb_newton_params cb_newton_params_default(void) { return newton_defaults; }

_Static_assert(sizeof(cb_definiteness) == sizeof(int), "CB_PARAM_CHOICE fields are int-sized");

/* Newton's config keys (integrator.<name>); the defaults are newton_defaults. */
static const char *const init_names[] = {"predict", "x0", NULL};
static const int init_values[] = {1, 0}; /* init_predict */
#define NP(f) offsetof(cb_newton_params, f)
static const cb_param_key newton_keys[] = {
    {.name = "max_iters",
     .kind = CB_PARAM_INT,
     .offset = NP(max_iters),
     .def = "50",
     .unit = "iterations",
     .lo = 1,
     .hi = 1000000,
     .doc = "Newton iterations per step at most; 1 is Baraff-Witkin's single linear solve."},
    CB_KEY_TOL(NP(tol)),
    CB_KEY_TOL_DX(NP(tol_dx)),
    CB_KEY_DEFINITENESS(NP(definiteness)),
    {.name = "init",
     .kind = CB_PARAM_CHOICE,
     .offset = NP(init_predict),
     .def = "predict",
     .unit = "-",
     .choices = init_names,
     .values = init_values,
     .doc = "Newton's initial guess: `predict` (x0 + dt v0) or `x0`."},
    {.name = "line_search",
     .kind = CB_PARAM_BOOL,
     .offset = NP(line_search),
     .def = "0",
     .unit = "-",
     .doc = "Backtracking (Armijo) line search on F in every Newton iteration (0 or 1)."},
    CB_KEY_END,
};
#undef NP

static void nt_free(cb_integrator *it) {
  newton_work *w = it->state;
  cb_objective_free(&w->obj);
  free(w->xtrial);
  free(w->gF);
  free(w->b);
  free(w->dx);
  cb_shift_free(w->shift);
}

/* Choi-Ko changes the springs' energy, which is fixed when the scene is
 * built: the policy Newton is given must be the one the springs have. */
static int check_definiteness(const cb_integrator *it, cb_definiteness def) {
  int choi_ko = 0, springs = 0;
  for (int k = 0; k < it->sys->nterms; k++) {
    springs += it->sys->terms[k]->type == cb_term_spring;
    choi_ko |= cb_spring_term_is_choi_ko(it->sys->terms[k]);
  }
  if (springs && choi_ko != (def == CB_DEF_CHOI_KO))
    return cb_fail("integrator: definiteness '%s' does not match the scene, whose springs were built %s the Choi-Ko "
                   "response (set integrator.definiteness before building the scene)",
                   cb_definiteness_names[def], choi_ko ? "with" : "without");
  return CB_OK;
}

static int nt_init(cb_integrator *it) {
  const cb_newton_params *p = it->type_params;
  int st = check_definiteness(it, p->definiteness);
  if (st) return st;
  newton_work *w = it->state;
  size_t n3 = (size_t)3 * it->scene->mesh.nv, nf = (size_t)it->sys->A.n;
  st = cb_objective_init(&w->obj, it->scene);
  if (st) return st;
  w->xtrial = cb_malloc(n3, sizeof(double));
  w->gF = cb_malloc(nf, sizeof(double));
  w->b = cb_malloc(nf, sizeof(double));
  w->dx = cb_malloc(nf, sizeof(double));
  if (!w->xtrial || !w->gF || !w->b || !w->dx) return CB_ENOMEM;
  w->constant_A = (it->solver->type->flags & CB_SOLVER_DIRECT) && p->definiteness != CB_DEF_SHIFT;
  for (int k = 0; k < it->sys->nterms; k++) {
    const cb_term_type *t = it->sys->terms[k]->type;
    if (t->hessian && !(t->flags & CB_TERM_CONSTANT_HESSIAN)) w->constant_A = 0;
    if (t->max_step) w->filtered = 1;
  }
  return cb_shift_alloc((int)nf, NULL, &w->shift);
}

static void move(const cb_scene *s, double *x, const double *base, const double *dx, double alpha) {
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) x[3 * i + a] = base[3 * i + a] + alpha * dx[3 * k + a];
  }
}

static int nt_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  newton_work *w = it->state;
  const cb_scene *s = it->scene;
  const cb_newton_params *p = it->type_params;
  cb_newton_hook hook = it->params.hook;
  void *hook_ctx = it->params.hook_ctx;
  cb_sparse *A = &it->sys->A;
  int nv3 = 3 * s->mesh.nv, nf = A->n;
  double dt = it->params.dt;
  cb_objective_begin(&w->obj, x, v, dt); /* x0 = x, xhat = x0 + dt v0 */
  cb_objective_guess(&w->obj, x, p->init_predict);
  if (w->filtered && p->init_predict) { /* the predictor filtered as a step: x(0) = x0 + a (xhat - x0) */
    double a = cb_system_max_step(it->sys, w->obj.x0, x);
    if (!(a > 0)) a = 0;
    for (int k = 0; a < 1 && k < s->model.nfree; k++) {
      int i = s->free_vertex[k];
      for (int c = 0; c < 3; c++) x[3 * i + c] = w->obj.x0[3 * i + c] + a * (x[3 * i + c] - w->obj.x0[3 * i + c]);
    }
  }

  cb_newton_event ev;
  memset(&ev, 0, sizeof ev);
  ev.alpha = 1.0;
  double g0 = 0.0, ghat = 0.0;
  int status = CB_OK, dx_converged = 0;
  for (int k = 0;; k++) {
    double t0 = cb_now_ms();
    double Fscale = 0.0;
    double F = cb_objective_eval(&w->obj, x, w->gF, &Fscale);
    double gn = cblas_dnrm2(nf, w->gF, 1);
    st->assemble_ms += cb_now_ms() - t0;
    if (k == 0) {
      g0 = gn;
      ghat = gn;
      if (!p->init_predict) { /* the common yardstick: |grad F(xhat)| */
        cb_objective_guess(&w->obj, w->xtrial, 1);
        cb_objective_eval(&w->obj, w->xtrial, w->b, NULL);
        ghat = cblas_dnrm2(nf, w->b, 1);
      }
    }
    st->F = F;
    st->grad_norm = gn;
    st->rel_grad = g0 > 0 ? gn / g0 : 0.0;
    st->rel_grad_hat = ghat > 0 ? gn / ghat : 0.0;
    st->newton_iters = k;
    if (!isfinite(F) || !isfinite(gn)) {
      status = CB_DIVERGED;
      break;
    }
    ev.iter = k;
    ev.F = F;
    ev.grad_norm = gn;
    ev.rel_grad = st->rel_grad;
    ev.x = x;
    ev.A = NULL;
    ev.b = NULL;
    ev.dx = NULL;
    ev.solver = NULL;
    if (hook) hook(hook_ctx, CB_NEWTON_GRADIENT, &ev);
    if (st->rel_grad <= p->tol || gn == 0.0 || dx_converged) break;
    if (k == p->max_iters) {
      status = CB_NOT_CONVERGED;
      break;
    }

    t0 = cb_now_ms();
    cb_system_assemble(it->sys, x, 1.0 / (dt * dt), p->definiteness, 0.0); /* A = M/dt^2 + H(x) */
    for (int i = 0; i < nf; i++) w->b[i] = -w->gF[i];                      /* b = -grad F */
    st->assemble_ms += cb_now_ms() - t0;
    ev.A = A;
    ev.b = w->b;
    if (hook) hook(hook_ctx, CB_NEWTON_SYSTEM, &ev);

    cb_shift_stats ds; /* factor + solve; `shift` retries with A + mu I */
    cb_shift *sh = p->definiteness == CB_DEF_SHIFT ? w->shift : NULL;
    int ls;
    if (w->constant_A && w->factored_dt == dt) { /* constant A, already factorised: solve only */
      memset(&ds, 0, sizeof ds);
      ls = cb_solver_solve(it->solver, A, w->b, w->dx);
      ds.solve_ms = it->solver->stats.solve_ms;
      ds.linear_iters = it->solver->stats.iters;
    } else {
      ls = cb_shift_solve(sh, it->solver, A, it->sys->diag, w->b, w->dx, &ds);
      w->factored_dt = w->constant_A && ls == CB_OK ? dt : 0.0;
    }
    st->factor_ms += ds.factor_ms; /* includes any set-up such as a rho estimate */
    st->solve_ms += ds.solve_ms;
    st->linear_iters += ds.linear_iters;
    st->factorizations += ds.factorizations;
    if (ds.mu > st->shift_mu) st->shift_mu = ds.mu;
    st->linear_status = ls;
    ev.dx = w->dx;
    ev.solver = it->solver;
    ev.status = ls;
    ev.shift_mu = ds.mu;
    if (hook) hook(hook_ctx, CB_NEWTON_SOLVED, &ev);
    if (ls == CB_NOT_SPD) {
      status = CB_NOT_SPD;
      break;
    }
    /* an iterative solve cut at its max_iters is inexact Newton, not a failure */
    if (ls != CB_OK && ls != CB_NOT_CONVERGED) {
      status = ls == CB_ENOMEM ? CB_ENOMEM : CB_LINEAR_FAILED;
      break;
    }

    /* the line-search filter (system.h): the fraction of dx no term forbids (IPC's CCD bound); 1 without one */
    double alpha = 1.0;
    if (w->filtered) {
      memcpy(w->xtrial, x, (size_t)nv3 * sizeof(double)); /* the pins stay where x has them (move sets the free) */
      move(s, w->xtrial, x, w->dx, 1.0);
      alpha = cb_system_max_step(it->sys, x, w->xtrial);
      if (!(alpha > 0)) {
        status = CB_LS_FAILED;
        break;
      }
    }
    double alpha_max = alpha;
    if (p->line_search) {
      double slope = cblas_ddot(nf, w->gF, 1, w->dx, 1); /* grad F . dx */
      if (!(slope < 0)) {
        status = CB_LS_FAILED;
        break;
      }
      int ok = -slope <= LS_FLAT * Fscale; /* decrease below F's round-off: full step */
      memcpy(w->xtrial, x, (size_t)nv3 * sizeof(double));
      if (ok) move(s, w->xtrial, x, w->dx, alpha_max);
      for (int h = 0; !ok && h <= LS_MAX_HALVINGS; h++, alpha *= 0.5) {
        move(s, w->xtrial, x, w->dx, alpha);
        double Ft = cb_objective_eval(&w->obj, w->xtrial, NULL, NULL);
        if (Ft <= F + 1e-4 * alpha * slope) {
          ok = 1;
          break;
        } /* Armijo */
        st->ls_backtracks++;
      }
      if (!ok) {
        status = CB_LS_FAILED;
        break;
      }
      memcpy(x, w->xtrial, (size_t)nv3 * sizeof(double));
    } else {
      move(s, x, x, w->dx, alpha_max);
    }
    double dmax = fabs(w->dx[cblas_idamax(nf, w->dx, 1)]) * alpha;
    ev.step_max = dmax;
    ev.alpha = alpha;
    if (!isfinite(dmax)) {
      status = CB_DIVERGED;
      st->newton_iters = k + 1;
      break;
    }
    if (p->tol_dx > 0 && dmax <= p->tol_dx) dx_converged = 1;
  }
  cb_objective_velocity(&w->obj, x, v); /* v1 = (x1 - x0)/dt; pinned vertices keep their v0 */
  return status;
}

const cb_integrator_type cb_integrator_newton = {
    .name = "newton",
    .flags = CB_INTEGRATOR_LINEAR_SOLVER | CB_INTEGRATOR_HESSIAN | CB_INTEGRATOR_STEP_FILTER,
    .size = sizeof(newton_work),
    .params_size = sizeof(cb_newton_params),
    .params_default = &newton_defaults,
    .keys = newton_keys,
    .init = nt_init,
    .step = nt_step,
    .free = nt_free,
};
