/* Explicit stability: prediction 2/omega_max, the cell classifier, and the
 * bisection of the largest stable time step. The math is in stability.h. */
#include "stability.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bind.h"
#include <clothbench/eigen.h>
#include <clothbench/run.h>
#include <clothbench/solver.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "rng.h"
#include "vec.h"

#define STANDARD_GRAVITY 9.8 /* m/s^2, used for the energy scale when gravity is off */

const char *cb_cell_class_name(int cls) {
  switch (cls) {
  case CB_CELL_STABLE: return "stable";
  case CB_CELL_UNSTABLE: return "unstable";
  case CB_CELL_DIVERGED: return "diverged";
  case CB_CELL_FAILED: return "failed";
  default: return "?";
  }
}

cb_stability_params cb_stability_params_default(void) {
  cb_stability_params p = {.sim_time = 2.0,
                           .min_steps = 200,
                           .max_steps = 0,
                           .unstable_ratio = 1.0,
                           .diverge_ratio = 10.0,
                           .energy_every = 1,
                           .mark_time = 0};
  return p;
}

long cb_stability_steps(const cb_stability_params *p, double dt) {
  double n = ceil(p->sim_time / dt - 1e-9);
  if (!(n >= 1)) n = 1;
  if (n > 4e18) n = 4e18;
  long steps = (long)n;
  if (steps < p->min_steps) steps = p->min_steps;
  if (p->max_steps > 0 && steps > p->max_steps) steps = p->max_steps;
  return steps;
}

/* ---- classifier ----------------------------------------------------------- */

void cb_classifier_init(cb_classifier *c) {
  memset(c, 0, sizeof *c);
  c->cls = CB_CELL_STABLE;
}

int cb_classifier_push(cb_classifier *c, const cb_stability_params *p, double r) {
  c->samples++;
  c->last_ratio = r;
  if (c->cls == CB_CELL_DIVERGED || c->cls == CB_CELL_FAILED) return 1;
  if (!isfinite(r) || r > p->diverge_ratio) { /* NaN/Inf, or past R_d: decided */
    if (isfinite(r) || r > 0) c->max_ratio = fmax(c->max_ratio, r);
    c->cls = CB_CELL_DIVERGED;
    return 1;
  }
  if (r > c->max_ratio) c->max_ratio = r;
  if (r > p->unstable_ratio) c->cls = CB_CELL_UNSTABLE; /* may still diverge later */
  return 0;
}

int cb_stability_classify(const double *r, long n, const cb_stability_params *p, double *max_ratio) {
  cb_classifier c;
  cb_classifier_init(&c);
  for (long i = 0; i < n; i++)
    if (cb_classifier_push(&c, p, r[i])) break;
  if (max_ratio) *max_ratio = c.max_ratio;
  return c.cls;
}

/* ---- start state and energy scale -------------------------------------------- */

double cb_stability_energy_scale(const cb_scene *s, const double *x, const double *v) {
  double g = cb_v3_norm(s->gravity);
  if (!(g > 0)) g = STANDARD_GRAVITY;
  /* S = elastic(x) + kinetic(v) + (sum m_i) g D + 1e-12 J */
  return cb_system_elastic_energy(&s->sys, x) + cb_scene_kinetic(s, v) +
         cb_scene_total_mass(s) * g * cb_mesh_bbox_diagonal(&s->mesh) + 1e-12;
}

void cb_stability_perturb(const cb_scene *s, double ke, unsigned seed, double *v) {
  int nv = s->mesh.nv;
  memset(v, 0, (size_t)3 * nv * sizeof(double));
  cb_rng rng = cb_rng_seed((uint64_t)seed + 1);
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) v[3 * i + a] = 2.0 * cb_rng_uniform(&rng) - 1.0; /* uniform in [-1, 1) */
  }
  double k0 = cb_scene_kinetic(s, v);
  double scale = k0 > 0 && ke > 0 ? sqrt(ke / k0) : 0.0; /* kinetic scales with the square of v */
  for (int i = 0; i < 3 * nv; i++) v[i] *= scale;
}

