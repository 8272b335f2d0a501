/* Contact responses (issue 34 §1; docs/contact.md). `contact.method` names a
 * registered response; each is one file in lib/core/contact/ ending with its
 * cb_contact_type table, plus one line in the registry (contact.c). Its
 * config keys (`contact.<name>`) are in its own key table, the shared ones
 * (thickness, friction) defined once in lib/core/contact/contact_keys.h.
 *
 * The two responses here are energy terms that stack with the others:
 *
 *   penalty  E = sum_pairs k/2 (h - d)^2        for d < h = contact.thickness
 *   ipc      E = sum_pairs kappa e b(d^2),      b(s) = -(s - sh)^2 ln(s / sh) for s < sh = dhat^2,
 *            dhat = contact.thickness, e the edge-edge mollifier (1 for point-triangle pairs)
 *
 * over the point-triangle and edge-edge pairs (distance.h) of the cloth with
 * itself (adjacent primitives left out; pinned vertices take part, as
 * obstacles) and of the cloth with the scene's obstacle mesh (collider.type =
 * mesh). The pairs are found by the broad phase (broadphase.h) at every
 * evaluation of the energy, so E is a function of x alone. `ipc` also gives
 * the minimisers a step bound: the largest fraction of a step that additive
 * CCD (Li, Kaufman & Jiang 2021) certifies free of contact
 * (cb_system_max_step, system.h). With contact.friction mu > 0, `ipc` adds
 * lagged, smoothed Coulomb friction (Li et al. 2020, section 5) over the
 * pairs within reach at each step's start: sum_pairs mu lam f0(|u|), u the
 * pair's tangential displacement over the step (the obstacle's motion
 * included), lam its normal force at the start (contact_term.c, "Friction").
 *
 * `bridson` (Bridson, Fedkiw & Anderson 2002; contact_bridson.c) is no
 * energy: it is a post-step response (scene.h) that filters every step
 * x_start -> x of every integrator: repulsion impulses for close pairs
 * (with Coulomb friction), CCD impulses iterated, rigid impact zones as the
 * fail-safe. */
#ifndef CB_CONTACT_H
#define CB_CONTACT_H

#include "energy.h"
#include "obstacle.h"
#include "params.h"

struct cb_param_key;     /* params.h */
struct cb_response;      /* response.h */
struct cb_response_type; /* response.h */

/* Every response's parameters (each type reads the fields its keys name). */
typedef struct cb_contact_params {
  int cookie; /* CB_PARAMS_COOKIE, set by cb_contact_params_default() and checked by cb_contact_params_check (params.h)
               */
  double thickness;  /* m, > 0: the penalty's thickness h, IPC's activation distance dhat. Default 1e-3 */
  double friction;   /* Coulomb mu >= 0; above 0 only for a response with friction (ipc, bridson). Default 0 */
  double stiffness;  /* penalty k, and bridson's repulsion spring, N/m, > 0. Default 1e4 */
  double kappa;      /* IPC barrier stiffness, J/m^4 (b is in m^4), > 0. Default 1e8 */
  double epsv;       /* IPC friction's static-to-dynamic velocity eps_v, m/s, > 0. Default 1e-3 */
  int bridson_iters; /* bridson: CCD impulse passes before the rigid impact zones, >= 0. Default 10 */
} cb_contact_params;

cb_contact_params cb_contact_params_default(void);

typedef struct cb_contact_type {
  const char *name;                /* the value of contact.method */
  const struct cb_param_key *keys; /* its keys `contact.<name>` (into cb_contact_params), ended by a NULL name */
  /* Its energy term on the model, or *out = NULL for none (NULL: no term); fails with a message naming the key. */
  int (*term_alloc)(const cb_model *m, const cb_contact_params *p, cb_term **out);
  /* Its post-step response (response.h), or NULL: the scene runs it after every step of every integrator, after the
   * collider's, with the cb_contact_params as its init's params. */
  const struct cb_response_type *response;
  int friction; /* 1 if it implements contact.friction > 0 (else a mu above 0 is refused) */
} cb_contact_type;

extern const cb_contact_type *const cb_contact_types[]; /* the registry, NULL-terminated; "none" first */
extern const char *const cb_contact_names[];            /* their names, NULL-terminated */
const cb_contact_type *cb_contact_type_find(const char *name);

/* Checks p for method `name`: -> CB_EINVAL with "contact.<key>: ..." (an
 * unknown method, thickness <= 0 or not finite, friction < 0, or > 0 for a
 * response without friction, epsv <= 0 or not finite, a stiffness or kappa
 * <= 0, bridson_iters < 0). */
int cb_contact_params_check(const char *name, const cb_contact_params *p);

/* ---- the pair term both responses are ------------------------------------- */

/* The scalar function of the squared distance s a pair's energy is, with
 * its first and second derivatives in s. */
