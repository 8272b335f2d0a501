/* The GAMES103 lab's implicit solver: Jacobi on the nonlinear problem
 * min F(x), without linearising, and its Chebyshev acceleration (Wang 2015,
 * "A Chebyshev semi-iterative approach for accelerating projective and
 * position-based dynamics").
 *
 *   xhat = x0 + dt v0,  x_0 = xhat                       (objective.h)
 *   K times (integrator.iters; the lab uses 32):
 *     g_k     = M (x_k - xhat)/dt^2 + grad E(x_k)         (gravity included)
 *     y_k     = x_k - alpha D^-1 g_k                      (free vertices only)
 *     x_{k+1} = omega_k y_k + (1 - omega_k) x_{k-1}       (chebyshev-nl; jacobi-nl: omega = 1)
 *     omega_0 = 1, omega_1 = 2/(2 - rho^2), omega_k = 4/(4 - rho^2 omega_{k-1})
 *   v1 = (x_K - x0)/dt
 *
 * D (integrator.diagonal), per free vertex i:
 *   lab      d_i = m_i/dt^2 + 4k, constant: the lab's "4k", the valence of
 *            its grid's axis springs (k = material.stretch_k), whatever the mesh;
 *   valence  d_i = m_i/dt^2 + k n_i, n_i the vertex's stretch springs
 *            (pinned neighbours included): the same rule for any mesh (6k at
 *            an interior vertex of the regular grid);
 *   exact    the 3x3 block (M/dt^2 + H(x_k))_ii, with the definiteness policy
 *            (integrator.definiteness), reassembled every iteration; a block
 *            that is not positive definite ends the step with not_spd.
 * alpha (integrator.alpha, default 1) scales the step: it is Wang's
 * under-relaxation gamma, x_{k+1} = omega (gamma (y - x_k) + x_k) + (1 - omega) x_{k-1}.
 *
 * rho (chebyshev-nl, integrator.rho): a number in [0, 1), or `auto`: before
 * its first step the integrator runs integrator.rho_iters plain Jacobi
 * iterations (omega = 1) of that step from xhat, records |x_{k+1} - x_k|,
 * and takes Wang's estimate, the decay rate of those updates over the second
 * half (cb_rho_from_updates). It costs rho_iters gradient evaluations once
 * per integrator, counted in that first step's factor_ms and wall_ms; the
 * rho used is in the step stats. rho = 0 is jacobi-nl exactly.
 *
 * Step stats: newton_iters = K; rel_grad = rel_grad_hat = |grad F(x_K)| /
 * |grad F(xhat)| (one extra gradient evaluation at the end); assemble_ms the
 * gradient (and, for exact, Hessian) evaluations, solve_ms the updates.
 * A non-finite gradient ends the step with `diverged`, and so does a
 * non-finite F at x_0 or x_K (the iterates between need only the gradient,
 * so F is not evaluated there: diverged()). The hook sees
 * CB_NEWTON_GRADIENT at every iterate (iter 0 = xhat, ..., K). */
#include <cblas.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "integrator_keys.h"
#include "vec.h"

#include "nl_kernel.h"

enum { DIAG_LAB = 0, DIAG_VALENCE = 1, DIAG_EXACT = 2 };

static const cb_nljacobi_params jacobi_defaults = {.cookie = CB_PARAMS_COOKIE,
                                                   .iters = 32,
                                                   .diagonal = DIAG_LAB,
                                                   .alpha = 1.0,
                                                   .rho = 0.0,
                                                   .rho_iters = 64,
                                                   .definiteness = CB_DEF_DROP};
static const cb_nljacobi_params chebyshev_defaults = {.cookie = CB_PARAMS_COOKIE,
                                                      .iters = 32,
                                                      .diagonal = DIAG_LAB,
                                                      .alpha = 1.0,
                                                      .rho = 0.995,
                                                      .rho_iters = 64,
                                                      .definiteness = CB_DEF_DROP};

cb_nljacobi_params cb_nljacobi_params_default(void) { return chebyshev_defaults; }

const char *const cb_nljacobi_diagonal_names[] = {"lab", "valence", "exact", NULL};

/* The keys; iters, rho, rho_iters and definiteness are the shared ones of
 * integrator_keys.h (projective dynamics, vbd and Newton declare them too). */