void cb_stability_swing(const cb_scene *s, double ke, const double dir[3], double *v) {
  double n = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]), msum = 0;
  for (int k = 0; k < s->model.nfree; k++) msum += s->mass[s->free_vertex[k]];
  if (!(n > 0) || !(msum > 0) || !(ke > 0)) return;
  double c = sqrt(2.0 * ke / msum) / n; /* 1/2 (sum m_i) c^2 = ke */
  for (int k = 0; k < s->model.nfree; k++)
    for (int a = 0; a < 3; a++) v[3 * s->free_vertex[k] + a] += c * dir[a];
}

/* ---- equilibrium -------------------------------------------------------------- */

cb_equilibrium_params cb_equilibrium_params_default(void) {
  cb_equilibrium_params p = {.dt0 = 0.05, .dt_max = 10.0, .max_steps = 200, .tol = 1e-4};
  return p;
}

/* max_i |grad_i E| over free DOFs (g: 3*nv gradient). */
static double free_max_abs(const cb_scene *s, const double *g) {
  double r = 0;
  for (int k = 0; k < s->model.nfree; k++) {
    int i = s->free_vertex[k];
    for (int a = 0; a < 3; a++) r = fmax(r, fabs(g[3 * i + a]));
  }
  return r;
}

static void strain_range(const cb_scene *s, const double *x, double *smin, double *smax) {
  const cb_topology *t = &s->topo;
  const double *X = s->mesh.x;
  *smin = INFINITY;
  *smax = -INFINITY;
  for (int e = 0; e < t->ne; e++) {
    int i = t->edge[2 * e], j = t->edge[2 * e + 1];
    double l2 = 0, L2 = 0;
    for (int a = 0; a < 3; a++) {
      double d = x[3 * i + a] - x[3 * j + a], D = X[3 * i + a] - X[3 * j + a];
      l2 += d * d;
      L2 += D * D;
    }
    double eps = sqrt(l2) / sqrt(L2) - 1.0; /* (l - L)/L */
    *smin = fmin(*smin, eps);
    *smax = fmax(*smax, eps);
  }
  if (t->ne == 0) *smin = *smax = 0;
}

int cb_stability_equilibrium(cb_scene *s, double *x, const cb_equilibrium_params *pp, cb_equilibrium_stats *st) {
  cb_equilibrium_params p = pp ? *pp : cb_equilibrium_params_default();
  memset(st, 0, sizeof *st);
  double t0 = cb_now_ms();
  int nv3 = 3 * s->mesh.nv;
  double *v = cb_calloc((size_t)nv3, sizeof(double)), *g = cb_malloc((size_t)nv3, sizeof(double));
  if (!v || !g) {
    free(v);
    free(g);
    return CB_ENOMEM;
  }
  double gn = cb_v3_norm(s->gravity), fscale = 0;
  if (!(gn > 0)) gn = STANDARD_GRAVITY;
  for (int i = 0; i < s->mesh.nv; i++) fscale = fmax(fscale, s->mass[i] * gn); /* largest weight, N */
  cb_integrator_params ip = cb_integrator_params_default();
  ip.dt = p.dt0;
  cb_newton_params np = cb_newton_params_default();
  np.max_iters = 5;
  np.tol = 1e-6;
  np.init_predict = 0;
  np.line_search = 1;
  np.definiteness = CB_DEF_DROP; /* A SPD: each Newton step is a descent direction */
  cb_solver_params sp = cb_solver_params_default();
  cb_integrator *it = NULL;
  int rc = CB_OK;
  st->status = CB_NOT_CONVERGED;
  double h = p.dt0;
  for (int k = 0;; k++) {
    cb_system_energy(&s->sys, x, g, NULL);
    st->residual = free_max_abs(s, g) / fscale;
    if (!isfinite(st->residual)) {
      st->status = CB_DIVERGED;
      break;
    }
    if (st->residual <= p.tol) {
      st->status = CB_OK;
      break;
    }
    if (k == p.max_steps) break;
    if (!it && (rc = cb_integrator_alloc("newton", s, &ip, &np, "cholmod", &sp, &it))) break;
    it->params.dt = h;
    memset(v, 0, (size_t)nv3 * sizeof(double)); /* from rest: x <- argmin E(y) + |y - x|_M^2/(2h^2) */
    cb_step_stats ss;
    int r = cb_integrator_step(it, x, v, &ss);
    st->steps++;
    st->newton_iters += ss.newton_iters;
    /* not converged / line search stalls near the minimum are tolerated: the
     * residual test above decides; a solver failure or NaN is not */
    if (r == CB_DIVERGED || r == CB_NOT_SPD || r == CB_LINEAR_FAILED) {
      st->status = r;
      break;
    }
    h = fmin(2.0 * h, p.dt_max);
  }
  strain_range(s, x, &st->min_strain, &st->max_strain);
  cb_integrator_free(it);
  free(v);
  free(g);
  st->ms = cb_now_ms() - t0;
  return rc;
}

