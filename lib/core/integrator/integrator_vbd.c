/* Vertex block descent (Chen, Liu, Yang and Yuksel 2024, "Vertex block
 * descent", ACM TOG 43(4)), and its Chebyshev acceleration (their section 3.7,
 * after Wang 2015).
 *
 * The implicit-Euler objective F(x) = 1/(2 dt^2)|x - y|_M^2 + E(x), y = xhat =
 * x0 + dt v0 (objective.h), is minimised one vertex at a time: for each free
 * vertex i, with every other vertex held,
 *   f_i = -(m_i/dt^2)(x_i - y_i) - dE/dx_i                  (gravity's m_i g included)
 *   H_i = (m_i/dt^2) I + d2E/dx_i^2                          (3x3)
 *   x_i += H_i^-1 f_i                                        (one Newton step on x_i alone)
 * where dE/dx_i and d2E/dx_i^2 sum, over every element of every energy term
 * that touches i, that element's gradient at i and the (i, i) block of its
 * Hessian, read through the term interface (cb_term_type.element; springs,
 * bending, FEM and the penalty collider all provide it; where a type also has
 * element_vertex, that: the vertex's blocks alone, the same numbers). H_i is used as is
 * when its Cholesky factor exists; otherwise it is projected to SPD
 * (eigenvalues clamped at 0) and, if it is then near singular (smallest
 * eigenvalue below 1e-12 of the largest), the vertex is skipped this sweep.
 *
 * Line search (integrator.vbd_line_search, off by default as in the paper):
 * backtracking on the vertex's own objective F_i(x_i) = m_i/(2 dt^2)|x_i - y_i|^2
 * - m_i g.x_i + (the energies of the elements that touch i), with Armijo's
 * condition F_i(x_i + a dx) <= F_i(x_i) - 1e-4 a f_i.dx, a = 1, 1/2, ...,
 * at most 30 halvings (then the vertex is left where it is). Since F changes
 * by exactly the change of F_i when only x_i moves, this makes every sweep
 * non-increasing in F; without it a Newton step on x_i alone can overshoot
 * (a contact's penalty switching on or off within the step).
 *
 * Order: Gauss-Seidel over a vertex colouring (vertices that share an
 * element get different colours), computed once per scene, greedily in
 * vertex order (each vertex takes the smallest colour none of its coloured
 * neighbours has); the colours are swept in order 0, 1, ..., and within a
 * colour in vertex order (independent updates, so the order inside a colour
 * does not change the result). One iteration is one sweep over all colours;
 * integrator.iters sweeps per step.
 *
 * Initial guess (integrator.vbd_init):
 *   inertia   x = y = x0 + dt v0
 *   previous  x = x0
 *   adaptive  x = x0 + dt v0 + dt^2 a~, a~ = g^ clamp(a_prev . g^, 0, |g|),
 *             a_prev = (v0 - v_prev)/dt the last step's acceleration, g^ =
 *             g/|g| (the paper's adaptive initialisation; inertia without
 *             gravity or on the first step, when a_prev is unknown).
 *
 * vbd-chebyshev: x_{k+1} = omega_k x^_{k+1} + (1 - omega_k) x_{k-1}, x^ the
 * plain sweep's result from x_k, omega as in cb_chebyshev_omega; rho
 * (integrator.rho) a number in [0, 1) or `auto`: Wang's estimate from
 * integrator.rho_iters plain sweeps of the first step, once
 * (cb_rho_from_updates), then made safe for Gauss-Seidel sweeps: a trial of
 * 2 rho_iters accelerated sweeps must end with an update below the plain
 * sweeps' last and below its own at halfway, else 1 - rho is doubled and the
 * trial repeated (at most 8 times, then rho = 0). A Gauss-Seidel sweep's
 * iteration matrix is not symmetric, so its eigenvalues need not be real and
 * Chebyshev's blend at the plain rate can diverge (Wang 2015 tunes rho down
 * for Gauss-Seidel by hand). The paper starts the acceleration at iteration 2.
 *
 * Contact (docs/contact.md, "VBD"; Chen et al. 2024 sections 3.5-3.7, and the conservative bounds of Offset
 * Geometric Contact, Chen et al. 2025). A term whose elements move with x (the contact pairs: cb_term_type
 * vertex_collect, vertex_blocks, vertex_bound) cannot be a fixed stencil; it is read vertex by vertex:
 *   - collect: at the step's start, at x_c = x0 with the pins at their prescribed places, for the initial guess's
 *     largest move, and again before every integrator.vbd_collect-th sweep at the current x, for twice the last
 *     span's largest move (the term widens its query radius to let a vertex with nothing near move that far);
 *     each free vertex gets its bound b_v, the smallest the terms give;
 *   - f_i and H_i gain the term's blocks of vertex i (each pair's diagonal block projected to PSD), F_i its pairs'
 *     energy;
 *   - every move keeps |x_i - x_i(c)| <= b_v: the initial guess is clamped onto the ball (radially), a sweep's
 *     step truncated where it leaves it (x_i + a dx, a the largest in [0, 1] inside; the line search then starts
 *     from that a), vbd-chebyshev's blend clamped back onto it. The balls are convex, so every straight path
 *     between such states keeps every pair apart (the term's argument, contact_term.c): no contact is reached
 *     or crossed, without CCD, and a term with a step bound (ipc) is accepted (CB_INTEGRATOR_VERTEX_BOUNDS).
 * The colouring does not see the pairs: two vertices of one colour may share a pair, and the sweep, sequential,
 * updates them one after the other (a Gauss-Seidel order still; a parallel sweep would need the pairs coloured).
 * A start state that intersects (the term's `intersections`, exact) is refused at set-up.
 *
 * Pinned vertices keep their prescribed positions. Step stats: newton_iters
 * = sweeps, rel_grad = |grad F(x_K)|/|grad F(x_init)|, rel_grad_hat =
 * |grad F(x_K)|/|grad F(xhat)|, assemble_ms the objective evaluations,
 * solve_ms the sweeps. With a hook, CB_NEWTON_GRADIENT at every iterate
 * (iter 0 = the initial guess), one gradient evaluation each. No allocation
 * in a step. */