#define NJ(f) offsetof(cb_nljacobi_params, f)
#define KEY_DIAG \
  { \
    .name = "diagonal", .kind = CB_PARAM_CHOICE, .offset = NJ(diagonal), .def = "lab", .unit = "-", \
    .choices = cb_nljacobi_diagonal_names, \
    .doc = "Diagonal D of the nonlinear Jacobi update x <- x - alpha D^-1 grad F(x): `lab` m_i/dt^2 + 4k (the lab's " \
           "constant, k = material.stretch_k), `valence` m_i/dt^2 + k x (the vertex's spring count), `exact` the 3x3 " \
           "diagonal blocks of M/dt^2 + H(x) with integrator.definiteness, recomputed every iteration." \
  }
#define KEY_ALPHA \
  { \
    .name = "alpha", .kind = CB_PARAM_DOUBLE, .offset = NJ(alpha), .def = "1", .unit = "-", .hi = 2, .lo_open = 1, \
    .doc = "Step weight of the nonlinear Jacobi update (Wang's under-relaxation gamma); 1 is the lab's." \
  }
static const cb_param_key jacobi_keys[] = {
    CB_KEY_ITERS(NJ(iters)), KEY_DIAG, KEY_ALPHA, CB_KEY_DEFINITENESS(NJ(definiteness)), CB_KEY_END,
};
static const cb_param_key chebyshev_keys[] = {
    CB_KEY_ITERS(NJ(iters)),         KEY_DIAG,   KEY_ALPHA, CB_KEY_DEFINITENESS(NJ(definiteness)), CB_KEY_RHO(NJ(rho)),
    CB_KEY_RHO_ITERS(NJ(rho_iters)), CB_KEY_END,
};
#undef NJ

typedef struct {
  cb_objective obj;
  double *gF;         /* 3*nfree */
  double *xprev;      /* 3*nv: x_{k-1} */
  double *dinv;       /* nfree: 1/d_i (lab, valence) */
  double *blk;        /* 6*nfree: Cholesky factors of the diagonal blocks (exact) */
  int *slot, *stride; /* nfree: slot of block (i, i) in A (exact) */
  double *dnorm;      /* rho_iters: update norms of the rho estimate */
  double rho;         /* the rho in use (-1 until auto has been estimated) */
  double rho_ms;      /* time of the estimate, ms */
  int fast;           /* the fused kernel applies (fast_init) */
  int nterms;
  const cb_term *term[CB_MAX_TERMS]; /* the system's terms, in its order */
  int gravity[CB_MAX_TERMS];         /* term t is gravity (else springs) */
  double grav[CB_MAX_TERMS][3];      /* its g */
} nlj_work;

static void nlj_free(cb_integrator *it) {
  nlj_work *w = it->state;
  cb_objective_free(&w->obj);
  free(w->gF);
  free(w->xprev);
  free(w->dinv);
  free(w->blk);
  free(w->slot);
  free(w->stride);
  free(w->dnorm);
}

/* The fused kernel applies to the lab and valence diagonals when every term
 * is springs or gravity and the free vertices are in mesh order. */
static void fast_init(nlj_work *w, const cb_scene *s, int diagonal) {
  w->fast = 0;
  if (diagonal == DIAG_EXACT || s->sys.nterms > CB_MAX_TERMS) return;
  for (int b = 1; b < s->model.nfree; b++)
    if (s->free_vertex[b] <= s->free_vertex[b - 1]) return;
  w->nterms = s->sys.nterms;
  for (int t = 0; t < s->sys.nterms; t++) {
    const cb_term *term = s->sys.terms[t];
    w->term[t] = term;
    w->gravity[t] = term->type == cb_term_gravity;
    if (w->gravity[t]) cb_gravity_term_vector(term, w->grav[t]);
    else if (term->type != cb_term_spring) return;
  }
  w->fast = 1;
}

