/* Squared distances between mesh primitives, with their gradients and
 * Hessians with respect to every coordinate of the pair (lib/core/geometry/
 * distance*.c; formulas, cases and sources in docs/geometry-distance.md).
 * Geometry sits below physics: these know points, edges and triangles, not
 * materials (DESIGN.md, "Contact").
 *
 * The unsigned distance between two primitives is piecewise: the closest
 * points lie in a vertex, edge or face region. As in IPC (Li et al. 2020) a
 * pair is first *classified* into the case whose formula holds, and each case
 * has a smooth formula of the coordinates it reads:
 *
 *   point-point   d^2 = |p - q|^2
 *   point-line    d^2 = |(p - e0) x (e1 - e0)|^2 / |e1 - e0|^2
 *   point-plane   d^2 = ((p - t0) . n)^2 / |n|^2,       n = (t1 - t0) x (t2 - t0)
 *   line-line     d^2 = ((a0 - b0) . n)^2 / |n|^2,      n = (a1 - a0) x (b1 - b0)
 *
 * A pair's squared distance, gradient and Hessian are those of its case's
 * formula at x: exact inside a case's region, the squared distance C^1
 * across regions (the Hessian jumps there). Coordinates are flat: vertex k
 * of a pair is x[3k..3k+2]; a Hessian is (3 nverts)^2 doubles, row-major,
 * symmetric. No function allocates. */
#ifndef CB_DISTANCE_H
#define CB_DISTANCE_H

/* The smooth formulas. */
typedef enum {
  CB_DIST_POINT_POINT = 0, /* p, q */
  CB_DIST_POINT_LINE = 1,  /* p, e0, e1 */
  CB_DIST_POINT_PLANE = 2, /* p, t0, t1, t2 */
  CB_DIST_LINE_LINE = 3    /* a0, a1, b0, b1 */
} cb_distance_form;

/* The vertices each form reads: 2, 3, 4, 4. */
int cb_distance_form_nverts(cb_distance_form f);
/* "point-point", "point-line", "point-plane", "line-line". */
const char *cb_distance_form_name(cb_distance_form f);

/* The squared distance of form f on the 3 nverts(f) coordinates x; g (3
 * nverts doubles) and H ((3 nverts)^2) get its gradient and Hessian unless
 * NULL. A degenerate input the form is undefined for (a zero-length line, a
 * zero-area plane, parallel lines: a zero denominator) gives NaN: the
 * classifiers below never choose a form there. */
double cb_distance_form_eval(cb_distance_form f, const double *x, double *g, double *H);

/* A classified pair: the form that holds, and which of the pair's vertices
 * it reads, in the form's order (v[0..nverts(form)-1]). */
typedef struct cb_distance_case {
  cb_distance_form form;
  int v[4];
} cb_distance_case;

/* The pair's squared distance by its case c: the form on the vertices
 * c->v, its gradient scattered into g (3 nverts doubles, the other vertices'
 * entries zero) and its Hessian into H ((3 nverts)^2), unless NULL. */
double cb_distance_case_eval(const cb_distance_case *c, int nverts, const double *x, double *g, double *H);

/* The classifiers (the pair types' own, exposed for tests and contact code).
 * Each returns CB_OK, or CB_EINVAL (and a message) when a coordinate is not
 * finite, leaving *c a point-point case on vertices 0, 1.
 *
 * point-triangle (p, t0, t1, t2): point-plane if p projects into the closed
 * triangle, else the nearest of the three edges' point-line or point-point
 * cases (a triangle of sin^2 angle <= CB_DIST_DEGENERATE has no face).
 * edge-edge (a0, a1, b0, b1): line-line if the lines' closest points lie on
 * both closed segments and the edges are not parallel (|a x b|^2 >
 * CB_DIST_PARALLEL |a|^2 |b|^2); else the nearest of the four endpoint-to-
 * segment cases (point-line or point-point; for parallel segments an endpoint
 * is always among the closest points).
 * point-edge (p, e0, e1): point-line if p projects into the open segment,
 * else point-point to the nearer end. */
#define CB_DIST_PARALLEL 1e-20   /* sin^2 of the angle below which two edges are parallel */
#define CB_DIST_DEGENERATE 1e-20 /* sin^2 of a triangle's angle at t0 below which it has no face */
int cb_distance_point_triangle_case(const double *x, cb_distance_case *c);
int cb_distance_edge_edge_case(const double *x, cb_distance_case *c);
int cb_distance_point_edge_case(const double *x, cb_distance_case *c);

/* ---- primitive pairs as plug-ins ------------------------------------------
 * One type per primitive pair, each a file ending with its type table, and
 * one line in the registry (distance.c). Tests loop over every registered
 * pair (tests/test_distance.c). */
typedef struct cb_distance_type {
  const char *name; /* "point-triangle", "edge-edge", ... */
  int nverts;       /* vertices of the pair: coordinates 3 nverts */
  int na;           /* the first primitive is vertices 0..na-1 (a point, edge or triangle), the
                       second na..nverts-1 */
  int (*classify)(const double *x, cb_distance_case *c);
  double (*distance)(const double *x);            /* squared distance; NaN on non-finite input */
  double (*gradient)(const double *x, double *g); /* g: 3 nverts; returns the squared distance */
  double (*hessian)(const double *x, double *H);  /* H: (3 nverts)^2; returns the squared distance */
} cb_distance_type;

extern const cb_distance_type cb_distance_point_point;    /* p, q */
extern const cb_distance_type cb_distance_point_edge;     /* p, e0, e1 */
extern const cb_distance_type cb_distance_point_triangle; /* p, t0, t1, t2 */
extern const cb_distance_type cb_distance_edge_edge;      /* a0, a1, b0, b1 */

extern const cb_distance_type *const cb_distance_types[]; /* the registry, NULL-terminated */
/* The registered pair called name, or NULL. */
const cb_distance_type *cb_distance_type_find(const char *name);

/* ---- the edge-edge mollifier (Li et al. 2020, IPC, section 4.3) ------------
 * Nearly parallel edges: the edge-edge barrier is multiplied by e_x(c),
 * c = |(a1 - a0) x (b1 - b0)|^2, which rises from 0 at parallel edges to 1:
 *   e_x(c) = (2 - c / eps_x) c / eps_x   for c < eps_x,   1 otherwise,
 * C^1 in c at eps_x (e_x' = 2 (1 - c/eps_x) / eps_x -> 0). eps_x =
 * 1e-3 |a1 - a0|^2 |b1 - b0|^2 at rest. */
#define CB_MOLLIFIER_SCALE 1e-3
/* eps_x of the edge pair at its rest coordinates x_rest (a0, a1, b0, b1). */
double cb_edge_edge_mollifier_threshold(const double *x_rest);
/* c = |(a1 - a0) x (b1 - b0)|^2 at x, with its gradient (12) and Hessian (144) unless NULL. */
double cb_edge_edge_cross_squared(const double *x, double *g, double *H);
/* e_x(c(x)) for eps_x > 0, with its gradient (12) and Hessian (144) with
 * respect to x unless NULL (zero for c >= eps_x); NaN if eps_x <= 0. */
double cb_edge_edge_mollifier(const double *x, double eps_x, double *g, double *H);

#endif