#include <cblas.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/integrator.h>
#include <clothbench/objective.h>
#include <clothbench/projection.h>
#include <clothbench/stencil.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include "integrator_keys.h"

enum { INIT_INERTIA = 0, INIT_PREVIOUS = 1, INIT_ADAPTIVE = 2 };
enum { MAXK = 4 }; /* vertices per element at most (a hinge) */

const char *const cb_vbd_init_names[] = {"inertia", "previous", "adaptive", NULL};

static const cb_vbd_params vbd_defaults = {.cookie = CB_PARAMS_COOKIE,
                                           .iters = 32,
                                           .init = INIT_ADAPTIVE,
                                           .line_search = 0,
                                           .rho = 0.0,
                                           .rho_iters = 64,
                                           .collect = 1};
static const cb_vbd_params vbdc_defaults = {.cookie = CB_PARAMS_COOKIE,
                                            .iters = 32,
                                            .init = INIT_ADAPTIVE,
                                            .line_search = 0,
                                            .rho = 0.995,
                                            .rho_iters = 64,
                                            .collect = 1};

cb_vbd_params cb_vbd_params_default(void) { return vbdc_defaults; }

/* iters, rho and rho_iters: the shared keys of integrator_keys.h */
#define VP(f) offsetof(cb_vbd_params, f)
#define KEY_INIT \
  { \
    .name = "vbd_init", .kind = CB_PARAM_CHOICE, .offset = VP(init), .def = "adaptive", .unit = "-", \
    .choices = cb_vbd_init_names, \
    .doc = "vbd, vbd-chebyshev: the initial guess (Chen et al. 2024): `inertia` x0 + dt v0, `previous` x0, " \
           "`adaptive` x0 + dt v0 + dt^2 a~ with a~ the last step's acceleration along gravity, clamped to [0, |g|]." \
  }
#define KEY_LS \
  { \
    .name = "vbd_line_search", .kind = CB_PARAM_BOOL, .offset = VP(line_search), .def = "0", .unit = "-", \
    .doc = "vbd, vbd-chebyshev: backtracking (Armijo) on each vertex's own objective, so that no sweep raises F (0 " \
           "or 1; the paper's update is 0)." \
  }
#define KEY_COLLECT \
  { \
    .name = "vbd_collect", .kind = CB_PARAM_INT, .offset = VP(collect), .def = "1", .unit = "-", .lo = 1, .hi = 1e6, \
    .doc = "vbd, vbd-chebyshev: sweeps between two collects of the contact pairs and of each vertex's conservative " \
           "displacement bound (docs/contact.md, VBD); 1 collects before every sweep." \
  }
static const cb_param_key vbd_keys[] = {
    CB_KEY_ITERS(VP(iters)), KEY_INIT, KEY_LS, KEY_COLLECT, CB_KEY_END,
};
static const cb_param_key vbdc_keys[] = {
    CB_KEY_ITERS(VP(iters)),         KEY_INIT,    KEY_LS,     CB_KEY_RHO(VP(rho)),
    CB_KEY_RHO_ITERS(VP(rho_iters)), KEY_COLLECT, CB_KEY_END,
};
#undef VP

typedef struct {
  int term, elem, local; /* an element of a term that touches the vertex, and the vertex's place in it */
} incidence;

