/* The system: a sum of energy terms over one fixed-pattern sparse matrix.
 *
 * The pattern covers the free (unpinned) vertices only. It is built once when
 * the system is initialised; each term then knows the slots of its blocks, so
 * assembling A = s M + H(x) (+ mu I) writes numbers and never allocates.
 * Terms flagged CB_TERM_CONSTANT_HESSIAN are evaluated once, at
 * initialisation; assembly adds their stored values. */
#ifndef CB_SYSTEM_H
#define CB_SYSTEM_H

#include "definiteness.h"
#include "energy.h"
#include "sparse.h"

#define CB_MAX_TERMS 8

typedef struct cb_system {
  const cb_model *model;
  int nterms;
  cb_term *terms[CB_MAX_TERMS];
  cb_sparse A;    /* values are overwritten by cb_system_assemble */
  int *diag;      /* 3*nfree: index in A.val of each diagonal entry */
  double *hconst; /* A.nnz: sum of the constant Hessians, or NULL if no term has one */
} cb_system;

/* Takes ownership of the terms (freed by cb_system_free, also on failure). */
int cb_system_init(cb_system *s, const cb_model *m, cb_term **terms, int nterms);
void cb_system_free(cb_system *s);

/* Total potential energy E(x) = sum of terms, J. If grad != NULL it is
 * overwritten with dE/dx (3*nv). If per_term != NULL, it receives each term's
 * energy. */
double cb_system_energy(const cb_system *s, const double *x, double *grad, double *per_term);

/* A = mass_scale * M + H(x) + shift * I over the free degrees of freedom.
 * The policy def reaches the terms as its element projection
 * (cb_definiteness_projection: none, clamp or abs); the shift of `shift` is
 * the solve's (solver_shift.h), and Choi-Ko is already in the springs. */
void cb_system_assemble(cb_system *s, const double *x, double mass_scale, cb_definiteness def, double shift);

/* The line-search filter every minimiser shares: the smallest of the terms'
 * max_step bounds (energy.h) for the step x -> x1 (3*nv each), in [0, 1]; 1
 * when no term has one. A minimiser starts its line search at that fraction
 * of its step (Newton, integrator_newton.c). */
double cb_system_max_step(const cb_system *s, const double *x, const double *x1);
/* The start of a step at x (3*nv) with time step dt: every term's begin_step
 * (energy.h), in order; the first failing status. The integrator wrapper
 * (cb_integrator_step) calls it before every step of every type. */
int cb_system_begin_step(const cb_system *s, const double *x, double dt);
/* Elastic (non-gravity) part of the energy: the sum over terms with a Hessian. */
double cb_system_elastic_energy(const cb_system *s, const double *x);

#endif