/* ---- prediction -------------------------------------------------------------- */

static int top_converged(void *ctx, const cb_eig_result *r) {
  (void)ctx;
  return r->res_max <= 1e-6 * fabs(r->lmax);
}

int cb_stability_predict(cb_scene *s, const double *x, cb_eig_method method, cb_prediction *out) {
  memset(out, 0, sizeof *out);
  double t0 = cb_now_ms();
  out->lambda_dense = out->lambda_min_dense = out->lambda_lanczos = out->lanczos_res = NAN;
  cb_sparse *A = &s->sys.A;
  int n = A->n;
  out->ndof = n;
  if (n == 0) return cb_fail("stability prediction: the scene has no free vertex");
  cb_system_assemble(&s->sys, x, 0.0, CB_DEF_NONE, 0.0); /* K = H(x), exact, free DOFs */
  double *d = cb_malloc((size_t)n, sizeof(double)), *work = cb_malloc((size_t)n, sizeof(double));
  double *eval = NULL;
  int st = d && work ? CB_OK : CB_ENOMEM;
  for (int k = 0; st == CB_OK && k < s->model.nfree; k++)
    for (int a = 0; a < 3; a++) d[3 * k + a] = 1.0 / sqrt(s->mass[s->free_vertex[k]]); /* M^-1/2 */
  int dense = method == CB_EIG_DENSE || method == CB_EIG_BOTH || (method == CB_EIG_AUTO && n <= CB_STABILITY_DENSE_MAX);
  int lanczos = method == CB_EIG_LANCZOS || method == CB_EIG_BOTH || (method == CB_EIG_AUTO && !dense);
  if (st == CB_OK && dense) {
    eval = cb_malloc((size_t)n, sizeof(double));
    st = eval ? cb_dense_eigenvalues(A, d, eval) : CB_ENOMEM; /* eigenvalues of M^-1/2 K M^-1/2 */
    if (st == CB_OK) {
      out->lambda_dense = eval[n - 1];
      out->lambda_min_dense = eval[0];
    }
  }
  if (st == CB_OK && lanczos) {
    /* Lanczos until the largest Ritz pair's residual bound is below 1e-6
     * lambda (some eigenvalue then lies within that bound); only lambda_max
     * matters here, so the smallest end is not waited for. */
    cb_scaled_op op = {A, d, work};
    cb_lanczos_params lp = cb_lanczos_params_default();
    lp.max_steps = 640;
    lp.done = top_converged;
    cb_eig_result er;
    st = cb_lanczos(n, cb_scaled_op_apply, &op, &lp, &er);
    if (st == CB_OK) {
      out->lambda_lanczos = er.lmax;
      out->lanczos_res = er.res_max;
      out->lanczos_steps = er.steps;
      out->lanczos_status = er.status;
    }
  }
  if (st == CB_OK) {
    out->method = dense ? CB_EIG_DENSE : CB_EIG_LANCZOS;
    out->lambda_max = dense ? out->lambda_dense : out->lambda_lanczos;
    out->omega_max = out->lambda_max > 0 ? sqrt(out->lambda_max) : 0.0;
    out->dt_crit = out->lambda_max > 0 ? 2.0 / out->omega_max : INFINITY; /* dt_crit = 2/omega_max */
  }
  free(d);
  free(work);
  free(eval);
  out->ms = cb_now_ms() - t0;
  return st;
}