typedef struct {
  cb_objective obj;
  int nterms;
  const cb_term *terms[CB_MAX_TERMS]; /* the terms with elements */
  const cb_stencil *st[CB_MAX_TERMS];
  int *inc_ptr;   /* nv + 1 */
  incidence *inc; /* the elements of every vertex */
  int ncolors;
  int *color_ptr; /* ncolors + 1 */
  int *order;     /* free vertices by colour, then index */
  double *gF;     /* 3 nfree */
  double *xprev;  /* 3 nv: x_{k-1} (Chebyshev) */
  double *vprev;  /* 3 nv: the previous step's v0 (adaptive init) */
  int have_vprev;
  double *dnorm;          /* rho_iters */
  double grav[3];         /* m/s^2, zero without a gravity term */
  double rho;             /* in use; CB_AUTO until estimated */
  cb_projection_work *pw; /* 3x3 projection */
  /* the terms whose elements move (contact pairs: cb_term_type.vertex_collect), read vertex by vertex */
  int ndyn;
  const cb_term *dyn[CB_MAX_TERMS];
  double *anchor; /* 3 nv: x at the last collect */
  double *bound;  /* nv: each free vertex's displacement bound from anchor, m (the smallest the terms give) */
  long truncated; /* vertex updates the bounds shortened, this step */
} vbd_work;

static void vbd_free(cb_integrator *it) {
  vbd_work *w = it->state;
  cb_objective_free(&w->obj);
  free(w->inc_ptr);
  free(w->inc);
  free(w->color_ptr);
  free(w->order);
  free(w->gF);
  free(w->xprev);
  free(w->vprev);
  free(w->dnorm);
  free(w->anchor);
  free(w->bound);
  cb_projection_work_free(w->pw);
}

/* The vertex -> element incidence of every term with elements (free vertices only). */
static int build_incidence(vbd_work *w, const cb_scene *s) {
  int nv = s->mesh.nv;
  w->inc_ptr = cb_calloc((size_t)nv + 1, sizeof(int));
  if (!w->inc_ptr) return CB_ENOMEM;
  for (int pass = 0; pass < 2; pass++) {
    int *fill = pass ? cb_calloc((size_t)nv, sizeof(int)) : NULL;
    if (pass && !fill) return CB_ENOMEM;
    for (int t = 0; t < w->nterms; t++) {
      const cb_stencil *st = w->st[t];
      for (int e = 0; e < st->ne; e++)
        for (int a = 0; a < st->k; a++) {
          int v = st->vert[st->k * e + a];
          if (s->free_index[v] < 0) continue;
          if (!pass) w->inc_ptr[v + 1]++;
          else w->inc[w->inc_ptr[v] + fill[v]++] = (incidence){t, e, a};
        }
    }
    if (!pass) {
      for (int v = 0; v < nv; v++) w->inc_ptr[v + 1] += w->inc_ptr[v];
      w->inc = cb_malloc((size_t)w->inc_ptr[nv] + 1, sizeof(incidence));
      if (!w->inc) return CB_ENOMEM;
    }
    free(fill);
  }
  return CB_OK;
}

/* Greedy colouring of the free vertices: neighbours share an element. */
static int build_colouring(vbd_work *w, const cb_scene *s) {
  int nv = s->mesh.nv, nf = s->model.nfree;
  int *color = cb_malloc((size_t)nv + 1, sizeof(int));
  int *mark = cb_malloc((size_t)nv + 1, sizeof(int)); /* mark[c] = v: colour c is taken by a neighbour of v */
  w->order = cb_malloc((size_t)nf + 1, sizeof(int));
  if (!color || !mark || !w->order) {
    free(color);
    free(mark);
    return CB_ENOMEM;
  }
  for (int v = 0; v < nv; v++) {
    color[v] = -1;
    mark[v] = -1;
  }
  w->ncolors = 0;
  for (int v = 0; v < nv; v++) {
    if (s->free_index[v] < 0) continue;
    for (int q = w->inc_ptr[v]; q < w->inc_ptr[v + 1]; q++) {
      const incidence *in = &w->inc[q];
      const cb_stencil *st = w->st[in->term];
      for (int a = 0; a < st->k; a++) {
        int u = st->vert[st->k * in->elem + a];
        if (u != v && color[u] >= 0) mark[color[u]] = v;
      }
    }
    int c = 0;
    while (mark[c] == v) c++;
    color[v] = c;
    if (c + 1 > w->ncolors) w->ncolors = c + 1;
  }
  w->color_ptr = cb_calloc((size_t)w->ncolors + 2, sizeof(int));
  if (!w->color_ptr) {
    free(color);
    free(mark);
    return CB_ENOMEM;
  }
  for (int v = 0; v < nv; v++)
    if (color[v] >= 0) w->color_ptr[color[v] + 1]++;
  for (int c = 0; c < w->ncolors; c++) w->color_ptr[c + 1] += w->color_ptr[c];
  for (int c = 0; c < w->ncolors + 1; c++) mark[c] = w->color_ptr[c];
  for (int v = 0; v < nv; v++)
    if (color[v] >= 0) w->order[mark[color[v]]++] = v;
  free(color);
  free(mark);
  return CB_OK;
}

