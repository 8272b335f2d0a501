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
 * the largest mu of the step is reported in the step stats. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/solver_shift.h>
#include <clothbench/integrator.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>

enum { LS_MAX_HALVINGS = 40 };
#define LS_FLAT 1e-12 /* |grad F . dx| / S below which F cannot resolve the decrease */

typedef struct {
  double *x0, *xhat, *xtrial, *g; /* 3*nv */
  double *gF, *b, *dx;            /* 3*nfree */
  cb_shift *shift;                /* workspace of the shift policy */
} newton_work;

static void nw_free(newton_work *w) {
  if (!w) return;
  free(w->x0); free(w->xhat); free(w->xtrial); free(w->g);
  free(w->gF); free(w->b); free(w->dx);
  cb_shift_free(w->shift);
  free(w);
}

static int nt_alloc(cb_integrator *it) {
  if (!it->solver) return cb_fail("newton: needs a linear solver");
  size_t n3 = (size_t)3 * it->scene->mesh.nv, nf = (size_t)it->sys->A.n;
  newton_work *w = cb_calloc(1, sizeof *w);
  if (!w) return CB_ENOMEM;
  w->x0 = cb_malloc(n3, sizeof(double));
  w->xhat = cb_malloc(n3, sizeof(double));
  w->xtrial = cb_malloc(n3, sizeof(double));
  w->g = cb_malloc(n3, sizeof(double));
  w->gF = cb_malloc(nf, sizeof(double));
  w->b = cb_malloc(nf, sizeof(double));
  w->dx = cb_malloc(nf, sizeof(double));
  if (!w->x0 || !w->xhat || !w->xtrial || !w->g || !w->gF || !w->b || !w->dx) {
    nw_free(w);
    return CB_ENOMEM;
  }
  int st = cb_shift_alloc((int)nf, NULL, &w->shift);
  if (st) {
    nw_free(w);
    return st;
  }
  it->work = w;
  return CB_OK;
}

/* F(x); if gF != NULL also grad F over the free DOFs (uses w->g); if
 * scale != NULL also S = |x - xhat|_M^2/(2 dt^2) + sum_t |E_t|, the size of
 * the summands of F (its round-off is ~ eps S). */
static double objective(cb_integrator *it, const double *x, double *gF, double *scale) {
  newton_work *w = it->work;
  const cb_scene *s = it->scene;
  double inv_dt2 = 1.0 / (it->params.dt * it->params.dt);
  double per[CB_MAX_TERMS];
  double E = cb_system_energy(it->sys, x, gF ? w->g : NULL, per);
  double inertia = 0.0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) {
      double d = x[3 * i + a] - w->xhat[3 * i + a];
      inertia += s->mass[i] * d * d;                              /* |x - xhat|_M^2 */
      if (gF) gF[3 * k + a] = s->mass[i] * d * inv_dt2 + w->g[3 * i + a]; /* M(x - xhat)/dt^2 + dE/dx */
    }
  }
  if (scale) {
    *scale = 0.5 * inv_dt2 * inertia;
    for (int t = 0; t < it->sys->nterms; t++) *scale += fabs(per[t]);
  }
  return 0.5 * inv_dt2 * inertia + E;
}

static void move(const cb_scene *s, double *x, const double *base, const double *dx, double alpha) {
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) x[3 * i + a] = base[3 * i + a] + alpha * dx[3 * k + a];
  }
}