/* ---- cells ----------------------------------------------------------------- */

int cb_cell_work_alloc(const cb_scene *s, cb_cell_work *w) {
  w->x = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
  w->v = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
  if (!w->x || !w->v) {
    cb_cell_work_free(w);
    return CB_ENOMEM;
  }
  return CB_OK;
}

void cb_cell_work_free(cb_cell_work *w) {
  free(w->x);
  free(w->v);
  w->x = w->v = NULL;
}

static double total_energy(const cb_scene *s, const double *x, const double *v) {
  return cb_system_energy(&s->sys, x, NULL, NULL) + cb_scene_kinetic(s, v); /* E = potential + kinetic */
}

int cb_stability_cell(cb_integrator *it, double dt, const double *x0, const double *v0, double S,
                      const cb_stability_params *p, cb_cell_work *w, cb_cell_result *out) {
  memset(out, 0, sizeof *out);
  const cb_scene *s = it->scene;
  size_t n3 = (size_t)3 * s->mesh.nv;
  if (!(dt > 0) || !isfinite(dt)) return cb_fail("stability cell: dt must be positive and finite, got %g", dt);
  if (!(S > 0) || !isfinite(S)) return cb_fail("stability cell: energy scale must be positive, got %g", S);
  it->params.dt = dt;
  memcpy(w->x, x0, n3 * sizeof(double));
  memcpy(w->v, v0, n3 * sizeof(double));
  double E0 = total_energy(s, w->x, w->v);
  if (!isfinite(E0)) return cb_fail("stability cell: the start state has a non-finite energy");
  long n = cb_stability_steps(p, dt);
  out->dt = dt;
  out->steps_planned = n;
  out->energy0 = out->energy_end = E0;
  out->energy_scale = S;
  cb_classifier c;
  cb_classifier_init(&c);
  int marked = 0;
  double t0 = cb_now_ms();
  for (long k = 0; k < n; k++) {
    cb_step_stats st;
    int r = cb_integrator_step(it, w->x, w->v, &st);
    out->steps = k + 1;
    out->newton_iters += st.newton_iters;
    if (st.newton_iters > out->max_newton_iters) out->max_newton_iters = st.newton_iters;
    if (r == CB_NOT_CONVERGED) out->not_converged_steps++;
    if (r != CB_OK) out->step_status = r;
    if (r == CB_DIVERGED) { /* NaN/Inf in the state */
      out->energy_end = NAN;
      cb_classifier_push(&c, p, NAN);
      break;
    }
    if (r != CB_OK && r != CB_NOT_CONVERGED) {
      c.cls = CB_CELL_FAILED;
      break;
    }
    int mark = !marked && p->mark_time > 0 && (double)(k + 1) * dt >= p->mark_time * (1 - 1e-12);
    if (mark || k + 1 == n || (p->energy_every > 0 && (k + 1) % p->energy_every == 0)) {
      double E = total_energy(s, w->x, w->v);
      out->energy_end = E;
      if (mark) {
        marked = 1;
        out->t_mark = (double)(k + 1) * dt;
        out->energy_mark = E;
      }
      if (cb_classifier_push(&c, p, (E - E0) / S)) break; /* r = (E - E0)/S */
    }
  }
  out->wall_ms = cb_now_ms() - t0;
  out->t_end = (double)out->steps * dt;
  if (!marked) {
    out->t_mark = out->t_end;
    out->energy_mark = out->energy_end;
  }
  out->cls = c.cls;
  out->max_energy_ratio = c.max_ratio;
  out->final_energy_ratio = c.samples ? c.last_ratio : 0.0;
  return CB_OK;
}