static int vbd_init(cb_integrator *it) {
  const cb_vbd_params *p = it->type_params;
  vbd_work *w = it->state;
  const cb_scene *s = it->scene;
  const char *name = it->type->name;
  if (p->iters < 1) return cb_fail("%s: iters must be >= 1, got %d", name, p->iters);
  if (p->init < INIT_INERTIA || p->init > INIT_ADAPTIVE) return cb_fail("%s: unknown vbd_init %d", name, p->init);
  if (!(p->rho == CB_AUTO || (p->rho >= 0 && p->rho < 1)))
    return cb_fail("%s: rho must be in [0, 1) or auto, got %g", name, p->rho);
  if (p->rho == CB_AUTO && p->rho_iters < 4) return cb_fail("%s: rho_iters must be >= 4", name);
  if (p->collect < 1) return cb_fail("%s: vbd_collect must be >= 1, got %d", name, p->collect);
  for (int t = 0; t < s->sys.nterms; t++) {
    const cb_term *term = s->sys.terms[t];
    if (term->type == cb_term_gravity) { /* its force m_i g is read from the scene */
      memcpy(w->grav, s->gravity, sizeof w->grav);
      continue;
    }
    if (term->type->vertex_blocks) { /* moving elements: read vertex by vertex, collected during the step */
      if (!term->type->vertex_collect || !term->type->vertex_bound)
        return cb_fail("%s: the energy term '%s' (%s) gives vertex blocks without vertex_collect and vertex_bound",
                       name, term->label, term->type->name);
      w->dyn[w->ndyn++] = term;
      continue;
    }
    if (!term->type->element || !term->type->stencil)
      return cb_fail("%s: the energy term '%s' (%s) gives no per-element gradient and Hessian (cb_term_type.element), "
                     "which vertex block descent needs",
                     name, term->label, term->type->name);
    const cb_stencil *st = term->type->stencil(term);
    if (st->k > MAXK)
      return cb_fail("%s: term '%s' has %d-vertex elements (at most %d)", name, term->label, st->k, MAXK);
    w->terms[w->nterms] = term;
    w->st[w->nterms++] = st;
  }
  int nv = s->mesh.nv, nf = s->model.nfree;
  int st = cb_objective_init(&w->obj, s);
  if (st == CB_OK) st = build_incidence(w, s);
  if (st == CB_OK) st = build_colouring(w, s);
  if (st) return st;
  w->gF = cb_malloc(3 * (size_t)nf + 1, sizeof(double));
  w->xprev = cb_malloc(3 * (size_t)nv + 1, sizeof(double));
  w->vprev = cb_malloc(3 * (size_t)nv + 1, sizeof(double));
  if (!w->gF || !w->xprev || !w->vprev) return CB_ENOMEM;
  if ((st = cb_projection_work_alloc(3, &w->pw))) return st;
  if (p->rho == CB_AUTO && !(w->dnorm = cb_malloc(2 * (size_t)p->rho_iters, sizeof(double)))) return CB_ENOMEM;
  w->rho = p->rho;
  if (w->ndyn) {
    w->anchor = cb_malloc(3 * (size_t)nv + 1, sizeof(double));
    w->bound = cb_malloc((size_t)nv + 1, sizeof(double));
    if (!w->anchor || !w->bound) return CB_ENOMEM;
  }
  for (int t = 0; t < w->ndyn; t++) { /* the bounds keep a state free of intersections: they cannot start from one */
    const cb_term *term = w->dyn[t];
    long nx = 0;
    if (term->type->intersections && (st = term->type->intersections(term, s->x0, &nx))) return st;
    if (nx > 0)
      return cb_fail("%s: the start state intersects (%ld triangle pairs of the term '%s' (%s)): the displacement "
                     "bounds keep a state free of intersections, they cannot start from one",
                     name, nx, term->label, term->type->name);
    if ((st = term->type->vertex_collect(term, s->x0, 0.0))) return st; /* the collect's structures, at set-up */
  }
  return CB_OK;
}

/* Collects the moving elements of every such term at x, which becomes the anchor, and each free vertex's bound
 * (the smallest the terms give); move: the largest move expected of a vertex before the next collect. */
static int collect(vbd_work *w, const cb_scene *s, const double *x, double move) {
  if (!w->ndyn) return CB_OK;
  if (x != w->anchor) memcpy(w->anchor, x, 3 * (size_t)s->mesh.nv * sizeof(double));
  for (int b = 0; b < s->model.nfree; b++) w->bound[s->free_vertex[b]] = INFINITY;
  for (int t = 0; t < w->ndyn; t++) {
    const cb_term *term = w->dyn[t];
    int st = term->type->vertex_collect(term, x, move);
    if (st) return st;
    for (int b = 0; b < s->model.nfree; b++) {
      int i = s->free_vertex[b];
      w->bound[i] = fmin(w->bound[i], term->type->vertex_bound(term, i));
    }
  }
  return CB_OK;
}

