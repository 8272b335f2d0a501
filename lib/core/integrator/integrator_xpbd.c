/* Position-based dynamics (Müller, Heidelberger, Hennix and Ratcliff 2007,
 * "Position based dynamics") and extended PBD (Macklin, Müller and
 * Chentanez 2016, "XPBD: position-based simulation of compliant constrained
 * dynamics"), with substepping (Macklin, Storey, Lu, Terdiman, Chentanez,
 * Jeschke and Müller 2019, "Small steps in physics simulation").
 *
 * Constraints: one distance constraint per spring of the scene (the stretch
 * springs on every edge, and the bending springs when material.bend =
 * spring), C_c(x) = |x_i - x_j| - L_c, with n = (x_i - x_j)/|x_i - x_j|,
 * grad_{x_i} C = n and grad_{x_j} C = -n, and the spring's stiffness k_c.
 * Inverse masses w_i = 1/m_i, 0 for a pinned vertex.
 *
 * One step of length dt is integrator.substeps = S substeps of h = dt/S:
 *   xprev = x;  x <- x + h v + h^2 g                  (free vertices; pins: x <- x + h v_pin)
 *   lambda_c = 0 (xpbd)
 *   integrator.iters = K times, every constraint c in order (Gauss-Seidel):
 *     xpbd  alpha~ = 1/(k_c h^2)                          (compliance alpha = 1/k over h^2)
 *           dlambda = (-C - alpha~ lambda_c) / (w_i + w_j + alpha~);  lambda_c += dlambda
 *     pbd   dlambda = -s' C / (w_i + w_j),  s' = 1 - (1 - s)^(1/K)
 *           (s = integrator.pbd_stiffness in (0, 1]; Müller et al.'s correction, so that K
 *           iterations scale a lone constraint's violation by 1 - s whatever K)
 *     x_i += w_i n dlambda;  x_j -= w_j n dlambda
 *   v = (x - xprev)/h                                   (free vertices; pins keep v)
 * The order is fixed: the stretch springs in the topology's edge order (edges
 * sorted by (i, j)), then the bending springs in hinge order. A constraint
 * whose ends have collapsed onto each other (no direction n) or that joins
 * two pinned vertices is skipped in that sweep.
 *
 * What they converge to. PBD is not a minimiser of the implicit-Euler
 * objective F (its stiffness depends on K and dt; claim X1). XPBD with S = 1
 * reaches, as K grows, the fixed point of its lambda update, where
 * C(x) + alpha~ lambda = 0 at the final positions. Its positions, though,
 * accumulate w grad C(x_k) dlambda at every iterate x_k, not grad C at the
 * final x: the residual g(x) = M(x - xhat) - grad C(x)^T lambda that Macklin
 * et al. drop is not driven to zero, so the fixed point need not be implicit
 * Euler's minimiser (grad F = 0). The step stats report |grad F| at the end
 * of the step for F of the whole step dt (two gradient evaluations per step:
 * at xhat and at the end), which measures that gap. With S > 1 the step is S
 * implicit sub-steps of a different objective; rel_grad still measures the
 * end state against the full step's F (the error against a dt reference).
 *
 * Scope: spring energies (stretch and bending springs, linear response) and
 * gravity. Other terms (FEM, dihedral or quadratic bending, the penalty
 * collider) have no distance-constraint form here and are refused at init;
 * the `project` collider is a post-step response and works (it runs after
 * the whole step, not after each substep). No allocation in a step.
 * Step stats: newton_iters = K S (constraint sweeps), rel_grad = rel_grad_hat
 * = |grad F(x1)| / |grad F(xhat)|, assemble_ms the two gradient evaluations,
 * solve_ms the sweeps, constraint_residual the last sweep's largest
 * |C_c + alpha~ lambda_c| / L_c (pbd: |C_c| / L_c), how far the step is from
 * its fixed point (claim X1 chooses its iteration count by it). With a hook and S = 1, CB_NEWTON_GRADIENT is sent at
 * every iterate (iter 0 = xhat, ..., K), which costs a gradient each. */
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "integrator_keys.h"
#include "vec.h"