static int nlj_init(cb_integrator *it) {
  cb_nljacobi_params *p = it->type_params;
  nlj_work *w = it->state;
  const cb_scene *s = it->scene;
  int nf = s->model.nfree;
  if (p->diagonal < DIAG_LAB || p->diagonal > DIAG_EXACT)
    return cb_fail("%s: unknown diagonal %d", it->type->name, p->diagonal);
  if (p->diagonal == DIAG_EXACT && p->definiteness == CB_DEF_SHIFT)
    return cb_fail("%s: integrator.definiteness = shift is a linear-solve policy; the exact diagonal takes none, drop, "
                   "mirror or choi-ko",
                   it->type->name);
  if (!(p->alpha > 0 && p->alpha <= 2)) return cb_fail("%s: alpha must be in (0, 2], got %g", it->type->name, p->alpha);
  if (p->iters < 1) return cb_fail("%s: iters must be >= 1, got %d", it->type->name, p->iters);
  if (!(p->rho == CB_AUTO || (p->rho >= 0 && p->rho < 1)))
    return cb_fail("%s: rho must be in [0, 1) or auto, got %g", it->type->name, p->rho);
  if (p->rho == CB_AUTO && p->rho_iters < 4) return cb_fail("%s: rho_iters must be >= 4", it->type->name);
  int st = cb_objective_init(&w->obj, s);
  if (st) return st;
  w->gF = cb_malloc((size_t)3 * nf + 1, sizeof(double));
  w->xprev = cb_malloc((size_t)3 * s->mesh.nv, sizeof(double));
  w->dinv = cb_malloc((size_t)nf + 1, sizeof(double));
  if (!w->gF || !w->xprev || !w->dinv) return CB_ENOMEM;
  if (p->rho == CB_AUTO && !(w->dnorm = cb_malloc((size_t)p->rho_iters, sizeof(double)))) return CB_ENOMEM;
  w->rho = p->rho;
  double dt = it->params.dt, k = s->def.stretch_k;
  if (p->diagonal == DIAG_EXACT) {
    w->blk = cb_malloc((size_t)6 * nf + 1, sizeof(double));
    w->slot = cb_malloc((size_t)nf + 1, sizeof(int));
    w->stride = cb_malloc((size_t)nf + 1, sizeof(int));
    if (!w->blk || !w->slot || !w->stride) return CB_ENOMEM;
    for (int b = 0; b < nf; b++)
      if (cb_sparse_block_slot(&it->sys->A, b, b, &w->slot[b], &w->stride[b]) < 0)
        return cb_fail("%s: diagonal block %d missing from the system's pattern", it->type->name, b);
  } else {
    int *deg = cb_calloc((size_t)s->mesh.nv + 1, sizeof(int)); /* each vertex's stretch springs (valence) */
    if (!deg) return CB_ENOMEM;
    for (int e = 0; e < s->topo.ne; e++) {
      deg[s->topo.edge[2 * e]]++;
      deg[s->topo.edge[2 * e + 1]]++;
    }
    for (int b = 0; b < nf; b++) {
      int i = s->free_vertex[b];
      double springs = p->diagonal == DIAG_VALENCE ? deg[i] : 4.0; /* lab: 4k whatever the vertex */
      double d = s->mass[i] / (dt * dt) + springs * k;             /* d_i = m_i/dt^2 + n_i k */
      if (!(d > 0)) {
        free(deg);
        return cb_fail("%s: vertex %d has diagonal %g (no mass and no springs)", it->type->name, i, d);
      }
      w->dinv[b] = 1.0 / d;
    }
    free(deg);
  }
  fast_init(w, s, p->diagonal);
  return CB_OK;
}

/* Cholesky of the symmetric 3x3 block B (column-major at val + slot, column
 * stride `stride`): l = {l00, l10, l20, l11, l21, l22}. 0 unless SPD. */
static int chol3(const double *val, int slot, int stride, double *l) {
  const double *c0 = val + slot, *c1 = c0 + stride, *c2 = c1 + stride;
  double a00 = c0[0], a10 = c0[1], a20 = c0[2], a11 = c1[1], a21 = c1[2], a22 = c2[2];
  if (!(a00 > 0)) return 0;
  double l00 = sqrt(a00), l10 = a10 / l00, l20 = a20 / l00;
  double s11 = a11 - l10 * l10;
  if (!(s11 > 0)) return 0;
  double l11 = sqrt(s11), l21 = (a21 - l20 * l10) / l11;
  double s22 = a22 - l20 * l20 - l21 * l21;
  if (!(s22 > 0)) return 0;
  l[0] = l00;
  l[1] = l10;
  l[2] = l20;
  l[3] = l11;
  l[4] = l21;
  l[5] = sqrt(s22);
  return 1;
}

/* y = B^-1 g with B = L L^T. */
static void chol3_solve(const double *l, const double *g, double *y) {
  double z0 = g[0] / l[0], z1 = (g[1] - l[1] * z0) / l[3], z2 = (g[2] - l[2] * z0 - l[4] * z1) / l[5];
  y[2] = z2 / l[5];
  y[1] = (z1 - l[4] * y[2]) / l[3];
  y[0] = (z0 - l[1] * y[1] - l[2] * y[2]) / l[0];
}

/* One pass of the fused kernel at x: each term's springs (cb_spring_term_forces), then one loop over
 * the vertices in mesh order that gathers each vertex's gradient (the terms in the system's order,
 * from 0: cb_system_energy's), gravity's energy, the objective's inertia and grad F
 * (cb_objective_eval's), and, when xn is not NULL, the update of x_{k+1} into xn (xn holds x_{k-1}
 * of the free vertices on entry; iterate's update). Every sum runs in its old order, so F, grad F
 * and x_{k+1} are bit for bit those of cb_objective_eval and the update loop. gF (if not NULL)
 * receives grad F; *gg gets sum (grad F)^2 and *d2 sum |x_{k+1} - x_k|^2; *bad (NULL when xn is) is ORed
 * with cb_nonfinite_bits of every x_{k+1} written. Returns F. */