static int nt_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  newton_work *w = it->work;
  const cb_scene *s = it->scene;
  const cb_integrator_params *p = &it->params;
  cb_sparse *A = &it->sys->A;
  int nv3 = 3 * s->mesh.nv, nf = A->n;
  double dt = p->dt;
  memcpy(w->x0, x, (size_t)nv3 * sizeof(double));
  for (int i = 0; i < nv3; i++) w->xhat[i] = x[i] + dt * v[i]; /* xhat = x0 + dt v0 */
  if (p->init_predict) memcpy(x, w->xhat, (size_t)nv3 * sizeof(double));
  for (int k = 0; k < s->npinned; k++) /* pins at their prescribed positions x0 + dt v0 */
    memcpy(x + 3 * s->pinned[k], w->xhat + 3 * s->pinned[k], 3 * sizeof(double));

  cb_newton_event ev;
  memset(&ev, 0, sizeof ev);
  ev.alpha = 1.0;
  double g0 = 0.0;
  int status = CB_OK, dx_converged = 0;
  for (int k = 0;; k++) {
    double t0 = cb_now_ms();
    double Fscale = 0.0;
    double F = objective(it, x, w->gF, &Fscale);
    double gn = cblas_dnrm2(nf, w->gF, 1);
    st->assemble_ms += cb_now_ms() - t0;
    if (k == 0) g0 = gn;
    st->F = F;
    st->grad_norm = gn;
    st->rel_grad = g0 > 0 ? gn / g0 : 0.0;
    st->newton_iters = k;
    if (!isfinite(F) || !isfinite(gn)) { status = CB_DIVERGED; break; }
    ev.iter = k; ev.F = F; ev.grad_norm = gn; ev.rel_grad = st->rel_grad; ev.x = x;
    ev.A = NULL; ev.b = NULL; ev.dx = NULL; ev.solver = NULL;
    if (p->hook) p->hook(p->hook_ctx, CB_NEWTON_GRADIENT, &ev);
    if (st->rel_grad <= p->tol || gn == 0.0 || dx_converged) break;
    if (k == p->max_iters) { status = CB_NOT_CONVERGED; break; }

    t0 = cb_now_ms();
    cb_system_assemble(it->sys, x, 1.0 / (dt * dt), p->definiteness, 0.0); /* A = M/dt^2 + H(x) */
    for (int i = 0; i < nf; i++) w->b[i] = -w->gF[i];                      /* b = -grad F */
    st->assemble_ms += cb_now_ms() - t0;
    ev.A = A; ev.b = w->b;
    if (p->hook) p->hook(p->hook_ctx, CB_NEWTON_SYSTEM, &ev);

    cb_shift_stats ds; /* factor + solve; `shift` retries with A + mu I */
    cb_shift *sh = p->definiteness == CB_DEF_SHIFT ? w->shift : NULL;
    int ls = cb_shift_solve(sh, it->solver, A, it->sys->diag, w->b, w->dx, &ds);
    st->factor_ms += ds.factor_ms; /* includes any set-up such as a rho estimate */
    st->solve_ms += ds.solve_ms;
    st->linear_iters += ds.linear_iters;
    st->factorizations += ds.factorizations;
    if (ds.mu > st->shift_mu) st->shift_mu = ds.mu;
    st->linear_status = ls;
    ev.dx = w->dx; ev.solver = it->solver; ev.status = ls; ev.shift_mu = ds.mu;
    if (p->hook) p->hook(p->hook_ctx, CB_NEWTON_SOLVED, &ev);
    if (ls == CB_NOT_SPD) { status = CB_NOT_SPD; break; }
    /* an iterative solve cut at its max_iters is inexact Newton, not a failure */
    if (ls != CB_OK && ls != CB_NOT_CONVERGED) { status = CB_LINEAR_FAILED; break; }

    double alpha = 1.0;
    if (p->line_search) {
      double slope = cblas_ddot(nf, w->gF, 1, w->dx, 1); /* grad F . dx */
      if (!(slope < 0)) { status = CB_LS_FAILED; break; }
      int ok = -slope <= LS_FLAT * Fscale; /* decrease below F's round-off: full step */
      memcpy(w->xtrial, x, (size_t)nv3 * sizeof(double));
      if (ok) move(s, w->xtrial, x, w->dx, 1.0);
      for (int h = 0; !ok && h <= LS_MAX_HALVINGS; h++, alpha *= 0.5) {
        move(s, w->xtrial, x, w->dx, alpha);
        double Ft = objective(it, w->xtrial, NULL, NULL);
        if (Ft <= F + 1e-4 * alpha * slope) { ok = 1; break; } /* Armijo */
        st->ls_backtracks++;
      }
      if (!ok) { status = CB_LS_FAILED; break; }
      memcpy(x, w->xtrial, (size_t)nv3 * sizeof(double));
    } else {
      move(s, x, x, w->dx, 1.0);
    }
    double dmax = fabs(w->dx[cblas_idamax(nf, w->dx, 1)]) * alpha;
    ev.step_max = dmax;
    ev.alpha = alpha;
    if (!isfinite(dmax)) { status = CB_DIVERGED; st->newton_iters = k + 1; break; }
    if (p->tol_dx > 0 && dmax <= p->tol_dx) dx_converged = 1;
  }
  for (int k = 0; k < s->model.nfree; k++) { /* v1 = (x1 - x0)/dt; pinned vertices keep their v0 */
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) v[3 * i + a] = (x[3 * i + a] - w->x0[3 * i + a]) / dt;
  }
  return status;
}

static void nt_free(cb_integrator *it) { nw_free(it->work); }

const cb_integrator_type cb_integrator_newton = {"newton", nt_alloc, nt_step, nt_free};