/* The largest t in [0, 1] with |x_i + t dx - anchor_i| <= b_i (x_i inside the ball): the positive root of
 * |p + t dx|^2 = b^2, p = x_i - anchor_i, in the form without cancellation. */
static double ball_fraction(const vbd_work *w, int i, const double *x, const double dx[3]) {
  double p[3], a = 0, pb = 0, c = 0, b = w->bound[i], e = 0;
  for (int k = 0; k < 3; k++) {
    p[k] = x[3 * i + k] - w->anchor[3 * i + k];
    a += dx[k] * dx[k];
    pb += p[k] * dx[k];
    c += p[k] * p[k];
    e += (p[k] + dx[k]) * (p[k] + dx[k]);
  }
  if (!(a > 0) || e <= b * b) return 1.0;
  c -= b * b;
  if (!(c < 0)) return 0.0; /* on the sphere already (or a bound of 0) */
  double r = sqrt(pb * pb - a * c), t = pb >= 0 ? -c / (pb + r) : (r - pb) / a;
  return t < 0 ? 0.0 : t > 1 ? 1.0 : t;
}

/* The largest distance of a free vertex of x from the anchor, m. */
static double largest_move(const vbd_work *w, const cb_scene *s, const double *x) {
  double m2 = 0;
  for (int b = 0; b < s->model.nfree; b++) {
    int i = s->free_vertex[b];
    double d2 = 0;
    for (int k = 0; k < 3; k++) d2 += (x[3 * i + k] - w->anchor[3 * i + k]) * (x[3 * i + k] - w->anchor[3 * i + k]);
    m2 = fmax(m2, d2);
  }
  return sqrt(m2);
}

/* Moves vertex i back onto its ball (radially), if it is outside. */
static void clamp_ball(vbd_work *w, int i, double *x) {
  double n2 = 0, b = w->bound[i];
  for (int k = 0; k < 3; k++) n2 += (x[3 * i + k] - w->anchor[3 * i + k]) * (x[3 * i + k] - w->anchor[3 * i + k]);
  if (n2 <= b * b) return;
  double f = b / sqrt(n2);
  for (int k = 0; k < 3; k++) x[3 * i + k] = w->anchor[3 * i + k] + f * (x[3 * i + k] - w->anchor[3 * i + k]);
  w->truncated++;
}

extern const cb_integrator_type cb_integrator_vbd, cb_integrator_vbd_chebyshev; /* below */

int cb_vbd_colors(const cb_integrator *it) {
  if (!it || (it->type != &cb_integrator_vbd && it->type != &cb_integrator_vbd_chebyshev)) return -1;
  return ((const vbd_work *)it->state)->ncolors;
}

long cb_vbd_truncated(const cb_integrator *it) {
  if (!it || (it->type != &cb_integrator_vbd && it->type != &cb_integrator_vbd_chebyshev)) return -1;
  return ((const vbd_work *)it->state)->truncated;
}

/* Solves H dx = f (3x3 SPD); returns 0, or -1 if H is not SPD. */
static int chol3_solve(const double H[9], const double f[3], double dx[3]) {
  double l00 = H[0];
  if (!(l00 > 0)) return -1;
  l00 = sqrt(l00);
  double l10 = H[3] / l00, l20 = H[6] / l00;
  double d1 = H[4] - l10 * l10;
  if (!(d1 > 0)) return -1;
  double l11 = sqrt(d1), l21 = (H[7] - l20 * l10) / l11;
  double d2 = H[8] - l20 * l20 - l21 * l21;
  if (!(d2 > 0)) return -1;
  double l22 = sqrt(d2);
  double y0 = f[0] / l00, y1 = (f[1] - l10 * y0) / l11, y2 = (f[2] - l20 * y0 - l21 * y1) / l22; /* L y = f */
  dx[2] = y2 / l22;                                                                              /* L^T dx = y */
  dx[1] = (y1 - l21 * dx[2]) / l11;
  dx[0] = (y0 - l10 * dx[1] - l20 * dx[2]) / l00;
  return 0;
}

/* The element of an incidence at x: its energy and, unless NULL, the
 * vertex's gradient block g (3) and Hessian block H (3x3): from the term's
 * element_vertex where it has one (it computes no more than that), else from
 * element's whole gradient and Hessian (g_e, H_e: scratch), the same numbers. */
static double vertex_element(const vbd_work *w, const incidence *in, const double *x, double *g, double *H, double *g_e,
                             double *H_e) {
  const cb_term *term = w->terms[in->term];
  if (term->type->element_vertex) return term->type->element_vertex(term, in->elem, in->local, x, g, H);
  int k3 = 3 * w->st[in->term]->k, a = in->local;
  double E = term->type->element(term, in->elem, x, CB_PROJ_NONE, g_e, H_e);
  for (int c = 0; c < 3; c++) {
    if (g) g[c] = g_e[3 * a + c];
    if (H)
      for (int d = 0; d < 3; d++) H[3 * c + d] = H_e[(3 * a + c) * k3 + 3 * a + d];
  }
  return E;
}