/* The objective and the update at free vertex v (block b) with gradient g of E: iterate's arithmetic. */
static inline __attribute__((always_inline)) void fast_vertex(const double *xv, const double *xh, double mv,
                                                              double dinv, double inv_dt2, const double g[3],
                                                              double *gF, double *xn, double omega, double alpha,
                                                              double *inertia, double *gg, double *d2, uint64_t *bad) {
  double gf[3];
  for (int a = 0; a < 3; a++) {
    double d = xv[a] - xh[a];
    if (inertia) *inertia += mv * d * d; /* |x - xhat|_M^2 */
    gf[a] = mv * d * inv_dt2 + g[a];     /* M(x - xhat)/dt^2 + dE/dx */
    if (gg) *gg += gf[a] * gf[a];
  }
  if (gF)
    for (int a = 0; a < 3; a++) gF[a] = gf[a];
  if (xn)
    for (int a = 0; a < 3; a++) {
      double xk = xv[a];
      double xnew = omega * (xk - alpha * (dinv * gf[a])) + (1.0 - omega) * xn[a]; /* iterate's update */
      double dx = xnew - xk;
      if (d2) *d2 += dx * dx;
      *bad |= cb_nonfinite_bits(xnew); /* x_{k+1} finite? (cb_bits_finite) */
      xn[a] = xnew;
    }
}

/* fast_pass for springs pushed (cb_spring_push), then gravity gr: the same sums in the same order. An
 * update pass (xn not NULL) computes no objective: no energies, no inertia, no sum (grad F)^2 (iterate_fast
 * checks the update instead: *sbad, cb_bits_finite), and sum |x_{k+1} - x_k|^2 only if d2 (the rho
 * estimate's). Its vertex update is fast_vertex's on 4-vectors (x_k from the padded P.x4): lane by lane the
 * same operations, so the same bits. */