static const cb_xpbd_params xpbd_defaults = {.cookie = CB_PARAMS_COOKIE, .iters = 32, .substeps = 1, .stiffness = 1.0};

cb_xpbd_params cb_xpbd_params_default(void) { return xpbd_defaults; }

#define XP(f) offsetof(cb_xpbd_params, f)
#define KEY_SUBSTEPS \
  { \
    .name = "substeps", .kind = CB_PARAM_INT, .offset = XP(substeps), .def = "1", .unit = "substeps", .lo = 1, \
    .hi = 1000000, \
    .doc = "pbd, xpbd: substeps per step (Macklin et al. 2019's small steps): dt is split into this many substeps of " \
           "dt/substeps, each with integrator.iters constraint sweeps." \
  }
static const cb_param_key xpbd_keys[] = {
    CB_KEY_ITERS(XP(iters)),
    KEY_SUBSTEPS,
    CB_KEY_END,
};
static const cb_param_key pbd_keys[] = {
    CB_KEY_ITERS(XP(iters)),
    KEY_SUBSTEPS,
    {.name = "pbd_stiffness",
     .kind = CB_PARAM_DOUBLE,
     .offset = XP(stiffness),
     .def = "1",
     .unit = "-",
     .hi = 1,
     .lo_open = 1,
     .doc = "pbd: the constraint stiffness factor s in (0, 1] of Müller et al. 2007; each projection moves by s' = 1 - "
            "(1 - s)^(1/iters) of the violation (their correction for the iteration count). It does not depend on "
            "material.stretch_k."},
    CB_KEY_END,
};
#undef XP

typedef struct {
  cb_objective obj;
  int nc;         /* constraints */
  int *ends;      /* 2*nc */
  double *rest;   /* nc: L_c, m */
  double *kc;     /* nc: the spring's k, N/m */
  double *lambda; /* nc */
  double *w;      /* nv: inverse masses, 0 when pinned */
  double *xprev;  /* 3*nv */
  double *gF;     /* 3*nfree */
  double grav[3]; /* m/s^2, zero without a gravity term */
  int pbd;        /* 1 = pbd, 0 = xpbd */
} xpbd_work;

static void xp_free(cb_integrator *it) {
  xpbd_work *w = it->state;
  cb_objective_free(&w->obj);
  free(w->ends);
  free(w->rest);
  free(w->kc);
  free(w->lambda);
  free(w->w);
  free(w->xprev);
  free(w->gF);
}

