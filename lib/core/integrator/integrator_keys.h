/* The config keys that more than one integrator type declares, each defined
 * once (a type's key table lists e.g. CB_KEY_ITERS(offsetof(its_params,
 * iters))): the name, kind, default, unit, range and text are shared, the
 * offset into each type's parameter struct is its own. The config layer
 * refuses one name declared with two definitions (lib/config/config.c). */
#ifndef CB_INTEGRATOR_KEYS_H
#define CB_INTEGRATOR_KEYS_H

#include <clothbench/definiteness.h>
#include <clothbench/integrator.h>

#define CB_KEY_ITERS(off) \
  { \
    .name = "iters", .kind = CB_PARAM_INT, .offset = (off), .def = "32", .unit = "iterations", .lo = 1, \
    .hi = 100000000, \
    .doc = "Iterations per step of the fixed-iteration methods (jacobi-nl, chebyshev-nl, pd, pd-chebyshev; " \
           "constraint sweeps per substep of pbd and xpbd; the most of lbfgs); the GAMES103 lab uses 32, Liu et al. " \
           "2013 use 10 for projective dynamics." \
  }
#define CB_KEY_RHO(off) \
  { \
    .name = "rho", .kind = CB_PARAM_DOUBLE_AUTO, .offset = (off), .def = "0.995", .unit = "-", .lo = 0, \
    .hi = 0.999999, \
    .doc = "Chebyshev spectral radius of chebyshev-nl and pd-chebyshev (Wang 2015): a number in [0, 1) (0 = no " \
           "acceleration; the lab uses 0.995), or `auto`: estimated once, before the first step, from the decay of " \
           "the updates of integrator.rho_iters unaccelerated iterations." \
  }
#define CB_KEY_RHO_ITERS(off) \
  { \
    .name = "rho_iters", .kind = CB_PARAM_INT, .offset = (off), .def = "64", .unit = "iterations", .lo = 4, \
    .hi = 100000, \
    .doc = "Unaccelerated iterations run once, on the first step, to estimate rho when integrator.rho = auto." \
  }
#define CB_KEY_TOL(off) \
  { \
    .name = "tol", .kind = CB_PARAM_DOUBLE, .offset = (off), .def = "1e-8", .unit = "-", .lo = 0, .hi = 1, \
    .doc = "Newton stops when |grad F(x)| <= tol |grad F(x(0))|, x(0) being the step's initial guess. Below about " \
           "1e-11 the tolerance may be under round-off (e.g. a step from rest, where grad F(x(0)) is gravity alone): " \
           "pair it with `tol_dx`." \
  }
#define CB_KEY_TOL_DX(off) \
  { \
    .name = "tol_dx", .kind = CB_PARAM_DOUBLE, .offset = (off), .def = "0", .unit = "m", .lo = 0, .hi = 1e9, \
    .doc = "Newton also stops when the largest component of the step |dx| is <= tol_dx; 0 turns this test off." \
  }
#define CB_KEY_DEFINITENESS(off) \
  { \
    .name = "definiteness", .kind = CB_PARAM_CHOICE, .offset = (off), .def = "drop", .unit = "-", \
    .choices = cb_definiteness_names, \
    .doc = "Spring Hessian treatment when a spring is compressed: `none` keeps the exact Hessian; `drop` drops the " \
           "k(1 - L/|x|) term when |x| < L (the lecture's fix; the transverse eigenvalue clamped at 0); `mirror` " \
           "uses |1 - L/|x||; `shift` keeps the exact Hessian and adds mu I to Newton's matrix, raising mu until " \
           "Cholesky (or CG) succeeds; `choi-ko` replaces the compressed spring by Choi & Ko's (2002) " \
           "immediate-buckling response (see `material.buckling_kb`), a different energy, with its exact Hessian." \
  }
#define CB_KEY_PD_MATRIX(off) \
  { \
    .name = "pd_matrix", .kind = CB_PARAM_CHOICE, .offset = (off), .def = "auto", .unit = "-", \
    .choices = cb_pd_matrix_names, \
    .doc = "The constant matrix of pd, pd-chebyshev and lbfgs: `auto` factors the n x n P once and solves x, y and z " \
           "as one 3-column right-hand side (Liu et al. 2013, 2017) when the solver is cholmod and every term's part " \
           "is of the form P (x) I_3, else the 3n x 3n block matrix P (x) I_3; `block` always the block matrix. The " \
           "CSV's global_matrix column names the one used." \
  }
#define CB_KEY_END \
  { .name = NULL } /* ends a type's list */

#endif