static inline __attribute__((always_inline)) void
push_pass(const cb_spring_push *Pp, const cb_scene *s, const double *restrict x, const double *gr,
          const double *restrict xhat, const double *restrict dinv, double inv_dt2, double *gF, double *xn,
          double omega, double alpha, int d2, double *inertia, double *sgg, double *sd2, double *Et, uint64_t *sbad) {
  const cb_spring_push P = *Pp;
  const double *restrict m = s->mass; /* s->model.mass is the same array */
  const int *restrict fi = s->free_index;
  const int nv = s->mesh.nv, objective = !xn;
  const double g0 = gr[0], g1 = gr[1], g2 = gr[2];
  const cb_v4d gv = {g0, g1, g2, 0.0};
  const cb_v4u exp3 = {CB_DOUBLE_EXP_BITS, CB_DOUBLE_EXP_BITS, CB_DOUBLE_EXP_BITS, 0}; /* lanes 0-2 */
  cb_v4u bad4 = {0, 0, 0, 0};
  double in = 0.0, gg = 0.0, dd = 0.0;
  const int *restrict first = P.first, *restrict slot = P.slot;
  const int mask = P.M - 1;
  double *restrict acc = P.acc;
  double Es = 0.0, Eg = 0.0;
  memset(acc, 0, (size_t)4 * P.M * sizeof *acc);
  const double *restrict f = P.f;
  const cb_v4d zero = {0.0, 0.0, 0.0, 0.0};
  for (int v0 = 0, filled = 0; v0 < nv; v0 += CB_SPRING_CHUNK) {
    int v1 = v0 + CB_SPRING_CHUNK < nv ? v0 + CB_SPRING_CHUNK : nv, e0 = first[v0];
    int reach = v1 + P.M < nv ? v1 + P.M : nv; /* the chunk's springs end below v1 - 1 + M */
    cb_spring_push_positions(&P, x, filled, reach);
    filled = reach;
    cb_spring_push_forces(&P, x, e0, first[v1], objective); /* the chunk's springs at once (vectorised) */
    const double *fe = f;                                   /* spring e's force, e from e0 on */
    const int *restrict sl = slot + e0;                     /* and its slot */
    for (int v = v0; v < v1; v++) {
      const double *xv = x + 3 * v;
      double *av = acc + 4 * (v & mask);
      cb_v4d g4, f4, a4;
      cb_v4d_get(&g4, av); /* 0 - f_e of the springs ending at v, in spring order */
      cb_v4d_put(av, &zero);
      for (int n = first[v + 1] - first[v]; n > 0; n--, fe += 4, sl++) { /* + f_e of those starting at v, E_e */
        double *aj = acc + *sl;
        cb_v4d_get(&f4, fe);
        cb_v4d_get(&a4, aj);
        g4 += f4;
        a4 -= f4;
        cb_v4d_put(aj, &a4);
        if (objective) Es += fe[3];
      }
      int b = fi[v];
      if (!objective) { /* an update pass: fast_vertex's arithmetic on 4-vectors (lane 3 is not used) */
        if (b < 0) continue;
        const double *xh = xhat + 3 * v;
        double *xp = xn + 3 * v;
        cb_v4d xk, xh4 = {xh[0], xh[1], xh[2], 0.0}, xp4 = {xp[0], xp[1], xp[2], 0.0};
        cb_v4d_get(&xk, P.x4 + 4 * (size_t)v);        /* x_k at v (cb_spring_push_positions) */
        g4 -= m[v] * gv;                              /* gravity: g -= m_v g */
        cb_v4d gf = m[v] * (xk - xh4) * inv_dt2 + g4; /* M(x - xhat)/dt^2 + dE/dx */
        cb_v4d x1 = omega * (xk - alpha * (dinv[b] * gf)) + (1.0 - omega) * xp4; /* iterate's update */
        cb_v4u u;
        memcpy(&u, &x1, sizeof u);
        bad4 |= (u & exp3) + CB_DOUBLE_EXP_ONE; /* x_{k+1} finite? cb_nonfinite_bits on lanes 0-2 (3: 0 + one) */
        for (int a = 0; a < 3; a++) {
          if (d2) {
            double dx = x1[a] - xk[a];
            dd += dx * dx;
          }
          xp[a] = x1[a];
        }
        continue;
      }
      double g[3] = {g4[0], g4[1], g4[2]};                 /* an objective pass */
      Eg -= m[v] * (g0 * xv[0] + g1 * xv[1] + g2 * xv[2]); /* gravity_energy */
      g[0] -= m[v] * g0;
      g[1] -= m[v] * g1;
      g[2] -= m[v] * g2;
      if (b >= 0)
        fast_vertex(xv, xhat + 3 * v, m[v], dinv[b], inv_dt2, g, gF ? gF + 3 * b : NULL, NULL, omega, alpha, &in, &gg,
                    NULL, NULL);
    }
  }
  Et[0] = Es;
  Et[1] = Eg;
  *inertia = in;
  *sgg = gg;
  *sd2 = dd;
  if (sbad) *sbad = bad4[0] | bad4[1] | bad4[2];
}