/* ---- boundary ---------------------------------------------------------------- */

int cb_stability_grid_bracket(const double *dt, const int *cls, int n, double *lo, double *hi, int *monotone) {
  int first = n;
  for (int i = 0; i < n; i++)
    if (cls[i] != CB_CELL_STABLE) {
      first = i;
      break;
    }
  *monotone = 1;
  for (int i = first + 1; i < n; i++)
    if (cls[i] == CB_CELL_STABLE) *monotone = 0;
  *lo = first > 0 ? dt[first - 1] : 0.0;
  *hi = first < n ? dt[first] : 0.0;
  return first == 0 ? CB_NOT_CONVERGED : CB_OK;
}

static int run_cell(cb_integrator *it, double dt, const double *x0, const double *v0, double S,
                    const cb_stability_params *p, cb_cell_work *w, cb_cell_hook hook, void *ctx, int *runs,
                    int *stable) {
  cb_cell_result r;
  int st = cb_stability_cell(it, dt, x0, v0, S, p, w, &r);
  if (st) return st;
  (*runs)++;
  if (hook) hook(ctx, &r);
  *stable = r.cls == CB_CELL_STABLE;
  return CB_OK;
}

int cb_stability_bisect(cb_integrator *it, const double *x0, const double *v0, double S, const cb_stability_params *p,
                        cb_cell_work *w, double lo, double hi, double grow, int iters, cb_cell_hook hook, void *ctx,
                        cb_bisect_result *out) {
  memset(out, 0, sizeof *out);
  out->status = CB_OK;
  if (!(grow > 1)) return cb_fail("bisection: grow must be > 1, got %g", grow);
  if (!(lo > 0) && !(hi > 0)) return cb_fail("bisection: needs a stable lo or an unstable hi");
  int st = CB_OK, stable = 0;
  if (!(hi > 0)) { /* everything up to lo was stable: search upward */
    for (int i = 0; i < 40 && st == CB_OK; i++) {
      double d = lo * grow;
      st = run_cell(it, d, x0, v0, S, p, w, hook, ctx, &out->runs, &stable);
      if (st == CB_OK && !stable) {
        hi = d;
        break;
      }
      if (st == CB_OK) lo = d;
    }
  } else if (!(lo > 0)) { /* even hi's grid neighbour was unstable: search downward */
    for (int i = 0; i < 40 && st == CB_OK; i++) {
      double d = hi / grow;
      st = run_cell(it, d, x0, v0, S, p, w, hook, ctx, &out->runs, &stable);
      if (st == CB_OK && stable) {
        lo = d;
        break;
      }
      if (st == CB_OK) hi = d;
    }
  }
  if (st) return st;
  if (!(lo > 0) || !(hi > 0)) {
    out->status = CB_NOT_CONVERGED;
    out->dt_stable = lo > 0 ? lo : NAN;
    out->dt_unstable = hi > 0 ? hi : NAN;
    return CB_OK;
  }
  for (int i = 0; i < iters && st == CB_OK; i++) {
    double mid = sqrt(lo * hi); /* bisection of log dt */
    st = run_cell(it, mid, x0, v0, S, p, w, hook, ctx, &out->runs, &stable);
    if (st == CB_OK) {
      if (stable) lo = mid;
      else hi = mid;
    }
  }
  out->dt_stable = lo;
  out->dt_unstable = hi;
  return st;
}

int cb_stability_boundary_from_guess(cb_integrator *it, const double *x0, const double *v0, double S,
                                     const cb_stability_params *p, cb_cell_work *w, double guess, double grow,
                                     int iters, cb_cell_hook hook, void *ctx, cb_bisect_result *out) {
  memset(out, 0, sizeof *out);
  int runs = 0, stable = 0;
  int st = run_cell(it, guess, x0, v0, S, p, w, hook, ctx, &runs, &stable);
  if (st) return st;
  st =
      cb_stability_bisect(it, x0, v0, S, p, w, stable ? guess : 0.0, stable ? 0.0 : guess, grow, iters, hook, ctx, out);
  out->runs += runs;
  return st;
}

