/* The pair term the contact responses share (contact_term.c), for their type
 * tables: each response's file names these in its cb_term_type and gives its
 * potential (contact.h). Internal to the core. */
#ifndef CB_CONTACT_TERM_H
#define CB_CONTACT_TERM_H

#include <clothbench/contact.h>

double cb_contact_energy(const cb_term *t, const double *x, double *grad);
int cb_contact_pattern(const cb_term *t, cb_pattern *p);
int cb_contact_bind(cb_term *t, const cb_sparse *A);
void cb_contact_hessian(const cb_term *t, const double *x, cb_projection proj, double *val);
void cb_contact_free(cb_term *t);
double cb_contact_max_step(const cb_term *t, const double *x, const double *x1);
int cb_contact_indefinite(const cb_term *t, const double *x, int *nelements);

/* The conformance examples (on any model): 0, a parallel sheet: an obstacle
 * that is a copy of the model's rest mesh moved 0.25 m along its normal and
 * turned 0.01 rad about it (point-triangle pairs and nearly parallel edge
 * pairs inside the 0.3 m reach at the test's states); 1, self-contact only,
 * reach 0.3 m (non-adjacent primitives of the small grids come that close). */
int cb_contact_example(const cb_model *m, int i, const cb_term_type *type, cb_contact_potential f, int mollify, int ccd,
                       const cb_contact_params *p, cb_term **out);

/* Vertex block descent's per-vertex access (energy.h; the math is in contact_term.c): the pairs within the query
 * radius max(reach / (1 - 2 gamma), move / gamma) collected at x, each vertex's pairs' energy, gradient and diagonal
 * Hessian block, its conservative displacement bound gamma min(query radius, distance of its nearest collected pair);
 * and the exact intersection count (cb_contact_term_intersections) as the type's `intersections`. */
#define CB_CONTACT_VBD_GAMMA 0.4
int cb_contact_vertex_collect(const cb_term *t, const double *x, double move);
double cb_contact_vertex_blocks(const cb_term *t, int v, const double *x, cb_projection proj, double *g, double *H);
double cb_contact_vertex_bound(const cb_term *t, int v);

enum { CB_CONTACT_DENSE_MAX = 64 }; /* free vertices up to which the pattern holds every pair */

#endif