CB_KERNEL_CLONES static double fast_pass(nlj_work *w, const cb_scene *s, const double *x, double *gF, double *xn,
                                         double omega, double alpha, double *gg, double *d2, uint64_t *bad) {
  cb_spring_gather G[CB_MAX_TERMS];
  double Et[CB_MAX_TERMS];
  int nt = w->nterms, nv = s->mesh.nv;
  cb_spring_push P;
  int push = nt == 2 && !w->gravity[0] && w->gravity[1] && cb_spring_term_push(w->term[0], &P);
  for (int t = 0; t < nt; t++) {
    Et[t] = 0.0;
    if (!w->gravity[t] && !push) cb_spring_term_forces(w->term[t], x, &G[t]);
  }
  const double *m = s->model.mass, *ms = s->mass, *xhat = w->obj.xhat, *dinv = w->dinv;
  const int *fi = s->free_index;
  double inv_dt2 = 1.0 / (w->obj.dt * w->obj.dt), inertia = 0.0, sgg = 0.0, sd2 = 0.0;
  if (push) { /* springs (a mesh's edges), then gravity: the push kernel (nl_kernel.h), one copy per use */
#define PUSH(GF, XN, ALPHA, D2) \
  push_pass(&P, s, x, w->grav[1], xhat, dinv, inv_dt2, GF, XN, omega, ALPHA, D2, &inertia, &sgg, &sd2, Et, bad)
    if (!xn) PUSH(gF, NULL, alpha, 0);
    else if (alpha == 1.0 && !d2) PUSH(NULL, xn, 1.0, 0); /* the lab's: alpha * y = y exactly, folded */
    else PUSH(NULL, xn, alpha, d2 != NULL);               /* any alpha, and the rho estimate's passes */
#undef PUSH
  } else if (nt == 2 && !w->gravity[0] && w->gravity[1]) { /* springs, then gravity: the common scene, in registers */
    cb_spring_gather *G0 = &G[0];
    const double g0 = w->grav[1][0], g1 = w->grav[1][1], g2 = w->grav[1][2];
    double Es = 0.0, Eg = 0.0;
    for (int v0 = 0; v0 < nv; v0 += CB_SPRING_CHUNK) { /* chunks: the streamed forces stay in cache */
      int v1 = v0 + CB_SPRING_CHUNK < nv ? v0 + CB_SPRING_CHUNK : nv;
      cb_spring_gather_upto(G0, v1);
      for (int v = v0; v < v1; v++) {
        const double *xv = x + 3 * v;
        double g[3] = {0.0, 0.0, 0.0};
        cb_spring_gather_add(G0, v, &g[0], &g[1], &g[2], &Es);
        Eg -= m[v] * (g0 * xv[0] + g1 * xv[1] + g2 * xv[2]); /* gravity_energy */
        g[0] -= m[v] * g0;
        g[1] -= m[v] * g1;
        g[2] -= m[v] * g2;
        int b = fi[v];
        if (b >= 0)
          fast_vertex(xv, xhat + 3 * v, ms[v], dinv[b], inv_dt2, g, gF ? gF + 3 * b : NULL, xn ? xn + 3 * v : NULL,
                      omega, alpha, &inertia, &sgg, &sd2, bad);
      }
    }
    Et[0] = Es;
    Et[1] = Eg;
  } else {
    for (int v0 = 0; v0 < nv; v0 += CB_SPRING_CHUNK) {
      int v1 = v0 + CB_SPRING_CHUNK < nv ? v0 + CB_SPRING_CHUNK : nv;
      for (int t = 0; t < nt; t++)
        if (!w->gravity[t]) cb_spring_gather_upto(&G[t], v1);
      for (int v = v0; v < v1; v++) {
        const double *xv = x + 3 * v;
        double g[3] = {0.0, 0.0, 0.0};
        for (int t = 0; t < nt; t++) {
          if (w->gravity[t]) { /* gravity_energy */
            const double *gr = w->grav[t];
            Et[t] -= m[v] * (gr[0] * xv[0] + gr[1] * xv[1] + gr[2] * xv[2]);
            for (int a = 0; a < 3; a++) g[a] -= m[v] * gr[a];
          } else {
            cb_spring_gather_add(&G[t], v, &g[0], &g[1], &g[2], &Et[t]);
          }
        }
        int b = fi[v];
        if (b >= 0)
          fast_vertex(xv, xhat + 3 * v, ms[v], dinv[b], inv_dt2, g, gF ? gF + 3 * b : NULL, xn ? xn + 3 * v : NULL,
                      omega, alpha, &inertia, &sgg, &sd2, bad);
      }
    }
  }
  double E = 0.0;
  for (int t = 0; t < nt; t++) {
    if (!push && !w->gravity[t] && !G[t].sorted) Et[t] = cb_spring_gather_energy(&G[t]);
    E += Et[t]; /* cb_system_energy's order */
  }
  *gg = sgg;
  if (d2) *d2 = sd2;
  return 0.5 * inv_dt2 * inertia + E;
}

/* The step diverges at iterate k when grad F(x_k) is not finite, or, at x_0 and x_K (the iterates whose
 * F is reported), when F is not: the iterates between need only the gradient, so the fused kernel's
 * update passes compute no objective (iterate and iterate_fast share this rule). */
static int diverged(double F, double gn, int k, int K) { return !isfinite(gn) || ((k == 0 || k == K) && !isfinite(F)); }

/* iterate with the fused kernel (no hook, lab or valence diagonal): the
 * first and last iterates are measured as iterate measures them (F, grad F
 * stored, cblas_dnrm2); the ones between evaluate the gradient and update in
 * one pass that computes no objective (push_pass), writing x_{k+1} over
 * x_{k-1} and swapping the two arrays. A pass whose x_{k+1} is not finite (at a
 * free vertex: the pass ORs cb_nonfinite_bits of what it writes) is measured again the old way at x_k,
 * which is intact, so the
 * step diverges exactly where iterate's does, with the same stats and x. */