/* ---- cases ----------------------------------------------------------------- */

cb_case_params cb_case_params_default(void) {
  cb_case_params p = {.equilibrium = 1,
                      .perturb = 1e-6,
                      .swing = 1e-3,
                      .swing_dir = {0, 0, 1},
                      .seed = 1,
                      .eig = CB_EIG_AUTO,
                      .predict_rest = 1,
                      .eq = cb_equilibrium_params_default()};
  return p;
}

void cb_stability_case_free(cb_stability_case *c) {
  if (!c) return;
  cb_integrator_free(c->expl);
  cb_integrator_free(c->newton);
  cb_cell_work_free(&c->work);
  free(c->x_start);
  free(c->v_start);
  cb_scene_free(c->scene);
  memset(c, 0, sizeof *c);
}

static void prediction_nan(cb_prediction *p) {
  memset(p, 0, sizeof *p);
  p->lambda_max = p->omega_max = p->dt_crit = p->lambda_dense = p->lambda_min_dense = p->lambda_lanczos =
      p->lanczos_res = NAN;
}

int cb_stability_case_init(cb_stability_case *c, const cb_config *cfg, const cb_case_params *pp) {
  cb_case_params p = pp ? *pp : cb_case_params_default();
  memset(c, 0, sizeof *c);
  prediction_nan(&c->pred);
  prediction_nan(&c->pred_rest);
  int st = cb_scene_from_config(cfg, &c->scene);
  if (st) return st;
  cb_scene *s = c->scene;
  size_t n3 = (size_t)3 * s->mesh.nv;
  c->x_start = cb_malloc(n3, sizeof(double));
  c->v_start = cb_calloc(n3, sizeof(double));
  if (!c->x_start || !c->v_start) st = CB_ENOMEM;
  if (st == CB_OK) st = cb_cell_work_alloc(s, &c->work);
  if (st == CB_OK) {
    memcpy(c->x_start, s->x0, n3 * sizeof(double));
    if (p.equilibrium) {
      st = cb_stability_equilibrium(s, c->x_start, &p.eq, &c->eq);
      c->has_equilibrium = st == CB_OK && !cb_status_is_fatal(c->eq.status == CB_NOT_CONVERGED ? CB_OK : c->eq.status);
      if (!c->has_equilibrium)
        memcpy(c->x_start, s->x0, n3 * sizeof(double)); /* fall back to x0 (eq.status says why) */
    }
  }
  if (st == CB_OK) { /* v_start: a random part and a swing, as fractions of S0 = S(x_start, 0) */
    double S0 = cb_stability_energy_scale(s, c->x_start, c->v_start);
    cb_stability_perturb(s, p.perturb * S0, p.seed, c->v_start);
    cb_stability_swing(s, p.swing * S0, p.swing_dir, c->v_start);
    c->kinetic0 = cb_scene_kinetic(s, c->v_start);
    c->S = cb_stability_energy_scale(s, c->x_start, c->v_start);
  }
  if (st == CB_OK) st = cb_stability_predict(s, c->x_start, p.eig, &c->pred);
  if (st == CB_OK && p.predict_rest) st = cb_stability_predict(s, s->mesh.x, p.eig, &c->pred_rest);
  cb_integrator_params ip;
  cb_newton_params np;
  if (st == CB_OK) st = cb_integrator_params_from_config(cfg, &ip);
  if (st == CB_OK) st = cb_newton_params_from_config(cfg, &np);
  if (st == CB_OK) st = cb_integrator_alloc("explicit", s, &ip, NULL, NULL, NULL, &c->expl);
  if (st == CB_OK) {
    cb_solver_params sp = cb_solver_params_from_config(cfg);
    st = cb_integrator_alloc("newton", s, &ip, &np, cfg->solver, &sp, &c->newton);
  }
  if (st) cb_stability_case_free(c);
  return st;
}