/* Vertex i's inertia and gravity at x: m_i/(2 dt^2)|x_i - y_i|^2 - m_i g.x_i. */
static double inertia_F(const vbd_work *w, const cb_scene *s, double dt, const double *x, int i) {
  double mi = s->mass[i] / (dt * dt), F = 0.0;
  for (int a = 0; a < 3; a++) {
    double d = x[3 * i + a] - w->obj.xhat[3 * i + a];
    F += 0.5 * mi * d * d - s->mass[i] * w->grav[a] * x[3 * i + a];
  }
  return F;
}

/* F_i at x (only x_i is read as a variable): inertia, gravity, and the
 * energies of the elements that touch i, summed in the order the sweep sums
 * them (so that F_i at the sweep's x is the sweep's F0, bit for bit); no
 * gradient or Hessian where the term can leave them out (g_e, H_e:
 * scratch for those that cannot). */
static double local_F(vbd_work *w, const cb_scene *s, double dt, const double *x, int i, double *g_e, double *H_e) {
  double F = inertia_F(w, s, dt, x, i);
  for (int r = w->inc_ptr[i]; r < w->inc_ptr[i + 1]; r++) F += vertex_element(w, &w->inc[r], x, NULL, NULL, g_e, H_e);
  for (int t = 0; t < w->ndyn; t++) F += w->dyn[t]->type->vertex_blocks(w->dyn[t], i, x, CB_PROJ_CLAMP, NULL, NULL);
  return F;
}

/* One Gauss-Seidel sweep over the colours; returns |x_new - x_old|. */
static double sweep(vbd_work *w, const cb_scene *s, double dt, int line_search, double *x) {
  double g_e[3 * MAXK], H_e[9 * MAXK * MAXK], d2 = 0.0;
  const double *y = w->obj.xhat;
  for (int q = 0; q < s->model.nfree; q++) {
    int i = w->order[q];
    double mi = s->mass[i] / (dt * dt), f[3], H[9] = {mi, 0, 0, 0, mi, 0, 0, 0, mi};
    for (int a = 0; a < 3; a++)
      f[a] = -mi * (x[3 * i + a] - y[3 * i + a]) + s->mass[i] * w->grav[a]; /* - M(x - y)/dt^2 + m g */
    /* F0 = F_i(x_i), for the line search: the energies come with the gradients and Hessians below (local_F's sum) */
    double F0 = line_search ? inertia_F(w, s, dt, x, i) : 0.0;
    for (int r = w->inc_ptr[i]; r < w->inc_ptr[i + 1]; r++) {
      double g_i[3], H_ii[9];
      F0 += vertex_element(w, &w->inc[r], x, g_i, H_ii, g_e, H_e);
      for (int c = 0; c < 3; c++) {
        f[c] -= g_i[c];                                              /* f_i -= dE_e/dx_i */
        for (int d = 0; d < 3; d++) H[3 * c + d] += H_ii[3 * c + d]; /* H_i += (H_e)_ii */
      }
    }
    for (int t = 0; t < w->ndyn; t++) { /* the moving elements (contact pairs), each pair's block made PSD */
      double g_i[3], H_ii[9];
      F0 += w->dyn[t]->type->vertex_blocks(w->dyn[t], i, x, CB_PROJ_CLAMP, g_i, H_ii);
      for (int c = 0; c < 3; c++) {
        f[c] -= g_i[c];
        for (int d = 0; d < 3; d++) H[3 * c + d] += H_ii[3 * c + d];
      }
    }
    double dx[3];
    if (chol3_solve(H, f, dx)) { /* not SPD: project (eigenvalues clamped at 0), skip if near singular */
      cb_projection_apply(CB_PROJ_CLAMP, 3, H, w->pw);
      double tr = H[0] + H[4] + H[8];
      double Hs[9];
      memcpy(Hs, H, sizeof Hs);
      for (int c = 0; c < 3; c++) Hs[4 * c] -= 1e-12 * tr; /* SPD iff the smallest eigenvalue > 1e-12 tr */
      if (!(tr > 0) || chol3_solve(Hs, f, dx)) continue;
      chol3_solve(H, f, dx);
    }
    double alpha = 1.0;
    if (w->ndyn) { /* the displacement bound: the step truncated where it leaves the vertex's ball */
      alpha = ball_fraction(w, i, x, dx);
      if (alpha < 1.0) w->truncated++;
      if (!(alpha > 0)) continue;
    }
    if (line_search) { /* Armijo on F_i: F_i(x_i + a dx) <= F_i(x_i) - 1e-4 a f.dx */
      double slope = -(f[0] * dx[0] + f[1] * dx[1] + f[2] * dx[2]);
      double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
      int ok = 0;
      for (int h = 0; h <= 30 && !ok; h++, alpha *= 0.5) { /* from the bound's alpha down */
        for (int c = 0; c < 3; c++) x[3 * i + c] = xi[c] + alpha * dx[c];
        ok = local_F(w, s, dt, x, i, g_e, H_e) <= F0 + 1e-4 * alpha * slope;
        if (ok) break;
      }
      for (int c = 0; c < 3; c++) x[3 * i + c] = xi[c];
      if (!ok) continue;
    }
    for (int c = 0; c < 3; c++) {
      x[3 * i + c] += alpha * dx[c];
      d2 += alpha * alpha * dx[c] * dx[c];
    }
  }
  return sqrt(d2);
}

