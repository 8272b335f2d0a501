/* Stackable energy terms. "As long as we have E(x), we can calculate force and
 * Hessian. Forces and Hessians are stackable." (lecture, summary slide)
 *
 * A term is a plug-in described by a cb_term_type table, in the manner of
 * gsl_multiroot_fsolver_type, and registered by one X(id) line in energy.c.
 * It computes E, adds its gradient, declares the 3x3 blocks of its Hessian
 * once, looks up their slots once (stencil.h does both for k-vertex
 * elements), and then adds Hessian values into the fixed-pattern matrix
 * without allocating. A term whose Hessian can be indefinite applies the
 * projection it is handed (projection.h) to each element. */
#ifndef CB_ENERGY_H
#define CB_ENERGY_H

#include "definiteness.h"
#include "mesh.h"
#include "projection.h"
#include "sparse.h"
#include "topology.h"

/* A term's k-vertex elements (stencil.h, which the terms that have them include). */
typedef struct cb_stencil cb_stencil;

/* Choi & Ko's immediate-buckling response of a spring of rest length L
 * compressed to 0 < l < L, with bending stiffness kb (N m^2): its energy E (J),
 * dE/dl (N, negative: it pushes the ends apart) and d2E/dl^2 (N/m). Formulas
 * in energy_spring_choi_ko.c. Returns theta = kappa L / 2. Zeros for l >= L. */
double cb_choi_ko_response(double L, double l, double kb, double *E, double *dE, double *d2E);

/* The compressed spring as the choi-ko policy models it (energy_spring_choi_ko.c):
 * the linear spring k (l - L) while its push k (L - l) is below the buckling
 * force f_b(l), the buckled arc beyond that, so the force is continuous. */
typedef struct cb_choi_ko {
  double k, L, kb; /* N/m, m, N m^2 */
  double lc;       /* compression L - l* at which the spring buckles, m (L: never) */
  double Ec;       /* buckling energy E_b(l*) at that point, J */
} cb_choi_ko;
/* Fails unless k > 12 pi^2 kb / L^3 (the buckled branch softer than the spring). */
int cb_choi_ko_init(cb_choi_ko *c, double k, double L, double kb);
/* E(l), dE/dl, d2E/dl^2 for any l > 0 (the linear spring for l >= L - lc). */
void cb_choi_ko_eval(const cb_choi_ko *c, double l, double *E, double *dE, double *d2E);

/* What terms are built from. Pinned vertices have free_index -1: their rows
 * and columns are eliminated from the matrix (not penalised). */
typedef struct cb_model {
  const cb_mesh *mesh; /* rest positions in mesh->x */
  const cb_topology *topo;
  const double *mass;    /* nv, kg */
  const int *free_index; /* nv: block index in the matrix, or -1 if pinned */
  int nfree;
} cb_model;

typedef struct cb_term cb_term;

/* Flags of a term type. */
enum {
  /* H does not depend on x (quadratic energies: quadratic bending,
   * frozen-rotation FEM, a projective-dynamics matrix). The system evaluates
   * it once, when it is finalised, with projection none, and adds the stored
   * values at every assembly: such a Hessian must be PSD (no projection is
   * applied to it) and must not depend on x (the conformance test checks
   * both). */
  CB_TERM_CONSTANT_HESSIAN = 1u << 0,
  /* The hessian callback gives a PSD model of the Hessian, not the Hessian
   * of E itself (the frozen-rotation FEM matrix; a projective-dynamics
   * matrix): Newton with it is a quasi-Newton method. The conformance test
   * checks such a type's gradient, symmetry and positive semidefiniteness,
   * but not that its matrix equals the finite-difference Hessian. */
  CB_TERM_MODEL_HESSIAN = 1u << 1
};