static int xp_init(cb_integrator *it) {
  const cb_xpbd_params *p = it->type_params;
  xpbd_work *w = it->state;
  const cb_scene *s = it->scene;
  const char *name = it->type->name;
  w->pbd = strcmp(name, "pbd") == 0;
  if (p->iters < 1) return cb_fail("%s: iters must be >= 1, got %d", name, p->iters);
  if (p->substeps < 1) return cb_fail("%s: substeps must be >= 1, got %d", name, p->substeps);
  if ((long long)p->iters * p->substeps > INT_MAX) /* the step's sweep count is an int */
    return cb_fail("%s: iters x substeps = %d x %d = %lld sweeps per step, more than %d", name, p->iters, p->substeps,
                   (long long)p->iters * p->substeps, INT_MAX);
  if (w->pbd && !(p->stiffness > 0 && p->stiffness <= 1))
    return cb_fail("%s: pbd_stiffness must be in (0, 1], got %g", name, p->stiffness);
  /* the constraints: every spring of every spring term, in term order */
  int nc = 0;
  for (int t = 0; t < s->sys.nterms; t++) {
    const cb_term *term = s->sys.terms[t];
    int ns;
    const int *ends;
    const double *rest;
    double k;
    if (term->type == cb_term_gravity) {
      memcpy(w->grav, s->gravity, sizeof w->grav);
      continue;
    }
    if (term->type != cb_term_spring)
      return cb_fail("%s: the scene's energy term '%s' (%s) has no distance-constraint form; %s projects the distance "
                     "constraints of spring terms only (material.stretch = spring, material.bend = none or spring, "
                     "collider.type = none or project)",
                     name, term->label, term->type->name, name);
    if (cb_spring_term_is_choi_ko(term))
      return cb_fail("%s: the '%s' springs have the Choi-Ko compressed response, a different energy than the distance "
                     "constraint |x_i - x_j| = L that %s enforces (integrator.definiteness = choi-ko)",
                     name, term->label, name);
    cb_spring_term_springs(term, &ns, &ends, &rest, &k);
    nc += ns;
  }
  int nv = s->mesh.nv, nf = s->model.nfree;
  int st = cb_objective_init(&w->obj, s);
  if (st) return st;
  w->ends = cb_malloc(2 * (size_t)nc + 1, sizeof(int));
  w->rest = cb_malloc((size_t)nc + 1, sizeof(double));
  w->kc = cb_malloc((size_t)nc + 1, sizeof(double));
  w->lambda = cb_malloc((size_t)nc + 1, sizeof(double));
  w->w = cb_malloc((size_t)nv + 1, sizeof(double));
  w->xprev = cb_malloc(3 * (size_t)nv + 1, sizeof(double));
  w->gF = cb_malloc(3 * (size_t)nf + 1, sizeof(double));
  if (!w->ends || !w->rest || !w->kc || !w->lambda || !w->w || !w->xprev || !w->gF) return CB_ENOMEM;
  w->nc = 0;
  for (int t = 0; t < s->sys.nterms; t++) {
    int ns;
    const int *ends;
    const double *rest;
    double k;
    if (s->sys.terms[t]->type != cb_term_spring) continue;
    cb_spring_term_springs(s->sys.terms[t], &ns, &ends, &rest, &k);
    for (int c = 0; c < ns; c++, w->nc++) {
      w->ends[2 * w->nc] = ends[2 * c];
      w->ends[2 * w->nc + 1] = ends[2 * c + 1];
      w->rest[w->nc] = rest[c];
      w->kc[w->nc] = k;
    }
  }
  for (int i = 0; i < nv; i++) w->w[i] = s->free_index[i] >= 0 && s->mass[i] > 0 ? 1.0 / s->mass[i] : 0.0;
  return CB_OK;
}

/* One Gauss-Seidel sweep over the constraints for a substep of length h;
 * sprime is pbd's per-projection factor s' (unused by xpbd, which updates lambda). With res (may be
 * NULL), *res gets the sweep's largest residual over the rest length, max_c |C_c + alpha~ lambda_c| / L_c
 * (pbd: |C_c| / L_c), each taken just before constraint c's update (the Gauss-Seidel residual: the
 * fixed point has it 0; it costs a compare per constraint). */
static void sweep(xpbd_work *w, double *x, double h, double sprime, double *res) {
  double rmax = 0.0;
  for (int c = 0; c < w->nc; c++) {
    int i = w->ends[2 * c], j = w->ends[2 * c + 1];
    double wi = w->w[i], wj = w->w[j];
    if (wi + wj == 0.0) continue;
    double *xi = x + 3 * i, *xj = x + 3 * j;
    double d[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(l > 0)) continue; /* no direction */
    double C = l - w->rest[c], dl;
    if (w->pbd) {
      dl = -sprime * C / (wi + wj); /* dlambda = -s' C/(w_i + w_j) */
      if (res) rmax = fmax(rmax, fabs(C) / w->rest[c]);
    } else {
      double at = 1.0 / (w->kc[c] * h * h); /* alpha~ = alpha/h^2, alpha = 1/k */
      if (!isfinite(at)) continue;          /* infinite compliance (k = 0, or k h^2 below 1/DBL_MAX): no constraint */
      double r = -C - at * w->lambda[c];    /* the constraint's residual -(C + alpha~ lambda) */
      dl = r / (wi + wj + at);              /* dlambda = (-C - alpha~ lambda)/(w_i + w_j + alpha~) */
      w->lambda[c] += dl;
      if (res) rmax = fmax(rmax, fabs(r) / w->rest[c]);
    }
    double inv = dl / l; /* n dlambda = d dlambda / l */
    for (int a = 0; a < 3; a++) {
      xi[a] += wi * inv * d[a]; /* x_i += w_i n dlambda */
      xj[a] -= wj * inv * d[a]; /* x_j -= w_j n dlambda */
    }
  }
  if (res) *res = rmax;
}