/* K sweeps (Chebyshev-accelerated when rho > 0) from the x given; dnorm gets the update norms. */
static int iterate(cb_integrator *it, double *x, int K, double rho, double *dnorm, cb_step_stats *st, int report,
                   double g_hat) {
  vbd_work *w = it->state;
  const cb_scene *s = it->scene;
  cb_newton_hook hook = report ? it->params.hook : NULL;
  int nf3 = 3 * s->model.nfree, nv3 = 3 * s->mesh.nv;
  double dt = it->params.dt, omega = 1.0, g0 = 0.0;
  memcpy(w->xprev, x, (size_t)nv3 * sizeof(double));
  for (int k = 0;; k++) {
    if (report && (k == 0 || k == K || hook) && cb_integrator_measure(it, &w->obj, x, w->gF, k, &g0, g_hat, hook, st))
      return CB_DIVERGED;
    if (k == K || nf3 == 0) break;
    double t0 = cb_now_ms();
    double d;
    if (w->ndyn && k > 0 && k % ((const cb_vbd_params *)it->type_params)->collect == 0) { /* the pairs again, the */
      int cs = collect(w, s, x, 2.0 * largest_move(w, s, x)); /* radius for twice the last span's largest move */
      if (cs) return cs;
    }
    if (rho > 0) { /* x_{k+1} = omega x^_{k+1} + (1 - omega) x_{k-1}: the sweep first, then the blend */
      omega = cb_chebyshev_omega(k, rho, omega);
      double *tmp = w->gF; /* scratch: x_k's free DOFs, before the sweep */
      for (int b = 0; b < s->model.nfree; b++)
        for (int a = 0; a < 3; a++) tmp[3 * b + a] = x[3 * s->free_vertex[b] + a];
      sweep(w, s, dt, ((const cb_vbd_params *)it->type_params)->line_search, x);
      double d2 = 0.0;
      for (int b = 0; b < s->model.nfree; b++) {
        int i = s->free_vertex[b];
        for (int a = 0; a < 3; a++) {
          double xk = tmp[3 * b + a], xn = omega * x[3 * i + a] + (1.0 - omega) * w->xprev[3 * i + a];
          d2 += (xn - xk) * (xn - xk);
          w->xprev[3 * i + a] = xk;
          x[3 * i + a] = xn;
        }
        if (w->ndyn) { /* the blend extrapolates: back into the ball, and the update norm from there */
          double xn[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
          clamp_ball(w, i, x);
          for (int a = 0; a < 3; a++) {
            double xk = w->xprev[3 * i + a];
            d2 += (x[3 * i + a] - xk) * (x[3 * i + a] - xk) - (xn[a] - xk) * (xn[a] - xk);
          }
        }
      }
      d = sqrt(d2);
    } else {
      d = sweep(w, s, dt, ((const cb_vbd_params *)it->type_params)->line_search, x);
    }
    st->solve_ms += cb_now_ms() - t0;
    if (!isfinite(d)) return CB_DIVERGED;
    if (dnorm) dnorm[k] = d;
  }
  return CB_OK;
}

/* The initial guess (vbd_init) into x, from the step's (x0, v0). With moving elements (contact), they are
 * collected at x0 with the pins at their prescribed places (the anchor), for the guess's largest move, and the
 * guess is clamped into the bounds. */
static int initial_guess(vbd_work *w, const cb_scene *s, const cb_vbd_params *p, double dt, const double *v,
                         double *x) {
  cb_objective_guess(&w->obj, x, p->init != INIT_PREVIOUS); /* xhat, or x0 (pins at xhat either way) */
  double gl = sqrt(s->gravity[0] * s->gravity[0] + s->gravity[1] * s->gravity[1] + s->gravity[2] * s->gravity[2]);
  if (p->init == INIT_ADAPTIVE && w->have_vprev && gl > 0)
    for (int b = 0; b < s->model.nfree; b++) {
      int i = s->free_vertex[b];
      double ag = 0.0; /* a_prev . g^ */
      for (int a = 0; a < 3; a++) ag += (v[3 * i + a] - w->vprev[3 * i + a]) / dt * s->gravity[a] / gl;
      ag = ag < 0 ? 0 : ag > gl ? gl : ag; /* clamp to [0, |g|] */
      for (int a = 0; a < 3; a++) x[3 * i + a] += dt * dt * ag * s->gravity[a] / gl;
    }
  if (!w->ndyn) return CB_OK;
  cb_objective_guess(&w->obj, w->anchor, 0); /* x0, pins at xhat */
  int st = collect(w, s, w->anchor, largest_move(w, s, x));
  if (st) return st;
  for (int b = 0; b < s->model.nfree; b++) clamp_ball(w, s->free_vertex[b], x);
  return CB_OK;
}

static int vbd_step(cb_integrator *it, double *x, double *v, cb_step_stats *st) {
  vbd_work *w = it->state;
  const cb_vbd_params *p = it->type_params;
  const cb_scene *s = it->scene;
  int nf3 = 3 * s->model.nfree, nv3 = 3 * s->mesh.nv;
  double dt = it->params.dt;
  cb_objective_begin(&w->obj, x, v, dt);
  /* |grad F(xhat)|, the yardstick shared with the other minimisers */
  double t0 = cb_now_ms();
  cb_objective_guess(&w->obj, w->xprev, 1);
  cb_objective_eval(&w->obj, w->xprev, w->gF, NULL);
  double g_hat = cblas_dnrm2(nf3, w->gF, 1);
  st->assemble_ms += cb_now_ms() - t0;
  if (w->rho == CB_AUTO) { /* Wang's estimate, once, from the first step's sweeps, made safe */
    t0 = cb_now_ms();
    cb_step_stats scratch;
    memset(&scratch, 0, sizeof scratch);
    int n = p->rho_iters, r = initial_guess(w, s, p, dt, v, x);
    if (r == CB_OK) r = iterate(it, x, n, 0.0, w->dnorm, &scratch, 0, g_hat);
    double rho = r == CB_OK ? cb_rho_from_updates(w->dnorm, n) : 0.0, d_plain = w->dnorm[n - 1];
    /* Safe for Gauss-Seidel: the estimate is the plain sweeps' decay rate, but a Gauss-Seidel sweep's
       iteration matrix is not symmetric (its eigenvalues may be complex), so Chebyshev's blend with that
       rate can grow instead of converge (81^2: rho 0.990 diverged, 0.95 converged; issue 31). A trial of
       2 rho_iters accelerated sweeps from the same guess must end with an update below the plain sweeps'
       last one and below its own halfway (still decaying); else 1 - rho doubles, at most 8 times, then
       rho = 0 (plain sweeps). */
    for (int trial = 0; rho > 0; trial++) {
      memset(&scratch, 0, sizeof scratch);
      r = initial_guess(w, s, p, dt, v, x);
      if (r == CB_OK) r = iterate(it, x, 2 * n, rho, w->dnorm, &scratch, 0, g_hat);
      double d_end = w->dnorm[2 * n - 1], d_half = w->dnorm[n - 1];
      if (r == CB_OK && isfinite(d_end) && d_end <= d_plain && d_end < d_half) break;
      rho = trial < 8 ? 1.0 - 2.0 * (1.0 - rho) : 0.0; /* 1 - rho doubled */
      if (rho < 0) rho = 0.0;
    }
    w->rho = rho;
    st->factor_ms += cb_now_ms() - t0;
  }
  st->rho = w->rho;
  w->truncated = 0;
  int status = initial_guess(w, s, p, dt, v, x);
  if (status) return status;
  status = iterate(it, x, p->iters, w->rho, NULL, st, 1, g_hat);
  memcpy(w->vprev, v, (size_t)nv3 * sizeof(double));
  w->have_vprev = 1;
  cb_objective_velocity(&w->obj, x, v);
  return status;
}

const cb_integrator_type cb_integrator_vbd = {
    .name = "vbd",
    .flags = CB_INTEGRATOR_HISTORY | CB_INTEGRATOR_VERTEX_BOUNDS, /* the adaptive initial guess; contact's bounds */
    .size = sizeof(vbd_work),
    .params_size = sizeof(cb_vbd_params),
    .params_default = &vbd_defaults,
    .keys = vbd_keys,
    .init = vbd_init,
    .step = vbd_step,
    .free = vbd_free,
};

const cb_integrator_type cb_integrator_vbd_chebyshev = {
    .name = "vbd-chebyshev",
    .flags = CB_INTEGRATOR_HISTORY | CB_INTEGRATOR_VERTEX_BOUNDS,
    .size = sizeof(vbd_work),
    .params_size = sizeof(cb_vbd_params),
    .params_default = &vbdc_defaults,
    .keys = vbdc_keys,
    .init = vbd_init,
    .step = vbd_step,
    .free = vbd_free,
};