typedef double (*cb_contact_potential)(const cb_contact_params *p, double s, double *ds, double *dss);

/* A contact term on model m: potential f of the squared distance (nonzero
 * only for s < reach^2), mollified edge-edge pairs if mollify, CCD step
 * bounds if ccd. type is the registered term type it is. */
int cb_contact_term_alloc(const cb_model *m, const cb_term_type *type, const cb_contact_params *p,
                          cb_contact_potential f, double reach, int mollify, int ccd, cb_term **out);
/* Gives the term the obstacle mesh o (static at its current positions o->x
 * during a step: its motion is taken between steps), or NULL for none. */
int cb_contact_term_set_obstacle(cb_term *t, const cb_obstacle *o);
/* Lagged friction (ipc with contact.friction > 0; contact_term.c, "Friction"):
 * freezes, at the step's start state x with time step dt, each active pair's
 * normal force, tangent basis and closest-point weights, and the obstacle's
 * displacement over the step (from its motion, cb_obstacle_positions). The
 * term's type calls it as its begin_step (energy.h); tests call it directly.
 * A term without friction (mu = 0) keeps no pairs. */
int cb_contact_term_begin_step(cb_term *t, const double *x, double dt);
/* Nonzero if t is a contact term (either response). */
int cb_contact_term_is(const cb_term *t);

/* *count = the triangle pairs that intersect at x (closed triangles, exactly,
 * intersect.h): the cloth's non-adjacent pairs and cloth against obstacle.
 * The scene refuses such a start state for a response that bounds its steps
 * (ipc): its barrier cannot start from it. */
int cb_contact_term_intersections(const cb_term *t, const double *x, long *count);

/* What the last evaluation found. */
typedef struct cb_contact_stats {
  long candidates;     /* primitive pairs the broad phase gave */
  long active;         /* pairs within reach (nonzero energy) */
  long mollified;      /* active edge-edge pairs inside the mollifier's range (c < eps_x; ipc only) */
  long decoupled;      /* active pairs of the last Hessian whose cross blocks the matrix pattern lacked (block-
                          diagonal model, docs/contact.md) */
  double min_dist;     /* smallest distance of a candidate pair, m (inf without one) */
  long ccd_queries;    /* pairs the last step bound ran CCD on */
  long ccd_iters;      /* additive-CCD advances those queries took */
  double max_step;     /* the last step bound, in (0, 1] */
  long grows;          /* candidate or friction arrays grown past their set-up capacity (allocations outside set-up) */
  long friction_pairs; /* pairs the last begin_step froze for friction (0 without friction) */
  long sliding;        /* of those, pairs whose tangential displacement |u| >= eps_v dt at the last energy call */
  double friction_energy; /* the friction potential's part of the last energy call, J */
  /* Phase timers (CLOCK_MONOTONIC, cb_now_ms), ms, accumulated since the term was allocated and never reset: a
   * reader takes differences (cb_integrator_step does, into cb_step_stats' contact_*_ms). Disjoint:
   *   broad_ms    the broad phase (refit and traversal, static or swept boxes) of every evaluation, step bound,
   *               friction freeze and vertex block descent's collect;
   *   ccd_ms      the step bound's narrow phase (the distance filter and additive CCD of the candidates);
   *   barrier_ms  the pairs' value, gradient and Hessian (and friction's: its freeze and its pairs), with the
   *               Hessian's projection and scatter: the energy and Hessian calls less their broad phase.
   * Two clock reads per call (tens of ns against a broad phase of microseconds); vertex block descent's per-vertex
   * blocks are not timed (they are called per vertex). */
  double broad_ms, ccd_ms, barrier_ms;
} cb_contact_stats;
const cb_contact_stats *cb_contact_term_stats(const cb_term *t);

/* ---- bridson ---------------------------------------------------------------- */

/* What the last step's bridson filter did (contact_bridson.c). */
typedef struct cb_bridson_stats {
  long close;        /* pairs closer than the thickness at the step's start (repulsion stage) */
  long repulsions;   /* of them, pairs that received an impulse */
  long ccd_queries;  /* CCD queries over all passes */
  long collisions;   /* CCD hits that received an impulse, over all passes */
  int passes;        /* CCD passes run (the last found nothing, unless zone_passes > 0) */
  int zone_passes;   /* rigid-impact-zone passes (0: the impulses sufficed) */
  int zones;         /* impact zones of two or more vertices at the end */
  int zone_vertices; /* cloth vertices in those zones */
  int unresolved;    /* 1 if the zone passes hit their cap with CCD still finding collisions */
  double min_dist;   /* smallest distance of a close pair at the step's start, m (inf: none) */
  long grows;        /* candidate arrays grown past their set-up capacity (allocations inside a step) */
} cb_bridson_stats;
/* Those of r, or NULL if r is not the bridson response. */
const cb_bridson_stats *cb_bridson_stats_of(const struct cb_response *r);

#endif