static int xp_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  xpbd_work *w = it->state;
  const cb_xpbd_params *p = it->type_params;
  const cb_scene *s = it->scene;
  cb_newton_hook hook = p->substeps == 1 ? it->params.hook : NULL;
  int nf = s->model.nfree, nv = s->mesh.nv;
  double dt = it->params.dt, h = dt / p->substeps;
  double sprime = w->pbd ? 1.0 - pow(1.0 - p->stiffness, 1.0 / p->iters) : 0.0; /* s' = 1 - (1 - s)^(1/K) */
  /* F of the whole step, for the stats: begin at (x0, v0), measure at xhat */
  cb_objective_begin(&w->obj, x, v, dt);
  cb_objective_guess(&w->obj, w->xprev, 1);
  double g0 = 0.0; /* |grad F(xhat)|, the yardstick of rel_grad */
  int status = cb_integrator_measure(it, &w->obj, w->xprev, w->gF, 0, &g0, -1.0, hook, st);
  double t0 = cb_now_ms();
  for (int sub = 0; status == CB_OK && sub < p->substeps; sub++) {
    memcpy(w->xprev, x, (size_t)3 * nv * sizeof(double));
    for (int i = 0; i < nv; i++) { /* predict: x <- x + h v (+ h^2 g for free vertices) */
      int free_i = s->free_index[i] >= 0;
      for (int a = 0; a < 3; a++) x[3 * i + a] += h * v[3 * i + a] + (free_i ? h * h * w->grav[a] : 0.0);
    }
    for (int c = 0; c < w->nc; c++) w->lambda[c] = 0.0;
    for (int k = 1; k <= p->iters && status == CB_OK; k++) {
      sweep(w, x, h, sprime, sub == p->substeps - 1 && k == p->iters ? &st->constraint_residual : NULL);
      if (!hook) continue;
      st->solve_ms += cb_now_ms() - t0; /* S = 1 with a hook: F after every sweep */
      status = cb_integrator_measure(it, &w->obj, x, w->gF, k, &g0, -1.0, hook, st);
      t0 = cb_now_ms();
    }
    double inv_h = 1.0 / h;
    for (int b = 0; b < nf; b++) { /* v = (x - xprev)/h */
      int i = s->free_vertex[b];
      for (int a = 0; a < 3; a++) v[3 * i + a] = (x[3 * i + a] - w->xprev[3 * i + a]) * inv_h;
    }
  }
  st->solve_ms += cb_now_ms() - t0;
  if (status == CB_OK && !hook) /* the end of the step */
    status = cb_integrator_measure(it, &w->obj, x, w->gF, p->iters * p->substeps, &g0, -1.0, NULL, st);
  st->newton_iters = p->iters * p->substeps;
  if (status == CB_OK && !(cb_vec_all_finite(3 * nv, x) && cb_vec_all_finite(3 * nv, v))) status = CB_DIVERGED;
  return status;
}

const cb_integrator_type cb_integrator_xpbd = {
    .name = "xpbd",
    .flags = 0,
    .size = sizeof(xpbd_work),
    .params_size = sizeof(cb_xpbd_params),
    .params_default = &xpbd_defaults,
    .keys = xpbd_keys,
    .init = xp_init,
    .step = xp_step,
    .free = xp_free,
};

const cb_integrator_type cb_integrator_pbd = {
    .name = "pbd",
    .flags = 0,
    .size = sizeof(xpbd_work),
    .params_size = sizeof(cb_xpbd_params),
    .params_default = &xpbd_defaults,
    .keys = pbd_keys,
    .init = xp_init,
    .step = xp_step,
    .free = xp_free,
};
