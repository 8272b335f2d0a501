/* Conservative continuous collision detection (issue 33 §2; docs/geometry-ccd.md).
 *
 * A query is 8 points: points 0-3 at t = 0 and points 4-7 (the same points) at
 * t = 1, each moving on a straight line x_k(t) = (1 - t) x_k + t x_{k+4}.
 *   vertex-face (vf): point 0 is the vertex, points 1, 2, 3 the triangle;
 *   edge-edge (ee):   points 0-1 are one edge, points 2-3 the other.
 * This is the order of Wang et al. 2021's CCD benchmark.
 *
 * Contact at time t means the two primitives (closed point, closed triangle or
 * closed segments) come within the minimum separation eta >= 0 at t. The
 * first contact is t* = the smallest such t in [0, 1].
 *
 * Conservative: whenever a contact exists in [0, 1], the query reports a hit,
 * and its toi satisfies toi <= t*. A hit may be false (a "false positive": the
 * primitives came within eta plus a tolerance, see tol below, but not within
 * eta), which only costs a caller a smaller step.
 *
 * Each coordinate may be given as an interval [lo, hi] (a rational of the
 * benchmark that is no double is the interval between its two neighbouring
 * doubles): the guarantee then holds for every query whose coordinates lie in
 * the intervals. cb_ccd_vf/cb_ccd_ee take plain doubles (lo = hi).
 *
 * Methods are plug-ins: a type table {name, vf, ee} per file
 * (lib/core/geometry/ccd_<name>.c) and one line in the registry
 * (lib/core/geometry/ccd.c). */
#ifndef CB_CCD_H
#define CB_CCD_H

typedef struct cb_ccd_params {
  double eta;     /* minimum separation, length units, >= 0; default 0 */
  double tol;     /* relative tolerance (> 0) of the distance function: a box of (t, u, v) whose values of the
                     separation vector vary by at most tol * (the query's extent) is accepted as a hit;
                     default 1e-6 */
  long max_boxes; /* budget of boxes a query may examine (>= 1); past it the query stops with a conservative
                     hit at the earliest time it could not exclude and status CB_NOT_CONVERGED; default 1e6 */
} cb_ccd_params;

cb_ccd_params cb_ccd_params_default(void);

typedef struct cb_ccd_result {
  int hit;    /* 1: contact possible in [0, 1]; 0: certainly none */
  double toi; /* when hit: a time in [0, 1] no later than the first contact; 1 when no hit */
  long boxes; /* boxes examined (the cost) */
} cb_ccd_result;

/* One query's coordinates as intervals: lo[k][j] <= x_k[j] <= hi[k][j], k = 0..7 (0-3 at t = 0, 4-7 at t = 1). */
typedef struct cb_ccd_query {
  double lo[8][3], hi[8][3];
} cb_ccd_query;

typedef struct cb_ccd_type {
  const char *name;
  /* Both return CB_OK, CB_NOT_CONVERGED (budget spent; the result is still conservative) or CB_EINVAL (the
   * wrapper has checked the input before; a method may still refuse). */
  int (*vf)(const cb_ccd_query *q, const cb_ccd_params *p, cb_ccd_result *r);
  int (*ee)(const cb_ccd_query *q, const cb_ccd_params *p, cb_ccd_result *r);
} cb_ccd_type;

/* The registry, NULL-terminated; cb_ccd_type_find(NULL) is the default method (the first). */
extern const cb_ccd_type *const cb_ccd_types[];
const cb_ccd_type *cb_ccd_type_find(const char *name);

enum { CB_CCD_VF = 0, CB_CCD_EE = 1 };

/* Checks the query and parameters (CB_EINVAL with a message on NaN, inf, lo > hi, |x| > 2^500, eta < 0 or
 * NaN, tol <= 0, max_boxes < 1: never a silent "no hit"), then runs the method. r is always written: on an
 * error r->hit = 1, r->toi = 0 (a caller that ignores the status still stops). type NULL: the default. */
int cb_ccd_run(const cb_ccd_type *type, int kind, const cb_ccd_query *q, const cb_ccd_params *p, cb_ccd_result *r);
/* Plain-double queries, flat as positions are: x0[3k..3k+2] the point k at t = 0, x1[3k..3k+2] at t = 1
 * (vf: vertex then triangle; ee: edge then edge). */
int cb_ccd_vf(const cb_ccd_type *type, const double x0[12], const double x1[12], const cb_ccd_params *p,
              cb_ccd_result *r);
int cb_ccd_ee(const cb_ccd_type *type, const double x0[12], const double x1[12], const cb_ccd_params *p,
              cb_ccd_result *r);

#endif