static int iterate_fast(cb_integrator *it, double *x, int K, double rho, double *dnorm, cb_step_stats *st, int report) {
  nlj_work *w = it->state;
  const cb_scene *s = it->scene;
  const cb_nljacobi_params *p = it->type_params;
  int nf = s->model.nfree, nf3 = 3 * nf;
  size_t nv3 = (size_t)3 * s->mesh.nv;
  double alpha = p->alpha, omega = 1.0, g0 = 0.0, gg, d2, d2k = 0.0;
  cb_objective_guess(&w->obj, x, 1); /* x_0 = xhat, pins at their prescribed positions */
  memcpy(w->xprev, x, nv3 * sizeof(double));
  double *cur = x, *prev = w->xprev;
  int status = CB_OK;
  for (int k = 0;; k++) {
    double t0 = cb_now_ms();
    if (k > 0 && k < K) { /* evaluate and update in one pass */
      omega = cb_chebyshev_omega(k, rho, omega);
      uint64_t bad = 0;
      fast_pass(w, s, cur, NULL, prev, omega, alpha, &gg, dnorm ? &d2k : NULL, &bad);
      /* every grad F entry was finite: x_{k+1} = omega (x_k - alpha D^-1 g) + (1 - omega) x_{k-1}, with alpha,
       * D^-1 and omega > 0, is not finite where g is not (the pins' entries are their positions) */
      if (cb_bits_finite(bad)) {
        double *tmp = cur;
        cur = prev;
        prev = tmp;
        if (dnorm) dnorm[k] = sqrt(d2k);
        st->assemble_ms += cb_now_ms() - t0;
        continue;
      }
    }
    double F = fast_pass(w, s, cur, w->gF, NULL, 1.0, alpha, &gg, &d2, NULL); /* measured: F, grad F, |grad F| */
    double gn = cblas_dnrm2(nf3, w->gF, 1);
    st->assemble_ms += cb_now_ms() - t0;
    if (k == 0) g0 = gn;
    if (report) {
      st->F = F;
      st->grad_norm = gn;
      st->rel_grad = st->rel_grad_hat = g0 > 0 ? gn / g0 : 0.0;
      st->newton_iters = k;
    }
    if (diverged(F, gn, k, K)) {
      status = CB_DIVERGED;
      break;
    }
    if (k == K) break;
    if (k > 0) { /* a pass measured again and found finite: its update stands */
      double *tmp = cur;
      cur = prev;
      prev = tmp;
      if (dnorm) dnorm[k] = sqrt(d2k);
      continue;
    }
    t0 = cb_now_ms();
    omega = cb_chebyshev_omega(k, rho, omega); /* k = 0: the update of iterate */
    d2 = 0.0;
    for (int b = 0; b < nf; b++) {
      double *xi = cur + 3 * s->free_vertex[b], *xp = prev + 3 * s->free_vertex[b];
      const double *g = w->gF + 3 * b;
      for (int a = 0; a < 3; a++) {
        double xk = xi[a];
        double xn = omega * (xk - alpha * (w->dinv[b] * g[a])) + (1.0 - omega) * xp[a];
        double dx = xn - xk;
        d2 += dx * dx;
        xp[a] = xk;
        xi[a] = xn;
      }
    }
    st->solve_ms += cb_now_ms() - t0;
    if (dnorm) dnorm[k] = sqrt(d2);
  }
  if (cur != x) memcpy(x, cur, nv3 * sizeof(double));
  return status;
}

/* K iterations from xhat with the given rho; dnorm (if not NULL) receives
 * |x_{k+1} - x_k| of each. Leaves x_K in x. */
