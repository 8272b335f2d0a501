/* The config keys every contact response declares (contact.thickness,
 * contact.friction), each defined once: a response's key table lists
 * CB_KEY_CONTACT_THICKNESS, CB_KEY_CONTACT_FRICTION and its own keys. The
 * config layer refuses one name declared with two definitions. */
#ifndef CB_CONTACT_KEYS_H
#define CB_CONTACT_KEYS_H

#include <stddef.h>

#include <clothbench/contact.h>
#include <clothbench/integrator.h>

#define CB_CKEY(field) offsetof(cb_contact_params, field)
#define CB_KEY_CONTACT_THICKNESS \
  { \
    .name = "thickness", .kind = CB_PARAM_DOUBLE, .offset = CB_CKEY(thickness), .def = "1e-3", .unit = "m", .lo = 0, \
    .hi = 1e9, .lo_open = 1, \
    .doc = "Contact distance: the penalty acts on pairs closer than it; IPC's barrier activation distance dhat; " \
           "bridson repels pairs closer than it." \
  }
#define CB_KEY_CONTACT_FRICTION \
  { \
    .name = "friction", .kind = CB_PARAM_DOUBLE, .offset = CB_CKEY(friction), .def = "0", .unit = "-", .lo = 0, \
    .hi = 1e9, \
    .doc = "Coulomb friction coefficient mu >= 0: lagged, smoothed Coulomb friction for `ipc` (Li et al. 2020, " \
           "section 5; docs/contact.md) and bridson's friction impulses; `penalty` refuses a value above 0." \
  }
#define CB_KEY_CONTACT_STIFFNESS \
  { \
    .name = "stiffness", .kind = CB_PARAM_DOUBLE, .offset = CB_CKEY(stiffness), .def = "1e4", .unit = "N/m", .lo = 0, \
    .hi = 1e15, .lo_open = 1, \
    .doc = "Contact spring stiffness k: contact.method = penalty's E = k/2 (thickness - d)^2 per pair closer than " \
           "the " \
           "thickness; bridson's repulsion impulse dt k (thickness - d), limited as in its paper." \
  }
#define CB_KEY_CONTACT_END \
  { .name = NULL }

#endif