typedef struct cb_term_type {
  const char *name;
  unsigned flags; /* CB_TERM_* */
  /* Returns E(x) in J and, if grad != NULL, adds dE/dx (3*nv). */
  double (*energy)(const cb_term *t, const double *x, double *grad);
  /* Declares the blocks its Hessian writes; NULL if the Hessian is zero. */
  int (*pattern)(const cb_term *t, cb_pattern *p);
  /* Looks up the slots of those blocks in the finalised matrix. */
  int (*bind)(cb_term *t, const cb_sparse *A);
  /* Adds its Hessian at x, each element projected by proj, to the matrix
   * values (only free-free blocks). NULL if the Hessian is zero. */
  void (*hessian)(const cb_term *t, const double *x, cb_projection proj, double *val);
  void (*free)(cb_term *t);
  /* Per-element access, for methods that work vertex by vertex (vertex
   * block descent, integrator_vbd.c). stencil gives the term's elements (k
   * vertices each); element fills, for element e at x, its gradient g (3k)
   * and its Hessian H (3k x 3k row-major, the element projected by proj as
   * in hessian), and returns its energy. The element sums are the term's
   * energy, gradient and Hessian (the conformance test checks it). NULL for
   * both when the term has no elements (gravity, whose force the methods
   * read from the scene). */
  const cb_stencil *(*stencil)(const cb_term *t);
  double (*element)(const cb_term *t, int e, const double *x, cb_projection proj, double *g, double *H);
  /* Optional, beside element: element e's energy at x and, unless NULL,
   * its vertex a's part (0 <= a < k) of what element gives with CB_PROJ_NONE:
   * the gradient block g (3) and the diagonal Hessian block H (3x3,
   * row-major), the same numbers bit for bit, without computing the rest of
   * the element where the type can avoid it (vertex block descent needs no
   * more; its line search only the energy). NULL: the methods read element
   * (the conformance test checks that the two agree). */
  double (*element_vertex)(const cb_term *t, int e, int a, const double *x, double *g, double *H);
  /* Conformance (tests/test_energy_conformance.c): builds example i,
   * 0 <= i < nexamples, of this term on any model (any mesh, any pins), with
   * the parameters a scene would give it. Registering a type is all it takes
   * to have its gradient and Hessian checked by finite differences. */
  int nexamples;
  int (*example)(const cb_model *m, int i, cb_term **out);
  /* The elements whose Hessian at x can be indefinite before projection
   * (a spring with l < L, a hinge whose exact element Hessian has a
   * negative eigenvalue, a vertex inside the penalty sphere); *nelements
   * gets the term's number of elements. NULL: the type does not count them
   * (cb_term_count_indefinite gives 0 of 0). */
  int (*indefinite)(const cb_term *t, const double *x, int *nelements);
  /* Optional: the line-search filter (IPC's CCD-limited step, contact.h).
   * The largest alpha in [0, 1] such that the straight path x -> x + alpha
   * (x1 - x) keeps the term's energy finite (no contact crossed or
   * reached); 1 when nothing is in the way, 0 on an error (with a message).
   * Minimisers call it through cb_system_max_step (system.h), one hook they
   * share. NULL: no bound. */
  double (*max_step)(const cb_term *t, const double *x, const double *x1);
  /* Optional: called once at the start of every step, at the step's start
   * state x (3*nv) with its time step dt (s), before the step's first
   * evaluation, for a term that freezes quantities for the step (IPC's lagged
   * friction, contact.h). Returns a status (with a message). The term's
   * energy is a function of x alone between two calls. Minimisers do not call
   * it: the integrator wrapper does, through cb_system_begin_step (system.h).
   * NULL: nothing to freeze. */
  int (*begin_step)(cb_term *t, const double *x, double dt);
  /* Optional: per-vertex access to a term whose elements change with x (the
   * contact pairs the broad phase finds), which a fixed stencil cannot hold;
   * vertex block descent reads it (integrator_vbd.c, docs/contact.md).
   * vertex_collect gathers the term's elements near x (within the term's
   * query radius, widened so that a vertex with nothing near may move
   * `move` m: the largest move the caller expects of a vertex before the
   * next collect, 0 for the term's smallest radius) and keeps them, with
   * each vertex's list, in the term (no allocation, except past its set-up
   * capacity, counted like the contact term's other grows); it returns a
   * status. Until the next collect:
   * vertex_blocks gives, at any x, the energy of the collected elements
   * vertex v takes part in and, unless NULL, v's gradient block g (3) and
   * diagonal Hessian block H (3x3 row-major), each element's block
   * projected by proj (3x3); vertex_bound gives v's conservative
   * displacement bound (m): while every vertex stays within its bound of
   * where it was at the collect, no element of the term reaches its
   * singular configuration (two primitives touching) on any straight path
   * between such states, and the collected set holds every element with
   * nonzero energy there (so vertex_blocks is the term's own gradient
   * block). intersections counts, exactly, the primitive pairs that
   * intersect at x: such a start state is one the bounds cannot keep.
   * NULL: the term has none (a type gives all four or none). */
  int (*vertex_collect)(const cb_term *t, const double *x, double move);
  double (*vertex_blocks)(const cb_term *t, int v, const double *x, cb_projection proj, double *g, double *H);
  double (*vertex_bound)(const cb_term *t, int v);
  int (*intersections)(const cb_term *t, const double *x, long *count);
} cb_term_type;

struct cb_term {
  const cb_term_type *type;
  const cb_model *model;
  char label[32]; /* role in the scene: "stretch", "bend", "gravity" */
};

/* Every term type, one X(id) line each (energy.c); NULL-terminated. */
extern const cb_term_type *const cb_term_types[];
/* The registered type called name, or NULL. */
const cb_term_type *cb_term_type_find(const char *name);

extern const cb_term_type *const cb_term_spring;
extern const cb_term_type *const cb_term_gravity;

/* Springs between vertex pairs ends[2s], ends[2s+1], stiffness k (N/m), rest
 * lengths measured on the model's rest mesh. Zero rest length is rejected. */
int cb_spring_term_alloc(const cb_model *m, const char *label, int ns, const int *ends, double k, cb_term **out);