static int iterate(cb_integrator *it, double *x, int K, double rho, double *dnorm, cb_step_stats *st, int report) {
  nlj_work *w = it->state;
  const cb_scene *s = it->scene;
  const cb_nljacobi_params *p = it->type_params;
  cb_newton_hook hook = report ? it->params.hook : NULL;
  if (w->fast && !hook) return iterate_fast(it, x, K, rho, dnorm, st, report);
  int nf = s->model.nfree, nf3 = 3 * nf;
  double dt = it->params.dt, alpha = p->alpha, omega = 1.0, g0 = 0.0;
  cb_objective_guess(&w->obj, x, 1); /* x_0 = xhat, pins at their prescribed positions */
  memcpy(w->xprev, x, (size_t)3 * s->mesh.nv * sizeof(double));
  cb_newton_event ev;
  memset(&ev, 0, sizeof ev);
  ev.alpha = alpha;
  for (int k = 0;; k++) {
    double t0 = cb_now_ms();
    double F = cb_objective_eval(&w->obj, x, w->gF, NULL); /* g = M (x - xhat)/dt^2 + grad E(x) */
    double gn = cblas_dnrm2(nf3, w->gF, 1);
    st->assemble_ms += cb_now_ms() - t0;
    if (k == 0) g0 = gn;
    if (report) {
      st->F = F;
      st->grad_norm = gn;
      st->rel_grad = st->rel_grad_hat = g0 > 0 ? gn / g0 : 0.0;
      st->newton_iters = k;
    }
    if (diverged(F, gn, k, K)) return CB_DIVERGED;
    if (hook) {
      ev.iter = k;
      ev.F = F;
      ev.grad_norm = gn;
      ev.rel_grad = g0 > 0 ? gn / g0 : 0.0;
      ev.x = x;
      hook(it->params.hook_ctx, CB_NEWTON_GRADIENT, &ev);
    }
    if (k == K) break;
    if (p->diagonal == DIAG_EXACT) {
      t0 = cb_now_ms();
      cb_system_assemble(it->sys, x, 1.0 / (dt * dt), p->definiteness, 0.0); /* A = M/dt^2 + H(x) */
      for (int b = 0; b < nf; b++)
        if (!chol3(it->sys->A.val, w->slot[b], w->stride[b], w->blk + 6 * b))
          return cb_fail_status(CB_NOT_SPD,
                                "%s: iteration %d: the diagonal block of free vertex %d (vertex %d) of A = M/dt^2 + "
                                "H(x) is not positive definite, so integrator.diagonal = exact cannot invert it "
                                "(integrator.definiteness = %s keeps the compressed springs' negative curvature; "
                                "drop or mirror makes every block positive definite)",
                                it->type->name, k + 1, b, s->free_vertex[b], cb_definiteness_names[p->definiteness]);
      st->assemble_ms += cb_now_ms() - t0;
    }
    t0 = cb_now_ms();
    omega = cb_chebyshev_omega(k, rho, omega);
    double dmax = 0.0, d2 = 0.0;
    for (int b = 0; b < nf; b++) {
      double *xi = x + 3 * s->free_vertex[b], *xp = w->xprev + 3 * s->free_vertex[b];
      const double *g = w->gF + 3 * b;
      double step[3];
      if (p->diagonal == DIAG_EXACT) chol3_solve(w->blk + 6 * b, g, step);
      else
        for (int a = 0; a < 3; a++) step[a] = w->dinv[b] * g[a];
      for (int a = 0; a < 3; a++) {
        double xk = xi[a];
        double xn = omega * (xk - alpha * step[a]) + (1.0 - omega) * xp[a]; /* x_{k+1} = w y_k + (1-w) x_{k-1} */
        double dx = xn - xk;
        d2 += dx * dx;
        if (fabs(dx) > dmax) dmax = fabs(dx);
        xp[a] = xk;
        xi[a] = xn;
      }
    }
    st->solve_ms += cb_now_ms() - t0;
    if (dnorm) dnorm[k] = sqrt(d2);
    ev.step_max = dmax;
  }
  return CB_OK;
}

static int nlj_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  nlj_work *w = it->state;
  const cb_nljacobi_params *p = it->type_params;
  cb_objective_begin(&w->obj, x, v, it->params.dt); /* x0 = x, xhat = x0 + dt v0 */
  if (w->rho == CB_AUTO) { /* Wang's estimate, once: the decay of rho_iters plain updates of this step */
    double t0 = cb_now_ms();
    cb_step_stats scratch;
    memset(&scratch, 0, sizeof scratch);
    int r = iterate(it, x, p->rho_iters, 0.0, w->dnorm, &scratch, 0);
    w->rho = r == CB_OK ? cb_rho_from_updates(w->dnorm, p->rho_iters) : 0.0;
    w->rho_ms = cb_now_ms() - t0;
    st->factor_ms += w->rho_ms;
  }
  st->rho = w->rho;
  int status = iterate(it, x, p->iters, w->rho, NULL, st, 1);
  cb_objective_velocity(&w->obj, x, v); /* v1 = (x_K - x0)/dt; pinned vertices keep their v0 */
  return status;
}

const cb_integrator_type cb_integrator_jacobi_nl = {
    .name = "jacobi-nl",
    .flags = CB_INTEGRATOR_HESSIAN, /* only the exact diagonal assembles it */
    .size = sizeof(nlj_work),
    .params_size = sizeof(cb_nljacobi_params),
    .params_default = &jacobi_defaults,
    .keys = jacobi_keys,
    .init = nlj_init,
    .step = nlj_step,
    .free = nlj_free,
};

const cb_integrator_type cb_integrator_chebyshev_nl = {
    .name = "chebyshev-nl",
    .flags = CB_INTEGRATOR_HESSIAN,
    .size = sizeof(nlj_work),
    .params_size = sizeof(cb_nljacobi_params),
    .params_default = &chebyshev_defaults,
    .keys = chebyshev_keys,
    .init = nlj_init,
    .step = nlj_step,
    .free = nlj_free,
};
