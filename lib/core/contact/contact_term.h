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

enum { CB_CONTACT_DENSE_MAX = 64 }; /* free vertices up to which the pattern holds every pair */

#endif