/* Compressed-spring response of a spring term (its energy, not only its
 * Hessian): CB_DEF_CHOI_KO gives Choi & Ko's immediate-buckling response with
 * bending stiffness kb (N m^2) when l < L; any other policy keeps the linear
 * spring. Set when the scene is built (integrator.definiteness,
 * material.buckling_kb). Fails if t is not a spring term. */
int cb_spring_term_set_response(cb_term *t, cb_definiteness def, double kb);
/* Nonzero if t is a spring term with the Choi-Ko response. */
int cb_spring_term_is_choi_ko(const cb_term *t);
/* The springs of a spring term, for methods that work on them directly (the
 * constraints of XPBD, the Laplacian of projective dynamics): ns springs
 * between ends[2s] and ends[2s+1], rest lengths rest[s] (m), stiffness k
 * (N/m). The arrays are the term's own. Fails (CB_EINVAL) if t is not a
 * spring term. */
int cb_spring_term_springs(const cb_term *t, int *ns, const int **ends, const double **rest, double *k);

/* Co-rotational triangle FEM (energy_fem.c): E_t = mu A_t |F - R|_F^2 on every
 * triangle, mu in N/m (an energy per unit rest area), R the polar rotation of
 * the deformation gradient F. Type `fem` has the exact Hessian (projected
 * like any element), `fem_frozen` the lecture's constant frozen-R matrix.
 * material.stretch picks springs or FEM (material.h), and
 * material.fem_hessian the Hessian (cb_fem_hessian_names, by enum value). */
typedef enum { CB_FEM_EXACT = 0, CB_FEM_FROZEN = 1 } cb_fem_hessian;
extern const char *const cb_fem_hessian_names[]; /* "exact", "frozen" */
/* Fails on a zero-area rest triangle or mu < 0. */
int cb_fem_term_alloc(const cb_model *m, const char *label, double mu, cb_fem_hessian h, cb_term **out);
/* Triangles of t that are degenerate at x (collapsed: sigma_2 <= 1e-8 sigma_1;
 * energy_fem.c says how they are treated); 0 if t is not an FEM term. ntri
 * gets the number of triangles of t. */
int cb_fem_term_degenerate(const cb_term *t, const double *x, int *ntri);
/* max over triangles of |sigma_i - 1| at x (the largest principal strain); NaN if not FEM. */
double cb_fem_term_max_strain(const cb_term *t, const double *x);

/* E = -sum_i m_i g . x_i */
int cb_gravity_term_alloc(const cb_model *m, const double g[3], cb_term **out);

void cb_term_free(cb_term *t);
/* The term's indefinite elements at x through its type's `indefinite`
 * (0 of 0 when the type does not count them); *nelements gets its elements. */
int cb_term_count_indefinite(const cb_term *t, const double *x, int *nelements);

/* The hinges of a topology, one per neighbouring-triangle pair p: vert[4p..4p+3]
 * = the shared edge's two vertices, then the opposite vertex of each
 * triangle (pair_opp). Returns np. */
int cb_hinge_vertices(const cb_topology *tp, int *vert);
/* Dihedral-angle hinges on every pair of neighbouring triangles (discrete
 * shells, energy_dihedral.c), k_b in N m: E = k_b 3|e|^2/(A_A + A_B) (theta - theta_bar)^2 / 2. */
int cb_hinge_term_alloc(const cb_model *m, const char *label, double k, cb_term **out);
/* material.bend_hessian: the dihedral term's Hessian (cb_bend_hessian_names, by
 * enum value): Gauss-Newton c grad theta grad theta^T (PSD, type `dihedral`,
 * what cb_hinge_term_alloc builds) or the exact one projected per element
 * (type `dihedral_exact`). energy_dihedral.c derives both. */
typedef enum { CB_BEND_GAUSS_NEWTON = 0, CB_BEND_EXACT = 1 } cb_bend_hessian;
extern const char *const cb_bend_hessian_names[]; /* "gauss-newton", "exact" */
/* Switches a dihedral term (either type) to Hessian kind, before a system is
 * built on it; fails if t is not a dihedral term. */
int cb_hinge_term_set_hessian(cb_term *t, cb_bend_hessian kind);
/* Nonzero if t is a dihedral term (either Hessian). */
int cb_hinge_term_is(const cb_term *t);
/* Hinges of a dihedral term whose exact element Hessian at x has a negative
 * eigenvalue (the ones the projection changes); nhinges gets the count. */
int cb_hinge_term_count_indefinite(const cb_term *t, const double *x, int *nhinges);
/* Bergou et al.'s quadratic bending (energy_quadratic.c), k_b in N m:
 * E = k_b/2 (x - x_bar)^T Q (x - x_bar), Q = 3/(A_0 + A_1) q q^T, constant Hessian. */
int cb_quadratic_bend_term_alloc(const cb_model *m, const char *label, double k, cb_term **out);

#endif
